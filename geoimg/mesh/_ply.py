"""PLY files, ASCII and binary: faces of any size under any list name, triangle strips, normals, colours,
per-face texture coordinates (MeshLab's) and the texture a comment names.
"""
from __future__ import annotations

import struct
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MeshFileError
from ._appearance import ply_colors, texture_beside
from ._mesh import Mesh, pad_faces
from ._bom import BOM

__all__ = ["read_ply", "write_ply"]


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def _ply_type(name: str) -> str:
    if name not in _PLY_TYPES:
        raise MeshFileError(f"PLY property type {name!r} is not one of the PLY types "
                            f"({', '.join(sorted(_PLY_TYPES))})")
    return _PLY_TYPES[name]


def _parse_ply_header(data: bytes):
    if data.startswith(BOM):
        data = data[len(BOM):]
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise MeshFileError("missing PLY header")
    body = data.index(b"\n", end) + 1
    fmt = None
    elements: list[tuple[str, int, list]] = []       # (name, count, [(name, kind, count type, item type)])
    textures = []
    for line in data[:end].decode("ascii", errors="replace").splitlines()[1:]:
        p = line.split()
        if len(p) > 2 and p[0] == "comment" and p[1].lower() == "texturefile":
            textures.append(" ".join(p[2:]))            # MeshLab's texture file; its name may hold spaces
        if not p or p[0] in ("comment", "obj_info"):
            continue
        if p[0] == "format":
            fmt = p[1]
        elif p[0] == "element":
            if len(p) != 3 or int(p[2]) < 0:
                raise MeshFileError(f"bad PLY element line {line.strip()!r}")
            elements.append((p[1], int(p[2]), []))
        elif p[0] == "property":
            if not elements:
                raise MeshFileError("a PLY property comes before any element")
            if p[1] == "list" and len(p) == 5:
                elements[-1][2].append((p[4], "list", _ply_type(p[2]), _ply_type(p[3])))
            elif p[1] != "list" and len(p) == 3:
                elements[-1][2].append((p[2], _ply_type(p[1]), None, None))
            else:
                raise MeshFileError(f"bad PLY property line {line.strip()!r}")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise MeshFileError(f"unknown PLY format {fmt!r}")
    seen = [el[0] for el in elements]
    twice = sorted({name for name in seen if seen.count(name) > 1})
    if twice:                     # a second 'face' element would stand in for the first one's values
        raise MeshFileError(f"PLY element {twice[0]!r} declared {seen.count(twice[0])} times")
    # every element with data takes at least a byte (binary) or a token (ascii) per property and item:
    # counts that the rest of the file cannot hold are refused before anything is allocated
    room = len(data) - body
    for name, count, props in elements:
        if count and not props:
            raise MeshFileError(f"PLY element {name!r} declares {count} items but no properties")
        least = sum(1 if fmt == "ascii" else np.dtype(p[2] if p[1] == "list" else p[1]).itemsize for p in props)
        if count * least > room:
            raise MeshFileError(f"PLY element {name!r} declares {count} items, more than the file's "
                                f"{room} bytes of data can hold")
    return fmt, elements, body, textures


def read_ply(path: Path) -> Mesh:
    data = path.read_bytes()
    fmt, elements, body, textures = _parse_ply_header(data)
    values = {}
    if fmt == "ascii":
        values = _read_ply_ascii(path, data[body:], elements)
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        pos = body
        for name, count, props in elements:
            cols, pos = _read_ply_binary_element(data, pos, count, props, order)
            values[name] = cols
    if "vertex" not in values or not all(k in values["vertex"] for k in "xyz"):
        raise MeshFileError("no vertex element with x, y, z")
    vx = values["vertex"]
    vertices = np.stack([np.asarray(vx[k], np.float64) for k in "xyz"], axis=1)
    faces: Any = []
    if "face" in values:
        lists = [p[0] for el in elements if el[0] == "face" for p in el[2] if p[1] == "list"]
        names = [n for n in ("vertex_indices", "vertex_index") if n in lists] + lists
        if not names:
            raise MeshFileError("the face element has no list property of vertex indices")
        faces = values["face"][names[0]]
    elif "tristrips" in values:
        faces = _strips_to_triangles(values["tristrips"]["vertex_indices"])
    if len(faces) == 0:
        raise MeshFileError("no faces")
    faces = faces if isinstance(faces, np.ndarray) else pad_faces(faces)
    face_uv, texture = _ply_face_uv(path, values.get("face", {}), faces, textures)
    uv = None
    for a, b in (("u", "v"), ("s", "t"), ("texture_u", "texture_v")):
        if a in vx and b in vx:
            uv = np.stack([np.asarray(vx[a], float), np.asarray(vx[b], float)], axis=1)
    normals = None
    if all(k in vx for k in ("nx", "ny", "nz")):
        normals = np.stack([np.asarray(vx[k], float) for k in ("nx", "ny", "nz")], axis=1)
    return Mesh(vertices, faces, uv=uv, normals=normals, colors=ply_colors(vx), face_uv=face_uv, texture=texture)


def _ply_face_uv(path: Path, face: dict, faces: np.ndarray, textures: list):
    """``(face_uv, texture)`` from a face element's ``texcoord`` list (MeshLab: u, v per corner) and the
    header's ``TextureFile`` comment; (None, None) when there are none, or with a warning when they do not
    fit the faces.
    """
    name = next((n for n in ("texcoord", "texcoords", "texture_coordinates") if n in face), None)
    if name is None:
        return None, None
    sizes = (faces >= 0).sum(axis=1)
    rows = face[name]
    if len(rows) != len(faces) or any(len(r) != 2 * k for r, k in zip(rows, sizes.tolist())):
        warnings.warn(f"{path}: the faces' {name} lists do not hold a (u, v) per corner; not read", stacklevel=5)
        return None, None
    face_uv = np.zeros(faces.shape + (2,))
    for k in np.unique(sizes).tolist():
        chosen = np.flatnonzero(sizes == k)
        face_uv[chosen, :k] = np.array([rows[i] for i in chosen.tolist()], np.float64).reshape(-1, k, 2)
    if not np.isfinite(face_uv).all():
        warnings.warn(f"{path}: the faces' {name} hold NaN or infinite values; not read", stacklevel=5)
        return None, None
    return face_uv, texture_beside(path, path.parent / textures[0]) if textures else None


def _ascii_item(tokens: list, pos: int, props: list, cols: dict) -> int:
    """One element item's properties from ``tokens`` at ``pos`` into ``cols``; the position after them."""
    for pname, kind, _ctype, itype in props:
        if kind == "list":
            k = int(tokens[pos])
            item = float if itype[0] == "f" else int
            if pos + 1 + k > len(tokens):
                raise MeshFileError("the file ends before all elements were read")
            cols[pname].append([item(t) for t in tokens[pos + 1:pos + 1 + k]])
            pos += 1 + k
        else:
            cols[pname].append(float(tokens[pos]))
            pos += 1
    return pos


def _read_ply_ascii(path: Path, body: bytes, elements: list) -> dict:
    """The elements of an ASCII PLY body. Writers put one item a line, so when the lines are as many as the
    items, each item is read from its own line, and values a line holds beyond what the header declares
    are left out (with a warning: MeshLab writes some); otherwise the values are read as one stream.
    """
    lines = [ln for ln in body.split(b"\n") if ln.strip()]
    total = sum(count for _, count, _ in elements)
    values = {}
    if len(lines) == total:
        at, extra = 0, 0
        for name, count, props in elements:
            cols: dict[str, list] = {p[0]: [] for p in props}
            for row in lines[at:at + count]:
                tokens = row.split()
                end = _ascii_item(tokens, 0, props, cols)
                extra += end < len(tokens)
            at += count
            values[name] = cols
        if extra:
            warnings.warn(f"{path}: {extra} PLY lines hold more values than the header declares; the extra ones "
                          "are left out", stacklevel=5)
        return values
    tokens = body.split()
    pos = 0
    for name, count, props in elements:
        cols = {p[0]: [] for p in props}
        for _ in range(count):
            pos = _ascii_item(tokens, pos, props, cols)
        values[name] = cols
    return values


def _read_ply_binary_element(data, pos, count, props, order):
    if all(p[1] != "list" for p in props):
        dt = np.dtype([(p[0], order + p[1]) for p in props])
        if pos + dt.itemsize * count > len(data):
            raise MeshFileError("the file ends before all elements were read")
        arr = np.frombuffer(data, dt, count, pos)
        return {p[0]: arr[p[0]] for p in props}, pos + dt.itemsize * count
    if len(props) == 1 and count:
        # fast path: one list property whose every entry has the same length
        pname, _, ctype, itype = props[0]
        ct = np.dtype(order + ctype)
        k = int(np.frombuffer(data, ct, 1, pos)[0])
        dt = np.dtype([("n", ct), ("i", order + itype, (k,))])
        if pos + dt.itemsize * count <= len(data):
            arr = np.frombuffer(data, dt, count, pos)
            if np.all(arr["n"] == k):
                return {pname: arr["i"].astype(np.int64)}, pos + dt.itemsize * count
    cols = {p[0]: [] for p in props}
    for _ in range(count):
        for pname, kind, ctype, itype in props:
            if kind == "list":
                ct, it = np.dtype(order + ctype), np.dtype(order + itype)
                k = int(np.frombuffer(data, ct, 1, pos)[0])
                pos += ct.itemsize
                cols[pname].append(np.frombuffer(data, it, k, pos).tolist())
                pos += it.itemsize * k
            else:
                t = np.dtype(order + kind)
                cols[pname].append(float(np.frombuffer(data, t, 1, pos)[0]))
                pos += t.itemsize
    return cols, pos


def _strips_to_triangles(strips) -> np.ndarray:
    tris = []
    for strip in strips:
        run: list[int] = []
        for idx in list(strip) + [-1]:
            if idx < 0:
                for j in range(len(run) - 2):
                    a, b, c = run[j], run[j + 1], run[j + 2]
                    if a != b and b != c and a != c:
                        tris.append((a, b, c) if j % 2 == 0 else (b, a, c))
                run = []
            else:
                run.append(int(idx))
    return np.array(tris, np.int64).reshape(-1, 3)


def write_ply(mesh: Mesh, tmp: Path, _ext: str) -> None:
    nrm = mesh.normals is not None
    head = ["ply", "format binary_little_endian 1.0", "comment written by geoimg",
            f"element vertex {mesh.n_vertices}", "property double x", "property double y", "property double z"]
    if nrm:
        head += ["property float nx", "property float ny", "property float nz"]
    rgba = [] if mesh.colors is None else ["red", "green", "blue", "alpha"][: mesh.colors.shape[1]]
    head += [f"property uchar {c}" for c in rgba]
    head += [f"element face {mesh.n_faces}", "property list uchar int vertex_indices", "end_header"]
    vdt = [("x", "<f8"), ("y", "<f8"), ("z", "<f8")] + ([("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4")] if nrm else [])
    v = np.zeros(mesh.n_vertices, vdt + [(c, "u1") for c in rgba])
    v["x"], v["y"], v["z"] = mesh.vertices.T
    if mesh.normals is not None:
        v["nx"], v["ny"], v["nz"] = mesh.normals.T
    if mesh.colors is not None:
        for k, c in enumerate(rgba):
            v[c] = np.round(mesh.colors[:, k] * 255)
    with open(tmp, "wb") as fh:
        fh.write(("\n".join(head) + "\n").encode("ascii"))
        fh.write(v.tobytes())
        if np.all(mesh.face_sizes == mesh.faces.shape[1]):
            k = mesh.faces.shape[1]
            f = np.zeros(mesh.n_faces, [("n", "u1"), ("i", "<i4", (k,))])
            f["n"], f["i"] = k, mesh.faces
            fh.write(f.tobytes())
        else:
            for row, k in zip(mesh.faces, mesh.face_sizes):
                fh.write(struct.pack("<B", k) + row[:k].astype("<i4").tobytes())
