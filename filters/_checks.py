"""Validation shared by the filters: images, masks and positive sizes, with messages that name the argument."""
from __future__ import annotations

import numbers

import numpy as np


def as_image(image, name: str = "image") -> np.ndarray:
    """A finite real (H, W) or (H, W, C) array as float32 (kept) or float64 (anything else); not a copy."""
    a = np.asarray(image)
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool) \
            or np.issubdtype(a.dtype, np.complexfloating):
        raise TypeError(f"{name}: expected a real numeric array, got dtype {a.dtype}")
    if a.ndim not in (2, 3) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"{name}: expected shape (H, W) or (H, W, C), got {a.shape}")
    if a.dtype != np.float32:
        a = a.astype(np.float64, copy=False)
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: contains NaN or infinite values")
    return a


def as_weights(mask, shape, name: str = "mask") -> np.ndarray:
    """A mask as float64 weights in [0, 1] of shape ``shape`` (H, W): booleans, or numbers in [0, 1]."""
    m = np.asarray(mask)
    if m.dtype == object or not (np.issubdtype(m.dtype, np.number) or m.dtype == bool) \
            or np.issubdtype(m.dtype, np.complexfloating):
        raise TypeError(f"{name}: expected a boolean or real array, got dtype {m.dtype}")
    if m.shape != tuple(shape):
        raise ValueError(f"{name}: expected shape {tuple(shape)} (the image's H, W), got {m.shape}")
    m = m.astype(np.float64)
    if not np.isfinite(m).all() or m.min() < 0 or m.max() > 1:
        raise ValueError(f"{name}: values must lie in [0, 1]")
    return m


def positive(value, name: str, *, integer: bool = False, odd: bool = False, allow_zero: bool = False):
    """Validate a positive (or non-negative) number; odd integers where a kernel needs a centre."""
    ok_type = isinstance(value, numbers.Integral) if integer else isinstance(value, numbers.Real)
    if isinstance(value, bool) or not ok_type or not np.isfinite(value) or value < 0 or (value == 0 and not allow_zero):
        kind = "an integer" if integer else "a number"
        raise ValueError(f"{name}: expected {kind} {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    if odd and int(value) % 2 == 0:
        raise ValueError(f"{name}: expected an odd size (the kernel needs a centre pixel), got {value!r}")
    return value
