"""Image regions: where to filter a geometry image. Weights in [0, 1] from a mask file, a disk in the
image's coordinates or a ball in 3-D around a point of the surface, made symmetric over glued pixels.

A region is 1 inside, falls off smoothly over ``feather`` (same units as ``radius``) outside and is 0
beyond. For smoothing on the surface itself, see :mod:`geoimg.surface` (per-face s, s(u, v)).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .._raster import read_raster
from .._ball import ball_weights
from ._image import GeometryImage
from .._types import PathLike

__all__ = ["image_region", "uv_region", "load_mask"]


def image_region(image: GeometryImage, centre: ArrayLike, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights (H, W) of the pixels whose surface point lies in the ball around ``centre`` (3-D, the
    mesh's units): smooth, for example, the region around a point of the mesh.

    Parameters
    ----------
    image : GeometryImage
        The image whose pixels are weighed.
    centre : array_like
        (3,) the ball's centre.
    radius : float
        The ball's radius.
    feather : float
        The width of the falloff beyond the radius, in the mesh's units.

    Returns
    -------
    numpy.ndarray
        (H, W) weights in [0, 1]; 0 at masked pixels.

    Examples
    --------
    >>> x, y = np.meshgrid(np.arange(5.0), np.arange(3.0))
    >>> img = GeometryImage(np.stack([x, y, 0 * x], axis=-1))
    >>> image_region(img, [0, 0, 0], 1.0).astype(int).tolist()
    [[1, 1, 0, 0, 0], [1, 0, 0, 0, 0], [0, 0, 0, 0, 0]]
    """
    w = ball_weights(image.pixels, centre, radius, feather) * image.valid
    return image.domain.symmetric_mask(w)


def uv_region(shape: tuple[int, int], centre: ArrayLike, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights (H, W) of a disk in the image's [0, 1]^2 coordinates (u along columns, v along rows).

    Parameters
    ----------
    shape : tuple of int
        The image's (H, W).
    centre : array_like
        (u, v) of the disk's centre.
    radius : float
        The disk's radius, in image coordinates.
    feather : float
        The width of the falloff beyond the radius, in image coordinates.

    Returns
    -------
    numpy.ndarray
        (H, W) weights in [0, 1].

    Examples
    --------
    >>> uv_region((3, 3), (0.5, 0.5), 0.1).astype(int).tolist()
    [[0, 0, 0], [0, 1, 0], [0, 0, 0]]
    """
    h, w = shape
    uu, vv = np.meshgrid(np.linspace(0, 1, w), np.linspace(0, 1, h))
    return ball_weights(np.stack([uu, vv], axis=-1), centre, radius, feather)


def load_mask(path: PathLike, shape: tuple[int, int]) -> np.ndarray:
    """Weights (H, W) in [0, 1] from an image file (PNG, EXR, ...: the first channel, scaled by its
    type's range; 8-bit 255 is 1). The file must have the geometry image's size.

    Parameters
    ----------
    path : path-like
        An image file.
    shape : tuple of int
        The geometry image's (H, W), which the file must have.

    Returns
    -------
    numpy.ndarray
        (H, W) float64 weights.

    Raises
    ------
    ImageFileError
        When the file cannot be read.
    InputError
        When it has another size, or values outside [0, 1].

    Examples
    --------
    >>> import tempfile, pathlib, cv2
    >>> p = str(pathlib.Path(tempfile.mkdtemp()) / "mask.png")
    >>> _ = cv2.imwrite(p, np.array([[0, 255]], np.uint8))
    >>> load_mask(p, (1, 2)).tolist()
    [[0.0, 1.0]]
    """
    path = Path(path)
    data, _, _ = read_raster(path, what="mask image")
    if data.shape[:2] != tuple(shape):
        raise InputError(f"mask: {path} is {data.shape[1]} x {data.shape[0]} pixels; the geometry image is "
                         f"{shape[1]} x {shape[0]}")
    w = data[..., 0].astype(np.float64)
    if not np.isfinite(w).all() or w.min() < 0 or w.max() > 1:
        raise InputError(f"mask: {path}: values must lie in [0, 1]")
    return w


