"""Gaussian and mean curvature of a geometry image from its grid (paper Fig. 2f-h), at a stated scale.

At the faithful default a geometry image is nearly its piecewise-linear mesh, whose curvature lives on the
edges: computed pixel by pixel it is noise. A scale (a share of the bounding-box diagonal) smooths the
surface by a Gaussian of that standard deviation first, through the domain's boundary rule, so that the
maps show the shape's ridges and valleys at that size.
"""
from __future__ import annotations

import math
import numbers

import numpy as np

import filters
from filters import grid_curvature

from .._choices import DEFAULT_CURVATURE_SCALE
from ..errors import InputError
from ._image import GeometryImage

__all__ = ["image_curvature", "curvature_sigma", "DEFAULT_CURVATURE_SCALE", "MAX_CURVATURE_SCALE"]

MAX_CURVATURE_SCALE = 0.25


def curvature_sigma(image: GeometryImage, scale: float) -> float:
    """The Gaussian's standard deviation in pixels for a smoothing ``scale`` (a share of the bounding-box
    diagonal): the scale over the mean distance between neighbouring valid pixels.

    Parameters
    ----------
    image : GeometryImage
        The image.
    scale : float
        The share of the diagonal, from 0 (none) to :data:`MAX_CURVATURE_SCALE`.

    Returns
    -------
    float
        Pixels.

    Examples
    --------
    >>> x, y = np.meshgrid(np.linspace(0, 1, 101), np.linspace(0, 1, 101))
    >>> round(curvature_sigma(GeometryImage(np.stack([x, y, 0 * x], axis=-1)), 0.01), 3)   # 1 % of sqrt(2)
    1.414
    """
    if isinstance(scale, bool) or not isinstance(scale, numbers.Real) or not math.isfinite(float(scale)) \
            or not 0 <= float(scale) <= MAX_CURVATURE_SCALE:
        raise InputError(f"scale: expected a share of the diagonal from 0 to {MAX_CURVATURE_SCALE}, got {scale!r}")
    if scale == 0:
        return 0.0
    p = np.asarray(image.pixels, np.float64)
    valid = image.valid
    steps = []
    for axis in (0, 1):
        d = np.linalg.norm(np.diff(p, axis=axis), axis=2)
        both = valid[1:] & valid[:-1] if axis == 0 else valid[:, 1:] & valid[:, :-1]
        steps.append(d[both])
    spacing = float(np.concatenate(steps).mean()) if sum(map(len, steps)) else 0.0
    diagonal = float(np.linalg.norm(np.ptp(p[valid], axis=0))) if valid.any() else 0.0
    return float(scale) * diagonal / spacing if spacing > 0 else 0.0


def image_curvature(image: GeometryImage, scale: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """``(K, H)`` of a geometry image from its grid (:func:`filters.grid_curvature`), continuing the
    surface beyond the edges by its domain's rule (``domain.extension``) and oriented like it; with
    ``scale``, of the surface smoothed by a Gaussian of that share of the diagonal first.

    Parameters
    ----------
    image : GeometryImage
        The image.
    scale : float, default 0
        The smoothing scale, a share of the bounding-box diagonal (:data:`DEFAULT_CURVATURE_SCALE` shows a
        faithful image's features); 0: the grid as it is.

    Returns
    -------
    K, H : numpy.ndarray
        Gaussian and mean curvature per pixel, (H, W) each.

    Examples
    --------
    >>> x, y = np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9))
    >>> K, H = image_curvature(GeometryImage(np.stack([x, y, 0 * x], axis=-1)))
    >>> float(abs(K).max()), float(abs(H).max())     # a plane
    (0.0, 0.0)
    """
    sigma = curvature_sigma(image, scale)
    if sigma > 0:
        image = image.apply(filters.gaussian_filter, sigma)
    return grid_curvature(image.pixels, image.domain.extension, image.domain.orientation)
