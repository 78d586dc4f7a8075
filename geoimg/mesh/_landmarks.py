"""Suggested landmarks: a mesh's extremities (the tips of limbs, ears, tails), found as local maxima of the
average geodesic distance (Zhang, Liu and Wang's "feature points" of 2005; Hilaga et al. 2001): a point far,
on average, from everywhere else on the surface is at the end of something that sticks out.

Geodesic distances are shortest paths along the mesh's edges (Dijkstra), from a farthest-point sample of
sources; a local maximum is a vertex whose average distance is the largest within a geodesic radius of it,
and maxima are kept largest first, no two within that radius of each other. With ``spread``, a mesh with
fewer extremities than asked for is filled up by farthest-point sampling: each further point the vertex
geodesically farthest from every point already picked (elbows, knees, the chest of a figure).
"""
from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components, dijkstra

from ..errors import InputError, MeshError
from ._mesh import Mesh

__all__ = ["suggest_landmarks", "average_geodesic_distance", "SOURCES", "RADIUS"]

SOURCES = 48        # Dijkstra sources of the average (farthest-point sample)
RADIUS = 0.15       # of the largest average distance: a maximum rules over this geodesic radius


def _edge_graph(mesh: Mesh) -> sparse.csr_matrix:
    """The mesh's edges as a symmetric sparse matrix of their lengths."""
    f, nxt = mesh.faces, mesh.next_vertices()
    valid = f >= 0
    a, b = f[valid], nxt[valid]
    length = np.linalg.norm(mesh.vertices[a] - mesh.vertices[b], axis=1)
    length = np.maximum(length, 1e-12 * max(mesh.bounding_box_diagonal(), 1e-300))   # coincident ends still join
    n = mesh.n_vertices
    g = sparse.coo_matrix((length, (a, b)), shape=(n, n)).tocsr()
    return g.maximum(g.T).tocsr()


def average_geodesic_distance(mesh: Mesh, sources: int = SOURCES) -> np.ndarray:
    """Each vertex's mean edge-path distance to ``sources`` vertices spread over the surface by farthest-point
    sampling (NaN for vertices no face uses).

    Raises
    ------
    MeshError
        If the mesh has several pieces (distances between them are infinite): repair it into pieces first.

    Parameters
    ----------
    mesh : Mesh
        A mesh of one piece.
    sources : int
        How many source vertices (fewer when the mesh has fewer).

    Returns
    -------
    numpy.ndarray
        (N,) the mean distance per vertex, in the mesh's units.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0.1], [0, 1, 0]], [[0, 1, 3], [1, 2, 3]])
    >>> d = average_geodesic_distance(m)
    >>> int(np.argmax(d))                        # the far corner
    2
    """
    return _average_distance(mesh, _edge_graph(mesh), sources)


def _average_distance(mesh: Mesh, g: sparse.csr_matrix, sources: int) -> np.ndarray:
    """:func:`average_geodesic_distance` over the edge graph ``g`` already built."""
    used = mesh.referenced_vertices()
    n_pieces, label = connected_components(g[used][:, used], directed=False)
    if n_pieces > 1:
        raise MeshError(f"mesh: {n_pieces} separate pieces; landmarks are found on one piece at a time "
                        "(geoimg.mesh.repair splits them)")
    start = int(np.flatnonzero(used)[0])
    chosen, nearest, total = [], np.full(mesh.n_vertices, np.inf), np.zeros(mesh.n_vertices)
    for _ in range(min(int(sources), int(used.sum()))):
        d = dijkstra(g, indices=start)
        chosen.append(start)
        total += d
        nearest = np.minimum(nearest, d)
        start = int(np.argmax(np.where(used, nearest, -1.0)))
    return np.where(used, total / len(chosen), np.nan)


def suggest_landmarks(mesh: Mesh, count: int = 8, *, radius: float = RADIUS, spread: bool = False) -> np.ndarray:
    """Up to ``count`` vertex indices at the mesh's extremities, most extreme first: local maxima of
    :func:`average_geodesic_distance` over a geodesic ball of ``radius`` times its largest value, no two
    closer than that. With ``spread``, exactly ``count`` (as many as the mesh has vertices at most): after
    the extremities, each further point the vertex geodesically farthest from all those picked.

    Parameters
    ----------
    mesh : Mesh
        A mesh of one piece.
    count : int
        How many landmarks at most.
    radius : float
        The share of the largest average distance within which a maximum must be the largest.
    spread : bool
        Fill up to ``count`` with the farthest points.

    Returns
    -------
    numpy.ndarray
        Vertex indices (int64), most extreme first.

    Raises
    ------
    InputError
        When ``count`` is not a positive whole number or ``radius`` not in (0, 1).
    MeshError
        When the mesh has several pieces.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 11)
    >>> v = np.array([[x, y, 0.0] for y in t for x in t]) * [4, 1, 1]     # a long strip: its two ends
    >>> i = np.arange(121).reshape(11, 11)
    >>> f = np.concatenate([np.stack([i[:-1, :-1], i[:-1, 1:], i[1:, 1:]], -1).reshape(-1, 3),
    ...                     np.stack([i[:-1, :-1], i[1:, 1:], i[1:, :-1]], -1).reshape(-1, 3)])
    >>> sorted({round(float(x)) for x in Mesh(v, f).vertices[suggest_landmarks(Mesh(v, f), 2), 0]})
    [0, 4]
    >>> len(suggest_landmarks(Mesh(v, f), 5, spread=True))
    5
    """
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise InputError(f"count: expected a positive whole number of landmarks, got {count!r}")
    if not (isinstance(radius, (int, float, np.floating)) and 0 < radius < 1):
        raise InputError(f"radius: expected a fraction between 0 and 1, got {radius!r}")
    g = _edge_graph(mesh)
    agd = _average_distance(mesh, g, SOURCES)
    reach = radius * float(np.nanmax(agd))
    value = np.where(np.isnan(agd), -np.inf, agd)
    around = np.full(mesh.n_vertices, -np.inf)      # the largest value among each vertex's neighbours
    rows = np.flatnonzero(np.diff(g.indptr) > 0)
    around[rows] = np.maximum.reduceat(value[g.indices], g.indptr[rows])
    candidates = np.flatnonzero(np.isfinite(value) & (value >= around))   # maxima of their first ring
    picked: list[int] = []
    taken = np.zeros(mesh.n_vertices, bool)          # within reach of a landmark already picked
    for v in candidates[np.argsort(value[candidates])[::-1]]:
        if len(picked) == count:
            break
        if taken[v]:
            continue
        ball = np.isfinite(dijkstra(g, indices=int(v), limit=reach))
        if agd[v] >= np.nanmax(agd[ball]):            # the largest around it: an extremity, not a slope
            picked.append(int(v))
            taken |= ball
    if spread and len(picked) < count:
        picked = _farthest_points(g, picked, count, np.isfinite(value))
    return np.array(picked, np.int64)


def _farthest_points(g: sparse.csr_matrix, picked: list[int], count: int, usable: np.ndarray) -> list[int]:
    """``picked`` filled up to ``count`` (at most the usable vertices) by farthest-point sampling of the
    edge graph's distances.
    """
    picked = list(picked)
    nearest = np.full(g.shape[0], np.inf)
    if picked:
        nearest = dijkstra(g, indices=picked, min_only=True)
    while len(picked) < min(count, int(usable.sum())):
        v = int(np.argmax(np.where(usable, nearest, -1.0)))
        picked.append(v)
        nearest = np.minimum(nearest, dijkstra(g, indices=v))
    return picked
