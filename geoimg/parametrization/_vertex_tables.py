"""Each vertex's neighbours and faces as rows of a fixed width, for edge collapses in numba (no Python objects):
built once from the triangles, then changed collapse by collapse.

Examples
--------
Collapsing the edge (0, 1) of a tetrahedron's two faces on it leaves vertex 0 with the two other faces.

>>> tris = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
>>> nbrs, n_nbrs, faces, n_faces, alive = tables(tris, 4, 4)
>>> shared = np.empty(2, np.int64)
>>> bool(may_collapse(tris, nbrs, n_nbrs, faces, n_faces, 0, 1, shared)), shared.tolist()
(True, [0, 1])
"""
from __future__ import annotations

import heapq

import numpy as np
from numba import njit

__all__ = ["tables", "edge_heap", "may_collapse", "collapse", "remove", "add", "has"]


@njit(cache=True)
def remove(table, count, i, item):
    """Take ``item`` out of row ``i`` (the last one moves into its place)."""
    for k in range(count[i]):
        if table[i, k] == item:
            count[i] -= 1
            table[i, k] = table[i, count[i]]
            return


@njit(cache=True)
def add(table, count, i, item):
    """Put ``item`` in row ``i`` unless it is there; a full row raises ValueError."""
    for k in range(count[i]):
        if table[i, k] == item:
            return
    if count[i] == table.shape[1]:      # cannot happen on a closed manifold; never write past the row
        raise ValueError("edge collapses: a vertex has more neighbours or faces than a closed manifold allows")
    table[i, count[i]] = item
    count[i] += 1


@njit(cache=True)
def has(table, count, i, item):
    """Whether row ``i`` holds ``item``."""
    for k in range(count[i]):
        if table[i, k] == item:
            return True
    return False


@njit(cache=True)
def tables(tris, n, cap):
    """``(nbrs, n_nbrs, faces, n_faces, alive)`` of the triangles ``tris`` on ``n`` vertices: rows of ``cap``
    neighbours and faces, how many each row holds, and which vertices are on a triangle.
    """
    nbrs = np.empty((n, cap), np.int64)
    n_nbrs = np.zeros(n, np.int64)
    faces = np.empty((n, cap), np.int64)
    n_faces = np.zeros(n, np.int64)
    alive = np.zeros(n, np.bool_)
    for f in range(len(tris)):
        for i in range(3):
            w = tris[f, i]
            alive[w] = True
            add(faces, n_faces, w, f)
            add(nbrs, n_nbrs, w, tris[f, (i + 1) % 3])
            add(nbrs, n_nbrs, w, tris[f, (i + 2) % 3])
    return nbrs, n_nbrs, faces, n_faces, alive


@njit(cache=True)
def edge_heap(tris, lengths):
    """Every edge ``(a, b)``, ``a < b``, of the triangles ``tris`` (each on two of them) as a heap of ``(length,
    a, b)``, ``lengths[f, i]`` the length of the edge from corner ``i`` of triangle ``f`` to the next: the
    shortest first, ties by vertex numbers.
    """
    heap = [(0.0, 0, 0)]
    heap.pop()
    for f in range(len(tris)):
        for i in range(3):
            a, b = tris[f, i], tris[f, (i + 1) % 3]
            if a < b:
                heap.append((lengths[f, i], a, b))
    heapq.heapify(heap)
    return heap


@njit(cache=True)
def may_collapse(tris, nbrs, n_nbrs, faces, n_faces, u, v, shared):
    """The link condition of the edge ``(u, v)``: two faces on it (written to ``shared``, ascending), their
    third corners distinct and the endpoints' only common neighbours (the surface stays a closed manifold).
    """
    m = 0
    for j in range(n_faces[v]):
        f = faces[v, j]
        if tris[f, 0] == u or tris[f, 1] == u or tris[f, 2] == u:
            if m < 2:
                shared[m] = f
            m += 1
    if m != 2:
        return False
    if shared[0] > shared[1]:
        shared[0], shared[1] = shared[1], shared[0]
    o0 = tris[shared[0], 0] + tris[shared[0], 1] + tris[shared[0], 2] - u - v
    o1 = tris[shared[1], 0] + tris[shared[1], 1] + tris[shared[1], 2] - u - v
    common = 0
    for j in range(n_nbrs[u]):
        if has(nbrs, n_nbrs, v, nbrs[u, j]):
            common += 1
    return o0 != o1 and common == 2


@njit(cache=True)
def collapse(tris, nbrs, n_nbrs, faces, n_faces, alive, u, v, shared):
    """Collapse ``v`` into ``u``: the two faces ``shared`` removed (their rows set to -1), ``v``'s other faces
    given ``u``, the neighbour rows merged, ``v`` no longer alive.
    """
    for r in range(2):
        f = shared[r]
        for i in range(3):
            remove(faces, n_faces, tris[f, i], f)
        tris[f] = -1
    for j in range(n_faces[v]):
        f = faces[v, j]
        for i in range(3):
            if tris[f, i] == v:
                tris[f, i] = u
        add(faces, n_faces, u, f)
    n_faces[v] = 0
    for j in range(n_nbrs[v]):
        w = nbrs[v, j]
        remove(nbrs, n_nbrs, w, v)
        if w != u:
            add(nbrs, n_nbrs, w, u)
            add(nbrs, n_nbrs, u, w)
    n_nbrs[v] = 0
    alive[v] = False
