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
    on."""

    mesh: Mesh
    vertex_map: np.ndarray
    joined: int
    notes: tuple[str, ...] = ()

    def describe(self) -> str:
        """One line for a warning: how many corners were joined, and what happened to their attributes."""
        text = f"joined {self.joined} exactly coincident vertices (copies of one position)"
        return text + ("; " + "; ".join(self.notes) if self.notes else "")


def _disagree(values: np.ndarray, rep: np.ndarray) -> int:
    """How many vertices carry a value other than their group representative's."""
    return int(np.any(values != values[rep], axis=1).sum())


def weld_vertices(mesh: Mesh, *, seams_only: bool = True) -> Weld:
    """Join the vertices whose positions are exactly equal (``-0.0`` equal to ``0.0``), keeping the order in
    which positions are first seen; faces keep their rows and corner order. Only copies along seams are
    joined (an edge whose ends both have copies that make an edge too: two faces stored apart along it);
    copies that touch at a lone point (two pieces meeting at a corner) stay apart, since joined they would
    pinch, and so do vertices that no face uses.

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
    >>> w.describe()
    'joined 2 exactly coincident vertices (copies of one position); texture coordinates differ at 1 of them: kept per face corner'
    """
    used = mesh.referenced_vertices()
    ids = np.flatnonzero(used)
    v = mesh.vertices[ids] + 0.0                      # -0.0 becomes 0.0: equal positions, equal bits
    _, first, inverse = np.unique(v, axis=0, return_index=True, return_inverse=True)
    if len(first) == len(v):
        return Weld(mesh, np.arange(mesh.n_vertices), 0)
    group = np.arange(mesh.n_vertices)               # each vertex's first copy (unused vertices stay apart)
    group[ids] = ids[first[inverse.ravel()]]
    # a copy is joined only where it lies on a seam: an edge whose two ends both have copies that make an
    # edge too (two faces stored apart along it); copies touching at a lone point stay apart
    valid = mesh.faces >= 0
    a, b = mesh.faces[valid], mesh.next_vertices()[valid]
    n = mesh.n_vertices
    ga, gb = group[a], group[b]
    by_place = np.minimum(ga, gb) * n + np.maximum(ga, gb)
    by_index = np.minimum(a, b) * n + np.maximum(a, b)
    pairs = np.unique(np.stack([by_place, by_index], axis=1), axis=0)
    places, count = np.unique(pairs[:, 0], return_counts=True)
    seam_edge = np.isin(by_place, places[count > 1])
    on_seam = np.zeros(n, bool)
    on_seam[a[seam_edge]] = True
    on_seam[b[seam_edge]] = True
    if not seams_only:
        on_seam[ids] = True
    # each group's seam copies join the first of them
    target = np.full(n, n, np.int64)
    np.minimum.at(target, group[on_seam], np.flatnonzero(on_seam))
    rep_of_old = np.where(on_seam, target[group], np.arange(n))
    keep = rep_of_old == np.arange(n)
    if keep.all():
        return Weld(mesh, np.arange(n), 0)
    rep = np.flatnonzero(keep)                        # the input vertex each new vertex is, in input order
    new_of_old = (np.cumsum(keep) - 1)[rep_of_old]
    notes = []
    uv, face_uv = mesh.uv, mesh.face_uv
    if uv is not None and (n := _disagree(uv, rep_of_old)):
        if face_uv is None:
            valid = mesh.faces >= 0
            face_uv = np.where(valid[..., None], uv[np.where(valid, mesh.faces, 0)], 0.0)
        uv = None
        notes.append(f"texture coordinates differ at {n} of them: kept per face corner")
    elif uv is not None:
        uv = uv[rep]
    normals = mesh.normals
    if normals is not None and (n := _disagree(normals, rep_of_old)):
        normals = None
        notes.append(f"normals differ at {n} of them (hard edges): not kept")
    elif normals is not None:
        normals = normals[rep]
    colors = mesh.colors
    if colors is not None:
        if n := _disagree(colors, rep_of_old):
            notes.append(f"colours differ at {n} of them: the first copy's kept")
        colors = colors[rep]
    faces = np.where(mesh.faces >= 0, new_of_old[np.where(mesh.faces >= 0, mesh.faces, 0)], -1)
    welded = Mesh(mesh.vertices[rep], faces, uv=uv, normals=normals, colors=colors, face_uv=face_uv,
                  texture=mesh.texture)
    return Weld(welded, new_of_old, mesh.n_vertices - len(rep), tuple(notes))
