"""Squares glued along their perimeters: what the cut-open and the multi-chart domains share.

A square of ``n x n`` pixels has ``4 (n - 1)`` perimeter positions, counter-clockwise from pixel (0, 0)
along row 0 (:func:`perimeter_pixels`). A stretch of one square's perimeter is glued to a stretch of the
same or another square's in reverse, so a face near one side is seen beyond the other (:func:`ghost_copies`)
and a filter reads across it the pixels inward of the other side (:func:`copy_across`).
"""
from __future__ import annotations

import numpy as np

__all__ = ["perimeter_pixels", "perimeter_cells", "perimeter_sides", "INWARD", "corners_within", "straight_pieces",
           "glue_groups", "ghost_copies", "copy_across"]

INWARD = np.array([[1, 0], [0, -1], [-1, 0], [0, 1]])     # (row, col) step into a square, by side


def perimeter_pixels(n: int) -> np.ndarray:
    """Flat pixel index (in an ``n x n`` square) of each perimeter position 0 .. 4 (n - 1) (the last one is
    pixel 0 again).

    Parameters
    ----------
    n : int
        The square's side in pixels.

    Returns
    -------
    numpy.ndarray
        (4 (n - 1) + 1,) flat pixel indices.

    Examples
    --------
    >>> perimeter_pixels(3).tolist()
    [0, 1, 2, 5, 8, 7, 6, 3, 0]
    """
    row, col = perimeter_cells(np.arange(4 * (n - 1) + 1), n)
    return row * n + col


def perimeter_cells(t: np.ndarray, n) -> tuple[np.ndarray, np.ndarray]:
    """(row, column) in an ``n x n`` square of perimeter positions ``t`` (pixels, 0 .. 4 (n - 1)); ``n`` may be
    an array, one side per position.

    Examples
    --------
    >>> [x.tolist() for x in perimeter_cells(np.array([1, 3, 4]), np.array([3, 3, 5]))]
    [[0, 1, 0], [1, 2, 4]]
    """
    t = np.asarray(t, np.int64)
    m = np.asarray(n, np.int64) - 1
    side = np.minimum(t // m, 3)
    f = t - side * m
    zero, last = np.zeros_like(f), np.broadcast_to(m, f.shape)
    row = np.choose(side, [zero, f, last, m - f])
    col = np.choose(side, [f, last, m - f, zero])
    return row, col


def perimeter_sides(t: np.ndarray, n: int) -> np.ndarray:
    """The side (0: row 0, 1: last column, 2: last row, 3: column 0) of perimeter positions ``t`` (pixels)."""
    return np.minimum(np.asarray(t) // (n - 1), 3)


def corners_within(start: int, length: int, quantum: int) -> list:
    """The square's corners (perimeter positions, quanta) strictly inside ``start .. start + length``.

    Examples
    --------
    >>> corners_within(2, 8, 4)
    [4, 8]
    """
    return [c for c in range(quantum, 4 * quantum, quantum) if start < c < start + length]


def straight_pieces(start: int, length: int, twin_start: int, quantum: int, twin_quantum: int | None = None) -> list:
    """A glued segment split where either side turns a corner of its square: ``(o1, o2)`` offsets along it
    (offset ``o`` is ``start + o`` on this side, ``twin_start + length - o`` on the twin; the twin's square
    ``twin_quantum`` quanta a side, ``quantum`` when not given).

    Examples
    --------
    >>> straight_pieces(2, 4, 9, 4)      # this side turns at 4, the twin (9 .. 13) at 12
    [(0, 1), (1, 2), (2, 4)]
    """
    cuts = {0, length}
    cuts.update(c - start for c in corners_within(start, length, quantum))
    cuts.update(twin_start + length - c
                for c in corners_within(twin_start, length, quantum if twin_quantum is None else twin_quantum))
    ordered = sorted(cuts)
    return list(zip(ordered[:-1], ordered[1:]))


def glue_groups(size: int, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The glue of ``size`` pixels where pixel ``a[k]`` is pixel ``b[k]`` (flat indices): each group's first
    pixel and each pixel's group (what :meth:`~geoimg.Domain.glue` returns).

    Examples
    --------
    >>> [x.tolist() for x in glue_groups(4, np.array([0, 3]), np.array([2, 2]))]
    [[0, 1], [0, 1, 0, 0]]
    """
    from scipy import sparse                      # here: reading an image needs no scipy at import
    from scipy.sparse.csgraph import connected_components
    graph = sparse.coo_matrix((np.ones(len(a)), (a, b)), shape=(size, size))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, size, np.int64)
    np.minimum.at(first, label, np.arange(size))
    return np.unique(first[label], return_inverse=True)


def _to_segment(points: np.ndarray, p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
    """Distance of each of ``points`` (K, 2) to the segment from ``p0`` to ``p1``."""
    d = p1 - p0
    along = np.clip((points - p0) @ d / max(float(d @ d), 1e-300), 0.0, 1.0)
    return np.linalg.norm(points - (p0 + along[:, None] * d), axis=1)


def ghost_copies(centres: np.ndarray, reach: np.ndarray, pieces: list, rims: list,
                 size: np.ndarray | None = None) -> list:
    """Across each glued straight piece, the faces near its twin, turned and moved rigidly onto this piece's
    outside: ``(face indices, R, b)`` per piece that takes any. Each face goes with the piece whose twin is
    nearest to it (a face off the twin's ends, or within its ``size`` of one, goes with none: its copy would land
    or spill beside the perimeter's next stretch, where the surface beyond is another part of the mesh), if its
    ``reach`` gets there; no copy may come within its reach of a ``rim`` (the mesh's own
    boundary: its pixels are on the surface).

    Parameters
    ----------
    centres : numpy.ndarray
        (F, 2) the faces' parametric centres.
    reach : numpy.ndarray
        (F,) how far each face's weights reach.
    pieces : list
        ``((p0, p1), (q0, q1))`` per piece: its ends and its twin's, ``p0`` glued to ``q0``.
    rims : list
        ``(p0, p1)`` per straight piece of the mesh's own boundary.
    size : numpy.ndarray or None
        (F,) each face's own size; None: no margin at the twins' ends.

    Returns
    -------
    list
        ``(face indices, R (2, 2), b (2,))`` per copy.

    Examples
    --------
    >>> one = ((np.array([0.0, 0.0]), np.array([1.0, 0.0])), (np.array([1.0, 1.0]), np.array([0.0, 1.0])))
    >>> [(k.tolist(), b.tolist()) for k, R, b in ghost_copies(np.array([[0.5, 0.9]]), np.ones(1), [one], [])]
    [([0], [1.0, 1.0])]
    """
    c = np.asarray(centres, np.float64)
    if not pieces:
        return []
    dist = np.empty((len(pieces), len(c)))
    maps = []
    for k, ((p0, p1), (q0, q1)) in enumerate(pieces):
        ds, dt = p1 - p0, q1 - q0
        length2 = float(dt @ dt)
        along = (c - q0) @ dt / max(length2, 1e-300)
        dist[k] = np.linalg.norm(c - (q0 + np.clip(along, 0.0, 1.0)[:, None] * dt), axis=1)   # to the twin piece
        margin = 0.0 if size is None else size / np.sqrt(max(length2, 1e-300))     # along the twin
        dist[k][(along < margin) | (along > 1.0 - margin)] = np.inf
        cos, sin = (dt @ ds) / max(length2, 1e-300), (dt[0] * ds[1] - dt[1] * ds[0]) / max(length2, 1e-300)
        R = np.array([[cos, -sin], [sin, cos]])
        maps.append((R, p0 - R @ q0))
    nearest = np.argmin(dist, axis=0)
    out = []
    for k, (R, b) in enumerate(maps):
        take = np.flatnonzero((nearest == k) & (dist[k] < reach))
        if len(take) and rims:
            moved = c[take] @ R.T + b
            to_rim = np.min([_to_segment(moved, p0, p1) for p0, p1 in rims], axis=0)
            take = take[to_rim >= reach[take]]
        if len(take):
            out.append((take, R, b))
    return out


def copy_across(out: np.ndarray, a: np.ndarray, dst: tuple, src: tuple, steps: np.ndarray, offset: int) -> None:
    """Write into ``out`` (``a`` padded by ``offset``) beyond each glued perimeter pixel the pixels inward of
    its twin: ``dst = (rows, cols, sides)`` of the pixels (in ``a``) and the side each is on, ``src`` the
    same of their twins; pixel ``k`` steps out ``1 .. steps[k]`` from its side.
    """
    (rp, cp, side_p), (rq, cq, side_q) = dst, src
    H, W = a.shape[:2]
    for k in range(1, int(steps.max(initial=0)) + 1):
        go = steps >= k
        src_r = np.clip(rq[go] + k * INWARD[side_q[go], 0], 0, H - 1)
        src_c = np.clip(cq[go] + k * INWARD[side_q[go], 1], 0, W - 1)
        dst_r = rp[go] - k * INWARD[side_p[go], 0] + offset
        dst_c = cp[go] - k * INWARD[side_p[go], 1] + offset
        out[dst_r, dst_c] = a[src_r, src_c]
