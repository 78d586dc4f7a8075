"""A fold-free spherical map for shapes whose conformal map underflows (fingers, blades), after Praun &
Hoppe (2003): simplify the mesh by half-edge collapses, map the coarse mesh onto the sphere, then undo
the collapses one by one, placing each returning vertex inside its neighbourhood so that no triangle
turns over, and relax the map by area balancing every time the mesh has grown by a quarter.

A half-edge collapse ``v -> u`` keeps ``u`` where it is, so every intermediate mesh is made of the
original vertices at their original positions: the area-balancing energy of the full mesh applies to
each of them unchanged.
"""
from __future__ import annotations

import heapq
from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.extending import intrinsic

from ._orientation import facing_out
from ._vertex_tables import collapse, edge_heap, has, may_collapse, tables

__all__ = ["simplify", "progressive_sphere"]


class Collapses(NamedTuple):
    """Half-edge collapses ``v -> u`` in the order they were made: the two faces each removed (``removed``,
    their rows as they were in ``rows``) and the faces that changed ``v`` to ``u`` (``changed[changed_ptr[k]:
    changed_ptr[k + 1]]``, ascending).
    """

    v: np.ndarray
    u: np.ndarray
    removed: np.ndarray          # (k, 2)
    rows: np.ndarray             # (k, 2, 3)
    changed_ptr: np.ndarray      # (k + 1,)
    changed: np.ndarray


def simplify(x: np.ndarray, tris: np.ndarray, target: int, max_valence: int = 12):
    """Half-edge collapses, shortest edge first (ties by vertex numbers), until ``target`` vertices remain or
    no edge may go: an edge goes when the two faces on it are its endpoints' only shared neighbours (the
    link condition, so the surface stays a closed manifold) and the vertex it keeps has at most
    ``max_valence`` neighbours; the endpoint of lower valence is removed.

    Returns ``(alive, tris, collapses)``: the vertices left (bool mask), the coarse triangles (as an array
    whose removed rows are -1) and the :class:`Collapses`.
    """
    tris = np.array(tris, dtype=np.int64)
    valence = np.bincount(tris.ravel(), minlength=len(x))
    alive, out = _collapse(np.ascontiguousarray(x, np.float64), tris, int(target),
                           int(max_valence), max(int(valence.max()), int(max_valence)) + 1)
    return alive, tris, Collapses(*out)


@njit(cache=True)
def _length(x, a, b):
    d = x[a] - x[b]
    return np.sqrt(_dot(d, d))


@njit(cache=True)
def _collapse(x, tris, target, max_valence, cap):
    """:func:`simplify`'s collapses, in place on ``tris``; neighbours and faces of each vertex in rows of
    ``cap`` (no vertex gains any: the kept one has at most ``max_valence``).
    """
    n = len(x)
    nbrs, n_nbrs, faces, n_faces, alive = tables(tris, n, cap)
    lengths = np.empty(tris.shape)
    for f in range(len(tris)):
        for i in range(3):
            lengths[f, i] = _length(x, tris[f, i], tris[f, (i + 1) % 3])
    heap = edge_heap(tris, lengths)
    count = int(alive.sum())
    rec_v = np.empty(n, np.int64)
    rec_u = np.empty(n, np.int64)
    rec_removed = np.empty((n, 2), np.int64)
    rec_rows = np.empty((n, 2, 3), np.int64)
    changed_ptr = np.zeros(n + 1, np.int64)
    changed = np.empty(n * cap, np.int64)
    k = 0
    shared = np.empty(cap, np.int64)
    while count > target and len(heap) > 0:
        _, a, b = heapq.heappop(heap)
        if not (alive[a] and alive[b] and has(nbrs, n_nbrs, a, b)):
            continue
        v, u = (a, b) if n_nbrs[a] <= n_nbrs[b] else (b, a)
        if n_nbrs[u] + n_nbrs[v] - 4 > max_valence:
            continue
        if not may_collapse(tris, nbrs, n_nbrs, faces, n_faces, u, v, shared):
            continue
        base = changed_ptr[k]
        c = 0
        for j in range(n_faces[v]):
            f = faces[v, j]
            if f != shared[0] and f != shared[1]:
                changed[base + c] = f
                c += 1
        changed[base:base + c].sort()
        changed_ptr[k + 1] = base + c
        for r in range(2):
            rec_removed[k, r] = shared[r]
            rec_rows[k, r] = tris[shared[r]]
        collapse(tris, nbrs, n_nbrs, faces, n_faces, alive, u, v, shared)
        count -= 1
        rec_v[k], rec_u[k] = v, u
        k += 1
        for j in range(n_nbrs[u]):
            w = nbrs[u, j]
            heapq.heappush(heap, (_length(x, u, w), min(u, w), max(u, w)))
    return alive, (rec_v[:k].copy(), rec_u[:k].copy(), rec_removed[:k].copy(), rec_rows[:k].copy(),
                   changed_ptr[:k + 1].copy(), changed[:changed_ptr[k]].copy())


@njit(cache=True)
def _best_candidate(s, faces, v, cand):
    """The first candidate position of ``v`` whose smallest orientation ``det(a, b, c)`` over ``faces`` is
    largest, and that orientation. A candidate is dropped as soon as one of its faces is no better than
    the best so far (it cannot win), so the result is the argmax of the full scores.
    """
    best, best_score = 0, -np.inf
    p = np.empty((3, 3))
    for k in range(cand.shape[0]):
        worst = np.inf
        for f in range(faces.shape[0]):
            for j in range(3):
                w = faces[f, j]
                for c in range(3):
                    p[j, c] = cand[k, c] if w == v else s[w, c]
            det = (p[0, 0] * (p[1, 1] * p[2, 2] - p[1, 2] * p[2, 1])
                   - p[0, 1] * (p[1, 0] * p[2, 2] - p[1, 2] * p[2, 0])
                   + p[0, 2] * (p[1, 0] * p[2, 1] - p[1, 1] * p[2, 0]))
            if det < worst:
                worst = det
                if worst <= best_score:
                    break
        if worst > best_score:
            best, best_score = k, worst
    return best, best_score


@intrinsic
def _fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM's fma)."""
    def codegen(context, builder, signature, args):
        return builder.fma(*args)
    return types.float64(types.float64, types.float64, types.float64), codegen


@njit(cache=True)
def _dot(a, b):
    """A 3-vector dot product, fused as OpenBLAS's ``ddot`` does it."""
    return _fma(a[2], b[2], _fma(a[1], b[1], a[0] * b[0]))


@njit(cache=True)
def _cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@njit(cache=True)
def _place(s, v, u, faces, n_changed, cosines, sines, halves):
    """A position for the returning vertex ``v`` (next to ``u``) with every face of ``v`` positive.

    ``faces`` are v's faces, the last ``n_changed`` of them the ones that were u's while v was away;
    v belongs in the sector at ``u`` those filled, close enough to ``u``. Candidates lie on the rays from
    ``u`` to the mean of v's neighbours (a Tutte step), to each such face's centroid, along the wedge that
    the two faces holding u and v allow, and in the directions ``cosines, sines`` round ``u``, at the
    fractions ``halves`` (1, 1/2, 1/4, ...) of the distance to the neighbours; the one whose smallest face
    is largest wins (so the new faces are not needlessly small). Returns whether that face is positive;
    if not, ``v`` is left on ``u``.
    """
    ring = np.unique(faces.ravel())
    su = s[u].copy()
    n_ends = 2 + n_changed + len(cosines)
    ends = np.empty((n_ends, 3))
    # the mean of v's neighbours (summed row by row) and their mean distance (summed pairwise, as numpy does)
    mean = np.zeros(3)
    dist = np.empty(len(ring))
    k = 0
    for w in ring:
        if w != v and w != u:
            mean += s[w]
            d = s[w] - su
            dist[k] = np.sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2])
            k += 1
    ends[0] = mean / k
    reach = _pairwise_sum(dist[:k]) / k
    for i in range(n_changed):
        f = faces[len(faces) - n_changed + i]
        c = np.zeros(3)
        for j in range(3):
            c += s[u if f[j] == v else f[j]]
        ends[1 + i] = c / 3
    t1 = _cross(su, np.array([1.0, 0.0, 0.0]) if abs(su[0]) < 0.9 else np.array([0.0, 1.0, 0.0]))
    t1 /= np.sqrt(_dot(t1, t1))
    t2 = _cross(su, t1)
    # the faces holding both u and v are flat while v sits on u; each turns positive as v moves along its
    # gradient det(v, b, c) = v . (b x c): the sum of the unit gradients points into the wedge they allow
    wedge = np.zeros(3)
    for f in faces:
        if f[0] == u or f[1] == u or f[2] == u:
            j = 0 if f[0] == v else (1 if f[1] == v else 2)
            g = _cross(s[f[(j + 1) % 3]], s[f[(j + 2) % 3]])
            g -= _dot(g, su) * su
            wedge += g / max(np.sqrt(_dot(g, g)), 1e-300)
    ends[1 + n_changed] = su + reach * wedge / max(np.sqrt(_dot(wedge, wedge)), 1e-300)
    for i in range(len(cosines)):
        for c in range(3):
            ends[2 + n_changed + i, c] = su[c] + reach * (cosines[i] * t1[c] + sines[i] * t2[c])
    cand = np.empty((n_ends * len(halves), 3))
    for i in range(n_ends):
        for j in range(len(halves)):
            row = i * len(halves) + j
            for c in range(3):
                cand[row, c] = su[c] + (ends[i, c] - su[c]) * halves[j]
            size = np.sqrt((cand[row, 0] * cand[row, 0] + cand[row, 1] * cand[row, 1]) + cand[row, 2] * cand[row, 2])
            for c in range(3):      # a candidate at the sphere's centre (neighbours all round it): u itself
                cand[row, c] = cand[row, c] / size if size > 0 else su[c]
    best, score = _best_candidate(s, faces, v, cand)
    if score > 0:
        s[v] = cand[best]
        return True
    s[v] = su
    return False


@njit(cache=True)
def _pairwise_sum(a):
    """Numpy's sum of a 1-D float64 array (pairwise, eight running sums in blocks of up to 128)."""
    n = len(a)
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[i]
        return res
    if n <= 128:
        r = a[:8].copy()
        i = 8
        while i < n - n % 8:
            for j in range(8):
                r[j] += a[i + j]
            i += 8
        res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
        while i < n:
            res += a[i]
            i += 1
        return res
    half = n // 2
    half -= half % 8
    return _pairwise_sum(a[:half]) + _pairwise_sum(a[half:])


@njit(cache=True)
def _grow(s, cur, alive, collapses, start, stop, cosines, sines, halves):
    """Undo the ``start``-th to the ``stop - 1``-th last of the :class:`Collapses`, the last made first,
    placing each returning vertex with :func:`_place`; ``cur`` and ``alive`` follow. Returns how many
    found no fold-free place.
    """
    rec_v, rec_u, removed, rows, changed_ptr, changed = collapses
    misplaced = 0
    for i in range(start, stop):
        k = len(rec_v) - 1 - i
        v, u = rec_v[k], rec_u[k]
        for j in range(changed_ptr[k], changed_ptr[k + 1]):
            for c in range(3):
                if cur[changed[j], c] == u:
                    cur[changed[j], c] = v
        for r in range(2):
            cur[removed[k, r]] = rows[k, r]
        alive[v] = True
        n_chg = changed_ptr[k + 1] - changed_ptr[k]
        faces = np.empty((2 + n_chg, 3), np.int64)
        for r in range(2):
            faces[r] = cur[removed[k, r]]
        for j in range(n_chg):
            faces[2 + j] = cur[changed[changed_ptr[k] + j]]
        if not _place(s, v, u, faces, n_chg, cosines, sines, halves):
            misplaced += 1
    return misplaced


_DIRECTIONS = np.linspace(0.0, 2 * np.pi, 48, endpoint=False)
_HALVES = 0.5 ** np.arange(40)


def _tetrahedron(n, alive, coarse):
    """The four vertices left on a regular tetrahedron, turned so its faces run counter-clockwise."""
    s = np.zeros((n, 3))
    s[:, 2] = 1.0
    idx = np.flatnonzero(alive)
    s[idx] = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]) / np.sqrt(3.0)
    return facing_out(s, coarse)


def progressive_sphere(x, tris, used, coarse_map, relax, *, target: int = 4, growth: float = 1.25,
                       progress=None):
    """Unit vectors for the vertices of a closed genus-0 triangle mesh, built coarse to fine.

    The mesh is simplified down to ``target`` vertices (a tetrahedron by default, mapped onto a regular
    one; a coarser mesh that cannot be simplified further goes to ``coarse_map(alive, coarse_tris) -> s``);
    ``relax(s, alive, tris)`` improves a fold-free map of an intermediate mesh (area balancing). Returns
    ``(s, info)``; ``info`` counts the vertices that found no fold-free place (then left on their partner).
    """
    alive, coarse, collapses = simplify(x, tris, max(target, 4))
    live = coarse[coarse[:, 0] >= 0]
    count = int(alive.sum())
    s = _tetrahedron(len(x), alive, live) if count == 4 else coarse_map(alive, live)
    if progress is not None:
        progress(f"coarse mesh of {count} vertices mapped; {len(collapses.v)} vertices to put back")
    cur = coarse.copy()
    cosines, sines = np.cos(_DIRECTIONS), np.sin(_DIRECTIONS)
    misplaced = 0
    start, total = 0, len(collapses.v)
    while start < total:
        next_relax = int(count * growth)
        stop = min(total, start + max(1, next_relax - count))
        misplaced += _grow(s, cur, alive, collapses, start, stop, cosines, sines, _HALVES)
        count += stop - start
        start = stop
        s = relax(s, alive, cur[cur[:, 0] >= 0])
        if progress is not None:
            progress(f"{count} vertices on the sphere")
    s[~used] = [0.0, 0.0, 1.0]
    return s, {"coarse_vertices": int(len(x) - total), "misplaced": misplaced}
