"""Boundary padding of images: the one mechanism every filter uses at the image's edges."""
from __future__ import annotations

import numpy as np

__all__ = ["pad", "PAD_MODES"]

PAD_MODES = ("reflect", "wrap")
_NUMPY_MODE = {"reflect": "symmetric", "wrap": "wrap"}


def pad(image: np.ndarray, width: int, mode: str = "reflect") -> np.ndarray:
    """Pad the first two axes of an (H, W) or (H, W, C) array by ``width`` pixels.

    ``reflect`` mirrors about the edge (edge pixels repeated: the extension of a planar domain),
    ``wrap`` tiles periodically.

    Examples
    --------
    >>> pad(np.arange(3.0)[None, :], 1).tolist()
    [[0.0, 0.0, 1.0, 2.0, 2.0], [0.0, 0.0, 1.0, 2.0, 2.0], [0.0, 0.0, 1.0, 2.0, 2.0]]
    """
    if mode not in PAD_MODES:
        raise ValueError(f"mode: expected one of {PAD_MODES}, got {mode!r}")
    a = np.asarray(image)
    if a.ndim not in (2, 3):
        raise ValueError(f"image: expected shape (H, W) or (H, W, C), got {a.shape}")
    if isinstance(width, bool) or not isinstance(width, (int, np.integer)) or width < 0:
        raise ValueError(f"width: expected a non-negative integer, got {width!r}")
    spec = [(width, width), (width, width)] + [(0, 0)] * (a.ndim - 2)
    return np.pad(a, spec, mode=_NUMPY_MODE[mode])
