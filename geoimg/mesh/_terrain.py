"""Terrain meshes from elevation grids (DEMs)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from .._raster import read_raster
from ._mesh import Mesh
from .._types import PathLike

__all__ = ["grid_mesh", "grid_triangles", "load_dem"]


def grid_mesh(heights: ArrayLike, spacing: tuple[float, float] = (1.0, 1.0)) -> Mesh:
    """Triangulate a regular elevation grid: vertex (x, y, z) = (col * dx, -row * dy, height), z up.

    Rows run north to south as in a DEM, so y = -row * dy keeps north up; each grid cell becomes two
    triangles, counter-clockwise seen from above.

    Parameters
    ----------
    heights : array_like, shape (H, W)
        Finite elevations, H, W >= 2.
    spacing : (float, float)
        Cell size (dx, dy), positive.

    Returns
    -------
    Mesh
        H x W vertices and 2 (H - 1)(W - 1) triangles.

    Raises
    ------
    InputError
        When the grid is smaller than 2 x 2, holds NaN or infinity, or the spacing is not two positive
        numbers.

    Examples
    --------
    >>> m = grid_mesh([[0, 1, 2], [3, 4, 5]])
    >>> m.n_vertices, m.n_faces
    (6, 4)
    """
    h = np.asarray(heights, dtype=np.float64)
    if h.ndim != 2 or min(h.shape) < 2:
        raise InputError(f"heights: expected a 2-D grid of at least 2 x 2, got shape {h.shape}")
    if not np.isfinite(h).all():
        raise InputError("heights: contains NaN or infinite values (fill or crop no-data cells first)")
    dx, dy = (float(x) for x in spacing)
    if not (dx > 0 and dy > 0):
        raise InputError(f"spacing: expected two positive numbers, got {spacing!r}")
    H, W = h.shape
    cols, rows = np.meshgrid(np.arange(W), np.arange(H))
    vertices = np.stack([cols.ravel() * dx, -rows.ravel() * dy, h.ravel()], axis=1)
    return Mesh(vertices, grid_triangles(H, W))


def grid_triangles(rows: int, cols: int) -> np.ndarray:
    """Two triangles per cell of a ``rows x cols`` grid of points numbered row by row, split along the
    diagonal from each cell's first corner: (T, 3) indices, counter-clockwise seen from +z when row ``r``,
    column ``c`` lies at (c, -r) (the way :func:`grid_mesh` lays a DEM out).

    Parameters
    ----------
    rows, cols : int
        The grid's size in points, at least 2 each.

    Returns
    -------
    numpy.ndarray
        (2 (rows - 1)(cols - 1), 3) int64 indices.

    Examples
    --------
    >>> grid_triangles(2, 2).tolist()
    [[0, 2, 3], [0, 3, 1]]
    """
    idx = np.arange(rows * cols).reshape(rows, cols)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    # (row, col) -> (x, -y): going a->d->c is counter-clockwise seen from +z
    return np.concatenate([np.stack([a, d, c], 1), np.stack([a, c, b], 1)])


def load_dem(path: PathLike) -> np.ndarray:
    """Elevations (H, W) float64 of a single-band raster (GeoTIFF, EXR, ...) through OpenImageIO, or of
    the first array in an ``.npz``. Georeferencing is not read: give :func:`grid_mesh` the cell size.

    Parameters
    ----------
    path : path-like
        The raster file (or ``.npz``).

    Returns
    -------
    numpy.ndarray
        (H, W) float64 elevations.

    Raises
    ------
    MeshFileError
        When the file cannot be read or holds no finite grid.

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "dem.npz"
    >>> np.savez(p, heights=np.arange(6.0).reshape(2, 3))
    >>> load_dem(p).shape
    (2, 3)
    """
    path = Path(path)
    if path.suffix.lower() == ".npz":
        if not path.is_file():
            raise FileNotFoundError(f"no elevation file at {path}")
        with np.load(path) as data:
            return np.asarray(data[data.files[0]], np.float64)
    return read_raster(path, what="elevation")[0][..., 0].astype(np.float64)
