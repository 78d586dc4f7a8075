"""Boundary rules: the one mechanism every filter uses at an image's edges.

Images are vertex-sampled: the first and last rows and columns lie on the domain's boundary. Rules:

``reflect``
    even extension about the edge pixels (``f(-i) = f(i)``; the edge pixel is not repeated): the
    planar domain's natural extension, periodic with period ``2 (H - 1)`` (the symmetric extension
    the Fourier operations use).
``linear``
    odd extension about the edge pixels (``f(-i) = 2 f(0) - f(i)``): keeps linear functions exactly,
    so a flat sheet stays where it is and a smoothed boundary does not pull in. Not periodic: spatial
    filters only.
``wrap``
    periodic with period ``H``.
``octahedral``
    the unfolded octahedron (an odd square, ``N = M + 1``): crossing a side continues the image
    rotated by 180 degrees about that side's midpoint, so each side's two glued halves meet. The
    2M x 2M "unfolding" tiles the plane periodically.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ._checks import as_image, check_memory

__all__ = ["pad", "periodic_extension", "PAD_MODES", "PERIODIC_MODES"]

PAD_MODES = ("reflect", "linear", "wrap", "octahedral")
PERIODIC_MODES = ("reflect", "wrap", "octahedral")


def _check_mode(mode: str, modes=PAD_MODES) -> str:
    if mode not in modes:
        extra = " ('linear' is not periodic: use 'reflect' for Fourier operations)" if mode == "linear" else ""
        raise ValueError(f"mode: expected one of {modes}, got {mode!r}{extra}")
    return mode


def _check_octahedral(shape) -> int:
    h, w = shape[:2]
    if h != w or h < 3 or h % 2 == 0:
        raise ValueError(f"image: mode 'octahedral' needs an odd square image (N x N, N >= 3), got {h} x {w}")
    return h - 1


def _fold_octahedral(i: np.ndarray, j: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Source pixel of any integer position of the octahedral unfolding (side ``m + 1``)."""
    i, j = np.mod(i, 2 * m), np.mod(j, 2 * m)
    low = i > m                                   # across the bottom side: turn about its midpoint
    i, j = np.where(low, 2 * m - i, i), np.where(low, np.mod(m - j, 2 * m), j)
    right = j > m                                 # across the right side
    return np.where(right, m - i, i), np.where(right, 2 * m - j, j)


def _reflect_index(k: np.ndarray, n: int) -> np.ndarray:
    if n == 1:
        return np.zeros_like(k)
    k = np.mod(k, 2 * (n - 1))
    return np.where(k >= n, 2 * (n - 1) - k, k)


def _take(a: np.ndarray, rows: np.ndarray, cols: np.ndarray, mode: str) -> np.ndarray:
    """``a`` at integer positions ``rows`` x ``cols`` (1-D each) of its periodic extension by ``mode``."""
    h, w = a.shape[:2]
    if mode == "octahedral":
        i, j = _fold_octahedral(rows[:, None], cols[None, :], _check_octahedral(a.shape))
        return a[i, j]
    if mode == "wrap":
        return a[np.ix_(np.mod(rows, h), np.mod(cols, w))]
    return a[np.ix_(_reflect_index(rows, h), _reflect_index(cols, w))]


def pad(image: ArrayLike, width: int, mode: str = "reflect") -> np.ndarray:
    """Pad the first two axes of an (H, W) or (H, W, C) array by ``width`` pixels with a boundary rule.

    Parameters
    ----------
    image : array_like, shape (H, W) or (H, W, C)
    width : int
        Pixels added on each side (any size; the extension repeats as far as needed).
    mode : {'reflect', 'linear', 'wrap', 'octahedral'}
        See the module's description.

    Returns
    -------
    numpy.ndarray, shape (H + 2 width, W + 2 width[, C]); the input is not modified.

    Raises
    ------
    ValueError
        When ``width`` is not a non-negative integer or ``mode`` is unknown.

    Examples
    --------
    >>> pad(np.array([[0.0, 1.0, 3.0]]), 1)[1].tolist()
    [1.0, 0.0, 1.0, 3.0, 1.0]
    >>> pad(np.array([[0.0, 1.0, 3.0]]), 1, "linear")[1].tolist()
    [-1.0, 0.0, 1.0, 3.0, 5.0]
    >>> img = np.arange(9.0).reshape(3, 3)
    >>> pad(img, 1, "octahedral")[1:-1, -1].tolist()   # right of column 2: column 1, upside down
    [7.0, 4.0, 1.0]
    """
    _check_mode(mode)
    a = as_image(image)
    if isinstance(width, bool) or not isinstance(width, (int, np.integer)) or width < 0:
        raise ValueError(f"width: expected a non-negative integer, got {width!r}")
    h, w = a.shape[:2]
    check_memory(4.0 * (h + 2 * width) * (w + 2 * width) * a[:1, :1].nbytes, f"padding a {w} x {h} image by {width}")
    if mode == "linear":
        return _linear_pad(a, width)
    if mode == "octahedral":
        return _octahedral_pad(a, width)
    spec = [(width, width), (width, width)] + [(0, 0)] * (a.ndim - 2)
    return np.pad(a, spec, mode="reflect" if mode == "reflect" else "wrap")


def _octahedral_pad(a: np.ndarray, width: int) -> np.ndarray:
    """The image in the middle, and only the four border strips gathered through the fold."""
    m = _check_octahedral(a.shape)
    n = m + 1
    out = np.empty((n + 2 * width, n + 2 * width) + a.shape[2:], a.dtype)
    out[width:width + n, width:width + n] = a
    if width == 0:
        return out
    full = np.arange(-width, n + width)
    mid = np.arange(n)
    for rows, cols, where in ((np.arange(-width, 0), full, (slice(0, width), slice(None))),
                              (np.arange(n, n + width), full, (slice(n + width, None), slice(None))),
                              (mid, np.arange(-width, 0), (slice(width, width + n), slice(0, width))),
                              (mid, np.arange(n, n + width), (slice(width, width + n), slice(n + width, None)))):
        out[where] = _take(a, rows, cols, "octahedral")
    return out


def _linear_pad(a: np.ndarray, width: int) -> np.ndarray:
    """Odd extension, one axis after the other (so corners keep bilinear functions too), in steps of at
    most the current size less one, so any width extends linear functions exactly.
    """
    out = a
    for axis in (0, 1):
        left = width
        while left > 0:
            n = out.shape[axis]
            step = min(left, max(n - 1, 1))
            k = np.arange(-step, n + step)
            mirrored = np.take(out, _reflect_index(k, n), axis=axis)
            edge = np.take(out, np.clip(k, 0, n - 1), axis=axis)
            outside = ((k < 0) | (k >= n)).reshape((-1, 1) if axis == 0 else (1, -1))
            if out.ndim == 3:
                outside = outside[..., None]
            out = np.where(outside, 2 * edge - mirrored, mirrored)
            left -= step
    return out


def periodic_extension(image: ArrayLike, mode: str = "reflect") -> np.ndarray:
    """The array whose periodic tiling is the image extended by ``mode``: what the Fourier operations
    transform. ``reflect``: 2(H-1) x 2(W-1) (symmetric extension); ``wrap``: the image itself;
    ``octahedral``: the 2M x 2M unfolding. The image is its top-left H x W block.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    mode : str
        The periodic extension: ``reflect``, ``wrap`` or ``octahedral`` (:mod:`filters.padding`).

    Returns
    -------
    numpy.ndarray
        The extension, image first in its top-left corner.

    Examples
    --------
    >>> periodic_extension(np.array([[0.0, 1.0, 3.0]]), "reflect").tolist()
    [[0.0, 1.0, 3.0, 1.0]]
    >>> periodic_extension(np.arange(9.0).reshape(3, 3), "octahedral").shape
    (4, 4)
    """
    _check_mode(mode, PERIODIC_MODES)
    a = as_image(image)
    h, w = a.shape[:2]
    if mode == "wrap":
        return a.copy()
    if mode == "octahedral":   # blocks: the image, its two half-turns about side midpoints, and a shift
        m = _check_octahedral(a.shape)
        ext = np.empty((2 * m, 2 * m) + a.shape[2:], a.dtype)
        ext[:m + 1, :m + 1] = a
        ext[m + 1:, :m + 1] = a[m - 1:0:-1, ::-1]
        ext[:m + 1, m + 1:] = a[::-1, m - 1:0:-1]
        ext[m + 1:, m + 1:] = a[1:m, 1:m]
        return ext
    ph, pw = max(2 * (h - 1), 1), max(2 * (w - 1), 1)
    return _take(a, np.arange(ph), np.arange(pw), mode)
