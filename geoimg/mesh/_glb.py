"""Binary glTF 2.0 (``.glb``) written with numpy: one mesh of triangles (quads split along their shorter
diagonal, as geometry images are drawn and measured) with, when the mesh has them, its vertex colours
(``COLOR_0``) or its texture (``TEXCOORD_0``, the image as PNG in the file, vertices split where a position has
several texture coordinates). Reading glTF goes through trimesh (:mod:`._trimesh_io`), whose import alone costs
more than writing a 513² image's quad mesh here.
"""
from __future__ import annotations

import io
import json
import struct
from pathlib import Path

import numpy as np
from PIL import Image

from ..errors import MeshFileError
from ._appearance import split_corners
from ._mesh import Mesh

__all__ = ["write_glb"]

_FLOAT, _UBYTE, _UINT = 5126, 5121, 5125        # glTF component types
_VERTICES, _INDICES = 34962, 34963               # buffer view targets


def write_glb(mesh: Mesh, tmp: Path, _ext: str) -> None:
    """A GLB of ``mesh``: positions (float32) and triangle indices (uint32), vertex colours as normalized RGBA
    bytes, or texture coordinates (v measured from the image's top, as glTF has it) and the texture.

    Examples
    --------
    >>> import tempfile
    >>> square = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> path = Path(tempfile.mkdtemp()) / "square.glb"
    >>> write_glb(square, path, ".glb")
    >>> data = path.read_bytes()
    >>> data[:4], struct.unpack("<I", data[8:12])[0] == len(data)
    (b'glTF', True)
    """
    uv: np.ndarray | None = None
    image = b""
    if mesh.texture is not None:
        source, uv, faces = split_corners(mesh)
        image = _png(mesh.texture)
        mesh = Mesh(mesh.vertices[source], faces)
    colors = mesh.colors
    tris, _ = mesh.triangulate(quads="shorter")
    if len(mesh.vertices) >= 2 ** 32 - 1:
        raise MeshFileError(f"{tmp.name}: {len(mesh.vertices)} vertices; a glTF index counts at most 2^32 - 2")
    views: list[dict] = []
    accessors: list[dict] = []
    chunks: list[bytes] = []

    def view(data: bytes, target: int | None) -> int:
        offset = sum(len(c) for c in chunks)
        chunks.append(data + b"\0" * (-len(data) % 4))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
                     | ({"target": target} if target else {}))
        return len(views) - 1

    def accessor(values: np.ndarray, component: int, kind: str, target: int, **extra) -> int:
        accessors.append({"bufferView": view(values.tobytes(), target), "componentType": component,
                          "count": len(values), "type": kind, **extra})
        return len(accessors) - 1

    position = np.ascontiguousarray(mesh.vertices, np.float32)
    attributes = {"POSITION": accessor(position, _FLOAT, "VEC3", _VERTICES,
                                       min=position.min(axis=0).tolist(), max=position.max(axis=0).tolist())}
    indices = accessor(np.ascontiguousarray(tris, np.uint32).ravel(), _UINT, "SCALAR", _INDICES)
    primitive: dict = {"attributes": attributes, "indices": indices, "mode": 4}
    gltf: dict = {"asset": {"version": "2.0", "generator": "geoimg"}, "scene": 0, "scenes": [{"nodes": [0]}],
                  "nodes": [{"mesh": 0}], "meshes": [{"primitives": [primitive]}]}
    if uv is not None:
        st = np.column_stack([uv[:, 0], 1.0 - uv[:, 1]]).astype(np.float32)
        attributes["TEXCOORD_0"] = accessor(st, _FLOAT, "VEC2", _VERTICES)
        gltf.update(images=[{"bufferView": view(image, None), "mimeType": "image/png"}], textures=[{"source": 0}],
                    materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}])
        primitive["material"] = 0
    elif colors is not None:
        rgba = np.ones((len(colors), 4))
        rgba[:, :colors.shape[1]] = colors[:, :4]
        attributes["COLOR_0"] = accessor(np.round(np.clip(rgba, 0.0, 1.0) * 255).astype(np.uint8), _UBYTE, "VEC4",
                                         _VERTICES, normalized=True)
    binary = b"".join(chunks)
    gltf.update(buffers=[{"byteLength": len(binary)}], bufferViews=views, accessors=accessors)
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    with open(tmp, "wb") as fh:
        fh.write(struct.pack("<4sII", b"glTF", 2, total))
        fh.write(struct.pack("<I4s", len(text), b"JSON") + text)
        fh.write(struct.pack("<I4s", len(binary), b"BIN\0") + binary)


def _png(texture: np.ndarray) -> bytes:
    """The texture (H, W, 3 or 4) as PNG bytes."""
    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(texture)).save(out, format="PNG")
    return out.getvalue()
