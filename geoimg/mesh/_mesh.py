"""The polygon mesh: float64 vertices and faces of any size, kept exactly as given.

Faces are stored as a padded ``(F, K)`` int64 array, ``K`` the largest face size, with
``-1`` after the last index of a shorter face; ``face_sizes`` holds each face's count.
Nothing is triangulated, merged or reordered.
"""
from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import mapbox_earcut
import numpy as np
from numpy.typing import ArrayLike

from ..errors import MeshError

__all__ = ["Mesh", "pad_faces", "reverse_corners", "once"]

_MADE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def once(mesh: Mesh, key: Any, make: Callable[[], Any]) -> Any:
    """``make()`` of ``mesh``, made once while the mesh lives and handed out again: a mesh's arrays are
    read-only, so what is made of them alone stays true (its topology, its edges, its triangles: the
    repairs, the choice of a map, the map and the measurement each ask). Arrays are handed out read-only.

    Examples
    --------
    >>> m = Mesh(np.eye(3), [[0, 1, 2]])
    >>> once(m, "corners", lambda: m.faces.sum()) is once(m, "corners", lambda: None)
    True
    """
    known = _MADE.setdefault(mesh, {})
    if key not in known:
        value = make()
        for a in value if isinstance(value, tuple) else (value,):
            if isinstance(a, np.ndarray):
                a.setflags(write=False)
        known[key] = value
    return known[key]


MAX_PADDED_ENTRIES = 200_000_000     # the padded (F, K) face table: 1.6 GB
LARGE_POLYGON = 64                   # polygons of more corners are split in near-linear time (no Python ears)


def pad_faces(faces: Any) -> np.ndarray:
    """Turn faces given as an ``(F, K)`` array or a sequence of index sequences into a padded array.

    Parameters
    ----------
    faces : array_like or sequence of sequences of int
        Vertex indices of each face; ``-1`` entries of an array are padding.

    Returns
    -------
    numpy.ndarray
        ``(F, K)`` int64, shorter faces padded with ``-1``.

    Raises
    ------
    MeshError
        When the indices are not integers, not 2-D, or would not fit in memory.

    Examples
    --------
    >>> pad_faces([[0, 1, 2], [0, 2, 3, 4]]).tolist()
    [[0, 1, 2, -1], [0, 2, 3, 4]]
    """
    if isinstance(faces, np.ndarray):
        arr = faces
    else:
        faces = list(faces)
        if not faces:
            return np.zeros((0, 3), np.int64)
        lengths = [len(f) for f in faces]
        if len(faces) * max(lengths) > MAX_PADDED_ENTRIES:
            raise MeshError(f"faces: {len(faces)} faces with up to {max(lengths)} vertices each would take "
                            f"{len(faces) * max(lengths) * 8 / 1e9:.1f} GB as a padded table (limit "
                            f"{MAX_PADDED_ENTRIES * 8 / 1e9:.1f} GB); split the largest polygons first")
        if len(set(lengths)) == 1:
            arr = np.asarray(faces)
        else:
            arr = np.full((len(faces), max(lengths)), -1, np.int64)
            try:
                for i, f in enumerate(faces):
                    arr[i, : len(f)] = f
            except OverflowError:
                raise MeshError("faces: a vertex index is beyond 64-bit integers") from None
    if arr.ndim != 2:
        raise MeshError(f"faces: expected a 2-D (F, K) index array, got shape {arr.shape}")
    if arr.size and arr.dtype.kind not in "biuf":          # e.g. integers beyond 64 bits come as objects
        raise MeshError(f"faces: expected integer vertex indices (64-bit at most), got {arr.dtype} values")
    if arr.size and not np.issubdtype(arr.dtype, np.integer):
        if not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
            raise MeshError(f"faces: expected integer vertex indices, got dtype {arr.dtype} with non-integers")
    return np.array(arr, dtype=np.int64)


def reverse_corners(table: np.ndarray, sizes: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """A copy of a per-corner table (F, K[, ...]) with the corners of faces ``rows`` in reverse order (padding
    after a face's ``sizes`` corners stays where it is): faces turned over.

    Examples
    --------
    >>> reverse_corners(np.array([[0, 1, 2, -1], [3, 4, 5, 6]]), np.array([3, 4]), np.array([0, 1])).tolist()
    [[2, 1, 0, -1], [6, 5, 4, 3]]
    """
    out = table.copy()
    j = np.arange(table.shape[1])
    k = sizes[rows][:, None]
    order = np.where(j < k, k - 1 - j, j)
    out[rows] = np.take_along_axis(table[rows], order.reshape(order.shape + (1,) * (table.ndim - 2)), axis=1)
    return out


def _frozen(a: np.ndarray) -> bool:
    """Whether nobody can write ``a``'s data: it and every array it is a view of are read-only."""
    base: Any = a
    while isinstance(base, np.ndarray):
        if base.flags.writeable:
            return False
        base = base.base
    return True


@dataclass(frozen=True, eq=False)
class Mesh:
    """A polygon mesh with optional per-vertex UVs, normals and colours, per-corner UVs and a texture.

    Parameters
    ----------
    vertices : array_like, shape (N, 3)
        Positions; stored as float64 (units are kept, never rescaled).
    faces : array_like or sequence of sequences
        Vertex indices per face (see :func:`pad_faces`); at least 3 per face.
    uv : array_like, shape (N, 2), optional
        Per-vertex parameter coordinates (for example from OBJ ``vt``).
    normals : array_like, shape (N, 3), optional
        Per-vertex unit normals.
    colors : array_like, shape (N, 3) or (N, 4), optional
        Per-vertex RGB or RGBA colours in [0, 1] (for example from PLY ``red green blue``).
    face_uv : array_like, shape (F, K, 2), optional
        Texture coordinates per face corner (OBJ ``vt``), so a position may have several (a UV seam);
        entries on a face's padding are ignored. (0, 0) is the texture's bottom-left corner, as in OBJ.
    texture : array_like of uint8, shape (h, w, 3) or (h, w, 4), optional
        The colour texture that ``face_uv`` reads (row 0 at the top, as image files store it).

    Raises
    ------
    MeshError
        When the vertices or faces are malformed (shapes, NaN, indices out of range, faces of fewer than
        3 corners, coordinates beyond what float32 images hold) or an attribute does not fit them.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> m.n_vertices, m.n_faces, m.face_sizes.tolist()
    (4, 1, [4])
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None = None
    normals: np.ndarray | None = None
    colors: np.ndarray | None = None
    face_uv: np.ndarray | None = None
    texture: np.ndarray | None = None
    face_sizes: np.ndarray = field(init=False, repr=False)

    if TYPE_CHECKING:        # what the constructor takes (the fields hold them converted and checked)
        def __init__(self, vertices: ArrayLike, faces: ArrayLike, uv: ArrayLike | None = None,
                     normals: ArrayLike | None = None, colors: ArrayLike | None = None,
                     face_uv: ArrayLike | None = None, texture: ArrayLike | None = None) -> None: ...

    def __post_init__(self):
        v = np.array(self.vertices, dtype=np.float64, copy=True)
        if v.ndim != 2 or v.shape[1] != 3:
            raise MeshError(f"vertices: expected shape (N, 3), got {v.shape}")
        if v.shape[0] == 0:
            raise MeshError("vertices: the mesh has no vertices")
        bad = ~np.isfinite(v).all(axis=1)
        if bad.any():
            raise MeshError(
                f"vertices: {int(bad.sum())} vertices have NaN or infinite coordinates "
                f"(first at index {int(np.flatnonzero(bad)[0])})")
        f = pad_faces(self.faces)
        if f.shape[0] == 0:
            raise MeshError("faces: the mesh has no faces")
        valid = f >= 0
        sizes = valid.sum(axis=1)
        # padding must be trailing: a -1 followed by an index is malformed
        if np.any(valid[:, 1:] & ~valid[:, :-1]):
            raise MeshError("faces: -1 padding must come after a face's indices")
        if np.any(f < -1):
            raise MeshError(f"faces: negative vertex index {int(f.min())} (only -1 padding is allowed)")
        if sizes.min() < 3:
            i = int(np.argmin(sizes))
            raise MeshError(f"faces: every face needs at least 3 vertices; face {i} has {int(sizes[i])}")
        if f.max() >= v.shape[0]:
            i = int(np.argwhere(f >= v.shape[0])[0, 0])
            raise MeshError(
                f"faces: face {i} refers to vertex {int(f[i].max())} but there are only {v.shape[0]} vertices")
        for name, width in (("uv", 2), ("normals", 3)):
            a = getattr(self, name)
            if a is None:
                continue
            a = np.array(a, dtype=np.float64, copy=True)
            if a.shape != (v.shape[0], width):
                raise MeshError(f"{name}: expected shape ({v.shape[0]}, {width}), got {a.shape}")
            if not np.isfinite(a).all():
                raise MeshError(f"{name}: contains NaN or infinite values")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        self._check_attributes(v.shape[0], f, valid)
        v.setflags(write=False)
        f.setflags(write=False)
        sizes = sizes.astype(np.int64)
        sizes.setflags(write=False)
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f)
        object.__setattr__(self, "face_sizes", sizes)

    def _check_attributes(self, n: int, f: np.ndarray, valid: np.ndarray) -> None:
        """Colours, per-corner UVs and the texture checked and stored read-only."""
        if self.colors is not None:
            c = np.array(self.colors, dtype=np.float64, copy=True)
            if c.ndim != 2 or c.shape[0] != n or c.shape[1] not in (3, 4):
                raise MeshError(f"colors: expected shape ({n}, 3) or ({n}, 4), got {c.shape}")
            if not np.isfinite(c).all() or c.min() < 0 or c.max() > 1:
                raise MeshError("colors: expected values in [0, 1]")
            c.setflags(write=False)
            object.__setattr__(self, "colors", c)
        if self.face_uv is not None:
            t = np.array(self.face_uv, dtype=np.float64, copy=True)
            if t.shape != f.shape + (2,):
                raise MeshError(f"face_uv: expected shape {f.shape + (2,)} (a (u, v) per face corner), got {t.shape}")
            t[~valid] = 0.0
            if not np.isfinite(t).all():
                raise MeshError("face_uv: contains NaN or infinite values")
            t.setflags(write=False)
            object.__setattr__(self, "face_uv", t)
        if self.texture is not None:
            # a read-only 8-bit texture (another mesh's: every piece of a repaired mesh, every derived mesh)
            # is shared, not copied: a texture can be far larger than its mesh
            t0 = self.texture
            shared = isinstance(t0, np.ndarray) and t0.dtype == np.uint8 and _frozen(t0)
            img = t0 if shared else np.array(t0, copy=True)
            if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] not in (3, 4) or min(img.shape[:2]) < 1:
                raise MeshError(f"texture: expected an 8-bit (h, w, 3) or (h, w, 4) image, got {img.dtype} "
                                f"{img.shape}")
            if self.face_uv is None:
                raise MeshError("texture: a texture needs face_uv (texture coordinates per face corner)")
            if not shared:
                img.setflags(write=False)
            object.__setattr__(self, "texture", img)

    def derived(self, faces: Any, *, vertex_source: Any = None, face_source: Any = None,
                turned: Any = None) -> Mesh:
        """A mesh made from this one, its attributes carried: vertex ``i`` is this mesh's vertex
        ``vertex_source[i]`` (default: the same vertices), face ``j`` is this mesh's face
        ``face_source[j]`` (default: the same faces) with the corners ``faces[j]``, read backwards where
        ``turned[j]`` (a face turned over).

        Parameters
        ----------
        faces : array_like
            (F', K) corners of the new faces, in the new vertex numbering.
        vertex_source : array_like or None
            (N',) each new vertex's vertex in this mesh.
        face_source : array_like or None
            (F',) each new face's face in this mesh (for per-corner texture coordinates).
        turned : array_like or None
            (F',) booleans: faces whose corners run backwards.

        Returns
        -------
        Mesh
            The new mesh, with positions, UVs, normals, colours and texture carried.

        Examples
        --------
        >>> m = Mesh(np.eye(3), [[0, 1, 2]], colors=np.eye(3))
        >>> m.derived([[0, 2, 1]], turned=[True]).colors.tolist() == m.colors.tolist()
        True
        """
        def pick(a):
            return a if a is None or vertex_source is None else a[vertex_source]

        face_uv = self.face_uv
        if face_uv is not None:
            face_uv = face_uv if face_source is None else face_uv[face_source]
            if turned is not None and np.any(turned):
                sizes = self.face_sizes if face_source is None else self.face_sizes[face_source]
                face_uv = reverse_corners(face_uv, sizes, np.flatnonzero(turned))
        return Mesh(pick(self.vertices), faces, uv=pick(self.uv), normals=pick(self.normals),
                    colors=pick(self.colors), face_uv=face_uv, texture=self.texture)

    def _face_kinds(self) -> str:
        """``"5856 triangles"``, ``"348 triangles, 22117 quads"``: the faces by number of corners."""
        sizes, counts = np.unique(self.face_sizes, return_counts=True)
        return ", ".join(f"{c} {'triangles' if k == 3 else 'quads' if k == 4 else f'{k}-gons'}"
                         for k, c in zip(sizes.tolist(), counts.tolist()))

    def __repr__(self) -> str:
        kinds = self._face_kinds()
        extras = "".join(f", {name}" for name, value in (("uv", self.uv), ("normals", self.normals),
                                                          ("colors", self.colors), ("face_uv", self.face_uv))
                         if value is not None)
        if self.texture is not None:
            extras += f", {self.texture.shape[1]} x {self.texture.shape[0]} texture"
        return f"Mesh({self.n_vertices} vertices, {self.n_faces} faces: {kinds}{extras})"

    def _repr_html_(self) -> str:
        """A notebook's summary: counts, faces by kind, bounding box."""
        used = self.referenced_vertices()
        lo, hi = (self.vertices[used].min(axis=0), self.vertices[used].max(axis=0)) if used.any() else ((), ())
        yes = {True: "yes", False: "no"}
        rows = [("vertices", f"{self.n_vertices} ({int((~used).sum())} unreferenced)"),
                ("faces", f"{self.n_faces}: {self._face_kinds()}"),
                ("bounding box", f"{np.round(lo, 6).tolist()} .. {np.round(hi, 6).tolist()}"),
                ("UVs, normals", f"{yes[self.uv is not None]}, {yes[self.normals is not None]}"),
                ("colours, corner UVs, texture", f"{yes[self.colors is not None]}, {yes[self.face_uv is not None]}, "
                                                 f"{yes[self.texture is not None]}")]
        return "<table><caption>geoimg.Mesh</caption>" + "".join(
            f"<tr><th style='text-align:left'>{k}</th><td style='text-align:left'>{v}</td></tr>" for k, v in rows) + \
            "</table>"

    @property
    def n_vertices(self) -> int:
        """Number of vertices.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        >>> m.n_vertices
        4
        """
        return self.vertices.shape[0]

    @property
    def n_faces(self) -> int:
        """Number of faces.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        >>> m.n_faces
        1
        """
        return self.faces.shape[0]

    @property
    def is_triangle_mesh(self) -> bool:
        """Whether every face is a triangle.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        >>> m.is_triangle_mesh
        False
        """
        return bool(np.all(self.face_sizes == 3))

    def face_list(self) -> list[np.ndarray]:
        """Faces as a list of index arrays (each of its own length).

        Returns
        -------
        list of numpy.ndarray
            One index array per face.

        Examples
        --------
        >>> m = Mesh(np.eye(3), [[0, 1, 2]])
        >>> [f.tolist() for f in m.face_list()]
        [[0, 1, 2]]
        """
        return [row[:k] for row, k in zip(self.faces, self.face_sizes)]

    def next_vertices(self) -> np.ndarray:
        """(F, K) index of the vertex after each corner in its face (the last wraps to the first); -1 on padding.

        Returns
        -------
        numpy.ndarray
            (F, K) int64.

        Examples
        --------
        >>> Mesh(np.zeros((5, 3)), [[0, 1, 2], [1, 3, 4, 2]]).next_vertices().tolist()
        [[1, 2, 0, -1], [3, 4, 2, 1]]
        """
        nxt = np.roll(self.faces, -1, axis=1)
        nxt[np.arange(self.n_faces), self.face_sizes - 1] = self.faces[:, 0]
        return np.where(self.faces >= 0, nxt, -1)

    def triangulate(self, quads: str = "fan") -> tuple[np.ndarray, np.ndarray]:
        """Split every face into triangles: a fan from its first corner, or with ``quads="shorter"`` each
        quad along its shorter diagonal in space (as geometry images are drawn and measured: the split
        that bends a non-planar quad least), larger polygons fanned. A polygon of 5 corners or more that is
        not convex (in the plane that fits it best), or whose fan would have a triangle of zero area (corners
        on a line beside the first), is split by ear clipping instead, so that no triangle lies outside it
        or is flat. Two quads that share both edges at a vertex of valence 2 (a doublet, common in
        quad-dominant meshes) are split through that vertex, whichever way was asked: the other split
        gives one triangle twice, and the mesh of triangles would not be a manifold.

        Returns
        -------
        triangles : numpy.ndarray, shape (T, 3)
        face_index : numpy.ndarray, shape (T,)
            The face each triangle came from. Both are made once per mesh and ``quads`` and handed out
            again, read-only (copy them to change them).

        Parameters
        ----------
        quads : {"fan", "shorter"}
            How quads are split: from the first corner, or along the shorter diagonal.

        Examples
        --------
        >>> m = Mesh(np.eye(4, 3), [[0, 1, 2, 3]])
        >>> m.triangulate()[0].tolist()
        [[0, 1, 2], [0, 2, 3]]
        >>> Mesh([[0, 0, 0], [2, 0, 0], [3, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]]).triangulate("shorter")[0].tolist()
        [[1, 2, 3], [1, 3, 0]]

        An L-shaped hexagon: fanned from its first corner, vertex 1, the triangle (1, 3, 4) would cover the
        square the L lacks; ear clipping keeps every triangle inside:

        >>> L = Mesh([[1, 1, 0], [1, 2, 0], [0, 2, 0], [0, 0, 0], [2, 0, 0], [2, 1, 0]], [[1, 2, 3, 4, 5, 0]])
        >>> L.triangulate()[0].tolist()
        [[0, 1, 2], [0, 2, 3], [0, 3, 4], [4, 5, 0]]
        """
        tris, owner, _ = self.triangle_corners(quads)
        return tris, owner

    def triangle_corners(self, quads: str = "fan") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`triangulate`'s triangles and faces, and each triangle's corners as positions within its
        face (T, 3): ``triangles[t, k] == faces[face_index[t], corners[t, k]]``.

        Parameters
        ----------
        quads : {"fan", "shorter"}
            How quads are split (see :meth:`triangulate`).

        Returns
        -------
        triangles : numpy.ndarray
            (T, 3) vertex indices.
        face_index : numpy.ndarray
            (T,) the face each triangle came from.
        corners : numpy.ndarray
            (T, 3) each triangle corner's position within its face.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        >>> tris, faces, corners = m.triangle_corners()
        >>> corners.tolist()
        [[0, 1, 2], [0, 2, 3]]
        """
        if quads not in ("fan", "shorter"):
            raise MeshError(f"quads: expected 'fan' or 'shorter', got {quads!r}")
        return once(self, ("triangle_corners", quads), lambda: self._triangle_corners(quads))

    def _triangle_corners(self, quads: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        f = self.faces
        quad = self.face_sizes == 4
        turn = self._shorter_turns(quad) if quads == "shorter" and quad.any() else None
        if f.shape[1] == 4 and quad.all():     # quads only (an image's quad mesh): two triangles a face, at once
            owner = np.repeat(np.arange(self.n_faces), 2)
            pattern = np.array([[0, 1, 2], [0, 2, 3]])
            corners = (np.where(turn[:, None, None], (pattern + 1) % 4, pattern).reshape(-1, 3) if turn is not None
                       else np.tile(pattern, (self.n_faces, 1)))
            t = np.take_along_axis(f, corners.reshape(-1, 6), axis=1).reshape(-1, 3)
        else:
            per_face = self.face_sizes - 2                             # linear time, any polygon size
            owner = np.repeat(np.arange(self.n_faces), per_face)
            start = np.repeat(np.cumsum(per_face) - per_face, per_face)
            j = np.arange(len(owner)) - start + 1                      # 1 .. k - 2 within each face
            corners = np.stack([np.zeros_like(j), j, j + 1], axis=1)
            if turn is not None:       # a quad whose 1-3 diagonal is shorter is fanned from corner 1
                corners = np.where(turn[owner][:, None], (corners + 1) % 4, corners)
            for face in np.flatnonzero(self._reflex_faces()).tolist():
                k = int(self.face_sizes[face])
                ears = _ear_clip(_plane_coordinates(self.vertices[f[face, :k]]))
                if ears is not None:
                    corners[start[np.searchsorted(owner, face)] + np.arange(k - 2)] = ears
            for face in np.flatnonzero(self.face_sizes > LARGE_POLYGON).tolist():
                k = int(self.face_sizes[face])
                split = _large_polygon_corners(self.vertices[f[face, :k]])
                if split is not None:
                    corners[start[np.searchsorted(owner, face)] + np.arange(k - 2)] = split
            t = f[owner[:, None], corners]
        for _ in range(4 if quad.any() else 0):   # two quads on both edges of a valence-2 vertex: through it
            twice = _quads_split_twice(t, owner, quad)
            if not twice.any():
                break
            rows = twice[owner]
            corners[rows] = (corners[rows] + 1) % 4
            t = f[owner[:, None], corners]
        return t, owner, corners

    def _shorter_turns(self, quad: np.ndarray) -> np.ndarray:
        """Per face: a quad (of ``quad``) whose 1-3 diagonal is shorter in space than its 0-2 one."""
        every = bool(quad.all())
        v, q = self.vertices, self.faces if every else self.faces[quad, :4]
        d13, d02 = v[q[:, 1]] - v[q[:, 3]], v[q[:, 0]] - v[q[:, 2]]
        shorter = np.einsum("ij,ij->i", d13, d13) < np.einsum("ij,ij->i", d02, d02)
        if every:
            return shorter
        turn = np.zeros(self.n_faces, bool)
        turn[quad] = shorter
        return turn

    def _reflex_faces(self) -> np.ndarray:
        """Faces of 5 to :data:`LARGE_POLYGON` corners (quads keep their diagonal; larger polygons are split
        by :func:`_large_polygon_corners`) that a fan from the first corner would not split well, in the plane
        that fits them best: with a reflex corner, or a corner on a line next to the first one (a fan
        triangle of zero area); only faces flat enough to have that plane (see :func:`_polygon_shapes`).
        """
        out = np.zeros(self.n_faces, bool)
        sizes = self.face_sizes
        for k in np.unique(sizes[(sizes >= 5) & (sizes <= LARGE_POLYGON)]).tolist():
            rows = np.flatnonzero(sizes == k)
            reflex, flat_at_fan, flat_enough = _polygon_shapes(self.vertices[self.faces[rows, :k]])
            out[rows] = (reflex | flat_at_fan) & flat_enough
        return out

    def vertex_normals(self) -> np.ndarray:
        """Area-weighted unit vertex normals from the faces' orientation (zero for unused vertices).

        Returns
        -------
        numpy.ndarray
            (N, 3) float64 unit normals.

        Examples
        --------
        >>> Mesh(np.eye(4, 3) * [1, 1, 0], [[3, 0, 1]]).vertex_normals()[0].tolist()
        [0.0, 0.0, 1.0]
        """
        tris, _ = self.triangulate()
        v = self.vertices
        fn = np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]])
        n = np.stack([sum(np.bincount(tris[:, k], fn[:, c], minlength=len(v)) for k in range(3)) for c in range(3)],
                     axis=1)
        length = np.linalg.norm(n, axis=1, keepdims=True)
        return np.divide(n, length, out=np.zeros_like(n), where=length > 0)

    def referenced_vertices(self) -> np.ndarray:
        """Boolean (N,) mask of the vertices used by at least one face.

        Returns
        -------
        numpy.ndarray
            (N,) booleans.

        Examples
        --------
        >>> Mesh(np.eye(4)[:, :3], [[0, 1, 2]]).referenced_vertices().tolist()
        [True, True, True, False]
        """
        used = np.zeros(self.n_vertices, bool)
        used[self.faces[self.faces >= 0]] = True
        return used

    def bounding_box_diagonal(self) -> float:
        """Length of the diagonal of the axis-aligned bounding box of the referenced vertices.

        Returns
        -------
        float
            The diagonal's length, in the mesh's units.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        >>> round(m.bounding_box_diagonal(), 4)
        1.4142
        """
        v = self.vertices[self.referenced_vertices()]
        half = v.max(axis=0) / 2 - v.min(axis=0) / 2           # halves first: no overflow near 1e308
        scale = float(half.max())
        return 2.0 * scale * float(np.linalg.norm(half / scale)) if scale > 0 else 0.0

    def coordinate_scale(self) -> float:
        """The largest absolute coordinate of the referenced vertices, checked to be within what geoimg's
        arithmetic holds (squares of sizes and areas in float64, positions in float32 images).

        Raises
        ------
        MeshError
            If it is above 1e100 or below 1e-100 (and not 0): scale the mesh first.

        Returns
        -------
        float
            The largest absolute coordinate.

        Examples
        --------
        >>> Mesh([[0, 0, 0], [2, 0, 0], [0, 1, 0]], [[0, 1, 2]]).coordinate_scale()
        2.0
        """
        scale = float(np.abs(self.vertices[self.referenced_vertices()]).max())
        if 0 < scale < 1e-100 or scale > 1e100:
            raise MeshError(f"mesh: coordinates of size {scale:.3g} are beyond what geometry images (float32) "
                            "and the surface's arithmetic hold; scale the mesh first")
        return scale


def _polygon_shapes(p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For polygons ``p`` (R, k, 3), in the plane that fits each best (Newell's normal): whether it has a
    reflex corner (turning against the normal by more than rounding), whether corner 1 or k - 1 lies on a
    line with its neighbours (a fan from corner 0 would have a flat triangle there), and whether it is flat
    enough to have such a plane (within 5 % of its size: a polygon far from flat keeps its fan).
    """
    k = p.shape[1]
    nxt = np.roll(p, -1, axis=1)
    normal = np.cross(p, nxt).sum(axis=1)                     # Newell: twice the vector area
    edge = nxt - p
    turn = np.einsum("rkc,rc->rk", np.cross(edge, np.roll(edge, -1, axis=1)), normal)
    scale = np.einsum("rkc,rkc->rk", edge, edge) * np.linalg.norm(normal, axis=1)[:, None]
    flat = np.abs(turn) <= 1e-12 * scale          # a corner on a line: the fan's triangle there is flat
    flat_at_fan = flat[:, 0] | flat[:, k - 2]     # corners 1 and k - 1 (turn i is at corner i + 1)
    unit = normal / np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    q = p - p.mean(axis=1, keepdims=True)
    height = np.abs(np.einsum("rkc,rc->rk", q, unit)).max(axis=1)
    flat_enough = height <= 0.05 * np.linalg.norm(q, axis=2).max(axis=1)
    return (turn < -1e-12 * scale).any(axis=1), flat_at_fan, flat_enough


def _halving(k: int) -> np.ndarray:
    """Triangles (k - 2, 3) of corner positions that split a convex k-gon by halving: the triangle of
    corners 0, k/3 and 2k/3, then each run of corners between two of them at its middle, and so on; every
    triangle spans a run of corners, and the runs halve at each level (log k levels, linear time).

    Examples
    --------
    >>> _halving(6).tolist()
    [[0, 2, 4], [0, 1, 2], [2, 3, 4], [4, 5, 0]]
    """
    a = np.array([0, k // 3, 2 * k // 3])
    b = np.array([k // 3, 2 * k // 3, k])
    out = [np.array([[0, k // 3, 2 * k // 3]])]
    while len(a):
        keep = b - a > 1
        a, b = a[keep], b[keep]
        m = (a + b) // 2
        out.append(np.stack([a, m, b], axis=1))
        a, b = np.concatenate([a, m]), np.concatenate([m, b])
    return np.concatenate(out)[: k - 2] % k


def _large_polygon_corners(p: np.ndarray) -> np.ndarray | None:
    """Triangles (k - 2, 3) of corner positions that split a polygon of more than :data:`LARGE_POLYGON`
    corners ``p`` (k, 3) in linear or near-linear time: a flat one with a reflex corner by ear clipping in
    its plane (``mapbox_earcut``), any other (convex, or far from flat) by :func:`_halving` (a fan's
    triangles would all meet at its first corner, each as long as the polygon is wide); None for a flat
    polygon that crosses itself, and the caller keeps its fan.
    """
    reflex, _, flat_enough = _polygon_shapes(p[None])
    k = len(p)
    if not (reflex[0] and flat_enough[0]):
        return _halving(k)
    tris = np.asarray(mapbox_earcut.triangulate_float64(_plane_coordinates(p), np.array([k], np.uint32)))
    return tris.reshape(-1, 3).astype(np.int64) if tris.size == 3 * (k - 2) else None


def _plane_coordinates(p: np.ndarray) -> np.ndarray:
    """A polygon's corners (k, 3) in 2-D coordinates of the plane normal to its Newell normal, so that the
    polygon runs counter-clockwise.
    """
    normal = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
    normal = normal / max(float(np.linalg.norm(normal)), 1e-300)
    a = np.eye(3)[int(np.argmin(np.abs(normal)))]
    x = np.cross(normal, a)
    x /= max(float(np.linalg.norm(x)), 1e-300)
    y = np.cross(normal, x)
    q = p - p.mean(axis=0)
    return np.stack([q @ x, q @ y], axis=1)


def _quads_split_twice(tris: np.ndarray, owner: np.ndarray, quad: np.ndarray) -> np.ndarray:
    """The quads (a mask over the faces) one of whose triangles has the corners of another triangle: two
    quads that share both edges at a vertex of valence 2 (a "doublet" of quad-dominant meshes), each split
    along the diagonal that misses it, give the same triangle twice, its edges then on four triangles.
    Split through that vertex instead, they give a manifold.
    """
    key = np.sort(tris, axis=1)
    out = np.zeros(len(quad), bool)
    if len(key) and key[:, 2].max() < 1 << 21:         # one int64 a row: a 1-D sort, not one of rows
        key = (key[:, 0] << 42) | (key[:, 1] << 21) | key[:, 2]
        ordered = np.sort(key)
        twice = ordered[1:][ordered[1:] == ordered[:-1]]
        if not len(twice):                               # the common case: no triangle twice
            return out
        repeated = np.isin(key, twice)
    else:
        _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        repeated = counts[inverse.ravel()] > 1
    out[owner[repeated]] = True
    return out & quad


def _ear_clip(xy: np.ndarray) -> np.ndarray | None:
    """Triangles (k - 2, 3) of corner positions that split the counter-clockwise polygon ``xy`` (k, 2), by
    clipping ears (a convex corner whose triangle holds no other corner); None when none is found (a polygon
    that crosses itself), and the caller keeps its fan.
    """
    left = list(range(len(xy)))
    out: list[tuple[int, ...]] = []

    def cross(a, b, c):
        return (xy[b, 0] - xy[a, 0]) * (xy[c, 1] - xy[a, 1]) - (xy[b, 1] - xy[a, 1]) * (xy[c, 0] - xy[a, 0])

    while len(left) > 3:
        n = len(left)
        for i in range(n):
            a, b, c = left[i - 1], left[i], left[(i + 1) % n]
            if cross(a, b, c) <= 0:
                continue
            if any(cross(a, b, d) >= 0 and cross(b, c, d) >= 0 and cross(c, a, d) >= 0
                   for d in left if d not in (a, b, c) and not np.array_equal(xy[d], xy[b])):
                continue
            out.append((a, b, c))
            del left[i]
            break
        else:
            return None
    out.append(tuple(left))
    return np.array(out, np.int64)
