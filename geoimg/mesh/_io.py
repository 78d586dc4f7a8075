"""Reading and writing polygon meshes without triangulating, merging or reordering.

OBJ, OFF (ASCII and binary) and PLY (ASCII and binary, ``face`` lists or ``tristrips``) are read and
written here, so quads and n-gons survive. STL, GLB and glTF go through trimesh (``process=False``); they
hold triangles only. Every format has its exactly coincident positions joined on reading (reported; see
:mod:`geoimg.mesh._weld`).
"""
from __future__ import annotations

import json
import re
import struct
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from .._choices import MESH_FORMATS, MESH_READ_FORMATS
from .._atomic import write_all
from ..errors import InputTypeError, MeshError, MeshFileError
from ._appearance import (TEXTURE_SUFFIX, obj_colors, ply_colors, read_mtl_texture, split_corners,
                          texture_beside, write_texture)
from ._mesh import Mesh, pad_faces
from ._weld import weld_vertices
from .._types import PathLike, as_path

__all__ = ["load_mesh", "save_mesh", "mesh_file_jobs", "MESH_FORMATS", "MESH_READ_FORMATS"]

BOM = b"\xef\xbb\xbf"


def load_mesh(path: PathLike, *, weld: bool = True) -> Mesh:
    r"""Read a mesh file: faces of any size and order kept, copies of one position joined.

    Parameters
    ----------
    path : str or path-like
        An ``.obj``, ``.off``, ``.ply``, ``.stl``, ``.glb`` or ``.gltf`` file (a glTF's buffers and images
        beside it).
    weld : bool, default True
        Join copies of a position along seams (see :func:`geoimg.mesh.weld_vertices`; in an STL, a triangle
        soup, every copy), with a warning that says how many: files that store attributes per vertex (PLY,
        glTF, many OBJ exporters) repeat a position along every UV seam and hard edge, and read as stored
        their meshes fall apart into pieces. The vertices keep the order in which their positions first
        appear; texture coordinates that differ between copies are kept per face corner. ``False`` reads the
        vertices as stored.

    Returns
    -------
    Mesh
        With ``uv`` when the texture coordinates map one-to-one onto the positions; a position used with
        several (a UV seam) has them per face corner (``face_uv``) instead.

    Raises
    ------
    FileNotFoundError
        If there is no such file.
    MeshFileError
        If the format is unknown or the file is empty, truncated or corrupt.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "q.obj"
    >>> _ = p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    >>> load_mesh(p).faces.tolist()
    [[0, 1, 2, 3]]
    """
    path = as_path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no mesh file at {path}")
    ext = path.suffix.lower()
    readers = {".obj": _read_obj, ".off": _read_off, ".ply": _read_ply, ".stl": _read_trimesh, ".glb": _read_trimesh,
               ".gltf": _read_trimesh}
    if ext not in readers:
        raise MeshFileError(f"{path}: unknown mesh format {ext!r}; expected one of {', '.join(MESH_READ_FORMATS)}")
    if path.stat().st_size == 0:
        raise MeshFileError(f"{path}: the file is empty")
    try:
        mesh = readers[ext](path)
    except MeshError as e:  # a malformed mesh inside a file is a bad file: name it
        raise MeshFileError(f"{path}: {e}") from None
    except (ValueError, IndexError, struct.error, UnicodeDecodeError) as e:
        raise MeshFileError(f"{path}: corrupt or truncated {ext[1:].upper()} file ({e})") from None
    if not weld:
        return mesh
    welded = weld_vertices(mesh, seams_only=ext != ".stl")     # an STL cannot say two faces share a corner
    if welded.joined:
        warnings.warn(f"{path}: {welded.describe()}", stacklevel=2)
    return welded.mesh


def save_mesh(mesh: Mesh, path: PathLike, *, overwrite: bool = False) -> Path:
    """Write a mesh atomically; OBJ, OFF and PLY keep quads and n-gons, STL and GLB are triangulated (quads
    along their shorter diagonal).

    OBJ also writes ``vt`` and ``vn`` when the mesh has UVs or normals, ``v x y z r g b`` with colours, and
    with a texture its material library ``NAME.mtl`` and the texture ``NAME.png`` beside it (all three or
    none); PLY writes normals and colours; GLB colours, or texture coordinates with the texture.

    Parameters
    ----------
    mesh : Mesh
    path : str or path-like
    overwrite : bool, default False
        Replace an existing file.

    Returns
    -------
    pathlib.Path
        The written path.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "q.ply"
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> load_mesh(save_mesh(m, p)).faces.tolist()
    [[0, 1, 2, 3]]
    """
    return write_all(mesh_file_jobs(mesh, path), overwrite=overwrite)[0]


def mesh_file_jobs(mesh: Mesh, path: PathLike) -> list:
    """``(path, write)`` for every file that writing ``mesh`` to ``path`` makes (a textured OBJ: the OBJ, its
    ``.mtl`` and its ``.png``), for :func:`geoimg._atomic.write_all`: all of them or none. Warns when the
    format keeps no colours or texture that the mesh has.

    Parameters
    ----------
    mesh : Mesh
        The mesh to write.
    path : path-like
        The mesh file (its extension says the format).

    Returns
    -------
    list of tuple
        ``(path, write)`` pairs; ``write(tmp_path)`` writes one file.

    Examples
    --------
    >>> import geoimg
    >>> square = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> [p.name for p, _ in mesh_file_jobs(square, "square.obj")]
    ['square.obj']
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    path = as_path(path)
    ext = path.suffix.lower()
    writers = {
        ".obj": _write_obj,
        ".off": _write_off,
        ".ply": _write_ply,
        ".stl": _write_trimesh,
        ".glb": _write_trimesh,
    }
    if ext not in writers:
        raise MeshFileError(f"{path}: unknown mesh format {ext!r}; expected one of {', '.join(MESH_FORMATS)}")
    lost = [name for name, value, kept in (("colours", mesh.colors, ext in (".obj", ".ply", ".glb")),
                                           ("texture", mesh.texture, ext in (".obj", ".glb")))
            if value is not None and not kept]
    if lost:
        warnings.warn(f"{path}: {ext[1:].upper()} keeps no {' or '.join(lost)}; not written (OBJ keeps both, PLY "
                      "colours, GLB either)", stacklevel=3)
    if ext == ".obj" and mesh.texture is not None:     # the OBJ, its MTL and the texture
        stem = path.stem
        return [(path, lambda tmp: _write_obj(mesh, tmp, ext, material=stem)),
                (path.with_suffix(".mtl"), lambda tmp: tmp.write_text(
                    f"# written by geoimg\nnewmtl geoimg\nKd 1 1 1\nmap_Kd {stem}{TEXTURE_SUFFIX}\n")),
                (path.with_suffix(TEXTURE_SUFFIX), lambda tmp: write_texture(mesh.texture, tmp))]
    return [(path, lambda tmp: writers[ext](mesh, tmp, ext))]


# ----------------------------------------------------------------------------------------- OBJ
def _obj_index(tok: str, count: int) -> int:
    i = int(tok)
    if i < 0:
        return count + i
    if i == 0:
        raise MeshFileError("OBJ indices start at 1; found 0")
    return i - 1


def _obj_lines(fh):
    """The logical lines of an OBJ file: a line that ends with a backslash goes on in the next one."""
    held = ""
    for line in fh:
        stripped = line.rstrip("\r\n")
        if stripped.rstrip().endswith("\\"):
            held += stripped.rstrip()[:-1] + " "
            continue
        yield held + line
        held = ""
    if held:
        yield held


def _read_obj(path: Path) -> Mesh:
    verts, tex, faces, face_vt, libraries, used = [], [], [], [], [], []
    with open(path, encoding="utf-8-sig", errors="replace") as fh:    # -sig: a byte-order mark is dropped
        for line in _obj_lines(fh):
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
                nv, nt = len(verts), len(tex)
                fv, ft = [], []
                for tok in parts[1:]:
                    sub = tok.split("/")
                    fv.append(_obj_index(sub[0], nv))
                    ft.append(_obj_index(sub[1], nt) if len(sub) > 1 and sub[1] else -1)
                faces.append(fv)
                face_vt.append(ft)
    if not verts:
        raise MeshFileError("no vertices ('v' lines) found")
    if not faces:
        raise MeshFileError("no faces ('f' lines) found")
    short = [i for i, fv in enumerate(faces) if len(fv) < 3]
    if short:                                 # an 'f' of one or two corners is a point or a line, not a face
        if len(short) == len(faces):
            raise MeshFileError(f"no faces: all {len(faces)} 'f' lines have fewer than 3 corners")
        warnings.warn(f"{path}: left out {len(short)} 'f' lines of fewer than 3 corners (points or lines, not "
                      f"faces; the first is face {short[0] + 1})", stacklevel=4)
        drop = set(short)
        faces = [fv for i, fv in enumerate(faces) if i not in drop]
        face_vt = [ft for i, ft in enumerate(face_vt) if i not in drop]
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


def _write_obj(mesh: Mesh, tmp: Path, _ext: str, material: str | None = None) -> None:
    """OBJ: ``v`` (with ``r g b`` when the mesh has colours), ``vt`` per vertex or, with ``face_uv``, per
    distinct corner value, ``vn``; ``material`` names the MTL library (written beside) to use.
    """
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write("# written by geoimg\n")
        if material is not None:
            fh.write(f"mtllib {material}.mtl\n")
        if mesh.colors is not None:
            np.savetxt(fh, np.hstack([mesh.vertices, mesh.colors[:, :3]]), fmt="v %.17g %.17g %.17g %.6g %.6g %.6g")
        else:
            np.savetxt(fh, mesh.vertices, fmt="v %.17g %.17g %.17g")
        vt: np.ndarray | None = None
        if mesh.face_uv is not None:
            table, inverse = np.unique(mesh.face_uv.reshape(-1, 2), axis=0, return_inverse=True)
            np.savetxt(fh, table, fmt="vt %.17g %.17g")
            vt = inverse.reshape(mesh.faces.shape) + 1
        elif mesh.uv is not None:
            np.savetxt(fh, mesh.uv, fmt="vt %.17g %.17g")
            vt = mesh.faces + 1
        if mesh.normals is not None:
            np.savetxt(fh, mesh.normals, fmt="vn %.9g %.9g %.9g")
        if material is not None:
            fh.write("usemtl geoimg\n")
        one = (mesh.faces + 1).tolist()
        tok = "{0}/{1}/{0}" if vt is not None and mesh.normals is not None else "{0}/{1}" if vt is not None \
            else "{0}//{0}" if mesh.normals is not None else "{0}"
        corners = one if vt is None else vt.tolist()
        lines = []
        for row, trow, k in zip(one, corners, mesh.face_sizes.tolist()):
            lines.append("f " + " ".join(tok.format(i, j) for i, j in zip(row[:k], trow[:k])) + "\n")
        fh.write("".join(lines))


# ----------------------------------------------------------------------------------------- OFF
def _read_off(path: Path) -> Mesh:
    data = path.read_bytes()
    if data.startswith(BOM):
        data = data[len(BOM):]
    head = data[:64].lstrip()
    first_line = head.split(b"\n", 1)[0].strip()
    if first_line.startswith(b"OFF") and b"BINARY" in first_line.upper():
        return _read_off_binary(data)
    text = data.decode("utf-8", errors="replace")
    lines = [ln.split("#", 1)[0].strip() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln]
    if not lines or not lines[0].startswith(("OFF", "COFF", "NOFF", "CNOFF", "STOFF")):
        raise MeshFileError("missing OFF header")
    keyword = re.match(r"[A-Z]*OFF", lines[0])
    rest = lines[0][keyword.end() if keyword else 0:].split()     # counts may follow the keyword at once (OFF8 6 12)
    i = 1
    if not rest:
        rest, i = lines[1].split(), 2
    nv, nf = int(rest[0]), int(rest[1])
    if nv <= 0 or nf <= 0:
        raise MeshFileError(f"header says {nv} vertices and {nf} faces")
    if len(lines) < i + nv + nf:
        raise MeshFileError(f"header says {nv} vertices and {nf} faces but the file ends early")
    vertices = np.array([ln.split()[:3] for ln in lines[i:i + nv]], dtype=np.float64)
    j = i + nv
    quick = _same_size_faces([ln.split() for ln in lines[j:j + nf]])
    if quick is not None and len(quick) == nf:
        return Mesh(vertices, quick)
    faces: list[list[int]] = []
    for _ in range(nf):
        if j >= len(lines):
            raise MeshFileError(f"header says {nf} faces but the file ends after {len(faces)}")
        p = lines[j].split()
        j += 1
        k = int(p[0])
        while len(p) < k + 1 and j < len(lines):   # a long face may run on over several lines
            p += lines[j].split()
            j += 1
        if len(p) < k + 1:
            raise MeshFileError(f"a face of {k} vertices has only {len(p) - 1} indices")
        faces.append([int(x) for x in p[1:k + 1]])   # extra values on the line (colours) are ignored
    return Mesh(vertices, faces)


def _same_size_faces(rows: list[list[str]]) -> np.ndarray | None:
    """The faces of an OFF file whose face lines all hold ``k`` and ``k`` indices (no colours, none run on),
    as one array; None otherwise (the face-by-face reader then says what is wrong).
    """
    if not rows or not all(len(r) == len(rows[0]) and r[0] == rows[0][0] for r in rows):
        return None
    try:
        faces = np.array(rows, dtype=np.int64)
    except (ValueError, OverflowError):
        return None
    return faces[:, 1:] if faces[0, 0] == faces.shape[1] - 1 else None


def _read_off_binary(data: bytes) -> Mesh:
    """Binary OFF: counts and data as 32-bit words, big-endian (the original layout) or little-endian (what
    PMP and others write), each face's indices followed by a colour count, or not (PMP writes none): the
    byte order whose counts fit the file, and the face layout that reads to the file's last byte.
    """
    start = data.index(b"\n") + 1
    if len(data) < start + 12:
        raise MeshFileError("the file ends inside the binary OFF header")
    for order in (">", "<"):
        nv, nf, _ne = struct.unpack(order + "iii", data[start:start + 12])
        # each vertex takes 12 bytes and each face at least 16 (count, 3 indices)
        if nv > 0 and nf > 0 and start + 12 + 12 * nv + 16 * nf <= len(data):
            break
    else:
        raise MeshFileError(f"the binary OFF header's counts do not fit a file of {len(data)} bytes in either "
                            "byte order")
    off = start + 12
    vertices = np.frombuffer(data, order + "f4", nv * 3, off).reshape(nv, 3).astype(np.float64)
    off += nv * 12
    read = []
    for colour_counts in (True, False):
        try:
            read.append(_binary_off_faces(data, off, nf, order, colour_counts))
        except MeshFileError as e:
            read.append(e)
    parsed = [r for r in read if not isinstance(r, MeshFileError)]
    if not parsed:
        raise read[0]
    exact = [faces for faces, end in parsed if end == len(data)]
    return Mesh(vertices, exact[0] if exact else parsed[0][0])


def _binary_off_faces(data: bytes, off: int, nf: int, order: str, colour_counts: bool):
    """The ``nf`` faces of a binary OFF from byte ``off``, and the offset after them."""
    faces: list[tuple] = []
    word = struct.Struct(order + "i")
    for _ in range(nf):
        if off + 4 > len(data):
            raise MeshFileError(f"the file ends after {len(faces)} of {nf} faces")
        (k,) = word.unpack_from(data, off)
        if not 3 <= k <= (len(data) - off) // 4 - 1:
            raise MeshFileError(f"a face says it has {k} vertices")
        faces.append(struct.unpack_from(f"{order}{k}i", data, off + 4))
        off += 4 + 4 * k
        if colour_counts:
            if off + 4 > len(data):
                raise MeshFileError(f"the file ends inside face {len(faces) - 1}")
            (nc,) = word.unpack_from(data, off)
            if not 0 <= nc <= 4:
                raise MeshFileError(f"a face says it has {nc} colour components")
            off += 4 + 4 * nc
    return faces, off


def _write_off(mesh: Mesh, tmp: Path, _ext: str) -> None:
    with open(tmp, "w", encoding="ascii") as fh:
        fh.write(f"OFF\n{mesh.n_vertices} {mesh.n_faces} 0\n")
        np.savetxt(fh, mesh.vertices, fmt="%.17g %.17g %.17g")
        fh.write("".join(f"{k} " + " ".join(map(str, row[:k])) + "\n"
                         for row, k in zip(mesh.faces.tolist(), mesh.face_sizes.tolist())))


# ----------------------------------------------------------------------------------------- PLY
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


def _read_ply(path: Path) -> Mesh:
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


def _write_ply(mesh: Mesh, tmp: Path, _ext: str) -> None:
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


# ------------------------------------------------------------------------ STL, GLB, glTF (trimesh)
def _check_stl(path: Path) -> None:
    """Refuse a file that is neither a binary STL (an 80-byte header, a triangle count n, then 50 n bytes) nor
    an ASCII one (``solid`` ... ``facet``) before trimesh guesses (it then needs packages it does not declare).
    """
    size = path.stat().st_size
    with open(path, "rb") as fh:
        head = fh.read(1024)
    if size >= 84 and 84 + 50 * struct.unpack_from("<I", head, 80)[0] == size:
        return
    text = head.lstrip().lower()
    if text.startswith(b"solid") and b"facet" in text:
        return
    raise MeshFileError(f"not a valid STL: neither binary (84 + 50 bytes a triangle; this file has {size} bytes) "
                        "nor ASCII (starting with 'solid', then 'facet' lines)")


def _check_gltf(path: Path) -> None:
    """Refuse a ``.gltf`` that is not a JSON object with an ``asset`` before trimesh guesses (it then looks for
    files the glTF never named).
    """
    try:
        doc = json.loads(path.read_text(encoding="utf-8-sig"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise MeshFileError(f"not a valid glTF: its JSON cannot be read ({e})") from None
    if not isinstance(doc, dict) or "asset" not in doc:
        raise MeshFileError("not a valid glTF: a JSON object with an 'asset' is expected")


def _read_trimesh(path: Path) -> Mesh:
    if path.suffix.lower() == ".stl":
        _check_stl(path)
    if path.suffix.lower() == ".gltf":
        _check_gltf(path)
    import trimesh          # STL and GLB alone: its import costs half a second that OBJ, OFF and PLY never need
    try:
        loaded: Any = trimesh.load(str(path), process=False, force="mesh")
    except ImportError as e:
        raise MeshFileError(f"cannot be read as {path.suffix[1:].upper()}: trimesh needs the package {e.name} for "
                            f"this file (pip install {e.name})") from None
    except Exception as e:   # noqa: BLE001 - trimesh raises many kinds on a bad file
        raise MeshFileError(f"cannot be read as {path.suffix[1:].upper()} ({type(e).__name__}: {e})") from None
    v = np.asarray(loaded.vertices, np.float64)
    f = np.asarray(loaded.faces, np.int64)
    if len(v) == 0 or len(f) == 0:
        raise MeshFileError("no triangles found")
    if path.suffix.lower() == ".stl":
        return Mesh(v, f)                   # a triangle soup: load_mesh joins its coincident corners
    return Mesh(v, f, **_trimesh_look(loaded, len(v), f))


def _trimesh_look(loaded, n: int, faces: np.ndarray) -> dict:
    """A GLB's texture and texture coordinates, or its vertex colours, as Mesh fields."""
    visual = loaded.visual
    if getattr(visual, "kind", None) == "texture" and getattr(visual, "uv", None) is not None:
        image = getattr(getattr(visual, "material", None), "baseColorTexture", None) \
            or getattr(getattr(visual, "material", None), "image", None)
        uv = np.asarray(visual.uv, np.float64)
        if image is not None and uv.shape == (n, 2):       # trimesh turns glTF's into OBJ's (from the bottom)
            rgb = np.asarray(image.convert("RGBA" if image.mode in ("RGBA", "LA", "P") else "RGB"), np.uint8)
            return {"face_uv": uv[faces], "texture": rgb}
    if getattr(visual, "kind", None) == "vertex":
        rgba = np.asarray(visual.vertex_colors, np.float64) / 255.0
        if rgba.shape == (n, 4):
            return {"colors": rgba if (rgba[:, 3] < 1).any() else rgba[:, :3]}
    return {}


def _write_trimesh(mesh: Mesh, tmp: Path, ext: str) -> None:
    """STL (triangles only) and GLB (triangles with colours, or texture coordinates and the texture,
    vertices split at UV seams).
    """
    import trimesh
    visual: Any = None
    if ext == ".glb" and mesh.texture is not None:
        source, uv, faces = split_corners(mesh)
        texture = Image.fromarray(np.ascontiguousarray(mesh.texture))
        mesh = Mesh(mesh.vertices[source], faces)
        visual = trimesh.visual.TextureVisuals(uv=uv, image=texture)
    elif ext == ".glb" and mesh.colors is not None:
        visual = trimesh.visual.ColorVisuals(vertex_colors=np.round(mesh.colors * 255).astype(np.uint8))
    tris, _ = mesh.triangulate(quads="shorter")         # as geometry images are drawn and measured
    tm = trimesh.Trimesh(mesh.vertices, tris, process=False, visual=visual)
    with open(tmp, "wb") as fh:
        tm.export(fh, file_type=ext[1:])
