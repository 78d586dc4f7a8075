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


def _exact_format(values: np.ndarray) -> str:
    """The ``%`` format that keeps ``values``: ``%.9g`` when every value is a float32 (a geometry image's quad
    mesh: 9 significant digits name a float32 exactly, read back in single precision to the same bits and in
    double within 5e-9 of each value, relatively; written in half the time of 17), else ``%.17g`` (a
    float64's, read back to the same bits).

    Examples
    --------
    >>> _exact_format(np.array([0.5, 0.1], np.float32).astype(np.float64)), _exact_format(np.array([0.1]))
    ('%.9g', '%.17g')
    """
    values = np.asarray(values, np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        single = values.astype(np.float32).astype(np.float64)
    return "%.9g" if np.array_equal(single, values) else "%.17g"


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
    ``v``), one line per face in order: the text of ``%d`` formatting.
    """
    one = mesh.faces + 1
    if mesh.face_uv is None:                  # every index of a corner is its vertex's
        token = {(False, False): "{v}", (True, False): "{v}/{v}", (False, True): "{v}//{v}",
                 (True, True): "{v}/{v}/{v}"}[(vt is not None, mesh.normals is not None)]
        chars, lengths = _vertex_tokens(mesh.n_vertices, token)
        for start in range(0, len(one), ROWS_AT_ONCE):
            fh.write(_token_lines(one[start:start + ROWS_AT_ONCE], chars, lengths))
        return
    used = mesh.faces >= 0
    assert vt is not None
    parts: tuple[np.ndarray, ...] = (one, vt, one) if mesh.normals is not None else (one, vt)
    token = "%d/%d/%d" if mesh.normals is not None else "%d/%d"
    templates = {int(k): "f " + " ".join([token] * int(k)) + "\n" for k in np.unique(mesh.face_sizes)}
    sizes = mesh.face_sizes.tolist()
    args = np.stack([p[used] for p in parts], axis=1)             # the corners in face order, row by row
    ends = np.cumsum(mesh.face_sizes)
    for start in range(0, len(sizes), ROWS_AT_ONCE):
        stop = min(start + ROWS_AT_ONCE, len(sizes))
        lo, hi = (ends[start - 1] if start else 0), ends[stop - 1]
        text = "".join(templates[k] for k in sizes[start:stop])
        fh.write(text % tuple(args[lo:hi].ravel().tolist()))


def _vertex_tokens(n: int, token: str) -> tuple[np.ndarray, np.ndarray]:
    """The corner text of each 1-based vertex index ``1 .. n`` (``token`` with ``{v}`` for the index, e.g.
    ``"{v}/{v}/{v}"``) as rows of a character array, left-aligned, and their lengths.

    Examples
    --------
    >>> chars, lengths = _vertex_tokens(10, "{v}//{v}")
    >>> chars[0, :4].tobytes(), chars[9].tobytes(), lengths[[0, 9]].tolist()
    (b'1//1', b'10//10', [4, 6])
    """
    pieces = [np.frombuffer(piece.encode(), np.uint8) for piece in token.split("{v}")]
    width = len(str(n))
    size = sum(len(piece) for piece in pieces) + (len(pieces) - 1) * width
    out = np.zeros((n, size), np.uint8)
    lengths = np.zeros(n, np.int64)
    for d in range(1, width + 1):             # the indices of d digits: a run of rows, one slice each
        lo, hi = 10 ** (d - 1), min(10 ** d - 1, n)
        index = np.arange(lo, hi + 1, dtype=np.int64)
        digits = (index[:, None] // 10 ** np.arange(d - 1, -1, -1, dtype=np.int64) % 10 + 48).astype(np.uint8)
        parts = [np.broadcast_to(pieces[0], (len(index), len(pieces[0])))]
        for piece in pieces[1:]:
            parts += [digits, np.broadcast_to(piece, (len(index), len(piece)))]
        row = np.concatenate(parts, axis=1)
        out[lo - 1:hi, :row.shape[1]] = row
        lengths[lo - 1:hi] = row.shape[1]
    return out, lengths


def _token_lines(faces: np.ndarray, chars: np.ndarray, lengths: np.ndarray) -> str:
    """``f`` lines of faces given by 1-based vertex indices (0 or less: a shorter polygon's padding), each
    corner the vertex's token (:func:`_vertex_tokens`): gathered and masked as one character array (262,144
    quads: 0.17 s, where ``%d`` formatting 65,536 faces at a time took 0.43).
    """
    n, k = faces.shape
    present = faces > 0
    row = np.where(present, faces - 1, 0)
    width = chars.shape[1]
    body = np.concatenate([np.full((n, k, 1), 32, np.uint8), chars[row]], axis=2)          # " " + token
    keep = np.concatenate([present[..., None], (np.arange(width)[None, None, :] < lengths[row][..., None])
                           & present[..., None]], axis=2)
    text = np.concatenate([np.full((n, 1), 102, np.uint8), body.reshape(n, -1), np.full((n, 1), 10, np.uint8)],
                          axis=1)
    mask = np.concatenate([np.ones((n, 1), bool), keep.reshape(n, -1), np.ones((n, 1), bool)], axis=1)
    return text[mask].tobytes().decode("ascii")


def write_obj(mesh: Mesh, tmp: Path, _ext: str, material: str | None = None) -> None:
    """OBJ: ``v`` (with ``r g b`` when the mesh has colours), ``vt`` per vertex or, with ``face_uv``, per
    distinct corner value, ``vn``; ``material`` names the MTL library (written beside) to use.
    """
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write("# written by geoimg\n")
        if material is not None:
            fh.write(f"mtllib {material}.mtl\n")
        g = _exact_format(mesh.vertices)
        if mesh.colors is not None:
            _rows(fh, f"v {g} {g} {g} %.6g %.6g %.6g\n", np.hstack([mesh.vertices, mesh.colors[:, :3]]))
        else:
            _rows(fh, f"v {g} {g} {g}\n", mesh.vertices)
        vt: np.ndarray | None = None
        if mesh.face_uv is not None:
            table, inverse = np.unique(mesh.face_uv.reshape(-1, 2), axis=0, return_inverse=True)
            g = _exact_format(table)
            _rows(fh, f"vt {g} {g}\n", table)
            vt = inverse.reshape(mesh.faces.shape) + 1
        elif mesh.uv is not None:
            g = _exact_format(mesh.uv)
            _rows(fh, f"vt {g} {g}\n", mesh.uv)
            vt = mesh.faces + 1
        if mesh.normals is not None:
            _rows(fh, "vn %.9g %.9g %.9g\n", mesh.normals)
        if material is not None:
            fh.write("usemtl geoimg\n")
        _faces(fh, mesh, vt)
