"""The weighted-mean surface ``P(u, v) = sum_i W_i(u, v) P_i(u, v)`` of a parametrized polygon mesh.

Rational Gaussian weights (the paper's eq. 6-8) ``W_i = G_i / sum_j G_j``,
``G_i = exp(-|x - c_i|^2 / 2 sigma_i^2)``, ``sigma_i = s d_i``; or locally supported weights (eq. 10-13)
``W_i = 1 - 3R^2 + 2R^3`` with ``R = |x - c_i| / R_i``, ``R_i`` the radius holding the ``n`` nearest face
centres.

Truncation (``tol``, default 1e-10): a point inside face k has ``G_k >= g_ref = exp(-(4/3)^2 / 2 s^2)``
(no point of a triangle is farther than 4/3 d_k from its centroid). Face j is skipped where
``G_j < tol * g_ref``, i.e. outside ``|x - c_j| <= R_j = sigma_j sqrt(2 ln(1/tol) + (4/3)^2 / s^2)``
(about the paper's 7 sigma at s = 1). So every skipped weight ``W_j`` is below ``tol``. A point whose
truncated sum is below ``g_ref`` (outside the mesh, or next to a sliver) is recomputed exactly over
all faces in the log domain. ``tol=0`` evaluates the exact, untruncated sum everywhere.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from . import kernels
from .face_maps import FaceMaps, face_maps
from .mesh import Mesh
from .parametrization import Parametrization

__all__ = ["Surface", "fit_surface", "WEIGHTS", "TRUNCATION_RHO"]

WEIGHTS = ("gaussian", "local")
TRUNCATION_RHO = 4.0 / 3.0
MAX_AUTO_RESOLUTION = 4096


@dataclass(frozen=True, eq=False)
class Surface:
    """A fitted weighted-mean surface over a planar parameter rectangle; build it with :func:`fit_surface`.

    Attributes
    ----------
    faces : FaceMaps
        Face centres, sizes and affine maps.
    extent : tuple of float
        The parameter rectangle ``[0, extent[0]] x [0, extent[1]]``.
    s, weights, n, tol, sliver_rule
        The fit's settings.
    orientation : int
        +1 when ``P_u x P_v`` points along the mesh's face normals, else -1.
    """

    faces: FaceMaps
    extent: tuple
    s: float
    weights: str
    n: int
    tol: float
    sliver_rule: str
    orientation: int
    domain: str = "planar"
    polygons: np.ndarray = field(repr=False, default=None)   # (F, K, 2) parametric faces, for the mask
    sizes: np.ndarray = field(repr=False, default=None)
    _radius: np.ndarray = field(repr=False, default=None)
    _param: np.ndarray = field(repr=False, default=None)
    _cells: tuple = field(repr=False, default=None)
    s_face: np.ndarray = field(repr=False, default=None)   # per-face s when it varies (s is then its minimum)
    s_map: object = field(repr=False, default=None)        # s(u, v) varying with the point (s is its minimum)

    @property
    def log_g_ref(self) -> float:
        """log of the least Gaussian a point inside a face receives from that face (-inf for local weights)."""
        if self.weights != "gaussian":
            return -math.inf
        return reference_log_weight(self.s)

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
        pts = np.asarray(uv, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ValueError(f"uv: expected parameter points of shape (k, 2), got {pts.shape}")
        if not np.isfinite(pts).all():
            raise ValueError("uv: contains NaN or infinite values")
        kind = kernels.GAUSSIAN if self.weights == "gaussian" else kernels.LOCAL
        fm = self.faces
        factor = None
        if self.s_map is not None and kind == kernels.GAUSSIAN:   # exponents scale by (s_ref / s(u, v))^2
            sp, su, sv = self.s_map(pts)
            factor = ((self.s / sp) ** 2, -2.0 * self.s ** 2 * su / sp ** 3, -2.0 * self.s ** 2 * sv / sp ** 3)
        return kernels.evaluate_points(kind, pts, fm.centres, self._param, self._radius, fm.C, fm.A, fm.B,
                                       self._cells, log_g_ref=self.log_g_ref, exact=exact or self.tol == 0,
                                       factor=factor)

    def evaluate(self, uv, *, exact: bool = False) -> np.ndarray:
        """Surface points at parameter points.

        Parameters
        ----------
        uv : array_like, shape (k, 2)
        exact : bool, default False
            Sum over every face instead of the truncated neighbourhood.

        Returns
        -------
        numpy.ndarray, shape (k, 3) float64

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 1], [1, 1, 2], [0, 1, 1]], [[0, 1, 2], [0, 2, 3]])
        >>> p = geoimg.Parametrization(m.vertices[:, :2], (1, 1))
        >>> geoimg.fit_surface(m, p, s=1).evaluate([[0.5, 0.25]]).round(12).tolist()
        [[0.5, 0.25, 0.75]]
        """
        return self._points(uv, exact)[0]

    def derivatives(self, uv, *, exact: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Analytic first derivatives ``(P_u, P_v)``, each of shape (k, 3)."""
        _, pu, pv, _ = self._points(uv, exact)
        return pu, pv

    def normals(self, uv, *, exact: bool = False) -> np.ndarray:
        """Unit normals ``orientation * (P_u x P_v) / |P_u x P_v|`` from the analytic derivatives, shape (k, 3)."""
        pu, pv = self.derivatives(uv, exact=exact)
        return _unit(np.cross(pu, pv) * self.orientation)

    # ---------------------------------------------------------------- sampling
    def auto_resolution(self) -> int:
        """Pixels along the longer side for a sample spacing of ``s * mean(d_i)`` (the paper's section 4.4)."""
        spacing = self.s * float(self.faces.d.mean())
        res = int(math.ceil(max(self.extent) / spacing)) + 1
        if res > MAX_AUTO_RESOLUTION:
            warnings.warn(f"automatic resolution {res} capped at {MAX_AUTO_RESOLUTION}", stacklevel=3)
        return max(2, min(res, MAX_AUTO_RESOLUTION))

    def grid(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The sample positions ``u`` (columns) and ``v`` (rows) for a resolution along the longer side.

        The shorter side gets the count that keeps pixels nearly square; corners sit on the rectangle's
        corners (spacing ``extent / (count - 1)``, as the paper's increments of 1/255 for 256 samples).
        """
        if resolution is None:
            resolution = self.auto_resolution()
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ValueError(f"resolution: expected an integer >= 2, got {resolution!r}")
        big = max(self.extent)
        counts = [max(2, int(round((resolution - 1) * e / big)) + 1) for e in self.extent]
        return np.linspace(0.0, self.extent[0], counts[0]), np.linspace(0.0, self.extent[1], counts[1])

    def sample(self, resolution: int | None = None, *, normals: bool = True):
        """Resample the surface on a regular grid into a :class:`~geoimg.GeometryImage`.

        Parameters
        ----------
        resolution : int, optional
            Pixels along the longer side; default :meth:`auto_resolution`.
        normals : bool, default True
            Also compute exact normals from the analytic derivatives.

        Returns
        -------
        GeometryImage
            float32 pixels (H, W, 3); ``mask`` marks pixels inside the parametrized faces, or within
            half a pixel spacing of one, so a terrain whose border is not perfectly straight keeps its
            outer ring (and, for locally supported weights, not in a hole).

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 1], [1, 1, 2], [0, 1, 1]], [[0, 1, 2], [0, 2, 3]])
        >>> img = geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2], (1, 1)), s=2).sample(5)
        >>> img.pixels.shape, bool(img.mask.all())
        ((5, 5, 3), True)
        """
        from .image import GeometryImage

        u, v = self.grid(resolution)
        H, W = len(v), len(u)
        fm = self.faces
        n_exact = 0
        if self.weights == "gaussian" and self.tol > 0 and self.s_map is None:
            P, Pu, Pv, ok = kernels.sample_grid_gaussian(
                u, v, fm.centres, self.sigma, self._radius, fm.C, fm.A, fm.B, derivatives=normals, log_g_ref=self.log_g_ref)
            status = np.zeros((H, W), np.int8)
            if not ok.all():
                ii, jj = np.nonzero(~ok)
                p, pu, pv, st = self._points(np.stack([u[jj], v[ii]], axis=1), True)
                P[ii, jj], Pu[ii, jj], Pv[ii, jj], status[ii, jj] = p, pu, pv, st
                n_exact = len(ii)
        else:
            uu, vv = np.meshgrid(u, v)
            p, pu, pv, st = self._points(np.stack([uu.ravel(), vv.ravel()], axis=1), False)
            P, Pu, Pv = p.reshape(H, W, 3), pu.reshape(H, W, 3), pv.reshape(H, W, 3)
            status = st.reshape(H, W)
            n_exact = int((status == kernels.EXACT).sum())
        holes = status == kernels.HOLE
        eps = 0.5 * max(u[1] - u[0], v[1] - v[0])  # conservative: within half a pixel of a face
        mask = kernels.face_coverage(u, v, self.polygons, self.sizes, eps) & ~holes
        nrm = _unit(np.cross(Pu, Pv) * self.orientation).astype(np.float32) if normals else None
        meta = {
            "domain": self.domain, "s": float(self.s), "weights": self.weights, "n": int(self.n),
            "tol": float(self.tol), "sliver_rule": self.sliver_rule, "resolution": int(max(H, W)),
            "extent": [float(e) for e in self.extent], "source": "", "orientation": int(self.orientation),
            "exact_pixels": int(n_exact), "hole_pixels": int(holes.sum()),
        }
        if self.s_face is not None:
            meta["s_max"] = float(self.s_face.max())
        if self.s_map is not None:
            meta["s_max"] = float(self.s_map.max)
        if holes.any():
            warnings.warn(f"locally supported weights (n={self.n}) leave {int(holes.sum())} pixels uncovered "
                          "(holes); they are masked. Raise n to close them.", stacklevel=2)
        return GeometryImage(P.astype(np.float32), mask, domain=self.domain, normals=nrm, metadata=meta)


def reference_log_weight(s: float) -> float:
    """log of the least Gaussian weight a point inside a face gets from it: ``-(4/3)^2 / 2 s^2``."""
    return -TRUNCATION_RHO ** 2 / (2.0 * s ** 2)


def truncation_radius(sigma: np.ndarray, s: float, tol: float) -> np.ndarray:
    """Distance beyond which a face's weight is below ``tol`` times the least weight of a point's own face."""
    return sigma * math.sqrt(2.0 * math.log(1.0 / tol) + TRUNCATION_RHO ** 2 / s ** 2)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


def _smoothness(s, n_faces: int) -> tuple[float, np.ndarray | None, object]:
    """``(s, None, None)`` for a number; ``(min s, per-face s, None)`` for an array; ``(min s, None, map)``
    for a :class:`~geoimg.regions.SmoothnessMap` (truncation and its certificate use the minimum, which
    is conservative)."""
    from .regions import SmoothnessMap

    if isinstance(s, SmoothnessMap):
        return float(s.min), None, s
    if isinstance(s, (int, float, np.number)) and not isinstance(s, bool):
        if not (np.isfinite(s) and s > 0):
            raise ValueError(f"s: expected a positive finite number, got {s!r}")
        return float(s), None, None
    arr = np.asarray(s) if not isinstance(s, (str, bytes, bool)) else np.asarray([])
    if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or arr.shape != (n_faces,):
        raise ValueError(f"s: expected a positive number or {n_faces} per-face values, got {s!r:.80}")
    arr = arr.astype(np.float64)
    if not (np.isfinite(arr).all() and (arr > 0).all()):
        raise ValueError("s: per-face values must be positive and finite")
    return float(arr.min()), arr, None


def fit_surface(mesh: Mesh, param: Parametrization, s: float = 1.0, *, weights: str = "gaussian", n: int = 10,
                tol: float = 1e-10, sliver_rule: str = "robust") -> Surface:
    """Fit the weighted-mean surface of a parametrized mesh.

    Parameters
    ----------
    mesh : Mesh
    param : Parametrization
        Per-vertex (u, v) of the mesh (see :func:`geoimg.parametrize`).
    s : float, array_like of shape (mesh.n_faces,), or SmoothnessMap; default 1.0
        Smoothness: sigma_i = s d_i (Gaussian weights). Per-face values
        (:func:`geoimg.regions.smoothness_field`) or a map s(u, v) that varies with the point evaluated
        (:func:`geoimg.regions.uv_smoothness`, planar only) give a surface smoothed more in some places
        than in others, its normals still exact (paper 4.5). Per-face values cannot keep a region sharp
        inside a smoothed surrounding (the wide Gaussians around reach in); a map can.
    weights : {"gaussian", "local"}
        Rational Gaussian (infinitely smooth) or locally supported ``1 - 3R^2 + 2R^3`` (C1, faster, may
        leave holes, which are reported and masked).
    n : int, default 10
        Face centres inside each local weight's support (``weights="local"``).
    tol : float, default 1e-10
        Truncation: skipped weights are below ``tol``; 0 for the exact, untruncated sum.
    sliver_rule : {"robust", "paper"}
        How long thin faces are treated (see :mod:`geoimg.face_maps`).

    Returns
    -------
    Surface or SphereSurface
        A :class:`~geoimg.sphere_surface.SphereSurface` for a spherical (octahedral) parametrization.

    Raises
    ------
    ValueError
        On a bad ``s``, ``weights``, ``n``, ``tol`` or ``sliver_rule``, or a parametrization that does not
        match the mesh.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> surf = geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2], (1, 1)), s=2.0)
    >>> surf.evaluate([[0.5, 0.5]]).shape
    (1, 3)
    """
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    if not isinstance(param, Parametrization):
        raise TypeError(f"param: expected a geoimg.Parametrization, got {type(param).__name__}")
    if param.coords.shape[0] != mesh.n_vertices:
        raise ValueError(f"param: has {param.coords.shape[0]} points but the mesh has {mesh.n_vertices} vertices")
    if weights not in WEIGHTS:
        raise ValueError(f"weights: expected one of {WEIGHTS}, got {weights!r}")
    s, s_face, s_map = _smoothness(s, mesh.n_faces)
    if not (isinstance(tol, (int, float, np.number)) and 0 <= tol < 1):
        raise ValueError(f"tol: expected a number in [0, 1), got {tol!r}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"n: expected an integer >= 2, got {n!r}")
    if param.domain == "octahedral" and s_map is not None:
        raise ValueError("s: a smoothness map s(u, v) is for planar parametrizations; on the sphere give one s "
                         "per face (geoimg.regions.smoothness_field)")
    if param.domain == "octahedral":
        if weights != "gaussian":
            raise ValueError("weights: the octahedral (spherical) domain supports only 'gaussian' weights")
        from .sphere_surface import fit_sphere_surface

        return fit_sphere_surface(mesh, param.coords, s if s_face is None else s_face, float(tol), sliver_rule,
                                  int(param.info.get("orientation", 1)))
    fm = face_maps(mesh, param.coords, sliver_rule=sliver_rule)
    if fm.n_degenerate:
        warnings.warn(f"fit_surface: {fm.n_degenerate} faces of zero area in the parameter domain were left out",
                      stacklevel=2)
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
        dist, _ = cKDTree(fm.centres).query(fm.centres, k=k)
        radius = np.asarray(dist).reshape(len(fm.d), -1)[:, -1].copy()
        radius = np.maximum(radius, fm.d * 1e-6)  # a lone face still covers itself
        param_arr = np.zeros_like(radius)
    cells = kernels.build_cells(fm.centres, np.where(np.isfinite(radius), radius, 0.0))
    polys = param.coords[np.where(mesh.faces >= 0, mesh.faces, mesh.faces[:, :1])][fm.face_index]
    return Surface(fm, param.extent, s, weights, int(n), float(tol), sliver_rule,
                   int(param.info.get("orientation", 1)), param.domain, polys, mesh.face_sizes[fm.face_index], radius, param_arr, cells,
                   s_kept, s_map)
