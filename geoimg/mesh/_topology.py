"""Topology of a polygon mesh from its position indices: components, boundary loops, genus."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from ..errors import InputError
from ._mesh import Mesh, once

__all__ = ["Topology", "topology", "boundary_loops", "boundary_edges", "edge_uses", "corner_fans"]


@dataclass(frozen=True)
class Topology:
    """Counts that decide which parametrization a mesh can have.

    ``genus`` is ``(2 components - euler - boundary_loops) / 2``, valid for a manifold mesh; it is None
    when some edge has more than two faces.

    Parameters
    ----------
    vertices, edges, faces : int
        The counts of referenced vertices, distinct edges and faces.
    components : int
        Connected pieces.
    boundary_loops, boundary_edges : int
        Boundary loops and edges with one face.
    nonmanifold_edges : int
        Edges with more than two faces.
    euler : int
        ``vertices - edges + faces``.
    genus : int or None
        The genus (None when not manifold).
    nonmanifold_vertices : int
        Pinch vertices (several fans of faces).

    Examples
    --------
    >>> import geoimg
    >>> t = topology(geoimg.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))
    >>> t.euler, t.genus, t.boundary_edges
    (1, 0, 3)
    """

    vertices: int           # referenced by faces
    edges: int
    faces: int
    components: int
    boundary_loops: int
    boundary_edges: int
    nonmanifold_edges: int
    euler: int
    genus: int | None
    nonmanifold_vertices: int = 0    # pinch points: a vertex whose faces form more than one fan

    @property
    def closed(self) -> bool:
        """No boundary edge and no non-manifold edge or vertex.

        Examples
        --------
        >>> from geoimg.mesh import Mesh, topology
        >>> topology(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])).closed
        False
        """
        return self.boundary_edges == 0 and self.nonmanifold_edges == 0 and self.nonmanifold_vertices == 0

    def describe(self) -> str:
        """One line a user can read, e.g. ``closed surface of genus 1 (torus-like), 1 component``.

        Returns
        -------
        str
            The description.

        Examples
        --------
        >>> from geoimg.mesh import Mesh, topology
        >>> topology(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])).describe()
        'open surface with 1 boundary loop (a disk), 1 component'
        """
        parts = []
        if self.nonmanifold_edges or self.nonmanifold_vertices:
            what = []
            if self.nonmanifold_edges:
                what.append(f"{self.nonmanifold_edges} edges shared by more than two faces")
            if self.nonmanifold_vertices:
                what.append(f"{self.nonmanifold_vertices} vertices where separate fans of faces meet")
            parts.append(f"non-manifold ({'; '.join(what)})")
        elif self.closed:
            kind = {0: "sphere-like", 1: "torus-like"}.get(-1 if self.genus is None else self.genus,
                                                                f"{self.genus} handles")
            parts.append(f"closed surface of genus {self.genus} ({kind})")
        else:
            loops = "1 boundary loop" if self.boundary_loops == 1 else f"{self.boundary_loops} boundary loops"
            shape = "a disk" if self.boundary_loops == 1 and self.genus == 0 and self.components == 1 else \
                f"genus {self.genus}"
            parts.append(f"open surface with {loops} ({shape})")
        parts.append(f"{self.components} component" + ("s" if self.components != 1 else ""))
        return ", ".join(parts)


def topology(mesh: Mesh) -> Topology:
    """Count the topology of a mesh by position indices (UV seams do not split it).

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    Topology
        The counts.

    Examples
    --------
    >>> t = topology(Mesh(np.eye(4, 3), [[0, 1, 2], [0, 2, 3]]))
    >>> t.components, t.boundary_loops, t.genus, t.describe()
    (1, 1, 0, 'open surface with 1 boundary loop (a disk), 1 component')
    """
    return once(mesh, "topology", lambda: _topology(mesh))


def _topology(mesh: Mesh) -> Topology:
    f = mesh.faces
    valid = f >= 0
    a, b = f[valid], mesh.next_vertices()[valid]
    n = mesh.n_vertices
    lo, hi = np.minimum(a, b).astype(np.int64), np.maximum(a, b).astype(np.int64)
    keys, counts = np.unique(lo * n + hi, return_counts=True)        # 1-D keys: much faster than rows
    edges = np.stack([keys // n, keys % n], axis=1)
    used = mesh.referenced_vertices()
    adj = sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    n_comp, labels = connected_components(adj, directed=False)
    components = len(np.unique(labels[used]))
    bnd = edges[counts == 1]
    loops = 0
    if len(bnd):
        badj = sparse.coo_matrix((np.ones(len(bnd)), (bnd[:, 0], bnd[:, 1])), shape=(n, n))
        _, blabels = connected_components(badj, directed=False)
        loops = len(np.unique(blabels[np.unique(bnd)]))
    nonmanifold = int((counts > 2).sum())
    pinches = _pinch_vertices(mesh) if not nonmanifold else 0
    V, E, F = int(used.sum()), len(edges), len(f)
    euler = V - E + F
    twice = 2 * components - euler - loops
    genus = None if nonmanifold or pinches or twice % 2 else twice // 2
    return Topology(V, E, F, components, loops, len(bnd), nonmanifold, euler, genus, pinches)


def corner_fans(mesh: Mesh, *, across_nonmanifold: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The fan of every face corner: corners at one vertex are in one fan when their faces are joined
    across the edges at that vertex. Returns each valid corner's vertex (in ``mesh.faces[mesh.faces >= 0]``
    order) and its fan label. ``across_nonmanifold=False`` does not join faces across an edge that more
    than two faces share, so each of those faces starts a fan of its own there.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    across_nonmanifold : bool
        Join faces across edges of more than two faces.

    Returns
    -------
    vertex : numpy.ndarray
        Each valid corner's vertex.
    fan : numpy.ndarray
        Each valid corner's fan label (one label per fan, over the whole mesh).

    Examples
    --------
    >>> import geoimg
    >>> bowtie = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], [[0, 1, 2], [0, 3, 4]])
    >>> v, fan = corner_fans(bowtie)
    >>> len(set(fan[v == 0].tolist()))                  # the pinch vertex 0 has two fans
    2
    """
    joins_all = bool(across_nonmanifold) or not (edge_uses(mesh)[4] > 2).any()    # the same fans where no edge
    return once(mesh, ("corner_fans", joins_all), lambda: _corner_fans(mesh, joins_all))   # has more than two faces


def _corner_fans(mesh: Mesh, across_nonmanifold: bool) -> tuple[np.ndarray, np.ndarray]:
    f = mesh.faces
    valid = f >= 0
    corner_v = f[valid]
    nxt = mesh.next_vertices()[valid]
    k = mesh.face_sizes
    cols = np.arange(f.shape[1])[None, :]
    prv_idx = np.where(cols == 0, (k - 1)[:, None], cols - 1)
    prv = np.take_along_axis(f, prv_idx, axis=1)[valid]
    n_corners = len(corner_v)
    corner = np.arange(n_corners)
    # corners at v touching edge {v, w}; corners sharing a key are in one fan
    keys = np.concatenate([corner_v * mesh.n_vertices + nxt, corner_v * mesh.n_vertices + prv])
    owner = np.concatenate([corner, corner])
    order = np.argsort(keys, kind="stable")
    keys, owner = keys[order], owner[order]
    same = keys[1:] == keys[:-1]
    if not across_nonmanifold:
        _, counts = np.unique(keys, return_counts=True)
        run = np.repeat(counts, counts)
        same &= run[1:] == 2
    adj = sparse.coo_matrix((np.ones(int(same.sum())), (owner[:-1][same], owner[1:][same])),
                            shape=(n_corners, n_corners))
    _, label = connected_components(adj, directed=False)
    return corner_v, label


def _pinch_vertices(mesh: Mesh) -> int:
    """Vertices whose incident faces fall into more than one fan (faces joined across the edges at the
    vertex): the pinch points of an edge-manifold mesh.
    """
    corner_v, label = corner_fans(mesh)
    n_corners = len(corner_v)
    fans = np.unique(corner_v.astype(np.int64) * n_corners + label)
    per_vertex = np.bincount(fans // n_corners, minlength=mesh.n_vertices)
    return int((per_vertex > 1).sum())


def boundary_edges(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """The edges used by one face, as their faces run them: start and end vertex indices.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    start, end : numpy.ndarray
        (B,) vertex indices each.

    Examples
    --------
    >>> a, b = boundary_edges(Mesh(np.eye(4, 3), [[0, 1, 2], [0, 2, 3]]))
    >>> sorted(zip(a.tolist(), b.tolist()))
    [(0, 1), (1, 2), (2, 3), (3, 0)]
    """
    a, b, _, inv, counts = edge_uses(mesh)
    lone = counts[inv] == 1
    return a[lone], b[lone]


def edge_uses(mesh: Mesh) -> tuple:
    """Every face edge as its face runs it, and how many faces use its undirected edge: ``(start, end,
    valid, inverse, counts)``, ``start``/``end`` the vertices of the corners ``mesh.faces[valid]`` and their
    next ones, ``counts[inverse]`` each edge's number of faces.

    Examples
    --------
    >>> a, b, valid, inv, counts = edge_uses(Mesh(np.eye(4, 3), [[0, 1, 2], [0, 2, 3]]))
    >>> counts[inv].tolist()
    [1, 1, 2, 2, 1, 1]
    """
    return once(mesh, "edge_uses", lambda: _edge_uses(mesh))


def _edge_uses(mesh: Mesh) -> tuple:
    f = mesh.faces
    valid = f >= 0
    a, b = f[valid], mesh.next_vertices()[valid]
    key = np.minimum(a, b) * mesh.n_vertices + np.maximum(a, b)
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    return a, b, valid, inv, counts


def boundary_loops(mesh: Mesh) -> list[np.ndarray]:
    """The boundary loops of a manifold mesh as ordered vertex indices, each running the way its faces'
    edges do (counter-clockwise around the surface for counter-clockwise faces).

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    list of numpy.ndarray
        One array of vertex indices per loop.

    Raises
    ------
    InputError
        When the boundary is not manifold or the faces' orientations disagree.

    Examples
    --------
    >>> [loop.tolist() for loop in boundary_loops(Mesh(np.eye(4, 3), [[0, 1, 2], [0, 2, 3]]))]
    [[0, 1, 2, 3]]
    """
    a, b = boundary_edges(mesh)
    nxt = {}
    for s, t in zip(a.tolist(), b.tolist()):
        if s in nxt:
            raise InputError("boundary_loops: a vertex starts two boundary edges (the boundary is not manifold)")
        nxt[s] = t
    loops, seen = [], set()
    for start in sorted(nxt):
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = nxt.get(v)
            if v is None:
                raise InputError("boundary_loops: a boundary edge leads nowhere (inconsistent face orientation)")
        loops.append(np.array(loop, np.int64))
    return loops
