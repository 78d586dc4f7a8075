"""STL, GLB and glTF read through trimesh (as stored: ``process=False``), imported only for them (geoimg writes
STL and GLB itself: :mod:`._stl`, :mod:`._glb`).
"""
from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

import numpy as np

from .._quiet import library_logs
from ..errors import MeshFileError
from ._mesh import Mesh

__all__ = ["check_stl", "check_gltf", "read_with_trimesh"]


def check_stl(path: Path) -> None:
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


def check_gltf(path: Path) -> None:
    """Refuse a ``.gltf`` that is not a JSON object with an ``asset`` before trimesh guesses (it then looks for
    files the glTF never named).
    """
    try:
        doc = json.loads(path.read_text(encoding="utf-8-sig"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise MeshFileError(f"not a valid glTF: its JSON cannot be read ({e})") from None
    if not isinstance(doc, dict) or "asset" not in doc:
        raise MeshFileError("not a valid glTF: a JSON object with an 'asset' is expected")


def read_with_trimesh(path: Path) -> Mesh:
    if path.suffix.lower() == ".stl":
        check_stl(path)
    if path.suffix.lower() == ".gltf":
        check_gltf(path)
    import trimesh          # STL and GLB alone: its import costs half a second that OBJ, OFF and PLY never need
    try:
        with library_logs("trimesh", about=f"reading {path.name}"):      # its logged tracebacks look like crashes
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
