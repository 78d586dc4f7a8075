"""A closed triangle mesh decimated by edge collapses to the midpoint, shortest edge first: the coarse copy
that :mod:`._multilevel` maps.

The rules are libigl's ``decimate`` (Jacobson et al.) with its default cost and placement: the shortest edge
goes first, its two endpoints merge at its midpoint, the vertex of the smaller index stays; a collapse that
would break the link condition (or flatten a tetrahedron) is refused, and the refused edge is tried again only
once a collapse beside it has changed the faces around it. Here in numba, without the GIL, so that the fine
mesh's Sobolev factor is made meanwhile (:func:`._balance.sobolev_factor_later`): the same coarse mesh as
libigl's, bit for bit, on the twelve closed meshes of 14k-100k faces measured, 1.4-2.0x faster
(``benchmarks/bench_decimate.py``). Edges of exactly one length go by their vertex numbers here, by libigl's
edge numbers there: where many tie (a UV sphere's rings) the two copies differ, each as good.

Examples
--------
>>> import trimesh
>>> ball = trimesh.creation.icosphere(3)                  # 1,280 triangles
>>> U, G = decimate(ball.vertices, ball.faces, 300)
>>> len(G) <= 300, len(U) == len(G) // 2 + 2              # still a closed genus-0 surface
(True, True)
"""
from __future__ import annotations

import heapq

import numpy as np
from numba import njit

from ._vertex_tables import collapse, edge_heap, has, may_collapse, tables

__all__ = ["decimate", "ROW"]

ROW = 24        # at least this many neighbours a vertex may gain (its row's width; libigl has no such bound)


@njit(cache=True)
def _length(x, a, b):
    """``|x[a] - x[b]|``, summed in libigl's order (so the same edges tie and the same one goes first)."""
    d0, d1, d2 = x[a, 0] - x[b, 0], x[a, 1] - x[b, 1], x[a, 2] - x[b, 2]
    return np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@njit(cache=True)
def _refuse(tris, faces, n_faces, refused, u, v):
    """Mark the edge ``(u, v)`` refused in each of its faces (it goes back on the heap when a face changes)."""
    for j in range(n_faces[u]):
        f = faces[u, j]
        for i in range(3):
            p, q = tris[f, i], tris[f, (i + 1) % 3]
            if (p == u and q == v) or (p == v and q == u):
                refused[f, i] = True


@njit(cache=True, nogil=True)
def _collapse_to(x, tris, target, cap):
    """Collapse edges of ``tris`` (in place; removed rows -1) and move ``x`` (in place) until at most
    ``target`` triangles are left or no edge may go; returns which vertices are left.
    """
    nbrs, n_nbrs, faces, n_faces, alive = tables(tris, len(x), cap)
    lengths = np.empty(tris.shape)
    for f in range(len(tris)):
        for i in range(3):
            lengths[f, i] = _length(x, tris[f, i], tris[f, (i + 1) % 3])
    heap = edge_heap(tris, lengths)
    left = len(tris)
    refused = np.zeros((len(tris), 3), np.bool_)
    shared = np.empty(2, np.int64)
    while left > target and len(heap) > 0:
        length, u, v = heapq.heappop(heap)          # u < v: u stays
        if not (alive[u] and alive[v] and has(nbrs, n_nbrs, u, v)) or length != _length(x, u, v):
            continue                                # gone, or moved since (a newer entry is on the heap)
        if (n_nbrs[u] + n_nbrs[v] - 4 > cap or (n_nbrs[u] == 3 and n_nbrs[v] == 3)      # a lone tetrahedron stays
                or not may_collapse(tris, nbrs, n_nbrs, faces, n_faces, u, v, shared)):
            _refuse(tris, faces, n_faces, refused, u, v)
            continue
        collapse(tris, nbrs, n_nbrs, faces, n_faces, alive, u, v, shared)
        for d in range(3):
            x[u, d] = 0.5 * (x[u, d] + x[v, d])
        left -= 2
        for j in range(n_faces[u]):                # the edges round u: those at u moved, those refused retried
            f = faces[u, j]
            for i in range(3):
                p, q = tris[f, i], tris[f, (i + 1) % 3]
                if p != u and q != u:
                    if not refused[f, i]:
                        continue
                    refused[f, i] = False
                heapq.heappush(heap, (_length(x, p, q), min(p, q), max(p, q)))
    return alive


def decimate(x: np.ndarray, tris: np.ndarray, triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """The closed manifold triangle mesh ``x, tris`` decimated to at most ``triangles`` triangles (fewer
    collapses where no edge may go; none where it has no more: libigl's collapses one edge even then); the
    inputs are left as they are.

    Parameters
    ----------
    x : (n, 3) float
        Vertices.
    tris : (T, 3) int
        Triangles of a closed manifold surface (every edge on two of them).
    triangles : int
        The most triangles to keep.

    Returns
    -------
    U, G : numpy.ndarray
        The coarse mesh's vertices (float64, those left in their order) and triangles (int64, in their order).
    """
    xx = np.array(x, dtype=np.float64)
    t = np.array(tris, dtype=np.int64)
    valence = np.bincount(t.ravel(), minlength=len(xx))
    alive = _collapse_to(xx, t, int(triangles), max(int(valence.max(initial=0)), ROW) + 1)
    index = np.cumsum(alive) - 1
    return np.ascontiguousarray(xx[alive]), index[t[t[:, 0] >= 0]]
