"""The layout of cut-open and chart images: squares of quanta in a rectangle, positions along a square's
perimeter and the glued twins of its pixels (what :class:`~geoimg.image.CutDomain` and
:class:`~geoimg.image.ChartsDomain` address, and what the cut and chart maps lay out; no mesh here).
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["MIN_SCALE", "perimeter_point", "twin_positions", "layout_span", "tile_points", "layout_extent",
           "weld_defects"]

MIN_SCALE = 2             # pixels per quantum at least: a border of one quantum then has a pixel inside it


def perimeter_point(t: ArrayLike, quanta_per_side: int) -> np.ndarray:
    """(u, v) on the unit square's outline at perimeter positions ``t`` (in quanta, 0 to 4 Q):
    counter-clockwise from (0, 0) in (u, v), i.e. along row 0, down the last column, back along the last
    row, up column 0.

    Parameters
    ----------
    t : array_like
        Perimeter positions, in quanta.
    quanta_per_side : int
        Quanta per side of the square.

    Returns
    -------
    numpy.ndarray
        (..., 2) (u, v).

    Examples
    --------
    >>> perimeter_point([0, 2, 5, 7.5], 2).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [0.0, 0.25]]
    """
    s = np.asarray(t, np.float64) / quanta_per_side
    side = np.clip(np.floor(s).astype(int), 0, 3)
    f = s - side
    u = np.choose(side, [f, np.ones_like(f), 1 - f, np.zeros_like(f)])
    v = np.choose(side, [np.zeros_like(f), f, np.ones_like(f), 1 - f])
    return np.stack([u, v], axis=1)


def twin_positions(segments: list | tuple, scale: int) -> tuple:
    """Every glued perimeter pixel and its twin, both directions: ``(tile, position, twin's tile, twin's
    position)`` arrays, positions in pixels along a square's perimeter (``start * scale`` to ``(start +
    length) * scale``, not reduced modulo the perimeter), for ``segments`` ``(tile, start, length, twin)`` in
    quanta on squares of ``scale`` pixels per quantum. Offset ``j`` along a segment is offset ``length - j``
    along its twin.

    Parameters
    ----------
    segments : list or tuple
        ``(tile, start, length, twin)`` per segment (``twin`` an index into ``segments``, -1 for none).
    scale : int
        Pixels per quantum.

    Returns
    -------
    tuple of numpy.ndarray
        ``(tile, position, twin's tile, twin's position)``.

    Examples
    --------
    >>> [a.tolist() for a in twin_positions([(0, 0, 2, 1), (0, 2, 2, 0)], 1)]
    [[0, 0, 0, 0, 0, 0], [0, 1, 2, 2, 3, 4], [0, 0, 0, 0, 0, 0], [4, 3, 2, 2, 1, 0]]
    """
    out: list = [[], [], [], []]
    for tile, start, length, twin in segments:
        if twin < 0:
            continue
        j = np.arange(length * scale + 1)
        out[0].append(np.full(len(j), tile))
        out[1].append(start * scale + j)
        out[2].append(np.full(len(j), segments[twin][0]))
        out[3].append(segments[twin][1] * scale + length * scale - j)
    if not out[0]:
        return tuple(np.zeros(0, np.int64) for _ in range(4))
    return tuple(np.concatenate(x) for x in out)


def layout_span(squares: Sequence) -> tuple[int, int]:
    """Quanta across and down a layout of ``squares`` (``(row, column, side)`` per square, in quanta).

    Examples
    --------
    >>> layout_span([(0, 0, 4), (0, 6, 2)])
    (8, 4)
    """
    sq = np.asarray(squares, np.int64).reshape(-1, 3)
    return int((sq[:, 1] + sq[:, 2]).max()), int((sq[:, 0] + sq[:, 2]).max())


def tile_points(tile: np.ndarray, uv: np.ndarray, squares: Sequence) -> np.ndarray:
    """Points ``uv`` (K, 2) of the unit square of each ``tile`` (K,) of a layout of ``squares`` (``(row,
    column, side)`` per square, in quanta), scaled so that the layout's longer side is 1.

    Parameters
    ----------
    tile : numpy.ndarray
        (K,) square indices.
    uv : numpy.ndarray
        (K, 2) points of the unit square (u along columns, v along rows).
    squares : sequence
        ``(row, column, side)`` per square.

    Returns
    -------
    numpy.ndarray
        (K, 2) parameter points.

    Examples
    --------
    >>> tile_points(np.array([0, 1]), np.array([[0.0, 0.0], [1.0, 1.0]]), [(0, 0, 4), (0, 6, 4)]).tolist()
    [[0.0, 0.0], [1.0, 0.4]]
    """
    tile = np.asarray(tile, np.int64)
    sq = np.asarray(squares, np.int64).reshape(-1, 3)[tile]
    big = max(layout_span(squares))
    corner = np.stack([sq[:, 1], sq[:, 0]], axis=1)
    return (corner + np.asarray(uv, np.float64) * sq[:, 2:3]) / big


def layout_extent(layout: dict) -> tuple[float, float]:
    """The parameter rectangle of a layout of squares (``layout``: a :class:`~geoimg.image.ChartsDomain`'s
    fields), its longer side 1.

    Parameters
    ----------
    layout : dict
        ``squares`` (``(row, column, side)`` per square, in quanta).

    Returns
    -------
    tuple of float
        (width, height).

    Examples
    --------
    >>> layout_extent({"squares": [(0, 0, 4), (0, 6, 4)], "gutter": 2})
    (1.0, 0.4)
    """
    across, down = layout_span(layout["squares"])
    big = max(across, down)
    return across / big, down / big



def weld_defects(segments: list | tuple, sides: Sequence, scale: int) -> int:
    """How many perimeter edges of a layout of square charts (``segments``: ``(tile, start, length, twin)`` in
    quanta, square ``k`` ``sides[k]`` quanta a side) would not weld into a manifold quad mesh on an image of
    ``scale`` pixels per quantum: an edge whose two ends are glued into one vertex, more than two edges glued
    into one (a border of one quantum beside its own twin's neighbour at ``scale = 1``), or a square's corner
    whose two sides are glued there (the tip of a slit at a corner folds the corner's quad onto itself).

    Examples
    --------
    >>> weld_defects([(0, 0, 16, 1), (1, 0, 16, 0)], [4, 4], 1)         # two squares glued round their rims
    0
    >>> weld_defects([(0, 0, 8, 1), (0, 8, 8, 0)], [4], 2)              # one square folded: tips at two corners
    2
    """
    per = 4 * np.asarray(sides, np.int64) * scale
    off = np.concatenate([[0], np.cumsum(per)])
    tp, p, tq, q = twin_positions(segments, scale)
    n = int(off[-1])
    from scipy.sparse import coo_matrix                 # here: the domains import this module without scipy
    from scipy.sparse.csgraph import connected_components
    _, group = connected_components(coo_matrix((np.ones(len(p)), (off[tp] + p % per[tp], off[tq] + q % per[tq])),
                                               shape=(n, n)), directed=False)
    used = np.unique([s[0] for s in segments])
    i = np.concatenate([off[t] + np.arange(per[t]) for t in used])
    j = np.concatenate([off[t] + (np.arange(per[t]) + 1) % per[t] for t in used])
    x, y = group[i], group[j]
    collapsed = int(np.sum(x == y))
    _, counts = np.unique(np.minimum(x, y)[x != y] * n + np.maximum(x, y)[x != y], return_counts=True)
    folded = 0                                  # a slit's tip at a corner folds its quad
    for t in used:
        corner = np.arange(0, per[t], per[t] // 4)
        folded += int(np.sum(group[off[t] + (corner - 1) % per[t]] == group[off[t] + (corner + 1) % per[t]]))
    return collapsed + int(np.sum(counts[counts > 2])) + folded
