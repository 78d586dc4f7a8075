"""Morphing: a morph between shapes is a blend of their geometry images (paper Fig. 5).

:func:`morph` takes two or more key shapes (geometry images, or meshes it turns into geometry images),
brings them into one frame (centre, scale and, for spherical images, the rotation of the sphere that best
matches the first shape, or with landmarks a fold-free warp of the sphere that makes them meet) and
returns a :class:`Morph` whose frames are blends of consecutive keys, with an easing curve and optionally
a per-pixel timing mask (one region leads, the rest follows).
"""
from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass, field
from typing import Any
from collections.abc import Callable, Iterator

import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage, optimize
from scipy.spatial.transform import Rotation

import filters
from .._choices import ALIGNMENTS, EASINGS
from ..errors import InputError, InputTypeError
from .._convert import mesh_to_image
from .._options import ConversionOptions
from ..image import GeometryImage, OctahedralDomain
from ..mesh import Mesh, grid_triangles, suggest_landmarks
from ..parametrization import grid_directions, parametrize, sphere_to_square
from ._warp import warp_sphere
from ..spectrum import grid_directions as gauss_legendre_directions, harmonics, synthesize
from ..spectrum._transform import check_lmax
from .._types import Progress
from .._threads import fixed_order

__all__ = ["morph", "Morph", "EASINGS", "ALIGNMENTS"]

DEFAULT_RESOLUTION = 129
MAX_FRAMES = 100_000      # over an hour at 24 frames a second
_PAD = 16
WARP_CHECK = 257         # the least grid of directions a landmark warp is checked for folds on


def _ease(easing):
    if callable(easing):
        return easing
    if easing not in EASINGS:
        raise InputError(f"easing: expected one of {tuple(EASINGS)} or a function of t in [0, 1], got {easing!r}")
    return EASINGS[easing]


def _landmark_entry(entry, shape, k: int) -> int:
    """One key's landmark: a vertex index as it is, or a 3-D point snapped to the mesh's nearest vertex."""
    if isinstance(entry, (numbers.Integral, np.integer)) and not isinstance(entry, bool):
        return int(entry)
    point = np.asarray(entry) if isinstance(entry, (list, tuple, np.ndarray)) else None
    if point is None or point.shape != (3,) or point.dtype == object or not np.issubdtype(point.dtype, np.number) \
            or not np.isfinite(point).all():
        raise InputError(f"landmarks: shape {k}'s landmark {entry!r} is neither a vertex index nor a 3-D point")
    if not isinstance(shape, Mesh):       # refused below with its own message
        return -1
    used = np.flatnonzero(shape.referenced_vertices())
    return int(used[np.argmin(((shape.vertices[used] - point) ** 2).sum(axis=1))])


def _check_landmarks(landmarks, shapes) -> np.ndarray:
    """``landmarks`` as an (L, K) int array: a row per feature, a vertex index (or a 3-D point, snapped to the
    nearest vertex) of each key's mesh.
    """
    rows = list(landmarks) if isinstance(landmarks, (list, tuple, np.ndarray)) else None
    if not rows or any(not isinstance(r, (list, tuple, np.ndarray)) or len(r) != len(shapes) for r in rows):
        raise InputError(f"landmarks: expected one tuple of {len(shapes)} vertex indices or 3-D points (one per "
                         f"key) per feature")
    table = np.array([[_landmark_entry(e, shapes[k], k) for k, e in enumerate(r)] for r in rows], np.int64)
    for k, shape in enumerate(shapes):
        if not isinstance(shape, Mesh):
            raise InputError(f"landmarks: shape {k} is a geometry image without its mesh; landmarks name mesh "
                             "vertices, so every key must be a mesh")
        column = table[:, k]
        if column.min() < 0 or column.max() >= shape.n_vertices:
            bad = int(column.max() if column.max() >= shape.n_vertices else column.min())
            raise InputError(f"landmarks: vertex {bad} of shape {k} does not exist (it has {shape.n_vertices})")
        if len(np.unique(column)) != len(column) or \
                len(np.unique(np.round(shape.vertices[column], 12), axis=0)) != len(column):
            raise InputError(f"landmarks: two landmarks of shape {k} coincide")
    return table


def _require_sphere(param, k: int) -> None:
    """Landmarks are for keys on the sphere: refuse another parametrization."""
    if param.domain != "octahedral":
        raise InputError(f"landmarks: shape {k} is parametrized onto the {param.domain} domain; landmark warps are "
                         "for closed genus-0 meshes (spherical parametrizations)")


def _landmark_warp(sources: np.ndarray, targets: np.ndarray, n: int, k: int) -> dict:
    """The warp of the sphere taking key 0's landmark directions ``sources`` onto key ``k``'s ``targets``,
    carried by the directions of an ``n x n`` octahedral image: key ``k`` resampled there lines up with key 0.
    The warp is checked for folds on a grid of at least WARP_CHECK² directions (a coarse image would refuse
    steps that only squeeze below its pixels). Returns the warp's report with the warped ``directions``
    (n, n, 3).
    """
    m = max(n, WARP_CHECK)
    points = grid_directions(m).reshape(-1, 3)
    if m > n:
        points = np.vstack([points, grid_directions(n).reshape(-1, 3)])
    moved, info = warp_sphere(points, grid_triangles(m, m), sources, targets)   # any winding: folds are sign changes
    directions = moved[len(moved) - n * n:]
    if not info["met"]:
        warnings.warn(f"landmarks: shape {k}'s landmarks stop up to {info['residual']:.3g} rad from shape 0's: no "
                      "fold-free step of the warp was left (landmarks too close together, or whose paths cross)",
                      stacklevel=4)
    return dict(info, directions=directions.reshape(n, n, 3))


AUTO_COUNT = 8               # landmarks suggested on each key for landmarks="auto"
AUTO_MATCH_DEG = 40.0        # ... matched to key 0's when their spheres, turned, put them this close


def _auto_landmarks(shapes, images, how, params, align, progress):
    """Landmarks matched between keys: each key's suggested extremities, on its sphere turned the way the
    rigid alignment turns it, paired with key 0's by least total angle (Hungarian), pairs farther than
    AUTO_MATCH_DEG dropped; a feature is kept when every key has a partner for it. ``images``, ``how`` and
    ``params``: what :func:`_as_images` made of the keys. Returns the (L, K) table.
    """
    for k, param in enumerate(params):
        _require_sphere(param, k)
    _, report = _align(images, align, True, [h.startswith("shared") for h in how], None)
    marks = [suggest_landmarks(s, AUTO_COUNT) for s in shapes]
    base = params[0].coords[marks[0]]
    partner = np.full((len(marks[0]), len(shapes)), -1, np.int64)
    partner[:, 0] = marks[0]
    for k in range(1, len(shapes)):
        entry = report[k]
        turn = Rotation.from_rotvec(np.radians(entry.get("rotation_deg", 0.0)) * np.asarray(entry.get(
            "rotation_axis", [0.0, 0.0, 1.0])))
        d = turn.inv().apply(params[k].coords[marks[k]])
        angle = np.degrees(np.arccos(np.clip(base @ d.T, -1.0, 1.0)))
        rows, cols = optimize.linear_sum_assignment(angle)
        keep = angle[rows, cols] <= AUTO_MATCH_DEG
        partner[rows[keep], k] = marks[k][cols[keep]]
    table = partner[(partner >= 0).all(axis=1)]
    if len(table) == 0:
        raise InputError("landmarks='auto': no suggested landmark of shape 0 has a partner on every key; give "
                         "them (geoimg landmarks writes suggestions to edit)")
    if progress:
        progress(f"auto landmarks: {len(table)} matched (vertices {table.tolist()})")
    return table


def _as_images(shapes, resolution, progress):
    """Geometry images of the shapes; meshes with the same faces as the previous mesh reuse its
    parametrization, so their images correspond vertex for vertex. Returns the images, how each key was
    parametrized and the parametrizations (None for images).
    """
    images, used_param, last = [], [], None
    made = [None] * len(shapes)
    for k, shape in enumerate(shapes):
        if isinstance(shape, GeometryImage):
            images.append(shape)
            used_param.append("given image")
            continue
        if not isinstance(shape, Mesh):
            raise InputTypeError(f"shapes[{k}]: expected a geoimg.Mesh or GeometryImage, got {type(shape).__name__}")
        if last is not None and last[0].n_vertices == shape.n_vertices and np.array_equal(last[0].faces, shape.faces):
            param = last[1]
            used_param.append(f"shared with shape {last[2]} (same faces)")
        else:
            param = parametrize(shape)
            used_param.append(param.method)
        made[k] = param
        if progress:
            progress(f"shape {k}: {used_param[-1]} parametrization, sampling {resolution} pixels")
        images.append(mesh_to_image(shape, resolution, parametrization=param, fidelity=False))
        last = (shape, param, k)
    return images, used_param, made


SPECTRAL_CHOICE_LMAX = 16    # the degree up to which the ellipsoid frames' 24 turns are compared


def _spectral_keys(shapes, lmax: int, resolution: int, progress) -> tuple[list, list]:
    """The keys rebuilt from their harmonics to degree ``lmax`` with their spheres put in correspondence by
    the first-order ellipsoids (SPHARM's normalization), each shape left where it stands: pixel ``d`` of key
    ``k`` is ``x_k(V_k G_k^T d)``, ``V_k`` the sphere turn of its normalization and ``G_k`` the turn of the
    cube (of 24) that best matches key 0's normalized shape (the ellipsoid's axes leave their order and signs
    open when two have nearly one length). Blending such images is blending their coefficients. Returns the
    images and a report entry per key.
    """
    raw, unit = [], []
    for k, shape in enumerate(shapes):
        if not isinstance(shape, (Mesh, GeometryImage)):
            raise InputTypeError(f"shapes[{k}]: expected a geoimg.Mesh or GeometryImage, got {type(shape).__name__}")
        if progress:
            progress(f"shape {k}: harmonics to degree {lmax}")
        h = harmonics(shape, lmax, progress=progress)
        raw.append(h)
        unit.append(h.normalized(scale=True))
    low = min(lmax, SPECTRAL_CHOICE_LMAX)
    probe = gauss_legendre_directions(low).reshape(-1, 3)
    reference = synthesize(unit[0].truncated(low).coeffs, probe)
    turns = Rotation.create_group("O").as_matrix()
    domain = OctahedralDomain()
    n = domain.round_resolution(resolution)
    directions = domain.directions(n).reshape(-1, 3)
    images, entries = [], []
    for k, (h, u) in enumerate(zip(raw, unit)):
        g = np.eye(3)
        if k:
            c = u.truncated(low).coeffs

            def cost(sphere, shape, c=c):
                """Key k's normalized shape turned by ``shape`` with its sphere turned by ``sphere``, to key 0's."""
                return float(((synthesize(c, probe @ sphere) @ shape.T - reference) ** 2).mean())

            g = turns[int(np.argmin([cost(t, t) for t in turns]))]      # the frame's order and signs
            # then the sphere alone, turned a little further where that matches key 0 better
            fine = optimize.minimize(lambda r, g=g: cost(Rotation.from_rotvec(r).as_matrix() @ g, g), np.zeros(3),
                                     method="Nelder-Mead", options={"xatol": 1e-4, "fatol": 1e-12, "maxiter": 300})
            g = Rotation.from_rotvec(fine.x).as_matrix() @ g
        v = np.asarray(u.metadata["normalization"]["sphere_rotation"])
        pixels = synthesize(h.coeffs, directions @ g @ v.T).reshape(n, n, 3)
        meta = {key: h.metadata[key] for key in ("source", "psnr_db") if key in h.metadata}
        images.append(GeometryImage(pixels.astype(np.float32), None, domain, metadata=dict(meta, harmonics_lmax=lmax)))
        turn = Rotation.from_matrix(v @ g.T)
        entries.append({"harmonics_lmax": lmax, "sphere_turn_deg": float(np.degrees(turn.magnitude())),
                        "parametrization": f"harmonics to degree {lmax}, spheres matched by the ellipsoids"})
    return images, entries


def _landmark_warps(params, landmarks: np.ndarray, resolution: int) -> list:
    """Each later key's warp of the sphere that brings key 0's landmarks ((L, K) vertex indices) onto its
    own (the alignment resamples the key there); None for key 0.
    """
    for k, param in enumerate(params):
        _require_sphere(param, k)
    sources = params[0].coords[landmarks[:, 0]]
    warps: list = [None]
    for k, param in enumerate(params[1:], start=1):      # a loop, not a comprehension: the warning's stacklevel
        warps.append(_landmark_warp(sources, param.coords[landmarks[:, k]], resolution, k))
    return warps


def _centre_and_radius(img: GeometryImage):
    p = img.pixels[img.valid].astype(np.float64)
    lo, hi = p.min(axis=0), p.max(axis=0)
    centre = 0.5 * (lo + hi)
    return centre, float(np.sqrt(((p - centre) ** 2).sum(axis=1).mean()))


def _octahedral_sampler(pixels: np.ndarray, domain):
    """A function giving the cubic-spline interpolation of an octahedral image at unit directions (..., 3)."""
    n = pixels.shape[0]
    padded = domain.pad(np.asarray(pixels, np.float64), _PAD)
    coeffs = [ndimage.spline_filter(padded[..., c], order=3, mode="nearest") for c in range(padded.shape[2])]

    def sample(q):
        uv = sphere_to_square(q) * (n - 1) + _PAD
        coords = [uv[..., 1], uv[..., 0]]
        return np.stack([ndimage.map_coordinates(c, coords, order=3, mode="nearest", prefilter=False)
                         for c in coeffs], axis=-1)

    return sample


def _best_rotation(reference: GeometryImage, moving: np.ndarray) -> tuple[Rotation, float, float]:
    """Rotation R of the sphere minimizing the mean squared distance between ``reference(q)`` and
    ``moving(R q)`` on a coarse grid: the 24 rotations of the cube as starts, then Nelder-Mead.
    """
    n = 33
    q = grid_directions(n).reshape(-1, 3)
    ref = _octahedral_sampler(reference.pixels, reference.domain)(q)
    mov = _octahedral_sampler(moving, reference.domain)

    def cost(rotvec):
        return float(((mov(Rotation.from_rotvec(rotvec).apply(q)) - ref) ** 2).sum(axis=1).mean())

    starts = Rotation.create_group("O")
    scores = [cost(r.as_rotvec()) for r in starts]
    identity = cost(np.zeros(3))
    best = starts[int(np.argmin(scores))].as_rotvec()
    res = optimize.minimize(cost, best, method="Nelder-Mead", options={"xatol": 1e-3, "fatol": 1e-10, "maxiter": 400})
    rot = Rotation.from_rotvec(res.x) if res.fun < identity else Rotation.identity()
    return rot, identity, min(res.fun, identity)


def _resample(pixels: np.ndarray, colors, domain, directions: np.ndarray):
    """An octahedral image's pixels (and colours) at other ``directions`` (one per pixel): pixel ``i`` of the
    result shows the surface at ``directions[i]``; glued pixels averaged.
    """
    q = directions.reshape(-1, 3)
    out = domain.average_glued(_octahedral_sampler(pixels, domain)(q).reshape(pixels.shape))
    if colors is not None:            # the colours move with the surface
        colors = np.clip(domain.average_glued(_octahedral_sampler(colors, domain)(q).reshape(colors.shape)), 0.0, 1.0)
    return out, colors


def _align(images, align: str, rotate: bool, shared, progress, warps=None):
    """Move keys 1.. into key 0's frame; returns the new images and what was done to each. A key whose
    parametrization is shared with the key before it (``shared[k]``) gets that key's rotation, not a
    search of its own: its correspondence is the vertices'.
    """
    c0, r0 = _centre_and_radius(images[0])
    out, report = [images[0]], [{"shape": 0, "reference": True}]
    previous = Rotation.identity()
    for k, img in enumerate(images[1:], start=1):
        entry: dict = {"shape": k}
        p = img.pixels.astype(np.float64)
        colors = img.colors
        if align != "none":
            c, r = _centre_and_radius(img)
            scale = r0 / r if align == "similarity" and r > 0 else 1.0
            p = p + (c0 - c) if scale == 1.0 else (p - c) * scale + c0     # a shape already in place stays exact
            entry.update(translation=(c0 - c).tolist(), scale=float(scale))
        if warps is not None and warps[k] is not None:       # resampled where the warp sends key 0's pixels
            w = warps[k]
            entry.update(landmarks={"residual_rad": w["residual"], "met": w["met"], "folded": w["folded"],
                                    "steps": w["steps"], "area_log_rms": w["area_log_rms"]})
            p, colors = _resample(p, colors, img.domain, w["directions"])
            previous = Rotation.identity()
        elif rotate and img.domain.rotations:
            if shared[k]:
                rot = previous
                entry.update(rotation_from=k - 1)
            else:
                rot, before, after = _best_rotation(images[0], p)
                entry.update(rms_before=math.sqrt(before) / r0, rms_after=math.sqrt(after) / r0)
            angle = float(np.degrees(rot.magnitude()))
            if angle > 0:
                p, colors = _resample(p, colors, img.domain, rot.apply(grid_directions(p.shape[0]).reshape(-1, 3)))
            entry.update(rotation_deg=angle, rotation_axis=(rot.as_rotvec() / max(rot.magnitude(), 1e-300)).tolist())
            previous = rot
            if progress and "rms_before" in entry:
                progress(f"shape {k}: sphere turned by {angle:.1f} degrees (RMS to shape 0: "
                         f"{entry['rms_before']:.3f} -> {entry['rms_after']:.3f} of its radius)")
        meta = dict(img.metadata, morph_alignment=entry)
        out.append(GeometryImage(p.astype(img.pixels.dtype), img.mask, domain=img.domain, metadata=meta,
                                 colors=colors))
        report.append(entry)
    return out, report


@dataclass(frozen=True, eq=False)
class Morph:
    """A morph through key geometry images (aligned, same domain and size).

    ``times`` are the frames' positions along the keys, from 0 (key 0) to ``len(keys) - 1`` (last key);
    :meth:`frame` blends the two keys around a time. ``weights``/``lag``: per-pixel timing (pixels of
    weight 1 run ``lag`` ahead of those of weight 0 within each segment).

    Parameters
    ----------
    keys : list of GeometryImage
        The aligned keys, of one domain and size.
    times : numpy.ndarray
        (frames,) the frames' times, from 0 to ``len(keys) - 1``.
    easing : callable
        ``f(t)`` applied to each segment's local time.
    weights : numpy.ndarray or None
        (H, W) per-pixel timing weights in [0, 1].
    lag : float
        How far pixels of weight 1 run ahead, as a share of a segment.
    report : list
        What the alignment did to each key (a dict per key).

    Examples
    --------
    >>> import numpy as np
    >>> from geoimg import GeometryImage
    >>> from geoimg.animation import morph
    >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
    ...           frames=5, align="none")
    >>> isinstance(m, Morph), m.times.tolist()
    (True, [0.0, 0.25, 0.5, 0.75, 1.0])
    """

    keys: list
    times: np.ndarray
    easing: Callable[[Any], Any] = field(repr=False)
    weights: np.ndarray | None = field(repr=False, default=None)
    lag: float = 0.0
    report: list = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.times)

    def segment(self, t: float) -> tuple[int, float]:
        """Key index ``k`` and the time ``u`` in [0, 1] between keys ``k`` and ``k + 1``.

        Parameters
        ----------
        t : float
            A time from 0 to ``len(keys) - 1``.

        Returns
        -------
        k : int
            The key before it.
        u : float
            The time between keys ``k`` and ``k + 1``.

        Examples
        --------
        >>> from geoimg import GeometryImage
        >>> from geoimg.animation import morph
        >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
        ...           frames=3, easing="linear", align="none")
        >>> m.segment(0.5)
        (0, 0.5)
        """
        if not (isinstance(t, numbers.Real) and 0 <= t <= len(self.keys) - 1):
            raise InputError(f"t: expected a time in [0, {len(self.keys) - 1}], got {t!r}")
        k = min(int(math.floor(t)), len(self.keys) - 2)
        return k, float(t - k)

    def local_time(self, u: float) -> float | np.ndarray:
        """Eased blend weight at segment time ``u``: a number, or an (H, W) map with a timing mask.

        Parameters
        ----------
        u : float
            The time within a segment, in [0, 1].

        Returns
        -------
        float or numpy.ndarray
            The blend weight.

        Examples
        --------
        >>> from geoimg import GeometryImage
        >>> from geoimg.animation import morph
        >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
        ...           frames=3, easing="linear", align="none")
        >>> m.local_time(0.25)
        0.25
        """
        if self.weights is None:
            return float(self.easing(u))
        local = np.clip((u - self.lag * (1.0 - self.weights)) / (1.0 - self.lag), 0.0, 1.0)
        return np.clip(self.easing(local), 0.0, 1.0)

    def frame(self, t: float) -> GeometryImage:
        """The blended geometry image at time ``t``.

        Parameters
        ----------
        t : float
            A time from 0 (key 0) to ``len(keys) - 1``.

        Returns
        -------
        GeometryImage
            The frame.

        Examples
        --------
        >>> from geoimg import GeometryImage
        >>> from geoimg.animation import morph
        >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
        ...           frames=3, easing="linear", align="none")
        >>> float(m.frame(0.5).pixels[0, 0, 0])
        0.5
        """
        k, u = self.segment(t)
        a, b = self.keys[k], self.keys[k + 1]
        w = self.local_time(u)
        if isinstance(w, float) and w in (0.0, 1.0):
            px = (a if w == 0.0 else b).pixels
        else:
            px = filters.blend(a.pixels, b.pixels, w)
        mask = None
        if a.mask is not None or b.mask is not None:
            mask = a.valid & b.valid
        colors = None
        if a.colors is not None and b.colors is not None:     # colours blend with the shape
            colors = np.clip(filters.blend(a.colors[..., :3], b.colors[..., :3], w), 0.0, 1.0)
        return GeometryImage(px, mask, domain=a.domain, metadata={"morph_time": float(t)}, colors=colors)

    def frames(self) -> Iterator[GeometryImage]:
        """The frames, in order (a generator).

        Examples
        --------
        >>> from geoimg import GeometryImage
        >>> from geoimg.animation import morph
        >>> m = morph(GeometryImage(np.zeros((3, 3, 3), np.float32)), GeometryImage(np.ones((3, 3, 3), np.float32)),
        ...           frames=3, easing="linear", align="none")
        >>> len(list(m.frames()))
        3
        """
        for t in self.times:
            yield self.frame(float(t))


@fixed_order
def morph(*shapes: Any, frames: int = 30, easing: Any = "smoothstep", mask: ArrayLike | None = None, lag: float = 0.5,
          align: str = "similarity", rotate: bool = True, resolution: int = DEFAULT_RESOLUTION,
          resample: bool = False, landmarks: Any = None, spectral: int | None = None,
          progress: Progress | None = None) -> Morph:
    """Morph through two or more shapes.

    Parameters
    ----------
    *shapes : GeometryImage or Mesh
        Key shapes, in order. Meshes are parametrized (``auto``) and sampled at ``resolution``; a mesh
        with the same faces as the mesh before it reuses that parametrization (vertex correspondence).
    frames : int, default 30
        Frames in all, the first showing the first key and the last the last key.
    easing : str or callable
        ``linear``, ``smoothstep`` (default), ``ease-in-out``, ``ease-in``, ``ease-out``, or ``f(t)``.
    mask : array_like (H, W), optional
        Per-region timing: pixels of weight 1 start at once and finish ``lag`` early; weight 0 start
        ``lag`` late. Frame 0 and the last frame are the keys whatever the mask.
    align : {'similarity', 'centre', 'none'}
        Move keys 1.. onto key 0: bounding-box centres (``centre``), and scale to key 0's RMS radius
        (``similarity``).
    rotate : bool, default True
        For spherical (octahedral) images, turn each key's sphere by the rotation that best matches key
        0 (24 cube rotations tried, then refined); reported in ``Morph.report``. A mesh that shares the
        previous mesh's parametrization takes that mesh's rotation (its correspondence is the vertices').
    resample : bool, default False
        Resize keys of another size to key 0's size (else such keys are refused).
    landmarks : sequence of tuples, or "auto", optional
        Corresponding features: one tuple per feature holding, for each key's mesh (every key a closed
        genus-0 mesh), a vertex index or a 3-D point (snapped to the nearest vertex). Each later key is
        resampled through a smooth, one-to-one warp of the sphere (a rotation that best matches the
        landmarks, then a fold-free flow) that takes key 0's landmark directions onto its own (within 1e-4
        rad); the rotation search is skipped for it. ``Morph.report`` gives each key's residual, steps,
        folded triangles and the warp's area log-RMS. (Suggested landmarks:
        :func:`geoimg.mesh.suggest_landmarks`.) ``"auto"``: each key's suggested extremities, matched to key
        0's on the rigidly turned spheres (within 40 degrees); the report's ``auto_landmarks`` says which
        were matched.
    spectral : int, optional
        Blend the keys' spherical harmonics to this degree instead of their images: each key (a closed
        genus-0 mesh or an octahedral image) is expanded (:func:`geoimg.harmonics`), its sphere turned into
        its first-order ellipsoid's frame (:meth:`geoimg.Harmonics.normalized`; of the cube's 24 turns of that
        frame, the one nearest key 0's), and rebuilt at ``resolution``; ``align`` then moves and scales it as
        for images. The ellipsoids make the correspondence (``rotate`` is not used); every frame is of degree
        ``spectral``, so a low degree also smooths. Not with ``landmarks``.
    lag : float, default 0.5
        How far the mask's pixels of weight 1 run ahead, as a share of a segment.
    resolution : int, default 129
        Pixels per side for keys given as meshes.
    progress : callable, optional
        Called with each key's conversion progress.

    Returns
    -------
    Morph

    Raises
    ------
    ValueError
        Fewer than two shapes, a domain mismatch, a size mismatch without ``resample``, bad settings.

    Examples
    --------
    >>> a = GeometryImage(np.zeros((3, 3, 3), np.float32))
    >>> b = GeometryImage(np.ones((3, 3, 3), np.float32))
    >>> m = morph(a, b, frames=3, easing="linear", align="none")
    >>> [float(f.pixels[0, 0, 0]) for f in m.frames()]
    [0.0, 0.5, 1.0]
    """
    if len(shapes) < 2:
        raise InputError(f"shapes: a morph needs at least two shapes, got {len(shapes)}")
    if isinstance(frames, bool) or not isinstance(frames, numbers.Integral) or not 2 <= frames <= MAX_FRAMES:
        raise InputError(f"frames: expected an integer from 2 to {MAX_FRAMES}, got {frames!r}")
    ease = _ease(easing)
    resolution = ConversionOptions(resolution=resolution).resolution      # checked before any key is mapped
    if align not in ALIGNMENTS:
        raise InputError(f"align: expected one of {ALIGNMENTS}, got {align!r}")
    if not (isinstance(lag, numbers.Real) and 0 <= lag < 1):
        raise InputError(f"lag: expected a number in [0, 1), got {lag!r}")
    auto = isinstance(landmarks, str)
    if auto and landmarks != "auto":
        raise InputError(f"landmarks: expected vertex-index tuples or 'auto', got {landmarks!r}")
    if auto and not all(isinstance(s, Mesh) for s in shapes):
        raise InputError("landmarks='auto': every key must be a mesh (landmarks are suggested on meshes)")
    table = None if landmarks is None or auto else _check_landmarks(landmarks, shapes)   # refused before work
    spectral_report: list = [{}] * len(shapes)
    if spectral is not None:
        lmax = check_lmax(spectral)
        if landmarks is not None:
            raise InputError("spectral: the harmonics' ellipsoids make the correspondence; landmarks are for image "
                             "morphs (give one or the other)")
        images, spectral_report = _spectral_keys(shapes, lmax, resolution, progress)
        how, params = [e.pop("parametrization") for e in spectral_report], []
        rotate = False                                                 # the ellipsoids matched the spheres
    else:
        images, how, params = _as_images(shapes, resolution, progress)
    if auto:
        table = _auto_landmarks(shapes, images, how, params, align, progress)
    warps = None
    if table is not None:
        warps = _landmark_warps(params, table, images[0].shape[0])
        how = [h if k == 0 else h + " + landmark warp" for k, h in enumerate(how)]
    if not all(img.domain.same_kind(images[0].domain) for img in images[1:]):
        kinds = ", ".join(f"shape {k}: {img.domain.kind}" for k, img in enumerate(images))
        raise InputError(f"shapes: cannot morph between domains ({kinds}); geometry images must share a "
                         "parametrization domain (planar with planar, spherical with spherical, and cut-open "
                         "images only with the same cut layouts, i.e. meshes with the same faces)")
    for k, img in enumerate(images[1:], start=1):
        if img.shape != images[0].shape:
            if not resample:
                raise InputError(f"shapes: shape {k} is {img.shape[1]} x {img.shape[0]} pixels, shape 0 is "
                                 f"{images[0].shape[1]} x {images[0].shape[0]}; pass resample=True to resize it")
            px = filters.resize(img.pixels, images[0].shape, img.domain.extension)
            valid = None if img.mask is None else filters.resize(img.mask.astype(np.float64), images[0].shape) > 0.5
            colors = None if img.colors is None else np.clip(filters.resize(img.colors, images[0].shape,
                                                                            img.domain.extension), 0.0, 1.0)
            images[k] = GeometryImage(px, valid, domain=img.domain, metadata=img.metadata, colors=colors)
    weights = None
    if mask is not None:
        weights = images[0].domain.symmetric_mask(filters.as_weights(mask, images[0].shape))
    keys, report = _align(images, align, bool(rotate), [h.startswith("shared") for h in how], progress, warps)
    for entry, h, extra in zip(report, how, spectral_report):
        entry.update(extra, parametrization=h)
    if auto:
        report[0]["auto_landmarks"] = table.tolist()
    times = np.linspace(0.0, len(keys) - 1, int(frames))
    return Morph(keys, times, ease, weights, float(lag) if weights is not None else 0.0, report)
