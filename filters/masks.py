"""Masks: feathered weights and the masked application of any filter (the paper's partial smoothing)."""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage

from ._checks import as_image, as_weights, positive
from .padding import pad

__all__ = ["feather", "apply_masked"]


def feather(mask: ArrayLike | None, width: float = 0.0, mode: str = "reflect") -> np.ndarray:
    """Weights in [0, 1]: the mask, plus a smooth falloff over ``width`` pixels outside it.

    The falloff is ``smoothstep(1 - d / width)`` of the distance ``d`` (pixels, Euclidean, measured
    through the boundary rule ``mode``) to the nearest pixel of weight >= 0.5; it is exactly 0 from
    ``width`` pixels on, so pixels far from the mask stay untouched.

    Parameters
    ----------
    mask : array_like or None
        Booleans or weights in [0, 1], (H, W); None gives ones (everywhere).
    width : float
        The falloff's width, pixels (0: the mask itself).
    mode : str
        The boundary rule beyond the edges: ``reflect``, ``linear``, ``wrap`` or ``octahedral``
        (:mod:`filters.padding`).

    Returns
    -------
    numpy.ndarray
        float64 weights (H, W).

    Raises
    ------
    ValueError
        When the mask is not (H, W) or holds values outside [0, 1].

    Examples
    --------
    >>> m = np.zeros((1, 7), bool); m[0, 0] = True
    >>> feather(m, 4)[0].round(3).tolist()
    [1.0, 0.844, 0.5, 0.156, 0.0, 0.0, 0.0]
    """
    positive(width, "feather", allow_zero=True)
    m = np.asarray(mask)
    if m.ndim != 2:
        raise ValueError(f"mask: expected shape (H, W), got {m.shape}")
    w = as_weights(m, m.shape)
    if width == 0:
        return w
    mode = "reflect" if mode == "linear" else mode
    r = int(math.ceil(width)) + 1
    core = pad(w, r, mode) >= 0.5
    if not core.any():
        return w
    # distances matter only within r of the core: transform the core's bounding box grown by r
    rows, cols = np.flatnonzero(core.any(axis=1)), np.flatnonzero(core.any(axis=0))
    r0, r1 = max(rows[0] - r, 0), min(rows[-1] + r + 1, core.shape[0])
    c0, c1 = max(cols[0] - r, 0), min(cols[-1] + r + 1, core.shape[1])
    far = np.full(core.shape, np.inf)
    far[r0:r1, c0:c1] = ndimage.distance_transform_edt(~core[r0:r1, c0:c1])
    d = far[r:-r, r:-r]
    t = np.clip(1.0 - d / width, 0.0, 1.0)
    return np.maximum(w, t * t * (3.0 - 2.0 * t))


def apply_masked(original: ArrayLike, filtered: ArrayLike, weights: ArrayLike) -> np.ndarray:
    """``original + w (filtered - original)``: exactly ``original`` where ``w == 0`` and exactly
    ``filtered`` where ``w == 1``.

    Parameters
    ----------
    original, filtered : array_like
        The image before and after an operation, of one shape.
    weights : array_like
        (H, W) weights in [0, 1], as :func:`feather` gives.

    Returns
    -------
    numpy.ndarray
        The blend, of the inputs' shape.

    Raises
    ------
    ValueError
        When the images' shapes differ.

    Examples
    --------
    >>> apply_masked(np.zeros((1, 3)), np.ones((1, 3)), np.array([[0.0, 0.25, 1.0]])).tolist()
    [[0.0, 0.25, 1.0]]
    """
    a = as_image(original, "original")
    f = as_image(filtered, "filtered")
    if f.shape != a.shape:
        raise ValueError(f"filtered: expected shape {a.shape}, got {f.shape}")
    w = as_weights(weights, a.shape[:2], "weights")
    if a.ndim == 3:
        w = w[..., None]
    out = np.where(w == 0, a, np.where(w == 1, f, a + w * (f - a)))
    return out.astype(a.dtype, copy=False)
