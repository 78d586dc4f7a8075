"""A mesh's appearance in files: OBJ vertex colours, MTL textures, PLY colours, and vertices split where a
position has several texture coordinates (what glTF and renderers need).

Texture coordinates follow OBJ: (0, 0) is the texture's bottom-left corner; textures are stored as image
files store them, row 0 at the top.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from .._raster import UINT8, read_raster, write_raster
from ..errors import GeoimgError

__all__ = [
    "obj_colors",
    "map_file_name",
    "read_mtl_texture",
    "read_texture",
    "texture_beside",
    "write_texture",
    "ply_colors",
    "split_corners",
    "TEXTURE_SUFFIX",
]

TEXTURE_SUFFIX = ".png"


def obj_colors(rows: list, path) -> np.ndarray | None:
    """Vertex colours from OBJ ``v x y z r g b [a]`` lines (a common extension), or None (``v x y z w`` is a
    weight, not a colour). Values above 1 are taken as 0..255. Lines that disagree (some with colours, some
    without) give none, with a warning.
    """
    widths = {len(r) for r in rows}
    if widths <= {3, 4}:                      # x y z, or x y z w (a rational weight, not a colour)
        return None
    if len(widths) != 1 or widths.pop() not in (6, 7):
        warnings.warn(f"{path}: some 'v' lines have colours and some do not (or not 3 or 4 of them); vertex "
                      "colours not read", stacklevel=5)
        return None
    c = np.array([r[3:] for r in rows], dtype=np.float64)
    if not np.isfinite(c).all() or c.min() < 0 or c.max() > 255:
        warnings.warn(f"{path}: vertex colours outside [0, 1] and [0, 255]; not read", stacklevel=5)
        return None
    return c / 255.0 if c.max() > 1.0 else c


def ply_colors(vx: dict) -> np.ndarray | None:
    """Vertex colours of a PLY vertex element (``red green blue [alpha]``, integers 0..255 or floats in
    [0, 1]), or None.
    """
    for prefix in ("", "diffuse_"):
        keys = [prefix + k for k in ("red", "green", "blue", "alpha")]
        if all(k in vx for k in keys[:3]):
            c = np.stack([np.asarray(vx[k], np.float64) for k in keys if k in vx], axis=1)
            return c / 255.0 if c.max(initial=0.0) > 1.0 else c
    return None


def read_texture(path) -> np.ndarray:
    """An image file as an 8-bit (h, w, 3) or (h, w, 4) texture (grey becomes RGB)."""
    data, _, _ = read_raster(path, what="texture")
    if data.ndim == 2:
        data = data[..., None]
    if data.shape[2] in (1, 2):
        data = np.concatenate([np.repeat(data[..., :1], 3, axis=2), data[..., 1:2]], axis=2)
    return np.round(np.clip(data[..., :4], 0, 1) * 255).astype(np.uint8)


def write_texture(texture: np.ndarray, path: Path) -> None:
    """An 8-bit texture written as an image file (the format from the name)."""
    names = ["R", "G", "B", "A"][: texture.shape[2]]
    write_raster(path, texture, names, UINT8)


_MAP_OPTIONS = {"-blendu": 1, "-blendv": 1, "-bm": 1, "-boost": 1, "-cc": 1, "-clamp": 1, "-imfchan": 1,
                "-mm": 2, "-texres": 1, "-type": 1, "-o": 3, "-s": 3, "-t": 3}


def map_file_name(tokens: list) -> str:
    """The file name of an MTL ``map_*`` statement's arguments: its options (``-s 1 1``, ``-clamp on``) left
    out, the rest joined by spaces (file names may hold them).

    Examples
    --------
    >>> map_file_name(["-s", "2", "2", "-clamp", "on", "fuze", "uv.jpg"])
    'fuze uv.jpg'
    >>> map_file_name(["-o", "0.5", "tex.png"])
    'tex.png'
    """
    i = 0
    while i < len(tokens) - 1 and tokens[i].lower() in _MAP_OPTIONS:
        most = _MAP_OPTIONS[tokens[i].lower()]
        i += 1
        if most == 3:                         # -o -s -t: one to three numbers
            taken = 0
            while taken < 3 and i < len(tokens) - 1 and _is_number(tokens[i]):
                i, taken = i + 1, taken + 1
        else:
            i += most
    return " ".join(tokens[i:])


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _is_file(path: Path) -> bool:
    """Whether ``path`` is a file; False for a name the system cannot even look up (too long, a NUL byte)."""
    try:
        return path.is_file()
    except (OSError, ValueError):
        return False


def read_mtl_texture(obj_path: Path, libraries: list, used: list) -> np.ndarray | None:
    """The one diffuse texture (``map_Kd``) that the OBJ's used materials name, or None (with a warning
    when they name several, or when the library or image cannot be read).
    """
    maps = {}
    for lib in libraries:
        mtl = obj_path.parent / lib
        try:
            text = mtl.read_text(encoding="utf-8-sig", errors="replace") if _is_file(mtl) else None
        except OSError:                     # a folder of that name, no permission ...
            text = None
        if text is None:
            warnings.warn(f"{obj_path}: material library {lib} not found; textures not read", stacklevel=5)
            return None
        current = None
        for line in text.splitlines():
            parts = line.split()
            if len(parts) >= 2 and parts[0] == "newmtl":
                current = " ".join(parts[1:])
            elif len(parts) >= 2 and parts[0] == "map_Kd" and current is not None:
                maps[current] = mtl.parent / map_file_name(parts[1:])
    files = sorted({maps[m] for m in used if m in maps})
    if not files:
        return None
    if len(files) > 1:
        warnings.warn(f"{obj_path}: its materials use {len(files)} textures; geoimg carries one texture per mesh, "
                      "so none was read", stacklevel=5)
        return None
    return texture_beside(obj_path, files[0])


def texture_beside(mesh_path: Path, file: Path) -> np.ndarray | None:
    """The texture ``file`` that the mesh file ``mesh_path`` names, or None with a warning when it is not
    there or cannot be read (the mesh is read without it).
    """
    if not _is_file(file):
        warnings.warn(f"{mesh_path}: texture {file.name} not found; not read", stacklevel=6)
        return None
    try:
        return read_texture(file)
    except (GeoimgError, OSError) as e:
        warnings.warn(f"{mesh_path}: texture {file.name} cannot be read ({e}); not read", stacklevel=6)
        return None


def split_corners(mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices split where a position has several texture coordinates: ``(source, uv, faces)``, new vertex
    ``i`` being ``mesh`` vertex ``source[i]`` with texture coordinates ``uv[i]``, and the faces on the new
    vertices. Without ``face_uv``, the vertices as they are (``uv`` from ``mesh.uv``, or zeros).

    Examples
    --------
    >>> from geoimg.mesh import Mesh
    >>> m = Mesh(np.eye(4, 3), [[0, 1, 2], [0, 2, 3]], face_uv=[[[0, 0], [1, 0], [1, 1]], [[0.5, 0], [1, 1], [0, 1]]])
    >>> source, uv, faces = split_corners(m)
    >>> source.tolist(), faces.tolist()
    ([0, 0, 1, 2, 3], [[0, 2, 3], [1, 3, 4]])
    """
    if mesh.face_uv is None:
        uv = mesh.uv if mesh.uv is not None else np.zeros((mesh.n_vertices, 2))
        return np.arange(mesh.n_vertices), uv, mesh.faces
    valid = mesh.faces >= 0
    keys = np.concatenate([mesh.faces[valid][:, None].astype(np.float64), mesh.face_uv[valid]], axis=1)
    uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
    faces = np.full(mesh.faces.shape, -1, np.int64)
    faces[valid] = inverse.ravel()
    return uniq[:, 0].astype(np.int64), uniq[:, 1:], faces
