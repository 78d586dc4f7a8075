"""Smoothness that varies over the surface (paper 4.5): per-face values of s and a map s(u, v).

Both are given to :func:`geoimg.fit_surface` as ``s``. Per-face values come from a ball in 3-D around
a point of the mesh (:func:`smoothness_field`); a :class:`SmoothnessMap` varies with the point
evaluated, so it keeps a region sharp inside a smoothed surrounding (:func:`uv_smoothness`).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .._ball import ball_weights, checked_positive
from ..mesh import Mesh

__all__ = ["smoothness_field", "SmoothnessMap", "uv_smoothness"]


def smoothness_field(mesh: Mesh, centre: ArrayLike, radius: float, inside: float, outside: float = 1.0,
                     feather: float = 0.0) -> np.ndarray:
    """Per-face ``s`` for :func:`geoimg.fit_surface`: ``inside`` for faces whose centroid lies in the
    ball around ``centre`` (3-D), ``outside`` elsewhere, blended over ``feather``.

    Parameters
    ----------
    mesh : Mesh
        The mesh whose faces get an s each.
    centre : array_like
        (3,) the ball's centre, in the mesh's units.
    radius : float
        The ball's radius.
    inside, outside : float
        s in the ball, and beyond ``radius + feather``.
    feather : float
        The width of the blend between, in the mesh's units.

    Returns
    -------
    numpy.ndarray
        (F,) per-face s.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 0, 0]], [[0, 1, 2], [1, 4, 2]])
    >>> smoothness_field(m, [0, 0, 0], 1.0, inside=3.0).tolist()
    [3.0, 1.0]
    """
    inside, outside = checked_positive(inside, "inside"), checked_positive(outside, "outside")
    f, k = mesh.faces, mesh.face_sizes
    valid = f >= 0
    xyz = mesh.vertices[np.where(valid, f, f[:, :1])]
    centroid = (xyz * valid[..., None]).sum(axis=1) / k[:, None]
    w = ball_weights(centroid, centre, radius, feather)
    return outside + (inside - outside) * w


class SmoothnessMap:
    """A smoothness ``s(u, v)`` that varies with the point evaluated (paper 4.5): ``inside`` within
    ``radius`` of ``centre`` in the parameter domain, ``outside`` beyond ``radius + feather``, a
    smoothstep between. Every face's Gaussian at a point uses that point's s, so a region is kept sharp
    (or smoothed) whatever the faces around it do; the surface's derivatives include the map's own, so
    normals stay exact. Pass it as ``s`` to :func:`geoimg.fit_surface` (planar parametrizations).

    Parameters
    ----------
    centre : array_like
        (u, v) of the region's centre.
    radius : float
        The region's radius, in the parameter domain's units.
    inside, outside : float
        s within the radius, and beyond ``radius + feather``.
    feather : float
        The width of the smoothstep between.

    Raises
    ------
    InputError
        When the centre is not (u, v).
    ValueError
        When a smoothness or the feather is not above 0, or the radius is negative.

    Examples
    --------
    >>> m = uv_smoothness((0.5, 0.5), 0.1, inside=1.0, outside=4.0, feather=0.2)
    >>> s, su, sv = m(np.array([[0.5, 0.5], [0.5, 0.7], [0.5, 0.9]]))
    >>> s.round(12).tolist(), (m.min, m.max)
    ([1.0, 2.5, 4.0], (1.0, 4.0))
    """

    def __init__(self, centre: ArrayLike, radius: float, inside: float, outside: float, feather: float):
        self.centre = np.asarray(centre, np.float64)
        if self.centre.shape != (2,) or not np.isfinite(self.centre).all():
            raise InputError(f"centre: expected (u, v), got {centre!r}")
        self.radius = checked_positive(radius, "radius", allow_zero=True)
        self.feather = checked_positive(feather, "feather")
        self.inside, self.outside = checked_positive(inside, "inside"), checked_positive(outside, "outside")
        self.min, self.max = min(self.inside, self.outside), max(self.inside, self.outside)

    def __call__(self, uv):
        """``(s, ds/du, ds/dv)`` at parameter points (k, 2)."""
        d = np.asarray(uv, np.float64) - self.centre
        r = np.sqrt((d ** 2).sum(axis=1))
        t = np.clip(1.0 - (r - self.radius) / self.feather, 0.0, 1.0)
        w = t * t * (3.0 - 2.0 * t)
        dw_dt = 6.0 * t * (1.0 - t)
        dr = np.divide(d, r[:, None], out=np.zeros_like(d), where=r[:, None] > 0)
        dw = (dw_dt * (-1.0 / self.feather))[:, None] * dr          # zero where t is clipped (dw_dt = 0)
        s = self.outside + (self.inside - self.outside) * w
        grad = (self.inside - self.outside) * dw
        return s, grad[:, 0], grad[:, 1]


def uv_smoothness(centre: ArrayLike, radius: float, inside: float, outside: float = 1.0,
                  feather: float = 0.05) -> SmoothnessMap:
    """A :class:`SmoothnessMap` round ``centre`` in the parameter domain (the image's u, v).

    Parameters
    ----------
    centre : array_like
        (u, v) of the region's centre.
    radius : float
        The region's radius, in the parameter domain's units.
    inside, outside : float
        s within the radius, and beyond ``radius + feather``.
    feather : float
        The width of the smoothstep between.

    Returns
    -------
    SmoothnessMap
        The map, to pass as ``s``.

    Examples
    --------
    >>> sm = uv_smoothness((0.5, 0.5), 0.1, inside=4.0, outside=1.0)
    >>> sm(np.array([[0.5, 0.5], [0.0, 0.0]]))[0].tolist()
    [4.0, 1.0]
    """
    return SmoothnessMap(centre, radius, inside, outside, feather)
