"""numba kernel of the point-to-mesh distance: for each point, the exact distance to the nearest of its
candidate triangles (Ericson's Voronoi regions of a triangle; the numpy twin is
:func:`tests/reference.py:point_triangle_distance`)."""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["nearest_triangle_distances"]


@njit(cache=True)
def _segment(px, py, pz, v, a, b):
    """Distance from p to the segment a-b (a point when a == b)."""
    dx, dy, dz = v[b, 0] - v[a, 0], v[b, 1] - v[a, 1], v[b, 2] - v[a, 2]
    qx, qy, qz = px - v[a, 0], py - v[a, 1], pz - v[a, 2]
    dd = dx * dx + dy * dy + dz * dz
    t = 0.0 if dd == 0.0 else min(1.0, max(0.0, (qx * dx + qy * dy + qz * dz) / dd))
    return math.sqrt((qx - t * dx) ** 2 + (qy - t * dy) ** 2 + (qz - t * dz) ** 2)


@njit(cache=True, error_model="numpy")     # a 0/0 left over gives NaN, caught below, not an error
def _distance(px, py, pz, v, a, b, c):
    ax, ay, az = v[a, 0], v[a, 1], v[a, 2]
    abx, aby, abz = v[b, 0] - ax, v[b, 1] - ay, v[b, 2] - az
    acx, acy, acz = v[c, 0] - ax, v[c, 1] - ay, v[c, 2] - az
    nx, ny, nz = aby * acz - abz * acy, abz * acx - abx * acz, abx * acy - aby * acx
    scale = (abx * abx + aby * aby + abz * abz) * (acx * acx + acy * acy + acz * acz)
    if nx * nx + ny * ny + nz * nz <= 1e-24 * scale:       # no area (a segment or a point): its edges
        return min(_segment(px, py, pz, v, a, b), _segment(px, py, pz, v, b, c), _segment(px, py, pz, v, c, a))
    apx, apy, apz = px - ax, py - ay, pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        qx, qy, qz = ax, ay, az
    else:
        bpx, bpy, bpz = px - v[b, 0], py - v[b, 1], pz - v[b, 2]
        d3 = abx * bpx + aby * bpy + abz * bpz
        d4 = acx * bpx + acy * bpy + acz * bpz
        cpx, cpy, cpz = px - v[c, 0], py - v[c, 1], pz - v[c, 2]
        d5 = abx * cpx + aby * cpy + abz * cpz
        d6 = acx * cpx + acy * cpy + acz * cpz
        va = d3 * d6 - d5 * d4
        vb = d5 * d2 - d1 * d6
        vc = d1 * d4 - d3 * d2
        if d3 >= 0.0 and d4 <= d3:
            qx, qy, qz = v[b, 0], v[b, 1], v[b, 2]
        elif d6 >= 0.0 and d5 <= d6:
            qx, qy, qz = v[c, 0], v[c, 1], v[c, 2]
        elif va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
            t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
            qx, qy, qz = v[b, 0] + t * (v[c, 0] - v[b, 0]), v[b, 1] + t * (v[c, 1] - v[b, 1]), \
                v[b, 2] + t * (v[c, 2] - v[b, 2])
        elif vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
            t = d2 / (d2 - d6)
            qx, qy, qz = ax + t * acx, ay + t * acy, az + t * acz
        elif vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
            t = d1 / (d1 - d3)
            qx, qy, qz = ax + t * abx, ay + t * aby, az + t * abz
        else:
            denom = va + vb + vc
            if denom != 0.0:
                s, w = vb / denom, vc / denom
                qx, qy, qz = ax + s * abx + w * acx, ay + s * aby + w * acy, az + s * abz + w * acz
            else:                                   # a degenerate triangle: its first corner
                qx, qy, qz = ax, ay, az
    if not (math.isfinite(qx) and math.isfinite(qy) and math.isfinite(qz)):
        qx, qy, qz = ax, ay, az
    return math.sqrt((px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2)


@njit(parallel=True, cache=True)
def nearest_triangle_distances(points, vertices, tris, candidates):
    """``out[i]``: the smallest distance from ``points[i]`` to the triangles ``tris[candidates[i, :]]``."""
    n, k = candidates.shape
    out = np.empty(n)
    for i in prange(n):
        best = np.inf
        for j in range(k):
            t = candidates[i, j]
            d = _distance(points[i, 0], points[i, 1], points[i, 2], vertices, tris[t, 0], tris[t, 1], tris[t, 2])
            if d < best:
                best = d
        out[i] = best
    return out
