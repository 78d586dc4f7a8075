"""Sharpening: the paper's inverse filter (deconvolution of a known blur in the Fourier domain,
regularized) and unsharp masking.

The blur is a separable kernel (the mean filter's box by default, or a Gaussian) exactly as the
spatial filters of :mod:`filters.smoothing` apply it; its transfer function on the periodic extension
is ``H(fy) H(fx)`` with ``H(f) = sum_j k_j cos(2 pi f j)`` (real: the kernels are symmetric). The
inverse gain is regularized, by Wiener (``H / (H^2 + nsr (1 - H^2))``: exactly 1 at ``H = 1``) or by clamping
``|1/H|`` at
``max_gain``; the result's real part is kept.
"""
from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import ArrayLike

from ._checks import positive
from .fourier import fourier_filter
from .smoothing import gaussian_filter, gaussian_kernel_radius

__all__ = ["blur_taps", "blur_transfer", "inverse_filter", "unsharp_mask", "INVERSE_METHODS"]

INVERSE_METHODS = ("wiener", "clamp")


def blur_taps(blur: str = "mean", size: int = 3, sigma: float = 1.0) -> np.ndarray:
    """1-D taps of the separable blur: ``mean`` (box of ``size``) or ``gaussian`` (OpenCV's kernel,
    half-width ``ceil(4 sigma)``), centred.
    """
    if blur == "mean":
        positive(size, "size", integer=True, odd=True)
        return np.full(size, 1.0 / size)
    if blur == "gaussian":
        positive(sigma, "sigma")
        r = gaussian_kernel_radius(sigma)
        return cv2.getGaussianKernel(2 * r + 1, sigma, cv2.CV_64F).ravel()
    raise ValueError(f"blur: expected 'mean' or 'gaussian', got {blur!r}")


def blur_transfer(taps: np.ndarray):
    """Transfer function ``H(fy, fx)`` of the separable symmetric kernel with these 1-D taps.

    Examples
    --------
    >>> h = blur_transfer(blur_taps("mean", 3))
    >>> round(float(h(np.array(0.0), np.array(1 / 3))), 12)     # the 3-box's zero
    0.0
    """
    taps = np.asarray(taps, dtype=np.float64)
    offs = np.arange(len(taps)) - len(taps) // 2

    def one(f):
        return np.tensordot(np.cos(2 * np.pi * np.asarray(f)[..., None] * offs), taps, axes=([-1], [0]))

    return lambda fy, fx: one(fy) * one(fx)


def inverse_filter(image: ArrayLike, blur: str = "mean", size: int = 3, sigma: float = 1.0, mode: str = "reflect", *,
                   method: str = "wiener", nsr: float = 1e-3, max_gain: float = 10.0) -> np.ndarray:
    """Undo a known blur: the paper's inverse filter, regularized.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
    blur, size, sigma
        The blur to undo (see :func:`blur_taps`); the default undoes ``mean_filter(image, 3)``.
    mode : {'reflect', 'wrap', 'octahedral'}
        The periodic extension (the same rule the blur was applied with).
    method : {'wiener', 'clamp'}
        ``wiener``: gain ``H / (H^2 + nsr (1 - H^2))`` (the regularization fades where the blur
        passes all, ``H = 1``, so the mean position is not scaled); ``clamp``: ``1 / H`` with its magnitude capped at
        ``max_gain`` (the sign of ``H`` kept). ``nsr`` is the noise-to-signal power ratio: larger
        values sharpen less and amplify noise and float32 rounding less.

    nsr : float
        The noise-to-signal power ratio of ``wiener``.
    max_gain : float
        The largest gain magnitude of ``clamp``.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Raises
    ------
    ValueError
        When ``method`` or ``blur`` is unknown.

    Examples
    --------
    >>> from filters import mean_filter
    >>> img = np.cos(np.linspace(0, 3, 17))[None, :] * np.ones((12, 1))
    >>> back = inverse_filter(mean_filter(img, 3), nsr=1e-9)
    >>> float(abs(back - img).max()) < 1e-8
    True

    A frequency where ``H = 0`` is lost whatever the regularization: the 3-box's zero, 1/3 cycle per
    pixel, lies on the Fourier grid when the extension's period is a multiple of 3.
    """
    if method not in INVERSE_METHODS:
        raise ValueError(f"method: expected one of {INVERSE_METHODS}, got {method!r}")
    h = blur_transfer(blur_taps(blur, size, sigma))
    if method == "wiener":
        positive(nsr, "nsr")

        def gain(fy, fx):
            hh = h(fy, fx)
            return hh / (hh * hh + nsr * (1.0 - hh * hh))
    else:
        positive(max_gain, "max_gain")

        def gain(fy, fx):
            hh = h(fy, fx)
            mag = np.maximum(np.abs(hh), 1.0 / max_gain)
            return np.where(hh < 0, -1.0, 1.0) / mag

    return fourier_filter(image, gain, mode)


def unsharp_mask(image: ArrayLike, sigma: float = 1.0, amount: float = 1.0, mode: str = "reflect") -> np.ndarray:
    """``image + amount (image - gaussian_filter(image, sigma))``: the simple sharpening.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    sigma : float
        The Gaussian's standard deviation, pixels.
    amount : float
        How much of the detail is added back.
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> flat = np.full((4, 4), 3.0)
    >>> unsharp_mask(flat, 1.0, 2.0).tolist() == flat.tolist()
    True
    """
    positive(amount, "amount", allow_zero=True)
    a = np.asarray(image)
    blurred = gaussian_filter(a, sigma, mode)
    out = blurred + (1.0 + amount) * (np.asarray(a, blurred.dtype) - blurred)
    return out.astype(blurred.dtype, copy=False)
