"""Gaussian and mean curvature of the weighted-mean surface (paper Fig. 2f-h) and of geometry images.

From the surface: the exact first derivatives ``P_1, P_2`` and the derivatives of the exact unit normal
along the same directions, ``N_a``, give the shape operator ``S = -(J^T J)^-1 J^T [N_1 N_2]`` with
``J = [P_1 P_2]``; ``K = det S`` and ``H = trace(S) / 2``. The normal derivatives are central differences
of exact normals a small step away (``1e-4`` of a pixel spacing scaled to the domain), so the result
carries no grid error. On the sphere the directions are a tangent frame of the sphere, so the
octahedron's creases play no part. ``H`` is positive where the surface bends away from its normal: a
sphere with outward normals has ``H = -1/r``.
"""
from __future__ import annotations

import numpy as np
from typing import Any

from ..parametrization import grid_directions

__all__ = ["surface_curvature", "planar_curvature", "sphere_curvature", "shape_operator_curvatures"]

STEP = 1e-4


def shape_operator_curvatures(J1: np.ndarray, J2: np.ndarray, N1: np.ndarray,
                              N2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(K, H)`` from tangents ``J1, J2`` (k, 3) and the normal's derivatives ``N1, N2`` along them.

    Parameters
    ----------
    J1, J2 : numpy.ndarray
        (k, 3) tangent vectors.
    N1, N2 : numpy.ndarray
        (k, 3) the unit normal's derivatives along them.

    Returns
    -------
    K, H : numpy.ndarray
        (k,) Gaussian and mean curvature.

    Examples
    --------
    >>> e = np.eye(3)[None]
    >>> K, H = shape_operator_curvatures(e[:, 0], e[:, 1], e[:, 0] / 2, e[:, 1] / 2)   # sphere r = 2
    >>> float(K[0]), float(H[0])
    (0.25, -0.5)
    """
    J = np.stack([J1, J2], axis=-1)                      # (k, 3, 2)
    Nd = np.stack([N1, N2], axis=-1)
    g = np.einsum("kca,kcb->kab", J, J)
    rhs = np.einsum("kca,kcb->kab", J, Nd)
    det = g[:, 0, 0] * g[:, 1, 1] - g[:, 0, 1] ** 2
    ok = det > 0
    inv = np.stack([np.stack([g[:, 1, 1], -g[:, 0, 1]], -1), np.stack([-g[:, 1, 0], g[:, 0, 0]], -1)], -2)
    S = -np.einsum("kab,kbc->kac", inv, rhs) / np.where(ok, det, 1.0)[:, None, None]
    K = np.where(ok, S[:, 0, 0] * S[:, 1, 1] - S[:, 0, 1] * S[:, 1, 0], 0.0)
    H = np.where(ok, 0.5 * (S[:, 0, 0] + S[:, 1, 1]), 0.0)
    return K, H


def planar_curvature(surface, resolution):
    """``(K, H)`` of a surface over a parameter rectangle on its sampling grid."""
    u, v = surface.grid(resolution)
    uu, vv = np.meshgrid(u, v)
    uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
    hu, hv = STEP * (u[1] - u[0]), STEP * (v[1] - v[0])
    pu, pv = surface.derivatives(uv)
    ext = np.asarray(surface.extent, np.float64)

    def dn(axis, h):
        lo, hi = uv.copy(), uv.copy()
        lo[:, axis] = np.clip(lo[:, axis] - h, 0, ext[axis])
        hi[:, axis] = np.clip(hi[:, axis] + h, 0, ext[axis])
        return (surface.normals(hi) - surface.normals(lo)) / (hi[:, axis] - lo[:, axis])[:, None]

    K, H = shape_operator_curvatures(pu, pv, dn(0, hu), dn(1, hv))
    return K.reshape(len(v), len(u)), H.reshape(len(v), len(u))


def sphere_curvature(surface, resolution):
    """``(K, H)`` of a surface over the sphere on its octahedral sampling grid."""
    n = resolution if resolution is not None else surface.auto_resolution()
    q = grid_directions(n).reshape(-1, 3)
    _, P1, P2, t1, t2, _ = surface.evaluate_directions(q)
    eps = STEP * 2.0 * np.pi / (n - 1)

    def normal_at(d):
        _, a, b, _, _, _ = surface.evaluate_directions(d)
        n_ = np.cross(a, b) * surface.orientation
        return n_ / np.linalg.norm(n_, axis=1, keepdims=True)

    # steps along t on the sphere: q + eps t, renormalized, moves by eps (to second order) along t
    n1 = (normal_at(q + eps * t1) - normal_at(q - eps * t1)) / (2 * eps)
    n2 = (normal_at(q + eps * t2) - normal_at(q - eps * t2)) / (2 * eps)
    K, H = shape_operator_curvatures(P1, P2, n1, n2)
    return K.reshape(n, n), H.reshape(n, n)


def surface_curvature(surface: Any, resolution: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Gaussian and mean curvature ``(K, H)`` of a fitted surface on the grid ``surface.sample(resolution)``
    uses, each (H, W) float64.

    Parameters
    ----------
    surface : Surface
        A fitted surface.
    resolution : int or None
        The grid's size, as :meth:`Surface.sample` takes it.

    Returns
    -------
    K, H : numpy.ndarray
        (H, W) each.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> K, H = surface_curvature(geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2], (1, 1))), 5)
    >>> float(abs(K).max()), float(abs(H).max())     # a plane
    (0.0, 0.0)
    """
    return surface.curvature(resolution)
