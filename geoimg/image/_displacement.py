"""Displaced geometry images: a coarse base image, smoothly upsampled, and one scalar per pixel that moves
the upsampled point along the base's normal (the idea of normal meshes, Guskov et al. 2000, on an image grid).

Where X, Y and Z each carry the shape, the offsets carry only what the base misses across the surface: a
sample slid along the surface does not move the shape, so the two tangential thirds of what a plain image
codes are not coded at all. :func:`base_frame` is the decoder's half (and the encoder's, so that both
displace from the same points): the base upsampled by cubic splines through the domain's boundary rule
(:meth:`Domain.pad`, so an octahedral image's glued edges see across the fold), glued pixels averaged, and
unit normals by central differences through the same rule of the upsampled base smoothed a little
(:data:`NORMAL_SMOOTHING`; zero where the grid is degenerate: such a pixel stays on the base).
:func:`displace` puts the offsets on and welds what the domain glues.

Examples
--------
A sphere of radius 1 coded as a coarse ball and offsets of 0.5: a ball of radius about 1.5.

>>> from geoimg.image import OctahedralDomain
>>> d = OctahedralDomain()
>>> points, normals = base_frame(d.directions(9), d, (33, 33))
>>> out = displace(points, normals, np.full((33, 33), 0.5), d)
>>> r = np.linalg.norm(out, axis=-1)
>>> bool(abs(np.median(r) - 1.5) < 0.02)
True
"""
from __future__ import annotations

import numpy as np

import filters
from ._domain import Domain
from ._image import GeometryImage

__all__ = ["base_frame", "displace", "area_weights", "PAD", "NORMAL_SMOOTHING", "WEIGHT_RANGE"]

PAD = 4          # pixels of the boundary rule around the base: a cubic spline's reach, and more
# the normals are those of the upsampled base smoothed by a Gaussian of this many base pixels: a line along a
# smoother normal crosses the surface nearer square on (bunny.obj at Draco q8's 2,907 bytes 66.1 -> 67.0 dB,
# Spot at 3,195 70.1 -> 70.7; 1.5 base pixels no better, 0.5 less)
NORMAL_SMOOTHING = 0.75
# a pixel's share of the surface is clipped to [1 / WEIGHT_RANGE, WEIGHT_RANGE] times the mean before its square
# root weighs the offsets: a degenerate pixel divides by no less than 0.32 (clipped at 2 the camel's head gained
# 0.1 dB less; at 100 the same as 10)
WEIGHT_RANGE = 10.0


def base_frame(base: np.ndarray, domain: Domain, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The base (h, w, 3) upsampled to ``shape`` (H, W) by cubic splines, corner pixels on corner pixels, and
    its unit normals (zero where the grid has none).

    Parameters
    ----------
    base : numpy.ndarray
        (h, w, 3) coordinates, h and w at least 2.
    domain : Domain
        The image's domain (its boundary rule and its glue).
    shape : tuple of int
        (H, W): the upsampled size.

    Returns
    -------
    points, normals : numpy.ndarray
        (H, W, 3) float64 each.

    Examples
    --------
    >>> from geoimg.image import PlanarDomain
    >>> u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    >>> base = np.dstack([u, v, 0 * u])
    >>> p, n = base_frame(base, PlanarDomain(), (9, 9))
    >>> bool(np.allclose(p[::2, ::2], base)), n[4, 4].tolist()       # the base's pixels kept
    (True, [0.0, 0.0, 1.0])
    """
    from scipy import ndimage          # here: reading an image (geoimg mesh) starts without scipy

    b = np.asarray(base, np.float64)
    height, width = int(shape[0]), int(shape[1])
    padded = domain.pad(b, PAD)
    y = np.arange(height) * ((b.shape[0] - 1) / max(height - 1, 1)) + PAD
    x = np.arange(width) * ((b.shape[1] - 1) / max(width - 1, 1)) + PAD
    yy, xx = np.meshgrid(y, x, indexing="ij")
    points = np.stack([ndimage.map_coordinates(padded[..., c], [yy, xx], order=3, mode="nearest")
                       for c in range(3)], axis=-1)
    points = domain.average_glued(points)
    sigma = NORMAL_SMOOTHING * (height - 1) / max(b.shape[0] - 1, 1)      # in the upsampled image's pixels
    smooth = GeometryImage(points, None, domain).apply(filters.gaussian_filter, sigma).pixels   # across the glue
    around = domain.pad(smooth, 1)
    normals = np.cross(around[1:-1, 2:] - around[1:-1, :-2], around[2:, 1:-1] - around[:-2, 1:-1]) * domain.orientation
    normals = domain.average_glued(normals)
    length = np.linalg.norm(normals, axis=-1, keepdims=True)
    tiny = 1e-12 * max(float(np.ptp(points.reshape(-1, 3), axis=0).max()), 1e-300) ** 2
    normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > tiny)
    return points, normals


def displace(points: np.ndarray, normals: np.ndarray, offsets: np.ndarray, domain: Domain) -> np.ndarray:
    """``points + offsets * normals``, glued pixels welded (each group set to its mean).

    Parameters
    ----------
    points, normals : numpy.ndarray
        (H, W, 3), from :func:`base_frame`.
    offsets : numpy.ndarray
        (H, W) distances along the normals.
    domain : Domain
        The image's domain.

    Returns
    -------
    numpy.ndarray
        (H, W, 3) float64.

    Examples
    --------
    >>> from geoimg.image import PlanarDomain
    >>> p = np.zeros((2, 2, 3)); n = np.zeros((2, 2, 3)); n[..., 2] = 1
    >>> displace(p, n, np.full((2, 2), 0.25), PlanarDomain())[0, 0].tolist()
    [0.0, 0.0, 0.25]
    """
    return domain.average_glued(points + np.asarray(offsets, np.float64)[..., None] * normals)


def area_weights(points: np.ndarray, domain: Domain) -> np.ndarray:
    """The square root of each pixel's share of the surface ``points`` (H, W, 3) spans, over the mean share
    (the mean area of the four grid cells round it, through the domain's boundary rule), clipped to
    ``[1 / WEIGHT_RANGE, WEIGHT_RANGE]`` first: (H, W), a pixel of the mean share 1.

    The coder makes the mean squared error of what it codes least; offsets multiplied by these weights before
    coding (and divided after decoding) make it least in the surface's own measure, where a pixel that spans
    twice the area counts twice, as the distance between two surfaces counts it.

    Examples
    --------
    >>> from geoimg.image import PlanarDomain
    >>> u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5) ** 2)     # rows spaced wider further on
    >>> w = area_weights(np.dstack([u, v, 0 * u]), PlanarDomain())
    >>> bool(w[1, 2] < 1 < w[3, 2]), bool(np.allclose(w, w[:, :1]))
    (True, True)
    """
    around = domain.pad(np.asarray(points, np.float64), 1)
    cells = 0.5 * np.linalg.norm(np.cross(around[1:, 1:] - around[:-1, :-1], around[1:, :-1] - around[:-1, 1:]),
                                 axis=-1)
    share = 0.25 * (cells[:-1, :-1] + cells[:-1, 1:] + cells[1:, :-1] + cells[1:, 1:])
    mean = float(share.mean())
    if not mean > 0.0:                        # no area anywhere: every pixel alike
        return np.ones(share.shape)
    return np.sqrt(np.clip(share / mean, 1.0 / WEIGHT_RANGE, WEIGHT_RANGE))
