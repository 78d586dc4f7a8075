"""Binary STL files written with numpy: triangles (quads split along their shorter diagonal, as geometry
images are drawn and measured), each with its unit normal, in single precision as the format stores them.
Reading STL goes through trimesh (:mod:`._trimesh_io`), whose import alone costs more than writing a 513^2
image's quad mesh here.
"""
from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from ..errors import MeshFileError
from ._mesh import Mesh

__all__ = ["write_stl", "STL_RECORD"]

# one triangle of a binary STL: its normal, its three corners, a 16-bit attribute (0): 50 bytes
STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def write_stl(mesh: Mesh, tmp: Path, _ext: str) -> None:
    """A binary STL of ``mesh``: an 80-byte header, the triangle count, a :data:`STL_RECORD` per triangle (a
    degenerate triangle's normal is zero).

    Examples
    --------
    >>> import tempfile
    >>> square = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> path = Path(tempfile.mkdtemp()) / "square.stl"
    >>> write_stl(square, path, ".stl")
    >>> data = path.read_bytes()
    >>> len(data), struct.unpack("<I", data[80:84])[0], np.frombuffer(data[84:], STL_RECORD)["normal"][0].tolist()
    (184, 2, [0.0, 0.0, 1.0])
    """
    tris, _ = mesh.triangulate(quads="shorter")
    if len(tris) >= 2 ** 32:
        raise MeshFileError(f"{tmp.name}: {len(tris)} triangles; a binary STL counts at most 2^32 - 1")
    corners = mesh.vertices[tris]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    records = np.zeros(len(tris), STL_RECORD)
    records["normal"] = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    records["corners"] = corners
    with open(tmp, "wb") as fh:
        fh.write(b"binary STL written by geoimg".ljust(80, b" ") + struct.pack("<I", len(tris)))
        fh.write(records.tobytes())
