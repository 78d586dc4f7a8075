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
from numba import njit

from ._orientation import facing_out

__all__ = ["simplify", "progressive_sphere"]


def _link_ok(u, v, nbrs, faces_of, tris) -> tuple[bool, list]:
    """The link condition for collapsing edge (u, v) of a closed manifold: the two faces on the edge,
    and no other common neighbour."""
    shared = [f for f in faces_of[v] if u in tris[f]]
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
        changed = [f for f in faces_of[v] if f not in shared]
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
def _scores(s, faces, v, cand):
    """For each candidate position of ``v``, the smallest orientation ``det(a, b, c)`` over ``faces``."""
    out = np.empty(cand.shape[0])
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
        out[k] = worst
    return out


def _place(s, v, u, faces, n_changed):
    """A position for the returning vertex ``v`` (next to ``u``) with every face of ``v`` positive.

    ``faces`` are v's faces, the last ``n_changed`` of them the ones that were u's while v was away;
    v belongs in the sector at ``u`` those filled, close enough to ``u``. Candidates lie on the rays from
    ``u`` to the mean of v's neighbours (a Tutte step), to each such face's centroid, along the wedge that
    the two faces holding u and v allow, and in 48 directions round ``u``, at steps 1, 1/2, 1/4, ... of
    the distance to the neighbours; the one whose smallest face is largest wins (so the new faces are not
    needlessly small).
    """
    ring = np.unique(faces)
    su = s[u]
    others = s[ring[(ring != v) & (ring != u)]]
    targets = [others.mean(axis=0)]
    for f in faces[len(faces) - n_changed:]:
        targets.append(s[np.where(f == v, u, f)].mean(axis=0))
    reach = float(np.linalg.norm(others - su, axis=1).mean())
    t1 = np.cross(su, [1.0, 0.0, 0.0] if abs(su[0]) < 0.9 else [0.0, 1.0, 0.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(su, t1)
    ang = np.linspace(0.0, 2 * np.pi, 48, endpoint=False)
    # the faces holding both u and v are flat while v sits on u; each turns positive as v moves along its
    # gradient det(v, b, c) = v . (b x c): the sum of the unit gradients points into the wedge they allow
    wedge = np.zeros(3)
    for f in faces:
        if u in f:
            j = int(np.flatnonzero(f == v)[0])
            g = np.cross(s[f[(j + 1) % 3]], s[f[(j + 2) % 3]])
            g -= (g @ su) * su
            wedge += g / max(np.linalg.norm(g), 1e-300)
    ends = np.vstack([targets, su + reach * wedge / max(np.linalg.norm(wedge), 1e-300),
                      su + reach * (np.cos(ang)[:, None] * t1 + np.sin(ang)[:, None] * t2)])
    steps = 0.5 ** np.arange(40)
    cand = (su + (ends - su)[:, None, :] * steps[None, :, None]).reshape(-1, 3)
    cand /= np.linalg.norm(cand, axis=1, keepdims=True)
    score = _scores(s, np.ascontiguousarray(faces, np.int64), int(v), cand)
    best = int(np.argmax(score))
    if score[best] > 0:
        s[v] = cand[best]
        return True
    s[v] = su
    return False


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
    misplaced = 0
    next_relax = int(count * growth)
    for i, (v, u, removed, changed) in enumerate(reversed(records)):
        for f in changed:
            cur[f][cur[f] == u] = v
        for f, row in removed:
            cur[f] = row
        alive[v] = True
        count += 1
        faces = cur[[f for f, _ in removed] + list(changed)]
        if not _place(s, v, u, faces, len(changed)):
            misplaced += 1
        if count >= next_relax or i == len(records) - 1:
            s = relax(s, alive, cur[cur[:, 0] >= 0])
            next_relax = int(count * growth)
            if progress is not None:
                progress(f"{count} vertices on the sphere")
    s[~used] = [0.0, 0.0, 1.0]
    return s, {"coarse_vertices": int(len(x) - len(records)), "misplaced": misplaced}
