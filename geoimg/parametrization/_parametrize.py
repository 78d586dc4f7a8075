"""Parametrizations: per-vertex (u, v) in the unit square (u right, v down), or unit vectors on the sphere.

Planar methods: ``uv`` (the mesh's own UVs), ``heightfield`` (projection onto the mesh's best-fitting
plane or onto the plane normal to a named axis) and ``disk`` (one boundary loop onto the square, see
:func:`geoimg.parametrization.disk_coords`). Coordinates are shifted and scaled by one factor so the longer
side spans [0, 1]; the aspect ratio is kept and recorded in ``extent``. ``sphere`` (see
:func:`geoimg.parametrization.sphere_coords`) maps a closed genus-0 mesh onto the unit sphere, for the
``octahedral`` domain.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .._choices import AXES, DEFAULT_DISK_BALANCE, PARAMETRIZATION_METHODS
from ..errors import InputTypeError, ParametrizationError
from ..mesh import Mesh, boundary_loops, topology
from ._charts import DEFAULT_CHARTS, chart_coords
from ._layout import layout_extent
from ._cut import cut_coords
from ._disk import disk_coords, resampling_error
from ._laplacian import planar_cross, starved_share, triangle_areas
from ._sphere import sphere_coords
from .._types import Progress
from .._threads import fixed_order

__all__ = ["Parametrization", "parametrize", "signed_face_areas", "PARAMETRIZATION_METHODS", "AXES"]

_AXES = {"x": 0, "y": 1, "z": 2}
SNAP_DEGREES = 15.0
CHARTS_WHEN_STARVED = 0.25  # auto tries charts where one disk or cut-open chart starves more than this share
MAX_OUTLINE_GAP = 0.25     # auto takes a height field or the mesh's UVs only when the outline fills its hull this well
# auto weighs a disk map against a height field whose resampling error is above this (terrains' maps: 0.28-0.39,
# a flat sheet's 0.29; a hemisphere's walls seen from above: 1.18, its disk map 0.27)
STEEP_HEIGHTFIELD = 0.6
COORD_DIMS = {
    "planar": 2,
    "octahedral": 3,
    "cut": 2,
    "charts": 2,
}  # a parametrization's domain kind -> per-vertex coordinates: (u, v), unit vectors


@dataclass(frozen=True, eq=False)
class Parametrization:
    """Per-vertex parameter coordinates of a mesh.

    Parameters
    ----------
    coords : numpy.ndarray, shape (N, 2) or (N, 3)
        Planar: (u, v) of every vertex, inside ``[0, extent[0]] x [0, extent[1]]``.
        Octahedral: unit vectors on the sphere.
    extent : tuple of float
        Size of the parametrized rectangle; the larger side is 1 ((1, 1) for the octahedral square).
    domain : str
        The kind of geometry image it leads to: ``"planar"``, ``"octahedral"`` or ``"cut"`` (see
        :class:`geoimg.Domain`).
    method : str
        How it was made.
    flipped_faces : int
        Faces whose orientation in (u, v) disagrees with the majority (0 for a bijective map).
    degenerate_faces : int
        Faces of zero area in (u, v).
    info : dict
        Method details (projection axes, scale).
    mesh : Mesh or None
        The mesh the coordinates belong to, when the method had to change the input (``cut``: the input
        cut open into a disk, vertices along the cut copied); None when they are the input's.
    source : numpy.ndarray (N, 2) or None
        With ``mesh``: the input edge ``(a, b)`` each of its vertices lies on (``a == b`` for a copy of an
        input vertex) ...
    source_weight : numpy.ndarray (N,) or None
        ... and the weight ``w`` along it: the vertex is ``(1 - w) p_a + w p_b``.
    domain_fields : dict
        Fields of the image's :class:`~geoimg.Domain` that the method sets (``cut``: the layout of the cut
        on the square).

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.grid_mesh([[0.0, 1.0], [2.0, 3.0]], (1.0, 1.0))
    >>> p = geoimg.parametrize(m, "heightfield", axis="z")
    >>> type(p).__name__, p.domain, p.coords.shape, p.extent
    ('Parametrization', 'planar', (4, 2), (1.0, 1.0))
    """

    coords: np.ndarray
    extent: tuple
    domain: str = "planar"
    method: str = ""
    flipped_faces: int = 0
    degenerate_faces: int = 0
    info: dict = field(default_factory=dict)
    mesh: Mesh | None = field(default=None, repr=False)
    source: np.ndarray | None = field(default=None, repr=False)
    source_weight: np.ndarray | None = field(default=None, repr=False)
    domain_fields: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        c = np.array(self.coords, dtype=np.float64, copy=True)
        if self.domain not in COORD_DIMS:
            raise ParametrizationError(f"domain: expected one of {tuple(COORD_DIMS)}, got {self.domain!r}")
        dim = COORD_DIMS[self.domain]
        if c.ndim != 2 or c.shape[1] != dim:
            raise ParametrizationError(f"coords: expected shape (N, {dim}) for the {self.domain} domain, got {c.shape}")
        if not np.isfinite(c).all():
            raise ParametrizationError("coords: contains NaN or infinite values")
        if dim == 3 and not np.allclose(np.linalg.norm(c, axis=1), 1.0, atol=1e-9):
            raise ParametrizationError("coords: octahedral coordinates must be unit vectors")
        c.setflags(write=False)
        object.__setattr__(self, "coords", c)
        object.__setattr__(self, "extent", tuple(float(x) for x in self.extent))


def signed_face_areas(mesh: Mesh, coords: np.ndarray) -> np.ndarray:
    """Signed area of every face in 2-D coordinates (shoelace formula; positive = counter-clockwise).

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    coords : numpy.ndarray
        (N, 2) per-vertex coordinates.

    Returns
    -------
    numpy.ndarray
        (F,) signed areas.

    Examples
    --------
    >>> m = Mesh(np.zeros((3, 3)), [[0, 1, 2]])
    >>> signed_face_areas(m, np.array([[0., 0], [1, 0], [0, 1]])).tolist()
    [0.5]
    """
    first = mesh.faces[:, :1]
    p = coords[np.where(mesh.faces >= 0, mesh.faces, first)]   # padding repeats the first vertex:
    nxt = mesh.next_vertices()
    q = coords[np.where(nxt >= 0, nxt, first)]                  # its (v0, v0) term adds zero area
    cross = p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]
    return 0.5 * cross.sum(axis=1)


def _orientation_report(mesh: Mesh, coords: np.ndarray) -> tuple[int, int, int]:
    """``(folded faces, flat faces, majority orientation)`` of a plane map, judged on the triangles the map
    is built on and those the image samples (fanned, and quads along their shorter diagonal): a polygon can
    fold inside while its outline turns the right way (a bent pentagon seen from above).
    """
    tris, owner = (np.concatenate(t) for t in zip(mesh.triangulate(), mesh.triangulate(quads="shorter")))
    area = planar_cross(coords, tris)
    degenerate = np.abs(area) <= 1e-14 * max(np.abs(area).max(), 1e-300)
    pos = int(np.sum(area[~degenerate] > 0))
    neg = int(np.sum(area[~degenerate] < 0))
    majority = 1 if pos >= neg else -1
    folded = np.zeros(mesh.n_faces, bool)
    folded[owner[~degenerate & (np.sign(area) == -majority)]] = True
    flat = np.zeros(mesh.n_faces, bool)
    flat[owner[degenerate]] = True
    return int(folded.sum()), int((flat & ~folded).sum()), majority


def _normalize(coords: np.ndarray, used: np.ndarray) -> tuple[np.ndarray, tuple, dict]:
    lo = coords[used].min(axis=0)
    span = coords[used].max(axis=0) - lo
    size = span.max()
    if not size > 0:
        raise ParametrizationError("the parameter coordinates of the mesh span no area (all points coincide)")
    out = (coords - lo) / size
    extent = tuple(span / size)
    if min(extent) <= 1e-12:
        raise ParametrizationError("the parameter coordinates of the mesh lie on a line; nothing to sample")
    return out, extent, {"offset": lo.tolist(), "scale": float(size)}


@fixed_order
def parametrize(mesh: Mesh, method: str = "auto", *, axis: str | None = None, boundary: str = "square",
                balance: str = DEFAULT_DISK_BALANCE, progress: Progress | None = None) -> Parametrization:
    """Parametrize a mesh over a planar rectangle or the sphere.

    Parameters
    ----------
    mesh : Mesh
    method : {"auto", "heightfield", "uv", "disk", "sphere", "cut", "charts"}
        ``heightfield`` projects the vertices onto the best-fitting plane (or the plane normal to
        ``axis``), for terrains; ``uv`` uses ``mesh.uv``; ``disk`` maps a mesh with one boundary loop
        onto the square (mean-value coordinates); ``sphere`` maps a closed genus-0 mesh onto the sphere
        (octahedral domain); ``cut`` cuts any other manifold piece (handles, several boundary loops) open
        into a disk and maps that onto the square (cut domain; see :mod:`geoimg.parametrization._cut`);
        the returned parametrization then carries the cut-open mesh. ``charts`` splits such a piece into
        discs, each on a square of its own (charts domain; see :mod:`geoimg.parametrization._charts`).
        ``auto`` takes the mesh's UVs when they fold nothing, else a height field that folds no face (for a
        mesh with one boundary loop, only when its outline fills 75 % of its convex hull: the mask of a
        narrow, winding outline would cut the image's quad mesh apart; and without an ``axis``, a steep height
        field gives way to the disk map where that map's image is expected closer), else ``disk`` for one boundary
        loop, ``sphere`` for a closed genus-0 mesh, ``cut`` for any other manifold piece (``charts`` where
        the one disk or cut-open chart starves more than a quarter of it and the charts' image is expected
        closer), else fails saying what it found and what to do.
    axis : {"x", "y", "z"}, optional
        For ``heightfield``: the up axis (for example ``"y"`` for a y-up terrain). Default: the normal
        of the least-squares plane through the vertices, or the coordinate axis nearest to it when the
        two are within 15 degrees (terrains are stored axis-up; ``info["snapped_to_axis"]`` says so).
    boundary : {"square", "keep"}
        For ``disk``: the boundary on the unit square, or kept as it is when it is a convex planar polygon.
    balance : {"area", "slim", "none"}
        For ``disk`` (and ``cut``, whose boundary is always held: its sides are glued in pairs): after the mean-value
        map, balance its area as the sphere's map is balanced, the
        boundary vertices sliding along the square's sides and the corners held (``"area"``); or lower
        its distortion with SLIM, the boundary held (``"slim"``). Either opens up what the mean-value map
        squeezes (fingers, ears, a snout), every step fold-free. ``"none"`` keeps the mean-value map.
        ``info`` records both maps' area distortion.
    progress : callable, optional
        For ``sphere``, ``disk`` and ``cut``: called with a short message as the map's balancing goes on.

    Returns
    -------
    Parametrization
        Its ``flipped_faces`` counts folded faces; a warning is issued when it is not 0.

    Raises
    ------
    ParametrizationError
        If the method is unknown, the mesh has no UVs for ``uv``, or the coordinates span no area.

    Examples
    --------
    >>> m = Mesh([[0, 5, 0], [2, 6, 0], [2, 5, 1], [0, 4, 1]], [[0, 1, 2, 3]])
    >>> p = parametrize(m, "heightfield", axis="y")
    >>> p.extent, p.flipped_faces
    ((1.0, 0.5), 0)
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    check_axis(method, axis)
    _check_area(mesh)
    if method == "auto":
        return _auto(mesh, axis, boundary, balance, progress)
    return _by_method(mesh, method, axis, boundary, balance, progress)


def check_axis(method: str, axis: str | None) -> None:
    """Refuse an up axis with a method that takes none (it was ignored without a word)."""
    if axis is not None and method not in ("auto", "heightfield"):
        raise ParametrizationError(f"axis: the up axis of a height field (method 'heightfield' or 'auto'); "
                                   f"method {method!r} takes none, so leave it out")


def _by_method(mesh: Mesh, method: str, axis, boundary, balance, progress, topo=None) -> Parametrization:
    """One method, on a mesh already checked (``topo``: its topology, when known)."""
    used = mesh.referenced_vertices()
    info: dict = {}
    if method == "sphere":
        coords, info = sphere_coords(mesh, progress=progress)
        info["orientation"] = 1
        if info["flipped_triangles"]:
            warnings.warn(f"parametrize('sphere'): {info['flipped_triangles']} triangles are folded over on the "
                          "sphere; the map is not one-to-one there", stacklevel=2)
        return Parametrization(coords, (1.0, 1.0), "octahedral", "sphere", info["flipped_triangles"], 0, info)
    if method == "cut":
        return _cut(mesh, topo, balance, progress)
    if method == "charts":
        return _charts(mesh, topo, balance, progress)
    if method == "disk":
        raw, info = disk_coords(mesh, boundary, balance, progress=progress)
    elif method == "uv":
        if mesh.uv is None:
            raise ParametrizationError(
                "method='uv': the mesh has no per-vertex UVs (OBJ 'vt' that map one-to-one onto positions); "
                "use method='heightfield' for a terrain")
        raw = mesh.uv
    elif method == "heightfield":
        v = mesh.vertices
        centre = v[used].mean(axis=0)
        if axis is None:
            _, _, vt = np.linalg.svd(v[used] - centre, full_matrices=False)
            normal = vt[2]
            # point the normal to the side the faces face (area-weighted face normals)
            tris, _ = mesh.triangulate()
            fn = np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]]).sum(axis=0)
            if fn @ normal < 0:
                normal = -normal
            # terrains are stored axis-up: take the nearest coordinate axis when within SNAP_DEGREES
            k = int(np.argmax(np.abs(normal)))
            if np.degrees(np.arccos(min(1.0, abs(normal[k])))) <= SNAP_DEGREES:
                normal = np.sign(normal[k]) * np.eye(3)[k]
                info["snapped_to_axis"] = "xyz"[k]
        else:
            if axis not in _AXES:
                raise ParametrizationError(f"axis: expected one of 'x', 'y', 'z', got {axis!r}")
            normal = np.eye(3)[_AXES[axis]]
        # a right-handed in-plane frame (e1, e2, normal) keeps faces that face +normal counter-clockwise
        # u along the coordinate axis least aligned with the normal (x for a y-up or z-up terrain)
        helper = np.eye(3)[np.argmin(np.abs(normal))]
        e1 = helper - (helper @ normal) * normal
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        raw = np.stack([(v - centre) @ e1, (v - centre) @ e2], axis=1)
        info.update(normal=normal.tolist(), u_axis=e1.tolist(), v_axis=e2.tolist())
    else:
        raise ParametrizationError(
            f"method: expected one of {', '.join(map(repr, PARAMETRIZATION_METHODS))}, got {method!r}")
    coords, extent, norm = _normalize(raw, used)
    info.update(norm)
    flipped, degenerate, majority = _orientation_report(mesh, coords)
    info["orientation"] = majority
    if flipped:
        warnings.warn(f"parametrize({method!r}): {flipped} of {mesh.n_faces} faces are folded over in (u, v); "
                      "the map is not one-to-one there", stacklevel=2)
    return Parametrization(coords, extent, "planar", method, flipped, degenerate, info)


def _one_manifold_piece(mesh: Mesh, method: str, topo=None):
    """The mesh's topology, or an error when it is not one manifold piece."""
    topo = topology(mesh) if topo is None else topo
    if not (topo.components == 1 and topo.nonmanifold_edges == 0 and topo.nonmanifold_vertices == 0):
        raise ParametrizationError(f"method={method!r} needs one manifold piece; the mesh is a {topo.describe()}: "
                                   "geoimg.mesh.repair splits it (geoimg.mesh_to_images does so itself)")
    return topo


def _cut_open(mesh: Mesh, method: str, topo, coords_of, balance: str, progress,
              extent_of=lambda layout: (1.0, 1.0)) -> Parametrization:
    """A parametrization whose method cuts the mesh open (``coords_of`` returns its cut mesh, coordinates,
    sources, the domain's fields and info; ``extent_of`` the parameter rectangle from those fields).
    """
    disk, coords, (source, weight), layout, info = coords_of(mesh, balance=balance, progress=progress)
    flipped, degenerate, majority = _orientation_report(disk, coords)
    info.update(orientation=majority, genus=topo.genus, boundary_loops=topo.boundary_loops)
    if flipped:
        warnings.warn(f"parametrize({method!r}): {flipped} of {disk.n_faces} faces are folded over in (u, v); the "
                      "map is not one-to-one there", stacklevel=4)
    return Parametrization(coords, extent_of(layout), method, method, flipped, degenerate, info, mesh=disk,
                           source=source, source_weight=weight, domain_fields=layout)


def _cut(mesh: Mesh, topo=None, balance: str = DEFAULT_DISK_BALANCE,
         progress: Progress | None = None) -> Parametrization:
    topo = _one_manifold_piece(mesh, "cut", topo)
    if topo.closed and topo.genus == 0:
        raise ParametrizationError("method='cut': a closed genus-0 mesh has nothing to cut; use method='sphere'")
    return _cut_open(mesh, "cut", topo, cut_coords, balance, progress)


def _charts(mesh: Mesh, topo=None, balance: str = DEFAULT_DISK_BALANCE,
            progress: Progress | None = None, charts: int = DEFAULT_CHARTS) -> Parametrization:
    topo = _one_manifold_piece(mesh, "charts", topo)
    return _cut_open(mesh, "charts", topo, lambda m, **kw: chart_coords(m, charts=charts, **kw), balance, progress,
                     layout_extent)


def _starved_to_charts(mesh: Mesh, single: Parametrization, topo, balance: str, progress) -> Parametrization:
    """``single`` (a disk or cut-open map: one chart), or the multi-chart map when the one chart starves more
    than :data:`CHARTS_WHEN_STARVED` of the surface and the charts' image is expected closer (a lower
    :func:`._disk.resampling_error` over the image's area). Trimesh's ``fixed_top.ply``, a ring gear of genus
    7, cut open: 39.0 -> 63.5 dB at 257^2; the body of the ogre of alecjacobson/common-3d-test-models, a disk
    open at a small hole: 18.0 -> 75.8 dB; the Beetle's car body there, 11 holes: 39.1 -> 82.2 dB; trimesh's
    ``plate_holes.STL`` keeps its cut (67.4 dB; the charts, which starve about as much, 65.5).
    """
    starved = single.info.get("starved_share")
    if starved is None:                          # a disk's map: measured here
        tris, _ = mesh.triangulate()
        starved = starved_share(triangle_areas(mesh.vertices, tris), np.abs(planar_cross(single.coords, tris)))
        single.info["starved_share"] = starved
    if starved <= CHARTS_WHEN_STARVED:
        return single
    return _closer(mesh, single, lambda: _charts(mesh, topo, balance, progress), "charts",
                   f"one chart starved {100 * starved:.0f} % of the surface: multi-chart map taken")


def _steep_to_disk(mesh: Mesh, heights: Parametrization, topo, boundary: str, balance: str,
                   progress) -> Parametrization:
    """``heights`` (a fold-free height field), or the disk map of a mesh with one boundary loop where the height
    field is steep (its :func:`._disk.resampling_error` above :data:`STEEP_HEIGHTFIELD`: walls seen from
    above get few pixels) and the disk map's image is expected closer. hemisphere.off (pmp-data) at 129^2:
    77.0 -> 93.7 dB; terrains never reach the test (their height fields: 0.28-0.39).
    """
    single = topo.components == 1 and topo.nonmanifold_edges == 0 and topo.nonmanifold_vertices == 0 \
        and topo.genus == 0 and topo.boundary_loops == 1
    mine = _image_error(mesh, heights)
    if not single or mine <= STEEP_HEIGHTFIELD or not _has_interior_vertex(mesh):
        return heights

    def disk() -> Parametrization:
        return _starved_to_charts(mesh, _by_method(mesh, "disk", None, boundary, balance, progress, topo), topo,
                                  balance, progress)
    return _closer(mesh, heights, disk, "disk map", "height field steep: disk map taken", mine)


def _closer(mesh: Mesh, mine: Parametrization, make, tried: str, taken: str,
            error: float | None = None) -> Parametrization:
    """``mine``, or the map ``make()`` builds (``tried`` names it) where it folds no more faces and its image
    is expected closer (a lower :func:`._disk.resampling_error`; ``error``: ``mine``'s, when known); the map
    kept records which was taken (``taken``) or tried, and why, in its ``info["stages"]``.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            other = make()
        except ParametrizationError as e:
            mine.info["stages"] = mine.info.get("stages", []) + [f"{tried} tried, not kept ({e})"]
            return mine
    ours = _image_error(mesh, mine) if error is None else error
    theirs = _image_error(mesh, other)
    if other.flipped_faces <= mine.flipped_faces and theirs < ours:
        other.info["stages"] = [f"{taken} (resampling error {ours:.3g} -> {theirs:.3g})"] + \
            other.info.get("stages", [])
        return other
    mine.info["stages"] = mine.info.get("stages", []) + [
        f"{tried} tried, not kept (resampling error {theirs:.3g} against {ours:.3g})"]
    return mine


def _image_error(mesh: Mesh, p: Parametrization) -> float:
    """The :func:`._disk.resampling_error` of a planar map's image (the parametrized mesh's triangles)."""
    m = p.mesh if p.mesh is not None else mesh
    tris, _ = m.triangulate()
    return resampling_error(triangle_areas(m.vertices, tris), p.coords, tris, image_area=p.extent[0] * p.extent[1])


def _check_area(mesh: Mesh) -> None:
    """Refuse a mesh whose faces all have zero area (its points on a line or at one place)."""
    v = mesh.vertices
    scale = mesh.coordinate_scale()
    tris, _ = mesh.triangulate()
    area = np.linalg.norm(np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]]), axis=1)
    if not area.max() > 1e-24 * max(scale, 1e-300) ** 2:
        raise ParametrizationError(f"mesh: all {mesh.n_faces} faces have zero area (the points lie on a line or at "
                                   "one place): there is no surface to parametrize")


def _outline_gap(mesh: Mesh, coords: np.ndarray, topo) -> float:
    """For a mesh with one boundary loop (``topo``: its topology): the share of the convex hull of its (u, v)
    outline that the outline leaves empty (0 for a convex outline); 0 for other meshes.
    """
    loops = boundary_loops(mesh) if topo.boundary_loops == 1 else []
    if len(loops) != 1 or len(loops[0]) < 3:
        return 0.0
    xy = coords[loops[0]]
    inside = 0.5 * abs(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - xy[:, 1] * np.roll(xy[:, 0], -1)))
    from scipy.spatial import ConvexHull      # here: choosing a map starts without scipy.spatial

    hull = ConvexHull(xy).volume
    return float(max(0.0, 1.0 - inside / hull)) if hull > 0 else 0.0


def _has_interior_vertex(mesh: Mesh) -> bool:
    """Whether some vertex of the mesh lies off its boundary loops (a polygon split into triangles has none)."""
    on_rim = np.zeros(mesh.n_vertices, bool)
    for loop in boundary_loops(mesh):
        on_rim[loop] = True
    return bool((mesh.referenced_vertices() & ~on_rim).any())


def _auto(mesh: Mesh, axis: str | None, boundary: str, balance: str, progress) -> Parametrization:
    tried = []
    topo = topology(mesh)
    candidates = (["uv"] if mesh.uv is not None and axis is None else []) + ["heightfield"]
    for method in candidates:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                p = _by_method(mesh, method, axis, boundary, balance, progress)
            except ParametrizationError as e:
                tried.append(f"{method}: {e}")
                continue
        # a mesh without inner vertices keeps its height field (a disk map pins every vertex to the square's
        # rim); asked only where a rule needs it, not on every conversion
        if p.flipped_faces == 0 and (p.degenerate_faces == 0 or not _has_interior_vertex(mesh)):
            gap = _outline_gap(mesh, p.coords, topo)
            if gap <= MAX_OUTLINE_GAP or not _has_interior_vertex(mesh):
                steep = method == "heightfield" and axis is None
                return _steep_to_disk(mesh, p, topo, boundary, balance, progress) if steep else p
            tried.append(f"{method}: its outline leaves {100 * gap:.0f} % of its convex hull empty (narrow parts "
                         "would come apart in the image's mask)")
            continue
        tried.append(f"{method}: {p.flipped_faces} of {mesh.n_faces} faces fold over" if p.flipped_faces else
                     f"{method}: {p.degenerate_faces} of {mesh.n_faces} faces project to a line")
    single = topo.components == 1 and topo.nonmanifold_edges == 0 and topo.nonmanifold_vertices == 0 \
        and topo.genus == 0
    if single and topo.boundary_loops == 1 and axis is None:
        return _starved_to_charts(mesh, _by_method(mesh, "disk", None, boundary, balance, progress), topo, balance,
                                  progress)
    if single and topo.closed and axis is None:
        return _by_method(mesh, "sphere", None, boundary, balance, progress)
    manifold = topo.components == 1 and topo.nonmanifold_edges == 0 and topo.nonmanifold_vertices == 0
    if manifold and axis is None and topo.genus is not None:
        return _starved_to_charts(mesh, _cut(mesh, topo, balance, progress), topo, balance, progress)
    if topo.components > 1:
        advice = (f"a parametrization is of one piece: split the {topo.components} components "
                  "(geoimg.mesh.repair; geoimg.mesh_to_images converts each)")
    elif topo.nonmanifold_edges:
        advice = ("a parametrization needs a manifold mesh: separate the edges shared by more than two faces "
                  "(geoimg.mesh.repair; geoimg.mesh_to_images does so itself)")
    elif topo.nonmanifold_vertices:
        advice = ("a parametrization needs a manifold mesh: split the pinch vertices, one copy per fan of faces "
                  "(geoimg.mesh.repair; geoimg.mesh_to_images does so itself)")
    elif axis is not None:      # a manifold piece reaches here only when a height field was asked for
        advice = ("leave axis out, and auto maps the mesh as a disk, onto the sphere or cut open onto the square")
    else:
        advice = ("give it UVs (OBJ vt), or pass axis= for a terrain whose up axis is not its best-fitting "
                  "plane's normal")
    raise ParametrizationError(
        f"mesh: {topo.describe()}; no parametrization without folds was found ("
        + "; ".join(tried) + f"): it is not a height field and has no usable UVs. {advice}")
