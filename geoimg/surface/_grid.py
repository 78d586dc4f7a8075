"""The grid machinery both weight families share: bands of image rows for face-by-face kernels, the mask of
the pixels the faces hold, and unit normals from two tangents (numba, parallel over rows or points).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["grid_bands", "face_coverage", "unit_normals"]


@njit(cache=True)
def _band_lists(n_bands, band, faces, r0, r1):
    """CSR lists of ``faces`` (in their order) by the bands of ``band`` rows their rows ``r0..r1-1`` reach."""
    counts = np.zeros(n_bands + 1, np.int64)
    for k in range(faces.shape[0]):
        f = faces[k]
        for b in range(r0[f] // band, (r1[f] - 1) // band + 1):
            counts[b + 1] += 1
    ptr = np.cumsum(counts)
    fill = ptr[:-1].copy()
    out = np.empty(ptr[-1], np.int64)
    for k in range(faces.shape[0]):
        f = faces[k]
        for b in range(r0[f] // band, (r1[f] - 1) // band + 1):
            out[fill[b]] = f
            fill[b] += 1
    return ptr, out


def _band_rows(width: int) -> int:
    """Rows a band of the grid kernel holds: 16 for narrow images, fewer for wide ones, so that each of a
    band's running sums stays within 32 KB (4096 float64).
    """
    return max(1, min(16, 4096 // max(width, 1)))


def grid_bands(u, v, live, r0, r1, derivatives: bool):
    """What a face-by-face grid kernel runs on: the rows a band holds, the faces ``live`` listed by the bands
    their rows ``r0..r1-1`` reach, and its outputs (not zeroed: the kernels write every pixel, or say which they
    left): ``band, band_ptr, band_faces, P, Pu, Pv, ok``.
    """
    H, W = v.shape[0], u.shape[0]
    band = _band_rows(W)
    band_ptr, band_faces = _band_lists(-(-H // band), band, live, r0, r1)
    P = np.empty((H, W, 3))
    Pu = np.empty((H, W, 3) if derivatives else (1, 1, 3))
    Pv = np.empty_like(Pu)
    return band, band_ptr, band_faces, P, Pu, Pv, np.empty((H, W), np.bool_)


@njit(parallel=True, cache=True)
def _polygon_boxes(u, v, poly, sizes, eps):
    """Each polygon's grid index box ``[r0, r1) x [c0, c1)``, grown by ``eps``."""
    F = poly.shape[0]
    c0, c1 = np.empty(F, np.int64), np.empty(F, np.int64)
    r0, r1 = np.empty(F, np.int64), np.empty(F, np.int64)
    for f in prange(F):
        umin, umax, vmin, vmax = np.inf, -np.inf, np.inf, -np.inf
        for a in range(sizes[f]):
            umin = min(umin, poly[f, a, 0])
            umax = max(umax, poly[f, a, 0])
            vmin = min(vmin, poly[f, a, 1])
            vmax = max(vmax, poly[f, a, 1])
        c0[f] = np.searchsorted(u, umin - eps)
        c1[f] = np.searchsorted(u, umax + eps, side="right")
        r0[f] = np.searchsorted(v, vmin - eps)
        r1[f] = np.searchsorted(v, vmax + eps, side="right")
    return c0, c1, r0, r1


@njit(parallel=True, cache=True)
def _coverage_kernel(u, v, poly, sizes, eps, c0, c1, r0, r1, band, band_ptr, band_faces, mask):
    """Bands of ``band`` rows in parallel; each marks the pixels of its rows that its faces hold."""
    for b in prange(band_ptr.shape[0] - 1):
        for q in range(band_ptr[b], band_ptr[b + 1]):
            f = band_faces[q]
            k = sizes[f]
            for i in range(max(r0[f], b * band), min(r1[f], (b + 1) * band)):
                py = v[i]
                for j in range(c0[f], c1[f]):
                    if mask[i, j]:
                        continue
                    px = u[j]
                    inside = False
                    near = False
                    for a in range(k):
                        n = (a + 1) % k
                        ax, ay = poly[f, a, 0], poly[f, a, 1]
                        bx, by = poly[f, n, 0], poly[f, n, 1]
                        if (ay > py) != (by > py):
                            xc = ax + (py - ay) * (bx - ax) / (by - ay)
                            if px < xc:
                                inside = not inside
                        # distance from the pixel to the edge, for pixels on the boundary
                        ex, ey = bx - ax, by - ay
                        l2 = ex * ex + ey * ey
                        t = 0.0 if l2 == 0.0 else min(1.0, max(0.0, ((px - ax) * ex + (py - ay) * ey) / l2))
                        dx, dy = px - ax - t * ex, py - ay - t * ey
                        if dx * dx + dy * dy <= eps * eps:
                            near = True
                    if inside or near:
                        mask[i, j] = True


def face_coverage(u, v, polygons, sizes, eps):
    """Boolean (len(v), len(u)) mask of the grid points inside or within ``eps`` of any polygon.

    ``polygons`` is (F, K, 2) with ``sizes[f]`` real corners per face (even-odd rule, so non-convex
    faces are handled). Bands of rows run in parallel.
    """
    u = np.ascontiguousarray(u, np.float64)
    v = np.ascontiguousarray(v, np.float64)
    poly = np.ascontiguousarray(polygons, np.float64)
    sizes = np.ascontiguousarray(sizes, np.int64)
    c0, c1, r0, r1 = _polygon_boxes(u, v, poly, sizes, float(eps))
    live = np.flatnonzero((c1 > c0) & (r1 > r0))
    band = _band_rows(len(u))
    band_ptr, band_faces = _band_lists(-(-len(v) // band), band, live, r0, r1)
    mask = np.zeros((len(v), len(u)), np.bool_)
    _coverage_kernel(u, v, poly, sizes, float(eps), c0, c1, r0, r1, band, band_ptr, band_faces, mask)
    return mask


@njit(parallel=True, cache=True)
def _unit_cross(a, b, sign, out):
    for p in prange(a.shape[0]):
        x = (a[p, 1] * b[p, 2] - a[p, 2] * b[p, 1]) * sign
        y = (a[p, 2] * b[p, 0] - a[p, 0] * b[p, 2]) * sign
        z = (a[p, 0] * b[p, 1] - a[p, 1] * b[p, 0]) * sign
        n = math.sqrt(x * x + y * y + z * z)
        if n > 0:
            out[p, 0], out[p, 1], out[p, 2] = x / n, y / n, z / n
        else:
            out[p, 0] = out[p, 1] = out[p, 2] = 0.0


def unit_normals(a: np.ndarray, b: np.ndarray, sign: int) -> np.ndarray:
    """``unit(np.cross(a, b) * sign)`` for arrays of 3-vectors (same shape), bit for bit, in one parallel pass
    (zero crosses stay zero).
    """
    shape = np.shape(a)
    a2 = np.ascontiguousarray(a, np.float64).reshape(-1, 3)
    b2 = np.ascontiguousarray(b, np.float64).reshape(-1, 3)
    out = np.empty_like(a2)
    _unit_cross(a2, b2, float(sign), out)
    return out.reshape(shape)
