"""The numba kernels of the weighted-mean surface, behind plain functions of arrays.

Every weight contributes through ``(w, dw/du, dw/dv)``; with the face maps
``P_i = C_i + A_i (u - uc_i) + B_i (v - vc_i)`` the kernels accumulate
``S = sum w``, ``N = sum w P_i``, ``S_u = sum w_u``, ``N_u = sum w_u P_i``, ``N_A = sum w A_i`` (and the
same in v), from which ``P = N / S`` and ``P_u = (N_u + N_A - P S_u) / S``.

Truncation: a Gaussian face is summed only inside the box ``|u - uc_i| <= R_i, |v - vc_i| <= R_i``.
A point whose truncated Gaussian sum ``S`` falls below ``g_ref`` (the least weight its own face can
have) is not certified and is recomputed exactly over all faces, with exponents shifted by their
maximum so that nothing underflows.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._gaussian_fastexp import exp_inplace, plain_sum_floor
from ._grid import grid_bands

__all__ = [
    "sample_grid_gaussian",
    "truncation_boxes",
    "evaluate_points",
    "build_cells",
    "GAUSSIAN",
    "LOCAL",
    "TRUNCATED",
    "EXACT",
    "HOLE",
]

GAUSSIAN, LOCAL = 0, 1
TRUNCATED, EXACT, HOLE = 0, 1, 2   # per-point status codes


# --------------------------------------------------------------------------- regular grids
@njit(parallel=True, cache=True)
def _ranges(coord, centre, radius):
    """``searchsorted(coord, centre - radius, "left")`` and ``searchsorted(coord, centre + radius, "right")``
    for increasing ``coord``: a guess from its mean spacing (right at once for an image's even grid),
    then moved to the exact answer.
    """
    n = coord.shape[0]
    step = (coord[n - 1] - coord[0]) / (n - 1) if n > 1 else 1.0
    step = step if step > 0 else 1.0
    lo = np.empty(centre.shape[0], np.int64)
    hi = np.empty(centre.shape[0], np.int64)
    for f in prange(centre.shape[0]):
        x = centre[f] - radius[f]
        i = min(max(int(math.ceil((x - coord[0]) / step)), 0), n)
        while i > 0 and coord[i - 1] >= x:
            i -= 1
        while i < n and coord[i] < x:
            i += 1
        lo[f] = i
        x = centre[f] + radius[f]
        i = min(max(int(math.floor((x - coord[0]) / step)) + 1, 0), n)
        while i > 0 and coord[i - 1] > x:
            i -= 1
        while i < n and coord[i] <= x:
            i += 1
        hi[f] = i
    return lo, hi


@njit(parallel=True, cache=True)
def _gauss_exponents(coord, lo, ptr, centre, inv2s, out):
    for f in prange(lo.shape[0]):
        for t in range(ptr[f + 1] - ptr[f]):
            d = coord[lo[f] + t] - centre[f]
            out[ptr[f] + t] = -d * d * inv2s[f]


def truncation_boxes(u, v, centres, radius):
    """Each face's truncation box as index ranges of the grid, ``[c0, c1)`` of the columns ``u`` and
    ``[r0, r1)`` of the rows ``v``, and the faces whose box holds a pixel (``live``).
    """
    c0, c1 = _ranges(u, np.ascontiguousarray(centres[:, 0]), radius)
    r0, r1 = _ranges(v, np.ascontiguousarray(centres[:, 1]), radius)
    live = np.flatnonzero((c1 > c0) & (r1 > r0)).astype(np.int64)
    return c0, c1, r0, r1, live


def _gauss_tables(coord, lo, ptr, centre, inv2s, out):
    """``out[ptr[f] + t] = exp(-(coord[lo[f] + t] - centre[f])^2 inv2s[f])``: each face's Gaussian along
    one axis of the grid, over its box.
    """
    _gauss_exponents(coord, lo, ptr, centre, inv2s, out)
    exp_inplace(out)


@njit(cache=True, inline="always")
def _add_positions(gu, du, cx, cy, cz, ax, ay, az, gvv, s0, n0, n1, n2):
    """Adds one face's ``S`` and ``sum g p`` terms along a stretch of one row: ``gu`` its Gaussian along u
    there, ``du`` the columns' offsets from its centre, ``(cx, cy, cz) + (ax, ay, az) du`` its plane.
    """
    for t in range(gu.shape[0]):
        g = gu[t] * gvv
        d = du[t]
        s0[t] += g
        n0[t] += g * (cx + ax * d)
        n1[t] += g * (cy + ay * d)
        n2[t] += g * (cz + az * d)


@njit(cache=True, inline="always")
def _add_derivatives(gu, du, cx, cy, cz, ax, ay, az, bx, by, bz, gvv, k, hv, su, sv, nu0, nu1, nu2, nv0, nv1, nv2):
    """Adds, along the stretch :func:`_add_positions` covers, one face's terms of ``dS/du``, ``dS/dv``
    (``su``, ``sv``) and of ``d(sum g p)/du`` and ``/dv`` (``nu*``, ``nv*``: the weight's derivative times
    the plane, plus the weight times the plane's slope); ``k du`` and ``hv`` are the Gaussian's
    log-derivatives. (A separate loop: fused with the positions', both ran slower.)
    """
    for t in range(gu.shape[0]):
        g = gu[t] * gvv
        d = du[t]
        px, py, pz = cx + ax * d, cy + ay * d, cz + az * d
        gu_ = g * k * d
        gv_ = g * hv
        su[t] += gu_
        sv[t] += gv_
        nu0[t] += gu_ * px + g * ax
        nu1[t] += gu_ * py + g * ay
        nu2[t] += gu_ * pz + g * az
        nv0[t] += gv_ * px + g * bx
        nv1[t] += gv_ * py + g * by
        nv2[t] += gv_ * pz + g * bz


@njit(parallel=True, cache=True)
def _grid_kernel(u, v, uc, vc, inv2s, C, A, B, c0, cptr, gu, r0, r1, rptr, gv, band, band_ptr, band_faces,
                 derivs, g_ref, P, Pu, Pv, ok):
    """Bands of ``band`` rows run in parallel; in each, every face it lists adds its box's rows to the
    band's running sums (its constants loaded once a band, each row a contiguous stretch).
    """
    H, W = v.shape[0], u.shape[0]
    for b in prange(band_ptr.shape[0] - 1):
        i0 = b * band
        i1 = min(H, i0 + band)
        acc = np.zeros((4, band, W))
        dacc = np.zeros((8, band, W) if derivs else (8, 1, 1))
        du = np.empty(W)
        for q in range(band_ptr[b], band_ptr[b + 1]):
            f = band_faces[q]
            j0 = c0[f]
            n = cptr[f + 1] - cptr[f]
            j1 = j0 + n
            g_u = gu[cptr[f]:cptr[f + 1]]
            for t in range(n):
                du[t] = u[j0 + t] - uc[f]
            d_u = du[:n]
            ax, ay, az = A[f, 0], A[f, 1], A[f, 2]
            bx, by, bz = B[f, 0], B[f, 1], B[f, 2]
            k = -2.0 * inv2s[f]
            for i in range(max(r0[f], i0), min(r1[f], i1)):
                r = i - i0
                gvv = gv[rptr[f] + i - r0[f]]
                dv = v[i] - vc[f]
                cx, cy, cz = C[f, 0] + bx * dv, C[f, 1] + by * dv, C[f, 2] + bz * dv
                _add_positions(g_u, d_u, cx, cy, cz, ax, ay, az, gvv,
                               acc[0, r, j0:j1], acc[1, r, j0:j1], acc[2, r, j0:j1], acc[3, r, j0:j1])
                if derivs:
                    _add_derivatives(g_u, d_u, cx, cy, cz, ax, ay, az, bx, by, bz, gvv, k, -2.0 * dv * inv2s[f],
                                     dacc[0, r, j0:j1], dacc[1, r, j0:j1], dacc[2, r, j0:j1], dacc[3, r, j0:j1],
                                     dacc[4, r, j0:j1], dacc[5, r, j0:j1], dacc[6, r, j0:j1], dacc[7, r, j0:j1])
        for i in range(i0, i1):
            r = i - i0
            for j in range(W):
                s = acc[0, r, j]
                if not s >= g_ref:        # left to the exact sum, zeros until then
                    ok[i, j] = False
                    for c in range(3):
                        P[i, j, c] = 0.0
                        if derivs:
                            Pu[i, j, c] = 0.0
                            Pv[i, j, c] = 0.0
                    continue
                ok[i, j] = True
                for c in range(3):
                    p = acc[1 + c, r, j] / s
                    P[i, j, c] = p
                    if derivs:
                        Pu[i, j, c] = (dacc[2 + c, r, j] - p * dacc[0, r, j]) / s
                        Pv[i, j, c] = (dacc[5 + c, r, j] - p * dacc[1, r, j]) / s


def sample_grid_gaussian(u, v, centres, sigma, radius, C, A, B, *, derivatives, log_g_ref):
    """Truncated rational-Gaussian surface on the grid ``u`` (columns) x ``v`` (rows).

    Uses the separability of each Gaussian: per face, one table of ``exp`` along u and one along v
    over its box, so a pixel costs one product per face. Bands of rows run in parallel. Sums are certified when
    ``S >= plain_sum_floor(log_g_ref)``: below that (tiny s) plain exponentials may underflow,
    and the caller recomputes those pixels in the log domain.

    Returns
    -------
    P : numpy.ndarray, shape (H, W, 3) float64
        Surface points.
    Pu, Pv : numpy.ndarray, shape (H, W, 3) float64, or None
        First derivatives (None when ``derivatives`` is false).
    ok : numpy.ndarray, shape (H, W) bool
        Pixels whose truncated sum is certified (the others need an exact evaluation).
    """
    u = np.ascontiguousarray(u, np.float64)
    v = np.ascontiguousarray(v, np.float64)
    inv2s = 0.5 / sigma ** 2
    c0, c1, r0, r1, live = truncation_boxes(u, v, centres, radius)
    cn = np.where(c1 > c0, c1 - c0, 0)
    rn = np.where(r1 > r0, r1 - r0, 0)
    cptr = np.concatenate([[0], np.cumsum(cn)]).astype(np.int64)
    rptr = np.concatenate([[0], np.cumsum(rn)]).astype(np.int64)
    gu = np.empty(cptr[-1])
    gv = np.empty(rptr[-1])
    _gauss_tables(u, c0, cptr, centres[:, 0].copy(), inv2s, gu)
    _gauss_tables(v, r0, rptr, centres[:, 1].copy(), inv2s, gv)
    band, band_ptr, band_faces, P, Pu, Pv, ok = grid_bands(u, v, live, r0, r1, derivatives)
    _grid_kernel(u, v, centres[:, 0].copy(), centres[:, 1].copy(), inv2s, C, A, B, c0, cptr, gu, r0, r1, rptr,
                 gv, band, band_ptr, band_faces, bool(derivatives), plain_sum_floor(log_g_ref),
                 P, Pu, Pv, ok)
    return (P, Pu, Pv, ok) if derivatives else (P, None, None, ok)


# --------------------------------------------------------------------------- scattered points
@njit(cache=True)
def _fill_cells(lo_x, hi_x, lo_y, hi_y, nx, ny):
    counts = np.zeros(nx * ny + 1, np.int64)
    for f in range(lo_x.shape[0]):
        for iy in range(lo_y[f], hi_y[f] + 1):
            for ix in range(lo_x[f], hi_x[f] + 1):
                counts[iy * nx + ix + 1] += 1
    ptr = np.cumsum(counts)
    fill = ptr[:-1].copy()
    out = np.empty(ptr[-1], np.int64)
    for f in range(lo_x.shape[0]):
        for iy in range(lo_y[f], hi_y[f] + 1):
            for ix in range(lo_x[f], hi_x[f] + 1):
                c = iy * nx + ix
                out[fill[c]] = f
                fill[c] += 1
    return ptr, out


def build_cells(centres: np.ndarray, radius: np.ndarray, max_cells: int = 512):
    """Bin faces into a uniform grid of cells by the box of half-size ``radius`` around each centre.

    Returns ``(origin, h, nx, ny, ptr, faces)``: cell ``(ix, iy)`` lists
    ``faces[ptr[iy*nx+ix]:ptr[iy*nx+ix+1]]``.
    """
    lo = (centres - radius[:, None]).min(axis=0)
    hi = (centres + radius[:, None]).max(axis=0)
    span = np.maximum(hi - lo, 1e-300)
    h = max(float(np.median(radius)), float(span.max()) / max_cells)
    nx, ny = (np.floor(span / h).astype(np.int64) + 1).tolist()
    bx0 = np.clip(((centres[:, 0] - radius - lo[0]) / h).astype(np.int64), 0, nx - 1)
    bx1 = np.clip(((centres[:, 0] + radius - lo[0]) / h).astype(np.int64), 0, nx - 1)
    by0 = np.clip(((centres[:, 1] - radius - lo[1]) / h).astype(np.int64), 0, ny - 1)
    by1 = np.clip(((centres[:, 1] + radius - lo[1]) / h).astype(np.int64), 0, ny - 1)
    ptr, faces = _fill_cells(bx0, bx1, by0, by1, nx, ny)
    return lo.astype(np.float64), h, nx, ny, ptr, faces


@njit(cache=True)
def _weight(kind, du, dv, param, radius):
    """Weight exponent/value and its u, v derivative factors for one face at offset (du, dv)."""
    if kind == 0:  # Gaussian: returns the exponent; derivative factors multiply exp(...)
        e = -(du * du + dv * dv) * param
        return e, -2.0 * du * param, -2.0 * dv * param
    r2 = (du * du + dv * dv) / (radius * radius)
    t = math.sqrt(r2)
    w = 1.0 - 3.0 * r2 + 2.0 * r2 * t
    k = 6.0 * (t - 1.0) / (radius * radius)
    return w, k * du, k * dv


@njit(cache=True)
def _accumulate(kind, pu, pv, cand, n_cand, all_faces, uc, vc, param, radius, C, A, B, acc, kf, kfu, kfv):
    """Sum over candidate faces into acc[0:18]; returns the exponent shift (Gaussian) or 0.

    Gaussian exponents are ``-r^2 param_f kf`` with ``kf`` this point's factor (a smoothness that
    varies over the domain) and ``kfu, kfv`` its derivatives.
    """
    m = -np.inf
    if kind == 0:
        for k in range(n_cand):
            f = k if all_faces else cand[k]
            du = pu - uc[f]
            dv = pv - vc[f]
            if not all_faces and (abs(du) > radius[f] or abs(dv) > radius[f]):
                continue
            e = -(du * du + dv * dv) * param[f] * kf
            if e > m:
                m = e
        if m == -np.inf:
            return m
    else:
        m = 0.0
    for q in range(18):
        acc[q] = 0.0
    for k in range(n_cand):
        f = k if all_faces else cand[k]
        du = pu - uc[f]
        dv = pv - vc[f]
        if kind == 0:
            if not all_faces and (abs(du) > radius[f] or abs(dv) > radius[f]):
                continue
            e, hu, hv = _weight(0, du, dv, param[f] * kf, radius[f])
            r2p = (du * du + dv * dv) * param[f]
            hu -= r2p * kfu
            hv -= r2p * kfv
            w = math.exp(e - m)
            wu = w * hu
            wv = w * hv
        else:
            if du * du + dv * dv >= radius[f] * radius[f]:
                continue
            w, wu, wv = _weight(1, du, dv, param[f], radius[f])
        for c in range(3):
            p = C[f, c] + A[f, c] * du + B[f, c] * dv
            acc[1 + c] += w * p
            acc[6 + c] += wu * p
            acc[9 + c] += wv * p
            acc[12 + c] += w * A[f, c]
            acc[15 + c] += w * B[f, c]
        acc[0] += w
        acc[4] += wu
        acc[5] += wv
    return m


@njit(parallel=True, cache=True)
def _points_kernel(kind, pts, uc, vc, param, radius, C, A, B, origin, h, nx, ny, cptr, cfaces,
                   log_g_ref, force_exact, kf, kfu, kfv, P, Pu, Pv, status):
    n_faces = uc.shape[0]
    dummy = np.zeros(1, np.int64)
    for p in prange(pts.shape[0]):
        acc = np.zeros(18)
        pu = pts[p, 0]
        pv = pts[p, 1]
        st = TRUNCATED
        certified = False
        if not force_exact:
            ix = int(math.floor((pu - origin[0]) / h))
            iy = int(math.floor((pv - origin[1]) / h))
            if 0 <= ix < nx and 0 <= iy < ny:
                c = iy * nx + ix
                cand = cfaces[cptr[c]:cptr[c + 1]]
                m = _accumulate(kind, pu, pv, cand, cand.shape[0], False, uc, vc, param, radius, C, A, B, acc,
                                kf[p], kfu[p], kfv[p])
                if kind == 0:
                    certified = m > -np.inf and math.log(acc[0]) + m >= log_g_ref
                else:
                    certified = acc[0] > 0.0
        if not certified:
            if kind == 0:
                _accumulate(0, pu, pv, dummy, n_faces, True, uc, vc, param, radius, C, A, B, acc, kf[p], kfu[p],
                            kfv[p])
                st = EXACT
            elif force_exact:
                _accumulate(1, pu, pv, dummy, n_faces, True, uc, vc, param, radius, C, A, B, acc, 1.0, 0.0, 0.0)
                st = EXACT
            if kind == 1 and not acc[0] > 0.0:
                # a hole of the locally supported weights: report it, take the nearest face's plane
                best = 0
                bestd = np.inf
                for f in range(n_faces):
                    d2 = ((pu - uc[f]) ** 2 + (pv - vc[f]) ** 2) / (radius[f] * radius[f])
                    if d2 < bestd:
                        bestd = d2
                        best = f
                for q in range(18):
                    acc[q] = 0.0
                du = pu - uc[best]
                dv = pv - vc[best]
                acc[0] = 1.0
                for c in range(3):
                    acc[1 + c] = C[best, c] + A[best, c] * du + B[best, c] * dv
                    acc[12 + c] = A[best, c]
                    acc[15 + c] = B[best, c]
                st = HOLE
        s = acc[0]
        status[p] = st
        for c in range(3):
            val = acc[1 + c] / s
            P[p, c] = val
            Pu[p, c] = (acc[6 + c] + acc[12 + c] - val * acc[4]) / s
            Pv[p, c] = (acc[9 + c] + acc[15 + c] - val * acc[5]) / s


def evaluate_points(kind, pts, centres, param, radius, C, A, B, cells, *, log_g_ref, exact=False, factor=None):
    """Evaluate the surface and its first derivatives at scattered parameter points.

    Parameters
    ----------
    kind : int
        ``GAUSSIAN`` (``param`` = 1 / (2 sigma^2), ``radius`` = truncation half-box) or ``LOCAL``
        (``radius`` = support radius R_i).
    pts : (k, 2) float64
    cells : tuple from :func:`build_cells`
    log_g_ref : float
        log of the certification threshold of the truncated Gaussian sum.
    exact : bool
        Sum over every face (no truncation).
    factor : (kf, kf_u, kf_v) of (k,) arrays, optional
        Per-point factor of the Gaussian exponents and its derivatives (a smoothness map).

    Returns
    -------
    P, Pu, Pv : (k, 3) float64
    status : (k,) int8
        ``TRUNCATED``, ``EXACT`` (recomputed over all faces) or ``HOLE`` (no local weight covers it).
    """
    origin, h, nx, ny, cptr, cfaces = cells
    pts = np.ascontiguousarray(pts, np.float64)
    k = pts.shape[0]
    P, Pu, Pv = np.zeros((k, 3)), np.zeros((k, 3)), np.zeros((k, 3))
    status = np.zeros(k, np.int8)
    if factor is None:
        factor = (np.ones(k), np.zeros(k), np.zeros(k))
    kf, kfu, kfv = (np.ascontiguousarray(a, np.float64) for a in factor)
    _points_kernel(int(kind), pts, np.ascontiguousarray(centres[:, 0]), np.ascontiguousarray(centres[:, 1]),
                   param, radius, C, A, B, origin, float(h), int(nx), int(ny), cptr, cfaces,
                   float(log_g_ref), bool(exact), kf, kfu, kfv, P, Pu, Pv, status)
    return P, Pu, Pv, status


# --------------------------------------------------------------------------- coverage mask


# --------------------------------------------------------------------------- normals


