"""Exactly coincident positions joined into one vertex, so that topology follows the shape and not the file.

Files that store per-vertex attributes (PLY, glTF, STL's triangle soup, many OBJ exporters) repeat a
position wherever its texture coordinates, normal or colour change: along every UV seam, at every hard
edge. Read as they are, such meshes fall apart into pieces (a textured box into six squares). Joining the
copies along such seams, positions bit-for-bit equal, gives the surface its real topology; nothing is
moved, positions that differ by any amount stay apart, and so do pieces that only touch at a point.

What the joined copies carried is kept where it can be: per-vertex texture coordinates that differ along a
seam become per-corner ones (``face_uv``); normals that differ are dropped (geoimg derives its own); colours
that differ keep the first copy's. Each of these is said in the returned notes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._mesh import Mesh

__all__ = ["Weld", "weld_vertices"]


@dataclass(frozen=True)
class Weld:
    """What :func:`weld_vertices` did: the welded mesh, each input vertex's new index (``vertex_map``, (N,)),
    how many vertices were joined into others, and notes on the attributes that the joined copies disagreed
    on.

    Parameters
    ----------
    mesh : Mesh
        The welded mesh.
    vertex_map : numpy.ndarray
        (N,) each input vertex's index in ``mesh``.
    joined : int
        How many vertices were joined into others.
    notes : tuple of str
        What the joined copies disagreed on.

    Examples
    --------
    >>> import geoimg
    >>> soup = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [3, 4, 5]])
    >>> w = weld_vertices(soup, seams_only=False)
    >>> w.mesh.n_vertices, w.joined, w.vertex_map.tolist()
    (4, 2, [0, 1, 2, 1, 3, 2])
    """

    mesh: Mesh
    vertex_map: np.ndarray
    joined: int
    notes: tuple[str, ...] = ()

    def describe(self) -> str:
        """One line for a warning: how many corners were joined, and what happened to their attributes.

        Returns
        -------
        str
            The description.

        Examples
        --------
        >>> from geoimg.mesh import Mesh, weld_vertices
        >>> soup = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [3, 4, 5]])
        >>> weld_vertices(soup, seams_only=False).describe().startswith('joined 2')
        True
        """
        text = f"joined {self.joined} exactly coincident vertices (copies of one position)"
        return text + ("; " + "; ".join(self.notes) if self.notes else "")


def _disagree(values: np.ndarray, rep: np.ndarray) -> int:
    """How many vertices carry a value other than their group representative's."""
    return int(np.any(values != values[rep], axis=1).sum())


def _seam_representatives(mesh: Mesh, group: np.ndarray) -> np.ndarray:
    """Each vertex's first copy among those it is joined to along seams: two copies of one position are
    joined when edges at them coincide (both ends copies of each other: two faces stored apart along one
    edge), and so on through such joins; copies that only touch at a point are not.
    """
    valid = mesh.faces >= 0
    a, b = mesh.faces[valid], mesh.next_vertices()[valid]
    n = mesh.n_vertices
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    glo, ghi = group[lo], group[hi]
    flip = glo > ghi                                  # the edge's ends ordered by their positions' groups
    lo, hi = np.where(flip, hi, lo), np.where(flip, lo, hi)
    place = np.minimum(glo, ghi) * n + np.maximum(glo, ghi)
    order = np.argsort(place, kind="stable")
    place, lo, hi = place[order], lo[order], hi[order]
    first = np.r_[True, place[1:] != place[:-1]]
    head = np.maximum.accumulate(np.where(first, np.arange(len(place)), 0))   # each edge's first at its place
    links = (lo != lo[head]) | (hi != hi[head])
    rows = np.concatenate([lo[links], hi[links]])
    cols = np.concatenate([lo[head][links], hi[head][links]])
    from scipy import sparse                      # here: reading and writing meshes need no scipy at import
    from scipy.sparse.csgraph import connected_components
    _, label = connected_components(sparse.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)),
                                    directed=False)
    smallest = np.full(label.max() + 1, n, np.int64)
    np.minimum.at(smallest, label, np.arange(n))
    return smallest[label]


def weld_vertices(mesh: Mesh, *, seams_only: bool = True) -> Weld:
    """Join the vertices whose positions are exactly equal (``-0.0`` equal to ``0.0``), keeping the order in
    which positions are first seen; faces keep their rows and corner order. Only copies along seams are
    joined: two copies are joined where edges at them coincide (two faces stored apart along one edge), and
    so on through such joins; copies that touch at a lone point (two pieces meeting at a corner, even where
    each has a seam of its own there) stay apart, since joined they would pinch, and so do vertices that no
    face uses.

    Parameters
    ----------
    mesh : Mesh
        The mesh as read. It is not changed.
    seams_only : bool, default True
        Join copies along seams only; ``False`` joins every copy of a position (a triangle soup such as STL,
        which cannot say that two faces share a vertex, is read so).

    Returns
    -------
    Weld
        The welded mesh (``mesh`` itself when no two positions coincide), the new index of each input
        vertex, the count joined and notes on attributes: per-vertex ``uv`` that differ between copies move to
        per-corner ``face_uv`` (so a UV seam survives), ``normals`` that differ are dropped, ``colors``
        that differ keep the first copy's.

    Examples
    --------
    Two triangles of a square that a file stored with their own corners, with a UV seam between them:

    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [3, 4, 5]],
    ...          uv=[[0, 0], [1, 0], [1, 1], [0.5, 0], [1, 1], [0, 1]])
    >>> w = weld_vertices(m)
    >>> w.mesh.faces.tolist(), w.joined, w.mesh.uv is None, w.mesh.face_uv[1, 0].tolist()
    ([[0, 1, 2], [0, 2, 3]], 2, True, [0.5, 0.0])
    >>> for part in w.describe().split("; "):
    ...     print(part)
    joined 2 exactly coincident vertices (copies of one position)
    texture coordinates differ at 1 of them: kept per face corner
    """
    used = mesh.referenced_vertices()
    ids = np.flatnonzero(used)
    v = mesh.vertices[ids] + 0.0                      # -0.0 becomes 0.0: equal positions, equal bits
    _, first, inverse = np.unique(v, axis=0, return_index=True, return_inverse=True)
    if len(first) == len(v):
        return Weld(mesh, np.arange(mesh.n_vertices), 0)
    group = np.arange(mesh.n_vertices)               # each vertex's first copy (unused vertices stay apart)
    group[ids] = ids[first[inverse.ravel()]]
    rep_of_old = _seam_representatives(mesh, group) if seams_only else group   # else every copy joins the first
    keep = rep_of_old == np.arange(mesh.n_vertices)
    if keep.all():
        return Weld(mesh, np.arange(mesh.n_vertices), 0)
    rep = np.flatnonzero(keep)                        # the input vertex each new vertex is, in input order
    new_of_old = (np.cumsum(keep) - 1)[rep_of_old]
    notes = []
    uv, face_uv = mesh.uv, mesh.face_uv
    if uv is not None and (count := _disagree(uv, rep_of_old)):
        if face_uv is None:
            valid = mesh.faces >= 0
            face_uv = np.where(valid[..., None], uv[np.where(valid, mesh.faces, 0)], 0.0)
        uv = None
        notes.append(f"texture coordinates differ at {count} of them: kept per face corner")
    elif uv is not None:
        uv = uv[rep]
    normals = mesh.normals
    if normals is not None and (count := _disagree(normals, rep_of_old)):
        normals = None
        notes.append(f"normals differ at {count} of them (hard edges): not kept")
    elif normals is not None:
        normals = normals[rep]
    colors = mesh.colors
    if colors is not None:
        if count := _disagree(colors, rep_of_old):
            notes.append(f"colours differ at {count} of them: the first copy's kept")
        colors = colors[rep]
    faces = np.where(mesh.faces >= 0, new_of_old[np.where(mesh.faces >= 0, mesh.faces, 0)], -1)
    welded = Mesh(mesh.vertices[rep], faces, uv=uv, normals=normals, colors=colors, face_uv=face_uv,
                  texture=mesh.texture)
    return Weld(welded, new_of_old, mesh.n_vertices - len(rep), tuple(notes))
