"""numba kernels of the weighted-mean surface on the sphere (octahedral domain).

A face i has a weight centre ``c_i`` (unit vector), a plane ``n_i . g = h_i`` through its vertices on
the sphere, a frame ``(o_i, e1_i, e2_i)`` in that plane and the affine map ``P_i = C_i + A_i a + B_i b``
of the frame coordinates. A direction ``q`` reaches the plane by orthogonal projection,
``a = (q - o_i) . e1_i``, ``b = (q - o_i) . e2_i``: the map of a face is its own plane's, extended over
the whole sphere as an affine function of ``q``, bounded everywhere (a central projection would blow up
for faces turned 90 degrees away, which carry weight on coarse meshes), and faces across the
octahedron's creases need no special case. Weights are ``exp(-|q - c_i|^2 / 2 sigma_i^2)``.

For each point the kernel returns P and its derivatives along two tangent directions ``t1, t2``.
Faces are skipped outside ``|q - c_i| <= R_i`` (3-D cells); a point whose largest weight exponent is
below ``log_g_ref`` is recomputed over all faces. Sums are shifted by the largest exponent (no underflow).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["build_cells_3d", "evaluate_sphere", "TRUNCATED", "EXACT"]

TRUNCATED, EXACT = 0, 1


def build_cells_3d(centres: np.ndarray, radius: np.ndarray, max_cells: int = 96):
    """Bin faces into a uniform grid of cubes over [-1, 1]^3: each face into the cubes its ball of
    ``radius`` around its centre reaches (not every cube of the ball's bounding box: fewer candidates per
    point, the same sums). Returns ``(h, n, ptr, faces)``; cell ``(ix, iy, iz)`` is ``(iz * n + iy) * n + ix``."""
    r = np.minimum(radius, 2.0)
    h = max(float(np.median(r)), 2.0 / max_cells)
    n = int(math.ceil(2.0 / h)) + 1
    c = np.ascontiguousarray(centres, np.float64)
    lo = np.clip(np.floor((c - r[:, None] + 1.0) / h).astype(np.int64), 0, n - 1)
    hi = np.clip(np.floor((c + r[:, None] + 1.0) / h).astype(np.int64), 0, n - 1)
    ptr, faces = _fill(c, np.ascontiguousarray(r, np.float64), lo, hi, n, h)
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
def _fill(c, r, lo, hi, n, h):
    counts = np.zeros(n * n * n + 1, np.int64)
    for f in range(lo.shape[0]):
        for iz in range(lo[f, 2], hi[f, 2] + 1):
            for iy in range(lo[f, 1], hi[f, 1] + 1):
                for ix in range(lo[f, 0], hi[f, 0] + 1):
                    if _reaches(c[f], r[f], ix, iy, iz, h):
                        counts[(iz * n + iy) * n + ix + 1] += 1
    ptr = np.cumsum(counts)
    fill = ptr[:-1].copy()
    out = np.empty(ptr[-1], np.int64)
    for f in range(lo.shape[0]):
        for iz in range(lo[f, 2], hi[f, 2] + 1):
            for iy in range(lo[f, 1], hi[f, 1] + 1):
                for ix in range(lo[f, 0], hi[f, 0] + 1):
                    if _reaches(c[f], r[f], ix, iy, iz, h):
                        cell = (iz * n + iy) * n + ix
                        out[fill[cell]] = f
                        fill[cell] += 1
    return ptr, out


@njit(cache=True)
def _sum(q, t1, t2, cand, n_cand, all_faces, centre, inv2s, radius, origin, e1, e2, C, A, B, deriv, acc):
    """Accumulate over candidate faces (the derivatives' sums only with ``deriv``); returns the largest
    exponent (-inf when no face is in range)."""
    m = -np.inf
    for k in range(n_cand):
        f = k if all_faces else cand[k]
        d2 = 0.0
        for c in range(3):
            d2 += (q[c] - centre[f, c]) ** 2
        if not all_faces and d2 > radius[f] * radius[f]:
            continue
        e = -d2 * inv2s[f]
        if e > m:
            m = e
    if m == -np.inf:
        return m
    for j in range(16):
        acc[j] = 0.0
    for k in range(n_cand):
        f = k if all_faces else cand[k]
        d2 = 0.0
        for c in range(3):
            d2 += (q[c] - centre[f, c]) ** 2
        if not all_faces and d2 > radius[f] * radius[f]:
            continue
        w = math.exp(-d2 * inv2s[f] - m)
        a = 0.0
        b = 0.0
        for c in range(3):      # orthogonal projection onto the face's plane, in its frame: affine in q
            g = q[c] - origin[f, c]
            a += g * e1[f, c]
            b += g * e2[f, c]
        acc[0] += w
        if not deriv:
            for c in range(3):
                acc[1 + c] += w * (C[f, c] + A[f, c] * a + B[f, c] * b)
            continue
        dq1 = 0.0
        dq2 = 0.0
        a1 = 0.0
        b1 = 0.0
        a2 = 0.0
        b2 = 0.0
        for c in range(3):
            dc = q[c] - centre[f, c]
            dq1 += dc * t1[c]
            dq2 += dc * t2[c]
            a1 += t1[c] * e1[f, c]
            b1 += t1[c] * e2[f, c]
            a2 += t2[c] * e1[f, c]
            b2 += t2[c] * e2[f, c]
        w1 = -2.0 * inv2s[f] * dq1 * w
        w2 = -2.0 * inv2s[f] * dq2 * w
        for c in range(3):
            p = C[f, c] + A[f, c] * a + B[f, c] * b
            acc[1 + c] += w * p
            acc[4 + c] += w1 * p + w * (A[f, c] * a1 + B[f, c] * b1)
            acc[7 + c] += w2 * p + w * (A[f, c] * a2 + B[f, c] * b2)
        acc[10] += w1
        acc[11] += w2
    return m


@njit(parallel=True, cache=True)
def _kernel(q, t1, t2, centre, inv2s, radius, origin, e1, e2, C, A, B, h, n, ptr, cells,
            log_g_ref, force_exact, deriv, P, P1, P2, status):
    n_faces = centre.shape[0]
    dummy = np.zeros(1, np.int64)
    for p in prange(q.shape[0]):
        acc = np.zeros(16)
        certified = False
        if not force_exact:
            ix = min(max(int(math.floor((q[p, 0] + 1.0) / h)), 0), n - 1)
            iy = min(max(int(math.floor((q[p, 1] + 1.0) / h)), 0), n - 1)
            iz = min(max(int(math.floor((q[p, 2] + 1.0) / h)), 0), n - 1)
            c = (iz * n + iy) * n + ix
            cand = cells[ptr[c]:ptr[c + 1]]
            m = _sum(q[p], t1[p], t2[p], cand, cand.shape[0], False, centre, inv2s, radius, origin, e1, e2,
                     C, A, B, deriv, acc)
            certified = m >= log_g_ref
        status[p] = TRUNCATED
        if not certified:
            _sum(q[p], t1[p], t2[p], dummy, n_faces, True, centre, inv2s, radius, origin, e1, e2, C, A, B, deriv, acc)
            status[p] = EXACT
        s = acc[0]
        for c in range(3):
            val = acc[1 + c] / s
            P[p, c] = val
            P1[p, c] = (acc[4 + c] - val * acc[10]) / s
            P2[p, c] = (acc[7 + c] - val * acc[11]) / s


def evaluate_sphere(q, t1, t2, faces, cells, *, log_g_ref, exact=False, derivatives=True):
    """Surface points and derivatives along ``t1``, ``t2`` at unit directions ``q`` (k, 3).

    ``faces`` is a tuple ``(centre, inv2s, radius, origin, e1, e2, C, A, B)``; ``cells``
    comes from :func:`build_cells_3d`. Returns ``P, P_t1, P_t2`` (k, 3) and a status per point; without
    ``derivatives`` the derivatives are not summed (about half the work) and come back as zeros.
    """
    q = np.ascontiguousarray(q, np.float64)
    k = len(q)
    P, P1, P2 = np.zeros((k, 3)), np.zeros((k, 3)), np.zeros((k, 3))
    status = np.zeros(k, np.int8)
    h, n, ptr, cf = cells
    _kernel(q, np.ascontiguousarray(t1, np.float64), np.ascontiguousarray(t2, np.float64), *faces,
            float(h), int(n), ptr, cf, float(log_g_ref), bool(exact), bool(derivatives), P, P1, P2, status)
    return P, P1, P2, status
