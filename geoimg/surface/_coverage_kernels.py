"""numba kernels of the coverage-weighted surface (see :mod:`geoimg.surface._coverage`).

Every triangle ``t`` is given in homogeneous point coordinates ``p`` (``(u, v, 1)`` on the plane, a unit
direction ``q`` on the sphere): its barycentric coordinates are ``M_t^-1 p`` (divided by their sum on the
sphere: the central projection onto its chord plane), so

- its edge functions ``z_k = E_tk . p`` are signed distances to its three edges (to their great circles, as
  sines, on the sphere) in units of the triangle's own width (the rows come divided by it), positive inside;
- its map ``P_t(p) = K_t p / (w_t . p)`` interpolates its corners' positions (affine on the plane, where
  ``w_t . p = 1``);
- its weight ``F_t = Phi(z_0) Phi(z_1) Phi(z_2)`` (``Phi`` the normal distribution function) is the
  Gaussian-blurred indicator of the triangle, as a product over its edges: 1 deep inside, 1/2 on an edge,
  1/4 near a corner, falling like a Gaussian outside. Two triangles sharing an edge have weights
  ``Phi(z)`` and ``Phi(-z)``, which add to 1.

``P = sum F_t P_t / sum F_t``. A triangle is skipped where one of its edge functions is below ``zmin``
(its weight then below ``Phi(zmin)``, the tolerance). A point whose sum of weights is below ``floor`` lies
outside the triangles (beyond a planar mesh's border) and is recomputed in the log domain over the
triangles ``fallback`` lists (the border's), shifted by the largest log-weight so that nothing
underflows: status ``EXACT``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._kernels import grid_bands
from ._sphere_kernels import _cell_of

__all__ = ["evaluate_coverage", "sample_grid_coverage", "offset_boxes", "log_ndtr", "TRUNCATED", "EXACT"]

TRUNCATED, EXACT = 0, 1
WMIN = 0.5          # w . p at or below it: the triangle is skipped (see _add)
_SQRT1_2 = 1.0 / math.sqrt(2.0)
_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


@njit(cache=True)
def log_ndtr(z):
    """``log Phi(z)``, without underflow: ``erfc`` down to z = -37, then the asymptotic series."""
    if z > -37.0:
        return math.log(0.5 * math.erfc(-z * _SQRT1_2))
    r = 1.0 / (z * z)
    return -0.5 * z * z - math.log(-z) - _LOG_SQRT_2PI + math.log1p(r * (-1.0 + r * (3.0 - 15.0 * r)))


TABLE_LO, TABLE_STEP, TABLE_SIZE = -8.0, 1.0 / 512, 8193      # Phi and phi at -8, ..., +8


def _table() -> np.ndarray:
    z = TABLE_LO + TABLE_STEP * np.arange(TABLE_SIZE)
    cdf = np.array([0.5 * math.erfc(-x * _SQRT1_2) for x in z])
    return np.ascontiguousarray(np.stack([cdf, np.exp(-0.5 * z * z - _LOG_SQRT_2PI)], axis=1))


TABLE = _table()


@njit(cache=True, inline="always")
def _edge(z, zmax, deriv, table):
    """``Phi(z)`` and ``(dPhi/dz / Phi)(z)`` (0 unless ``deriv``); 1 and 0 from ``zmax`` on. Cubic Hermite
    interpolation of ``Phi`` between the table's knots (values and slopes ``phi`` there: within 1e-13 of
    ``Phi``), and the derivative of that interpolant, so that the surface's derivatives are exactly those of
    the surface evaluated (an erfc per edge cost 10 times as much).
    """
    if z >= zmax:
        return 1.0, 0.0
    x = (z - TABLE_LO) / TABLE_STEP
    if x < 0.0:
        x = 0.0
    i = min(int(x), TABLE_SIZE - 2)
    t = x - i
    t2 = t * t
    t3 = t2 * t
    f0, d0 = table[i, 0], table[i, 1] * TABLE_STEP
    f1, d1 = table[i + 1, 0], table[i + 1, 1] * TABLE_STEP
    cdf = (2.0 * t3 - 3.0 * t2 + 1.0) * f0 + (t3 - 2.0 * t2 + t) * d0 + (3.0 * t2 - 2.0 * t3) * f1 + (t3 - t2) * d1
    if not deriv:
        return cdf, 0.0
    slope = ((6.0 * t2 - 6.0 * t) * f0 + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (6.0 * t - 6.0 * t2) * f1
             + (3.0 * t2 - 2.0 * t) * d1) / TABLE_STEP
    return cdf, slope / cdf


@njit(cache=True, inline="always")
def _log_edge(z):
    """``log Phi(z)`` and ``(phi / Phi)(z)``, stable far outside."""
    lc = log_ndtr(z)
    return lc, math.exp(-0.5 * z * z - _LOG_SQRT_2PI - lc)


@njit(cache=True, inline="always")
def _add(t, p, t1, t2, E, K, w, zmin, zmax, deriv, shift, log_domain, wmin, table, acc):
    """Add triangle ``t``'s terms at ``p`` into ``acc`` (``S, N[3], S_1, N_1[3], S_2, N_2[3]``); in the log
    domain its weight is ``exp(log F - shift)``. Returns False when it is skipped: an edge function below
    ``zmin``, or a direction far from the triangle (``w . p <= wmin``, ``w`` scaled to 1 at its lowest
    corner: the central projection grows without bound towards ``w . p = 0``).
    """
    z0 = (E[t, 0, 0] * p[0] + E[t, 0, 1] * p[1] + E[t, 0, 2] * p[2])
    if not log_domain and z0 < zmin:
        return False
    z1 = (E[t, 1, 0] * p[0] + E[t, 1, 1] * p[1] + E[t, 1, 2] * p[2])
    if not log_domain and z1 < zmin:
        return False
    z2 = (E[t, 2, 0] * p[0] + E[t, 2, 1] * p[1] + E[t, 2, 2] * p[2])
    if not log_domain and z2 < zmin:
        return False
    wp = w[t, 0] * p[0] + w[t, 1] * p[1] + w[t, 2] * p[2]
    if not wp > wmin:
        return False
    if log_domain:
        c0, r0 = _log_edge(z0)
        c1, r1 = _log_edge(z1)
        c2, r2 = _log_edge(z2)
        F = math.exp(c0 + c1 + c2 - shift)
    else:
        c0, r0 = _edge(z0, zmax, deriv, table)
        c1, r1 = _edge(z1, zmax, deriv, table)
        c2, r2 = _edge(z2, zmax, deriv, table)
        F = c0 * c1 * c2
    if F == 0.0:                # nothing to add; a near-degenerate triangle's map may be huge there (0 * inf)
        return True
    inv_wp = 1.0 / wp
    P0 = (K[t, 0, 0] * p[0] + K[t, 0, 1] * p[1] + K[t, 0, 2] * p[2]) * inv_wp
    P1 = (K[t, 1, 0] * p[0] + K[t, 1, 1] * p[1] + K[t, 1, 2] * p[2]) * inv_wp
    P2 = (K[t, 2, 0] * p[0] + K[t, 2, 1] * p[1] + K[t, 2, 2] * p[2]) * inv_wp
    acc[0] += F
    acc[1] += F * P0
    acc[2] += F * P1
    acc[3] += F * P2
    if not deriv:
        return True
    for a in range(2):
        tau = t1 if a == 0 else t2
        g = (r0 * (E[t, 0, 0] * tau[0] + E[t, 0, 1] * tau[1] + E[t, 0, 2] * tau[2])
             + r1 * (E[t, 1, 0] * tau[0] + E[t, 1, 1] * tau[1] + E[t, 1, 2] * tau[2])
             + r2 * (E[t, 2, 0] * tau[0] + E[t, 2, 1] * tau[1] + E[t, 2, 2] * tau[2]))
        dF = F * g
        wt = w[t, 0] * tau[0] + w[t, 1] * tau[1] + w[t, 2] * tau[2]
        d0 = ((K[t, 0, 0] * tau[0] + K[t, 0, 1] * tau[1] + K[t, 0, 2] * tau[2]) - P0 * wt) * inv_wp
        d1 = ((K[t, 1, 0] * tau[0] + K[t, 1, 1] * tau[1] + K[t, 1, 2] * tau[2]) - P1 * wt) * inv_wp
        d2 = ((K[t, 2, 0] * tau[0] + K[t, 2, 1] * tau[1] + K[t, 2, 2] * tau[2]) - P2 * wt) * inv_wp
        o = 4 + 4 * a
        acc[o] += dF
        acc[o + 1] += dF * P0 + F * d0
        acc[o + 2] += dF * P1 + F * d1
        acc[o + 3] += dF * P2 + F * d2
    return True


@njit(cache=True)
def _largest_log_weight(p, cand, E, w, wmin):
    m = -np.inf
    for k in range(cand.shape[0]):
        t = cand[k]
        wp = w[t, 0] * p[0] + w[t, 1] * p[1] + w[t, 2] * p[2]
        if not wp > wmin:
            continue
        lf = 0.0
        for e in range(3):
            lf += log_ndtr(E[t, e, 0] * p[0] + E[t, e, 1] * p[1] + E[t, e, 2] * p[2])
        if lf > m:
            m = lf
    return m


@njit(cache=True)
def _finish(i, p, t1, t2, E, K, w, zmin, zmax, floor, fallback, deriv, force_exact, table, acc, P, D1, D2, status):
    """Point ``i``'s values from its truncated sums ``acc``, or, where those are below ``floor`` (or with
    ``force_exact``), from the exact sum over ``fallback`` in the log domain.
    """
    status[i] = TRUNCATED
    if force_exact or not acc[0] >= floor:
        for q in range(12):
            acc[q] = 0.0
        wmin = WMIN
        m = _largest_log_weight(p, fallback, E, w, wmin)
        if m == -np.inf:            # no triangle near: any in front (a coarse mesh's far side)
            wmin = 0.0
            m = _largest_log_weight(p, fallback, E, w, wmin)
        for k in range(fallback.shape[0]):
            _add(fallback[k], p, t1, t2, E, K, w, zmin, zmax, deriv, m, True, wmin, table, acc)
        status[i] = EXACT
    s = acc[0]
    for c in range(3):
        val = acc[1 + c] / s
        P[i, c] = val
        D1[i, c] = (acc[5 + c] - val * acc[4]) / s
        D2[i, c] = (acc[9 + c] - val * acc[8]) / s


@njit(parallel=True, cache=True)
def _kernel(pts, t1, t2, E, K, w, zmin, zmax, floor, order, group_ptr, group_cell, ptr, cells, fallback, deriv,
            force_exact, table, P, D1, D2, status):
    """The points cell by cell (``order[group_ptr[g]:group_ptr[g + 1]]`` are the points in cell
    ``group_cell[g]``): each of the cell's triangles is read once for all its points, and every point sums
    its triangles in the cell's order, as it would alone.
    """
    for g in prange(group_cell.shape[0]):
        members = order[group_ptr[g]:group_ptr[g + 1]]
        m = members.shape[0]
        acc = np.zeros((m, 12))
        here = np.empty((m, 3))                 # the cell's points side by side
        for j in range(m):
            for a in range(3):
                here[j, a] = pts[members[j], a]
        c = group_cell[g]
        if not force_exact:
            for k in range(ptr[c], ptr[c + 1]):
                t = cells[k]
                # the edge tests of _add, with the triangle's rows held in registers: most candidates end here
                e00, e01, e02 = E[t, 0, 0], E[t, 0, 1], E[t, 0, 2]
                e10, e11, e12 = E[t, 1, 0], E[t, 1, 1], E[t, 1, 2]
                e20, e21, e22 = E[t, 2, 0], E[t, 2, 1], E[t, 2, 2]
                for j in range(m):
                    p0, p1, p2 = here[j, 0], here[j, 1], here[j, 2]
                    if (e00 * p0 + e01 * p1 + e02 * p2) < zmin or (e10 * p0 + e11 * p1 + e12 * p2) < zmin \
                            or (e20 * p0 + e21 * p1 + e22 * p2) < zmin:
                        continue
                    i = members[j]
                    _add(t, pts[i], t1[i], t2[i], E, K, w, zmin, zmax, deriv, 0.0, False, WMIN, table, acc[j])
        for j in range(members.shape[0]):
            i = members[j]
            _finish(i, pts[i], t1[i], t2[i], E, K, w, zmin, zmax, floor, fallback, deriv, force_exact, table,
                    acc[j], P, D1, D2, status)


@njit(cache=True)
def _cells_of(pts, h, n):
    out = np.empty(pts.shape[0], np.int64)
    for i in range(pts.shape[0]):
        out[i] = _cell_of(pts[i, 0], pts[i, 1], pts[i, 2], h, n)
    return out


def evaluate_coverage(pts, t1, t2, tables, cells, fallback, *, zmin, floor, derivatives=True, exact=False):
    """The coverage-weighted surface and its derivatives along ``t1, t2`` at points ``pts`` (k, 3) given in
    homogeneous coordinates (see the module's text). ``tables`` is ``(E, K, w)``: (T, 3, 3) edge rows over
    each triangle's width, (T, 3, 3) maps and (T, 3) denominators; ``cells`` from
    :func:`~._sphere_kernels.build_cells_3d` over the triangles' reach; ``fallback`` the triangles a point outside
    them is summed over (all of them with
    ``exact``). Returns ``P, P_t1, P_t2`` (k, 3) and a status per point.
    """
    pts = np.ascontiguousarray(pts, np.float64)
    k = len(pts)
    t1 = np.ascontiguousarray(t1, np.float64)
    t2 = np.ascontiguousarray(t2, np.float64)
    P, D1, D2 = np.empty((k, 3)), np.empty((k, 3)), np.empty((k, 3))
    status = np.empty(k, np.int8)
    E, K, w = tables
    h, n, ptr, cf = cells
    cell = _cells_of(pts, float(h), int(n))
    order = np.argsort(cell, kind="stable").astype(np.int64)       # the points grouped by cell
    group_cell, group_start = np.unique(cell[order], return_index=True)
    group_ptr = np.append(group_start, len(order)).astype(np.int64)
    _kernel(pts, t1, t2, E, K, w, float(zmin), float(-zmin), float(floor), order, group_ptr,
            group_cell.astype(np.int64), ptr, cf, np.ascontiguousarray(fallback, np.int64), bool(derivatives),
            bool(exact), TABLE, P, D1, D2, status)
    return P, D1, D2, status


@njit(parallel=True, cache=True)
def _grid_kernel(u, v, E, K, w, c0, c1, r0, r1, band, band_ptr, band_faces, zmin, zmax, floor, deriv, table,
                 P, Pu, Pv, ok):
    """Planar grids, triangle by triangle: bands of ``band`` rows run in parallel; every triangle a band lists
    adds its terms over the pixels of its box (where its weight can reach ``Phi(zmin)``) to the band's
    running sums. Pixels whose sum is below ``floor`` are left to the points kernel (``ok`` False).
    """
    H, W = v.shape[0], u.shape[0]
    for b in prange(band_ptr.shape[0] - 1):
        i0 = b * band
        i1 = min(H, i0 + band)
        acc = np.zeros((band, W, 12))          # a pixel's sums side by side
        p = np.empty(3)
        p[2] = 1.0
        for q in range(band_ptr[b], band_ptr[b + 1]):
            t = band_faces[q]
            for i in range(max(r0[t], i0), min(r1[t], i1)):
                r = i - i0
                p[1] = v[i]
                for j in range(c0[t], c1[t]):
                    p[0] = u[j]
                    z0 = E[t, 0, 0] * p[0] + E[t, 0, 1] * p[1] + E[t, 0, 2]
                    if z0 < zmin:
                        continue
                    z1 = E[t, 1, 0] * p[0] + E[t, 1, 1] * p[1] + E[t, 1, 2]
                    if z1 < zmin:
                        continue
                    z2 = E[t, 2, 0] * p[0] + E[t, 2, 1] * p[1] + E[t, 2, 2]
                    if z2 < zmin:
                        continue
                    c_0, g0 = _edge(z0, zmax, deriv, table)
                    c_1, g1 = _edge(z1, zmax, deriv, table)
                    c_2, g2 = _edge(z2, zmax, deriv, table)
                    F = c_0 * c_1 * c_2
                    if F == 0.0:
                        continue
                    inv_wp = 1.0 / (w[t, 0] * p[0] + w[t, 1] * p[1] + w[t, 2])
                    X = (K[t, 0, 0] * p[0] + K[t, 0, 1] * p[1] + K[t, 0, 2]) * inv_wp
                    Y = (K[t, 1, 0] * p[0] + K[t, 1, 1] * p[1] + K[t, 1, 2]) * inv_wp
                    Z = (K[t, 2, 0] * p[0] + K[t, 2, 1] * p[1] + K[t, 2, 2]) * inv_wp
                    acc[r, j, 0] += F
                    acc[r, j, 1] += F * X
                    acc[r, j, 2] += F * Y
                    acc[r, j, 3] += F * Z
                    if deriv:
                        for a in range(2):
                            dF = F * (g0 * E[t, 0, a] + g1 * E[t, 1, a] + g2 * E[t, 2, a])
                            wt = w[t, a]
                            o = 4 + 4 * a
                            acc[r, j, o] += dF
                            acc[r, j, o + 1] += dF * X + F * (K[t, 0, a] - X * wt) * inv_wp
                            acc[r, j, o + 2] += dF * Y + F * (K[t, 1, a] - Y * wt) * inv_wp
                            acc[r, j, o + 3] += dF * Z + F * (K[t, 2, a] - Z * wt) * inv_wp
        for i in range(i0, i1):
            r = i - i0
            for j in range(W):
                s = acc[r, j, 0]
                ok[i, j] = s >= floor
                if not ok[i, j]:
                    continue
                for c in range(3):
                    val = acc[r, j, 1 + c] / s
                    P[i, j, c] = val
                    if deriv:
                        Pu[i, j, c] = (acc[r, j, 5 + c] - val * acc[r, j, 4]) / s
                        Pv[i, j, c] = (acc[r, j, 9 + c] - val * acc[r, j, 8]) / s


def offset_boxes(E, zmin):
    """The bounding box ``(umin, umax, vmin, vmax)`` of each planar triangle's region where all its edge
    functions are at least ``zmin`` (the triangle grown by ``-zmin`` widths: its corners meet where two
    grown edges do).
    """
    T = E.shape[0]
    corners = np.empty((T, 3, 2))
    for k in range(3):                  # Cramer's rule on E_a . (x, y, 1) = E_b . (x, y, 1) = zmin
        a, b = (k + 1) % 3, (k + 2) % 3
        ra, rb = zmin - E[:, a, 2], zmin - E[:, b, 2]
        det = E[:, a, 0] * E[:, b, 1] - E[:, a, 1] * E[:, b, 0]
        corners[:, k, 0] = (ra * E[:, b, 1] - rb * E[:, a, 1]) / det
        corners[:, k, 1] = (E[:, a, 0] * rb - E[:, b, 0] * ra) / det
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    return lo[:, 0], hi[:, 0], lo[:, 1], hi[:, 1]


def sample_grid_coverage(u, v, tables, *, zmin, floor, derivatives=True):
    """The coverage-weighted surface on the planar grid ``u`` (columns) x ``v`` (rows), triangle by triangle
    over each one's box (see :func:`_grid_kernel`). ``tables`` are ``(E, K, w)`` with ``E`` divided by each
    triangle's width. Returns ``P, Pu, Pv`` (H, W, 3) and ``ok`` (H, W): pixels whose sum is certified (the
    others are left unwritten: the points kernel's to fill).
    """
    E, K, w = tables
    u = np.ascontiguousarray(u, np.float64)
    v = np.ascontiguousarray(v, np.float64)
    umin, umax, vmin, vmax = offset_boxes(E, zmin)
    c0 = np.searchsorted(u, umin, "left").astype(np.int64)
    c1 = np.searchsorted(u, umax, "right").astype(np.int64)
    r0 = np.searchsorted(v, vmin, "left").astype(np.int64)
    r1 = np.searchsorted(v, vmax, "right").astype(np.int64)
    live = np.flatnonzero((c1 > c0) & (r1 > r0)).astype(np.int64)
    band, band_ptr, band_faces, P, Pu, Pv, ok = grid_bands(u, v, live, r0, r1, derivatives)
    _grid_kernel(u, v, E, K, w, c0, c1, r0, r1, band, band_ptr, band_faces, float(zmin), float(-zmin), float(floor),
                 bool(derivatives), TABLE, P, Pu, Pv, ok)
    return P, (Pu if derivatives else None), (Pv if derivatives else None), ok
