r"""Wavefront OBJ files: faces of any size, ``vt`` and ``vn`` per corner, ``v x y z r g b`` colours, an MTL
material's texture, ``\\`` continuations.
"""
from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np

from ..errors import MeshFileError
from ._appearance import obj_colors, read_mtl_texture
from ._mesh import MAX_PADDED_ENTRIES, Mesh, pad_faces

__all__ = ["read_obj", "write_obj"]


def _obj_index(tok: str, count: int) -> int:
    i = int(tok)
    if i < 0:
        return count + i
    if i == 0:
        raise MeshFileError("OBJ indices start at 1; found 0")
    return i - 1


def _obj_lines(lines):
    """The logical lines of an OBJ file: a line that ends with a backslash goes on in the next one."""
    held = ""
    for line in lines:
        stripped = line.rstrip("\r\n")
        if stripped.rstrip().endswith("\\"):
            held += stripped.rstrip()[:-1] + " "
            continue
        yield held + line
        held = ""
    if held:
        yield held


# a corner written with positive indices: v, v/vt, v/vt/vn, v//vn or v/vt/ (ASCII digits only)
_CORNER = "[0-9]+(?:/[0-9]*(?:/[0-9]*)?)?"
_CORNERS = re.compile(f"{_CORNER}(?: {_CORNER})*")
_INDICES = re.compile("([0-9]+)(?:/([0-9]*)(?:/[0-9]*)?)?")
# the usual files write every corner alike: (the corners, the separator within one, its numbers, the vt's place)
_N = "[0-9]{1,18}"                                     # below 2^63
_ALIKE = [(re.compile(f"{one}(?: {one})*"), sep, per, vt) for one, sep, per, vt in (
    (_N, "", 1, None), (f"{_N}/{_N}", "/", 2, 1), (f"{_N}/{_N}/{_N}", "/", 3, 1), (f"{_N}//{_N}", "//", 2, None))]


def _numbers(joined: str) -> tuple | None:
    """``(v, vt, given)``: each corner's vertex and vt index as written (1-based; vt 0 where none is
    ``given``), from the corners joined by single spaces, or None where they are not all numbers.
    """
    for corners, sep, per, vt in _ALIKE:
        if corners.fullmatch(joined):                  # all alike: numbers read by numpy's parser
            table = np.fromstring(joined.replace(sep, " ") if sep else joined, np.int64, sep=" ").reshape(-1, per)
            return table[:, 0], table[:, vt] if vt else np.zeros(len(table), np.int64), vt is not None
    if _CORNERS.fullmatch(joined) is None:
        return None
    pairs = _INDICES.findall(joined)                   # one (v, vt or "") per corner, in order
    try:
        return (np.array([a for a, _ in pairs], np.int64), np.array([b or "0" for _, b in pairs], np.int64),
                np.array([b != "" for _, b in pairs]))
    except OverflowError:                              # beyond 64 bits
        return None


def _corners_at_once(rows: list) -> tuple | None:
    """``(faces, face_vt, sizes)`` of the 'f' lines' corner tokens (a list per line), 0-based and padded with
    -1, a missing vt -1, when every index is written as a positive number (a file's usual form), parsed at
    once; None otherwise (relative or zero indices, other forms: :func:`_corners_one_by_one` reads them and
    says what is wrong).
    """
    sizes = np.fromiter(map(len, rows), np.int64, len(rows))
    if not len(rows) or len(rows) * int(sizes.max()) > MAX_PADDED_ENTRIES:
        return None
    joined = " ".join([" ".join(r) for r in rows])
    found = _numbers(joined) if joined.isascii() else None
    if found is None:
        return None
    v, t, given = found
    if len(v) != int(sizes.sum()) or not (v > 0).all() or (given & (t == 0)).any():
        return None
    used = np.arange(int(sizes.max())) < sizes[:, None]
    faces, face_vt = np.full(used.shape, -1, np.int64), np.full(used.shape, -1, np.int64)
    faces[used], face_vt[used] = v - 1, t - 1
    return faces, face_vt, sizes


def _corners_one_by_one(rows: list, nv: list, nt: list) -> tuple:
    """What :func:`_corners_at_once` returns, as lists, for any form: relative indices count back from the
    ``nv`` vertices and ``nt`` vt lines before each 'f' line; an index 0 is refused.
    """
    faces, face_vt = [], []
    for row, n_v, n_t in zip(rows, nv, nt):
        fv, ft = [], []
        for tok in row:
            sub = tok.split("/")
            fv.append(_obj_index(sub[0], n_v))
            ft.append(_obj_index(sub[1], n_t) if len(sub) > 1 and sub[1] else -1)
        faces.append(fv)
        face_vt.append(ft)
    return faces, face_vt, np.array([len(fv) for fv in faces], np.int64)


def read_obj(path: Path) -> Mesh:
    verts, tex, rows, nv, nt, libraries, used = [], [], [], [], [], [], []
    with open(path, encoding="utf-8-sig", errors="replace") as fh:    # -sig: a byte-order mark is dropped
        text = fh.read()
    lines = text.split("\n")
    for line in _obj_lines(lines) if "\\" in text else lines:
        line = line.lstrip()                                            # indented lines count too
        if not line or line[0] not in "vfmu":
            continue
        parts = line.split()
        if not parts:
            continue
        key = parts[0]
        if key == "mtllib" and len(parts) > 1:
            libraries.append(" ".join(parts[1:]))
        elif key == "usemtl" and len(parts) > 1:
            used.append(" ".join(parts[1:]))
        elif key == "v":
            verts.append(parts[1:8])
        elif key == "vt":
            tex.append(parts[1:3])
        elif key == "f":
            rows.append(parts[1:])
            nv.append(len(verts))
            nt.append(len(tex))
    faces, face_vt, sizes = _corners_at_once(rows) or _corners_one_by_one(rows, nv, nt)
    if not verts:
        raise MeshFileError("no vertices ('v' lines) found")
    if not len(sizes):
        raise MeshFileError("no faces ('f' lines) found")
    short = np.flatnonzero(sizes < 3)
    if len(short):                            # an 'f' of one or two corners is a point or a line, not a face
        if len(short) == len(sizes):
            raise MeshFileError(f"no faces: all {len(sizes)} 'f' lines have fewer than 3 corners")
        warnings.warn(f"{path}: left out {len(short)} 'f' lines of fewer than 3 corners (points or lines, not "
                      f"faces; the first is face {short[0] + 1})", stacklevel=4)
        keep = sizes >= 3
        if isinstance(faces, np.ndarray):
            faces, face_vt = faces[keep], face_vt[keep]
        else:
            faces = [fv for fv, k in zip(faces, keep) if k]
            face_vt = [ft for ft, k in zip(face_vt, keep) if k]
    if any(len(v) < 3 for v in verts):
        raise MeshFileError("a 'v' line has fewer than 3 coordinates")
    vertices = np.array([v[:3] for v in verts], dtype=np.float64)
    colors = obj_colors(verts, path)
    f = pad_faces(faces)
    uv = face_uv = texture = None
    if tex:
        t = pad_faces(face_vt)
        uv, face_uv = _obj_uv(f, t, np.array([x + ["0"] * (2 - len(x)) for x in tex], dtype=np.float64),
                              len(vertices), path)
        if face_uv is not None and libraries:
            texture = read_mtl_texture(path, libraries, used)
    return Mesh(vertices, f, uv=uv, colors=colors, face_uv=face_uv, texture=texture)


def _obj_uv(f: np.ndarray, t: np.ndarray, tex: np.ndarray, n: int, path: Path):
    """``(uv, face_uv)``: texture coordinates per corner when every corner has a vt, and per vertex as well
    when each position is used with a single vt (a UV seam gives per-corner ones only); (None, None) when
    some corners have none (with a warning).
    """
    used = f >= 0
    if np.any(t[used] < 0):
        warnings.warn(f"{path}: some faces have no vt indices; texture coordinates not read", stacklevel=4)
        return None, None
    if np.any(t[used] >= len(tex)):
        raise MeshFileError(f"a face refers to vt {int(t.max()) + 1} but there are only {len(tex)}")
    face_uv = tex[np.where(used, t, 0)]
    pv, pt = f[used], t[used]
    pairs = np.unique(np.stack([pv, pt], axis=1), axis=0)
    if len(pairs) != len(np.unique(pv)):    # UV seams: (position, vt) pairs not one-to-one
        return None, face_uv
    uv = np.zeros((n, 2))
    uv[pairs[:, 0]] = tex[pairs[:, 1]]
    return uv, face_uv


ROWS_AT_ONCE = 65536      # rows formatted by one % operation (in C), in blocks to bound the text held


def _rows(fh, line: str, values: np.ndarray) -> None:
    """Each row of ``values`` as ``line % row`` (the text numpy.savetxt writes, formatted in C a block at a
    time instead of a row at a time).
    """
    values = np.asarray(values, np.float64)
    for start in range(0, len(values), ROWS_AT_ONCE):
        block = values[start:start + ROWS_AT_ONCE]
        fh.write((line * len(block)) % tuple(block.ravel().tolist()))


def _faces(fh, mesh: Mesh, vt: np.ndarray | None) -> None:
    """The ``f`` lines: each corner ``v``, ``v/t``, ``v//n`` or ``v/t/n`` (normals are per vertex, so ``n`` is
    ``v``), one line per face in order.
    """
    one = mesh.faces + 1
    used = mesh.faces >= 0
    parts: tuple[np.ndarray, ...]
    if vt is not None and mesh.normals is not None:
        token, parts = "%d/%d/%d", (one, vt, one)
    elif vt is not None:
        token, parts = "%d/%d", (one, vt)
    elif mesh.normals is not None:
        token, parts = "%d//%d", (one, one)
    else:
        token, parts = "%d", (one,)
    templates = {int(k): "f " + " ".join([token] * int(k)) + "\n" for k in np.unique(mesh.face_sizes)}
    sizes = mesh.face_sizes.tolist()
    args = np.stack([p[used] for p in parts], axis=1)             # the corners in face order, row by row
    ends = np.cumsum(mesh.face_sizes)
    for start in range(0, len(sizes), ROWS_AT_ONCE):
        stop = min(start + ROWS_AT_ONCE, len(sizes))
        lo, hi = (ends[start - 1] if start else 0), ends[stop - 1]
        text = "".join(templates[k] for k in sizes[start:stop])
        fh.write(text % tuple(args[lo:hi].ravel().tolist()))


def write_obj(mesh: Mesh, tmp: Path, _ext: str, material: str | None = None) -> None:
    """OBJ: ``v`` (with ``r g b`` when the mesh has colours), ``vt`` per vertex or, with ``face_uv``, per
    distinct corner value, ``vn``; ``material`` names the MTL library (written beside) to use.
    """
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write("# written by geoimg\n")
        if material is not None:
            fh.write(f"mtllib {material}.mtl\n")
        if mesh.colors is not None:
            _rows(fh, "v %.17g %.17g %.17g %.6g %.6g %.6g\n", np.hstack([mesh.vertices, mesh.colors[:, :3]]))
        else:
            _rows(fh, "v %.17g %.17g %.17g\n", mesh.vertices)
        vt: np.ndarray | None = None
        if mesh.face_uv is not None:
            table, inverse = np.unique(mesh.face_uv.reshape(-1, 2), axis=0, return_inverse=True)
            _rows(fh, "vt %.17g %.17g\n", table)
            vt = inverse.reshape(mesh.faces.shape) + 1
        elif mesh.uv is not None:
            _rows(fh, "vt %.17g %.17g\n", mesh.uv)
            vt = mesh.faces + 1
        if mesh.normals is not None:
            _rows(fh, "vn %.9g %.9g %.9g\n", mesh.normals)
        if material is not None:
            fh.write("usemtl geoimg\n")
        _faces(fh, mesh, vt)
