"""Faces binned by their reach, for both weight families on the sphere: tangent frames of directions, 3-D
cells of the faces' reach (balls, or half-spaces beyond a plane), the cell of a point; and a face's size, the
radius of its enclosing circle in the parameter domain.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["tangent_frames", "build_cells_3d", "enclosing_circle_radius"]


@njit(parallel=True, cache=True)
def tangent_frames(q):
    """Unit tangents ``t1, t2`` (k, 3) at unit directions ``q`` with ``t1 x t2 = q``: ``t1`` along
    ``e x q`` for ``e`` the axis of ``q``'s smallest component (the first on ties), ``t2 = q x t1``.
    """
    n = q.shape[0]
    t1 = np.empty((n, 3))
    t2 = np.empty((n, 3))
    for p in prange(n):
        x, y, z = q[p, 0], q[p, 1], q[p, 2]
        k = 1 if abs(y) < abs(x) else 0
        if abs(z) < (abs(y) if k == 1 else abs(x)):
            k = 2
        hx, hy, hz = (1.0 if k == 0 else 0.0), (1.0 if k == 1 else 0.0), (1.0 if k == 2 else 0.0)
        cx, cy, cz = hy * z - hz * y, hz * x - hx * z, hx * y - hy * x
        length = math.sqrt(cx * cx + cy * cy + cz * cz)
        cx, cy, cz = cx / length, cy / length, cz / length
        t1[p, 0], t1[p, 1], t1[p, 2] = cx, cy, cz
        t2[p, 0], t2[p, 1], t2[p, 2] = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return t1, t2


def build_cells_3d(centres: np.ndarray, radius: np.ndarray, max_cells: int = 96, *, planes: np.ndarray | None = None,
                   floor: float = 0.0, unit: bool = False, z: float | None = None):
    """Bin faces into a uniform grid of cubes over [-1, 1]^3: each face into the cubes its ball of
    ``radius`` around its centre reaches (not every cube of the ball's bounding box: fewer candidates per
    point, the same sums). With ``planes`` (T, 3, 3), a face also stays out of every cube where one of its
    three linear functions ``planes[f, e] . p`` is below ``floor`` throughout (where its terms are cut off):
    the ball of a face with a sharp corner is far larger than where it counts. With ``unit`` (points that are
    unit vectors), only the cubes that meet the unit sphere hold faces; with ``z`` (points all on the plane
    ``z``: a planar domain's homogeneous ``(u, v, 1)``), only the layer of cubes that holds it (a third or
    less of the work, the same lists there). The cubes' side is the radii's median, at least
    ``2 / max_cells``. Returns ``(h, n, ptr, faces)``; cell ``(ix, iy, iz)`` is
    ``(iz * n + iy) * n + ix``.
    """
    r = np.minimum(radius, 2.0)
    h = max(float(np.median(r)), 2.0 / max_cells)
    n = int(math.ceil(2.0 / h)) + 1
    c = np.ascontiguousarray(centres, np.float64)
    lo = np.clip(np.floor((c - r[:, None] + 1.0) / h).astype(np.int64), 0, n - 1)
    hi = np.clip(np.floor((c + r[:, None] + 1.0) / h).astype(np.int64), 0, n - 1)
    if z is not None:                  # the layer _cell_of puts the points in; a face that misses it, nowhere
        layer = _cell_of(-1.0, -1.0, float(z), h, n) // (n * n)
        reach = (lo[:, 2] <= layer) & (layer <= hi[:, 2])
        lo[:, 2] = np.where(reach, layer, 1)
        hi[:, 2] = np.where(reach, layer, 0)
    use = planes is not None
    pl = np.ascontiguousarray(planes if use else np.zeros((1, 3, 3)), np.float64)
    ptr, faces = _fill(c, np.ascontiguousarray(r, np.float64), lo, hi, n, h, pl, float(floor), use, bool(unit))
    return h, n, ptr, faces


@njit(cache=True)
def _reaches(c, r, ix, iy, iz, h):
    """Whether the ball of radius ``r`` round ``c`` meets cell (ix, iy, iz) (cube [-1 + i h, -1 + (i + 1) h])."""
    d2 = 0.0
    for k, i in ((0, ix), (1, iy), (2, iz)):
        lo = -1.0 + i * h
        if c[k] < lo:
            d2 += (lo - c[k]) ** 2
        elif c[k] > lo + h:
            d2 += (c[k] - lo - h) ** 2
    return d2 <= r * r


@njit(cache=True)
def _on_sphere(ix, iy, iz, h):
    """Whether cell (ix, iy, iz) meets the unit sphere (its nearest point inside it, its farthest outside)."""
    near = 0.0
    far = 0.0
    for i in (ix, iy, iz):
        lo = -1.0 + i * h
        hi = lo + h
        near += 0.0 if lo <= 0.0 <= hi else min(lo * lo, hi * hi)
        far += max(lo * lo, hi * hi)
    return near <= 1.0 + 1e-9 and far >= 1.0 - 1e-9


@njit(cache=True)
def _above(pl, f, floor, ix, iy, iz, h):
    """Whether each of face ``f``'s three linear functions reaches ``floor`` somewhere in cell (ix, iy, iz)."""
    for e in range(3):
        top = 0.0
        for k, i in ((0, ix), (1, iy), (2, iz)):
            lo = -1.0 + i * h
            a = pl[f, e, k]
            top += max(a * lo, a * (lo + h))
        if top < floor:
            return False
    return True


@njit(cache=True, inline="always")
def _meets(c, r, f, ix, iy, iz, h, pl, floor, use_planes, unit):
    return (_reaches(c[f], r[f], ix, iy, iz, h) and (not unit or _on_sphere(ix, iy, iz, h))
            and (not use_planes or _above(pl, f, floor, ix, iy, iz, h)))


@njit(parallel=True, cache=True)
def _face_cells(c, r, lo, hi, n, h, pl, floor, use_planes, unit, start, out):
    """Each face's cells, in order, into ``out[start[f]:]`` (counted only, when ``out`` is empty); faces in
    parallel. Returns the counts.
    """
    counts = np.zeros(lo.shape[0], np.int64)
    write = out.shape[0] > 0
    for f in prange(lo.shape[0]):
        k = 0
        for iz in range(lo[f, 2], hi[f, 2] + 1):
            for iy in range(lo[f, 1], hi[f, 1] + 1):
                for ix in range(lo[f, 0], hi[f, 0] + 1):
                    if _meets(c, r, f, ix, iy, iz, h, pl, floor, use_planes, unit):
                        if write:
                            out[start[f] + k] = (iz * n + iy) * n + ix
                        k += 1
        counts[f] = k
    return counts


@njit(cache=True)
def _by_cell(cell_of, face_of, n_cells):
    """A counting sort of the (cell, face) pairs by cell, faces in order within each cell."""
    ptr = np.zeros(n_cells + 1, np.int64)
    for i in range(cell_of.shape[0]):
        ptr[cell_of[i] + 1] += 1
    for i in range(n_cells):
        ptr[i + 1] += ptr[i]
    fill = ptr[:-1].copy()
    out = np.empty(cell_of.shape[0], np.int64)
    for i in range(cell_of.shape[0]):
        out[fill[cell_of[i]]] = face_of[i]
        fill[cell_of[i]] += 1
    return ptr, out


def _fill(c, r, lo, hi, n, h, pl, floor, use_planes, unit):
    """The cells' face lists: ``(ptr, faces)``, each cell's faces ascending."""
    args = (c, r, lo, hi, n, h, pl, floor, use_planes, unit)
    counts = _face_cells(*args, np.zeros(len(lo), np.int64), np.empty(0, np.int64))
    start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    cell_of = np.empty(int(counts.sum()), np.int64)
    _face_cells(*args, start, cell_of)
    return _by_cell(cell_of, np.repeat(np.arange(len(lo), dtype=np.int64), counts), n * n * n)


@njit(cache=True, inline="always")
def _cell_of(x, y, z, h, n):
    """The index of the cube of :func:`build_cells_3d` (side ``h``, ``n`` a side) holding point (x, y, z)."""
    ix = min(max(int(math.floor((x + 1.0) / h)), 0), n - 1)
    iy = min(max(int(math.floor((y + 1.0) / h)), 0), n - 1)
    iz = min(max(int(math.floor((z + 1.0) / h)), 0), n - 1)
    return (iz * n + iy) * n + ix


def enclosing_circle_radius(p: np.ndarray) -> np.ndarray:
    """Radius of the smallest circle enclosing each triangle ``p`` of shape (T, 3, 2).

    Half the longest edge for a right or obtuse triangle, the circumradius otherwise.

    Examples
    --------
    >>> enclosing_circle_radius(np.array([[[0., 0], [2, 0], [1, 0.1]]])).round(6).tolist()
    [1.0]
    """
    e = np.stack([p[:, 1] - p[:, 2], p[:, 2] - p[:, 0], p[:, 0] - p[:, 1]], axis=1)
    sq = np.einsum("tij,tij->ti", e, e)
    longest = sq.max(axis=1)
    rest = sq.sum(axis=1) - longest
    area2 = np.abs(e[:, 1, 0] * e[:, 2, 1] - e[:, 1, 1] * e[:, 2, 0])  # twice the area
    obtuse = longest >= rest
    with np.errstate(divide="ignore", invalid="ignore"):
        circum = np.sqrt(sq.prod(axis=1)) / (2.0 * area2)
    return np.where(obtuse | (area2 == 0), 0.5 * np.sqrt(longest), circum)
