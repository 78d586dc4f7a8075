"""The weighted-mean surface over the sphere, sampled on the octahedral square.

Each face lives on the sphere through its parametrized vertices: its plane through them (the chord
polygon), a frame in that plane, ``d_i`` the smallest enclosing circle of the chord triangle (mean vertex
distance for n > 3) and the affine map of the frame coordinates onto the face in space, as in
:mod:`geoimg.surface._gaussian_face_maps` (same sliver rule). Weights are Gaussians of the chord distance between a
direction and the face's centre, ``sigma_i = s d_i``; truncation and its certificate are those of
:mod:`geoimg.surface._base`. See :mod:`geoimg.surface._gaussian_sphere_kernels` for the evaluation.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, ParametrizationError
from ..image import Domain
from ..mesh import Mesh
from ..parametrization._octahedral import directions
from . import _gaussian_sphere_kernels as sphere_kernels
from ._addressing import MAX_SPHERE_RESOLUTION, SphereAddressing
from ._cells import build_cells_3d, enclosing_circle_radius, tangent_frames
from ._base import Surface, truncation_radius
from ._curvature import sphere_curvature
from ._gaussian_face_maps import SphereFaceMaps, fit_planes, robust_sliver_planes
from ._grid import unit_normals

__all__ = ["SphereSurface", "fit_sphere_surface", "MAX_AUTO_RESOLUTION"]

MAX_AUTO_RESOLUTION = MAX_SPHERE_RESOLUTION


def _project(points: np.ndarray, normal: np.ndarray, height: np.ndarray) -> np.ndarray:
    """Orthogonal projection of points (F, K, 3) onto the planes ``n . g = h`` of their faces."""
    return points - (np.einsum("fkc,fc->fk", points, normal) - height[:, None])[..., None] * normal[:, None]


def _sphere_face_maps(mesh: Mesh, s: np.ndarray, sliver_rule: str) -> SphereFaceMaps:
    f, k = mesh.faces, mesh.face_sizes
    valid = f >= 0
    idx = np.where(valid, f, f[:, :1])
    sp = s[idx]                                            # (F, K, 3) on the sphere
    xyz = mesh.vertices[idx]
    nxt = np.roll(sp, -1, axis=1)
    nxt = np.where(np.roll(valid, -1, axis=1)[..., None], nxt, sp[:, :1])   # Newell's normal of the polygon
    normal = (np.cross(sp, nxt) * valid[..., None]).sum(axis=1)
    origin = (sp * valid[..., None]).sum(axis=1) / k[:, None]
    nlen = np.linalg.norm(normal, axis=1)
    keep = nlen > 1e-300
    normal = normal / np.where(keep, nlen, 1.0)[:, None]
    height = np.einsum("fc,fc->f", normal, origin)
    keep &= height > 1e-9
    g = _project(sp, normal, height)
    e1 = g[:, 1] - g[:, 0]
    e1 = e1 - np.einsum("fc,fc->f", e1, normal)[:, None] * normal
    e1len = np.linalg.norm(e1, axis=1)
    keep &= e1len > 1e-300
    e1 = e1 / np.where(keep, e1len, 1.0)[:, None]
    e2 = np.cross(normal, e1)
    ab = np.stack([np.einsum("fkc,fc->fk", g - origin[:, None], e1), np.einsum("fkc,fc->fk", g - origin[:, None], e2)],
                  axis=-1)
    nxt_ab = np.where(np.roll(valid, -1, axis=1)[..., None], np.roll(ab, -1, axis=1), ab[:, :1])
    area = 0.5 * np.abs((ab[..., 0] * nxt_ab[..., 1] - ab[..., 1] * nxt_ab[..., 0]).sum(axis=1))
    d = np.empty(len(f))
    tri = k == 3
    if tri.any():
        d[tri] = enclosing_circle_radius(ab[tri, :3])
    if (~tri).any():
        d[~tri] = (np.linalg.norm(ab[~tri], axis=2) * valid[~tri]).sum(axis=1) / k[~tri]
    scale = max(float(d[keep].max()) if keep.any() else 0.0, 1e-300)
    keep &= (d > 1e-12 * scale) & (area > 1e-14 * scale * scale)
    if not keep.any():
        raise ParametrizationError("every face has zero area on the sphere")
    face_index = np.flatnonzero(keep)
    sel = (normal, height, origin, e1, e2, ab, xyz, valid, d, area)
    normal, height, origin, e1, e2, ab, xyz, valid, d, area = (a[keep] for a in sel)
    C, A, B = fit_planes(ab, xyz, valid, np.zeros((len(d), 2)))
    n_slivers = 0
    if sliver_rule == "robust":
        def ring_coords(ridx, sliver):   # ring vertices in each sliver's frame
            rg = _project(s[ridx], normal[sliver], height[sliver])
            usable = np.einsum("fkc,fc->fk", s[ridx], normal[sliver]) > 0
            rel = rg - origin[sliver][:, None]
            rab = np.stack([np.einsum("fkc,fc->fk", rel, e1[sliver]), np.einsum("fkc,fc->fk", rel, e2[sliver])], -1)
            return rab, usable, np.zeros((int(sliver.sum()), 2))

        d, n_slivers = robust_sliver_planes(mesh, face_index, d, area, C, A, B, ring_coords)
    centre = origin / np.linalg.norm(origin, axis=1, keepdims=True)
    return SphereFaceMaps(centre, d, C, A, B, face_index, n_slivers, int((~keep).sum()), origin, e1, e2)


@dataclass(frozen=True, eq=False)
class SphereSurface(SphereAddressing, Surface):
    """A fitted weighted-mean surface over the sphere; build it with :func:`geoimg.fit_surface` on a
    ``sphere`` parametrization. Points are addressed by octahedral image coordinates ``(u, v)`` in
    ``[0, 1]^2`` (or by unit directions, see :meth:`evaluate_directions`).
    """

    domain: Domain
    s: float
    tol: float
    sliver_rule: str
    d: np.ndarray = field(repr=False)
    face_index: np.ndarray = field(repr=False)
    n_slivers: int = 0
    n_degenerate: int = 0
    _faces: Any = field(repr=False, default=None)
    _cells: Any = field(repr=False, default=None)
    weights: str = "gaussian"
    n: int = 0
    s_face: Any = field(repr=False, default=None)   # per-face s when it varies (s is its minimum)

    def evaluate_directions(self, q: ArrayLike, *, exact: bool = False, derivatives: bool = True) -> tuple:
        """Points and derivatives along a tangent frame ``(t1, t2)`` (with ``t1 x t2 = q``) at unit
        directions ``q`` (k, 3). Returns ``P, P_t1, P_t2, t1, t2, status`` (the derivatives zeros without
        ``derivatives``: about half the work).
        """
        d = np.asarray(q, dtype=np.float64)
        if d.ndim != 2 or d.shape[1] != 3:
            raise InputError(f"q: expected finite directions of shape (k, 3), got {d.shape}")
        d = directions(d, "q")
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        t1, t2 = tangent_frames(d)
        P, P1, P2, st = sphere_kernels.evaluate_sphere(d, t1, t2, self._faces, self._cells, log_g_ref=self.log_g_ref,
                                                       exact=exact or self.tol == 0, derivatives=derivatives)
        return P, P1, P2, t1, t2, st

    def curvature(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        return sphere_curvature(self, resolution)

    def auto_resolution(self) -> int:
        """Odd side whose pixels cover about ``(s * mean d)^2`` of the sphere each, on average."""
        spacing = self.s * float(self.d.mean())
        side = int(math.ceil(math.sqrt(4.0 * math.pi) / spacing)) + 1
        return max(3, self._capped(side, MAX_AUTO_RESOLUTION))

    def _s_max(self):
        return None if self.s_face is None else float(self.s_face.max())

    def _sample_grid(self, shape, normals: bool, backend: str = "cpu"):
        """Glued boundary pixels are evaluated at bit-identical directions, so they hold identical values."""
        if backend != "cpu":
            raise InputError(f"backend {backend!r}: octahedral (spherical) images are sampled on the CPU only")
        n = shape[0]
        q = self.domain.directions(n).reshape(-1, 3)             # type: ignore[attr-defined]   # octahedral
        if self.tol > 0:        # by tiles of pixels
            t1, t2 = tangent_frames(q) if normals else (None, None)
            P, P1, P2, st = sphere_kernels.sample_sphere_grid(q, t1, t2, self._faces, self._cells,
                                                              log_g_ref=self.log_g_ref, derivatives=normals)
        else:
            P, P1, P2, _, _, st = self.evaluate_directions(q, derivatives=normals)
        nrm = unit_normals(P1, P2, self.orientation).reshape(n, n, 3) if normals else None
        return P.reshape(n, n, 3), nrm, None, int((st == sphere_kernels.EXACT).sum()), 0


def fit_sphere_surface(mesh: Mesh, coords: np.ndarray, domain: Domain, s: float, s_face, s_map, *, weights: str,
                       n: int, tol: float, sliver_rule: str) -> SphereSurface:
    """Fit the surface to a mesh whose vertices have unit vectors ``coords`` (called by ``fit_surface``,
    which has checked the settings); ``s`` the smallest of ``s_face`` when that is given.
    """
    if s_map is not None:
        raise InputError("s: a smoothness map s(u, v) is for planar parametrizations; on the sphere give one s "
                         "per face (geoimg.surface.smoothness_field)")
    if weights != "gaussian":
        raise InputError("weights: the octahedral (spherical) domain supports only 'gaussian' weights")
    s = s if s_face is None else s_face
    fm = _sphere_face_maps(mesh, coords, sliver_rule)
    if fm.n_degenerate:
        warnings.warn(f"fit_surface: {fm.n_degenerate} faces of zero area on the sphere were left out",
                      stacklevel=4)
    s_face = None if np.ndim(s) == 0 else np.asarray(s, np.float64)[fm.face_index]
    s = float(np.min(s))
    sigma = (s if s_face is None else s_face) * fm.d
    radius = truncation_radius(sigma, s, tol) if tol > 0 else np.full_like(sigma, 4.0)
    faces = tuple(np.ascontiguousarray(a, np.float64) for a in (
        fm.centres, 0.5 / sigma ** 2, radius, fm.origin, fm.e1, fm.e2, fm.C, fm.A, fm.B))
    cells = build_cells_3d(fm.centres, np.minimum(radius, 4.0))
    return SphereSurface(domain, s, float(tol), sliver_rule, fm.d, fm.face_index, fm.n_slivers, fm.n_degenerate,
                         faces, cells, s_face=s_face)
