"""Disk parametrization: a mesh with one boundary loop onto the unit square (or its own convex outline).

The boundary goes to the square's sides by arc length, with the four corners at boundary vertices
chosen to be the sharpest turns near quarter lengths of the loop, and so that no face has all its
corners on one side (which would flatten it). When no choice avoids that (a boundary with more than
four "ears"), the sides are bowed out by 2 % at their middles, so the outline is strictly convex and no
face is flat; the pixels outside the bowed square are masked. The interior follows from Floater's mean-value
coordinates: every free vertex is the mean-value-weighted mean of its neighbours. The weights are
positive and the boundary convex, so no triangle folds over (Floater 2003). The mean-value map squeezes
what sticks out (a finger's area shrinks about geometrically along it), so by default the area balancing
of the sphere's map (:mod:`._balance`) then evens the area out, the boundary vertices sliding along the
square's straight sides with the corners held, every step fold-free; ``balance="slim"`` runs libigl's SLIM
with the boundary held instead (:mod:`._slim`).
"""
from __future__ import annotations

import numpy as np

from .._choices import DEFAULT_DISK_BALANCE, DISK_BALANCES, DISK_BOUNDARIES
from .._types import Progress
from ..errors import ParametrizationError
from ..mesh import Mesh, boundary_loops, topology
from ._balance import settle
from ._laplacian import corner_angles, mean_value_weights, planar_cross, solve_free, triangle_areas, uniform_weights
from ._newton import NEWTON_STEPS, newton_balance, slides_on_axes
from ._slim import area_log_rms, relax

__all__ = ["disk_coords", "relax_planar", "DISK_BOUNDARIES", "DISK_BALANCES"]

_CANDIDATE_STARTS = 24
BULGE = 0.02


def _check_disk(mesh: Mesh):
    topo = topology(mesh)
    if not (
        topo.nonmanifold_edges == 0
        and topo.nonmanifold_vertices == 0
        and topo.components == 1
        and topo.boundary_loops == 1
        and topo.genus == 0
    ):
        raise ParametrizationError(
            f"method='disk' needs one boundary loop around a single genus-0 piece; the mesh is a {topo.describe()}")


def _interior_angle_sums(mesh: Mesh, tris: np.ndarray) -> np.ndarray:
    return np.bincount(tris.ravel(), corner_angles(mesh.vertices, tris).ravel(), minlength=mesh.n_vertices)


def _square_positions(t: np.ndarray, corners: np.ndarray, total: float, bulge: float = 0.0) -> np.ndarray:
    """Points on the unit square's outline (counter-clockwise from (0, 0)) for arc positions ``t`` of
    the loop, with the four ``corners`` (arc positions, increasing from 0) going to the square's corners.
    ``bulge`` > 0 bows each side outwards by that much at its middle (a parabola), which makes the
    outline strictly convex.
    """
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]])
    outward = np.array([[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])
    knots = np.append(corners, total)
    side = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, 3)
    frac = (t - knots[side]) / (knots[side + 1] - knots[side])
    pos = square[side] + frac[:, None] * (square[side + 1] - square[side])
    return pos + (bulge * 4.0 * frac * (1.0 - frac))[:, None] * outward[side]


def _side_of(t: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Side (0-3) of every boundary arc position; corners count as lying on both neighbouring sides."""
    side = np.clip(np.searchsorted(corners, t, side="right") - 1, 0, 3)
    at_corner = np.isin(t, corners)
    return side, at_corner


def _flat_faces(faces_b: np.ndarray, t_of: np.ndarray, corners: np.ndarray) -> int:
    """Triangles whose corners all lie on one side of the square (they would have zero area)."""
    side, at_corner = _side_of(t_of, corners)
    bad = 0
    for s in range(4):
        on = (side == s) | (at_corner & (side == (s + 1) % 4))
        bad += int(np.all(on[faces_b], axis=1).sum())
    return bad


def _corner_choice(idx: list, arc: np.ndarray, total: float, faces_b: np.ndarray, sharp: np.ndarray):
    """``(key, t_of, corners, idx)`` for the boundary vertices ``idx`` as the square's corners, in loop order
    from ``idx[0]``: ``t_of`` each boundary vertex's arc position from the first corner, ``key`` what ranks
    the choice (flat faces, then the corners' sharpness); None when they are not four distinct places.
    """
    if len(set(idx)) < 4:
        return None
    order = np.argsort([(arc[i] - arc[idx[0]]) % total for i in idx])
    idx = [idx[k] for k in order]
    t_of = (arc - arc[idx[0]]) % total
    corners = np.sort(t_of[idx])
    if np.any(np.diff(np.append(corners, total)) <= 0):
        return None
    return (_flat_faces(faces_b, t_of, corners), -float(sharp[idx].sum())), t_of, corners, idx


def _choose_corners(mesh: Mesh, loop: np.ndarray, arc: np.ndarray, total: float, sharp: np.ndarray):
    n = len(loop)
    if n < 4:
        raise ParametrizationError(f"method='disk': the boundary has {n} vertices; four are needed for the corners")
    local = np.full(mesh.n_vertices, -1, np.int64)
    local[loop] = np.arange(n)
    # the triangles the map is built on and those the image samples (a polygon whose corners are all on the
    # boundary is flat in a triangle cut off a straight side, even when its own corners span two sides)
    tris = np.unique(np.sort(np.concatenate([mesh.triangulate()[0], mesh.triangulate(quads="shorter")[0]]),
                             axis=1), axis=0)
    faces_b = local[tris[np.all(local[tris] >= 0, axis=1)]]
    starts = np.unique(np.concatenate([np.argsort(-sharp)[:_CANDIDATE_STARTS // 2],
                                       np.linspace(0, n, _CANDIDATE_STARTS // 2, endpoint=False).astype(int)]))
    best = None
    for s in starts:
        targets = (arc[s] + total * np.arange(4) / 4.0) % total
        # snap each quarter point to the sharpest vertex within an eighth of the loop, preferring near ones
        idx: list[int] = []
        for q in targets:
            dist = np.abs((arc - q + total / 2) % total - total / 2)
            score = sharp - 4.0 * dist / total * np.pi
            score[dist > total / 8] = -np.inf
            score[idx] = -np.inf
            idx.append(int(np.argmax(score)))
        found = _corner_choice(idx, arc, total, faces_b, sharp)
        if found is not None and (best is None or found[0] < best[0]):
            best = found
    if best is None:                # no sharp vertex near each quarter (a short loop): the nearest ones, in order
        t0 = (arc - arc[0]) % total
        idx = []
        for q in total * np.arange(4) / 4.0:
            dist = np.abs((t0 - q + total / 2) % total - total / 2)
            dist[idx] = np.inf
            idx.append(int(np.argmin(dist)))
        best = _corner_choice(sorted(idx, key=lambda i: t0[i]), arc, total, faces_b, sharp)
    if best is None:
        raise ParametrizationError("method='disk': could not place four distinct corners on the boundary")
    return best


def _keep_outline(mesh: Mesh, loop: np.ndarray) -> np.ndarray:
    p = mesh.vertices[loop]
    c = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - c, full_matrices=False)
    xy = (p - c) @ vt[:2].T
    area = 0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - xy[:, 1] * np.roll(xy[:, 0], -1))
    if area < 0:
        xy[:, 1] = -xy[:, 1]
    planar = np.abs((p - c) @ vt[2]).max() <= 1e-6 * np.abs(xy).max()
    e = np.roll(xy, -1, axis=0) - xy
    turn = np.roll(e[:, 0], 1) * e[:, 1] - np.roll(e[:, 1], 1) * e[:, 0]   # previous edge x this edge
    reflex = int(np.sum(turn < -1e-12 * np.abs(turn).max()))
    if reflex or not planar:
        why = f"{reflex} reflex boundary vertices" if reflex else "the boundary is not planar"
        raise ParametrizationError(f"boundary='keep' needs a boundary that is a convex polygon in a plane ({why}); "
                                   "use boundary='square'")
    return xy


def disk_coords(mesh: Mesh, boundary: str = "square", balance: str = DEFAULT_DISK_BALANCE, *,
                progress: Progress | None = None) -> tuple[np.ndarray, dict]:
    """Per-vertex (u, v) of a disk-like mesh; boundary on the unit square or on its own convex outline; the
    interior by mean-value coordinates, then balanced (``balance="area"``: the boundary slides along the
    square's straight sides, a kept or bowed outline is held) or relaxed by SLIM with the boundary held
    (``"slim"``).

    Parameters
    ----------
    mesh : Mesh
        A manifold, oriented mesh of one piece with one boundary loop and genus 0.
    boundary : {"square", "keep"}
        The boundary on the unit square, or on the mesh's own convex planar outline.
    balance : {"area", "slim", "none"}
        How the map inside is relaxed.
    progress : callable or None
        Called with the area balancing's progress.

    Returns
    -------
    coords : (N, 2) float64
        Unreferenced vertices get (0, 0).
    info : dict
        ``corners`` (vertex indices at the square's corners), ``boundary_vertices``, ``balance``,
        ``balance_steps`` (``slim_steps``: the same for SLIM, else 0), and the area distortion (log-RMS
        of each triangle's share of the parameter area over its share of the surface) of the mean-value
        map (``mean_value_area_log_rms``) and of the result (``area_log_rms``).

    Raises
    ------
    ParametrizationError
        When ``boundary`` or ``balance`` is unknown, or the boundary has zero length.

    Examples
    --------
    >>> v = [[0, 0, 0], [1, 0, 0], [2, 0, 1], [2, 1, 1], [1, 1, 0], [0, 1, 0], [1, 0.5, 0.2]]
    >>> m = Mesh(v, [[0, 1, 6], [1, 2, 6], [2, 3, 6], [3, 4, 6], [4, 5, 6], [5, 0, 6]])
    >>> uv, info = disk_coords(m)
    >>> sorted(info["corners"])
    [0, 2, 3, 5]
    """
    if boundary not in DISK_BOUNDARIES:
        raise ParametrizationError(f"boundary: expected one of {DISK_BOUNDARIES}, got {boundary!r}")
    if balance not in DISK_BALANCES:
        raise ParametrizationError(f"balance: expected one of {DISK_BALANCES}, got {balance!r}")
    _check_disk(mesh)
    loop = boundary_loops(mesh)[0]
    tris, _ = mesh.triangulate()
    info: dict = {"boundary_vertices": int(len(loop))}
    slide = None                 # the boundary's directions of sliding and its held vertices, loop order
    if boundary == "keep":
        pos = _keep_outline(mesh, loop)
    else:
        seg = np.linalg.norm(mesh.vertices[np.roll(loop, -1)] - mesh.vertices[loop], axis=1)
        arc = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
        total = float(seg.sum())
        if not total > 0:
            raise ParametrizationError("method='disk': the boundary has zero length")
        sharp = np.pi - _interior_angle_sums(mesh, tris)[loop]
        (flat, _), t_of, corners, idx = _choose_corners(mesh, loop, arc, total, sharp)
        # faces with every corner on one side would be flat: bow the sides out a little instead
        bulge = BULGE if flat else 0.0
        pos = _square_positions(t_of, corners, total, bulge)
        info.update(corners=loop[idx].tolist(), side_bulge=bulge)
        if not bulge:            # straight sides: their vertices may slide along them, the corners stay
            side, at_corner = _side_of(t_of, corners)
            along = np.where((side % 2 == 0)[:, None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
            along[at_corner] = 0.0
            slide = (along, at_corner)
    used = np.flatnonzero(mesh.referenced_vertices())
    index = np.full(mesh.n_vertices, -1, np.int64)
    index[used] = np.arange(len(used))
    relaxed, part = planar_interior(mesh.vertices[used], index[tris], index[loop], pos, balance, slide, progress)
    coords = np.zeros((mesh.n_vertices, 2))
    coords[used] = relaxed
    info.update(part)
    return coords, info


PLANAR_SWEEP_ROUNDS = 2
NEWTON_FIRST_STEPS = 2   # Gauss-Newton steps of a start's first balancing (the two starts compared after them)
START_LEAD = 1.0         # a fold-free start balanced once to over 1/START_LEAD times the other's error stops
START_WEIGHTS = ("mean-value", "uniform")     # the interior's starts: Floater's weights, Tutte's
ERROR_RESOLUTION = 257                         # the image side the starts are compared at (Gu et al.'s)


def resampling_error(area3: np.ndarray, uv: np.ndarray, f: np.ndarray, resolution: int = ERROR_RESOLUTION, *,
                     image_area: float | None = None) -> float:
    """How far an image resampled through the planar map ``uv`` of triangles ``f`` (3-D areas ``area3``) is
    expected to be from them, at ``resolution`` squared pixels: ``sum_t A_t min(A_t / a_t, 2 N^2 A_t)^2``
    over the triangles' shares ``A_t`` of the surface and ``a_t`` of the parameter area. A triangle gets
    ``N^2 a_t`` samples, ``h_t^2 ~ A_t / (N^2 a_t)`` apart on it, and resampling errs by about ``h_t^2``
    times the curvature (the form :func:`.sampling_rotation` ranks sphere maps by); one that gets less than
    half a sample errs by about its own size instead, however small its share of the map. ``a_t`` is a share
    of the map's own area, or with ``image_area`` of that area (a layout that leaves part of the image empty,
    such as the charts', gives its triangles less than their share of the map).

    On trimesh's CAD models cut open, this ranks the two starts of :func:`planar_interior` as their images
    at 257^2 do on 10 of 11 (without the cap, on 9: it made the Stanford scan's worst-starved start look
    best, 41.7 dB against 45.3).

    Examples
    --------
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> resampling_error(np.ones(2), uv, f), resampling_error(np.array([1.0, 3.0]), uv, f) > 1
    (1.0, True)
    """
    a = np.abs(planar_cross(uv, f))
    A = area3 / max(float(area3.sum()), 1e-300)
    a = a / max(float(a.sum()) if image_area is None else float(image_area), 1e-300)
    ratio = np.minimum(A / np.maximum(a, 1e-300), 2.0 * resolution ** 2 * A)
    return float(np.sum(A * ratio ** 2))


def _folds(uv: np.ndarray, f: np.ndarray) -> int:
    """Triangles of no area or turned against the majority in the planar map ``uv``."""
    signed = planar_cross(uv, f)
    return int(np.sum(signed * (1.0 if signed.sum() >= 0 else -1.0) <= 0))


class GaussNewtonStalled(Exception):
    """:func:`planar_interior` with ``newton_only``: the Gauss-Newton steps stalled on every start."""


def planar_interior(v: np.ndarray, f: np.ndarray, loop: np.ndarray, pos: np.ndarray, balance: str, slide=None,
                    progress: Progress | None = None, *, newton_only: bool = False) -> tuple[np.ndarray, dict]:
    """A disk's planar map from its boundary: ``loop`` held at ``pos`` (or sliding as ``slide`` says), every
    other vertex of the triangles ``v, f`` (each vertex on one) at the weighted mean of its neighbours, then
    relaxed (:func:`relax_planar`).

    With ``balance="area"`` (the default) two starts are relaxed, Floater's mean-value weights and Tutte's
    uniform ones (:data:`START_WEIGHTS`), and the map kept is the one with fewer folded triangles, then the
    lower :func:`resampling_error`. Angle-based weights squeeze a fan of long thin triangles (CAD
    tessellations) far more than uniform ones, and the balancing does not always undo it; on smooth meshes
    the two end close. Trimesh's CAD models cut open, 257^2: ``featuretype.ply`` 45.2 -> 54.8 dB,
    ``plate_holes.STL`` 56.0 -> 67.3, ``idler_riser.STL`` 51.1 -> 57.8, ``fixed_top.ply`` 5 folds -> 0;
    ``ADIS16480.STL`` keeps the mean-value start (36.2 dB against 32.2), see ``benchmarks/README.md``.
    Each start is balanced once first (:data:`NEWTON_FIRST_STEPS` Gauss-Newton steps, or the Sobolev steps
    where those stall: :func:`relax_planar`); when both are then fold-free (a folded map is not balanced until the
    sweeps open it), the one behind (error over ``1 / START_LEAD`` times the other's) goes no further.
    Measured on 9 disk and cut meshes at 257²: on 7 the start so dropped ended behind too (the same map to
    the bit); on the hemisphere and Demosthenes the two ended within 1 % and the image within 0.07 dB
    (102.75 -> 102.74, 75.46 -> 75.39); the maps 1.0-1.6x faster (the terrain's disk 17.0 -> 10.7 s).
    ``"slim"`` and ``"none"`` keep the mean-value start. ``progress`` hears from each relaxing, its messages
    led by the start's name (``"uniform start: Gauss-Newton step 3: energy 0.7032"``). ``newton_only`` (with
    ``"area"``): a start whose Gauss-Newton steps stall is dropped rather than balanced by the Sobolev steps
    and sweeps, and :class:`GaussNewtonStalled` is raised where both are (a trial the caller gives up).

    Returns
    -------
    coords : (N, 2) float64
    info : dict
        ``balance``, ``balance_steps``, ``slim_steps``, ``gauss_newton`` (whether Gauss-Newton steps made
        the map kept, see :func:`relax_planar`), ``start`` (the start kept), ``start_errors`` (each
        start's :func:`resampling_error` after relaxing, or after its first balancing when it went no
        further), ``stages`` (a line saying which start was kept,
        against what), ``mean_value_area_log_rms`` (the mean-value map's
        area distortion) and ``area_log_rms`` (the result's).
    """
    free = np.setdiff1d(np.arange(len(v)), loop)
    area3 = triangle_areas(v, f)
    tries: list[_Start] = []
    names = START_WEIGHTS if balance == "area" and len(free) else START_WEIGHTS[:1]
    cache: dict = {}          # one Sobolev factor for every balancing of every start (the same mesh)
    rounds = 0 if len(names) > 1 else PLANAR_SWEEP_ROUNDS       # two starts: each balanced once, then ...
    for name in names:
        start = np.zeros((len(v), 2))
        start[loop] = pos
        if len(free):
            weights = mean_value_weights(v, f) if name == "mean-value" else uniform_weights(f, len(v))
            start[free] = solve_free(weights, loop, pos, free)
        if not tries:
            first = area_log_rms(area3, start, f)
        heard = None if progress is None else (lambda msg, name=name: progress(f"{name} start: {msg}"))
        coords, steps, newton = (relax_planar(v, f, start, loop, balance, slide, heard, rounds, cache=cache,
                                              newton_only=newton_only) if len(free) else (start, 0, False))
        if newton_only and len(free) and not newton:     # its Gauss-Newton steps stalled: dropped
            continue
        tries.append(_Start(name, coords, steps, heard, area3, f, newton))
    if not tries:
        raise GaussNewtonStalled("the Gauss-Newton steps stalled on every start")
    if len(tries) > 1:          # ... the rest for each start not left far behind (see START_LEAD)
        best = min(tries, key=_Start.rank)
        for i, t in enumerate(tries):         # each compared with the best after its first balancing
            if t is not best and t.folds == best.folds == 0 and best.error < START_LEAD * t.error:
                t.stopped = True
                continue
            coords, more, newton = relax_planar(v, f, t.coords, loop, balance, slide, t.heard,
                                                PLANAR_SWEEP_ROUNDS, balanced=True, cache=cache, newton=t.newton)
            tries[i] = _Start(t.name, coords, t.steps + more, t.heard, area3, f, newton)
    kept = min((t for t in tries if not t.stopped), key=_Start.rank)
    name, coords, steps, error = kept.name, kept.coords, kept.steps, kept.error
    others = ", ".join(f"{t.name} {t.error:.3g}{' after its first balancing' * t.stopped}" for t in tries
                       if t.name != name)
    stage = (f"{name} start" + " by Gauss-Newton steps" * kept.newton
             + (f" (resampling error {error:.3g}; {others})" if others else ""))
    info = {"balance": balance, "balance_steps": steps, "slim_steps": steps if balance == "slim" else 0,
            "gauss_newton": kept.newton, "start": name, "start_errors": {t.name: t.error for t in tries},
            "stages": [stage],
            "mean_value_area_log_rms": first,
            "area_log_rms": area_log_rms(area3, coords, f) if steps else first}
    return coords, info


class _Start:
    """One start of :func:`planar_interior`: its map so far, the balancing steps it took, whom its progress
    goes to, whether Gauss-Newton steps made it (its relaxing goes on with them), and that map's folds and
    :func:`resampling_error`; ``stopped`` once it goes no further.
    """

    def __init__(self, name: str, coords: np.ndarray, steps: int, heard, area3: np.ndarray, f: np.ndarray,
                 newton: bool = False):
        self.name, self.coords, self.steps, self.heard, self.newton = name, coords, steps, heard, newton
        self.folds, self.error = _folds(coords, f), resampling_error(area3, coords, f)
        self.stopped = False

    def rank(self) -> tuple[int, float]:
        """Fewer folds first, then the lower error."""
        return self.folds, self.error


def relax_planar(v: np.ndarray, f: np.ndarray, coords: np.ndarray, loop: np.ndarray, balance: str,
                 slide=None, progress: Progress | None = None, rounds: int = PLANAR_SWEEP_ROUNDS, *,
                 balanced: bool = False, cache: dict | None = None,
                 newton: bool = True, newton_only: bool = False) -> tuple[np.ndarray, int, bool]:
    """A fold-free planar map ``coords`` of the triangles ``v, f`` (every vertex on one), with its boundary
    ``loop``, relaxed as ``balance`` says: ``"slim"``, libigl's SLIM with the boundary held; ``"none"``, as
    it is; ``"area"``, the area balancing the sphere's map uses, the boundary sliding as ``slide`` says
    (directions and held vertices in loop order) or held:

    - with ``newton``, Gauss-Newton steps first (:func:`._newton.newton_balance`): to convergence, or
      :data:`NEWTON_FIRST_STEPS` of them when ``rounds`` is 0 (a start's first balancing); ``balanced``:
      ``coords`` is that first balancing's result, and the steps go on from it;
    - when they stall (far from balanced: a CAD fan squeezed to nothing, a triangle of no area), or without
      ``newton``: the Sobolev steps, then ``rounds`` times single-vertex sweeps and Sobolev steps again
      (:func:`._balance.settle`; ``balanced``: the first balancing is done, ``coords`` its result), from
      ``coords`` as given. The sweeps open what holds every vertex's step back at once (a triangle of no
      area in the mean-value map, one squeezed part; the camel's head's disk 73.1 -> 81.0 dB, a CAD plate
      cut open 43.8 -> 56.2 dB, resampled linearly at 257^2).

    ``cache`` keeps what depends on the mesh alone between calls (the Sobolev factor,
    :func:`._balance.balance`; the Gauss-Newton pattern, :func:`._newton.newton_balance`). ``progress``
    hears from either. ``newton_only``: where the Gauss-Newton steps stall, ``coords`` come back as they
    are (no Sobolev steps). Returns the coordinates, the steps taken, and whether Gauss-Newton steps made the
    map.
    """
    if balance == "slim":
        return (*relax(v, f, coords, loop), False)
    if balance == "none":
        return coords, 0, False
    held = np.zeros(len(v), bool)
    along = np.zeros((len(v), 3))
    held[loop] = True if slide is None else slide[1]
    if slide is not None:
        along[loop] = slide[0]
    start = np.column_stack([coords, np.zeros(len(v))])
    if newton and slides_on_axes(along):
        first = rounds == 0 and not balanced
        out, steps, _, stalled = newton_balance(start, v, f, ~held, along, progress=progress, cache=cache,
                                                steps=NEWTON_FIRST_STEPS if first else NEWTON_STEPS)
        if not stalled:
            return out[:, :2], steps, True
    if newton_only:             # no Sobolev steps: the map as it came, not made by Gauss-Newton steps
        return coords, 0, False
    out, steps, _ = settle(start, v, f, rounds, progress=progress, planar=True, held=held, along=along,
                           balanced=balanced, cache=cache)
    return out[:, :2], steps, False
