"""The weighted-mean surface ``P(u, v) = sum_i W_i(u, v) P_i(u, v)`` of a mesh parametrized over a plane.

Rational Gaussian weights (the paper's eq. 6-8) ``W_i = G_i / sum_j G_j``,
``G_i = exp(-|x - c_i|^2 / 2 sigma_i^2)``, ``sigma_i = s d_i``; or locally supported weights (eq. 10-13)
``W_i = 1 - 3R^2 + 2R^3`` with ``R = |x - c_i| / R_i``, ``R_i`` the radius holding the ``n`` nearest face
centres. Truncation: see :mod:`geoimg.surface._base`.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any
from collections.abc import Callable

import numpy as np

from ..errors import InputError
from ..image import Domain
from ..mesh import Mesh
from . import _gaussian_kernels as kernels
from . import _grid as grid
from ._addressing import MAX_PLANAR_RESOLUTION, PlanarAddressing, with_ghosts
from ._base import Surface, truncation_radius
from ._curvature import planar_curvature
from ._gaussian_face_maps import FaceMaps, face_maps

__all__ = ["PlanarSurface", "fit_planar_surface", "MAX_AUTO_RESOLUTION"]

MAX_AUTO_RESOLUTION = MAX_PLANAR_RESOLUTION


@dataclass(frozen=True, eq=False)
class PlanarSurface(PlanarAddressing, Surface):
    """A fitted weighted-mean surface over a planar parameter rectangle; build it with
    :func:`geoimg.fit_surface`.

    Attributes
    ----------
    faces : FaceMaps
        Face centres, sizes and affine maps.
    domain : Domain
        The parameter rectangle ``[0, extent[0]] x [0, extent[1]]`` and the orientation.
    s, weights, n, tol, sliver_rule
        The fit's settings.
    """

    faces: FaceMaps
    domain: Domain
    s: float
    weights: str
    n: int
    tol: float
    sliver_rule: str
    polygons: Any = field(repr=False, default=None)   # (F, K, 2) parametric faces, for the mask
    sizes: Any = field(repr=False, default=None)
    _radius: Any = field(repr=False, default=None)
    _param: Any = field(repr=False, default=None)
    _cells: Any = field(repr=False, default=None)
    s_face: Any = field(repr=False, default=None)   # per-face s when it varies (s is then its minimum)
    s_map: Any = field(repr=False, default=None)        # s(u, v) varying with the point (s is its minimum)

    @property
    def g_ref(self) -> float:
        """``exp(log_g_ref)`` (underflows to 0 for s below about 0.035)."""
        return math.exp(self.log_g_ref)

    @property
    def sigma(self) -> np.ndarray:
        """sigma_i = s_i d_i of every face (Gaussian weights)."""
        return (self.s if self.s_face is None else self.s_face) * self.faces.d

    # ---------------------------------------------------------------- evaluation
    def _points(self, uv, exact):
        pts = self._uv(uv)
        kind = kernels.GAUSSIAN if self.weights == "gaussian" else kernels.LOCAL
        fm = self.faces
        factor = None
        if self.s_map is not None and kind == kernels.GAUSSIAN:   # exponents scale by (s_ref / s(u, v))^2
            sp, su, sv = self.s_map(pts)
            factor = ((self.s / sp) ** 2, -2.0 * self.s ** 2 * su / sp ** 3, -2.0 * self.s ** 2 * sv / sp ** 3)
        out = kernels.evaluate_points(kind, pts, fm.centres, self._param, self._radius, fm.C, fm.A, fm.B,
                                      self._cells, log_g_ref=self.log_g_ref, exact=exact or self.tol == 0,
                                      factor=factor)
        for values in out[:3]:                 # points, P_u, P_v: the faces' planes extended that far overflow
            bad = ~np.isfinite(values).all(axis=1)
            if bad.any():
                raise InputError(f"uv: {int(bad.sum())} points (the first {pts[bad][0].tolist()}) lie so far "
                                 f"outside the parameter domain (extent {list(self.extent)}) that the surface "
                                 "overflows there")
        return out

    # ---------------------------------------------------------------- sampling
    def auto_resolution(self) -> int:
        """Pixels along the longer side for a sample spacing of ``s * mean(d_i)`` (the paper's section 4.4)."""
        spacing = self.s * float(self.faces.d.mean())
        return max(2, self._capped(int(math.ceil(max(self.extent) / spacing)) + 1, MAX_AUTO_RESOLUTION))

    def curvature(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        return planar_curvature(self, resolution)

    def _s_max(self):
        if self.s_face is not None:
            return float(self.s_face.max())
        return None if self.s_map is None else float(self.s_map.max)

    def _grid_arguments(self, u: np.ndarray, v: np.ndarray) -> tuple:
        """The grid kernels' positional arguments for the columns ``u`` and rows ``v`` (see
        :func:`~geoimg.surface._gaussian_kernels.sample_grid_gaussian`).
        """
        fm = self.faces
        return u, v, fm.centres, self.sigma, self._radius, fm.C, fm.A, fm.B

    def _sample_grid(self, shape, normals: bool, backend: str = "cpu"):
        """The grid kernel for truncated Gaussians (on the CPU or a CUDA GPU), else the point kernel;
        ``mask`` marks pixels inside the parametrized faces, or within half a pixel spacing of one, so a
        terrain whose border is not perfectly straight keeps its outer ring (and, for locally supported
        weights, not in a hole).
        """
        u, v = self.domain.pixel_uv(shape)
        H, W = shape
        n_exact = 0
        grid_kernel = self.weights == "gaussian" and self.tol > 0 and self.s_map is None
        if backend == "cuda" and not grid_kernel:
            raise InputError("backend 'cuda': samples Gaussian weights with truncation (tol > 0) and one s or "
                             "per-face s; use backend='cpu' for local weights, tol=0 or a smoothness map")
        if grid_kernel:
            sample_grid: Callable[..., tuple]
            if backend == "cuda":
                from ._gaussian_cuda_kernels import sample_grid_gaussian_cuda as sample_grid
            else:
                sample_grid = kernels.sample_grid_gaussian
            P, Pu, Pv, ok = sample_grid(*self._grid_arguments(u, v), derivatives=normals, log_g_ref=self.log_g_ref)
            status = np.zeros((H, W), np.int8)
            if not ok.all():
                ii, jj = np.nonzero(~ok)
                p, pu, pv, st = self._points(np.stack([u[jj], v[ii]], axis=1), True)
                P[ii, jj], status[ii, jj] = p, st
                if normals:
                    Pu[ii, jj], Pv[ii, jj] = pu, pv
                n_exact = len(ii)
        else:
            uu, vv = np.meshgrid(u, v)
            p, pu, pv, st = self._points(np.stack([uu.ravel(), vv.ravel()], axis=1), False)
            P, Pu, Pv = p.reshape(H, W, 3), pu.reshape(H, W, 3), pv.reshape(H, W, 3)
            status = st.reshape(H, W)
            n_exact = int((status == kernels.EXACT).sum())
        holes = status == kernels.HOLE
        eps = 0.5 * max(u[1] - u[0], v[1] - v[0])  # conservative: within half a pixel of a face
        mask = grid.face_coverage(u, v, self.polygons, self.sizes, eps) & ~holes
        nrm = grid.unit_normals(Pu, Pv, self.orientation) if normals else None
        return P, nrm, mask, n_exact, int(holes.sum())


def fit_planar_surface(mesh: Mesh, coords: np.ndarray, domain: Domain, s: float, s_face, s_map, *, weights: str,
                       n: int, tol: float, sliver_rule: str) -> PlanarSurface:
    """Fit the surface to a mesh whose vertices have (u, v) ``coords`` (called by ``fit_surface``, which
    has checked the settings). Faces the domain glues across its edges (a cut) are added as copies
    beyond the edges (:meth:`~geoimg.Domain.ghosts`), so the weighted mean sees the surface continue.
    """
    fm = face_maps(mesh, coords, sliver_rule=sliver_rule)
    if fm.n_degenerate:
        warnings.warn(f"fit_surface: {fm.n_degenerate} faces of zero area in the parameter domain were left out",
                      stacklevel=3)
    polys = coords[np.where(mesh.faces >= 0, mesh.faces, mesh.faces[:, :1])][fm.face_index]
    sizes = mesh.face_sizes[fm.face_index]
    ghosts = domain.ghosts(fm.centres, _reach(fm, s, s_face, s_map, weights, n, tol)[0])
    if ghosts:
        mesh, coords, source = with_ghosts(mesh, coords, fm.face_index, ghosts)
        fm = face_maps(mesh, coords, sliver_rule=sliver_rule)
        if s_face is not None:
            s_face = s_face[source]
    radius, param_arr, s_kept = _reach(fm, s, s_face, s_map, weights, n, tol)
    cells = kernels.build_cells(fm.centres, np.where(np.isfinite(radius), radius, 0.0))
    return PlanarSurface(fm, domain, s, weights, int(n), float(tol), sliver_rule, polys, sizes, radius, param_arr,
                         cells, s_kept, s_map)


def _reach(fm, s, s_face, s_map, weights, n, tol):
    """Each face's reach (the truncation radius, or the local weight's support), the kernel parameter
    ``1 / 2 sigma^2`` (0 for local weights) and the per-face s of the kept faces.
    """
    s_kept = None if s_face is None else s_face[fm.face_index]
    if weights == "gaussian":
        sigma = (s if s_kept is None else s_kept) * fm.d
        param_arr = 0.5 / sigma ** 2
        if tol > 0:     # the widest Gaussian a point can give a face sets its reach
            radius = truncation_radius(sigma * (s_map.max / s if s_map is not None else 1.0), s, tol)
        else:
            radius = np.full_like(sigma, np.inf)
    else:
        k = min(int(n), len(fm.d))
        from scipy.spatial import cKDTree      # here: a conversion by other weights starts without it

        dist, _ = cKDTree(fm.centres).query(fm.centres, k=k)
        radius = np.asarray(dist).reshape(len(fm.d), -1)[:, -1].copy()
        radius = np.maximum(radius, fm.d * 1e-6)  # a lone face still covers itself
        param_arr = np.zeros_like(radius)
    return radius, param_arr, s_kept


