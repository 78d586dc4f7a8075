"""Area balancing of a one-to-one map of a triangle mesh onto the sphere or the plane: one descent for both.

A descent on ``E = sum_t a_t [log(r_t)^2 + beta (D_t / A_t - 2)]`` (``r_t`` a triangle's share of the map's
area over its share of the mesh's, or over the share asked of it: :func:`target_shares`; ``D_t / A_t - 2``
its conformal distortion; energy and gradient in numba, :mod:`._balance_kernels`) moves the vertices; every
accepted step keeps every triangle positive, so
a one-to-one map stays one. On the sphere the vertices move in their tangent planes and are put back on
the sphere; on the plane a vertex may be held (a corner of the square) or slide along a line (a side of the
square), so squeezed parts near the boundary can open along it.

Examples
--------
A square's four triangles round a centre pulled towards one corner: balancing moves it back.

>>> x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
>>> tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
>>> start = x.copy(); start[4, :2] = 0.2
>>> held = np.array([True, True, True, True, False])
>>> out, steps, (e0, e1) = balance(start, x, tris, planar=True, held=held)
>>> bool(e1 < 1e-6 < e0), np.round(out[4], 3).tolist()
(True, [0.5, 0.5, 0.0])
"""
from __future__ import annotations

from concurrent.futures import Future, ThreadPoolExecutor

import numpy as np
from scipy import sparse

from ..errors import InputError
from ._balance_kernels import balance_energy, balance_gradient, local_sweeps, project_moves, step_to
from ._laplacian import (
    corner_cotangents,
    cotangent_weights,
    factor_symmetric,
    laplacian,
    triangle_areas,
    vertex_areas,
    vertex_shares,
)

__all__ = [
    "balance",
    "sobolev_factor_later",
    "lower_along",
    "relax_locally",
    "target_shares",
    "settle",
    "sobolev_factor",
    "vertex_triangles",
    "default_steps",
    "squeeze_scale",
    "neighbour_mean",
    "local_sizes",
    "SCALE_SMOOTHING",
    "SWEEPS",
    "DEFAULT_STEPS",
]

SWEEPS = 60              # single-vertex sweeps a relaxation takes (relax_locally)
SCALE_SMOOTHING = 3      # neighbour means taken of the log area ratio behind the scaled step
DEFAULT_STEPS = 200
SMALL_MESH_WORK = 2_000_000   # a mesh under 10,000 triangles balances on, up to this many triangle-steps ...
MAX_STEPS = 2000              # ... and this many steps, until it has converged


def default_steps(triangles: int) -> int:
    """The balancing's step cap: 200, or 2,000,000 / T on a mesh of T < 10,000 triangles (at most 2,000), which
    costs no more than 200 steps on 10,000 triangles and lets small meshes converge.

    >>> default_steps(100_000), default_steps(4_000), default_steps(10)
    (200, 500, 2000)
    """
    return int(np.clip(SMALL_MESH_WORK // max(triangles, 1), DEFAULT_STEPS, MAX_STEPS))


def local_sizes(s: np.ndarray, edges: np.ndarray, *, ignore_below: float | None = None) -> np.ndarray:
    """Each vertex's shortest edge in the map (inf for vertices on no edge); with ``ignore_below``, edges no
    longer than that share of the longest are left out (vertices on one point get their other edges).
    """
    length = np.linalg.norm(s[edges[:, 0]] - s[edges[:, 1]], axis=1)
    if ignore_below is not None:
        length[length <= ignore_below * length.max()] = np.inf
    h = np.full(len(s), np.inf)
    np.minimum.at(h, edges[:, 0], length)
    np.minimum.at(h, edges[:, 1], length)
    return h


def neighbour_mean(edges: np.ndarray, n: int) -> sparse.csr_matrix:
    """The operator that replaces a value per vertex by its mean over the vertex and its neighbours."""
    adj = sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    adj = ((adj + adj.T) > 0).astype(np.float64) + sparse.identity(n, format="csr")
    return (sparse.diags(1.0 / np.asarray(adj.sum(axis=1)).ravel()) @ adj).tocsr()


def squeeze_scale(area: np.ndarray, share: np.ndarray, tris: np.ndarray, used: np.ndarray,
                  smooth: sparse.csr_matrix) -> np.ndarray:
    """Each vertex's linear scale, (n, 1): the square root of its share of the map (``area``, per triangle,
    summing to 1) over its share of the mesh (``share``, per vertex: :func:`vertex_shares`), its log averaged
    ``SCALE_SMOOTHING`` times with the neighbours' (``smooth``: :func:`neighbour_mean`), and at most 1: only
    squeezed parts are slowed.
    """
    n = len(used)
    known = used & (share > 0)                  # a vertex only on faces of no area has no ratio: 1
    ratio = vertex_shares(area, tris, n) / np.where(known, share, 1.0)
    log_ratio = np.log(np.where(known, ratio, 1.0))
    for _ in range(SCALE_SMOOTHING):
        log_ratio = smooth @ log_ratio
    return np.exp(0.5 * np.minimum(log_ratio, 0.0))[:, None]


def vertex_triangles(tris: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each vertex's triangles: ``ring[ptr[i]:ptr[i + 1]]`` are vertex ``i``'s, ascending.

    >>> ptr, ring = vertex_triangles(np.array([[0, 1, 2], [0, 2, 3]]), 5)
    >>> ptr.tolist(), ring.tolist()
    ([0, 2, 3, 5, 6, 6], [0, 1, 0, 0, 1, 1])
    """
    flat = np.asarray(tris, np.int64).ravel()
    ring = (np.argsort(flat, kind="stable") // 3).astype(np.int64)
    ptr = np.concatenate([[0], np.cumsum(np.bincount(flat, minlength=n))]).astype(np.int64)
    return ptr, ring


def relax_locally(s, x, tris, used=None, beta: float = 0.3, sweeps: int = SWEEPS, *, planar: bool = False,
                  held=None, along=None, reach: float = 0.3, shares=None):
    """Sweeps of single-vertex moves down the area-balancing energy (:func:`._balance_kernels.local_sweeps`):
    each vertex of ``used`` (and not ``held``) in turn (colour by colour, one colour's in parallel) steps at
    most ``reach`` times its shortest edge along
    its own gradient, so long as its triangles' energy falls and all stay positive. What :func:`balance`
    cannot do where one squeezed triangle blocks every step of all vertices at once. ``shares`` as for
    :func:`balance`. Returns the new map; ``s`` is left as it is.

    >>> x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
    >>> tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    >>> start = x.copy(); start[4, :2] = 0.2
    >>> out = relax_locally(start, x, tris, planar=True, held=np.array([True, True, True, True, False]))
    >>> np.round(out[4], 2).tolist()
    [0.5, 0.5, 0.0]
    """
    out = np.array(s, dtype=np.float64)
    tris = np.ascontiguousarray(tris, np.int64)
    n = len(out)
    used = np.isin(np.arange(n), tris) if used is None else np.asarray(used, bool)
    moves = np.ascontiguousarray(used & (~np.asarray(held, bool) if held is not None else True))
    ptr, ring = vertex_triangles(tris, n)
    along = np.zeros((n, 3)) if along is None else np.ascontiguousarray(along, np.float64)
    local_sweeps(out, tris, ptr, ring, target_shares(x, tris, shares), corner_cotangents(x, tris), float(beta),
                 bool(planar), moves, along, int(sweeps), float(reach))
    return out


def target_shares(x, tris, shares=None) -> np.ndarray:
    """The share of the map each triangle is balanced towards (T,, summing to 1): ``shares`` normalized, or
    by default its share of the mesh's area.

    >>> x = np.array([[0., 0, 0], [2, 0, 0], [0, 1, 0], [2, 1, 0]])
    >>> tris = np.array([[0, 1, 2], [1, 3, 2]])
    >>> target_shares(x, tris).tolist(), target_shares(x, tris, [1.0, 3.0]).tolist()
    ([0.5, 0.5], [0.25, 0.75])
    """
    w = triangle_areas(x, tris) if shares is None else np.asarray(shares, np.float64)
    if w.shape != (len(tris),) or not (np.isfinite(w).all() and (w >= 0).all() and w.sum() > 0):
        raise InputError("shares: expected one finite share >= 0 per triangle, not all 0")
    return np.ascontiguousarray(w / w.sum())


def balance(s, x, tris, lap=None, vertex_area=None, used=None, beta: float = 0.3, steps: int | None = None,
            progress=None, *, planar: bool = False, held=None, along=None, shares=None, cache: dict | None = None):
    """Descend the area-balancing energy from the map ``s`` of the mesh ``x, tris``; every accepted step keeps
    all triangles positive. Returns ``(s, steps taken, (energy at the start, energy at the end))``.

    Parameters
    ----------
    s : (n, 3) float
        Unit vectors (a map onto the sphere) or points ``(u, v, 0)`` (onto the plane, counter-clockwise).
    x, tris : the mesh's vertices (n, 3) and triangles (T, 3).
    steps : int, optional
        Steps at most (:func:`default_steps` by default); the descent stops sooner once a step lowers the
        energy by less than 1e-6 of itself.
    lap, vertex_area : optional
        The mesh's cotangent Laplacian and vertex areas (computed when not given).
    used : (n,) bool, optional
        The vertices that move (default: those on a triangle).
    planar : bool, default False
        A map onto the plane (``s[:, 2]`` is 0) rather than the sphere.
    held : (n,) bool, optional
        On the plane: vertices that stay where they are.
    along : (n, 3) float, optional
        On the plane: a unit direction per vertex that may only slide along it (zero rows move freely).
    shares : (T,) float, optional
        The share of the map each triangle is balanced towards (:func:`target_shares`; by default its share
        of the mesh's area; :func:`._sampling_shares.sampling_shares` asks more for the parts that bend).
    cache : dict, optional
        Keeps the factored Sobolev matrix (:func:`sobolev_factor`) for the next call with the same mesh and
        ``used`` (a settling's balancings, a disk's starts): the same factor, so the same map.

    Steps follow the Laplacian-smoothed gradient (limbs move as a whole). Every other step is scaled on
    both sides of the smoothing by each squeezed vertex's linear scale ``sigma < 1`` (:func:`squeeze_scale`):
    the energy's curvature grows like ``1 / sigma^2`` where the map squeezes, so a squeezed part moves by
    a fraction of its own size instead of holding the whole step back. The two kinds of step take turns,
    each with its own step length, and each stands in for the other when it finds no lower energy. When
    neither finds a step that keeps every triangle positive (a region squeezed to 1e-15 of the map blocks
    any global move), a step along the gradient scaled per vertex by its local size is taken instead, so
    tiny regions grow by a fraction of themselves while the rest moves normally.
    """
    s = np.array(s, dtype=np.float64)
    tris = np.ascontiguousarray(tris, np.int64)
    n = len(s)
    steps = default_steps(len(tris)) if steps is None else int(steps)
    used = np.isin(np.arange(n), tris) if used is None else np.asarray(used, bool)
    moves = np.ascontiguousarray(used & (~np.asarray(held, bool) if held is not None else True))
    a, cot = target_shares(x, tris, shares), corner_cotangents(x, tris)
    e, state = balance_energy(s, tris, a, cot, beta, planar)
    if not np.isfinite(e) or steps <= 0:       # nothing to descend: no Laplacian to build
        return s, 0, (e, e)
    precond = sobolev_factor(x, tris, used, lap, vertex_area, cache)
    e_start = e
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    smooth = neighbour_mean(edges, n)
    share = vertex_shares(a, tris, n)          # each vertex's share of the mesh, for the scaled steps
    along = np.zeros((n, 3)) if along is None else np.ascontiguousarray(along, np.float64)

    def tangent(v):
        v = np.ascontiguousarray(v)
        project_moves(v, s, planar, moves, along)
        return v

    columns = 2 if planar else 3              # on the plane z stays 0: its solve is skipped (the same bits)

    def sobolev(g, sigma):
        rhs = np.asfortranarray(sigma * g[:, :columns])                       # SuperLU takes columns: no copy
        d = np.zeros_like(g)
        d[:, :columns] = precond.solve(rhs)
        d = tangent(-sigma * d)
        return d / max(np.abs(d).max(), 1e-300)

    def search(d, alpha):
        return lower_along(s, d, alpha, e, tris, a, cot, beta, planar)

    alphas, done = [1.0, 1.0], 0            # each kind of step keeps its own step length
    for step in range(steps):
        g = tangent(balance_gradient(s, tris, a, cot, beta, state))
        kinds = (step % 2, 1 - step % 2)        # scaled and plain steps take turns; each stands in for the other
        for kind in kinds:
            sigma = squeeze_scale(state[0] * state[1], share, tris, used, smooth) if kind == 0 else 1.0
            found = search(sobolev(g, sigma), alphas[kind])
            if found is not None:
                alphas[kind] = min(2.0 * found[3], 1.0)
                break
            alphas[kind] = 1.0
        local = found is None
        if local:
            h = local_sizes(s, edges)
            on_edge = np.isfinite(h)
            d = -g * np.where(on_edge, h, 0.0)[:, None] ** 2
            reach = np.linalg.norm(d, axis=1) / np.where(on_edge, h, 1.0)
            d /= max(2.0 * reach.max(), 1e-300)            # no vertex moves more than half its shortest edge
            found = search(d, 1.0)
            if found is None:
                break
        trial, e_new, st, _ = found
        converged = not local and e - e_new < 1e-6 * e
        s, e, state, done = trial, e_new, st, step + 1
        if progress is not None and step % 10 == 0:
            progress(f"area balancing step {step}: energy {e:.4f}")
        if converged:
            break
    return s, done, (e_start, e)


def lower_along(s, d, alpha, e, tris, a, cot, beta, planar, above: float = 1e-10):
    """The step ``s + alpha d`` (on the sphere, put back on it) halved from ``alpha`` while ``alpha > above``
    until its energy is lower than ``e`` with every triangle positive: ``(map, energy, state, alpha)``, or None.

    >>> x = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]]); tris = np.array([[0, 1, 2]])
    >>> a, cot = target_shares(x, tris), corner_cotangents(x, tris)
    >>> e = balance_energy(x, tris, a, cot, 0.3, True)[0]
    >>> lower_along(x, np.array([[0, 0, 0], [0, 0, 0], [0, -2.0, 0]]), 1.0, e, tris, a, cot, 0.3, True) is None
    True
    """
    while alpha > above:
        trial = np.empty_like(s)
        step_to(s, d, alpha, planar, trial)
        e_new, state = balance_energy(trial, tris, a, cot, beta, planar)
        if e_new < e:
            return trial, e_new, state, alpha
        alpha *= 0.5
    return None


def sobolev_factor(x, tris, used, lap=None, vertex_area=None, cache: dict | None = None):
    """The factored matrix of :func:`balance`'s Sobolev steps, ``L + 0.01 tr(L) diag(m + ~used)`` (``L`` the
    cotangent Laplacian, ``m`` the vertex areas' shares), or the one ``cache`` holds; put in ``cache``.

    >>> x = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    >>> tris, cache = np.array([[0, 1, 2], [1, 3, 2]]), {}
    >>> used = np.ones(4, bool)
    >>> sobolev_factor(x, tris, used, cache=cache) is sobolev_factor(x, tris, used, cache=cache)
    True
    """
    if cache is not None and "sobolev" in cache:
        if isinstance(cache["sobolev"], Future):          # made in the background: wait for it
            cache["sobolev"] = cache["sobolev"].result()
        return cache["sobolev"]
    lap = laplacian(cotangent_weights(x, tris)) if lap is None else lap
    vertex_area = vertex_areas(x, tris) if vertex_area is None else vertex_area
    mass = vertex_area / vertex_area.sum()
    factor = factor_symmetric(lap + 1e-2 * lap.diagonal().sum() * sparse.diags(mass + (~np.asarray(used, bool))))
    if cache is not None:
        cache["sobolev"] = factor
    return factor


def sobolev_factor_later(x, tris, used, lap=None, vertex_area=None) -> dict:
    """A ``cache`` for :func:`balance` and :func:`settle` whose Sobolev factor (:func:`sobolev_factor`) is made
    from now on in a thread of its own; the first balancing waits for it. SuperLU lets go of the GIL while it
    factors, so work done meanwhile that does too (the decimated copy of a large mesh, :mod:`._decimate`)
    hides its time: ``bunny.off``'s sphere map 0.1-0.2 s sooner. The same factor as made in line, bit for bit.

    >>> x = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    >>> tris, used = np.array([[0, 1, 2], [1, 3, 2]]), np.ones(4, bool)
    >>> b = np.arange(4.0)
    >>> cache = sobolev_factor_later(x, tris, used)
    >>> np.array_equal(sobolev_factor(x, tris, used, cache=cache).solve(b), sobolev_factor(x, tris, used).solve(b))
    True
    """
    pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="geoimg-sobolev")
    try:
        return {"sobolev": pool.submit(sobolev_factor, x, tris, used, lap, vertex_area)}
    finally:
        pool.shutdown(wait=False)          # the thread ends when the factor is made


def settle(s, x, tris, rounds: int, lap=None, vertex_area=None, used=None, beta: float = 0.3, steps: int | None = None,
           progress=None, *, planar: bool = False, held=None, along=None, shares=None, balanced: bool = False,
           cache: dict | None = None):
    """:func:`balance`, then ``rounds`` times :data:`SWEEPS` single-vertex sweeps (:func:`relax_locally`) and
    :func:`balance` again: the sweeps open what held back the steps of all vertices at once (a triangle of no
    area, one squeezed part), and the steps then go on. ``steps`` caps each balancing (none is swept after
    when ``steps`` is 0). ``balanced``: ``s`` is already the first balancing's result (a settling in two calls,
    ``rounds`` 0 then the rest, gives the same map as one). Returns what :func:`balance` does: the map, the
    steps taken in all and the energy at the start and at the end (with ``balanced``, no steps and the energy
    of ``s`` when ``rounds`` is 0). ``cache`` as for :func:`balance` (the balancings share one either way).

    >>> x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
    >>> tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    >>> start = x.copy(); start[4, :2] = 0.2
    >>> out, steps, (e0, e1) = settle(start, x, tris, 1, planar=True, held=np.array([1, 1, 1, 1, 0], bool))
    >>> bool(e1 < 1e-6 < e0), np.round(out[4], 3).tolist()
    (True, [0.5, 0.5, 0.0])
    """
    kw = {"planar": planar, "held": held, "along": along, "shares": shares}
    cache = {} if cache is None else cache
    out, taken, (e_start, e_end) = balance(s, x, tris, lap, vertex_area, used, beta, 0 if balanced else steps,
                                           progress, cache=cache, **kw)
    for _ in range(rounds if steps != 0 else 0):
        if progress is not None:
            progress(f"{SWEEPS} single-vertex sweeps")
        out = relax_locally(out, x, tris, used, beta, SWEEPS, **kw)
        out, more, (_, e_end) = balance(out, x, tris, lap, vertex_area, used, beta, steps, progress, cache=cache,
                                        **kw)
        taken += more
    return out, taken, (e_start, e_end)
