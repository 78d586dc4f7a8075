"""The coverage-weighted surface: the paper's weighted mean of the faces' planes, each face weighted by how
much of a Gaussian footprint around the point it covers, so that the surface tends to the mesh itself as
``s -> 0`` while staying infinitely smooth.

The paper's rational Gaussians weigh a face by the distance from the point to the face's *centre*
(``G_i = exp(-|x - c_i|^2 / 2 sigma_i^2)``). However small ``s``, a point then follows the face whose
centre is nearest in units of ``d_i``, not the face that holds it, and the surface stays a few tenths of a
face away from the mesh (the plateau measured in ``benchmarks/bench_fidelity.py``). Here the weight of a
triangle ``t`` is the integral over ``t`` of a Gaussian of width ``sigma`` centred on the point, in the
closed form of a product over its edges, ``F_t(x) = Phi(z_0) Phi(z_1) Phi(z_2)`` with ``z_k`` the signed
distance of ``x`` to edge ``k`` over ``sigma`` (exact for one edge, and for two edges meeting at a right
angle; near a corner it is the blur of the wedge its two edges make). Inside a triangle, farther than a few
``sigma`` from its edges, its weight is 1 and every other one vanishes: ``P`` is the triangle's own map.
Across an edge the weights of its two triangles are ``Phi(z)`` and ``Phi(-z)``: the crease is rounded over a
few ``sigma``. So ``P -> `` the piecewise-linear mesh as ``sigma -> 0``, ``P`` is C-infinity for every
``sigma > 0``, and with ``sigma`` about a pixel spacing the rounding is a prefilter for the image's grid
(anti-aliasing: what point sampling lacks).

Each polygon is split into triangles (quads along their shorter diagonal in space), and each triangle
maps by its own corners (barycentric interpolation; on the sphere, of the central projection of the
direction onto its chord triangle), so the limit is the triangulated mesh exactly. ``sigma = s * dbar``,
``dbar`` the triangles' mean enclosing-circle radius in the parameter domain, the same for every triangle
(the prefilter of a regular grid is the same everywhere) but two kinds: a triangle whose map is steeper than
the median narrows its width in proportion, and a thin one (enclosing circle :data:`THIN` times its incircle)
to at most its inradius (see :meth:`CoverageSurface.widths`). :func:`prefilter_s` gives the ``s`` that
serves a resolution.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import ndtri

from ..errors import InputError, ParametrizationError
from ..image import Domain, GeometryImage
from ..mesh import Mesh
from ..parametrization._laplacian import planar_cross
from ..parametrization._octahedral import directions
from ..parametrization._orientation import chord_orientation
from . import _coverage_kernels as ck
from . import _grid as grid
from ._addressing import (MAX_PLANAR_RESOLUTION, MAX_SPHERE_RESOLUTION, PlanarAddressing, SphereAddressing,
                          with_ghosts)
from ._base import Surface
from ._curvature import planar_curvature, sphere_curvature
from ._cells import build_cells_3d, enclosing_circle_radius, tangent_frames
from ._coverage_rim import boundary_segments, snap_rim
from ._weights import COVERAGE_S_RANGE, check_coverage_s

__all__ = ["CoverageSurface", "PlanarCoverageSurface", "SphereCoverageSurface", "fit_coverage_surface",
           "PREFILTER", "prefilter_s", "check_s", "COVERAGE_S_RANGE"]

PREFILTER = 0.4     # sigma in pixel spacings of the default image (0.2 to 0.5 measured: benchmarks/README.md)
DEGENERATE = 1e-12  # a triangle whose inradius is this share of the domain's size or less has no width
THIN = 4.0          # a triangle whose enclosing circle is THIN times its incircle or more is thin
FLOOR_OVER_TOL = 1e4    # a sum of weights below FLOOR_OVER_TOL * tol is outside the triangles: recomputed exactly


check_s = check_coverage_s          # one number in COVERAGE_S_RANGE


def prefilter_s(surface: CoverageSurface, resolution: int) -> float:
    """The ``s`` whose width ``sigma = s * dbar`` is :data:`PREFILTER` of the pixel spacing of a
    ``resolution`` image of ``surface``'s domain (the mean spacing on the sphere).

    Parameters
    ----------
    surface : CoverageSurface
        A surface with coverage weights.
    resolution : int
        The image's pixels along its longer side.

    Returns
    -------
    float
        The s to fit with.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.grid_mesh(np.zeros((5, 5)), (1.0, 1.0))
    >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.CoverageWeights(s=1.0))
    >>> s = prefilter_s(surf, 33)
    >>> bool(0 < s < prefilter_s(surf, 9))               # a finer grid, a narrower prefilter
    True
    """
    return PREFILTER * surface.pixel_spacing(resolution) / surface.dbar


@dataclass(frozen=True, eq=False)
class CoverageSurface(Surface):
    """A fitted coverage-weighted surface (``weights="coverage"``); build it with :func:`geoimg.fit_surface`.

    Attributes
    ----------
    domain : Domain
    s : float
        ``sigma = s * dbar``.
    dbar : float
        The triangles' mean size (enclosing-circle radius) in the parameter domain.
    tol : float
        Weights below it are skipped (0: every triangle is summed, in the log domain).
    """

    UNIT_POINTS = False     # evaluated at unit vectors only (the cells then hold the sphere's shell alone)
    POINTS_Z: ClassVar[float | None] = None     # evaluated on this plane only (the cells then hold its layer alone)

    domain: Domain
    s: float
    tol: float
    dbar: float
    tables: Any = field(repr=False)         # (E, K, w) of the triangles (see _coverage_kernels)
    centres: Any = field(repr=False)        # (T, 3) homogeneous centroids
    size: Any = field(repr=False)           # (T,) largest distance of a corner from the centroid
    spread: Any = field(repr=False)         # (T,) 1 / sin(smallest angle / 2)
    fallback: Any = field(repr=False)       # triangles a point outside them is summed over
    narrow: Any = field(repr=False)         # (T,) each triangle's width over sigma: min(1, median slope / its slope)
    thin: Any = field(repr=False)           # (T,) the inradius of a thin triangle (aspect beyond THIN), else inf
    polygons: Any = field(repr=False, default=None)    # (T, 3, 2) planar triangles, for the mask
    rim: Any = field(repr=False, default=None)        # (B, 2, 2) the mesh's boundary, that a planar rim snaps to
    serve: bool = False     # CoverageWeights(s=None): sampled at the width that serves the resolution
    weights: str = "coverage"
    n: int = 0
    sliver_rule: str = "exact"
    _cells: Any = field(repr=False, default=None)
    _edges: Any = field(repr=False, default=None)

    @property
    def sigma(self) -> float:
        """The weights' width in the parameter domain."""
        return self.s * self.dbar

    @property
    def log_g_ref(self) -> float:
        return -math.inf

    def with_s(self, s: float) -> CoverageSurface:
        """The same surface at another ``s`` (nothing refitted)."""
        return type(self)(**{**self.__dict__, "s": check_s(s), "serve": False, "_cells": None, "_edges": None})

    def sample(self, resolution: int | None = None, *, normals: bool = True, backend: str = "cpu") -> GeometryImage:
        """As :meth:`Surface.sample`; fitted with ``CoverageWeights(s=None)``, at the width that serves
        ``resolution`` (:func:`prefilter_s`).
        """
        if not self.serve:
            return super().sample(resolution, normals=normals, backend=backend)
        res = self.auto_resolution() if resolution is None else resolution
        self.domain.grid_shape(res)                                     # a resolution it has, before its width
        return self.with_s(prefilter_s(self, res)).sample(res, normals=normals, backend=backend)

    def widths(self) -> np.ndarray:
        """Each triangle's own width: ``sigma``, narrowed where its map is steeper than the median (so that
        its plane, carried a width beyond it, stays as close as a typical one's) and, for a thin triangle, at
        most its inradius (a blurred needle would reach far beyond itself: the product of its edges' terms
        overstates a sharp corner's share).
        """
        return np.minimum(self.sigma * self.narrow, self.thin)

    def edges(self) -> np.ndarray:
        """Each triangle's edge rows divided by its own width: ``z = E . p`` (made once)."""
        if self._edges is None:
            E = self.tables[0] / self.widths()[:, None, None]
            object.__setattr__(self, "_edges", np.ascontiguousarray(E))
        return self._edges

    def _zmin(self) -> float:
        return float(ndtri(self.tol)) if self.tol > 0 else -math.inf

    def cells(self) -> tuple:
        """Triangles binned by their reach (made once, on first use)."""
        if self._cells is None:
            reach = np.minimum(self._reach(), 4.0) if self.tol > 0 else np.full(len(self.size), 4.0)
            cut = self.tol > 0                   # cut off below zmin: the cells past that leave a triangle out
            object.__setattr__(self, "_cells", build_cells_3d(
                self.centres, reach, planes=self.edges() if cut else None, floor=self._zmin(), unit=self.UNIT_POINTS,
                z=self.POINTS_Z))
        return self._cells

    def _reach(self) -> np.ndarray:
        """How far from its centre each triangle's terms reach: its corners' distance, plus the grown edges'
        offset at its sharpest corner.
        """
        return self.size + 1.05 * (-self._zmin()) * self.widths() * self.spread

    def _evaluate(self, pts, t1, t2, derivatives=True, exact=False):
        exact = exact or self.tol == 0
        fallback = np.arange(len(self.size)) if exact else self.fallback
        return ck.evaluate_coverage(pts, t1, t2, (self.edges(),) + tuple(self.tables[1:]),
                                    None if exact else self.cells(), fallback,
                                    zmin=self._zmin(), floor=FLOOR_OVER_TOL * self.tol, derivatives=derivatives,
                                    exact=exact)

    def pixel_spacing(self, resolution: int) -> float:
        """The distance between neighbouring pixels of a ``resolution`` image, in parameter units."""
        raise NotImplementedError


@dataclass(frozen=True, eq=False)
class PlanarCoverageSurface(PlanarAddressing, CoverageSurface):
    """The coverage-weighted surface over a parameter rectangle."""

    POINTS_Z = 1.0          # its points are homogeneous (u, v, 1)

    def pixel_spacing(self, resolution: int) -> float:
        return max(self.extent) / (int(resolution) - 1)

    def _points(self, uv, exact):
        pts = self._uv(uv)
        k = len(pts)
        hom = np.column_stack([pts, np.ones(k)])
        P, Pu, Pv, st = self._evaluate(hom, np.tile([1.0, 0.0, 0.0], (k, 1)), np.tile([0.0, 1.0, 0.0], (k, 1)),
                                       exact=exact)
        bad = ~np.isfinite(P).all(axis=1)
        if bad.any():
            raise InputError(f"uv: {int(bad.sum())} points (the first {pts[bad][0].tolist()}) lie so far outside the "
                             "parameter domain that the surface overflows there")
        return P, Pu, Pv, st

    def curvature(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        return planar_curvature(self, resolution)

    def auto_resolution(self) -> int:
        """Pixels along the longer side for a sample spacing of ``s * dbar`` (the paper's section 4.4)."""
        spacing = self.s * self.dbar
        return max(2, self._capped(int(math.ceil(max(self.extent) / spacing)) + 1, MAX_PLANAR_RESOLUTION))

    def _sample_grid(self, shape, normals: bool, backend: str = "cpu"):
        if backend != "cpu":
            raise InputError(f"backend {backend!r}: coverage weights are sampled on the CPU only; use backend='cpu'")
        u, v = self.domain.pixel_uv(shape)
        H, W = shape
        if self.tol > 0:            # triangle by triangle over the grid; the uncertified pixels point by point
            P, Pu, Pv, ok = ck.sample_grid_coverage(u, v, (self.edges(),) + tuple(self.tables[1:]), zmin=self._zmin(),
                                                    floor=FLOOR_OVER_TOL * self.tol, derivatives=True)
            ii, jj = np.nonzero(~ok)
            if len(ii):
                P[ii, jj], Pu[ii, jj], Pv[ii, jj], _ = self._points(np.stack([u[jj], v[ii]], axis=1), False)
            n_exact = len(ii)
        else:
            uu, vv = np.meshgrid(u, v)
            p, pu, pv, st = self._points(np.stack([uu.ravel(), vv.ravel()], axis=1), False)
            P, Pu, Pv = p.reshape(H, W, 3), pu.reshape(H, W, 3), pv.reshape(H, W, 3)
            n_exact = int((st == ck.EXACT).sum())
        eps = 0.5 * max(u[1] - u[0], v[1] - v[0])  # within half a pixel of a triangle
        mask = grid.face_coverage(u, v, self.polygons, np.full(len(self.polygons), 3), eps)
        if self.rim is not None and self.domain.glue(shape) is None:    # a rim that follows the mesh's outline
            ii, jj, uv = snap_rim(mask, u, v, self.rim)
            if len(ii):
                P[ii, jj], Pu[ii, jj], Pv[ii, jj], _ = self._points(uv, False)
        nrm = grid.unit_normals(Pu, Pv, self.orientation) if normals else None
        return P, nrm, mask, n_exact, 0


@dataclass(frozen=True, eq=False)
class SphereCoverageSurface(SphereAddressing, CoverageSurface):
    """The coverage-weighted surface over the sphere (octahedral images)."""

    UNIT_POINTS = True

    def pixel_spacing(self, resolution: int) -> float:
        return math.sqrt(4.0 * math.pi) / (int(resolution) - 1)

    def evaluate_directions(self, q: ArrayLike, *, exact: bool = False, derivatives: bool = True) -> tuple:
        """Points and derivatives along a tangent frame ``(t1, t2)`` at directions ``q`` (k, 3): ``P, P_t1,
        P_t2, t1, t2, status``, as :meth:`SphereSurface.evaluate_directions` returns them.
        """
        d = np.asarray(q, dtype=np.float64)
        if d.ndim != 2 or d.shape[1] != 3:
            raise InputError(f"q: expected finite directions of shape (k, 3), got {d.shape}")
        d = directions(d, "q")
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        t1, t2 = tangent_frames(d)
        P, P1, P2, st = self._evaluate(d, t1, t2, derivatives=derivatives, exact=exact)
        return P, P1, P2, t1, t2, st

    def curvature(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        return sphere_curvature(self, resolution)

    def _reach(self) -> np.ndarray:
        """On the sphere the planar rule falls short for large triangles (the sphere bulges beyond the chord
        triangle, and the edges' planes through the centre meet its plane at a slant): the bound of
        :func:`~._coverage_kernels.sphere_reach` instead.
        """
        return ck.sphere_reach(self.edges(), self.tables[2], self._zmin(), self.centres)

    def auto_resolution(self) -> int:
        """Odd side whose pixels are ``s * dbar`` apart on the sphere, on average."""
        side = int(math.ceil(math.sqrt(4.0 * math.pi) / (self.s * self.dbar))) + 1
        return max(3, self._capped(side, MAX_SPHERE_RESOLUTION))

    def _sample_grid(self, shape, normals: bool, backend: str = "cpu"):
        if backend != "cpu":
            raise InputError(f"backend {backend!r}: octahedral (spherical) images are sampled on the CPU only")
        n = shape[0]
        q = self.domain.directions(n).reshape(-1, 3)             # type: ignore[attr-defined]   # octahedral
        if self.tol > 0:     # triangle by triangle over each octant; the uncertified pixels exactly
            P, P1, P2, ok = ck.sample_octahedral_coverage(q, (self.edges(),) + tuple(self.tables[1:]),
                                                          zmin=self._zmin(), floor=FLOOR_OVER_TOL * self.tol,
                                                          derivatives=normals)
            redo = np.flatnonzero(~ok)
            if len(redo):      # along tangent frames there: any two tangents give the normal
                t1, t2 = tangent_frames(q[redo])
                P[redo], P1[redo], P2[redo], _ = self._evaluate(q[redo], t1, t2, derivatives=normals, exact=True)
            n_exact = len(redo)
        else:
            t1, t2 = tangent_frames(q)
            P, P1, P2, st = self._evaluate(q, t1, t2, derivatives=normals)
            n_exact = int((st == ck.EXACT).sum())
        nrm = grid.unit_normals(P1, P2, self.orientation).reshape(n, n, 3) if normals else None
        return P.reshape(n, n, 3), nrm, None, n_exact, 0


def _triangle_tables(corners: np.ndarray, xyz: np.ndarray, planar: bool):
    """Edge rows ``E``, maps ``K``, denominators ``w`` of triangles with homogeneous corner coordinates
    ``corners`` (T, 3, 3) and positions ``xyz`` (T, 3, 3); and which triangles are kept (not degenerate).
    """
    M = np.transpose(corners, (0, 2, 1))                     # columns: the corners
    det = np.linalg.det(M)
    scale = np.abs(M).max(axis=(1, 2)) ** 3
    keep = np.abs(det) > 1e-14 * scale
    Minv = np.zeros_like(M)
    Minv[keep] = np.linalg.inv(M[keep])
    spatial = Minv[:, :, :2] if planar else Minv
    norm = np.linalg.norm(spatial, axis=2)
    keep &= (norm > 0).all(axis=1)
    E = Minv / np.where(norm > 0, norm, 1.0)[..., None]
    K = np.einsum("tic,tcj->tij", np.transpose(xyz, (0, 2, 1)), Minv)   # positions by barycentric coordinates
    w = Minv.sum(axis=1)
    if not planar:      # scaled so that w . q = 1 at the corner nearest the plane's parallel great circle
        level = np.einsum("tc,tkc->tk", w, corners / np.linalg.norm(corners, axis=2, keepdims=True)).min(axis=1)
        level = np.where(keep & (level > 0), level, 1.0)
        K, w = K / level[:, None, None], w / level[:, None]
    return E, K, w, keep


def _shape(corners: np.ndarray):
    """Each triangle's centroid, the largest distance of a corner from it, and 1 / sin(half its smallest
    angle) (how far its outline moves at a corner when its edges move out by 1).
    """
    centroid = corners.mean(axis=1)
    size = np.linalg.norm(corners - centroid[:, None], axis=2).max(axis=1)
    cos = []
    for k in range(3):
        a = corners[:, (k + 1) % 3] - corners[:, k]
        b = corners[:, (k + 2) % 3] - corners[:, k]
        cos.append(np.einsum("tc,tc->t", a, b) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1),
                                                            1e-300))
    smallest = np.arccos(np.clip(np.max(cos, axis=0), -1.0, 1.0))
    return centroid, size, 1.0 / np.maximum(np.sin(0.5 * smallest), 1e-3)


def _border_triangles(tris: np.ndarray) -> np.ndarray:
    """Triangles with an edge no other triangle shares (all of them when there are none)."""
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, inverse, counts = np.unique(e, axis=0, return_inverse=True, return_counts=True)
    lone = (counts[inverse.ravel()] == 1).reshape(3, -1).any(axis=0)
    return np.flatnonzero(lone) if lone.any() else np.arange(len(tris))


def fit_coverage_surface(mesh: Mesh, coords: np.ndarray, domain: Domain, s: float, *, tol: float,
                         serve: bool = False) -> CoverageSurface:
    """Fit the coverage-weighted surface to a mesh whose vertices have ``coords`` in ``domain``: (N, 2)
    planar or (N, 3) unit vectors (called by ``fit_surface``, which has checked the settings).
    """
    planar = coords.shape[1] == 2
    tris, owner = mesh.triangulate(quads="shorter")
    tris = _quads_unfolded(mesh, tris, owner, coords)
    tri_mesh = Mesh(mesh.vertices, tris)
    polygons = coords[tris] if planar else None
    rim = boundary_segments(tri_mesh, coords) if planar else None
    if planar:        # faces a cut glues across the square's sides continue beyond them, as copies
        d = enclosing_circle_radius(coords[tris])
        ghosts = domain.ghosts(coords[tris].mean(axis=1), 4.0 * d + 8.0 * s * float(d.mean()), d)
        if ghosts:
            tri_mesh, coords, _ = with_ghosts(tri_mesh, coords, np.arange(len(tris)), ghosts)
            tris = tri_mesh.faces
    corners = np.concatenate([coords[tris], np.ones(tris.shape + (1,))], axis=2) if planar else coords[tris]
    E, K, w, keep = _triangle_tables(corners, tri_mesh.vertices[tris], planar)
    # a triangle thinner than rounding in the parameter domain has no width to weigh it by: left out too
    inradius = _inradius(corners[:, :, :2] if planar else corners)
    extent = float(np.ptp(corners[keep][:, :, :2].reshape(-1, 2), axis=0).max()) if planar and keep.any() else 1.0
    keep &= inradius > DEGENERATE * extent
    if not keep.any():
        raise ParametrizationError("every face has zero area in the parameter domain")
    if not keep.all():
        warnings.warn(f"fit_surface: {int((~keep).sum())} triangles of zero area in the parameter domain were left "
                      "out", stacklevel=4)
    tris, corners, E, K, w, inradius = tris[keep], corners[keep], E[keep], K[keep], w[keep], inradius[keep]
    enclosing = enclosing_circle_radius(corners[:, :, :2]) if planar else _sphere_sizes(corners)
    dbar = float(enclosing.mean())
    centres, size, spread = _shape(corners)
    slope = _slopes(corners, tri_mesh.vertices[tris], planar)
    narrow = np.clip(float(np.median(slope)) / np.maximum(slope, 1e-300), DEGENERATE, 1.0)
    thin = np.where(enclosing > THIN * inradius, inradius, np.inf)
    tables = tuple(np.ascontiguousarray(a, np.float64) for a in (E, K, w))
    kind = PlanarCoverageSurface if planar else SphereCoverageSurface
    return kind(domain, float(s), float(tol), dbar, tables, np.ascontiguousarray(centres), size, spread,
                _border_triangles(tris) if planar else np.arange(len(tris)), narrow, thin, polygons, rim, serve)


def _orientation(coords: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Each triangle's orientation in the parameter domain: :func:`planar_cross` on the plane,
    :func:`chord_orientation` on the sphere.
    """
    return planar_cross(coords, tris) if coords.shape[1] == 2 else chord_orientation(coords, tris)


def _quads_unfolded(mesh: Mesh, tris: np.ndarray, owner: np.ndarray, coords: np.ndarray) -> np.ndarray:
    """``tris`` (quads split along their shorter diagonal in space), with every quad whose split folds over in
    the parameter domain split along its other diagonal where that one does not. A map is one-to-one on the
    triangles it was made on (fans for the planar maps; sphere maps are made on these very triangles): a quad
    it leaves non-convex, split the other way, has a triangle turned over, and the surface's triangles then
    overlap (a 112-face cage of odedstein/meshes' fish on a fan-made sphere map: 11 % of its diagonal away at
    257^2, 40.2 dB).
    """
    o = _orientation(coords, tris)
    sign = 1.0 if np.sum(o > 0) >= np.sum(o < 0) else -1.0
    bad = np.zeros(mesh.n_faces, bool)
    bad[owner[o * sign <= 0]] = True
    bad &= mesh.face_sizes == 4
    if not bad.any():
        return tris
    rows = np.flatnonzero(bad[owner])                   # two per quad, in order
    q = mesh.faces[owner[rows[::2]], :4]
    first = tris[rows[::2]]
    # the split the triangulation made goes through corner 0 or corner 1 of the quad
    through0 = (first == q[:, [0]]).any(axis=1) & (first == q[:, [2]]).any(axis=1)
    other = np.where(through0[:, None, None],
                     np.stack([q[:, [1, 2, 3]], q[:, [1, 3, 0]]], axis=1),
                     np.stack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]], axis=1))
    ok = (_orientation(coords, other.reshape(-1, 3)).reshape(-1, 2) * sign > 0).all(axis=1)
    out = tris.copy()
    out[rows[::2][ok]] = other[ok, 0]
    out[rows[1::2][ok]] = other[ok, 1]
    return out


def _inradius(corners: np.ndarray) -> np.ndarray:
    """Inradius of triangles (T, 3, d): twice the area over the perimeter."""
    a = np.linalg.norm(corners[:, 1] - corners[:, 2], axis=1)
    b = np.linalg.norm(corners[:, 2] - corners[:, 0], axis=1)
    c = np.linalg.norm(corners[:, 0] - corners[:, 1], axis=1)
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    g = np.einsum("tc,tc->t", e1, e1) * np.einsum("tc,tc->t", e2, e2) - np.einsum("tc,tc->t", e1, e2) ** 2
    return np.sqrt(np.maximum(g, 0.0)) / np.maximum(a + b + c, 1e-300)


def _slopes(corners: np.ndarray, xyz: np.ndarray, planar: bool) -> np.ndarray:
    """Each triangle's largest stretch from the parameter domain into space: the largest singular value of
    the map taking its parameter edges ``b1, b2`` (chord edges on the sphere) to its edges in space ``a1, a2``.

    In closed form: in an orthonormal frame of the parameter triangle (``b1`` along the first axis) the map's
    columns are ``c1 = a1 / |b1|`` and ``c2 = (a2 - mu a1) / h`` (``mu = b1.b2 / |b1|^2``, ``h`` the height over
    ``b1``), and the largest singular value of ``[c1 c2]`` is the root of its 2 x 2 Gram matrix's larger
    eigenvalue. Elementwise arithmetic, so the same bits on every machine; LAPACK's batched SVDs (``pinv``
    and the 2-norm) agreed within 1e-13 relatively on bunny.off, a terrain and a CAD plate, and took 20 times
    as long (0.27 s on 70,000 triangles).

    >>> flat = np.array([[[0., 0], [1, 0], [0, 1]]])
    >>> xyz = np.array([[[0., 0, 0], [2, 0, 0], [0, 1, 0]]])
    >>> _slopes(flat, xyz, True).tolist()
    [2.0]
    """
    flat = corners[:, :, :2] if planar else corners
    b1, b2 = flat[:, 1] - flat[:, 0], flat[:, 2] - flat[:, 0]
    a1, a2 = xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0]
    l2 = np.einsum("td,td->t", b1, b1)
    l1 = np.maximum(np.sqrt(l2), 1e-300)
    twice = np.abs(b1[:, 0] * b2[:, 1] - b1[:, 1] * b2[:, 0]) if planar else np.linalg.norm(np.cross(b1, b2), axis=1)
    h = np.maximum(twice / l1, 1e-300)
    mu = np.einsum("td,td->t", b1, b2) / np.maximum(l2, 1e-300)
    c1 = a1 / l1[:, None]
    c2 = (a2 - mu[:, None] * a1) / h[:, None]
    p, q, r = np.einsum("tc,tc->t", c1, c1), np.einsum("tc,tc->t", c2, c2), np.einsum("tc,tc->t", c1, c2)
    return np.sqrt(0.5 * (p + q) + np.sqrt((0.5 * (p - q)) ** 2 + r * r))


def _sphere_sizes(corners: np.ndarray) -> np.ndarray:
    """Enclosing-circle radii of chord triangles (T, 3, 3), each measured in its own plane."""
    e1 = corners[:, 1] - corners[:, 0]
    e2 = corners[:, 2] - corners[:, 0]
    l1 = np.linalg.norm(e1, axis=1)
    x1 = e1 / np.maximum(l1, 1e-300)[:, None]
    a = np.einsum("tc,tc->t", e2, x1)
    b = np.linalg.norm(e2 - a[:, None] * x1, axis=1)
    flat = np.stack([np.zeros((len(l1), 2)), np.stack([l1, np.zeros_like(l1)], 1), np.stack([a, b], 1)], axis=1)
    return enclosing_circle_radius(flat)
