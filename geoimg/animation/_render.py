"""Headless pictures: meshes and geometry images shaded to PNG with a fixed camera, morphs to GIF or MP4.

OpenGL through moderngl on an EGL context (Mesa's llvmpipe on the CPU; no display needed). Triangles are
shaded with two directional lights on both sides (a mesh's orientation does not matter) and 4x
multisampling. A morph keeps one camera for all its frames, fitted to the union of its keys' bounds.
"""
from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import ArrayLike
from PIL import Image

from .._choices import UP_AXES
from .._atomic import atomic_path
from .._optional import require
from ..errors import InputError, InputTypeError, RenderError
from ..image import GeometryImage
from ..mesh import Mesh
from ..mesh._appearance import split_corners
from .._types import PathLike

__all__ = ["Renderer", "Camera", "render", "save_png", "save_animation", "RenderError", "UP_AXES", "up_axis",
           "label_points"]

MARGIN = 0.04             # a fitted camera leaves this fraction of the picture free on the tightest side

_VERTEX = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
in vec3 in_nrm;
in vec3 in_col;
in vec2 in_uv;
out vec3 v_nrm;
out vec3 v_col;
out vec2 v_uv;
void main() {
    v_nrm = in_nrm;
    v_col = in_col;
    v_uv = in_uv;
    gl_Position = mvp * vec4(in_pos, 1.0);
}
"""
_FRAGMENT = """
#version 330
uniform vec3 key_dir;
uniform vec3 fill_dir;
uniform bool textured;
uniform sampler2D tex;
in vec3 v_nrm;
in vec3 v_col;
in vec2 v_uv;
out vec4 color;
void main() {
    vec3 n = normalize(v_nrm);
    float light = 0.22 + 0.62 * abs(dot(n, key_dir)) + 0.22 * abs(dot(n, fill_dir));
    vec3 albedo = textured ? texture(tex, v_uv).rgb : v_col;
    color = vec4(min(albedo * light, vec3(1.0)), 1.0);
}
"""


_LINE_VERTEX = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    gl_Position.z -= 2e-4 * gl_Position.w;    // drawn just in front of the surface it lies on
}
"""
_LINE_FRAGMENT = """
#version 330
uniform vec3 line_color;
out vec4 color;
void main() { color = vec4(line_color, 1.0); }
"""


@dataclass(frozen=True)
class Camera:
    """A perspective camera looking at ``target`` from ``eye``; light directions follow it.

    Parameters
    ----------
    eye, target, up : numpy.ndarray
        (3,) the camera's position, the point it looks at, and its up direction.
    fov_deg : float
        The vertical field of view, degrees.
    near, far : float
        The clipping planes' distances.

    Examples
    --------
    >>> cam = Camera(eye=np.array([0.0, 0.0, 5.0]), target=np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
    >>> cam.fov_deg, float(np.linalg.norm(cam.eye - cam.target))
    (30.0, 5.0)
    """

    eye: np.ndarray
    target: np.ndarray
    up: np.ndarray
    fov_deg: float = 30.0
    near: float = 0.01
    far: float = 100.0

    @classmethod
    def fit(cls, lo, hi, *, azimuth: float = 30.0, elevation: float = 20.0, up: str = "y", aspect: float = 4 / 3,
            points: np.ndarray | None = None):
        """Frame the box ``lo..hi`` from ``azimuth``, ``elevation`` (degrees) about the ``up`` axis: the
        camera looks at the box's centre from as near as lets every one of ``points`` (default: the box's
        corners) show, with a margin of :data:`MARGIN`.

        Parameters
        ----------
        lo, hi : array_like
            (3,) the box's corners.
        azimuth, elevation : float
            The view direction, degrees around and above the shape.
        up : {"x", "y", "z"}
            The up axis.
        aspect : float
            The picture's width over its height.
        points : numpy.ndarray or None
            (k, 3) the shape's points, for a tighter fit than the box's.

        Returns
        -------
        Camera
            The camera.

        Examples
        --------
        >>> cam = Camera.fit([-1, -1, -1], [1, 1, 1], aspect=1.0)
        >>> cam.fov_deg
        30.0
        """
        if up not in UP_AXES:
            raise InputError(f"up: expected one of {UP_AXES}, got {up!r}")
        for name, value in (("azimuth", azimuth), ("elevation", elevation)):
            if not (isinstance(value, (int, float, np.number)) and np.isfinite(value)):
                raise InputError(f"{name}: expected a finite number of degrees, got {value!r}")
        lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
        centre = 0.5 * (lo + hi)
        radius = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-9)
        u = UP_AXES.index(up)
        a, b = (u + 1) % 3, (u + 2) % 3            # a right-handed frame (a, b, up)
        az, el = math.radians(azimuth), math.radians(elevation)
        d = np.zeros(3)
        d[b] = math.cos(el) * math.cos(az)
        d[a] = math.cos(el) * math.sin(az)
        d[u] = math.sin(el)
        fov = 30.0
        upv = np.zeros(3)
        upv[u] = 1.0
        if points is None:
            points = np.array(np.meshgrid(*zip(lo, hi), indexing="ij")).reshape(3, -1).T
        points = np.asarray(points, np.float64)
        t = math.tan(math.radians(fov) / 2)
        for _ in range(3):           # centre the picture on what it shows (a view from above puts it low)
            dist, shift = _fitting_distance(points - centre, d, upv, t, aspect)
            centre = centre + shift
        dist = max(_fitting_distance(points - centre, d, upv, t, aspect)[0], radius * 1e-3)
        return cls(centre + d * dist, centre, upv, fov, max(dist - radius, dist * 0.01) * 0.5, dist + 2.0 * radius)

    def matrices(self, aspect: float) -> np.ndarray:
        """The view-projection matrix (4 x 4, row-major) for an image of this aspect (width / height).

        Parameters
        ----------
        aspect : float
            The picture's width over its height.

        Returns
        -------
        numpy.ndarray
            (4, 4) float32.

        Examples
        --------
        >>> Camera.fit([-1, -1, -1], [1, 1, 1], aspect=1.0).matrices(1.0).shape
        (4, 4)
        """
        f = self.target - self.eye
        f /= np.linalg.norm(f)
        side, upv = _view_frame(f, self.up)
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = side, upv, -f
        view[:3, 3] = -view[:3, :3] @ self.eye
        t = 1.0 / math.tan(math.radians(self.fov_deg) / 2)
        proj = np.zeros((4, 4))
        proj[0, 0], proj[1, 1] = t / aspect, t
        proj[2, 2] = (self.far + self.near) / (self.near - self.far)
        proj[2, 3] = 2 * self.far * self.near / (self.near - self.far)
        proj[3, 2] = -1.0
        return proj @ view

    def lights(self) -> tuple[np.ndarray, np.ndarray]:
        """Key light from the upper left of the viewer, fill from the right (unit vectors).

        Returns
        -------
        key, fill : numpy.ndarray
            (3,) unit directions.

        Examples
        --------
        >>> cam = Camera.fit([-1, -1, -1], [1, 1, 1], aspect=1.0)
        >>> [round(float(np.linalg.norm(d)), 6) for d in cam.lights()]
        [1.0, 1.0]
        """
        f = self.target - self.eye
        f /= np.linalg.norm(f)
        side, upv = _view_frame(f, self.up)
        key = -f + 0.6 * upv - 0.5 * side
        fill = -f + 0.8 * side - 0.2 * upv
        return key / np.linalg.norm(key), fill / np.linalg.norm(fill)


def _view_frame(forward: np.ndarray, up: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit right and up directions of a view along the unit ``forward`` with ``up`` above."""
    side = np.cross(forward, up)
    if np.linalg.norm(side) < 1e-9:              # looking straight along up
        side = np.cross(forward, np.roll(up, 1))
    side /= np.linalg.norm(side)
    return side, np.cross(side, forward)


def _fitting_distance(p: np.ndarray, d: np.ndarray, up: np.ndarray, t: float, aspect: float):
    """The least distance along the unit view direction ``d`` (from the target towards the eye) at which a
    camera of half-angle tangent ``t`` sees all of ``p`` (relative to the target) inside the margin, and
    the move of the target that would centre the points' picture.
    """
    side, upv = _view_frame(-d, up)
    toward, x, y = p @ d, p @ side, p @ upv
    reach = (1.0 - 2.0 * MARGIN) * t
    dist = float(np.max(toward + np.maximum(np.abs(x) / (reach * aspect), np.abs(y) / reach)))
    depth = np.maximum(dist - toward, 1e-12)
    sx, sy = x / depth, y / depth                      # where each point lands, in tangent units
    shift = dist * (0.5 * (sx.max() + sx.min()) * side + 0.5 * (sy.max() + sy.min()) * upv)
    return dist, shift


def up_axis(obj: Any) -> str:
    """The up axis a picture of ``obj`` uses by default: the one a geometry image records (``metadata["up"]``,
    a terrain's), else ``"y"``.

    Parameters
    ----------
    obj : Mesh or GeometryImage
        The shape to be drawn.

    Returns
    -------
    str
        ``"x"``, ``"y"`` or ``"z"``.

    Examples
    --------
    >>> up_axis(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))
    'y'
    """
    up = obj.metadata.get("up") if isinstance(obj, GeometryImage) else None
    return up if up in UP_AXES else "y"


def _geometry(obj):
    """Vertices, triangles, per-vertex normals, colours (or None), texture coordinates (OpenGL's, from the
    texture's first row) and texture (or None) of a mesh or a geometry image (its quad mesh); a textured
    mesh's vertices are split where its corners' texture coordinates differ.
    """
    mesh = obj.to_mesh() if isinstance(obj, GeometryImage) else obj
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"expected a geoimg.Mesh or GeometryImage, got {type(obj).__name__}")
    n = np.asarray(mesh.normals if mesh.normals is not None else mesh.vertex_normals(), np.float64)
    c = None if mesh.colors is None else np.asarray(mesh.colors[:, :3], np.float64)
    if mesh.texture is None:
        tris, _ = mesh.triangulate(quads="shorter")
        return (np.asarray(mesh.vertices, np.float64), np.ascontiguousarray(tris, np.uint32), n, c,
                np.zeros((mesh.n_vertices, 2)), None)
    source, uv, faces = split_corners(mesh)
    tris, _ = mesh.derived(faces, vertex_source=source).triangulate(quads="shorter")
    return (np.asarray(mesh.vertices[source], np.float64), np.ascontiguousarray(tris, np.uint32), n[source], None,
            np.column_stack([uv[:, 0], 1.0 - uv[:, 1]]), mesh.texture)


class Renderer:
    """An offscreen OpenGL renderer of fixed size; reuse it for many frames (a context manager: its
    OpenGL context is released on leaving the ``with`` block). Shapes with colours are drawn in them,
    others in ``albedo``; ``background=None`` makes the background transparent (RGBA pictures).

    Raises
    ------
    RenderError
        When no EGL/OpenGL 3.3 context can be made (the message says what to install).

    Parameters
    ----------
    width, height : int
        The pictures' size, pixels.
    samples : int
        Multisampling (antialiasing) samples per pixel.
    background : tuple of float or None
        RGB in [0, 1]; None for a transparent background.
    albedo : tuple of float
        RGB in [0, 1] of shapes without colours.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> with Renderer(64, 48) as r:
    ...     picture = r.render(m, r.camera_for(m))
    >>> picture.shape, picture.dtype
    ((48, 64, 3), dtype('uint8'))
    """

    def __init__(self, width: int = 800, height: int = 600, *, samples: int = 4,
                 background: tuple[float, float, float] | None = (1.0, 1.0, 1.0),
                 albedo: tuple[float, float, float] = (0.78, 0.74, 0.68)):
        for name, value in (("width", width), ("height", height)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 8 <= value <= 8192:
                raise InputError(f"{name}: expected an integer from 8 to 8192, got {value!r}")
        moderngl = require("moderngl", "rendering")
        try:
            self.ctx = moderngl.create_standalone_context(backend="egl")
        except Exception as e:   # noqa: BLE001 - any failure to get a context means the same to the user
            raise RenderError("no headless OpenGL context: geoimg renders through EGL with Mesa "
                              "(Debian/Ubuntu: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri); "
                              f"the error was: {e}") from None
        self.size, self.albedo = (int(width), int(height)), tuple(albedo)
        self.background = None if background is None else tuple(background)
        self.prog = self.ctx.program(vertex_shader=_VERTEX, fragment_shader=_FRAGMENT)
        self.lines = self.ctx.program(vertex_shader=_LINE_VERTEX, fragment_shader=_LINE_FRAGMENT)
        self.samples = samples if samples <= self.ctx.max_samples else 0
        self.fbo = self.ctx.framebuffer(color_attachments=[self.ctx.renderbuffer(self.size, samples=self.samples)],
                                        depth_attachment=self.ctx.depth_renderbuffer(self.size, samples=self.samples))
        self.resolved = self.ctx.framebuffer(color_attachments=[self.ctx.renderbuffer(self.size)])

    def camera_for(self, *objects: Any, azimuth: float = 30.0, elevation: float = 20.0,
                   up: str | None = None) -> Camera:
        """A camera framing all the objects (meshes or geometry images) together, tightly; ``up`` defaults
        to the first object's (:func:`up_axis`).

        Parameters
        ----------
        *objects : Mesh or GeometryImage
            The shapes to frame together.
        azimuth, elevation : float
            The view direction, degrees.
        up : {"x", "y", "z"} or None
            The up axis; None for :func:`up_axis` of the first object.

        Returns
        -------
        Camera
            The camera.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> with Renderer(32, 24) as r:
        ...     cam = r.camera_for(m, elevation=35)
        >>> type(cam).__name__
        'Camera'
        """
        return self._camera([_geometry(o)[0] for o in objects], azimuth, elevation,
                            up_axis(objects[0]) if up is None else up)

    def _camera(self, pts: list, azimuth: float, elevation: float, up: str) -> Camera:
        """A camera framing the point sets ``pts`` together, tightly (a subsample of each, and their box)."""
        lo = np.min([p.min(axis=0) for p in pts], axis=0)
        hi = np.max([p.max(axis=0) for p in pts], axis=0)
        hull = np.vstack([p[:: max(1, len(p) // 20000)] for p in pts] + [lo[None], hi[None]])
        return Camera.fit(lo, hi, azimuth=azimuth, elevation=elevation, up=up, aspect=self.size[0] / self.size[1],
                          points=hull)

    def render(self, obj: Any, camera: Camera | None = None, *, edges: Mesh | None = None,
               edge_color: tuple[float, float, float] = (0.75, 0.1, 0.1)) -> np.ndarray:
        """An (H, W, 3) uint8 picture of the object, (H, W, 4) with a transparent background; ``edges``: a
        mesh whose polygon edges are drawn over it (hidden where the surface is in front).

        Parameters
        ----------
        obj : Mesh or GeometryImage
            What to draw.
        camera : Camera or None
            The camera; None for :meth:`camera_for` of the object.
        edges : Mesh or None
            A mesh whose edges are drawn over it (a wireframe).
        edge_color : tuple of float
            The edges' RGB in [0, 1].

        Returns
        -------
        numpy.ndarray
            (H, W, 3) or (H, W, 4) uint8.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> with Renderer(32, 24, background=None) as r:
        ...     rgba = r.render(m)
        >>> rgba.shape
        (24, 32, 4)
        """
        v, tris, n, c, uv, texture = _geometry(obj)
        self.ctx.__enter__()        # this context made current: another renderer's release unbinds it
        if camera is None:                              # the default view of camera_for, from what is drawn
            camera = self._camera([v], 30.0, 20.0, up_axis(obj))
        if c is None:
            c = np.broadcast_to(np.asarray(self.albedo, np.float64), v.shape)
        mvp = camera.matrices(self.size[0] / self.size[1]).T.astype("f4").tobytes()
        with self._vertex_array(self.prog, np.hstack([v, n, c, uv]).astype("f4"), "3f 3f 3f 2f",
                                ("in_pos", "in_nrm", "in_col", "in_uv"), tris) as vao, self._texture(texture):
            self.prog["textured"].value = texture is not None
            self.prog["mvp"].write(mvp)
            key, fill = camera.lights()
            self.prog["key_dir"].value = tuple(key)
            self.prog["fill_dir"].value = tuple(fill)
            self.fbo.use()
            self.ctx.enable(self.ctx.DEPTH_TEST)
            self.fbo.clear(*(self.background or (0.0, 0.0, 0.0)), 1.0 if self.background else 0.0)
            vao.render()
        if edges is not None:
            self._draw_edges(edges, mvp, edge_color)
        self.ctx.copy_framebuffer(self.resolved, self.fbo)
        k = 3 if self.background else 4
        raw = self.resolved.read(components=k, alignment=1)
        img = np.frombuffer(raw, np.uint8).reshape(self.size[1], self.size[0], k)
        return img[::-1].copy()                          # OpenGL's rows run bottom up

    @contextlib.contextmanager
    def _texture(self, texture):
        """The texture bound to unit 0 for one draw (nothing without one), released afterwards."""
        if texture is None:
            yield
            return
        rgb = np.ascontiguousarray(texture[..., :3], np.uint8)
        tex = self.ctx.texture((rgb.shape[1], rgb.shape[0]), 3, rgb.tobytes(), alignment=1)
        tex.repeat_x = tex.repeat_y = True
        tex.build_mipmaps()
        tex.filter = (self.ctx.LINEAR_MIPMAP_LINEAR, self.ctx.LINEAR)
        tex.use(0)
        self.prog["tex"].value = 0
        try:
            yield
        finally:
            tex.release()

    @contextlib.contextmanager
    def _vertex_array(self, program, data: np.ndarray, layout: str, names, indices: np.ndarray):
        """Buffers for one draw, released afterwards."""
        vbo = self.ctx.buffer(np.ascontiguousarray(data).tobytes())
        ibo = self.ctx.buffer(np.ascontiguousarray(indices, np.uint32).tobytes())
        vao = self.ctx.vertex_array(program, [(vbo, layout, *names)], ibo)
        try:
            yield vao
        finally:
            vao.release()
            vbo.release()
            ibo.release()

    def _draw_edges(self, mesh: Mesh, mvp: bytes, color) -> None:
        f, k = mesh.faces, mesh.face_sizes
        nxt = np.where(np.arange(f.shape[1])[None, :] + 1 < k[:, None], np.roll(f, -1, axis=1), f[:, :1])
        valid = f >= 0
        pairs = np.stack([f[valid], nxt[valid]], axis=1)
        with self._vertex_array(self.lines, np.asarray(mesh.vertices, "f4"), "3f", ("in_pos",), pairs) as vao:
            self.lines["mvp"].write(mvp)
            self.lines["line_color"].value = tuple(color)
            vao.render(mode=self.ctx.LINES)

    def release(self) -> None:
        self.ctx.release()

    def __enter__(self) -> Renderer:
        return self

    def __exit__(self, *exc) -> None:
        self.release()


def render(obj: Any, width: int = 800, height: int = 600, *, azimuth: float = 30.0, elevation: float = 20.0,
           up: str | None = None, transparent: bool = False) -> np.ndarray:
    """Shade a mesh or geometry image to an (H, W, 3) uint8 picture ((H, W, 4) when ``transparent``), the
    camera fitted tightly to it, its up axis ``up`` (default: :func:`up_axis`).

    Parameters
    ----------
    obj : Mesh or GeometryImage
        What to draw.
    width, height : int
        The picture's size, pixels.
    azimuth, elevation : float
        The view direction, degrees around and above the shape.
    up : {"x", "y", "z"} or None
        The up axis; None for :func:`up_axis`.
    transparent : bool
        A transparent background (RGBA).

    Returns
    -------
    numpy.ndarray
        (H, W, 3) or (H, W, 4) uint8.

    Raises
    ------
    RenderError
        When no OpenGL context can be made.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> render(m, 64, 48).shape
    (48, 64, 3)
    """
    with Renderer(width, height, background=None if transparent else (1.0, 1.0, 1.0)) as r:
        return r.render(obj, r.camera_for(obj, azimuth=azimuth, elevation=elevation, up=up))


def label_points(rgb: np.ndarray, points: ArrayLike, camera: Camera, labels: list | None = None) -> np.ndarray:
    """The picture with each 3-D point (k, 3) drawn as a ring and numbered (``labels``, default 0, 1, ...)
    where ``camera`` sees it: a copy; points behind the camera are left out.

    Parameters
    ----------
    rgb : numpy.ndarray
        (H, W, 3) uint8, the picture ``camera`` made.
    points : array_like
        (k, 3) the points.
    camera : Camera
        The camera of the picture.
    labels : list or None
        The text of each point; 0, 1, ... by default.

    Returns
    -------
    numpy.ndarray
        The labelled copy.

    Examples
    --------
    >>> cam = Camera.fit([-1, -1, -1], [1, 1, 1], aspect=1.0)
    >>> out = label_points(np.full((64, 64, 3), 255, np.uint8), [[0.0, 0.0, 0.0]], cam)
    >>> bool((out[32, 32] == 255).all()) and bool((out != 255).any())       # a ring around the middle
    True
    """
    out = np.ascontiguousarray(np.array(rgb, np.uint8))
    h, w = out.shape[:2]
    p = np.atleast_2d(np.asarray(points, np.float64))
    clip = np.hstack([p, np.ones((len(p), 1))]) @ camera.matrices(w / h).T
    size = max(4, round(min(h, w) / 60))
    for k, (x, y, _, depth) in enumerate(clip):
        if depth <= 0:
            continue
        px, py = int(round((x / depth + 1) * 0.5 * w)), int(round((1 - y / depth) * 0.5 * h))
        text = str(k if labels is None else labels[k])
        cv2.circle(out, (px, py), size, (200, 20, 20), max(1, size // 3), cv2.LINE_AA)
        cv2.putText(out, text, (px + size + 2, py - size), cv2.FONT_HERSHEY_SIMPLEX, size / 12, (20, 20, 20),
                    max(1, size // 4), cv2.LINE_AA)
    return out


def save_png(rgb: np.ndarray, path: PathLike, *, overwrite: bool = False) -> Path:
    """Write an (H, W, 3) or (H, W, 4) uint8 picture as PNG (atomically).

    Parameters
    ----------
    rgb : numpy.ndarray
        (H, W, 3) or (H, W, 4) uint8.
    path : path-like
        The ``.png`` file.
    overwrite : bool
        Replace the file if it exists.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    InputError
        When the name is not a ``.png``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> save_png(np.zeros((4, 4, 3), np.uint8), pathlib.Path(tempfile.mkdtemp()) / "black.png").name
    'black.png'
    """
    iio = require("imageio.v3", "writing pictures")
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise InputError(f"{path}: expected a .png name")
    with atomic_path(path, overwrite) as tmp:
        iio.imwrite(tmp, np.asarray(rgb, np.uint8), extension=".png")
    return path


def _write_gif(frames: np.ndarray, path: Path, fps: float) -> None:
    """An animated GIF (looping) of ``frames`` (n, H, W, 3) uint8 with one palette for all of them: 256
    colours by median cut from every few frames' pixels, each frame mapped to it with Floyd-Steinberg
    dithering (3x faster than a palette per frame, and no colours flicker between frames).
    """
    n, _, _, _ = frames.shape
    sample = np.ascontiguousarray(frames[::max(1, n // 8), ::2, ::2])
    palette = Image.fromarray(sample.reshape(-1, sample.shape[2], 3)).quantize(256, Image.Quantize.MEDIANCUT)
    pictures = [Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG) for f in frames]
    pictures[0].save(path, format="GIF", save_all=True, append_images=pictures[1:],
                     duration=max(1, int(round(1000.0 / fps))), loop=0, optimize=False)


def save_animation(frames: Any, path: PathLike, *, fps: float = 24.0, overwrite: bool = False) -> Path:
    """Write pictures (each (H, W, 3) uint8) as an animated GIF (looping) or an H.264 MP4 (needs the
    ``imageio-ffmpeg`` package: ``pip install geoimg[video]``).

    Parameters
    ----------
    frames : iterable of numpy.ndarray
        The pictures, (H, W, 3) uint8, one size.
    path : path-like
        A ``.gif`` or ``.mp4`` file.
    fps : float
        Frames per second.
    overwrite : bool
        Replace the file if it exists.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    MissingDependency
        For an MP4 without ``imageio-ffmpeg``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> frames = [np.full((8, 8, 3), v, np.uint8) for v in (0, 128, 255)]
    >>> save_animation(frames, pathlib.Path(tempfile.mkdtemp()) / "a.gif").suffix
    '.gif'
    """
    iio = require("imageio.v3", "writing animations")
    path = Path(path)
    ext = path.suffix.lower()
    if not (isinstance(fps, (int, float, np.number)) and np.isfinite(fps) and fps > 0):
        raise InputError(f"fps: expected a positive finite number, got {fps!r}")
    frames = [np.asarray(f, np.uint8) for f in frames]
    if not frames:
        raise InputError("frames: nothing to write")
    if ext == ".gif":
        with atomic_path(path, overwrite) as tmp:
            _write_gif(np.stack(frames), tmp, fps)
    elif ext == ".mp4":
        require("imageio_ffmpeg", "MP4 (GIF needs nothing more)")
        with atomic_path(path, overwrite) as tmp:
            iio.imwrite(tmp, np.stack(frames), extension=".mp4", fps=fps, codec="libx264", macro_block_size=8)
    else:
        raise InputError(f"{path}: expected a .gif or .mp4 name")
    return path
