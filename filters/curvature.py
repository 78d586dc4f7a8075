"""Gaussian and mean curvature of a geometry image from its grid (finite differences)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ._checks import as_image
from .padding import pad

__all__ = ["grid_curvature"]


def grid_curvature(image: ArrayLike, mode: str = "linear", orientation: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Gaussian curvature ``K`` and mean curvature ``H`` (H, W) of a geometry image (H, W, 3), from
    central differences over the image padded by ``mode``.

    Curvatures do not depend on the parametrization's scale, so pixel units serve. ``linear`` (the
    default, for planar images) keeps one-sided first differences at the border and reads no bending
    across it; on an octahedral image use ``octahedral`` (the octahedron's creases, where the map
    bends, read slightly wrong: the surface's own curvature has no such lines). ``H`` is positive
    where the surface bends away from its normal (normal ``P_u x P_v`` times ``orientation``), so a
    sphere with outward normals has ``H = -1/r``.

    Parameters
    ----------
    image : array_like
        A geometry image (H, W, 3).
    mode : str
        The boundary rule of the differences (:mod:`filters.padding`).
    orientation : int
        +1 or -1: the sign of the normal ``P_u x P_v``.

    Returns
    -------
    K, H : numpy.ndarray
        Gaussian and mean curvature, (H, W) each.

    Raises
    ------
    ValueError
        When the image is not (H, W, 3).

    Examples
    --------
    >>> u, v = np.meshgrid(np.linspace(-0.2, 0.2, 21), np.linspace(-0.2, 0.2, 21))
    >>> r = 2.0
    >>> img = np.stack([u, v, np.sqrt(r * r - u * u - v * v)], axis=-1)   # a cap, normal up
    >>> K, H = grid_curvature(img)
    >>> round(float(K[10, 10]), 3), round(float(H[10, 10]), 3)
    (0.25, -0.5)
    """
    a = as_image(image).astype(np.float64)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"image: expected a geometry image (H, W, 3), got {a.shape}")
    p = pad(a, 1, mode)
    c = p[1:-1, 1:-1]
    pu = 0.5 * (p[1:-1, 2:] - p[1:-1, :-2])
    pv = 0.5 * (p[2:, 1:-1] - p[:-2, 1:-1])
    puu = p[1:-1, 2:] - 2 * c + p[1:-1, :-2]
    pvv = p[2:, 1:-1] - 2 * c + p[:-2, 1:-1]
    puv = 0.25 * (p[2:, 2:] - p[2:, :-2] - p[:-2, 2:] + p[:-2, :-2])
    n = np.cross(pu, pv) * orientation
    ln = np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.divide(n, ln, out=np.zeros_like(n), where=ln > 0)
    E, F, G = (pu * pu).sum(-1), (pu * pv).sum(-1), (pv * pv).sum(-1)
    L, M, N = (puu * n).sum(-1), (puv * n).sum(-1), (pvv * n).sum(-1)
    det = E * G - F * F
    ok = det > 1e-30 * max(float(np.abs(det).max()), 1e-300)
    safe = np.where(ok, det, 1.0)
    K = np.where(ok, (L * N - M * M) / safe, 0.0)
    H = np.where(ok, (E * N - 2 * F * M + G * L) / (2 * safe), 0.0)
    return K, H
