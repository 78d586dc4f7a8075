"""Blending and compositing geometry images: the morph's blend, masked composite, cut-and-paste, and
resampling to a common size.
"""
from __future__ import annotations

import numbers

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse

from ._checks import as_image, as_weights, check_memory, positive
from .masks import apply_masked, feather as feather_mask
from .padding import pad

__all__ = ["blend", "composite", "paste", "resize"]

_RESIZE_PAD = 4   # the cubic (Keys) kernel reads 2 pixels each side


def _same_shape(a: np.ndarray, b: np.ndarray, names=("a", "b")) -> None:
    if a.shape != b.shape:
        raise ValueError(f"{names[1]}: expected the shape of {names[0]}, {a.shape}, got {b.shape} "
                         "(resample one with filters.resize first)")


def blend(a: ArrayLike, b: ArrayLike, t: float | ArrayLike = 0.5) -> np.ndarray:
    """``(1 - t) a + t b``, with ``t`` a number or per-pixel weights (H, W) in [0, 1]; exactly ``a`` at
    ``t = 0`` or where ``a == b``, exactly ``b`` at ``t = 1``.

    Parameters
    ----------
    a, b : array_like
        Two images of one shape, (H, W) or (H, W, C).
    t : float or array_like
        The weight of ``b``: a number in [0, 1] or per-pixel weights (H, W).

    Returns
    -------
    numpy.ndarray
        The blended image, of the inputs' shape.

    Raises
    ------
    ValueError
        When the images' shapes differ or ``t`` is not finite.

    Examples
    --------
    >>> blend(np.zeros((1, 2)), np.ones((1, 2)), 0.25).tolist()
    [[0.25, 0.25]]
    """
    a, b = as_image(a, "a"), as_image(b, "b")
    _same_shape(a, b)
    if isinstance(t, numbers.Real) and not isinstance(t, bool):
        if not np.isfinite(t):
            raise ValueError(f"t: expected a finite number, got {t!r}")
        w = float(t)
    else:
        w = as_weights(t, a.shape[:2], "t")
        w = w[..., None] if a.ndim == 3 else w
    dtype = np.result_type(a.dtype, b.dtype)
    out = a + w * (b.astype(np.float64) - a)          # a where a == b, whatever t: a morph of a shape with itself
    out = np.where(np.asarray(w) == 1.0, b, out)      # and b itself at t = 1
    return out.astype(dtype, copy=False)


def composite(base: ArrayLike, overlay: ArrayLike, mask: ArrayLike | None, feather: float = 0.0,
              mode: str = "reflect") -> np.ndarray:
    """``overlay`` inside the mask, ``base`` outside, blended over ``feather`` pixels; far from the mask
    the result is ``base`` bit for bit.

    Parameters
    ----------
    base, overlay : array_like
        Two images of one shape, (H, W) or (H, W, C).
    mask : array_like or None
        Where ``overlay`` shows: booleans or weights in [0, 1] (H, W); None means everywhere.
    feather : float
        Width in pixels of the blend at the mask's edge (0: a hard edge).
    mode : str
        The boundary rule the feathering's blur meets the edges with (:mod:`filters.padding`).

    Returns
    -------
    numpy.ndarray
        The composite, of the inputs' shape.

    Examples
    --------
    >>> m = np.zeros((1, 4), bool); m[0, :2] = True
    >>> composite(np.zeros((1, 4)), np.ones((1, 4)), m).tolist()
    [[1.0, 1.0, 0.0, 0.0]]
    """
    b, o = as_image(base, "base"), as_image(overlay, "overlay")
    _same_shape(b, o, ("base", "overlay"))
    return apply_masked(b, o.astype(b.dtype), feather_mask(as_weights(mask, b.shape[:2]), feather, mode))


def paste(target: ArrayLike, source: ArrayLike, mask: ArrayLike | None, feather: float = 4.0, mode: str = "reflect", *,
          align: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Cut the masked region of ``source`` and paste it onto ``target`` (same parametrization).

    With ``align``, the pasted piece is first moved by the mean of ``target - source`` over the
    feathered rim (weights strictly between 0 and 1, else the mask's own pixels), so it sits where the
    target's surface is and the rim shows no step. Returns ``(image, offset)``.

    Parameters
    ----------
    target, source : array_like
        Two geometry images (H, W, C) of one parametrization.
    mask : array_like or None
        The region of ``source`` to paste (booleans or weights in [0, 1], (H, W)).
    feather : float
        Width in pixels of the blend at the region's rim.
    mode : str
        The boundary rule of the feathering (:mod:`filters.padding`).
    align : bool
        Move the piece by the mean offset over the rim first.

    Returns
    -------
    image : numpy.ndarray
        ``target`` with the piece pasted in.
    offset : numpy.ndarray
        (C,) the offset the piece was moved by (zeros without ``align``).

    Examples
    --------
    >>> t, s = np.zeros((1, 9, 3)), np.full((1, 9, 3), 5.0)
    >>> m = np.zeros((1, 9), bool); m[0, 3:6] = True
    >>> out, off = paste(t, s, m, 2)
    >>> off.tolist(), float(abs(out).max())
    ([-5.0, -5.0, -5.0], 0.0)
    """
    t, s = as_image(target, "target"), as_image(source, "source")
    _same_shape(t, s, ("target", "source"))
    positive(feather, "feather", allow_zero=True)
    w = feather_mask(as_weights(mask, t.shape[:2]), feather, mode)
    offset = np.zeros(t.shape[2:])
    if align:
        rim = (w > 0) & (w < 1)
        if not rim.any():
            rim = w > 0
        if rim.any():
            offset = (t[rim].astype(np.float64) - s[rim]).mean(axis=0)
    return apply_masked(t, (s + offset).astype(t.dtype), w), offset


def _cubic_matrix(x: np.ndarray, n: int) -> sparse.csr_matrix:
    """Sparse (len(x), n) matrix of Keys' cubic convolution (a = -1/2: exact for quadratics) at ``x``."""
    base = np.floor(x).astype(np.int64)
    t = x - base
    w = np.stack([((-0.5 * t + 1.0) * t - 0.5) * t,
                  (1.5 * t - 2.5) * t * t + 1.0,
                  ((-1.5 * t + 2.0) * t + 0.5) * t,
                  (0.5 * t - 0.5) * t * t], axis=1)
    cols = np.clip(base[:, None] + np.arange(-1, 3), 0, n - 1)
    rows = np.repeat(np.arange(len(x)), 4)
    return sparse.csr_matrix((w.ravel(), (rows, cols.ravel())), shape=(len(x), n))


def resize(image: ArrayLike, shape: tuple[int, int], mode: str = "linear") -> np.ndarray:
    """Resample to ``shape`` (H', W') on the same domain, corners to corners (vertex sampling), by
    separable cubic convolution (Keys, exact for quadratics) over the image extended with ``mode``: ``linear`` keeps a
    planar image's linear
    functions (its X, Y) exact up to the border, ``octahedral`` keeps an octahedral one seamless.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C).
    shape : tuple of int
        The new (H', W'), each at least 2.
    mode : str
        The boundary rule beyond the edges (:mod:`filters.padding`).

    Returns
    -------
    numpy.ndarray
        The resampled image, (H', W') or (H', W', C).

    Raises
    ------
    TooLarge
        When the result would exceed the memory limit.

    Examples
    --------
    >>> x = np.linspace(0, 1, 5)[None, :].repeat(3, axis=0)
    >>> bool(np.allclose(resize(x, (3, 9)), np.linspace(0, 1, 9)[None, :]))
    True
    """
    a = as_image(image)
    if not (isinstance(shape, (tuple, list)) and len(shape) == 2
            and all(isinstance(n, numbers.Integral) and not isinstance(n, bool) and n >= 2 for n in shape)):
        raise ValueError(f"shape: expected (H, W) with integers >= 2, got {shape!r}")
    h, w = a.shape[:2]
    if mode == "octahedral" and (shape[0] != shape[1] or shape[0] % 2 == 0):
        raise ValueError(f"shape: an octahedral image needs an odd square size, got {tuple(shape)}")
    check_memory(
        3.0 * shape[0] * shape[1] * a[:1, :1].size * 8 + 3.0 * shape[0] * (w + 2 * _RESIZE_PAD) * a[:1, :1].size * 8,
        f"resizing to {shape[1]} x {shape[0]}",
    )
    r = _RESIZE_PAD
    padded = pad(a, r, mode).astype(np.float64)
    ry = _cubic_matrix(np.linspace(0, h - 1, shape[0]) + r, padded.shape[0])
    rx = _cubic_matrix(np.linspace(0, w - 1, shape[1]) + r, padded.shape[1])
    rest = padded.shape[2:]
    out = ry @ padded.reshape(padded.shape[0], -1)                          # rows
    out = out.reshape((shape[0], padded.shape[1]) + rest).swapaxes(0, 1)
    out = (rx @ out.reshape(padded.shape[1], -1)).reshape((shape[1], shape[0]) + rest).swapaxes(0, 1)
    return out.astype(a.dtype, copy=False)
