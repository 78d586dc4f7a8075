"""Repairs that make a mesh a set of manifold, consistently oriented pieces, each reported, never silent.

- Faces of zero area (a repeated vertex, corners on a line) are left out, and so are faces that repeat
  another face's corners (a surface stored twice).
- A pinch vertex (faces meeting there in two or more separate fans) becomes one vertex per fan.
- An edge shared by more than two faces is separated: the faces there no longer join across it.
- Faces of a piece that run against their neighbours are turned to agree with the piece's majority; a
  piece that cannot be oriented (a Moebius strip) is refused.
- A mesh of several pieces (components) is split into one mesh per piece.

Positions are never moved or merged: a split vertex is copied.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from ..errors import MeshError
from ._mesh import Mesh, once, reverse_corners
from ._topology import corner_fans, edge_uses

SOUP_SHARE = 0.05      # a mesh with more than this share of its edges shared by 3 faces or more is refused ...
SOUP_EDGES = 100       # ... when they are at least this many
MAX_PIECES = 1000      # a mesh of more separate pieces is refused (each would be mapped on its own)

__all__ = [
    "Repair",
    "drop_degenerate_faces",
    "drop_inner_walls",
    "drop_duplicate_faces",
    "refuse_face_soup",
    "split_fans",
    "orient_faces",
    "split_components",
    "repair",
]


@dataclass(frozen=True)
class Repair:
    """What :func:`repair` did to one piece: the piece, where its vertices came from in the input
    (``source_vertices``, (N,)), and the counts of split pinch vertices, separated non-manifold edges and
    turned faces.

    Parameters
    ----------
    mesh : Mesh
        The repaired piece.
    source_vertices : numpy.ndarray
        (N,) each vertex's index in the input.
    pinches : int
        Pinch vertices split.
    nonmanifold_edges : int
        Non-manifold edges separated.
    flipped_faces : int
        Faces turned.

    Examples
    --------
    >>> import geoimg
    >>> square = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> r = repair(square)[0]
    >>> r.mesh.n_faces, r.source_vertices.tolist(), r.pinches
    (1, [0, 1, 2, 3], 0)
    """

    mesh: Mesh
    source_vertices: np.ndarray
    pinches: int = 0
    nonmanifold_edges: int = 0
    flipped_faces: int = 0


def drop_degenerate_faces(mesh: Mesh) -> tuple[Mesh, int]:
    """The mesh without faces of zero area: a vertex repeated (fewer than three distinct corners) or all
    corners on a line. Returns the mesh and how many faces were left out.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    mesh : Mesh
        The new mesh (the input is left as it is).
    count : int
        How many faces were left out.

    Raises
    ------
    MeshError
        When every face has zero area.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]], [[0, 1, 2], [0, 0, 1], [0, 1, 3]])
    >>> kept, dropped = drop_degenerate_faces(m)
    >>> kept.faces.tolist(), dropped
    ([[0, 1, 2]], 2)
    """
    scale = mesh.coordinate_scale()                  # before any product of coordinates: refused if it would overflow
    f, valid = mesh.faces, mesh.faces >= 0
    v = mesh.vertices
    p = v[np.where(valid, f, f[:, :1])]
    nxt = v[np.where(mesh.next_vertices() >= 0, mesh.next_vertices(), f[:, :1])]
    normal = (np.cross(p, nxt) * valid[..., None]).sum(axis=1)           # Newell: twice the vector area
    area = np.linalg.norm(normal, axis=1)
    keep = area > 1e-14 * max(scale, 1e-300) ** 2
    if keep.all():
        return mesh, 0
    if not keep.any():
        raise MeshError(f"mesh: all {mesh.n_faces} faces have zero area")
    return mesh.derived(f[keep], face_source=np.flatnonzero(keep)), int((~keep).sum())


def _face_sets(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each face's corners as a set, the sets numbered in order: the first face of each set, each face's
    set and each set's number of faces (one count for :func:`drop_inner_walls` and
    :func:`drop_duplicate_faces`; triangles by a single integer key, which sorts as the rows do).
    """
    return once(mesh, "face_sets", lambda: _count_face_sets(mesh.faces, mesh.n_vertices))


def _count_face_sets(f: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    key = np.sort(np.where(f >= 0, f, np.iinfo(np.int64).max), axis=1)     # the corners as a set (padding last)
    axis: int | None = 0
    if f.shape[1] == 3 and n < 2 ** 20:
        key, axis = (key[:, 0] * n + key[:, 1]) * n + key[:, 2], None      # rows sort as these keys do
    _, first, inverse, counts = np.unique(key, return_index=True, return_inverse=True, return_counts=True, axis=axis)
    return first, inverse.ravel(), counts


def _windings(f: np.ndarray) -> np.ndarray:
    """Each face's winding as seen from its smallest corner (True where the corner after it is smaller than
    the one before it).
    """
    valid = f >= 0
    sizes = valid.sum(axis=1)
    rows = np.arange(len(f))
    first = np.argmin(np.where(valid, f, np.iinfo(np.int64).max), axis=1)
    after = f[rows, (first + 1) % np.maximum(sizes, 1)]
    before = f[rows, (first - 1) % np.maximum(sizes, 1)]
    return after < before


def drop_inner_walls(mesh: Mesh) -> tuple[Mesh, int]:
    """The outer surface of the faces of a volume mesh: faces stored exactly twice with opposite windings
    (the wall between two cells, once for each) left out, both copies, where that leaves a surface and
    fewer edges shared by more than two faces than keeping one copy of each would. Returns the mesh and
    how many faces were left out (0, and the mesh as it is, for any other mesh: a two-sided sheet keeps
    its faces for :func:`drop_duplicate_faces`).

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    mesh : Mesh
        The outer surface (the input is left as it is).
    count : int
        How many faces were left out.

    Examples
    --------
    Two unit cubes side by side, each with its six faces: the wall between them is stored twice.

    >>> import itertools
    >>> v = [[x, y, z] for x, y, z in itertools.product(range(3), range(2), range(2))]
    >>> def cube(o):
    ...     c = [o + i for i in (0, 1, 2, 3, 4, 5, 6, 7)]
    ...     return [[c[0], c[1], c[3], c[2]], [c[4], c[6], c[7], c[5]], [c[0], c[4], c[5], c[1]],
    ...             [c[2], c[3], c[7], c[6]], [c[0], c[2], c[6], c[4]], [c[1], c[5], c[7], c[3]]]
    >>> outer, dropped = drop_inner_walls(Mesh(v, cube(0) + cube(4)))
    >>> outer.n_faces, dropped
    (10, 2)
    """
    f = mesh.faces
    _, inverse, counts = _face_sets(mesh)
    twice = counts[inverse] == 2
    if not twice.any():
        return mesh, 0
    winding = _windings(f)
    ups = np.bincount(inverse[twice], winding[twice].astype(np.int64), minlength=len(counts))
    wall = twice & (ups[inverse] == 1)                    # the two copies run opposite ways
    if not wall.any() or wall.all():
        return mesh, 0
    outer = mesh.derived(f[~wall], face_source=np.flatnonzero(~wall))
    one_copy, _ = drop_duplicate_faces(mesh)
    if (edge_uses(outer)[4] > 2).sum() >= (edge_uses(one_copy)[4] > 2).sum():
        return mesh, 0
    return outer, int(wall.sum())


def refuse_face_soup(mesh: Mesh) -> None:
    """Refuse, in one line that says what the file is, a mesh of which more than :data:`SOUP_SHARE` of the
    edges (and at least :data:`SOUP_EDGES`) are shared by three faces or more: the faces of a volume mesh
    stored once each, or a soup of faces, not a surface. Separating each such edge would leave thousands
    of pieces, each mapped on its own.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Raises
    ------
    MeshError
        For such a mesh.

    Examples
    --------
    >>> refuse_face_soup(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))     # a surface: nothing said
    """
    counts = edge_uses(mesh)[4]
    shared = int((counts > 2).sum())
    if shared >= SOUP_EDGES and shared > SOUP_SHARE * len(counts):
        raise MeshError(f"mesh: {shared} of its {len(counts)} edges are shared by 3 to {int(counts.max())} faces: "
                        "not a surface but the faces of a volume mesh or a soup of faces; geoimg needs a "
                        "surface (export the volume's outer surface, or its boundary faces)")


def drop_duplicate_faces(mesh: Mesh) -> tuple[Mesh, int]:
    """The mesh without faces that repeat an earlier face's corners (in any order or winding: a surface
    stored twice, or two-sided). Returns the mesh and how many faces were left out.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    mesh : Mesh
        The new mesh (the input is left as it is).
    count : int
        How many faces were left out.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2], [0, 2, 1], [0, 1, 3], [1, 2, 0]])
    >>> kept, dropped = drop_duplicate_faces(m)
    >>> kept.faces.tolist(), dropped
    ([[0, 1, 2], [0, 1, 3]], 2)
    """
    f = mesh.faces
    first = _face_sets(mesh)[0]
    if len(first) == len(f):
        return mesh, 0
    keep = np.zeros(len(f), bool)
    keep[first] = True
    return mesh.derived(f[keep], face_source=np.flatnonzero(keep)), int((~keep).sum())


def split_fans(mesh: Mesh) -> tuple[Mesh, np.ndarray, int, int]:
    """One vertex per fan of faces (see :func:`geoimg.mesh.corner_fans`), faces not joined across edges
    that more than two faces share. Returns the new mesh, each new vertex's source vertex, the number of
    pinch vertices split and the number of non-manifold edges separated.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    mesh : Mesh
        The mesh with one vertex per fan.
    source : numpy.ndarray
        (N',) each new vertex's vertex in the input.
    pinches : int
        Pinch vertices split.
    nonmanifold_edges : int
        Non-manifold edges separated.

    Examples
    --------
    >>> v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]]
    >>> f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 5, 4], [0, 4, 6], [0, 6, 5], [4, 5, 6]]
    >>> m, src, pinches, edges = split_fans(Mesh(v, f))      # two tetrahedra touching at vertex 0
    >>> m.n_vertices, pinches, edges, src[-1].item()
    (8, 1, 0, 0)
    """
    _, _, _, _, counts = edge_uses(mesh)
    n_nonmanifold = int((counts > 2).sum())
    corner_v, label = corner_fans(mesh, across_nonmanifold=False)
    n_corners = len(corner_v)
    fan_key = corner_v.astype(np.int64) * n_corners + label
    fans, fan_of_corner = np.unique(fan_key, return_inverse=True)
    fan_vertex = fans // n_corners
    # the first fan of each vertex keeps its index; the others become new vertices, in order
    first = np.ones(len(fans), bool)
    first[1:] = fan_vertex[1:] != fan_vertex[:-1]
    new_index = np.where(first, fan_vertex, mesh.n_vertices + np.cumsum(~first) - 1)
    extra = fan_vertex[~first]
    if not len(extra):                                  # one fan at every vertex: the mesh itself
        return mesh, np.arange(mesh.n_vertices), 0, n_nonmanifold
    pinch_vertices = int(len(np.unique(extra)))
    faces = mesh.faces.copy()
    faces[faces >= 0] = new_index[fan_of_corner]
    source = np.concatenate([np.arange(mesh.n_vertices), extra])
    out = mesh.derived(faces, vertex_source=source)
    return out, source, pinch_vertices, n_nonmanifold


def orient_faces(mesh: Mesh) -> tuple[Mesh, int]:
    """Faces turned so that every manifold edge runs opposite ways in its two faces (the majority of each
    piece keeps its winding). Returns the mesh and the number of faces turned.

    Raises
    ------
    MeshError
        If a piece is not orientable (a Moebius strip, a Klein bottle).

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    mesh : Mesh
        The mesh with its faces turned (a new one).
    count : int
        How many faces were turned.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3], [3, 2, 0][::-1]][:2])
    >>> orient_faces(geoimg.Mesh(m.vertices, [[0, 1, 2], [0, 3, 2]]))[1]
    1
    """
    a, b, valid, inv, counts = edge_uses(mesh)
    face_of = np.nonzero(valid)[0]
    manifold = counts[inv] == 2
    order = np.argsort(inv[manifold], kind="stable")
    pair_face = face_of[manifold][order].reshape(-1, 2)
    pair_dir = (a[manifold] < b[manifold])[order].reshape(-1, 2)
    same = pair_dir[:, 0] == pair_dir[:, 1]             # both faces run the edge the same way: one must turn
    F = mesh.n_faces
    f, g = pair_face[:, 0], pair_face[:, 1]
    # node f: face f as it is; node F + f: face f turned. "same" joins f with turned g, else f with g.
    rows = np.concatenate([f, F + f])
    cols = np.concatenate([np.where(same, F + g, g), np.where(same, g, F + g)])
    n, label = connected_components(sparse.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(2 * F, 2 * F)),
                                    directed=False)
    if np.any(label[:F] == label[F:]):
        raise MeshError("mesh: a piece of it is not orientable (like a Moebius strip): geoimg needs surfaces with "
                        "two sides")
    # in each pair of labels, keep the side that more faces are on as they are
    keep_votes = np.bincount(label[:F], minlength=n)
    turn_votes = np.bincount(label[F:], minlength=n)
    turn = keep_votes[label[:F]] < turn_votes[label[F:]]
    turn |= (keep_votes[label[:F]] == turn_votes[label[F:]]) & (label[:F] > label[F:])
    if not turn.any():
        return mesh, 0
    faces = reverse_corners(mesh.faces, mesh.face_sizes, np.flatnonzero(turn))
    return mesh.derived(faces, turned=turn), int(turn.sum())


def split_components(mesh: Mesh) -> list[tuple[Mesh, np.ndarray]]:
    """One mesh per connected piece (faces joined by shared vertices), largest first (by face count),
    each with the indices of its vertices in ``mesh``; unreferenced vertices are dropped. A mesh of more
    than :data:`MAX_PIECES` pieces is refused (:class:`~geoimg.errors.MeshError`).

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    list of tuple
        ``(piece, vertex_indices)`` per piece, largest first.

    Examples
    --------
    >>> import geoimg
    >>> two = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], [[0, 1, 2], [3, 4, 5]])
    >>> [idx.tolist() for _, idx in split_components(two)]
    [[0, 1, 2], [3, 4, 5]]
    """
    f = mesh.faces
    valid = f >= 0
    face_of = np.nonzero(valid)[0]
    rows, cols = mesh.n_vertices + face_of, f[valid]
    n = mesh.n_vertices + mesh.n_faces
    _, label = connected_components(sparse.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)),
                                    directed=False)
    face_label = label[mesh.n_vertices:]
    labels, sizes = np.unique(face_label, return_counts=True)
    if len(labels) == 1 and mesh.referenced_vertices().all():
        return [(mesh, np.arange(mesh.n_vertices))]     # one piece, every vertex on it: the mesh itself
    if len(labels) > MAX_PIECES:
        raise MeshError(f"mesh: {len(labels)} separate pieces (the largest of {int(sizes.max())} faces), more than "
                        f"the {MAX_PIECES} geoimg converts one by one: a soup of faces rather than a surface; "
                        "join its pieces (weld its vertices) first")
    order = np.argsort(face_label, kind="stable")           # each piece's faces together, in their order
    ends = np.cumsum(sizes)
    pieces = []
    remap = np.zeros(mesh.n_vertices, np.int64)     # one table for all pieces: each writes only its own vertices
    for end, size in zip(ends.tolist(), sizes.tolist()):
        chosen = order[end - size:end]
        faces = f[chosen]
        used = np.unique(faces[faces >= 0])
        remap[used] = np.arange(len(used))
        faces = np.where(faces >= 0, remap[np.where(faces >= 0, faces, 0)], -1)
        pieces.append((mesh.derived(faces, vertex_source=used, face_source=chosen), used))
    pieces.sort(key=lambda p: -p[0].n_faces)
    return pieces


def repair(mesh: Mesh) -> list[Repair]:
    """The mesh as manifold, consistently oriented pieces, largest first: pinch vertices split, non-manifold
    edges separated, faces turned to agree, pieces apart. Each repair is announced with a warning giving
    its count.

    Parameters
    ----------
    mesh : Mesh
        The mesh.

    Returns
    -------
    list of Repair
        One per piece, largest first.

    Raises
    ------
    MeshError
        When a piece cannot be oriented.

    Examples
    --------
    >>> import warnings
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], [[0, 1, 2], [3, 4, 5]])
    >>> with warnings.catch_warnings(record=True):
    ...     pieces = repair(m)
    >>> [p.source_vertices.tolist() for p in pieces]
    [[0, 1, 2], [3, 4, 5]]
    """
    mesh, dropped = drop_degenerate_faces(mesh)
    if dropped:
        warnings.warn(f"repair: left out {dropped} faces of zero area", stacklevel=2)
    mesh, walls = drop_inner_walls(mesh)
    if walls:
        warnings.warn(f"repair: the faces of a volume mesh: left out the {walls} faces stored twice with opposite "
                      f"windings (walls between its cells), keeping the outer surface ({mesh.n_faces} faces)",
                      stacklevel=2)
    mesh, doubled = drop_duplicate_faces(mesh)
    if doubled:
        warnings.warn(f"repair: left out {doubled} faces that repeat another face's corners (a surface stored "
                      "twice, or two-sided)", stacklevel=2)
    refuse_face_soup(mesh)
    split, source, pinches, edges = split_fans(mesh)
    if pinches:
        warnings.warn(f"repair: split {pinches} pinch vertices (faces meeting in separate fans) into one vertex "
                      "per fan", stacklevel=2)
    if edges:
        warnings.warn(f"repair: separated the faces at {edges} edges shared by more than two faces", stacklevel=2)
    pieces = split_components(split)
    if len(pieces) > 1:
        sizes = ", ".join(str(p.n_faces) for p, _ in pieces[:12]) + (f" and {len(pieces) - 12} more"
                                                                      if len(pieces) > 12 else "")
        warnings.warn(f"repair: the mesh has {len(pieces)} separate pieces; each becomes a mesh of its own "
                      f"(faces: {sizes})", stacklevel=2)
    out = []
    for piece, used in pieces:
        oriented, flipped = orient_faces(piece)
        if flipped:
            warnings.warn(f"repair: turned {flipped} of {piece.n_faces} faces to agree with their neighbours",
                          stacklevel=2)
        out.append(Repair(oriented, source[used], pinches, edges, flipped))
    return out
