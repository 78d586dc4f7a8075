"""Orientation of a map onto the sphere: which triangles run counter-clockwise seen from outside."""
from __future__ import annotations

import numpy as np

__all__ = ["chord_orientation", "facing_out"]


def chord_orientation(s: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """``det(s_a, s_b, s_c)`` of every triangle on the sphere: positive when it runs counter-clockwise
    seen from outside.
    """
    a, b, c = s[tris[:, 0]], s[tris[:, 1]], s[tris[:, 2]]
    return np.einsum("ij,ij->i", a, np.cross(b, c))


def facing_out(s: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """``s``, mirrored if fewer than half its triangles run counter-clockwise seen from outside."""
    if np.sum(chord_orientation(s, tris) > 0) < len(tris) / 2:
        return s * [-1.0, 1.0, 1.0]
    return s
