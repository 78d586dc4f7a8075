"""numba kernels of the area-balancing energy of a map onto the sphere or the plane (see :mod:`._balance`),
and its Gauss-Newton metrics (see :mod:`._newton`).

``E = sum_t a_t [log(A_t / a_t)^2 + beta (D_t / A_t - 2)]`` over triangles ``t``: ``a_t`` the mesh's
triangle areas (summing to 1), ``A_t`` the mapped triangles' areas scaled to sum 1, and ``D_t`` the
Dirichlet energy of the triangle's affine map (cotangent formula with the mesh's corner cotangents
``cot``). On the sphere (``planar=False``) ``A_t`` is the chord triangle's area projected on its mean
direction; on the plane (points ``(u, v, 0)``, ``planar=True``) its area seen from +z. The plain numpy
version is ``tests/reference.py``'s ``AreaBalanceNumpy``; both give the same numbers.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["mapped_areas", "balance_energy", "balance_gradient", "project_moves", "step_to", "local_sweeps",
           "colouring", "gauss_newton_metric", "gauss_newton_metric_sphere"]


@njit(cache=True, inline="always")
def _corner(s, tris, t, k):
    v = tris[t, k]
    return s[v, 0], s[v, 1], s[v, 2]


@njit(cache=True, inline="always")
def _direction(s, tris, t, planar):
    """The direction triangle ``t`` is seen from: +z on the plane, its corners' sum on the sphere; and the
    sum's length (1 on the plane).
    """
    if planar:
        return 0.0, 0.0, 1.0, 1.0
    x0, y0, z0 = _corner(s, tris, t, 0)
    x1, y1, z1 = _corner(s, tris, t, 1)
    x2, y2, z2 = _corner(s, tris, t, 2)
    ux, uy, uz = x0 + x1 + x2, y0 + y1 + y2, z0 + z1 + z2
    return ux, uy, uz, math.sqrt(ux * ux + uy * uy + uz * uz)


@njit(cache=True, inline="always")
def _area(s, tris, t, planar):
    """Triangle ``t``'s projected area."""
    x0, y0, z0 = _corner(s, tris, t, 0)
    x1, y1, z1 = _corner(s, tris, t, 1)
    x2, y2, z2 = _corner(s, tris, t, 2)
    ux, uy, uz, ln = _direction(s, tris, t, planar)
    ax, ay, az = x1 - x0, y1 - y0, z1 - z0
    bx, by, bz = x2 - x0, y2 - y0, z2 - z0
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    return 0.5 * (cx * ux + cy * uy + cz * uz) / ln if ln > 0.0 else 0.0


@njit(parallel=True, cache=True)
def _areas(s, tris, planar, out):
    """Projected areas into ``out``; returns the number of triangles that are not positive."""
    bad = 0
    for t in prange(tris.shape[0]):
        area = _area(s, tris, t, planar)
        out[t] = area
        if not area > 0.0:
            bad += 1
    return bad


@njit(cache=True, inline="always")
def _term(s, tris, t, a, cot, area, lam, beta):
    """Triangle ``t``'s part of the energy, of area ``area``: ``(term, its Dirichlet energy, log r_t)``."""
    dsum = 0.0
    for k in range(3):
        k1, k2 = (k + 1) % 3, (k + 2) % 3
        l2 = 0.0
        for d in range(3):
            dv = s[tris[t, k1], d] - s[tris[t, k2], d]
            l2 += dv * dv
        dsum += cot[t, k] * l2
    dd = 0.5 * lam * dsum
    ay = lam * area
    lr = math.log(ay / a[t]) if a[t] > 0.0 else 0.0     # a face of no area on the mesh: no term
    return a[t] * lr * lr + beta * a[t] * (dd / ay - 2.0), dd, lr


CHUNK = 1024      # triangles per partial sum: fixed, so that the sums do not depend on the number of threads


@njit(parallel=True, cache=True)
def _terms(s, tris, a, cot, area, lam, beta, dirichlet):
    """The energy, and ``sum a_t log r_t`` (what the areas' normalization adds to the gradient). Each chunk of
    ``CHUNK`` triangles is summed in order, then the chunks' sums in order: the same bits on any number of
    threads (a reduction over ``prange`` adds in an order that depends on them).
    """
    n = tris.shape[0]
    n_chunks = -(-n // CHUNK)
    e_part = np.zeros(n_chunks)
    log_part = np.zeros(n_chunks)
    for c in prange(n_chunks):
        e = 0.0
        mean_log = 0.0
        for t in range(c * CHUNK, min(n, (c + 1) * CHUNK)):
            et, dd, lr = _term(s, tris, t, a, cot, area[t], lam, beta)
            dirichlet[t] = dd
            e += et
            mean_log += a[t] * lr
        e_part[c] = e
        log_part[c] = mean_log
    e = 0.0
    mean_log = 0.0
    for c in range(n_chunks):
        e += e_part[c]
        mean_log += log_part[c]
    return e, mean_log


def mapped_areas(s, tris, planar=False):
    """Each triangle's area in the map (as the energy sees it: on the sphere its chord triangle's, projected on
    its mean direction), and how many are not positive.

    >>> s = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> area, bad = mapped_areas(s, np.array([[0, 1, 2], [0, 2, 1]]), True)
    >>> area.tolist(), bad
    ([0.5, -0.5], 1)
    """
    area = np.empty(len(tris))
    bad = _areas(s, tris, bool(planar), area)
    return area, int(bad)


def balance_energy(s, tris, a, cot, beta, planar=False):
    """Energy of unit vectors ``s`` (n, 3), or of points ``(u, v, 0)`` with ``planar``; ``(inf, None)`` if a
    triangle is not positive, else ``(E, state)`` with the state :func:`balance_gradient` needs.
    """
    area = np.empty(len(tris))
    if _areas(s, tris, bool(planar), area):
        return np.inf, None
    lam = 1.0 / area.sum()
    dirichlet = np.empty(len(tris))
    e, mean_log = _terms(s, tris, a, cot, area, lam, float(beta), dirichlet)
    return float(e), (area, lam, dirichlet, float(mean_log), bool(planar))


@njit(cache=True, inline="always")
def _factors(a_t, ay, dd, lr, lam, beta):
    """The derivatives of a triangle's term by its Dirichlet energy and by its area, times ``lam``."""
    return beta * a_t / ay * lam, (2.0 * a_t * lr / ay - beta * a_t * dd / ay ** 2) * lam


@njit(cache=True, inline="always")
def _turning(s, tris, t, planar):
    """Triangle ``t``'s unit direction and what its turning adds to every corner's area gradient."""
    ux, uy, uz, ln = _direction(s, tris, t, planar)
    ux, uy, uz = ux / ln, uy / ln, uz / ln
    # area = 0.5 (e1 x e2) . u with u the normalized corner sum: on the sphere its turning adds, to every
    # corner, 0.5 (n - (n . u) u) / |p0 + p1 + p2| with n = e1 x e2 (on the plane u is fixed)
    tx, ty, tz = 0.0, 0.0, 0.0
    if not planar:
        i0, i1, i2 = tris[t, 0], tris[t, 1], tris[t, 2]
        ax, ay_, az = s[i1, 0] - s[i0, 0], s[i1, 1] - s[i0, 1], s[i1, 2] - s[i0, 2]
        bx, by, bz = s[i2, 0] - s[i0, 0], s[i2, 1] - s[i0, 1], s[i2, 2] - s[i0, 2]
        nx, ny, nz = ay_ * bz - az * by, az * bx - ax * bz, ax * by - ay_ * bx
        nu = nx * ux + ny * uy + nz * uz
        tx, ty, tz = 0.5 * (nx - nu * ux) / ln, 0.5 * (ny - nu * uy) / ln, 0.5 * (nz - nu * uz) / ln
    return ux, uy, uz, tx, ty, tz


@njit(cache=True, inline="always")
def _corner_gradient(s, tris, t, k, cot, f_d, f_a, ux, uy, uz, tx, ty, tz):
    """The gradient of triangle ``t``'s term with respect to its corner ``k``."""
    vk, v1, v2 = tris[t, k], tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]
    c1, c2 = cot[t, (k + 1) % 3], cot[t, (k + 2) % 3]
    ex = s[v2, 0] - s[v1, 0]
    ey = s[v2, 1] - s[v1, 1]
    ez = s[v2, 2] - s[v1, 2]
    gx = (0.5 * (uy * ez - uz * ey) + tx) * f_a + f_d * (c2 * (s[vk, 0] - s[v1, 0]) + c1 * (s[vk, 0] - s[v2, 0]))
    gy = (0.5 * (uz * ex - ux * ez) + ty) * f_a + f_d * (c2 * (s[vk, 1] - s[v1, 1]) + c1 * (s[vk, 1] - s[v2, 1]))
    gz = (0.5 * (ux * ey - uy * ex) + tz) * f_a + f_d * (c2 * (s[vk, 2] - s[v1, 2]) + c1 * (s[vk, 2] - s[v2, 2]))
    return gx, gy, gz


@njit(parallel=True, cache=True)
def _corner_gradients(s, tris, a, cot, area, lam, beta, dirichlet, shift, planar, out):
    """Each triangle's gradient with respect to its three corners, (T, 3, 3), in parallel."""
    for t in prange(tris.shape[0]):
        ay = lam * area[t]
        lr = math.log(ay / a[t]) if a[t] > 0.0 else 0.0     # a face of no area on the mesh: no term
        f_d, f_a = _factors(a[t], ay, dirichlet[t], lr, lam, beta)
        f_a -= shift
        ux, uy, uz, tx, ty, tz = _turning(s, tris, t, planar)
        for k in range(3):
            out[t, k, 0], out[t, k, 1], out[t, k, 2] = _corner_gradient(s, tris, t, k, cot, f_d, f_a,
                                                                        ux, uy, uz, tx, ty, tz)


@njit(cache=True)
def _scatter(tris, corner, g):
    for t in range(tris.shape[0]):
        for k in range(3):
            v = tris[t, k]
            for c in range(3):
                g[v, c] += corner[t, k, c]


def balance_gradient(s, tris, a, cot, beta, state):
    """Gradient (n, 3) of the energy at ``s``."""
    area, lam, dirichlet, mean_log, planar = state
    # the areas' normalization lam = 1 / sum(area) depends on every area too: d lam / d area_t = -lam^2
    # (summed in the energy's kernel: a numpy dot here would wake BLAS threads that fight numba's)
    shift = 2.0 * lam * mean_log
    corner = np.empty((len(tris), 3, 3))
    _corner_gradients(s, tris, a, cot, area, lam, float(beta), dirichlet, shift, planar, corner)
    g = np.zeros_like(s)
    _scatter(tris, corner, g)
    return g


SWEEP_HALVINGS = 10     # a single vertex's step is halved at most this many times a sweep


@njit(cache=True)
def _ring_energy(s, tris, ring, a, cot, lam, beta, planar):
    """The energy of the triangles ``ring`` (inf if one is not positive)."""
    e = 0.0
    for t in ring:
        area = _area(s, tris, t, planar)
        if not area > 0.0:
            return np.inf
        e += _term(s, tris, t, a, cot, area, lam, beta)[0]
    return e


@njit(cache=True)
def _to_neighbours(s, tris, mine, i, a, cot, lam, beta, planar, free):
    """Move vertex ``i`` (free to move in every direction) towards the mean of its triangles' other corners, as
    far as makes all its triangles positive (the whole way, or half, a quarter, ...); 1 if it moved.
    """
    if not free:
        return 0
    mx, my, mz = 0.0, 0.0, 0.0
    for t in mine:
        for k in range(3):
            w = tris[t, k]
            if w != i:
                mx, my, mz = mx + s[w, 0], my + s[w, 1], mz + s[w, 2]
    m = 2.0 * len(mine)
    mx, my, mz = mx / m, my / m, mz / m
    x0, y0, z0 = s[i, 0], s[i, 1], s[i, 2]
    share = 1.0
    for _half in range(SWEEP_HALVINGS):
        x, y, z = x0 + share * (mx - x0), y0 + share * (my - y0), z0 + share * (mz - z0)
        if not planar:
            ln = math.sqrt(x * x + y * y + z * z)
            x, y, z = x / ln, y / ln, z / ln
        s[i, 0], s[i, 1], s[i, 2] = x, y, z
        if _ring_energy(s, tris, mine, a, cot, lam, beta, planar) < np.inf:
            return 1
        share *= 0.5
    s[i, 0], s[i, 1], s[i, 2] = x0, y0, z0
    return 0


@njit(cache=True)
def colouring(tris, ring_ptr, ring, n):
    """A colour per vertex such that no two vertices of one triangle share one (greedy, in vertex order: the
    least colour no neighbour has), and the number of colours. Vertices of one colour move independently:
    none is on another's triangles.

    >>> import numpy as np
    >>> tris = np.array([[0, 1, 2], [0, 2, 3]])
    >>> colour, count = colouring(tris, np.array([0, 2, 3, 5, 6]), np.array([0, 1, 0, 0, 1, 1]), 4)
    >>> colour.tolist(), count
    ([0, 1, 2, 1], 3)
    """
    colour = np.full(n, -1, np.int64)
    seen = np.full(n + 1, -1, np.int64)      # seen[c] == i: a neighbour of i has colour c
    count = 0
    for i in range(n):
        for t in ring[ring_ptr[i]:ring_ptr[i + 1]]:
            for k in range(3):
                w = tris[t, k]
                if w != i and colour[w] >= 0:
                    seen[colour[w]] = i
        c = 0
        while seen[c] == i:
            c += 1
        colour[i] = c
        count = max(count, c + 1)
    return colour, count


@njit(parallel=True, cache=True)
def local_sweeps(s, tris, ring_ptr, ring, a, cot, beta, planar, moves, along, sweeps, reach):
    """Move the vertices one at a time, in place, each down its own triangles' energy (the areas'
    normalization held for a sweep): a step along the vertex's own gradient, halved until its triangles'
    energy falls and all stay positive. Each vertex keeps its step length from sweep to sweep (doubled after
    a success, at most ``reach`` times its shortest edge). ``ring[ring_ptr[i]:ring_ptr[i + 1]]`` are vertex
    ``i``'s triangles. Unlike a step of every vertex at once, which the most squeezed triangle holds back,
    each vertex moves as far as its own triangles allow, so a map stays one-to-one while its crowded parts
    spread. A vertex on a triangle that is not positive (none of its moves can lower an infinite energy)
    moves instead towards its neighbours' mean, as far as makes its triangles positive, if it may move
    freely. A sweep takes the vertices colour by colour (:func:`colouring`), those of one colour in
    parallel: none reads what another writes, so the map is the same on any number of threads. Returns the
    number of moves made.
    """
    n = s.shape[0]
    colour, count = colouring(tris, ring_ptr, ring, n)
    order = np.argsort(colour, kind="mergesort")          # by colour, vertices ascending within one
    start = np.zeros(count + 1, np.int64)
    for i in range(n):
        start[colour[i] + 1] += 1
    for c in range(count):
        start[c + 1] += start[c]
    area = np.empty(tris.shape[0])
    length = np.full(n, np.inf)        # each vertex's last step, as a share of its shortest edge
    made = 0
    for _ in range(sweeps):
        _areas(s, tris, planar, area)
        total = 0.0
        for t in range(tris.shape[0]):       # in order: the same sum on any thread count
            total += area[t]
        if not total > 0.0:            # every triangle flat or turned over: no areas to balance
            break
        lam = 1.0 / total
        for c in range(count):
            for k in prange(start[c], start[c + 1]):
                i = order[k]
                mine = ring[ring_ptr[i]:ring_ptr[i + 1]]
                if moves[i] and len(mine) > 0:
                    made += _sweep_vertex(s, tris, mine, i, a, cot, lam, beta, planar, along, length, reach)
    return made


@njit(cache=True)
def _sweep_vertex(s, tris, mine, i, a, cot, lam, beta, planar, along, length, reach):
    """One vertex's move of :func:`local_sweeps` (1 when it moved)."""
    h = np.inf
    for t in mine:
        for k in range(3):
            w = tris[t, k]
            if w != i:
                h = min(h, math.sqrt((s[w, 0] - s[i, 0]) ** 2 + (s[w, 1] - s[i, 1]) ** 2 + (s[w, 2] - s[i, 2]) ** 2))
    e0 = 0.0                        # its triangles' energy (as _ring_energy sums it) and its gradient, in one pass
    gx, gy, gz = 0.0, 0.0, 0.0
    for t in mine:
        area_t = _area(s, tris, t, planar)
        if not area_t > 0.0:       # a triangle of the vertex is not positive: towards its neighbours' mean
            return _to_neighbours(s, tris, mine, i, a, cot, lam, beta, planar, not _slides(along, i))
        et, dd, lr = _term(s, tris, t, a, cot, area_t, lam, beta)
        e0 += et
        ay = lam * area_t
        f_d, f_a = _factors(a[t], ay, dd, lr, lam, beta)
        ux, uy, uz, tx, ty, tz = _turning(s, tris, t, planar)
        k = 0 if tris[t, 0] == i else (1 if tris[t, 1] == i else 2)
        cx, cy, cz = _corner_gradient(s, tris, t, k, cot, f_d, f_a, ux, uy, uz, tx, ty, tz)
        gx, gy, gz = gx + cx, gy + cy, gz + cz
    gx, gy, gz = _project(gx, gy, gz, s, i, planar, along)
    size = math.sqrt(gx * gx + gy * gy + gz * gz)
    if not size > 0.0:
        return 0
    x0, y0, z0 = s[i, 0], s[i, 1], s[i, 2]
    share = min(2.0 * length[i], reach)
    moved = 0
    for _half in range(SWEEP_HALVINGS):
        step = share * h / size
        x, y, z = x0 - step * gx, y0 - step * gy, z0 - step * gz
        if not planar:
            ln = math.sqrt(x * x + y * y + z * z)
            x, y, z = x / ln, y / ln, z / ln
        s[i, 0], s[i, 1], s[i, 2] = x, y, z
        if _ring_energy(s, tris, mine, a, cot, lam, beta, planar) < e0:
            moved = 1
            break
        s[i, 0], s[i, 1], s[i, 2] = x0, y0, z0
        share *= 0.5
    length[i] = share
    return moved


@njit(cache=True, inline="always")
def _slides(along, i):
    """Whether vertex ``i`` may only slide along the line ``along[i]`` (a row that is not zero)."""
    return along[i, 0] != 0.0 or along[i, 1] != 0.0 or along[i, 2] != 0.0


@njit(cache=True, inline="always")
def _project(gx, gy, gz, s, i, planar, along):
    """The move ``(gx, gy, gz)`` of a movable vertex ``i`` projected onto the moves it may make: the tangent
    plane at ``s[i]`` on the sphere; on the plane, the plane itself, or its line ``along[i]``.
    """
    if planar:
        if _slides(along, i):
            p = gx * along[i, 0] + gy * along[i, 1]
            return p * along[i, 0], p * along[i, 1], p * along[i, 2]
        return gx, gy, 0.0
    p = gx * s[i, 0] + gy * s[i, 1] + gz * s[i, 2]
    return gx - p * s[i, 0], gy - p * s[i, 1], gz - p * s[i, 2]


@njit(parallel=True, cache=True)
def project_moves(v, s, planar, moves, along):
    """Project each row of ``v`` (n, 3), in place, onto the moves its vertex may make: the tangent plane at
    ``s[i]`` on the sphere; on the plane, the plane itself, or the line ``along[i]`` where that row is not
    zero; nothing where ``moves[i]`` is False.
    """
    for i in prange(v.shape[0]):
        if not moves[i]:
            v[i, 0] = 0.0
            v[i, 1] = 0.0
            v[i, 2] = 0.0
        else:
            v[i, 0], v[i, 1], v[i, 2] = _project(v[i, 0], v[i, 1], v[i, 2], s, i, planar, along)


@njit(parallel=True, cache=True)
def step_to(s, d, alpha, planar, out):
    """``out = s + alpha d``, each row put back on the unit sphere unless ``planar``."""
    for i in prange(s.shape[0]):
        x = s[i, 0] + alpha * d[i, 0]
        y = s[i, 1] + alpha * d[i, 1]
        z = s[i, 2] + alpha * d[i, 2]
        if not planar:
            n = math.sqrt(x * x + y * y + z * z)
            x, y, z = x / n, y / n, z / n
        out[i, 0], out[i, 1], out[i, 2] = x, y, z


@njit(cache=True)
def gauss_newton_metric(s, tris, a, cot, beta, slot, out_u, out_v):
    """The Gauss-Newton metric of the planar energy at the map ``s`` (points ``(u, v, 0)``, every triangle
    positive), u and v apart: ``sum_t 2 a_t / A_t^2 grad A_t grad A_t^T + beta a_t / A_t H_t`` (the log
    term's Gauss-Newton part, the angle term's convex part; ``H_t`` the triangle's cotangent stencil), its u
    block added into ``out_u`` and its v block into ``out_v`` (both zeroed first) at ``slot[t, k, l]``, the
    place of the entry (corner k, corner l) of triangle ``t`` in a sparse matrix's values. Serial, triangle
    by triangle: the same sums on any thread count.
    """
    out_u[:] = 0.0
    out_v[:] = 0.0
    gu = np.empty(3)
    gv = np.empty(3)
    for t in range(tris.shape[0]):
        for k in range(3):           # d area / d corner k: half the opposite edge turned a quarter
            i, j = tris[t, (k + 1) % 3], tris[t, (k + 2) % 3]
            gu[k] = 0.5 * (s[i, 1] - s[j, 1])
            gv[k] = 0.5 * (s[j, 0] - s[i, 0])
        area = _area(s, tris, t, True)
        w_area = 2.0 * a[t] / (area * area)
        w_angle = beta * a[t] / area
        for k in range(3):
            for m in range(3):
                out_u[slot[t, k, m]] += w_area * gu[k] * gu[m]
                out_v[slot[t, k, m]] += w_area * gv[k] * gv[m]
        for k in range(3):
            i, j = (k + 1) % 3, (k + 2) % 3
            c = w_angle * cot[t, k]
            for p, q, sign in ((i, i, 1.0), (j, j, 1.0), (i, j, -1.0), (j, i, -1.0)):
                out_u[slot[t, p, q]] += sign * c
                out_v[slot[t, p, q]] += sign * c


@njit(cache=True)
def gauss_newton_metric_sphere(s, tris, a, cot, beta, basis, slot, out):
    """The Gauss-Newton metric of the energy on the sphere at the map ``s`` (unit vectors, every triangle
    positive), in each vertex's tangent plane: ``basis[i]`` (3, 2) holds two orthonormal tangents at
    ``s[i]``, and vertex ``i``'s unknowns are its moves along them (rows ``2 i`` and ``2 i + 1``). The same
    terms as :func:`gauss_newton_metric` (``grad A_t`` the chord triangle's projected area's exact gradient,
    its turning included; ``H_t`` the cotangent stencil of the triangle's Dirichlet energy in space), added
    into ``out`` (zeroed first) at ``slot[t, p, q]``, the place of the entry of triangle ``t``'s unknowns
    ``p = 2 k + c`` and ``q`` (corner ``k``, tangent ``c``). Serial: the same sums on any thread count.
    """
    out[:] = 0.0
    jac = np.empty(6)
    for t in range(tris.shape[0]):
        area = _area(s, tris, t, False)
        ux, uy, uz, tx, ty, tz = _turning(s, tris, t, False)
        for k in range(3):           # d area / d corner k (f_d = 0, f_a = 1), along the corner's tangents
            gx, gy, gz = _corner_gradient(s, tris, t, k, cot, 0.0, 1.0, ux, uy, uz, tx, ty, tz)
            v = tris[t, k]
            for c in range(2):
                jac[2 * k + c] = gx * basis[v, 0, c] + gy * basis[v, 1, c] + gz * basis[v, 2, c]
        w_area = 2.0 * a[t] / (area * area)
        w_angle = beta * a[t] / area
        for p in range(6):
            for q in range(6):
                out[slot[t, p, q]] += w_area * jac[p] * jac[q]
        for k in range(3):           # the edge opposite corner k: (i, i), (j, j) +c I; (i, j), (j, i) -c B_i^T B_j
            i, j = (k + 1) % 3, (k + 2) % 3
            vi, vj = tris[t, i], tris[t, j]
            c = w_angle * cot[t, k]
            for ci in range(2):
                out[slot[t, 2 * i + ci, 2 * i + ci]] += c
                out[slot[t, 2 * j + ci, 2 * j + ci]] += c
                for cj in range(2):
                    bb = (basis[vi, 0, ci] * basis[vj, 0, cj] + basis[vi, 1, ci] * basis[vj, 1, cj]
                          + basis[vi, 2, ci] * basis[vj, 2, cj])
                    out[slot[t, 2 * i + ci, 2 * j + cj]] -= c * bb
                    out[slot[t, 2 * j + cj, 2 * i + ci]] -= c * bb
