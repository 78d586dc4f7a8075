"""Gauss-Newton descent of the area-balancing energy on the plane or the sphere: a few sparse solves where the
Sobolev steps of :mod:`._balance` take hundreds.

The energy is :mod:`._balance`'s, ``E = sum_t a_t [log(A_t / a_t)^2 + beta (D_t / A_t - 2)]``. Each step
solves ``M d = -grad E`` with the Gauss-Newton metric

    ``M = sum_t 2 a_t / A_t^2 grad A_t grad A_t^T + beta a_t / A_t H_t``

(the log term's Gauss-Newton part and the angle term's convex part, ``H_t`` the triangle's cotangent
stencil: positive semi-definite triangle by triangle, so nothing is clamped). It grows like ``1 / A^2``
where the map squeezes, which is what the Sobolev steps' squeeze scaling imitates. On the plane the area
term's coupling of u and v is left out, so u and v are two scalar systems: a vertex held does not move,
one sliding along a side of the square (axis-aligned) moves in one of them. On the sphere each vertex moves
in its tangent plane, two unknowns along two tangents of its own, and the metric is one system of 2 x 2
blocks (tangent planes of neighbours are not parallel: nothing separates); the step is put back on the
sphere. The metric is assembled in numba into the mesh's fixed sparsity pattern and factored by qdldl
(:class:`._laplacian.SymmetricFactor`: its order found at the first step, later steps refactored).
Every accepted step keeps every triangle positive and lowers the energy (the step halved from the full one
until it does).

Far from a balanced map (a CAD fan squeezed to 1e-9 of the square, a triangle of no area) the quadratic
model is poor and the steps short: a step shorter than :data:`SHORTEST_STEP` of the full one, or an energy
that is not finite, *stalls* the descent, and the caller goes back to the Sobolev steps and single-vertex
sweeps, which open such maps.

Examples
--------
A square's four triangles round a centre pulled towards one corner: a few steps move it back.

>>> x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
>>> tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
>>> start = x.copy(); start[4, :2] = 0.3
>>> moves = np.array([False, False, False, False, True])
>>> out, steps, (e0, e1), stalled = newton_balance(start, x, tris, moves, np.zeros((5, 3)))
>>> stalled, steps <= 5, np.round(out[4], 4).tolist()
(False, True, [0.5, 0.5, 0.0])

An octahedron's map onto the sphere with one corner pushed aside: back to the balanced map.

>>> x = np.array([[1., 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
>>> tris = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
>>> start = x.copy(); start[4] = [0.3, 0.2, 1.0]; start[4] /= np.linalg.norm(start[4])
>>> out, steps, (e0, e1), stalled = newton_balance(start, x, tris, np.ones(6, bool), planar=False)
>>> stalled, bool(e1 < 1e-6 < e0), round(float(np.dot(out[4], out[5])), 6)
(False, True, -1.0)
"""
from __future__ import annotations

import numpy as np
from concurrent.futures import ThreadPoolExecutor

from scipy import sparse

from ._balance import lower_along, target_shares
from ._balance_kernels import (balance_energy, balance_gradient, gauss_newton_metric, gauss_newton_metric_sphere,
                               mapped_areas, step_to)
from ._laplacian import SymmetricFactor, corner_cotangents

__all__ = ["newton_balance", "slides_on_axes", "tangent_basis", "NEWTON_STEPS", "NEWTON_TOLERANCE", "SHORTEST_STEP"]

NEWTON_STEPS = 40          # steps at most
NEWTON_TOLERANCE = 1e-3    # ... stopping once a step lowers the energy by less than this share of it
SHORTEST_STEP = 1 / 256    # a step shorter than this share of the full one stalls the descent
FLOOR = 1e-9               # an energy this low is 0 (a balanced map's; rounding makes it -1e-17)
LOCAL_HALVINGS = 12        # a step's moves halved at most this many times round the triangles it turns over
RIDGE = 1e-10              # each metric's diagonal raised by this share of its mean: a solve where it is flat


def slides_on_axes(along: np.ndarray) -> bool:
    """Whether every sliding direction (a row of ``along`` that is not zero) is the u or the v axis, so that
    u and v are separate systems.

    >>> slides_on_axes(np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, 0]])), slides_on_axes(np.array([[0.6, 0.8, 0]]))
    (True, False)
    """
    on = np.asarray(along, np.float64)[:, :2] != 0.0
    return bool((on.sum(axis=1) <= 1).all())


def tangent_basis(s: np.ndarray) -> np.ndarray:
    """Two orthonormal tangents at each unit vector of ``s`` (n, 3), as the columns of (n, 3, 2): ``s x e``
    (``e`` the axis least along ``s``) and ``s x`` that.

    >>> b = tangent_basis(np.array([[0.0, 0.0, 1.0], [0.6, 0.8, 0.0]]))
    >>> bool(np.allclose(np.einsum("nij,nik->njk", b, b), np.eye(2)))
    True
    >>> bool(np.allclose(np.einsum("ni,nic->nc", np.array([[0.0, 0.0, 1.0], [0.6, 0.8, 0.0]]), b), 0))
    True
    """
    s = np.asarray(s, np.float64)
    axis = np.zeros_like(s)
    axis[np.arange(len(s)), np.argmin(np.abs(s), axis=1)] = 1.0
    first = np.cross(s, axis)
    first /= np.linalg.norm(first, axis=1, keepdims=True)
    return np.ascontiguousarray(np.stack([first, np.cross(s, first)], axis=2))


def _pattern(tris: np.ndarray, n: int, block: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sparsity pattern (CSR ``indptr, indices``) of the ``block n`` square matrices with the diagonal and
    an entry for every two unknowns of a triangle (vertex ``i``'s unknowns ``block i`` to ``block i + block - 1``), and
    ``slot`` (T, 3 block, 3 block): where each entry of a triangle's unknowns ``block k + c`` (corner ``k``)
    is in the values.
    """
    size = block * n
    unknowns = (block * np.asarray(tris, np.int64)[:, :, None] + np.arange(block)).reshape(len(tris), 3 * block)
    rows = np.repeat(unknowns, 3 * block, axis=1).ravel()
    cols = np.tile(unknowns, (1, 3 * block)).ravel()
    every = np.arange(size)          # every diagonal entry, a vertex on no triangle's too (its ridge alone)
    m = sparse.csr_matrix((np.ones(len(rows) + size), (np.concatenate([rows, every]), np.concatenate([cols, every]))),
                          shape=(size, size))
    m.sum_duplicates()
    m.sort_indices()
    keys = np.repeat(np.arange(size, dtype=np.int64), np.diff(m.indptr)) * size + m.indices
    slot = np.searchsorted(keys, rows * size + cols)
    return m.indptr, m.indices, slot.reshape(-1, 3 * block, 3 * block)


def _block(indptr: np.ndarray, indices: np.ndarray, keep: np.ndarray, n: int):
    """The pattern (CSC ``indptr, indices``) of the upper triangle of the block of rows and columns ``keep``,
    where its values are in the whole matrix's (so each step takes them without indexing a matrix), and where
    its diagonal is in its own values.
    """
    numbered = sparse.csr_matrix((np.arange(1.0, len(indices) + 1.0), indices, indptr), shape=(n, n))
    block = sparse.triu(numbered[keep][:, keep], format="csc")
    block.sort_indices()
    columns = np.repeat(np.arange(len(block.indptr) - 1), np.diff(block.indptr))
    return block.indptr, block.indices, block.data.astype(np.int64) - 1, np.flatnonzero(block.indices == columns)


def _metric_block(block, values: np.ndarray) -> sparse.csc_matrix:
    """The upper triangle (CSC, :func:`_block`'s pattern) of the block of the metric with the given values,
    its diagonal raised by :data:`RIDGE` of its mean (a solve where the metric is flat).
    """
    indptr, indices, take, diagonal = block
    k = len(indptr) - 1
    data = values[take]
    data[diagonal] += RIDGE * max(float(data[diagonal].mean()), 1e-300)
    return sparse.csc_matrix((data, indices, indptr), shape=(k, k))


def _factor(block, values: np.ndarray, factor: SymmetricFactor | None = None) -> SymmetricFactor:
    """The factored :func:`_metric_block`; ``factor``: the block's factor of an earlier step, refactored in
    place (its order kept).
    """
    upper = _metric_block(block, values)
    return SymmetricFactor(upper) if factor is None else factor.refactor(upper)


def lower_locally(s, d, e, tris, a, cot, beta, planar, shortest: float = SHORTEST_STEP):
    """The lowest energy along the steps ``s + alpha d`` (on the sphere, put back on it), ``alpha`` 1, 1/2, 1/4,
    ... down to ``shortest``: where a step turns triangles over, only their corners' moves are halved (at
    most :data:`LOCAL_HALVINGS` times) rather than the whole step, so that a few squeezed triangles do not
    hold back every vertex. ``(map, energy, state, alpha)`` of the first step whose energy is lower than
    ``e`` and than the next shorter step's, or None where none is lower than ``e``.
    """
    scale = np.ones(len(s))
    best = None
    alpha = 1.0
    while alpha >= shortest:
        trial = np.empty_like(s)
        for _ in range(LOCAL_HALVINGS):
            step_to(s, d * scale[:, None], alpha, planar, trial)
            area, bad = mapped_areas(trial, tris, planar)
            if not bad:
                break
            scale[np.unique(tris[~(area > 0.0)])] *= 0.5
        e_new, state = balance_energy(trial, tris, a, cot, beta, planar)
        if best is not None and not e_new < best[1]:
            return best
        if e_new < e:
            best = (trial, e_new, state, alpha)
        alpha *= 0.5
        scale[:] = 1.0
    return best


def newton_balance(s, x, tris, moves, along=None, *, planar: bool = True, beta: float = 0.3, shares=None,
                   steps: int = NEWTON_STEPS, tolerance: float | None = None, progress=None, cache: dict | None = None):
    """Gauss-Newton descent of the balancing energy from ``s``: points ``(u, v, 0)`` on the plane, or with
    ``planar`` false unit vectors on the sphere.

    Parameters
    ----------
    s : (n, 3) float
        The map, counter-clockwise (on the sphere: every chord triangle facing out); left as it is.
    x, tris : the mesh's vertices (n, 3) and triangles (T, 3).
    moves : (n,) bool
        The vertices that move.
    along : (n, 3) float, optional
        On the plane: a direction per vertex that may only slide along it, the u or the v axis (zero rows
        move freely; see :func:`slides_on_axes`). None on the sphere.
    planar : bool, default True
        A map onto the plane rather than the sphere.
    beta, shares : as for :func:`._balance.balance`.
    steps : int
        Steps at most; the descent stops sooner once a step lowers the energy by less than ``tolerance``
        (:data:`NEWTON_TOLERANCE` by default) of itself.
    progress : callable, optional
        Hears each step's energy.
    cache : dict, optional
        Keeps the mesh's sparsity pattern for the next call with the same triangles (a disk's starts and
        their relaxing go on one mesh), as :func:`._balance.balance` keeps its Sobolev factor.

    Returns
    -------
    s, steps taken, (energy at the start, energy at the end), stalled
        ``stalled``: the energy was not finite, or a step had to be shorter than :data:`SHORTEST_STEP` of
        the full one while the quadratic model promised more than ``tolerance`` of the energy (the map so
        far is returned; the caller goes back to the Sobolev steps).
    """
    s = np.array(s, dtype=np.float64)
    tris = np.ascontiguousarray(tris, np.int64)
    tolerance = NEWTON_TOLERANCE if tolerance is None else float(tolerance)
    moves = np.asarray(moves, bool)
    n = len(s)
    if planar:
        along = np.zeros((n, 3)) if along is None else np.asarray(along, np.float64)
        if not slides_on_axes(along):
            raise ValueError("along: every sliding direction must be the u or the v axis")
        slides = np.any(along[:, :2] != 0.0, axis=1)
        unknowns = [np.flatnonzero(moves & (~slides | (along[:, c] != 0.0))) for c in range(2)]
    elif along is not None and np.any(along):
        raise ValueError("along: a vertex on the sphere moves in its tangent plane, not along a line")
    a, cot = target_shares(x, tris, shares), corner_cotangents(x, tris)
    e, state = balance_energy(s, tris, a, cot, beta, planar)
    e_start = e
    if not np.isfinite(e):
        return s, 0, (e, e), True
    if steps <= 0 or not (any(len(k) for k in unknowns) if planar else moves.any()):
        return s, 0, (e, e), False
    cache = {} if cache is None else cache
    if planar:
        if "newton_pattern" not in cache:
            cache["newton_pattern"] = _pattern(tris, n)
        indptr, indices, slot = cache["newton_pattern"]
    else:
        if "newton_sphere_pattern" not in cache:
            cache["newton_sphere_pattern"] = _pattern(tris, n, 2)
        indptr, indices, slot = cache["newton_sphere_pattern"]
        unknowns = [(2 * np.flatnonzero(moves)[:, None] + np.arange(2)).ravel()]
    block = 1 if planar else 2
    blocks = [_block(indptr, indices, k, block * n) for k in unknowns]
    values = [np.empty(len(indices)) for _ in unknowns]

    factors: list = [None] * len(unknowns)      # each block's factor, refactored step after step

    def solve(c, rhs):
        factors[c] = _factor(blocks[c], values[c], factors[c])
        return factors[c].solve(rhs)

    def planar_direction(pool, g):
        gauss_newton_metric(s, tris, a, cot, float(beta), slot, values[0], values[1])
        d = np.zeros_like(s)
        solving = [(c, pool.submit(solve, c, -g[unknowns[c], c])) for c in range(2) if len(unknowns[c])]
        for c, job in solving:
            d[unknowns[c], c] = job.result()
        return d

    def sphere_direction(pool, g):
        basis = tangent_basis(s)
        gauss_newton_metric_sphere(s, tris, a, cot, float(beta), basis, slot, values[0])
        along_tangents = np.einsum("nic,ni->nc", basis, g).ravel()
        delta = np.zeros(2 * n)
        delta[unknowns[0]] = solve(0, -along_tangents[unknowns[0]])
        return np.einsum("nic,nc->ni", basis, delta.reshape(n, 2))

    direction = planar_direction if planar else sphere_direction
    columns = 2 if planar else 3
    # on the plane u and v factored side by side: qdldl lets go of the interpreter while it factors (the
    # pair 1.3-1.8x faster on two cores; each factor the same bits as alone)
    with ThreadPoolExecutor(max_workers=2) as pool:
        for step in range(steps):
            g = balance_gradient(s, tris, a, cot, beta, state)
            d = direction(pool, g)
            found = (lower_along(s, d, 1.0, e, tris, a, cot, beta, planar, above=SHORTEST_STEP / 2) if planar else
                     lower_locally(s, d, e, tris, a, cot, beta, planar))
            if found is None:        # no lower energy: at the minimum (the model's decrease is tiny), or stalled
                predicted = -0.5 * float(np.add.reduce((g[:, :columns] * d[:, :columns]).ravel()))
                return s, step, (e_start, e), not predicted < tolerance * max(e, FLOOR)
            converged = e - found[1] < tolerance * max(e, FLOOR)
            s, e, state, _ = found
            if progress is not None:
                progress(f"Gauss-Newton step {step}: energy {e:.4f}")
            if converged:
                return s, step + 1, (e_start, e), False
        return s, steps, (e_start, e), False
