"""The interface every weighted-mean surface has, whatever its domain, and the truncation rule they share.

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
from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import ArrayLike

from .._budget import check_memory
from .._choices import BACKENDS
from ..errors import ImageError, InputError
from ..image import Domain, GeometryImage

__all__ = ["Surface", "check_backend", "reference_log_weight", "truncation_radius", "unit", "TRUNCATION_RHO"]

TRUNCATION_RHO = 4.0 / 3.0
SAMPLE_BYTES_PER_PIXEL = 200      # positions, two derivatives, sums and the mask while sampling, in float64


def _check_float32(P: np.ndarray) -> None:
    """Refuse surface points that a float32 image cannot hold: infinite in float32, or a surface so small
    that float32's subnormal range (below about 1e-31) leaves fewer than its 7 digits. Single coordinates
    near 0 that float32 rounds to 0 lose nothing next to the surface's size and pass.
    """
    size = max(float(P.max()), -float(P.min())) if P.size else 0.0      # NaN when any is NaN
    f32 = np.finfo(np.float32)
    if not size <= float(f32.max) or 0 < size < float(f32.tiny / f32.eps):
        raise ImageError(f"the surface's coordinates (up to {size:.3g}) cannot be held in a float32 image "
                         "(about 1e-31 to 3e38 for its 7 digits); scale the mesh first")


def check_backend(backend: str) -> None:
    """Refuse a sampling backend that is not one of :data:`BACKENDS`, or ``"cuda"`` where no CUDA GPU is usable."""
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise InputError(f"backend: expected one of {BACKENDS}, got {backend!r}")
    if backend == "cuda":
        from ._gaussian_cuda_kernels import cuda_unavailable
        why = cuda_unavailable()
        if why is not None:
            raise InputError(f"backend 'cuda': {why}; use the 'cpu' backend")


def reference_log_weight(s: float) -> float:
    """Log of the least Gaussian weight a point inside a face gets from it: ``-(4/3)^2 / 2 s^2``."""
    return -TRUNCATION_RHO ** 2 / (2.0 * s ** 2)


def truncation_radius(sigma: np.ndarray, s: float, tol: float) -> np.ndarray:
    """Distance beyond which a face's weight is below ``tol`` times the least weight of a point's own face."""
    return sigma * math.sqrt(2.0 * math.log(1.0 / tol) + TRUNCATION_RHO ** 2 / s ** 2)


def unit(v: np.ndarray) -> np.ndarray:
    """Rows of ``v`` scaled to length 1 (zero rows stay zero)."""
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


class Surface(ABC):
    """A fitted weighted-mean surface ``P(u, v)``; build one with :func:`geoimg.fit_surface`.

    Points are addressed by image coordinates ``(u, v)`` of its :attr:`domain` (the parameter rectangle
    ``[0, extent[0]] x [0, extent[1]]``). Every surface has the same methods: :meth:`evaluate`,
    :meth:`derivatives`, :meth:`normals`, :meth:`curvature`, :meth:`auto_resolution`, :meth:`grid`
    and :meth:`sample`.

    Attributes
    ----------
    domain : Domain
        The kind of geometry image it samples into, with its extent and orientation.
    s, weights, n, tol, sliver_rule
        The fit's settings (``s`` the smallest when it varies).

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
    >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
    >>> isinstance(surf, geoimg.Surface), surf.evaluate([[0.5, 0.5]]).shape, surf.sample(5).shape
    (True, (1, 3), (5, 5))
    """

    domain: Domain
    s: float
    weights: str
    n: int
    tol: float
    sliver_rule: str

    @property
    def extent(self) -> tuple:
        """The parameter rectangle's size (the longer side 1).

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> surf.extent
        (1.0, 1.0)
        """
        return self.domain.extent

    @property
    def orientation(self) -> int:
        """+1 when ``P_u x P_v`` points along the mesh's face normals, else -1.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> surf.orientation in (1, -1)
        True
        """
        return self.domain.orientation

    @property
    def log_g_ref(self) -> float:
        """Log of the least Gaussian a point inside a face receives from that face (-inf for local weights).

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> surf.log_g_ref < 0
        True
        """
        if self.weights != "gaussian":
            return -math.inf
        return reference_log_weight(self.s)

    @abstractmethod
    def evaluate(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Surface points (k, 3) at image coordinates ``uv`` (k, 2); ``exact`` sums over every face
        instead of the truncated neighbourhood.

        Parameters
        ----------
        uv : array_like
            (k, 2) image coordinates in the parameter rectangle.
        exact : bool
            Sum over every face instead of the truncated sum.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> surf.evaluate([[0.0, 0.0], [1.0, 1.0]]).shape
        (2, 3)
        """

    @abstractmethod
    def derivatives(self, uv: ArrayLike, *, exact: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Analytic first derivatives ``(P_u, P_v)``, each of shape (k, 3).

        Parameters
        ----------
        uv : array_like
            (k, 2) image coordinates in the parameter rectangle.
        exact : bool
            Sum over every face instead of the truncated sum.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> Pu, Pv = surf.derivatives([[0.5, 0.5]])
        >>> Pu.shape
        (1, 3)
        """

    @abstractmethod
    def normals(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Unit normals (k, 3) from the analytic derivatives, pointing like the mesh's faces.

        Parameters
        ----------
        uv : array_like
            (k, 2) image coordinates in the parameter rectangle.
        exact : bool
            Sum over every face instead of the truncated sum.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> n = surf.normals([[0.5, 0.5]])
        >>> bool(abs(np.linalg.norm(n) - 1) < 1e-12)
        True
        """

    @abstractmethod
    def curvature(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Gaussian and mean curvature ``(K, H)`` on the grid :meth:`sample` uses, each (H, W) float64.

        Parameters
        ----------
        resolution : int or None
            The grid's size (see :meth:`sample`).

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> K, H = surf.curvature(5)
        >>> K.shape
        (5, 5)
        """

    @abstractmethod
    def auto_resolution(self) -> int:
        """Pixels along the longer side for a sample spacing of ``s * mean(d_i)`` (the paper's section 4.4).

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> isinstance(surf.auto_resolution(), int)
        True
        """

    @abstractmethod
    def _sample_grid(self, shape, normals: bool, backend: str = "cpu"):
        """``(P, N, mask, exact_pixels, hole_pixels)`` on the domain's grid of ``shape``: positions
        (H, W, 3), unit normals or None, the validity mask or None, and how many pixels were summed
        exactly or left uncovered; ``backend`` one of :data:`BACKENDS` (an unsupported one raises
        :class:`~geoimg.errors.InputError`).
        """

    def _s_max(self) -> float | None:
        """The largest s when it varies over the surface."""
        return None

    def grid(self, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The image coordinates of the columns (u) and rows (v) for a resolution along the longer side
        (default :meth:`auto_resolution`).

        Parameters
        ----------
        resolution : int or None
            Pixels along the longer side (default :meth:`auto_resolution`).

        Returns
        -------
        u, v : numpy.ndarray
            The columns' and rows' coordinates.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.grid_mesh([[0.0, 0.0], [1.0, 1.0]], (1.0, 1.0))
        >>> surf = geoimg.fit_surface(m, geoimg.parametrize(m, "heightfield", axis="z"), geoimg.GaussianWeights())
        >>> u, v = surf.grid(5)
        >>> u.tolist()
        [0.0, 0.25, 0.5, 0.75, 1.0]
        """
        res = self.auto_resolution() if resolution is None else resolution
        return self.domain.pixel_uv(self.domain.grid_shape(res))

    def sample(self, resolution: int | None = None, *, normals: bool = True, backend: str = "cpu") -> GeometryImage:
        """Resample the surface on a regular grid into a :class:`~geoimg.GeometryImage`.

        Parameters
        ----------
        resolution : int, optional
            Pixels along the longer side; default :meth:`auto_resolution`.
        normals : bool, default True
            Also compute exact normals from the analytic derivatives.
        backend : {"cpu", "cuda"}, default "cpu"
            Where the truncated Gaussian sums run: numba on the CPU's cores, or numba.cuda on a CUDA GPU
            (planar domains with Gaussian weights, ``tol > 0`` and one s or per-face s, not a smoothness
            map; the pixels agree with the CPU's to rounding). ``"cuda"`` without a usable GPU, or where it
            does not apply, raises :class:`~geoimg.errors.InputError`.

        Returns
        -------
        GeometryImage
            float32 pixels (H, W, 3) of the surface's domain; the metadata records the fit's settings.
            Glued pixels are averaged; where they differed (the two sides of a cut, each seeing the
            surface from its side), ``metadata["glue_spread"]`` is the largest distance of one from their
            mean before.

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 1], [1, 1, 2], [0, 1, 1]], [[0, 1, 2], [0, 2, 3]])
        >>> param = geoimg.Parametrization(m.vertices[:, :2], (1, 1))
        >>> img = geoimg.fit_surface(m, param, geoimg.GaussianWeights(s=2)).sample(5)
        >>> img.pixels.shape, bool(img.mask.all()), img.metadata["s"]
        ((5, 5, 3), True, 2.0)
        """
        check_backend(backend)
        shape = self.domain.grid_shape(self.auto_resolution() if resolution is None else resolution)
        check_memory(shape[0] * shape[1] * SAMPLE_BYTES_PER_PIXEL, f"a {shape[1]} x {shape[0]} geometry image")
        P, nrm, mask, n_exact, n_holes = self._sample_grid(shape, normals, backend)
        _check_float32(P)
        P, nrm, spread = self._glue(P, nrm)
        meta = {"s": float(self.s), "weights": self.weights, "n": int(self.n), "tol": float(self.tol),
                "sliver_rule": self.sliver_rule, "resolution": int(max(shape)), "source": "",
                "exact_pixels": int(n_exact), "hole_pixels": int(n_holes)}
        s_max = self._s_max()
        if s_max is not None:
            meta["s_max"] = float(s_max)
        if spread > 0:      # glued pixels that the surface put apart (a cut's two sides), before averaging
            meta["glue_spread"] = spread
        if n_holes:
            warnings.warn(f"locally supported weights (n={self.n}) leave {n_holes} pixels uncovered (holes); they "
                          "are masked. Raise n to close them.", stacklevel=2)
        return GeometryImage(P.astype(np.float32), mask, self.domain,
                             normals=None if nrm is None else nrm.astype(np.float32), metadata=meta)

    def _glue(self, P: np.ndarray, nrm: np.ndarray | None):
        """Glued pixels made one point: positions (and normals) averaged over each group. Returns them and
        the largest distance of a pixel from its group's mean before (0 where the surface already agreed,
        as on the octahedral domain, whose glued pixels are evaluated at identical directions).
        """
        glued = self.domain.average_glued(P)
        if glued is P:
            return P, nrm, 0.0
        spread = float(np.linalg.norm(glued - P, axis=-1).max())
        if nrm is not None and spread > 0:
            averaged = self.domain.average_glued(nrm)
            moved = np.any(averaged != nrm, axis=-1)
            nrm = np.where(moved[..., None], unit(averaged), nrm)
        return glued, nrm, spread

    def _capped(self, resolution: int, cap: int) -> int:
        """``resolution`` made one the domain allows, and at most ``cap`` (with a warning when capped)."""
        res = self.domain.round_resolution(resolution)
        if res > cap:
            warnings.warn(f"automatic resolution {res} capped at {cap}", stacklevel=4)
            res = cap
            while self.domain.round_resolution(res) > cap:
                res -= 1
            res = self.domain.round_resolution(res)
        return res
