"""OFF files, ASCII and binary (either byte order): faces of any size, colours per vertex or face."""
from __future__ import annotations

import re
import struct
from pathlib import Path

import numpy as np

from ..errors import MeshFileError
from ._mesh import Mesh
from ._bom import BOM

__all__ = ["read_off", "write_off"]


def read_off(path: Path) -> Mesh:
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
    vertices = _numbers(lines[i:i + nv], np.float64, nv, 3)
    if vertices is None:            # more than x, y, z on a line (normals, colours), or something unreadable
        vertices = np.array([ln.split()[:3] for ln in lines[i:i + nv]], dtype=np.float64)
    j = i + nv
    quick = _numbers(lines[j:j + nf], np.int64, nf, None)
    if quick is not None and (quick[:, 0] == quick.shape[1] - 1).all():     # every line k and k indices
        return Mesh(vertices, quick[:, 1:])
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


def _numbers(lines: list[str], dtype, rows: int, width: int | None) -> np.ndarray | None:
    """The numbers of ``rows`` lines in one parse, as a (rows, width) array (``width`` None: the first line's
    count); None where a number does not parse or the count does not fill the rows (the line-by-line
    readers then take over: colours or normals on a line, faces of mixed sizes or running on). A tenth of the
    time of splitting every line (bunny.off's 35k vertices).
    """
    if not lines:
        return None
    width = len(lines[0].split()) if width is None else width
    try:
        values = np.fromstring("\n".join(lines), dtype=dtype, sep=" ")
    except ValueError:
        return None
    if values.dtype.kind == "i" and len(values) and (values.max() == np.iinfo(dtype).max
                                                     or values.min() == np.iinfo(dtype).min):
        return None                 # numpy clamps a number past 64 bits to the limit: the line readers refuse it
    return values.reshape(rows, width) if width and len(values) == rows * width else None


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


def write_off(mesh: Mesh, tmp: Path, _ext: str) -> None:
    with open(tmp, "w", encoding="ascii") as fh:
        fh.write(f"OFF\n{mesh.n_vertices} {mesh.n_faces} 0\n")
        np.savetxt(fh, mesh.vertices, fmt="%.17g %.17g %.17g")
        fh.write("".join(f"{k} " + " ".join(map(str, row[:k])) + "\n"
                         for row, k in zip(mesh.faces.tolist(), mesh.face_sizes.tolist())))
