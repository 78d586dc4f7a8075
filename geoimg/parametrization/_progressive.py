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

import numpy as np
from numba import njit, types
from numba.extending import intrinsic

from ._orientation import facing_out

__all__ = ["simplify", "progressive_sphere"]


def _link_ok(u, v, nbrs, faces_of, tris) -> tuple[bool, list]:
    """The link condition for collapsing edge (u, v) of a closed manifold: the two faces on the edge,
    and no other common neighbour."""
    shared = sorted(f for f in faces_of[v] if u in tris[f])
    if len(shared) != 2:
        return False, shared
    opposite = {int(w) for f in shared for w in tris[f] if w != u and w != v}
    return (nbrs[u] & nbrs[v]) == opposite and len(opposite) == 2, shared


def simplify(x: np.ndarray, tris: np.ndarray, target: int, max_valence: int = 12):
    """Half-edge collapses, shortest edge first, until ``target`` vertices remain (or no edge may go).

    Returns ``(alive, tris, records)``: the vertices left (bool mask), the coarse triangles (as an array
    whose removed rows are -1) and, in order, each collapse as ``(v, u, removed_faces, changed_faces)``
    with the removed faces' rows as they were.
    """
    tris = np.array(tris, dtype=np.int64)
    n = len(x)
    faces_of: list[set[int]] = [set() for _ in range(n)]
    for f, t in enumerate(tris):
        for w in t:
            faces_of[w].add(f)
    nbrs: list[set[int]] = [set() for _ in range(n)]
    for t in tris:
        for i in range(3):
            nbrs[t[i]].update((t[(i + 1) % 3], t[(i + 2) % 3]))
    alive = np.zeros(n, bool)
    alive[np.unique(tris)] = True
    count = int(alive.sum())
    heap = []
    for t in tris:
        for i in range(3):
            a, b = int(t[i]), int(t[(i + 1) % 3])
            if a < b:
                heap.append((float(np.linalg.norm(x[a] - x[b])), a, b))
    heapq.heapify(heap)
    records = []
    while count > target and heap:
        _, a, b = heapq.heappop(heap)
        if not (alive[a] and alive[b] and b in nbrs[a]):
            continue
        # remove the endpoint of lower valence (keeps the coarse mesh's valences even)
        v, u = (a, b) if len(nbrs[a]) <= len(nbrs[b]) else (b, a)
        if len(nbrs[u]) + len(nbrs[v]) - 4 > max_valence:
            continue
        ok, shared = _link_ok(u, v, nbrs, faces_of, tris)
        if not ok:
            continue
        removed = [(f, tris[f].copy()) for f in shared]
        changed = sorted(f for f in faces_of[v] if f not in shared)
        for f, _ in removed:
            for w in tris[f]:
                faces_of[w].discard(f)
            tris[f] = -1
        for f in changed:
            tris[f][tris[f] == v] = u
            faces_of[u].add(f)
        faces_of[v] = set()
        for w in nbrs[v]:
            nbrs[w].discard(v)
            if w != u:
                nbrs[w].add(u)
                nbrs[u].add(w)
        nbrs[u].discard(v)
        nbrs[v] = set()
        alive[v] = False
        count -= 1
        records.append((v, u, removed, changed))
        for w in nbrs[u]:
            heapq.heappush(heap, (float(np.linalg.norm(x[u] - x[w])), min(u, w), max(u, w)))
    return alive, tris, records


@njit(cache=True)
def _best_candidate(s, faces, v, cand):
    """The first candidate position of ``v`` whose smallest orientation ``det(a, b, c)`` over ``faces`` is
    largest, and that orientation. A candidate is dropped as soon as one of its faces is no better than
    the best so far (it cannot win), so the result is the argmax of the full scores."""
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
    # the mean of v's neighbours, summed row by row
    mean = np.zeros(3)
    k = 0
    for w in ring:
        if w != v and w != u:
            mean += s[w]
            k += 1
    ends[0] = mean / k
    for i in range(n_changed):
        f = faces[len(faces) - n_changed + i]
        c = np.zeros(3)
        for j in range(3):
            c += s[u if f[j] == v else f[j]]
        ends[1 + i] = c / 3
    # the mean distance to the neighbours, summed pairwise as numpy does
    dist = np.empty(k)
    k = 0
    for w in ring:
        if w != v and w != u:
            d = s[w] - su
            dist[k] = np.sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2])
            k += 1
    reach = _pairwise_sum(dist) / k
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
            for c in range(3):
                cand[row, c] /= size
    best, score = _best_candidate(s, faces, v, cand)
    if score > 0:
        s[v] = cand[best]
        return True
    s[v] = su
    return False


@njit(cache=True)
def _pairwise_sum(a):
    """numpy's sum of a 1-D float64 array (pairwise, eight running sums in blocks of up to 128)."""
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
def _grow(s, cur, alive, undo, start, stop, cosines, sines, halves):
    """Undo the collapses ``start .. stop - 1`` of ``undo`` (:func:`_undo_arrays`), placing each returning
    vertex with :func:`_place`; ``cur`` and ``alive`` follow. Returns how many found no fold-free place."""
    rec_v, rec_u, rem_ptr, rem_f, rem_rows, chg_ptr, chg_f = undo
    misplaced = 0
    for k in range(start, stop):
        v, u = rec_v[k], rec_u[k]
        for j in range(chg_ptr[k], chg_ptr[k + 1]):
            f = chg_f[j]
            for c in range(3):
                if cur[f, c] == u:
                    cur[f, c] = v
        for j in range(rem_ptr[k], rem_ptr[k + 1]):
            cur[rem_f[j]] = rem_rows[j]
        alive[v] = True
        n_rem, n_chg = rem_ptr[k + 1] - rem_ptr[k], chg_ptr[k + 1] - chg_ptr[k]
        faces = np.empty((n_rem + n_chg, 3), np.int64)
        for j in range(n_rem):
            faces[j] = cur[rem_f[rem_ptr[k] + j]]
        for j in range(n_chg):
            faces[n_rem + j] = cur[chg_f[chg_ptr[k] + j]]
        if not _place(s, v, u, faces, n_chg, cosines, sines, halves):
            misplaced += 1
    return misplaced


def _undo_arrays(records):
    """The collapses in the order they are undone, as flat arrays for :func:`_grow`."""
    rec = records[::-1]
    rem = [r[2] for r in rec]
    chg = [r[3] for r in rec]
    rem_ptr = np.concatenate([[0], np.cumsum([len(r) for r in rem])]).astype(np.int64)
    chg_ptr = np.concatenate([[0], np.cumsum([len(c) for c in chg])]).astype(np.int64)
    rem_f = np.array([f for r in rem for f, _ in r], np.int64)
    rem_rows = np.array([row for r in rem for _, row in r], np.int64).reshape(-1, 3)
    chg_f = np.array([f for c in chg for f in c], np.int64)
    return (np.array([r[0] for r in rec], np.int64), np.array([r[1] for r in rec], np.int64),
            rem_ptr, rem_f, rem_rows, chg_ptr, chg_f)


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
    alive, coarse, records = simplify(x, tris, max(target, 4))
    live = coarse[coarse[:, 0] >= 0]
    count = int(alive.sum())
    s = _tetrahedron(len(x), alive, live) if count == 4 else coarse_map(alive, live)
    if progress is not None:
        progress(f"coarse mesh of {count} vertices mapped; {len(records)} vertices to put back")
    cur = coarse.copy()
    undo = _undo_arrays(records)
    cosines, sines = np.cos(_DIRECTIONS), np.sin(_DIRECTIONS)
    misplaced = 0
    start, total = 0, len(records)
    while start < total:
        next_relax = int(count * growth)
        stop = min(total, start + max(1, next_relax - count))
        misplaced += _grow(s, cur, alive, undo, start, stop, cosines, sines, _HALVES)
        count += stop - start
        start = stop
        s = relax(s, alive, cur[cur[:, 0] >= 0])
        if progress is not None:
            progress(f"{count} vertices on the sphere")
    s[~used] = [0.0, 0.0, 1.0]
    return s, {"coarse_vertices": int(len(x) - len(records)), "misplaced": misplaced}
