"""numba kernels of the weighted-mean surface on the sphere (octahedral domain).

A face i has a weight centre ``c_i`` (unit vector), a plane ``n_i . g = h_i`` through its vertices on
the sphere, a frame ``(o_i, e1_i, e2_i)`` in that plane and the affine map ``P_i = C_i + A_i a + B_i b``
of the frame coordinates. A direction ``q`` reaches the plane by orthogonal projection,
``a = (q - o_i) . e1_i``, ``b = (q - o_i) . e2_i``: the map of a face is its own plane's, extended over
the whole sphere as an affine function of ``q``, bounded everywhere (a central projection would blow up
for faces turned 90 degrees away, which carry weight on coarse meshes), and faces across the
octahedron's creases need no special case. Weights are ``exp(-|q - c_i|^2 / 2 sigma_i^2)``.

For each point the kernels return P and its derivatives along two tangent directions ``t1, t2``.
Faces are skipped outside ``|q - c_i| <= R_i``.

- Scattered points (:func:`evaluate_sphere`): candidates from 3-D cells; sums shifted by the largest
  exponent (no underflow); a point whose largest weight exponent is below ``log_g_ref`` is recomputed
  over all faces.
- Images (:func:`sample_sphere_grid`): tiles of pixels, each face adding its weights and planes to the
  running sums of the sub-tiles it reaches, in loops over their pixels with a vectorized exponential
  (:mod:`geoimg.surface._gaussian_fastexp`); plain sums, certified when ``S >= max(g_ref, 1e-250)`` (every
  skipped weight then below ``tol``, as on the plane: ``_fastexp.plain_sum_floor``), the others
  recomputed by the first kernel over all faces.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._cells import _cell_of
from ._gaussian_fastexp import exp_into, plain_sum_floor

__all__ = ["evaluate_sphere", "sample_sphere_grid", "TRUNCATED", "EXACT"]

TRUNCATED, EXACT = 0, 1
TILE = 16                   # pixels along a tile's side
SUB = 8                     # pixels along a sub-tile's side (a divisor of TILE)


@njit(cache=True)
def _sum(q, t1, t2, cand, n_cand, all_faces, centre, inv2s, radius, origin, e1, e2, C, A, B, deriv, acc):
    """Accumulate over candidate faces (the derivatives' sums only with ``deriv``); returns the largest
    exponent (-inf when no face is in range).
    """
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
            c = _cell_of(q[p, 0], q[p, 1], q[p, 2], h, n)
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


@njit(cache=True, inline="always")
def _bounding_ball(q, idx, lo, hi):
    """A ball holding the points ``q[idx[lo:hi]]``: their mean and its largest distance to them."""
    cx = cy = cz = 0.0
    for k in range(lo, hi):
        cx += q[idx[k], 0]
        cy += q[idx[k], 1]
        cz += q[idx[k], 2]
    m = hi - lo
    cx, cy, cz = cx / m, cy / m, cz / m
    rho = 0.0
    for k in range(lo, hi):
        p = idx[k]
        rho = max(rho, math.sqrt((q[p, 0] - cx) ** 2 + (q[p, 1] - cy) ** 2 + (q[p, 2] - cz) ** 2))
    return cx, cy, cz, rho


@njit(cache=True)
def _tile_candidates(q, idx, m, centre, radius, h, n, ptr, cells, seen, stamp):
    """The faces, in index order, whose truncation ball can reach a pixel of the tile (``q[idx[:m]]``):
    those listed in the pixels' cells and within ``R_f`` of the tile's bounding ball. ``seen`` (one entry
    per face) marks the faces taken with ``stamp``, a number no other tile of its caller uses.
    """
    ids = np.empty(m, np.int64)
    for k in range(m):
        ids[k] = _cell_of(q[idx[k], 0], q[idx[k], 1], q[idx[k], 2], h, n)
    cx, cy, cz, rho = _bounding_ball(q, idx, 0, m)
    cell_ids = np.unique(ids)
    total = 0
    for c in cell_ids:
        total += ptr[c + 1] - ptr[c]
    out = np.empty(total, np.int64)
    kept = 0
    for c in cell_ids:
        for k in range(ptr[c], ptr[c + 1]):
            f = cells[k]
            if seen[f] == stamp:
                continue
            seen[f] = stamp
            reach = radius[f] + rho
            if (centre[f, 0] - cx) ** 2 + (centre[f, 1] - cy) ** 2 + (centre[f, 2] - cz) ** 2 <= reach * reach:
                out[kept] = f
                kept += 1
    out = out[:kept]
    out.sort()
    return out


@njit(parallel=True, cache=True, fastmath={"contract"})
def _tiles_kernel(q, t1, t2, side, tile_side, sub_side, centre, inv2s, radius, origin, e1, e2, C, A, B, h, n,
                  ptr, cells, deriv, g_thr, P, P1, P2, ok):
    """Tiles of ``TILE x TILE`` pixels of an octahedral image (``q`` its directions, row by row) run in
    parallel. A tile's candidate faces come from its pixels' cells; each adds its weights and planes to
    the running sums of the sub-tiles (``SUB x SUB`` pixels, contiguous in the tile's arrays) its ball
    reaches, in loops over their pixels. Plain exponentials, no shift: a sum below ``g_thr`` is not
    certified.
    """
    TILE, SUB = tile_side, sub_side
    nt = -(-side // TILE)
    ns = TILE // SUB
    n_chunks = min(nt * nt, 64)
    for chunk in prange(n_chunks):
        seen = np.full(centre.shape[0], -1, np.int64)
        for tile in range(chunk, nt * nt, n_chunks):
            _tile(tile, nt, ns, TILE, SUB, q, t1, t2, side, centre, inv2s, radius, origin, e1, e2, C, A, B, h, n,
                  ptr, cells, deriv, g_thr, P, P1, P2, ok, seen)


@njit(cache=True, fastmath={"contract"})
def _tile(tile, nt, ns, TILE, SUB, q, t1, t2, side, centre, inv2s, radius, origin, e1, e2, C, A, B, h, n, ptr,
          cells, deriv, g_thr, P, P1, P2, ok, seen):
    """One tile of :func:`_tiles_kernel`."""
    i0 = (tile // nt) * TILE
    j0 = (tile % nt) * TILE
    idx = np.empty(TILE * TILE, np.int64)
    start = np.zeros(ns * ns + 1, np.int64)
    ball = np.zeros((ns * ns, 4))           # each sub-tile's bounding ball: centre, radius
    m = 0
    for si in range(ns):
        for sj in range(ns):
            sub = si * ns + sj
            for i in range(i0 + si * SUB, min(side, i0 + (si + 1) * SUB)):
                for j in range(j0 + sj * SUB, min(side, j0 + (sj + 1) * SUB)):
                    idx[m] = i * side + j
                    m += 1
            start[sub + 1] = m
            if m > start[sub]:
                ball[sub, 0], ball[sub, 1], ball[sub, 2], ball[sub, 3] = _bounding_ball(q, idx, start[sub], m)
    Q = np.empty((3, m))
    T1 = np.empty((3, m if deriv else 0))
    T2 = np.empty((3, m if deriv else 0))
    for k in range(m):
        for c in range(3):
            Q[c, k] = q[idx[k], c]
            if deriv:
                T1[c, k] = t1[idx[k], c]
                T2[c, k] = t2[idx[k], c]
    acc = np.zeros((12 if deriv else 4, m))
    x = np.empty(m)
    w = np.empty(m)
    bits = np.empty(m, np.int64)
    for f in _tile_candidates(q, idx, m, centre, radius, h, n, ptr, cells, seen, tile):
        r2 = radius[f] * radius[f]
        a = inv2s[f]
        fx, fy, fz = centre[f, 0], centre[f, 1], centre[f, 2]
        for sub in range(ns * ns):
            lo, hi = start[sub], start[sub + 1]
            reach = radius[f] + ball[sub, 3]
            gap2 = (fx - ball[sub, 0]) ** 2 + (fy - ball[sub, 1]) ** 2 + (fz - ball[sub, 2]) ** 2
            if hi == lo or gap2 > reach * reach:
                continue
            qx, qy, qz = Q[0, lo:hi], Q[1, lo:hi], Q[2, lo:hi]
            wk = w[lo:hi]
            _weights(qx, qy, qz, fx, fy, fz, a, r2, x[lo:hi], wk, bits[lo:hi])
            _add_planes(f, qx, qy, qz, wk, origin, e1, e2, C, A, B,
                        acc[0, lo:hi], acc[1, lo:hi], acc[2, lo:hi], acc[3, lo:hi])
            if deriv:
                _add_slopes(f, qx, qy, qz, T1[0, lo:hi], T1[1, lo:hi], T1[2, lo:hi], T2[0, lo:hi],
                            T2[1, lo:hi], T2[2, lo:hi], wk, centre, a, origin, e1, e2, C, A, B,
                            acc[4, lo:hi], acc[5, lo:hi], acc[6, lo:hi], acc[7, lo:hi], acc[8, lo:hi],
                            acc[9, lo:hi], acc[10, lo:hi], acc[11, lo:hi])
    for k in range(m):
        p = idx[k]
        s = acc[0, k]
        ok[p] = s >= g_thr
        if not ok[p]:
            continue
        for c in range(3):
            val = acc[1 + c, k] / s
            P[p, c] = val
            if deriv:
                P1[p, c] = (acc[4 + c, k] - val * acc[10, k]) / s
                P2[p, c] = (acc[7 + c, k] - val * acc[11, k]) / s


@njit(cache=True, inline="always")
def _weights(qx, qy, qz, fx, fy, fz, a, r2, x, w, bits):
    """``w = exp(-a |q - c|^2)`` where ``|q - c|^2 <= r2``, else 0, for pixels ``(qx, qy, qz)``."""
    for k in range(qx.shape[0]):
        d2 = (qx[k] - fx) ** 2 + (qy[k] - fy) ** 2 + (qz[k] - fz) ** 2
        x[k] = -d2 * a if d2 <= r2 else -np.inf
    exp_into(x, w, bits)


@njit(cache=True, inline="always")
def _face(f, origin, e1, e2, C, A, B):
    """Face ``f``'s frame ``(o, e1, e2)`` and map ``(C, A, B)`` as 18 numbers, for the loops below."""
    return (origin[f, 0], origin[f, 1], origin[f, 2], e1[f, 0], e1[f, 1], e1[f, 2], e2[f, 0], e2[f, 1], e2[f, 2],
            C[f, 0], C[f, 1], C[f, 2], A[f, 0], A[f, 1], A[f, 2], B[f, 0], B[f, 1], B[f, 2])


@njit(cache=True, inline="always")
def _add_planes(f, qx, qy, qz, w, origin, e1, e2, C, A, B, s0, n0, n1, n2):
    """Adds ``w`` and ``w P_f(q)`` to the running sums ``s0``, ``n0..n2`` of pixels ``(qx, qy, qz)``."""
    ox, oy, oz, e1x, e1y, e1z, e2x, e2y, e2z, cx, cy, cz, ax, ay, az, bx, by, bz = _face(f, origin, e1, e2, C, A, B)
    for k in range(qx.shape[0]):
        gx, gy, gz = qx[k] - ox, qy[k] - oy, qz[k] - oz
        pa = gx * e1x + gy * e1y + gz * e1z
        pb = gx * e2x + gy * e2y + gz * e2z
        wk = w[k]
        s0[k] += wk
        n0[k] += wk * (cx + ax * pa + bx * pb)
        n1[k] += wk * (cy + ay * pa + by * pb)
        n2[k] += wk * (cz + az * pa + bz * pb)


@njit(cache=True, inline="always")
def _add_slopes(f, qx, qy, qz, t1x_, t1y_, t1z_, t2x_, t2y_, t2z_, w, centre, a, origin, e1, e2, C, A, B,
                u0, u1, u2, v0, v1, v2, su, sv):
    """Adds the derivatives' sums along the pixels' tangents ``t1``, ``t2``: the weight's derivative times
    the plane plus the weight times the plane's slope (``u*``, ``v*``), and the weight's (``su``, ``sv``).
    """
    ox, oy, oz, e1x, e1y, e1z, e2x, e2y, e2z, cx, cy, cz, ax, ay, az, bx, by, bz = _face(f, origin, e1, e2, C, A, B)
    fx, fy, fz = centre[f, 0], centre[f, 1], centre[f, 2]
    k2 = -2.0 * a
    for k in range(qx.shape[0]):
        gx, gy, gz = qx[k] - ox, qy[k] - oy, qz[k] - oz
        pa = gx * e1x + gy * e1y + gz * e1z
        pb = gx * e2x + gy * e2y + gz * e2z
        px, py, pz = cx + ax * pa + bx * pb, cy + ay * pa + by * pb, cz + az * pa + bz * pb
        dx, dy, dz = qx[k] - fx, qy[k] - fy, qz[k] - fz
        t1x, t1y, t1z = t1x_[k], t1y_[k], t1z_[k]
        t2x, t2y, t2z = t2x_[k], t2y_[k], t2z_[k]
        wk = w[k]
        w1 = k2 * (dx * t1x + dy * t1y + dz * t1z) * wk
        w2 = k2 * (dx * t2x + dy * t2y + dz * t2z) * wk
        a1 = t1x * e1x + t1y * e1y + t1z * e1z
        b1 = t1x * e2x + t1y * e2y + t1z * e2z
        a2 = t2x * e1x + t2y * e1y + t2z * e1z
        b2 = t2x * e2x + t2y * e2y + t2z * e2z
        u0[k] += w1 * px + wk * (ax * a1 + bx * b1)
        u1[k] += w1 * py + wk * (ay * a1 + by * b1)
        u2[k] += w1 * pz + wk * (az * a1 + bz * b1)
        v0[k] += w2 * px + wk * (ax * a2 + bx * b2)
        v1[k] += w2 * py + wk * (ay * a2 + by * b2)
        v2[k] += w2 * pz + wk * (az * a2 + bz * b2)
        su[k] += w1
        sv[k] += w2


def sample_sphere_grid(q, t1, t2, faces, cells, *, log_g_ref, derivatives=True, tile=None):
    """The surface over a square octahedral image whose pixels have directions ``q`` (side * side, 3),
    row by row, with tangent frames ``t1``, ``t2`` (used only with ``derivatives``); by tiles of
    ``tile = (TILE, SUB)`` pixels (see :func:`_tiles_kernel`). Pixels whose truncated sum is not certified
    are recomputed over all faces in the log domain (:func:`evaluate_sphere`). Returns ``P, P_t1, P_t2``
    (k, 3) and a status per pixel, as :func:`evaluate_sphere` does.
    """
    q = np.ascontiguousarray(q, np.float64)
    k = len(q)
    if not derivatives:
        t1 = t2 = np.zeros((k, 3))
    t1 = np.ascontiguousarray(t1, np.float64)
    t2 = np.ascontiguousarray(t2, np.float64)
    side = int(round(math.sqrt(k)))
    P, P1, P2 = np.zeros((k, 3)), np.zeros((k, 3)), np.zeros((k, 3))
    ok = np.zeros(k, np.bool_)
    h, n, ptr, cf = cells
    tile_side, sub_side = (TILE, SUB) if tile is None else tile
    _tiles_kernel(q, t1, t2, side, tile_side, sub_side, *faces, float(h), int(n), ptr, cf, bool(derivatives),
                  plain_sum_floor(log_g_ref), P, P1, P2, ok)
    status = np.full(k, TRUNCATED, np.int8)
    if not ok.all():
        redo = np.flatnonzero(~ok)
        P[redo], P1[redo], P2[redo], _ = evaluate_sphere(q[redo], t1[redo], t2[redo], faces, cells,
                                                        log_g_ref=log_g_ref, exact=True, derivatives=derivatives)
        status[redo] = EXACT
    return P, P1, P2, status
