"""Fourier operations on the periodic extension of an image: low-, high- and band-pass, and any
transfer function (inverse filtering builds on :func:`fourier_filter`).

The image is extended by its boundary rule (:func:`filters.padding.periodic_extension`: the symmetric
extension of a planar image, the 2 x 2 unfolding of an octahedral one), transformed with
``scipy.fft.rfft2``, multiplied by the gain, transformed back (a real result: coordinates are signed)
and cropped. On a planar image ``mode='wrap'`` is the naive FFT, which treats the opposite borders as
neighbours.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy import fft as sfft
from typing import Any

from ._checks import as_image, positive
from .padding import periodic_extension

__all__ = ["fourier_filter", "lowpass", "highpass", "bandpass", "butterworth"]


def fourier_filter(image: ArrayLike, gain: Any, mode: str = "reflect") -> np.ndarray:
    """Multiply the spectrum of the image's periodic extension by ``gain(fy, fx)`` and transform back.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
    gain : callable
        ``gain(fy, fx)`` of frequencies in cycles per pixel (``fy`` a column, ``fx`` a row: broadcast
        them) returning real or complex gains; evaluated on the ``rfft2`` grid of the extension.
    mode : {'reflect', 'wrap', 'octahedral'}
        ``reflect`` is computed as a DCT-I (the transform of the symmetric extension), so only the
        gain's even part (``gain(|fy|, |fx|)``, real) acts. float32 images are transformed in float32.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> img = np.random.default_rng(1).normal(size=(6, 7))
    >>> bool(np.allclose(fourier_filter(img, lambda fy, fx: 1 + 0 * fy * fx), img))
    True
    """
    a = as_image(image)
    real = np.float32 if a.dtype == np.float32 else np.float64
    h, w = a.shape[:2]
    if mode == "reflect" and h > 1 and w > 1:
        # the symmetric extension's spectrum is the DCT-I of the image: half the size, same result for
        # the even gains of smoothing and deconvolution (an even extension only sees a gain's even part)
        fy = (np.arange(h) / (2.0 * (h - 1)))[:, None]
        fx = (np.arange(w) / (2.0 * (w - 1)))[None, :]
        g = np.broadcast_to(np.real(np.asarray(gain(fy, fx))), (h, w)).astype(real)
        spec = sfft.dctn(a, type=1, axes=(0, 1), workers=-1)
        spec *= g[..., None] if a.ndim == 3 else g
        out = sfft.idctn(spec, type=1, axes=(0, 1), workers=-1)
        return out.astype(a.dtype, copy=False)
    ext = periodic_extension(a, mode)
    p, q = ext.shape[:2]
    fy, fx = sfft.fftfreq(p)[:, None], sfft.rfftfreq(q)[None, :]
    g = np.broadcast_to(np.asarray(gain(fy, fx)), (p, q // 2 + 1))
    g = g.astype(np.complex64 if real is np.float32 else np.complex128) if np.iscomplexobj(g) else g.astype(real)
    spec = sfft.rfft2(ext, axes=(0, 1), workers=-1)
    spec *= g[..., None] if ext.ndim == 3 else g
    out = sfft.irfft2(spec, s=(p, q), axes=(0, 1), workers=-1)
    return out[:h, :w].astype(a.dtype, copy=False)


def butterworth(cutoff: float, order: int = 2):
    """Gain ``1 / (1 + (f / cutoff)^(2 order))`` of the radial frequency ``f`` (cycles per pixel)."""
    positive(cutoff, "cutoff")
    positive(order, "order", integer=True)

    c2 = float(cutoff) ** 2             # 0 below 1e-162: every frequency but 0 is then far above the cutoff

    def gain(fy, fx):
        f2 = fy ** 2 + fx ** 2
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):     # gain 0 past float's range
            ratio = np.where(f2 > 0, f2 / c2, 0.0) if c2 == 0 else f2 / c2
            return 1.0 / (1.0 + ratio ** order)

    return gain


def lowpass(image: ArrayLike, cutoff: float, mode: str = "reflect", *, order: int = 2) -> np.ndarray:
    """Butterworth low-pass: frequencies above ``cutoff`` cycles per pixel (0.5: Nyquist) fade out.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    cutoff : float
        Cycles per pixel, in (0, 0.5].
    mode : str
        The periodic extension: ``reflect``, ``wrap`` or ``octahedral`` (:mod:`filters.padding`).
    order : int
        The Butterworth filter's order: larger is steeper.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> wave = np.cos(np.linspace(0, np.pi, 9))[None, :].repeat(4, axis=0)   # 1/16 cycle per pixel
    >>> float(abs(lowpass(wave, 0.2) - wave).max()) < 0.02                   # passes (gain 0.99)
    True
    """
    return fourier_filter(image, butterworth(cutoff, order), mode)


def highpass(image: ArrayLike, cutoff: float, mode: str = "reflect", *, order: int = 2) -> np.ndarray:
    """The detail the low-pass removes: ``image - lowpass(image)`` (zero mean; add it to another shape).

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    cutoff : float
        Cycles per pixel, in (0, 0.5].
    mode : str
        The periodic extension: ``reflect``, ``wrap`` or ``octahedral`` (:mod:`filters.padding`).
    order : int
        The Butterworth filter's order: larger is steeper.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Examples
    --------
    >>> flat = np.full((8, 8), 3.0)
    >>> float(abs(highpass(flat, 0.2)).max()) < 1e-12          # a constant has no detail
    True
    """
    lp = butterworth(cutoff, order)
    return fourier_filter(image, lambda fy, fx: 1.0 - lp(fy, fx), mode)


def bandpass(image: ArrayLike, low: float, high: float, mode: str = "reflect", *, order: int = 2) -> np.ndarray:
    """Frequencies between ``low`` and ``high`` cycles per pixel: ``lowpass(high) - lowpass(low)``.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    low, high : float
        The band's edges, cycles per pixel, ``0 <= low < high <= 0.5``.
    mode : str
        The periodic extension: ``reflect``, ``wrap`` or ``octahedral`` (:mod:`filters.padding`).
    order : int
        The Butterworth filter's order: larger is steeper.

    Returns
    -------
    numpy.ndarray
        The filtered image, of the input's shape; float32 stays float32.

    Raises
    ------
    ValueError
        When not ``0 < low < high``.

    Examples
    --------
    >>> flat = np.full((16, 16), 3.0)
    >>> band = bandpass(flat, 0.1, 0.3)                  # a constant lies below every band
    >>> band.shape, bool(abs(band).max() < 1e-12)
    ((16, 16), True)
    """
    positive(low, "low")
    positive(high, "high")
    if not low < high:
        raise ValueError(f"low, high: expected 0 < low < high, got {low!r}, {high!r}")
    lo, hi = butterworth(low, order), butterworth(high, order)
    return fourier_filter(image, lambda fy, fx: hi(fy, fx) - lo(fy, fx), mode)
