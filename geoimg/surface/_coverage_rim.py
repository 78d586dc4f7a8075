"""Rims that follow the mesh: the pixels on a planar image's rim moved onto the mesh's boundary.

A planar image of an open mesh whose outline is not the image's rectangle (a petal, a disk, a terrain cut
to a coastline) is masked: a pixel is valid within half a pixel of a triangle. The quad mesh's rim then runs
along pixel centres, a staircase up to a pixel and a half from the outline, which a picture shows as a saw
blade. Here each pixel on the quad mesh's rim (a corner of a quad with a missing neighbour) is moved to the
point of the mesh's boundary nearest to it in the parameter domain, and the surface evaluated there (for the
faithful surface, the mesh's boundary itself): the rim's vertices lie on the surface's outline, and the rim
follows it within the chord of two neighbouring pixels. A rim pixel already on the boundary (a terrain's
rectangle, a disk mapped to the square) is left as it is, to the bit.
"""
from __future__ import annotations

import numpy as np

from ..mesh import Mesh
from ..mesh._metrics import nearest_on_segments
from ..mesh._topology import boundary_edges

__all__ = ["boundary_segments", "rim_pixels", "snap_rim", "ON_BOUNDARY"]

ON_BOUNDARY = 1e-9      # a rim pixel this share of a pixel spacing from the boundary is on it: left alone


def boundary_segments(mesh: Mesh, coords: np.ndarray) -> np.ndarray:
    """The ends of the mesh's boundary edges (:func:`geoimg.mesh._topology.boundary_edges`) in the parameter
    domain, (B, 2, 2).

    Examples
    --------
    >>> uv = np.array([[0.0, 0], [1, 0], [0, 1]])
    >>> boundary_segments(Mesh(np.c_[uv, np.zeros(3)], [[0, 1, 2]]), uv).shape
    (3, 2, 2)
    """
    a, b = boundary_edges(mesh)
    return np.stack([coords[a], coords[b]], axis=1).astype(np.float64)


def rim_pixels(valid: np.ndarray) -> np.ndarray:
    """Where the quad mesh of a mask has its rim: pixels that are a corner of a quad (a 2 x 2 block of valid
    pixels) and of a missing one (or of none, at the image's edge).

    Examples
    --------
    >>> valid = np.ones((4, 4), bool); valid[0, 0] = False
    >>> rim_pixels(valid).astype(int)
    array([[0, 1, 1, 1],
           [1, 1, 0, 1],
           [1, 0, 0, 1],
           [1, 1, 1, 1]])
    """
    H, W = valid.shape
    quads = np.zeros((H + 1, W + 1), bool)          # quads[i + 1, j + 1]: the block of pixels (i..i+1, j..j+1)
    quads[1:-1, 1:-1] = valid[:-1, :-1] & valid[:-1, 1:] & valid[1:, :-1] & valid[1:, 1:]
    around = np.stack([quads[:-1, :-1], quads[:-1, 1:], quads[1:, :-1], quads[1:, 1:]])   # a pixel's four quads
    return np.asarray(around.any(axis=0) & ~around.all(axis=0))


def snap_rim(valid: np.ndarray, u: np.ndarray, v: np.ndarray, seg_uv: np.ndarray) -> tuple:
    """Where each rim pixel (:func:`rim_pixels`) off the boundary moves: its row, its column and the nearest
    point of the boundary in the parameter domain, there for the surface to be evaluated at.

    Parameters
    ----------
    valid : numpy.ndarray
        (H, W) the mask.
    u, v : numpy.ndarray
        The columns' and rows' parameter coordinates.
    seg_uv : numpy.ndarray
        (B, 2, 2) the boundary's edges (:func:`boundary_segments`).

    Returns
    -------
    rows, cols : numpy.ndarray
        (K,) the pixels that move.
    uv : numpy.ndarray
        (K, 2) where to.

    Examples
    --------
    >>> uv = np.array([[0.0, 0], [1, 0], [0, 1]])
    >>> seg = boundary_segments(Mesh(np.c_[uv, np.zeros(3)], [[0, 1, 2]]), uv)
    >>> g = np.linspace(0, 1, 5)
    >>> valid = g[None, :] + g[:, None] <= 1.1
    >>> rows, cols, to = snap_rim(valid, g, g, seg)
    >>> [(int(i), int(j), p.tolist()) for i, j, p in zip(rows, cols, to) if i == 1]   # (0.75, 0.25) is on it
    [(1, 2, [0.625, 0.375])]
    """
    ii, jj = np.nonzero(rim_pixels(valid))
    if not (len(seg_uv) and len(ii)):
        return ii[:0], jj[:0], np.zeros((0, 2))
    spacing = float(max(np.max(np.diff(u), initial=0), np.max(np.diff(v), initial=0)))
    pts = np.stack([u[jj], v[ii]], axis=1)
    t, dist, seg = nearest_on_segments(pts, seg_uv, spacing)
    move = dist > ON_BOUNDARY * spacing
    a, b = seg_uv[seg[move], 0], seg_uv[seg[move], 1]
    return ii[move], jj[move], a + t[move, None] * (b - a)
