"""Reading and writing polygon meshes without triangulating, merging or reordering.

OBJ, OFF (ASCII and binary) and PLY (ASCII and binary, ``face`` lists or ``tristrips``) are read and
written here, so quads and n-gons survive. STL and GLB are written here too (:mod:`._stl`, :mod:`._glb`) and
read through trimesh (``process=False``), as glTF is; they hold triangles only. Every format has
its exactly coincident positions joined on reading (reported; see :mod:`geoimg.mesh._weld`).
"""
from __future__ import annotations

import struct
import warnings
from pathlib import Path

from .._choices import MESH_FORMATS, MESH_READ_FORMATS
from .._atomic import write_all
from ..errors import InputTypeError, MeshError, MeshFileError
from ._appearance import TEXTURE_SUFFIX, write_texture
from ._mesh import Mesh
from ._weld import weld_vertices
from ._obj import read_obj, write_obj
from ._off import read_off, write_off
from ._ply import read_ply, write_ply
from ._glb import write_glb
from ._stl import write_stl
from ._trimesh_io import read_with_trimesh
from .._types import PathLike, as_path

__all__ = ["load_mesh", "save_mesh", "mesh_file_jobs", "MESH_FORMATS", "MESH_READ_FORMATS"]


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
    readers = {".obj": read_obj, ".off": read_off, ".ply": read_ply, ".stl": read_with_trimesh,
               ".glb": read_with_trimesh, ".gltf": read_with_trimesh}
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

    Raises
    ------
    InputTypeError
        When ``mesh`` is not a Mesh.
    MeshFileError
        When the extension is not a mesh format geoimg writes.

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
        ".obj": write_obj,
        ".off": write_off,
        ".ply": write_ply,
        ".stl": write_stl,
        ".glb": write_glb,
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
        return [(path, lambda tmp: write_obj(mesh, tmp, ext, material=stem)),
                (path.with_suffix(".mtl"), lambda tmp: tmp.write_text(
                    f"# written by geoimg\nnewmtl geoimg\nKd 1 1 1\nmap_Kd {stem}{TEXTURE_SUFFIX}\n")),
                (path.with_suffix(TEXTURE_SUFFIX), lambda tmp: write_texture(mesh.texture, tmp))]
    return [(path, lambda tmp: writers[ext](mesh, tmp, ext))]


