"""Gaussian and mean curvature of a geometry image from its grid (paper Fig. 2f-h)."""
from __future__ import annotations

import numpy as np

from filters import grid_curvature

from ._image import GeometryImage

__all__ = ["image_curvature"]


def image_curvature(image: GeometryImage) -> tuple[np.ndarray, np.ndarray]:
    """``(K, H)`` of a geometry image from its grid (:func:`filters.grid_curvature`), continuing the
    surface beyond the edges by its domain's rule (``domain.extension``) and oriented like it.

    Parameters
    ----------
    image : GeometryImage
        The image.

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
    return grid_curvature(image.pixels, image.domain.extension, image.domain.orientation)
