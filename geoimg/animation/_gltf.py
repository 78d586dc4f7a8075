"""Morph animation files: glTF 2.0 binary with morph targets (pygltflib), and per-frame mesh or EXR sequences.

The GLB holds one mesh: key 0's quad mesh, split into triangles, as the base, a morph target per further
key (position and normal displacements, named in the mesh's ``extras.targetNames``) and an animation of
the target weights sampled at every frame (linear between frames), so any glTF viewer plays the eased
morph. A morph with a timing mask cannot be written as weights of whole keys; it gets one target per frame
and a step animation instead. Vertices have texture coordinates (``TEXCOORD_0``: the pixel's place in the
image); keys with colours give vertex colours (``COLOR_0``, morphing too when every key has them, and the
vertices split where an octahedral image's glued sides meet, as its texture coordinates differ there). The
material is a plain rough white that the vertex colours tint.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .._choices import FRAME_FORMATS
from ..errors import InputError
from .._atomic import atomic_path, write_all
from .._optional import require
from ..image import GeometryImage
from ..mesh import Mesh, save_mesh
from ..mesh._appearance import split_corners
from ._morph import Morph
from .._types import PathLike, Progress

__all__ = ["save_glb", "save_frames", "frame_jobs", "FRAME_FORMATS"]



def _triangles(mesh) -> np.ndarray:
    tris, _ = mesh.triangulate(quads="shorter")
    return np.ascontiguousarray(tris, np.uint32)


def _vertex_normals(image, valid, colors=None) -> tuple[np.ndarray, Mesh]:
    """The quad mesh of an image over the pixels valid in every key, with normals from the grid (the
    same rule for every key, so normal displacements are consistent).
    """
    mask = None if valid is None else valid
    mesh = GeometryImage(image.pixels, mask, domain=image.domain, metadata=image.metadata, colors=colors).to_mesh()
    normals = mesh.normals if mesh.normals is not None else mesh.vertex_normals()
    return np.asarray(normals, np.float32), mesh


def _texcoords(mesh, domain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(source, texcoords, faces)``: the base mesh's vertices split where corners' texture coordinates
    differ, glTF's texture coordinates ((0, 0) the image's top-left) and the faces on the split vertices.
    """
    source, uv, faces = split_corners(mesh)
    if mesh.face_uv is not None:
        return source, np.column_stack([uv[:, 0], 1.0 - uv[:, 1]]), faces      # OBJ's are from the bottom
    return source, uv / np.asarray(domain.extent, np.float64), faces


def _target_names(morph: Morph, target_images) -> list:
    if morph.weights is not None:
        return [f"frame {i}" for i in range(len(target_images))]
    return [str(img.metadata.get("source") or f"key {k}") for k, img in enumerate(target_images, start=1)]


class _Buffer:
    """Accessors appended to one binary buffer."""

    def __init__(self, gl, gltf):
        self.gl, self.gltf, self.blob = gl, gltf, bytearray()

    def add(self, array: np.ndarray, kind: str, component: int, target=None, minmax=False) -> int:
        gl, data = self.gl, np.ascontiguousarray(array).tobytes()
        while len(self.blob) % 4:
            self.blob.append(0)
        view = gl.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target)
        self.blob.extend(data)
        self.gltf.bufferViews.append(view)
        acc = gl.Accessor(bufferView=len(self.gltf.bufferViews) - 1, componentType=component,
                          count=int(array.shape[0]), type=kind)
        if minmax:
            flat = array.reshape(array.shape[0], -1)
            acc.min, acc.max = flat.min(axis=0).tolist(), flat.max(axis=0).tolist()
        self.gltf.accessors.append(acc)
        return len(self.gltf.accessors) - 1


def _weights(morph: Morph) -> tuple[np.ndarray, list]:
    """Target weights (frames, targets) and the images whose displacements are the targets."""
    if morph.weights is None:
        w = np.zeros((len(morph), len(morph.keys) - 1), np.float32)
        for i, t in enumerate(morph.times):
            k, u = morph.segment(float(t))
            e = morph.local_time(u)
            if k > 0:
                w[i, k - 1] = 1.0 - e
            w[i, k] = e
        return w, morph.keys[1:]
    frames = list(morph.frames())
    return np.eye(len(frames), dtype=np.float32), frames


def save_glb(morph: Morph, path: PathLike, *, fps: float = 24.0, overwrite: bool = False,
             progress: Progress | None = None) -> Path:
    """Write the morph as a binary glTF 2.0 file with morph targets and a weights animation.

    Parameters
    ----------
    morph : Morph
        The morph to write.
    path : path-like
        The ``.glb`` file.
    fps : float
        Frames per second of the weights animation.
    overwrite : bool
        Replace the file if it exists.
    progress : callable or None
        Called as ``progress(done, total)`` after each frame.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        When the name is not a ``.glb`` or ``fps`` is not a positive finite number.
    MissingDependency
        Without pygltflib (``pip install geoimg[render]``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from geoimg import GeometryImage
    >>> from geoimg.animation import morph
    >>> import pygltflib as gl
    >>> a = GeometryImage(np.zeros((3, 3, 3), np.float32))
    >>> m = morph(a, GeometryImage(np.ones((3, 3, 3), np.float32)), frames=4, align="none")
    >>> p = save_glb(m, pathlib.Path(tempfile.mkdtemp()) / "m.glb")
    >>> g = gl.GLTF2().load(str(p))
    >>> len(g.meshes[0].primitives[0].targets), g.accessors[g.animations[0].samplers[0].input].count
    (1, 4)
    """
    path = Path(path)
    if path.suffix.lower() != ".glb":
        raise InputError(f"{path}: expected a .glb name")
    if not (isinstance(fps, (int, float, np.number)) and np.isfinite(fps) and fps > 0):
        raise InputError(f"fps: expected a positive finite number, got {fps!r}")
    gl = require("pygltflib", "writing a glTF morph")
    weights, target_images = _weights(morph)
    valid = None
    if any(k.mask is not None for k in morph.keys):
        valid = np.logical_and.reduce([k.valid for k in morph.keys])
    coloured = all(img.colors is not None for img in [morph.keys[0], *target_images])
    base_colors = None if morph.keys[0].colors is None else morph.keys[0].colors[..., :3]
    base_normals, base = _vertex_normals(morph.keys[0], valid, base_colors)
    source, texcoords, faces = _texcoords(base, morph.keys[0].domain)
    base_pos = np.asarray(base.vertices, np.float32)
    gltf = gl.GLTF2(
        asset=gl.Asset(generator="geoimg"),
        scene=0,
        scenes=[gl.Scene(nodes=[0])],
        materials=[
            gl.Material(
                name="geoimg",
                doubleSided=True,
                pbrMetallicRoughness=gl.PbrMetallicRoughness(
                    baseColorFactor=[1.0, 1.0, 1.0, 1.0], metallicFactor=0.0, roughnessFactor=0.8
                ),
            )
        ],
    )
    buf = _Buffer(gl, gltf)
    attributes = gl.Attributes(POSITION=buf.add(base_pos[source], gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER, minmax=True),
                               NORMAL=buf.add(base_normals[source], gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER),
                               TEXCOORD_0=buf.add(texcoords.astype(np.float32), gl.VEC2, gl.FLOAT, gl.ARRAY_BUFFER))
    if base.colors is not None:
        attributes.COLOR_0 = buf.add(base.colors[source].astype(np.float32), gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER)
    idx = buf.add(_triangles(base.derived(faces, vertex_source=source)).reshape(-1), gl.SCALAR, gl.UNSIGNED_INT,
                  gl.ELEMENT_ARRAY_BUFFER)
    targets = []
    for j, img in enumerate(target_images):
        n, m = _vertex_normals(img, valid, img.colors[..., :3] if coloured else None)
        dp = (np.asarray(m.vertices, np.float32) - base_pos)[source]
        target = gl.Attributes(POSITION=buf.add(dp, gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER, minmax=True),
                               NORMAL=buf.add((n - base_normals)[source], gl.VEC3, gl.FLOAT, gl.ARRAY_BUFFER))
        if coloured and m.colors is not None and base.colors is not None:
            target.COLOR_0 = buf.add((m.colors - base.colors)[source].astype(np.float32), gl.VEC3, gl.FLOAT,
                                     gl.ARRAY_BUFFER)
        targets.append(target)
        if progress:
            progress(f"glTF target {j + 1} of {len(target_images)}")
    prim = gl.Primitive(attributes=attributes, indices=idx, targets=targets, material=0)
    gltf.meshes.append(gl.Mesh(primitives=[prim], weights=[0.0] * len(targets), name="geoimg morph",
                               extras={"targetNames": _target_names(morph, target_images)}))
    gltf.nodes.append(gl.Node(mesh=0, name="morph"))
    times = (np.arange(len(morph), dtype=np.float32) / np.float32(fps))
    t_acc = buf.add(times, gl.SCALAR, gl.FLOAT, minmax=True)
    w_acc = buf.add(weights.reshape(-1), gl.SCALAR, gl.FLOAT)
    interp = gl.ANIM_LINEAR if morph.weights is None else gl.ANIM_STEP
    gltf.animations.append(gl.Animation(name="morph", samplers=[gl.AnimationSampler(input=t_acc, output=w_acc,
                                                                                     interpolation=interp)],
                                        channels=[gl.AnimationChannel(sampler=0, target=gl.AnimationChannelTarget(
                                            node=0, path="weights"))]))
    gltf.buffers.append(gl.Buffer(byteLength=len(buf.blob)))
    gltf.set_binary_blob(bytes(buf.blob))
    with atomic_path(path, overwrite) as tmp:
        gltf.save_binary(str(tmp))
    return path


def frame_jobs(morph: Morph, folder: PathLike, fmt: str = "obj", progress: Progress | None = None) -> list:
    """``(path, write)`` for every frame file ``folder/frame_0000.<fmt>`` (see :func:`save_frames`), for
    :func:`geoimg._atomic.write_all`; each frame is made when it is written.

    Parameters
    ----------
    morph : Morph
        The morph whose frames are written.
    folder : path-like
        The folder the frames go to.
    fmt : {"obj", "ply", "off", "exr"}
        The frames' file format.
    progress : callable or None
        Called as ``progress(done, total)`` after each frame.

    Returns
    -------
    list of tuple
        ``(path, write)`` pairs; ``write(tmp_path)`` writes one frame.

    Raises
    ------
    InputError
        When ``fmt`` is not a frame format.

    Examples
    --------
    >>> import numpy as np
    >>> from geoimg import GeometryImage
    >>> from geoimg.animation import morph
    >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
    ...           frames=3, align="none")
    >>> [p.name for p, _ in frame_jobs(m, "frames", "ply")]
    ['frame_0000.ply', 'frame_0001.ply', 'frame_0002.ply']
    """
    if fmt not in FRAME_FORMATS:
        raise InputError(f"fmt: expected one of {FRAME_FORMATS}, got {fmt!r}")
    folder = Path(folder)

    def writer(i: int):
        def write(tmp):
            frame = morph.frame(float(morph.times[i]))
            if fmt == "exr":
                frame.save(tmp, overwrite=True)
            else:
                quads = frame.to_mesh()                     # one file a frame: vertex colours, no texture
                save_mesh(Mesh(quads.vertices, quads.faces, uv=quads.uv, normals=quads.normals, colors=quads.colors),
                          tmp, overwrite=True)
            if progress:
                progress(i + 1, len(morph))
        return write

    return [(folder / f"frame_{i:04d}.{fmt}", writer(i)) for i in range(len(morph))]


def save_frames(morph: Morph, folder: PathLike, fmt: str = "obj", *, overwrite: bool = False,
                progress: Progress | None = None) -> list[Path]:
    """Write every frame to ``folder/frame_0000.<fmt>``: a quad mesh (obj, ply, off) or the geometry
    image (exr); all of them or, on any failure, none. Returns the paths.

    Parameters
    ----------
    morph : Morph
        The morph whose frames are written.
    folder : path-like
        The folder the frames go to (made if missing).
    fmt : {"obj", "ply", "off", "exr"}
        The frames' file format.
    overwrite : bool
        Replace frame files that exist (else refused before anything is written).
    progress : callable or None
        Called as ``progress(done, total)`` after each frame.

    Returns
    -------
    list of pathlib.Path
        The frame files, in order.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from geoimg import GeometryImage
    >>> from geoimg.animation import morph
    >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
    ...           frames=2, align="none")
    >>> [p.name for p in save_frames(m, tempfile.mkdtemp(), "obj")]
    ['frame_0000.obj', 'frame_0001.obj']
    """
    jobs = frame_jobs(morph, folder, fmt, progress)
    Path(folder).mkdir(parents=True, exist_ok=True)
    return write_all(jobs, overwrite=overwrite)
