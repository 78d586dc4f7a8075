"""Regions: where to smooth. Image masks from a file, a disk in parameter space or a ball in 3-D, and
per-face smoothness fields for the surface itself (paper 4.5).

A region is a weight in [0, 1]: 1 inside, a smooth falloff over ``feather`` (same units as ``radius``)
outside, 0 beyond. Masks of octahedral images are made symmetric on the glued boundary.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from filters._checks import positive

from .image import GeometryImage
from .mesh import Mesh

__all__ = ["ball_weights", "image_region", "uv_region", "load_mask", "smoothness_field", "symmetric_mask",
           "SmoothnessMap", "uv_smoothness"]


def _positive(value, name, allow_zero=False) -> float:
    return float(positive(value, name, allow_zero=allow_zero))


def ball_weights(points, centre, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights of points (..., D) for the ball ``|p - centre| <= radius``, falling off smoothly
    (smoothstep) over ``feather`` beyond it.

    Examples
    --------
    >>> ball_weights(np.array([[0.0], [1.5], [2.0], [3.0]]), [0.0], 1.0, 2.0).tolist()
    [1.0, 0.84375, 0.5, 0.0]
    """
    p = np.asarray(points, dtype=np.float64)
    c = np.asarray(centre, dtype=np.float64)
    if c.shape != p.shape[-1:] or not np.isfinite(c).all():
        raise ValueError(f"centre: expected {p.shape[-1]} finite coordinates, got {centre!r}")
    radius, feather = _positive(radius, "radius", allow_zero=True), _positive(feather, "feather", allow_zero=True)
    d = np.linalg.norm(p - c, axis=-1) - radius
    if feather == 0:
        return (d <= 0).astype(np.float64)
    t = np.clip(1.0 - d / feather, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def symmetric_mask(weights: np.ndarray) -> np.ndarray:
    """Largest weight of each group of glued pixels of an octahedral image, given to all of them."""
    from .octahedral import weld_index

    w = np.asarray(weights, dtype=np.float64)
    weld = weld_index(w.shape[0]).ravel()
    best = np.zeros(w.size)
    np.maximum.at(best, weld, w.ravel())
    return best[weld].reshape(w.shape)


def image_region(image: GeometryImage, centre, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights (H, W) of the pixels whose surface point lies in the ball around ``centre`` (3-D, the
    mesh's units): smooth, for example, the region around a point of the mesh.

    Examples
    --------
    >>> x, y = np.meshgrid(np.arange(5.0), np.arange(3.0))
    >>> img = GeometryImage(np.stack([x, y, 0 * x], axis=-1))
    >>> image_region(img, [0, 0, 0], 1.0).astype(int).tolist()
    [[1, 1, 0, 0, 0], [1, 0, 0, 0, 0], [0, 0, 0, 0, 0]]
    """
    w = ball_weights(image.pixels, centre, radius, feather) * image.valid
    return symmetric_mask(w) if image.domain == "octahedral" else w


def uv_region(shape, centre, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights (H, W) of a disk in the image's [0, 1]^2 coordinates (u along columns, v along rows).

    Examples
    --------
    >>> uv_region((3, 3), (0.5, 0.5), 0.1).astype(int).tolist()
    [[0, 0, 0], [0, 1, 0], [0, 0, 0]]
    """
    h, w = shape
    uu, vv = np.meshgrid(np.linspace(0, 1, w), np.linspace(0, 1, h))
    return ball_weights(np.stack([uu, vv], axis=-1), centre, radius, feather)


def load_mask(path, shape) -> np.ndarray:
    """Weights (H, W) in [0, 1] from an image file (PNG, EXR, ...: the first channel, scaled by its
    type's range; 8-bit 255 is 1). The file must have the geometry image's size."""
    from .image_io import read_raster

    path = Path(path)
    data, _, _ = read_raster(path, what="mask image")
    if data.shape[:2] != tuple(shape):
        raise ValueError(f"mask: {path} is {data.shape[1]} x {data.shape[0]} pixels; the geometry image is "
                         f"{shape[1]} x {shape[0]}")
    w = data[..., 0].astype(np.float64)
    if not np.isfinite(w).all() or w.min() < 0 or w.max() > 1:
        raise ValueError(f"mask: {path}: values must lie in [0, 1]")
    return w


def smoothness_field(mesh: Mesh, centre, radius: float, inside: float, outside: float = 1.0,
                     feather: float = 0.0) -> np.ndarray:
    """Per-face ``s`` for :func:`geoimg.fit_surface`: ``inside`` for faces whose centroid lies in the
    ball around ``centre`` (3-D), ``outside`` elsewhere, blended over ``feather``.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 0, 0]], [[0, 1, 2], [1, 4, 2]])
    >>> smoothness_field(m, [0, 0, 0], 1.0, inside=3.0).tolist()
    [3.0, 1.0]
    """
    inside, outside = _positive(inside, "inside"), _positive(outside, "outside")
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

    Examples
    --------
    >>> m = uv_smoothness((0.5, 0.5), 0.1, inside=1.0, outside=4.0, feather=0.2)
    >>> s, su, sv = m(np.array([[0.5, 0.5], [0.5, 0.7], [0.5, 0.9]]))
    >>> s.round(12).tolist(), (m.min, m.max)
    ([1.0, 2.5, 4.0], (1.0, 4.0))
    """

    def __init__(self, centre, radius: float, inside: float, outside: float, feather: float):
        self.centre = np.asarray(centre, np.float64)
        if self.centre.shape != (2,) or not np.isfinite(self.centre).all():
            raise ValueError(f"centre: expected (u, v), got {centre!r}")
        self.radius = _positive(radius, "radius", allow_zero=True)
        self.feather = _positive(feather, "feather")
        self.inside, self.outside = _positive(inside, "inside"), _positive(outside, "outside")
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


def uv_smoothness(centre, radius: float, inside: float, outside: float = 1.0, feather: float = 0.05):
    """A :class:`SmoothnessMap` round ``centre`` in the parameter domain (the image's u, v)."""
    return SmoothnessMap(centre, radius, inside, outside, feather)
