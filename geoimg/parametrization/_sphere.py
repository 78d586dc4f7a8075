"""Spherical parametrization of a closed genus-0 mesh: a one-to-one map of its vertices onto the unit sphere.

1. Linear conformal map (Angenent et al. 1999; Haker et al. 2000): one triangle ``f0`` is punctured and
   the (floored, positive) cotangent Laplacian is solved with a dipole at ``f0``, which maps the mesh
   onto the plane with ``f0`` at infinity.
2. The inverse stereographic projection puts it on the sphere, and Moebius transformations move the
   area-weighted centre of the vertices to the sphere's centre (the "centring" of Springborn; Baden,
   Crane & Kazhdan 2018).
3. Area balancing. A conformal map shrinks ears and limbs exponentially (the bunny's ears get a
   thousandth of their share of the sphere). A descent on
   ``E = sum_t a_t [log(r_t)^2 + beta (D_t / A_t - 2)]`` (``r_t`` a triangle's share of the sphere over
   its share of the mesh; ``D_t / A_t - 2`` its conformal distortion, the Dirichlet energy over the
   area) moves the vertices on the sphere. Gradients are smoothed by the mesh's Laplacian (a Sobolev
   preconditioner: limbs move as a whole); every other step is also scaled by each squeezed vertex's
   linear scale, so a squeezed part grows by a fraction of its own size. Every step that would turn a
   triangle over is halved until none does, so the map stays one-to-one. Then sweeps of single-vertex moves
   (each vertex in turn down its own triangles' energy, as far as they stay positive) open what one squeezed
   triangle held back, and the balancing goes on from there (:func:`._balance.settle`).
   A map of at most :data:`NEWTON_VERTICES` vertices made directly is balanced by Gauss-Newton steps
   instead (:func:`._newton.newton_balance`: each vertex moves in its tangent plane, a sparse solve a step,
   a step that would turn triangles over cut round them alone), 4-40 steps where the Sobolev steps take
   26-470; where those steps stall, the Sobolev steps and sweeps balance it as before. A conformal map
   that folds a few triangles (:data:`CONFORMAL_FOLDS_OPENED`) is then kept with its folds opened.
   A mesh of 20,000 triangles or more starts instead from the balanced map of a decimated copy of itself
   (:mod:`._multilevel`), which needs only a few fine steps and no sweeps: the slow part of the balancing,
   opening the squeezed ears and limbs, happens on the coarse copy. A shape whose direct maps fold, or whose
   conformal map folds (the mean-value map taken instead squeezes too much for the balancing to undo), is
   mapped coarse to fine (:mod:`._progressive`), balanced at every size (a few Gauss-Newton steps, or Sobolev
   steps and sweeps where those stall); so is such a decimated copy.
   The final balancing aims each triangle at its share of the *image* rather than of the area: its area
   times the cube root of its bending (:mod:`._sampling_shares`), the density that makes the resampling
   error least, so the parts that bend get the pixels the flat parts do not need.
4. A rotation lines the sphere up with the mesh (vertex directions from the mesh's centre), so the
   octahedral image shows the shape the way it stands; then the turn of the sphere whose octahedral image
   samples the bent parts best is taken (:func:`._octahedral.sampling_rotation`).
"""
from __future__ import annotations


import numpy as np
from scipy import sparse

from ..errors import InputError, ParametrizationError
from ..mesh import Mesh, topology
from ._balance import DEFAULT_STEPS, SWEEPS, balance, relax_locally, settle, sobolev_factor_later
from ._laplacian import (corner_angles, cotangent_weights, factor_symmetric, laplacian, mean_value_weights, solve_free,
                         triangle_areas, vertex_areas)
from ._multilevel import UNTANGLE_RINGS, multilevel_start, open_folds
from ._newton import newton_balance
from ._octahedral import sampling_rotation
from ._orientation import chord_orientation, facing_out
from ._progressive import progressive_sphere
from ._sampling_shares import bending_weight, sampling_shares
from .._types import Progress

__all__ = ["sphere_coords", "mobius_centre", "distortion", "chord_orientation"]

DEFAULT_BETA = 0.3
MULTILEVEL_TRIANGLES = 20_000     # from this size on, a decimated copy is mapped first ...
MULTILEVEL_STEPS = 30             # ... and the fine map balanced from it for at most this many steps, not
MULTILEVEL_SWEEP_ROUNDS = 0       # swept (10 steps, 60 sweeps, 10 steps: 1.3-2.0x slower, +0.1 dB on average)
SPHERE_SWEEP_ROUNDS = 1           # the final balancing: then sweeps and balancing again (armadillo +0.9 dB)
CONFORMAL_FOLDS_OPENED = 16      # a conformal map folding at most this many triangles is opened (_direct_start) ...
CONFORMAL_OPENED_FROM = 1_000     # ... on a mesh of at least this many triangles, at once in the widest
CONFORMAL_RINGS = UNTANGLE_RINGS[-1:]   # neighbourhood the untangling tries (the narrower ones failed on every
                                        # conformal map measured, 0.6-1.8 s lost on each)
NEWTON_VERTICES = 20_000          # a direct map of at most this many vertices: Gauss-Newton steps first (each
                                  # factors a 2n x 2n metric: bunny.off's 35k vertices 1.3 s, homer's 6k 0.06 s)
RELAX_STEPS = 30                  # the coarse-to-fine map's balancing at each size: steps of all vertices,
                                  # then SWEEPS sweeps of single-vertex moves (what the squeezed parts need)
PROGRESSIVE_NEWTON = True         # ... unless Gauss-Newton steps, at most PROGRESSIVE_NEWTON_STEPS, do not stall
PROGRESSIVE_NEWTON_STEPS = 4      # (human_man 3.04 -> 1.77 s, +0.23 dB; 2 steps: the scorpion -3.8 dB)


def _fold_count(s: np.ndarray, tris: np.ndarray) -> int:
    """How many triangles the map ``s`` turns over (or flattens) on the sphere."""
    return int(np.sum(chord_orientation(s, tris) <= 0))


def _check_sphere(mesh: Mesh):
    topo = topology(mesh)
    if not (topo.closed and topo.components == 1 and topo.genus == 0):
        raise ParametrizationError(
            f"method='sphere' needs a closed genus-0 mesh in one piece; the mesh is a {topo.describe()}")


def _inverse_stereographic(z: np.ndarray) -> np.ndarray:
    r2 = (z ** 2).sum(axis=1, keepdims=True)
    return np.hstack([2.0 * z, r2 - 1.0]) / (r2 + 1.0)


def mobius_centre(s: np.ndarray, weights: np.ndarray, *, tol: float = 1e-10, max_steps: int = 500) -> np.ndarray:
    """Apply Moebius transformations of the sphere until the weighted centre of the points ``s`` is 0.

    Uses ``phi_a(x) = (1 - |a|^2)(x - a) / |x - a|^2 - a``, which maps the sphere onto itself and
    spreads out the points near ``a``; ``a`` is half the current centre at each step.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> x = rng.normal(size=(500, 3)) + [0, 0, 3]
    >>> x /= np.linalg.norm(x, axis=1, keepdims=True)
    >>> c = mobius_centre(x, np.ones(500))
    >>> bool(np.linalg.norm(c.mean(axis=0)) < 1e-9), bool(np.allclose(np.linalg.norm(c, axis=1), 1))
    (True, True)
    """
    x = np.array(s, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64) / np.sum(weights)
    for _ in range(max_steps):
        mu = w @ x
        norm = np.linalg.norm(mu)
        if norm < tol:
            break
        a = 0.5 * mu
        d = x - a
        x = (1.0 - a @ a) * d / (d ** 2).sum(axis=1, keepdims=True) - a
        x /= np.linalg.norm(x, axis=1, keepdims=True)
    return x


def distortion(mesh_xyz: np.ndarray, s: np.ndarray, tris: np.ndarray, *, angles: bool = True) -> dict:
    """Area and angle distortion of a map of triangles onto the sphere (chord triangles).

    ``area_ratio`` of a triangle is its share of the sphere's area over its share of the mesh's; 1 is
    area-preserving. Angle distortion is the mean of ``|angle on sphere - angle on mesh|`` in degrees (left
    out when ``angles`` is false: it costs most of the time).
    """
    a3, a2 = triangle_areas(mesh_xyz, tris), triangle_areas(s, tris)
    ratio = (a2 / a2.sum()) / np.maximum(a3 / a3.sum(), 1e-300)
    w = a3 / a3.sum()
    lr = np.log(np.maximum(ratio, 1e-300))
    out = {
        "area_ratio_min": float(ratio.min()), "area_ratio_max": float(ratio.max()),
        "area_ratio_p01": float(np.percentile(ratio, 1)), "area_ratio_p99": float(np.percentile(ratio, 99)),
        "area_log_rms": float(np.sqrt(w @ lr ** 2)),
    }
    if angles:
        dang = np.degrees(np.abs(corner_angles(s, tris) - corner_angles(mesh_xyz, tris)))
        out.update(angle_error_mean_deg=float(dang.mean()), angle_error_max_deg=float(dang.max()))
    return out


def _align(s: np.ndarray, x: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Rotate the sphere so that ``s_i`` best matches the directions of ``x_i`` from their weighted centre."""
    d = x - w @ x / w.sum()
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    h = (s * w[:, None]).T @ d
    u, _, vt = np.linalg.svd(h)
    k = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T))])
    return s @ (vt.T @ k @ u.T).T


def _pick_removed_face(x: np.ndarray, tris: np.ndarray) -> int:
    area = triangle_areas(x, tris)
    e = np.linalg.norm(x[np.roll(tris, -1, axis=1)] - x[tris], axis=2)
    quality = 4.0 * np.sqrt(3.0) * area / np.maximum((e ** 2).sum(axis=1), 1e-300)   # 1 = equilateral
    good = quality >= 0.8 * quality.max()
    return int(np.flatnonzero(good)[np.argmax(area[good])])


def _conformal_plane(x: np.ndarray, tris: np.ndarray, lap: sparse.csc_matrix, f0: int, keep: np.ndarray):
    """Solve ``L z = b`` with the dipole of face ``f0`` on its corners (Haker et al. 2000, eq. 6-8)."""
    ia, ib, ic = tris[f0]
    a, b, c = x[ia], x[ib], x[ic]
    ab = np.linalg.norm(b - a)
    theta = (c - a) @ (b - a) / ab ** 2
    height = np.linalg.norm(c - (a + theta * (b - a)))
    rhs = np.zeros((len(x), 2))
    rhs[ia, 0], rhs[ib, 0] = -1.0 / ab, 1.0 / ab
    rhs[ia, 1], rhs[ib, 1], rhs[ic, 1] = (1.0 - theta) / height, theta / height, -1.0 / height
    # L is singular (constants): pin the vertex farthest from f0 at the origin
    idx = np.flatnonzero(keep)
    pin = idx[np.argmax(np.linalg.norm(x[idx] - a, axis=1))]
    free = idx[idx != pin]
    z = np.zeros((len(x), 2))
    z[free] = factor_symmetric(lap[free][:, free]).solve(rhs[free])
    return z


def _tutte_plane(x: np.ndarray, tris: np.ndarray, f0: int, keep: np.ndarray):
    """Pin ``f0``'s corners to an equilateral triangle and place every other vertex at the mean-value-weighted
    mean of its neighbours: a planar embedding whatever the mesh (Floater 2003), used when the conformal
    map folds triangles over.
    """
    fixed = tris[f0]
    ang = -np.pi / 2 - 2 * np.pi * np.arange(3) / 3
    pos = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    is_fixed = np.zeros(len(x), bool)
    is_fixed[fixed] = True
    free = np.flatnonzero(keep & ~is_fixed)
    z = np.zeros((len(x), 2))
    z[fixed] = pos
    z[free] = solve_free(mean_value_weights(x, tris), fixed, pos, free)
    return z


def _plane_to_sphere(z: np.ndarray, vertex_area: np.ndarray, used: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Inverse stereographic projection (half the mesh's area inside the equator), centred, faces outward."""
    z = z - vertex_area @ z / vertex_area.sum()
    r = np.linalg.norm(z, axis=1)
    order = np.argsort(r)
    cum = np.cumsum(vertex_area[order])
    radius = max(r[order][np.searchsorted(cum, cum[-1] / 2)], 1e-300)
    s = np.zeros((len(z), 3))
    s[:, 2] = 1.0
    idx = np.flatnonzero(used)
    s[idx] = mobius_centre(_inverse_stereographic(z[idx] / radius), vertex_area[idx] + 1e-12 * vertex_area.max())
    return facing_out(s, tris)


def _tutte_sphere(z: np.ndarray, used: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """A planar Tutte embedding on the sphere, its pinned triangle's corners at height 0.9: the removed
    face becomes a small cap round the north pole, so every face's chord triangle keeps the orientation
    it has in the plane (no centring: a Moebius map could blow the cap up past a hemisphere).
    """
    h = 0.9
    s = np.zeros((len(z), 3))
    s[:, 2] = 1.0
    idx = np.flatnonzero(used)
    s[idx] = _inverse_stereographic(z[idx] / np.sqrt((1 - h) / (1 + h)))
    return facing_out(s, tris)


def _direct_start(x, tris, used, vertex_area, lap, *, newton: bool = False):
    """The conformal map, or the mean-value (Tutte) embedding where that folds; (s, name, removed face).
    ``newton``: the map is to be balanced by Gauss-Newton steps (:func:`_newton_balanced`), so a conformal map
    that folds at most :data:`CONFORMAL_FOLDS_OPENED` triangles of a mesh of at least
    :data:`CONFORMAL_OPENED_FROM` is kept with them opened (:func:`open_folds`) where that works: those steps
    balance it as well and sooner than the mean-value map coarse to fine (a bunny of 17,800 faces, one
    triangle folded: 6.2 -> 2.8 s, 82.92 -> 82.99 dB at 257^2), where 200 Sobolev steps balanced it 0.8 dB
    worse. A smaller mesh goes coarse to fine in under a second, and better: Spot's 360-triangle control
    mesh 0.8-1.3 dB, the fish's 0.2-0.8 dB.
    """
    f0 = _pick_removed_face(x, tris)
    s = _plane_to_sphere(_conformal_plane(x, tris, lap, f0, used), vertex_area, used, tris)
    folded = int(np.sum(chord_orientation(s, tris) <= 0))
    if newton and 0 < folded <= CONFORMAL_FOLDS_OPENED and len(tris) >= CONFORMAL_OPENED_FROM and _newton_sized(used):
        opened, _, ok = open_folds(s, tris, CONFORMAL_RINGS)
        if ok:
            return opened, "conformal", f0
    if folded:
        z = _tutte_plane(x, tris, f0, used)
        # two ways onto the sphere: centred (spreads a crowded layout) or with the removed face a small cap
        # (keeps every big face's orientation); the one folding fewer triangles is taken
        ways = [_plane_to_sphere(z, vertex_area, used, tris), _tutte_sphere(z, used, tris)]
        folds = [_fold_count(w, tris) for w in ways]
        return ways[int(np.argmin(folds))], "mean-value", f0
    return s, "conformal", f0


def _direct_balanced(xs, t, beta, steps, *, decimated_copy=False):
    """A small mesh (every vertex on a triangle) mapped directly, then balanced (:func:`_newton_balanced`, or
    ``steps`` Sobolev steps where those stall). As a ``decimated_copy``
    (:func:`_decimated_map`): None where the direct maps fold, and coarse to fine first where
    :func:`_wants_coarse_to_fine` (kept where that folds nothing).
    """
    used = np.ones(len(xs), bool)
    va = vertex_areas(xs, t)
    lap = laplacian(cotangent_weights(xs, t))
    sc, start, _ = _direct_start(xs, t, used, va, lap, newton=True)
    if decimated_copy:
        if _fold_count(sc, t):
            return None
        if _wants_coarse_to_fine(start, 0):
            sp, _ = progressive_sphere(xs, t, used, _coarse_map(xs, beta), _relax(xs, beta))
            if not _fold_count(sp, t):
                sc = sp
    newton = _newton_balanced(sc, xs, t, used, beta, None, None)
    if newton is not None:
        return newton[0]
    sc, _, _ = balance(sc, xs, t, lap, va, used, float(beta), steps, None)
    return sc


def _newton_sized(used: np.ndarray) -> bool:
    """Whether a map of the vertices ``used`` is small enough for Gauss-Newton steps (:data:`NEWTON_VERTICES`)."""
    return int(np.count_nonzero(used)) <= NEWTON_VERTICES


def _newton_balanced(s, x, tris, used, beta, shares, progress):
    """The map balanced by Gauss-Newton steps (:func:`._newton.newton_balance`): ``(map, steps, energies)``,
    or None where the mesh has more than :data:`NEWTON_VERTICES` vertices or the steps stall.
    """
    if not _newton_sized(used):
        return None
    out, steps, energy, stalled = newton_balance(s, x, tris, used, planar=False, beta=float(beta), shares=shares,
                                                 progress=progress)
    return None if stalled else (out, steps, energy)


def _coarse_map(x, beta):
    """Map a coarse mesh (vertices ``alive`` of ``x``, triangles ``coarse``) directly, then balance it."""
    def run(alive, coarse):
        idx = np.flatnonzero(alive)
        remap = np.full(len(x), -1)
        remap[idx] = np.arange(len(idx))
        sc = _direct_balanced(x[idx], remap[coarse], beta, DEFAULT_STEPS)
        s = np.zeros((len(x), 3))
        s[:, 2] = 1.0
        s[idx] = sc
        return s
    return run


def _wants_coarse_to_fine(start: str, folds: int) -> bool:
    """Whether a shape is mapped coarse to fine (:func:`progressive_sphere`) after its direct map ``start``,
    which folds ``folds`` triangles: where it folds, and where the conformal map folded and the mean-value
    (Tutte) map was taken. That map squeezes what sticks out exponentially and the balancing stalls there:
    the bust of Nefertiti's coarse copy (8,000 triangles) balanced from it kept a log area ratio of RMS 2.7
    (triangles given a hundredth of their share and a thousand times it), 0.28 mapped coarse to fine; its
    image at 257^2 60.3 -> 83.5 dB.
    """
    return folds > 0 or start == "mean-value"


def _decimated_map(beta):
    """The map of a decimated copy (:func:`multilevel_start`): direct and balanced until it has converged (coarse
    to fine where :func:`_wants_coarse_to_fine`), or None where the direct maps fold (mapping the copy coarse
    to fine instead was measured on the sword: its transfer to the fine mesh left 1,910 folds that did not
    open, 10 s lost before the fine mesh's own coarse-to-fine map).
    """
    def run(U, G):
        return _direct_balanced(U, G, beta, None, decimated_copy=True)
    return run


def _open_folds(s, tris):
    """The last stage: open the folds a map still has (:func:`open_folds`); the map and what was done (None
    where nothing was folded).
    """
    folds = _fold_count(s, tris)
    if not folds:
        return s, None
    out, _, opened = open_folds(s, tris)
    if not opened:               # no worse than it came: keep whichever folds fewer
        left = _fold_count(out, tris) if np.isfinite(out).all() else folds
        if left < folds:
            return out, f"untangle ({left} of {folds} still folded)"
        return s, f"untangle failed ({folds} folded)"
    return out, f"untangled ({folds} folded)"


def _relax(x, beta, steps: int = RELAX_STEPS, sweeps: int = SWEEPS):
    """Area-balance the map of an intermediate mesh (the vertices ``alive``, triangles ``tris``): steps of all
    vertices at once, then sweeps of single-vertex moves, which open what one squeezed triangle holds back
    (a blade's tip given a hundredth of its share: 68 dB -> 81 dB through the sword's map at 257^2); unless
    (:data:`PROGRESSIVE_NEWTON`) at most :data:`PROGRESSIVE_NEWTON_STEPS` Gauss-Newton steps do it without
    stalling.
    """
    def run(s, alive, tris):
        if PROGRESSIVE_NEWTON and _newton_sized(alive):
            out, _, _, stalled = newton_balance(s, x, tris, alive, planar=False, beta=float(beta),
                                                steps=PROGRESSIVE_NEWTON_STEPS)
            if not stalled:
                return out
        out, _, _ = balance(s, x, tris, used=alive, beta=float(beta), steps=steps)   # its own Laplacian, areas
        return relax_locally(out, x, tris, alive, float(beta), sweeps)
    return run


def sphere_coords(mesh: Mesh, *, steps: int | None = None, beta: float = DEFAULT_BETA,
                  progress: Progress | None = None) -> tuple[np.ndarray, dict]:
    """Unit vectors of a closed genus-0 mesh's vertices: a spherical parametrization.

    Parameters
    ----------
    mesh : Mesh
        Closed, one component, genus 0; mapped as the image samples it: quads split along their shorter
        diagonal, larger polygons into fans.
    steps : int, optional
        Area-balancing steps at most (0: the centred, nearly conformal map); the balancing stops sooner
        when it has converged. Default: 200, or on a mesh of T < 10,000 triangles as many as 2,000,000 / T
        (at most 2,000), which costs no more than 200 steps on 10,000 triangles and lets small meshes
        converge. By default a mesh of at least 20,000 triangles (``MULTILEVEL_TRIANGLES``), every vertex on
        one, is first mapped through a decimated copy (:mod:`._multilevel`: coarse to fine where the copy's
        conformal map folds), balanced there until it has converged, and the fine map then takes at most
        30 steps (``MULTILEVEL_STEPS``) from it, not swept; where that gives no one-to-one start, the direct
        maps are used, and coarse to fine where the conformal map folds. By default the balancing of a map
        made otherwise is followed by single-vertex sweeps and balanced again (``SPHERE_SWEEP_ROUNDS``); a
        map made directly (not from the coarse copy) of at most ``NEWTON_VERTICES`` vertices is balanced by
        Gauss-Newton steps instead (the Sobolev steps and sweeps where they stall). Given ``steps``, the
        decimated copy is not used, no Gauss-Newton steps are taken, and the balancing is not swept.
    beta : float, default 0.3
        Weight of angle (conformal) distortion against area distortion while balancing.
    progress : callable, optional
        Called with a short message every ten steps.

    Returns
    -------
    coords : (N, 3) float64
        Unreferenced vertices get (0, 0, 1).
    info : dict
        ``flipped_triangles``, ``balance_steps``, ``start`` (``"multilevel"``, ``"conformal"``,
        ``"mean-value"`` or ``"progressive"``), ``stages`` (each stage that ran, with the folds it left:
        the coarse copy, the direct map, coarse to fine, the opening of folds), ``start_area_log_rms`` and
        the distortion figures of
        :func:`distortion`; ``multilevel`` says whether the coarse copy was used, or why not;
        ``gauss_newton`` whether Gauss-Newton steps balanced the map.

    Raises
    ------
    ParametrizationError
        If the mesh is not a closed genus-0 surface in one piece.

    Examples
    --------
    >>> t = (1 + 5 ** 0.5) / 2   # an icosahedron
    >>> v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
    ...      [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    >>> f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
    ...      [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
    ...      [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    >>> s, info = sphere_coords(Mesh(v, f))
    >>> info["flipped_triangles"], bool(np.allclose(np.linalg.norm(s, axis=1), 1))
    (0, True)
    """
    _check_sphere(mesh)
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0):
        raise InputError(f"steps: expected an integer >= 0, got {steps!r}")
    if not (isinstance(beta, (int, float, np.number)) and np.isfinite(beta) and beta >= 0):
        raise InputError(f"beta: expected a number >= 0, got {beta!r}")
    asked = steps
    x = mesh.vertices
    tris, _ = mesh.triangulate(quads="shorter")
    used = mesh.referenced_vertices()
    vertex_area = vertex_areas(x, tris)
    lap = laplacian(cotangent_weights(x, tris))
    info: dict = {}
    stages: list[str] = []
    s = None
    cache: dict | None = None
    if steps is None and len(tris) >= MULTILEVEL_TRIANGLES and used.all():
        if progress is not None:
            progress(f"{len(tris)} triangles: mapping a coarse copy first")
        cache = sobolev_factor_later(x, tris, used, lap, vertex_area)   # made beside the coarse copy's map
        s, extra = multilevel_start(x, tris, _decimated_map(beta), progress=progress)
        info.update(extra)
        stages.append("multilevel" if s is not None else f"multilevel ({extra['multilevel']})")
        if s is not None:
            start, f0, steps = "multilevel", None, MULTILEVEL_STEPS
        elif progress is not None:
            progress(f"no start from the coarse copy ({extra['multilevel']}): the direct maps")
    if s is None:
        s, start, f0 = _direct_start(x, tris, used, vertex_area, lap, newton=asked is None)
        folds = _fold_count(s, tris)
        stages.append(start if not folds else f"{start} ({folds} folded)")
        if _wants_coarse_to_fine(start, folds):
            if progress is not None:
                progress(f"the direct maps fold {folds} triangles: mapping coarse to fine" if folds else
                         "the conformal map folds: mapping coarse to fine")
            sp, extra = progressive_sphere(x, tris, used, _coarse_map(x, beta), _relax(x, beta), progress=progress)
            info.update(extra, direct_folds=folds)
            left = _fold_count(sp, tris)
            stages.append("progressive" if not left else f"progressive ({left} folded)")
            if left < folds or not left:          # keep whichever folds fewer triangles, coarse to fine on a tie at 0
                s, start = sp, "progressive"
    s, opened = _open_folds(s, tris)
    if opened is not None:
        stages.append(opened)
    info["stages"] = stages
    idx = np.flatnonzero(used)
    first = distortion(x, s, tris, angles=False)   # of the starting map
    if start in ("conformal", "mean-value"):
        info.update(conformal_area_ratio_min=first["area_ratio_min"], conformal_area_ratio_max=first["area_ratio_max"])
    rounds = (0 if asked is not None else                          # given steps, the plain balancing alone
              MULTILEVEL_SWEEP_ROUNDS if start == "multilevel" else SPHERE_SWEEP_ROUNDS)
    bend = bending_weight(x, tris)          # each triangle's share of the image: more where the surface bends
    shares = sampling_shares(x, tris, bend)
    # by Gauss-Newton steps unless steps were asked, or the map is the coarse copy's (10 Sobolev steps and
    # sweeps finish that sooner: the fish 1.8 against 3.4 s, the same image)
    direct = asked is None and start != "multilevel"
    newton = _newton_balanced(s, x, tris, used, beta, shares, progress) if direct else None
    if newton is not None:
        s, done, energy = newton
    else:
        s, done, energy = settle(s, x, tris, rounds, lap, vertex_area, used, float(beta), steps, progress,
                                 shares=shares, cache=cache)
    info["gauss_newton"] = newton is not None
    s[idx] = _align(s[idx], x[idx], vertex_area[idx])
    turn, gain = sampling_rotation(s, x, tris, bend)     # the octahedral image's best sampling of the mesh
    s[idx] = s[idx] @ turn.T
    info["sampling_gain_db"] = gain
    det = chord_orientation(s, tris)
    info.update({"flipped_triangles": int(np.sum(det <= 0)), "balance_steps": done, "removed_face": f0,
                 "start": start, "start_area_log_rms": first["area_log_rms"], "balance_energy": energy})
    info.update(distortion(x, s, tris))
    return s, info
