"""Denoisers from scikit-image and SciPy on float images through the shared boundary rules: a median
filter, total-variation denoising (Chambolle) and non-local means. Strengths are in the image's own
units (for a geometry image: coordinate units, about the noise's standard deviation).

Every function takes ``mode`` (see :mod:`filters.padding`) and an optional ``mask`` with ``feather``, as
the smoothing filters do.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage
from skimage import restoration

from ._checks import as_image, positive
from .smoothing import filter_padded

__all__ = ["median_filter", "denoise_tv", "denoise_nl_means"]

TV_PAD = 16           # total variation couples all pixels; its pull fades within a few pixels of an edge


def median_filter(image: ArrayLike, size: int = 3, mode: str = "reflect", *, mask: ArrayLike | None = None,
                  feather: float = 0.0) -> np.ndarray:
    """Each channel's median over the ``size x size`` block around each pixel: removes spikes (a
    scanner's outliers) that smoothing would spread.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    size : int
        The block's side, odd.
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
    >>> spike = np.zeros((5, 5))
    >>> spike[2, 2] = 9.0
    >>> float(median_filter(spike, 3).max())
    0.0
    """
    positive(size, "size", integer=True, odd=True)
    footprint = (size, size) + (1,) * (as_image(image).ndim - 2)
    return filter_padded(image, size // 2, mode, lambda p: ndimage.median_filter(p, size=footprint, mode="nearest"),
                         mask=mask, feather=feather)


def denoise_tv(image: ArrayLike, weight: float, mode: str = "reflect", *, mask: ArrayLike | None = None,
               feather: float = 0.0) -> np.ndarray:
    """Total-variation denoising (scikit-image's Chambolle), channels together; ``weight`` in the image's
    units: larger removes more and flattens more.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    weight : float
        The denoising weight, in the image's units.
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
    >>> noisy = np.random.default_rng(0).normal(0, 0.1, (32, 32))
    >>> bool(denoise_tv(noisy, 0.2).std() < 0.5 * noisy.std())
    True
    """
    positive(weight, "weight")
    a = as_image(image)
    axis = -1 if a.ndim == 3 else None
    return filter_padded(a, TV_PAD, mode, lambda p: restoration.denoise_tv_chambolle(
        p.astype(np.float64), weight=weight, channel_axis=axis), mask=mask, feather=feather)


def denoise_nl_means(image: ArrayLike, h: float, mode: str = "reflect", *, patch_size: int = 5, patch_distance: int = 6,
                     mask: ArrayLike | None = None, feather: float = 0.0) -> np.ndarray:
    """Non-local means (scikit-image, fast mode): each pixel the average of pixels whose ``patch_size``
    patches within ``patch_distance`` look alike; ``h`` in the image's units (about the noise's standard
    deviation).

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    h : float
        The filtering strength, in the image's units.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).
    patch_size : int
        Side of the patches compared, pixels.
    patch_distance : int
        How far patches are searched, pixels.
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
    >>> noisy = np.random.default_rng(0).normal(0, 0.1, (24, 24))
    >>> bool(denoise_nl_means(noisy, 0.1).std() < 0.5 * noisy.std())
    True
    """
    positive(h, "h")
    positive(patch_size, "patch_size", integer=True)
    positive(patch_distance, "patch_distance", integer=True)
    a = as_image(image)
    axis = -1 if a.ndim == 3 else None
    reach = patch_size // 2 + patch_distance
    return filter_padded(a, reach, mode, lambda p: restoration.denoise_nl_means(
        p.astype(np.float64), h=h, patch_size=patch_size, patch_distance=patch_distance, fast_mode=True,
        channel_axis=axis), mask=mask, feather=feather)
