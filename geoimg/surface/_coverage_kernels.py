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

Three ways to sum: scattered points cell by cell (:func:`evaluate_coverage`), planar grids triangle by
triangle over each one's box (:func:`sample_grid_coverage`), and octahedral grids triangle by triangle over
each octant's share of its reach (:func:`sample_octahedral_coverage`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._cells import _cell_of
from ._grid import _band_lists, _band_rows, grid_bands

__all__ = ["evaluate_coverage", "sample_grid_coverage", "sample_octahedral_coverage", "octant_owners", "offset_boxes",
           "log_ndtr", "TRUNCATED", "EXACT"]

TRUNCATED, EXACT = 0, 1
WMIN = 0.5          # w . p at or below it: the triangle is skipped (see _add)
UNDERFLOW_LOG = -800.0  # a log-domain term bounded this far below the largest: exp() gives exactly 0 (below -745.2)
EXACT_RUN = 16      # points summed exactly without cells go in runs of this many (the parallel loop's items)
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
    """The cubic Hermite interpolant of ``Phi`` between neighbouring knots (values and slopes ``phi`` there),
    as the coefficients ``c0..c3`` of ``c0 + c1 t + c2 t^2 + c3 t^3`` on each interval (t from 0 to 1).
    """
    z = TABLE_LO + TABLE_STEP * np.arange(TABLE_SIZE)
    f = np.array([0.5 * math.erfc(-x * _SQRT1_2) for x in z])
    d = np.exp(-0.5 * z * z - _LOG_SQRT_2PI) * TABLE_STEP
    f0, f1, d0, d1 = f[:-1], f[1:], d[:-1], d[1:]
    return np.ascontiguousarray(np.stack([f0, d0, 3.0 * (f1 - f0) - 2.0 * d0 - d1, 2.0 * (f0 - f1) + d0 + d1], axis=1))


TABLE = _table()


@njit(cache=True, inline="always")
def _edge(z, zmax, deriv, table):
    """``Phi(z)`` and ``(dPhi/dz / Phi)(z)`` (0 unless ``deriv``); 1 and 0 from ``zmax`` on. Cubic Hermite
    interpolation of ``Phi`` between the table's knots (values and slopes ``phi`` there: within 1e-13 of
    ``Phi``), by Horner's rule on each interval's coefficients, and the derivative of that interpolant, so
    that the surface's derivatives are exactly those of the surface evaluated (an erfc per edge cost 10 times
    as much).
    """
    if z >= zmax:
        return 1.0, 0.0
    x = (z - TABLE_LO) / TABLE_STEP
    if x < 0.0:
        x = 0.0
    i = min(int(x), TABLE_SIZE - 2)
    t = x - i
    c0, c1, c2, c3 = table[i, 0], table[i, 1], table[i, 2], table[i, 3]
    cdf = c0 + t * (c1 + t * (c2 + t * c3))
    if not deriv:
        return cdf, 0.0
    slope = (c1 + t * (2.0 * c2 + 3.0 * t * c3)) / TABLE_STEP
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
    return _add_terms(t, z0, z1, z2, p[0], p[1], p[2], t1, t2, E, K, w, zmax, deriv, shift, log_domain, wmin, table,
                      acc)


@njit(cache=True, inline="always")
def _term(t, z0, z1, z2, p0, p1, p2, K, w, zmax, deriv, shift, log_domain, wmin, table):
    """Triangle ``t``'s weight and point at ``(p0, p1, p2)`` from its edge functions ``z0, z1, z2``:
    ``(kind, F, r0, r1, r2, P0, P1, P2, 1 / (w . p))``, ``r_k`` the edges' ``dPhi/dz / Phi`` (with ``deriv``);
    ``kind`` 0 where it is skipped (``w . p <= wmin``), 1 where its weight is 0, 2 for a term.
    """
    wp = w[t, 0] * p0 + w[t, 1] * p1 + w[t, 2] * p2
    if not wp > wmin:
        return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
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
        return 1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv_wp = 1.0 / wp
    P0 = (K[t, 0, 0] * p0 + K[t, 0, 1] * p1 + K[t, 0, 2] * p2) * inv_wp
    P1 = (K[t, 1, 0] * p0 + K[t, 1, 1] * p1 + K[t, 1, 2] * p2) * inv_wp
    P2 = (K[t, 2, 0] * p0 + K[t, 2, 1] * p1 + K[t, 2, 2] * p2) * inv_wp
    return 2, F, r0, r1, r2, P0, P1, P2, inv_wp


@njit(cache=True, inline="always")
def _add_terms(t, z0, z1, z2, p0, p1, p2, t1, t2, E, K, w, zmax, deriv, shift, log_domain, wmin, table, acc):
    """The part of :func:`_add` after the edge tests: ``z0, z1, z2`` the edge functions at ``(p0, p1, p2)``."""
    kind, F, r0, r1, r2, P0, P1, P2, inv_wp = _term(t, z0, z1, z2, p0, p1, p2, K, w, zmax, deriv, shift, log_domain,
                                                    wmin, table)
    if kind < 2:
        return kind == 1
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


@njit(cache=True, inline="always")
def _log_weight_bound(t, p, E):
    """An upper bound on triangle ``t``'s log weight at ``p`` (the sum of its edges' ``log Phi(z)``), from its
    lowest edge function alone: ``log Phi(z) <= -z^2 / 2 - log 2`` for ``z <= 0`` (``erfc(x) <= exp(-x^2)``),
    three dot products where the weight itself takes three ``log_ndtr``.
    """
    z = min(E[t, 0, 0] * p[0] + E[t, 0, 1] * p[1] + E[t, 0, 2] * p[2],
            E[t, 1, 0] * p[0] + E[t, 1, 1] * p[1] + E[t, 1, 2] * p[2],
            E[t, 2, 0] * p[0] + E[t, 2, 1] * p[1] + E[t, 2, 2] * p[2])
    return -0.5 * z * z if z < 0.0 else 0.0


@njit(cache=True)
def _largest_log_weight(p, cand, E, w, wmin):
    m = -np.inf
    for k in range(cand.shape[0]):
        t = cand[k]
        if _log_weight_bound(t, p, E) <= m:         # cannot be the largest: the same m, sooner
            continue
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
            if _log_weight_bound(fallback[k], p, E) - m < UNDERFLOW_LOG:    # its exp() would be 0: adds nothing
                continue
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
    :func:`~._gaussian_sphere_kernels.build_cells_3d` over the triangles' reach (None with ``exact``: every point is
    summed over ``fallback`` alone, in runs of :data:`EXACT_RUN`); ``fallback`` the triangles a point outside
    them is summed over (all of them with ``exact``). Returns ``P, P_t1, P_t2`` (k, 3) and a status per point.
    """
    pts = np.ascontiguousarray(pts, np.float64)
    k = len(pts)
    t1 = np.ascontiguousarray(t1, np.float64)
    t2 = np.ascontiguousarray(t2, np.float64)
    P, D1, D2 = np.empty((k, 3)), np.empty((k, 3)), np.empty((k, 3))
    status = np.empty(k, np.int8)
    E, K, w = tables
    if cells is None:
        if not exact:
            raise ValueError("evaluate_coverage: cells are needed unless exact")
        cells = (2.0, 1, np.zeros(2, np.int64), np.zeros(0, np.int64))
        cell = np.arange(k, dtype=np.int64) // EXACT_RUN
    else:
        cell = _cells_of(pts, float(cells[0]), int(cells[1]))
    h, n, ptr, cf = cells
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


@njit(parallel=True, cache=True)
def offset_boxes(E, zmin):
    """The bounding box ``(umin, umax, vmin, vmax)`` of each planar triangle's region where all its edge
    functions are at least ``zmin`` (the triangle grown by ``-zmin`` widths: its corners meet where two
    grown edges do, by Cramer's rule on ``E_a . (x, y, 1) = E_b . (x, y, 1) = zmin``).
    """
    T = E.shape[0]
    umin, umax, vmin, vmax = np.empty(T), np.empty(T), np.empty(T), np.empty(T)
    for t in prange(T):
        ulo, uhi, vlo, vhi = np.inf, -np.inf, np.inf, -np.inf
        for k in range(3):
            a, b = (k + 1) % 3, (k + 2) % 3
            ra, rb = zmin - E[t, a, 2], zmin - E[t, b, 2]
            det = E[t, a, 0] * E[t, b, 1] - E[t, a, 1] * E[t, b, 0]
            x = (ra * E[t, b, 1] - rb * E[t, a, 1]) / det
            y = (E[t, a, 0] * rb - E[t, b, 0] * ra) / det
            ulo, uhi, vlo, vhi = _lower(ulo, x), _upper(uhi, x), _lower(vlo, y), _upper(vhi, y)
        umin[t], umax[t], vmin[t], vmax[t] = ulo, uhi, vlo, vhi
    return umin, umax, vmin, vmax


@njit(cache=True, inline="always")
def _lower(m, x):
    """``min`` as numpy's: a NaN wins."""
    return x if (x < m or x != x) else m


@njit(cache=True, inline="always")
def _upper(m, x):
    """``max`` as numpy's: a NaN wins."""
    return x if (x > m or x != x) else m


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


# Octahedral images, triangle by triangle. Inside one octant the octahedral unfolding is affine: image
# coordinates (a, b) in [-1, 1]^2 (a along columns, b along rows) give the octahedron's point
# o(a, b) = o0 + a oa + b ob, and the pixel's direction is o / |o|. An edge function z = E . q is then
# (E . o) / |o|, whose sign is affine in (a, b); where z >= zmin, E . o >= zmin |o| >= zmin max|o| (zmin < 0),
# a half-plane of the octant. So each triangle reaches, in each octant, no farther than a convex polygon: the
# octant's triangle clipped by its three edges' half-planes and by its denominator's (w . q > WMIN, so
# w . o > WMIN / sqrt(3)). Its pixel box is swept as the planar grid kernel sweeps a triangle's box, every
# pixel by the one octant that owns it (:func:`octant_owners`), so that a pixel gets each triangle once.
# The per-triangle set-up (reach polygons and their clipping, grown corners, column lines) is compiled as
# functions of their own, not inlined into each parallel kernel: inlined, a first conversion compiled for 70 s
# instead of 49 (benchmarks/bench_compile.py); only the per-row helpers are inlined.

_VERTS = 16             # room for a clipped polygon: the octant's 3 corners plus one per clip
_SLACK = 1e-6           # in units of the edge functions: rounding never drops a pixel
_W_FLOOR = WMIN / math.sqrt(3.0) * (1.0 - 1e-9) - _SLACK     # w . o > WMIN |o| >= WMIN / sqrt(3)


@njit(cache=True, inline="always")
def _octant(oc):
    """Octant ``oc`` (bit 0: x > 0, bit 1: y > 0, bit 2: the lower half, z < 0): ``o0, oa, ob`` of its
    affine unfolding and its triangle's three corners in ``(a, b)``.
    """
    sx = 1.0 if oc & 1 else -1.0
    sy = 1.0 if oc & 2 else -1.0
    if oc < 4:          # in the diamond |a| + |b| <= 1: o = (a, b, 1 - |a| - |b|)
        return (0.0, 0.0, 1.0), (1.0, 0.0, -sx), (0.0, 1.0, -sy), (0.0, 0.0, sx, 0.0, 0.0, sy)
    # in a corner triangle: o = (sx (1 - |b|), sy (1 - |a|), 1 - |a| - |b|)
    return (sx, sy, 1.0), (0.0, -sx * sy, -sx), (-sx * sy, 0.0, -sy), (sx, 0.0, 0.0, sy, sx, sy)


def _octant_sides() -> np.ndarray:
    """Each octant's triangle (:func:`_octant`'s corners) as the three half-planes ``g0 + ga a + gb b >= 0``
    that bound it (8, 3, 3): side ``k`` through corners ``k`` and ``k + 1``, positive towards the third.
    """
    out = np.empty((8, 3, 3))
    for oc in range(8):
        c = np.array(_octant.py_func(oc)[3]).reshape(3, 2)      # in Python: no compiling at import
        for k in range(3):
            p, q, r = c[k], c[(k + 1) % 3], c[(k + 2) % 3]
            ga, gb = p[1] - q[1], q[0] - p[0]             # normal to the side q - p
            g0 = -(ga * p[0] + gb * p[1])
            out[oc, k] = np.array([g0, ga, gb]) * np.sign(g0 + ga * r[0] + gb * r[1])
    return out


_OCTANT_SIDES = _octant_sides()


@njit(cache=True)
def _clip(pa, pb, m, g0, ga, gb, qa, qb):
    """The polygon ``(pa, pb)[:m]`` clipped to ``g0 + ga a + gb b >= 0``, in place (``qa, qb`` room to work);
    returns its size.
    """
    inside = 0
    for i in range(m):
        if g0 + ga * pa[i] + gb * pb[i] >= 0.0:
            inside += 1
    if inside == m or inside == 0:          # the line misses it: all of it, or nothing
        return inside
    k = 0
    first = g0 + ga * pa[0] + gb * pb[0]
    fi = first
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        fj = g0 + ga * pa[j] + gb * pb[j] if j else first
        if fi >= 0.0:
            qa[k] = pa[i]
            qb[k] = pb[i]
            k += 1
        if (fi >= 0.0) != (fj >= 0.0):
            t = fi / (fi - fj)
            qa[k] = pa[i] + t * (pa[j] - pa[i])
            qb[k] = pb[i] + t * (pb[j] - pb[i])
            k += 1
        fi = fj
    for i in range(k):
        pa[i] = qa[i]
        pb[i] = qb[i]
    return k


@njit(cache=True)
def _clip_by(pa, pb, m, H, count, qa, qb):
    """The polygon ``(pa, pb)[:m]`` clipped in place by the first ``count`` half-planes of ``H``; returns its
    size (0: nothing left).
    """
    for e in range(count):
        if m == 0:
            return 0
        m = _clip(pa, pb, m, H[e, 0], H[e, 1], H[e, 2], qa, qb)
    return m


@njit(cache=True)
def _reach_polygon(t, oc, E, w, zmin, H, pa, pb, qa, qb):
    """The polygon of octant ``oc`` (in ``(a, b)``, into ``pa, pb``) outside which triangle ``t``'s terms are
    cut off; returns its size (0: none there) and the bound on ``|o|`` it was clipped with (``H`` then holds
    its half-planes, see :func:`_half_planes`). Found twice: with ``max|o| = 1``, then with the largest
    ``|o|`` over the first polygon (``|o|`` is convex: its largest value is at a corner).
    """
    o0, oa, ob, corners = _octant(oc)
    _half_planes(t, oc, E, w, zmin, 1.0, H)
    m = _reach_in_octant(oc, H, corners, pa, pb, qa, qb)
    if m == 0:
        return 0, 1.0
    big = 0.0
    for k in range(m):
        x = o0[0] + oa[0] * pa[k] + ob[0] * pb[k]
        y = o0[1] + oa[1] * pa[k] + ob[1] * pb[k]
        z = o0[2] + oa[2] * pa[k] + ob[2] * pb[k]
        big = max(big, math.sqrt(x * x + y * y + z * z))
    big = min(big * (1.0 + 1e-9), 1.0)
    _half_planes(t, oc, E, w, zmin, big, H)
    return _reach_in_octant(oc, H, corners, pa, pb, qa, qb), big


@njit(cache=True)
def _reach_in_octant(oc, H, corners, pa, pb, qa, qb):
    """The polygon where the four half-planes of ``H`` hold in octant ``oc``'s triangle (``corners``), into
    ``pa, pb``; returns its size. Where the edges' three half-planes meet in a triangle (most do), that
    triangle clipped by the octant's sides and the denominator's half-plane, which most of them miss; else
    the octant's triangle clipped by the four.
    """
    if _edges_triangle(H, pa, pb):
        m = _clip_by(pa, pb, 3, _OCTANT_SIDES[oc], 3, qa, qb)
        return _clip(pa, pb, m, H[3, 0], H[3, 1], H[3, 2], qa, qb) if m else 0
    pa[0], pb[0], pa[1], pb[1], pa[2], pb[2] = corners
    return _clip_by(pa, pb, 3, H, 4, qa, qb)


@njit(cache=True)
def _edges_triangle(H, pa, pb):
    """Whether the three edges' half-planes of ``H`` meet in a triangle, with its corners (where two of their
    lines cross, by Cramer's rule) into ``pa, pb``: each corner must lie in the third half-plane (else they
    meet in nothing or in an unbounded region), and within the image's reach (|a|, |b| <= 2).
    """
    for k in range(3):
        e, f = (k + 1) % 3, (k + 2) % 3
        det = H[e, 1] * H[f, 2] - H[e, 2] * H[f, 1]
        x = (H[f, 0] * H[e, 2] - H[e, 0] * H[f, 2]) / det
        y = (H[e, 0] * H[f, 1] - H[f, 0] * H[e, 1]) / det
        if not (abs(x) <= 2.0 and abs(y) <= 2.0 and H[k, 0] + H[k, 1] * x + H[k, 2] * y >= 0.0):
            return False
        pa[k], pb[k] = x, y
    return True


@njit(cache=True)
def _half_planes(t, oc, E, w, zmin, big, H):
    """The four half-planes ``g0 + ga a + gb b >= 0`` of :func:`_reach_polygon` in octant ``oc``, its three
    edges' at ``big`` and its denominator's, into ``H`` (4, 3).
    """
    o0, oa, ob, corners = _octant(oc)
    for e in range(4):
        if e < 3:
            r0, r1, r2 = E[t, e, 0], E[t, e, 1], E[t, e, 2]
            floor = zmin * big - _SLACK
        else:
            r0, r1, r2 = w[t, 0], w[t, 1], w[t, 2]
            floor = _W_FLOOR
        H[e, 0] = r0 * o0[0] + r1 * o0[1] + r2 * o0[2] - floor
        H[e, 1] = r0 * oa[0] + r1 * oa[1] + r2 * oa[2]
        H[e, 2] = r0 * ob[0] + r1 * ob[1] + r2 * ob[2]


@njit(cache=True, inline="always")
def _octant_row(oc, i, m):
    """The columns ``j0..j1-1`` of row ``i`` of an ``(m + 1)``-pixel octahedral image that octant ``oc`` owns
    (:func:`octant_owners`): with ``A = 2j - m``, ``B = 2i - m``, the upper half holds ``|A| + |B| <= m``, ties go
    to the positive sides.
    """
    if (oc & 2 != 0) != (2 * i >= m):
        return 0, 0
    h = m // 2
    half_width = (m - abs(2 * i - m)) // 2
    if oc < 4:
        return (h, h + half_width + 1) if oc & 1 else (h - half_width, h)
    return (h + half_width + 1, m + 1) if oc & 1 else (0, h - half_width)


@njit(cache=True)
def _column_lines(H, half, L):
    """The half-planes of ``H`` (in ``(a, b)``) as bounds on the column ``j`` that move linearly with the row
    ``i``, into ``L`` (4, 3): ``(1, l0, l1)`` for ``j >= l0 + l1 i``, ``(-1, l0, l1)`` for ``j <= l0 + l1 i``, and
    ``(0, g0, g1)`` where a half-plane does not depend on the column: it holds on the rows where
    ``g0 + g1 i >= 0``. Divides once per triangle and octant, not once per row.
    """
    for e in range(H.shape[0]):
        g0 = H[e, 0] - H[e, 1] - H[e, 2]        # at a = j / half - 1, b = i / half - 1
        gj = H[e, 1] / half
        gi = H[e, 2] / half
        if gj > 0.0 or gj < 0.0:
            L[e, 0], L[e, 1], L[e, 2] = (1.0 if gj > 0.0 else -1.0), -g0 / gj, -gi / gj
        else:
            L[e, 0], L[e, 1], L[e, 2] = 0.0, g0, gi


@njit(cache=True, inline="always")
def _row_span(L, i, c0, c1):
    """The columns ``j0..j1-1`` of columns ``c0..c1-1`` on row ``i`` where every bound of
    :func:`_column_lines` holds (rounded outwards by a millionth of a pixel).
    """
    lo, hi = -np.inf, np.inf
    for e in range(L.shape[0]):
        x = L[e, 1] + L[e, 2] * i
        if L[e, 0] > 0.0:
            lo = max(lo, x)
        elif L[e, 0] < 0.0:
            hi = min(hi, x)
        elif x < 0.0:
            return c0, c0
    lo, hi = max(lo, c0 - 1.0), min(hi, float(c1))
    if not lo <= hi:
        return c0, c0
    return max(c0, int(math.ceil(lo - 1e-6))), min(c1, int(math.floor(hi + 1e-6)) + 1)


@njit(parallel=True, cache=True)
def _near_all(E, w, zmin):
    """:func:`_near_octants` of every triangle, as bits (T,)."""
    out = np.empty(E.shape[0], np.uint8)
    for t in prange(E.shape[0]):
        out[t] = _near_octants(np.int64(t), E, w, zmin)     # one signature for the helpers (prange's t is unsigned)
    return out


@njit(parallel=True, cache=True)
def _octant_boxes(E, w, zmin, n, near, start, entry, boxes, bigs):
    """Each triangle's pixel box in each octant :func:`_near_octants` leaves it (``near``, its bits), one slot
    each, from ``start[t]`` on in octant order: the entry ``8 t + octant`` into ``entry``, rows ``r0..r1-1``
    and columns ``c0..c1-1`` into ``boxes`` (slots, 4) (zeros where it reaches nothing there), and the bound
    on ``|o|`` its polygon was clipped with into ``bigs``. Runs of triangles in parallel.
    """
    half = 0.5 * (n - 1)
    T = E.shape[0]
    runs = min(T, 256)
    for run in prange(runs):
        pa = np.empty(_VERTS)
        pb = np.empty(_VERTS)
        qa = np.empty(_VERTS)
        qb = np.empty(_VERTS)
        H = np.empty((4, 3))
        for t in range(run * T // runs, (run + 1) * T // runs):
            slot = start[t]
            for oc in range(8):
                if not near[t] & (1 << oc):
                    continue
                entry[slot] = 8 * t + oc
                for k in range(4):
                    boxes[slot, k] = 0
                m, bigs[slot] = _reach_polygon(t, oc, E, w, zmin, H, pa, pb, qa, qb)
                if m > 0:
                    alo, ahi, blo, bhi = pa[0], pa[0], pb[0], pb[0]
                    for k in range(1, m):
                        alo, ahi = min(alo, pa[k]), max(ahi, pa[k])
                        blo, bhi = min(blo, pb[k]), max(bhi, pb[k])
                    boxes[slot, 0] = max(0, int(math.ceil((blo + 1.0) * half - 1e-6)))
                    boxes[slot, 1] = min(n, int(math.floor((bhi + 1.0) * half + 1e-6)) + 1)
                    boxes[slot, 2] = max(0, int(math.ceil((alo + 1.0) * half - 1e-6)))
                    boxes[slot, 3] = min(n, int(math.floor((ahi + 1.0) * half + 1e-6)) + 1)
                slot += 1


@njit(cache=True)
def _grown_corners(t, E, w, zmin):
    """The corners of the chord triangle that holds the central projection of every direction triangle ``t``'s
    terms reach, as ``(ok, G0, G1, G2)`` (``ok`` False where its edges do not fix them). With ``V_k`` its unit
    corners, ``w = sum_k mu_k E_k`` (``mu_k > 0``) and ``beta`` the barycentric coordinates of the projection
    of ``q`` onto its chord plane, ``beta_k = mu_k z_k / (w . q)``: where every ``z_k >= zmin`` and
    ``w . q > WMIN``, ``beta_k >= zmin mu_k / WMIN = -gamma_k``, the triangle grown to the corners
    ``G_j = (1 + sum_k gamma_k) V_j - sum_k gamma_k V_k``.
    """
    nothing = (0.0, 0.0, 0.0)
    v0 = _corner(t, 0, E)
    v1 = _corner(t, 1, E)
    v2 = _corner(t, 2, E)
    det = _det3(E[t, 0, 0], E[t, 1, 0], E[t, 2, 0], E[t, 0, 1], E[t, 1, 1], E[t, 2, 1], E[t, 0, 2], E[t, 1, 2],
                E[t, 2, 2])
    if v0[3] == 0.0 or v1[3] == 0.0 or v2[3] == 0.0 or not det != 0.0:
        return False, nothing, nothing, nothing
    # mu from w = sum_k mu_k E_k, by Cramer's rule on the columns E_k
    mu0 = _det3(w[t, 0], E[t, 1, 0], E[t, 2, 0], w[t, 1], E[t, 1, 1], E[t, 2, 1], w[t, 2], E[t, 1, 2], E[t, 2, 2]) / det
    mu1 = _det3(E[t, 0, 0], w[t, 0], E[t, 2, 0], E[t, 0, 1], w[t, 1], E[t, 2, 1], E[t, 0, 2], w[t, 2], E[t, 2, 2]) / det
    mu2 = _det3(E[t, 0, 0], E[t, 1, 0], w[t, 0], E[t, 0, 1], E[t, 1, 1], w[t, 1], E[t, 0, 2], E[t, 1, 2], w[t, 2]) / det
    if not (0.0 < mu0 < np.inf and 0.0 < mu1 < np.inf and 0.0 < mu2 < np.inf):
        return False, nothing, nothing, nothing
    grow = -zmin / WMIN * (1.0 + 1e-6)
    g0, g1, g2 = grow * mu0 + 1e-9, grow * mu1 + 1e-9, grow * mu2 + 1e-9
    top = 1.0 + g0 + g1 + g2
    base = (g0 * v0[0] + g1 * v1[0] + g2 * v2[0], g0 * v0[1] + g1 * v1[1] + g2 * v2[1],
            g0 * v0[2] + g1 * v1[2] + g2 * v2[2])
    return (True, (top * v0[0] - base[0], top * v0[1] - base[1], top * v0[2] - base[2]),
            (top * v1[0] - base[0], top * v1[1] - base[1], top * v1[2] - base[2]),
            (top * v2[0] - base[0], top * v2[1] - base[1], top * v2[2] - base[2]))


@njit(cache=True)
def _near_octants(t, E, w, zmin):
    """The octants triangle ``t``'s terms may reach (a superset), as bits: a direction it reaches lies in the
    cone over :func:`_grown_corners`, so on the side of each coordinate plane where all three of them are.
    """
    ok, G0, G1, G2 = _grown_corners(t, E, w, zmin)
    if not ok:
        return 255
    lx, hx = min(G0[0], G1[0], G2[0]), max(G0[0], G1[0], G2[0])
    ly, hy = min(G0[1], G1[1], G2[1]), max(G0[1], G1[1], G2[1])
    lz, hz = min(G0[2], G1[2], G2[2]), max(G0[2], G1[2], G2[2])
    tiny = 1e-12 * max(-lx, hx, -ly, hy, -lz, hz)
    bits = 0
    for oc in range(8):
        if (hx < -tiny if oc & 1 else lx > tiny) or (hy < -tiny if oc & 2 else ly > tiny) \
                or (lz > tiny if oc >= 4 else hz < -tiny):
            continue
        bits |= 1 << oc
    return bits


@njit(parallel=True, cache=True)
def sphere_reach(E, w, zmin, centres):
    """How far (chord distance) from its centre ``centres[t]`` a direction triangle ``t``'s terms reach can
    lie: at most ``max_j |G_j - c| + max(1 - h, max_j |G_j| - 1)`` with ``G_j`` its :func:`_grown_corners`
    and ``h`` the chord plane's distance from the origin (the central projection onto the unit sphere moves a
    point of the grown triangle by ``| |g| - 1 |``); 4 (the whole sphere) where they are not fixed.
    """
    T = E.shape[0]
    out = np.empty(T)
    for t in prange(T):
        ok, G0, G1, G2 = _grown_corners(np.int64(t), E, w, zmin)
        if not ok:
            out[t] = 4.0
            continue
        far = 0.0
        longest = 0.0
        for G in (G0, G1, G2):
            far = max(far, math.sqrt((G[0] - centres[t, 0]) ** 2 + (G[1] - centres[t, 1]) ** 2
                                     + (G[2] - centres[t, 2]) ** 2))
            longest = max(longest, math.sqrt(G[0] * G[0] + G[1] * G[1] + G[2] * G[2]))
        # the chord plane's distance from the origin: w is normal to it, and the centre lies on it
        h = (w[t, 0] * centres[t, 0] + w[t, 1] * centres[t, 1] + w[t, 2] * centres[t, 2]) \
            / math.sqrt(w[t, 0] ** 2 + w[t, 1] ** 2 + w[t, 2] ** 2)
        out[t] = min(4.0, (far + max(1.0 - h, longest - 1.0)) * (1.0 + 1e-9))
    return out


@njit(cache=True, inline="always")
def _corner(t, k, E):
    """Triangle ``t``'s unit corner ``k`` (across from edge ``k``: on edges ``k + 1`` and ``k + 2``, on the
    inner side of edge ``k``), and 1 (0, with zeros, when the edges do not fix it).
    """
    a, b = (k + 1) % 3, (k + 2) % 3
    x = E[t, a, 1] * E[t, b, 2] - E[t, a, 2] * E[t, b, 1]
    y = E[t, a, 2] * E[t, b, 0] - E[t, a, 0] * E[t, b, 2]
    z = E[t, a, 0] * E[t, b, 1] - E[t, a, 1] * E[t, b, 0]
    size = math.sqrt(x * x + y * y + z * z)
    side = x * E[t, k, 0] + y * E[t, k, 1] + z * E[t, k, 2]
    if not (size > 0.0 and side != 0.0 and size < np.inf):
        return 0.0, 0.0, 0.0, 0.0
    f = (1.0 if side > 0.0 else -1.0) / size
    return x * f, y * f, z * f, 1.0


@njit(cache=True, inline="always")
def _det3(a, b, c, d, e, f, g, h, i):
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def octant_owners(n: int) -> np.ndarray:
    """The octant (as :func:`_octant` numbers them) that owns each pixel of an ``n x n`` octahedral image:
    the one whose closed triangle holds it, ties to the upper half and to the positive sides. From integers.
    """
    k = 2 * np.arange(n, dtype=np.int64) - (n - 1)          # (n - 1) a along columns, (n - 1) b along rows
    A, B = np.meshgrid(k, k)
    lower = np.abs(A) + np.abs(B) > n - 1
    return ((A >= 0).astype(np.int8) + 2 * (B >= 0) + 4 * lower).astype(np.int8)


@njit(parallel=True, cache=True)
def _octahedral_kernel(q, E, K, w, entry, boxes, bigs, band, band_ptr, band_slots, zmin, zmax, floor, deriv, table,
                       P, Da, Db, ok):
    """Octahedral images, triangle by triangle and octant by octant: bands of ``band`` rows run in parallel;
    every (triangle, octant) slot a band lists (its entry ``8 t + octant``, its box and its bound on ``|o|``
    from :func:`_octant_boxes`) adds the triangle's terms over the pixels of its box that the octant owns
    (:func:`_octant_row`; on each row, only between the columns its half-planes leave: :func:`_column_lines`,
    :func:`_row_span`) to the band's running sums, as :func:`_term` gives them. A pixel's triangles come in
    ascending order, as the points kernel sums them: the same points. Derivatives are along the image's
    ``a`` and ``b`` (``Da``, ``Db``): in the pixel's octant ``dq/da = (o_a - q (q . o_a)) / |o|``, and
    ``1 / |o| = |q|_1``, so a triangle's terms need its rows times ``o_a``, ``o_b`` once per entry.
    Pixels whose sum is below ``floor`` are left to the points kernel (``ok`` False).
    """
    n = int(round(math.sqrt(q.shape[0])))
    half = 0.5 * (n - 1)
    for b in prange(band_ptr.shape[0] - 1):
        i0 = b * band
        i1 = min(n, i0 + band)
        acc = np.zeros((band, n, 12))
        H = np.empty((4, 3))
        L = np.empty((4, 3))
        for k in range(band_ptr[b], band_ptr[b + 1]):
            sl = band_slots[k]
            e = entry[sl]
            t = e >> 3
            oc = e & 7
            e00, e01, e02 = E[t, 0, 0], E[t, 0, 1], E[t, 0, 2]
            e10, e11, e12 = E[t, 1, 0], E[t, 1, 1], E[t, 1, 2]
            e20, e21, e22 = E[t, 2, 0], E[t, 2, 1], E[t, 2, 2]
            _, oa, ob, _ = _octant(oc)
            # the rows along the octant's two image directions
            ea0, ea1, ea2 = _along(E, t, 0, oa), _along(E, t, 1, oa), _along(E, t, 2, oa)
            eb0, eb1, eb2 = _along(E, t, 0, ob), _along(E, t, 1, ob), _along(E, t, 2, ob)
            wa = w[t, 0] * oa[0] + w[t, 1] * oa[1] + w[t, 2] * oa[2]
            wb = w[t, 0] * ob[0] + w[t, 1] * ob[1] + w[t, 2] * ob[2]
            ka0, ka1, ka2 = _along(K, t, 0, oa), _along(K, t, 1, oa), _along(K, t, 2, oa)
            kb0, kb1, kb2 = _along(K, t, 0, ob), _along(K, t, 1, ob), _along(K, t, 2, ob)
            _half_planes(t, oc, E, w, zmin, bigs[sl], H)
            _column_lines(H, half, L)
            for i in range(max(boxes[sl, 0], i0), min(boxes[sl, 1], i1)):
                r = i - i0
                o0, o1 = _octant_row(oc, i, n - 1)
                j0, j1 = _row_span(L, i, max(boxes[sl, 2], o0), min(boxes[sl, 3], o1))
                for j in range(j0, j1):
                    p = i * n + j
                    p0, p1, p2 = q[p, 0], q[p, 1], q[p, 2]
                    z0 = e00 * p0 + e01 * p1 + e02 * p2
                    if z0 < zmin:
                        continue
                    z1 = e10 * p0 + e11 * p1 + e12 * p2
                    if z1 < zmin:
                        continue
                    z2 = e20 * p0 + e21 * p1 + e22 * p2
                    if z2 < zmin:
                        continue
                    kind, F, r0, r1, r2, X, Y, Z, inv_wp = _term(t, z0, z1, z2, p0, p1, p2, K, w, zmax, deriv, 0.0,
                                                                 False, WMIN, table)
                    if kind < 2:
                        continue
                    a = acc[r, j]
                    a[0] += F
                    a[1] += F * X
                    a[2] += F * Y
                    a[3] += F * Z
                    if not deriv:
                        continue
                    inv_o = abs(p0) + abs(p1) + abs(p2)
                    sa = p0 * oa[0] + p1 * oa[1] + p2 * oa[2]
                    sb = p0 * ob[0] + p1 * ob[1] + p2 * ob[2]
                    R = r0 * z0 + r1 * z1 + r2 * z2
                    f = F * inv_o
                    g = f * inv_wp
                    dF = f * (r0 * ea0 + r1 * ea1 + r2 * ea2 - sa * R)
                    a[4] += dF
                    a[5] += dF * X + g * (ka0 - X * wa)
                    a[6] += dF * Y + g * (ka1 - Y * wa)
                    a[7] += dF * Z + g * (ka2 - Z * wa)
                    dF = f * (r0 * eb0 + r1 * eb1 + r2 * eb2 - sb * R)
                    a[8] += dF
                    a[9] += dF * X + g * (kb0 - X * wb)
                    a[10] += dF * Y + g * (kb1 - Y * wb)
                    a[11] += dF * Z + g * (kb2 - Z * wb)
        for i in range(i0, i1):
            r = i - i0
            for j in range(n):
                p = i * n + j
                s = acc[r, j, 0]
                ok[p] = s >= floor
                if not ok[p]:
                    continue
                for c in range(3):
                    val = acc[r, j, 1 + c] / s
                    P[p, c] = val
                    Da[p, c] = (acc[r, j, 5 + c] - val * acc[r, j, 4]) / s
                    Db[p, c] = (acc[r, j, 9 + c] - val * acc[r, j, 8]) / s


@njit(cache=True, inline="always")
def _along(M, t, k, d):
    """Row ``k`` of triangle ``t``'s matrix ``M`` times the vector ``d``."""
    return M[t, k, 0] * d[0] + M[t, k, 1] * d[1] + M[t, k, 2] * d[2]


def sample_octahedral_coverage(q, tables, *, zmin, floor, derivatives=True):
    """The coverage-weighted surface on a square octahedral image whose pixels have unit directions ``q``
    (n * n, 3), row by row, triangle by triangle over each one's box in each octant (see
    :func:`_octahedral_kernel`). ``tables`` are ``(E, K, w)`` with ``E`` divided by each triangle's width.
    Returns ``P, P_a, P_b`` (n * n, 3; the derivatives along the image's columns and rows, zeros without
    ``derivatives``) and ``ok`` (n * n): pixels whose sum is certified (the others are left unwritten: the
    points kernel's to fill).
    """
    E, K, w = tables
    q = np.ascontiguousarray(q, np.float64)
    n = int(round(math.sqrt(len(q))))
    near = _near_all(E, w, float(zmin))
    counts = np.unpackbits(near[:, None], axis=1).sum(axis=1)
    start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    slots = int(counts.sum())
    entry = np.empty(slots, np.int64)
    boxes = np.empty((slots, 4), np.int64)
    bigs = np.empty(slots)
    _octant_boxes(E, w, float(zmin), n, near, start, entry, boxes, bigs)
    band = _band_rows(n)
    band_ptr, band_slots = _band_lists(-(-n // band), band, np.arange(slots, dtype=np.int64),
                                       np.ascontiguousarray(boxes[:, 0]), np.ascontiguousarray(boxes[:, 1]))
    P, Da, Db = np.empty((n * n, 3)), np.empty((n * n, 3)), np.empty((n * n, 3))
    ok = np.empty(n * n, np.bool_)
    _octahedral_kernel(q, E, K, w, entry, boxes, bigs, band, band_ptr, band_slots, float(zmin),
                       float(-zmin), float(floor), bool(derivatives), TABLE, P, Da, Db, ok)
    return P, Da, Db, ok
