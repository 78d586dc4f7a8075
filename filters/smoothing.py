"""Smoothing: mean (box) filter as in the paper, Gaussian, and edge-preserving bilateral and guided
filters (OpenCV), on float images without quantization, through the shared boundary rules.

Every function takes ``mode`` (see :mod:`filters.padding`) and an optional ``mask`` with ``feather``:
then only the masked region is smoothed, blended into the rest over ``feather`` pixels, and pixels
farther away stay bit-identical.
"""
from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import ArrayLike

from ._checks import as_image, as_weights, positive
from .masks import apply_masked, feather as feather_mask
from .padding import pad

__all__ = ["mean_filter", "gaussian_filter", "bilateral_filter", "guided_filter", "filter_padded"]


def filter_padded(image, radius: int, mode: str, fn, *, mask=None, feather: float = 0.0) -> np.ndarray:
    """Apply ``fn`` (padded array -> array of the same shape) to the image padded by ``radius`` with
    ``mode`` and crop back: the one way every spatial filter meets the boundary. Then apply the mask.
    """
    a = as_image(image)
    h, w = a.shape[:2]
    padded = np.ascontiguousarray(pad(a, radius, mode))
    out = np.asarray(fn(padded)).reshape(padded.shape)[radius:radius + h, radius:radius + w]
    out = out.astype(a.dtype, copy=False)
    if mask is None:
        return out
    return apply_masked(a, out, feather_mask(as_weights(mask, (h, w)), feather, mode))


def mean_filter(image: ArrayLike, size: int = 3, mode: str = "reflect", *, iterations: int = 1,
                mask: ArrayLike | None = None, feather: float = 0.0) -> np.ndarray:
    """The paper's mean filter: each pixel becomes the mean of the ``size x size`` block around it.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    size : int
        The block's side, odd.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).
    iterations : int
        How many times the filter is applied.
    mask : array_like or None
        Where the operation acts (booleans or weights in [0, 1], (H, W)); None means everywhere.
    feather : float
        Pixels over which the result blends back into the input outside the mask.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> mean_filter(np.array([[0.0, 3.0, 0.0]]), 3, "wrap").tolist()
    [[1.0, 1.0, 1.0]]
    """
    positive(size, "size", integer=True, odd=True)
    positive(iterations, "iterations", integer=True)
    r = size // 2 * iterations

    def box(p):
        for _ in range(iterations):
            p = cv2.blur(p, (size, size), borderType=cv2.BORDER_REFLECT_101)
        return p

    return filter_padded(image, r, mode, box, mask=mask, feather=feather)


def gaussian_kernel_radius(sigma: float) -> int:
    """Half-width of the sampled Gaussian: ``ceil(4 sigma)`` pixels."""
    return max(1, int(math.ceil(4.0 * sigma)))


def gaussian_filter(image: ArrayLike, sigma: float = 1.0, mode: str = "reflect", *, mask: ArrayLike | None = None,
                    feather: float = 0.0) -> np.ndarray:
    """Gaussian smoothing, standard deviation ``sigma`` pixels (kernel of half-width ``ceil(4 sigma)``).

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    sigma : float
        Standard deviation, pixels.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).
    mask : array_like or None
        Where the operation acts (booleans or weights in [0, 1], (H, W)); None means everywhere.
    feather : float
        Pixels over which the result blends back into the input outside the mask.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> img = np.full((5, 5, 3), 2.0)
    >>> bool(np.allclose(gaussian_filter(img, 1.5), 2.0))
    True
    """
    positive(sigma, "sigma")
    r = gaussian_kernel_radius(sigma)
    return filter_padded(image, r, mode, lambda p: cv2.GaussianBlur(p, (2 * r + 1, 2 * r + 1), sigma, sigmaY=sigma,
                                                                  borderType=cv2.BORDER_REFLECT_101),
                         mask=mask, feather=feather)


def _three_or_one(a: np.ndarray, what: str) -> None:
    if a.ndim == 3 and a.shape[2] not in (1, 3):
        raise ValueError(f"image: the {what} takes 1 or 3 channels, got {a.shape[2]}")


def bilateral_filter(image: ArrayLike, sigma_space: float = 2.0, sigma_range: float = 1.0, mode: str = "reflect", *,
                     mask: ArrayLike | None = None, feather: float = 0.0) -> np.ndarray:
    """Edge-preserving bilateral filter (``cv2.bilateralFilter``, computed in float32).

    ``sigma_range`` is in the image's units (for a geometry image: coordinate units; OpenCV measures the
    difference of two pixels as the sum of the channels' absolute differences).

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    sigma_space : float
        The spatial Gaussian's standard deviation, pixels.
    sigma_range : float
        The range Gaussian's standard deviation, image units.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).
    mask : array_like or None
        Where the operation acts (booleans or weights in [0, 1], (H, W)); None means everywhere.
    feather : float
        Pixels over which the result blends back into the input outside the mask.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> step = np.repeat([[0.0] * 4 + [1.0] * 4], 3, axis=0).astype(np.float32)
    >>> out = bilateral_filter(step, 2.0, 0.1)
    >>> float(abs(out - step).max()) < 1e-3      # the edge survives
    True
    """
    positive(sigma_space, "sigma_space")
    positive(sigma_range, "sigma_range")
    a = as_image(image)
    _three_or_one(a, "bilateral filter")
    r = gaussian_kernel_radius(sigma_space) // 2 + 1
    out = filter_padded(a.astype(np.float32), r, mode,
                        lambda p: cv2.bilateralFilter(p, 2 * r + 1, float(sigma_range), float(sigma_space),
                                                      borderType=cv2.BORDER_REFLECT_101),
                        mask=mask, feather=feather)
    return out.astype(a.dtype)


def guided_filter(image: ArrayLike, radius: int = 4, eps: float = 1e-4, mode: str = "reflect", *,
                  guide: ArrayLike | None = None, mask: ArrayLike | None = None, feather: float = 0.0) -> np.ndarray:
    """Edge-preserving guided filter (He et al.; ``cv2.ximgproc.guidedFilter``, computed in float32).

    ``eps`` is the regularization in squared image units: structure with variance well above ``eps``
    within a window is kept, below it is smoothed. The guide defaults to the image itself.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    radius : int
        The window's radius, pixels.
    eps : float
        The regularization, squared image units.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).
    guide : array_like or None
        The guide image (H, W) or (H, W, C); the image itself by default.
    mask : array_like or None
        Where the operation acts (booleans or weights in [0, 1], (H, W)); None means everywhere.
    feather : float
        Pixels over which the result blends back into the input outside the mask.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Raises
    ------
    ValueError
        When the guide's (H, W) is not the image's.

    Examples
    --------
    >>> img = np.random.default_rng(0).normal(size=(16, 16)).astype(np.float32)
    >>> guided_filter(img, 2, 0.1).shape
    (16, 16)
    """
    positive(radius, "radius", integer=True)
    positive(eps, "eps")
    a = as_image(image)
    _three_or_one(a, "guided filter")
    g = a if guide is None else as_image(guide, "guide")
    if g.shape[:2] != a.shape[:2]:
        raise ValueError(f"guide: expected shape {a.shape[:2]} (H, W), got {g.shape[:2]}")
    _three_or_one(g, "guided filter's guide")
    reach = 2 * radius          # two rounds of box means: coefficients, then their means
    gp = np.ascontiguousarray(pad(g, reach, mode).astype(np.float32))
    out = filter_padded(a.astype(np.float32), reach, mode,
                        lambda p: cv2.ximgproc.guidedFilter(gp, p, int(radius), float(eps)),
                        mask=mask, feather=feather)
    return out.astype(a.dtype)
