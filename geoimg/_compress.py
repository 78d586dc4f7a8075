"""Shapes compressed as JPEG 2000 geometry images: :func:`compress` chooses the image's resolution and the
coder's rate for the least error within a byte budget (or the fewest bytes for an error), measuring each
candidate exactly (the decoded image's quad mesh against the mesh: two-sided RMS by an AABB tree).

With a byte budget, a mesh may also become a *displaced* file: a coarse base and one channel of offsets along
its normals (:mod:`geoimg.image._displacement`), which spends no bytes on where samples sit along the surface.

The file is a standard JP2 (see :mod:`geoimg.image._jp2`): :func:`geoimg.load_image`, ``geoimg mesh``,
``geoimg info`` read it like any geometry image, welding what its domain glues.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from collections.abc import Callable

import igl
import numpy as np

from ._atomic import atomic_path
from ._choices import READ_IMAGE_FORMATS
from ._convert import mesh_to_image
from ._offset_fit import BENDINGS, fit_offsets
from ._threads import fixed_order
from ._types import Progress
from .errors import InputError, InputTypeError
from .image import GeometryImage, load_image
from .image._displacement import area_weights, base_frame
from .image._jp2 import LOSSLESS, continue_masked, decode, encode, offsets_codestream
from .mesh import Mesh, load_mesh
from .mesh._metrics import ReferenceDistances
from .parametrization import parametrize

__all__ = ["compress", "Compressed", "DEFAULT_RESOLUTIONS"]

DEFAULT_RESOLUTIONS = (33, 65, 129, 257, 513)
LEVELS = (20.0, 140.0)         # the coder's PSNR targets searched (dB of its 16-bit range)
SEARCH_STEPS = 10              # bisection steps of the level: 0.12 dB apart at the end
SAMPLES = 20_000               # area samples a side for each candidate's error
DISPLACED_SHARES = (0.4, 0.5)        # a displaced candidate's base: these shares of the budget tried, then
SHARE_STEP, SHARE_RANGE = 0.1, (0.2, 0.8)   # steps of 0.1 on from the better one while they gain (within 0.2-0.8)
DISPLACED_FROM = 129           # displaced candidates at this side and above, on bases of 1/2 and 1/4 the side
PSNR_BUDGET_STEPS = 8         # with a PSNR target: a displaced file's budget bisected at most this often
PROJECTION_ROUNDS = 3          # the offsets: the closest point's distance along the normal, refined this often


@dataclass(frozen=True)
class Compressed:
    """What :func:`compress` made: the file's ``data``, the decoded ``image`` (what a reader gets), and how.

    Parameters
    ----------
    data : bytes
        The JP2 file.
    image : GeometryImage
        ``data`` decoded.
    resolution : int
        The image's side.
    level : float
        The coder's target PSNR (dB of the 16-bit range; 0: lossless).
    psnr_db : float
        Of the decoded shape against the source (the mesh, or the source image's pixels).
    tried : list of dict
        Every candidate resolution: its bytes and PSNR, or why it was left out.
    base : int or None
        A displaced file's base side (:mod:`geoimg.image._displacement`: the base coded, the offsets along its
        normals at ``resolution``); None for a plain image.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> c = compress(geoimg.GeometryImage(d.directions(17).astype(np.float32), None, d), max_bytes=1200)
    >>> c.resolution, c.image.shape
    (17, (17, 17))
    """

    data: bytes
    image: GeometryImage
    resolution: int
    level: float
    psnr_db: float
    tried: list = field(default_factory=list)
    base: int | None = None

    @property
    def nbytes(self) -> int:
        """The file's size in bytes.

        Returns
        -------
        int
            ``len(data)``.

        Examples
        --------
        >>> import geoimg
        >>> d = geoimg.OctahedralDomain()
        >>> c = compress(geoimg.GeometryImage(d.directions(17).astype(np.float32), None, d), max_bytes=1200)
        >>> c.nbytes == len(c.data) <= 1200
        True
        """
        return len(self.data)


def _check_target(max_bytes, psnr) -> None:
    if (max_bytes is None) == (psnr is None):
        raise InputError("give a byte budget (max_bytes) or a PSNR to reach (psnr), one of the two")
    if max_bytes is not None and (isinstance(max_bytes, bool) or not isinstance(max_bytes, numbers.Integral)
                                  or int(max_bytes) < 1):
        raise InputError(f"max_bytes: expected a whole number of bytes above 0, got {max_bytes!r}")
    if psnr is not None and (isinstance(psnr, bool) or not isinstance(psnr, numbers.Real)
                             or not math.isfinite(float(psnr)) or not 0 < float(psnr) < 200):
        raise InputError(f"psnr: expected a number of dB between 0 and 200, got {psnr!r}")


def _candidates(source, resolutions, progress) -> tuple[list[GeometryImage], Any]:
    """The images to code and what to measure them against (the mesh, or the source image)."""
    if isinstance(source, (str, Path)):
        path = Path(source)
        source = load_image(path) if path.suffix.lower() in READ_IMAGE_FORMATS else load_mesh(path)
    if isinstance(source, GeometryImage):
        if resolutions is not None:
            raise InputError("resolutions: an image is coded at its own size (give a mesh to choose the size)")
        return [continue_masked(source)], source
    if not isinstance(source, Mesh):
        raise InputTypeError(f"source: expected a Mesh, a GeometryImage or a file, got {type(source).__name__}")
    sizes = DEFAULT_RESOLUTIONS if resolutions is None else tuple(resolutions)
    if not sizes or any(isinstance(r, bool) or not isinstance(r, numbers.Integral) or not 3 <= int(r) <= 4097
                        for r in sizes):
        raise InputError(f"resolutions: expected sides from 3 to 4097, got {resolutions!r}")
    param = parametrize(source)
    images: list[GeometryImage] = []
    for r in sorted(set(int(r) for r in sizes)):
        if progress:
            progress(f"converting at {r} x {r}")
        with warnings.catch_warnings():      # a small candidate far from the mesh is no news: its PSNR is listed
            warnings.filterwarnings("ignore", message="the image is far from its mesh")
            # measured, so that the mesh resampled as it is is taken where it lies closer than the prefilter (a
            # beetle's 257² multi-chart image 51.7 -> 83.0 dB)
            image = mesh_to_image(source, r, parametrization=param)
        if all(image.shape != other.shape for other in images):    # a domain may round two sizes to one
            images.append(continue_masked(image))
    return images, source


def _error_db(reference, image: GeometryImage) -> float:
    """PSNR of ``image`` against the mesh (exact two-sided RMS; ``reference`` the mesh's
    :class:`~geoimg.mesh._metrics.ReferenceDistances`) or against the source image (its pixels).
    """
    if isinstance(reference, ReferenceDistances):
        return float(reference.to(image.to_mesh())["psnr_db"])
    valid = reference.valid & image.valid
    a, b = reference.pixels[valid].astype(np.float64), image.pixels[valid].astype(np.float64)
    diagonal = float(np.linalg.norm(np.ptp(a, axis=0)))
    rms = float(np.sqrt(((a - b) ** 2).sum(axis=1).mean()))
    return 20 * math.log10(diagonal / rms) if rms > 0 else math.inf


def _level_for_bytes(image: GeometryImage, max_bytes: int, channels: dict) -> tuple[float, bytes] | int:
    """The highest level whose file fits ``max_bytes`` (lossless first, if it fits), and the file; or the
    least size this image can take, when even the lowest level does not fit.
    """
    lossless = encode(image, LOSSLESS, **channels)
    if len(lossless) <= max_bytes:
        return LOSSLESS, lossless
    found = _bisect_level(lambda level: (len(data := encode(image, level, **channels)), data), max_bytes)
    return found if isinstance(found, int) else (found[0], found[1])


def _bisect_level(coded: Callable[[float], tuple[int, Any]], max_bytes: int) -> tuple[float, Any] | int:
    """The highest of :data:`LEVELS` (bisected) whose file fits ``max_bytes``, and what ``coded(level)`` (the
    file's size and anything) gave with it; or the lowest level's size, when that does not fit.
    """
    lo, hi = LEVELS
    size, low = coded(lo)
    if size > max_bytes:
        return size
    best = (lo, low)
    for _ in range(SEARCH_STEPS):
        mid = 0.5 * (lo + hi)
        size, got = coded(mid)
        if size <= max_bytes:
            lo, best = mid, (mid, got)
        else:
            hi = mid
    return best


class _Surface:
    """Closest points on a mesh (libigl's AABB tree, built at the first query and kept)."""

    def __init__(self, mesh: Mesh):
        self.mesh = mesh

    @functools.cached_property
    def _tree(self) -> tuple[np.ndarray, np.ndarray, Any]:
        vertices = np.ascontiguousarray(self.mesh.vertices, np.float64)
        tris = np.ascontiguousarray(self.mesh.triangulate(quads="shorter")[0], np.int64)
        tree = igl.AABB()
        tree.init(vertices, tris)
        return vertices, tris, tree

    def offsets(self, points: np.ndarray, normals: np.ndarray, rounds: int = PROJECTION_ROUNDS) -> np.ndarray:
        """How far along each normal (H, W, 3) from each point (H, W, 3) the mesh is: the closest point's
        distance along the normal, then ``rounds`` times the closest point's to the point so moved (a line
        that crosses the surface at a slant converges to where it crosses).
        """
        h = np.zeros(points.shape[:2])
        for _ in range(rounds + 1):
            moved = points + h[..., None] * normals
            on = self.closest(moved.reshape(-1, 3))[2]
            h += ((on.reshape(points.shape) - moved) * normals).sum(axis=-1)
        return h

    def closest(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For points ``q`` (m, 3): their squared distances to the mesh, the closest faces' unit normals and
        the closest points.
        """
        vertices, tris, tree = self._tree
        squared, faces, on = tree.squared_distance(vertices, tris, np.ascontiguousarray(q, np.float64))
        return squared, self._face_normals[faces], on

    @functools.cached_property
    def _face_normals(self) -> np.ndarray:
        vertices, tris, _ = self._tree
        n = np.cross(vertices[tris[:, 1]] - vertices[tris[:, 0]], vertices[tris[:, 2]] - vertices[tris[:, 0]])
        length = np.linalg.norm(n, axis=1, keepdims=True)
        return np.divide(n, length, out=np.zeros_like(n), where=length > 0)


def _displaced_for_bytes(full: GeometryImage, base: GeometryImage, surface: _Surface, max_bytes: int,
                         share: float, bendings: tuple = (None,)) -> list[tuple[Any, float, bytes]]:
    """Displaced files of ``full``'s size on ``base`` (coded in ``share`` of the budget) within ``max_bytes``,
    one for each of ``bendings`` (None: the offsets where each line meets the mesh; a number: those offsets
    fitted to the mesh in least squares with this bending, :mod:`geoimg._offset_fit`), the base coded, its
    frame and the lines' offsets found once for all: ``(bending, level, file)`` each, the offsets' level
    bisected; none where the budget holds no such file.
    """
    got = _level_for_bytes(base, int(share * max_bytes), {})
    if isinstance(got, int):
        return []
    base_level, base_data = got
    points, normals = base_frame(decode(base_data).pixels, full.domain, full.shape)
    crossing = surface.offsets(points, normals)
    weights = area_weights(points, full.domain)       # the coder's error least in the surface's measure
    files = []
    for bending in bendings:
        offsets = crossing if bending is None else fit_offsets(crossing, points, normals, surface.closest, bending)
        coded = _offsets_level_for_bytes(base, base_level, offsets, max_bytes, weights)
        if coded is not None:
            files.append((bending, *coded))
    return files


def _offsets_level_for_bytes(base: GeometryImage, base_level: float, offsets: np.ndarray, max_bytes: int,
                             weights: np.ndarray) -> tuple[float, bytes] | None:
    """The highest level of the offsets (coded with ``weights``, see :func:`offsets_codestream`) whose displaced
    file (``base`` coded at ``base_level``) fits ``max_bytes``, and the file; None where even the lowest does
    not fit.
    """
    # the file is the base's, the record and the offsets' codestream: only the last changes with its level
    coded = functools.cache(lambda level: len(offsets_codestream(offsets, level, weights)[0]))   # each coded once
    def file(level: float) -> bytes:
        return encode(base, base_level, offsets=offsets, offsets_level=level, offsets_weights=weights)

    fixed = len(file(LEVELS[0])) - coded(LEVELS[0])
    found = _bisect_level(lambda level: (fixed + coded(level), None), max_bytes)
    if isinstance(found, int):
        return None
    return found[0], file(found[0])


def _measured_displaced(full: GeometryImage, base: GeometryImage, surface: _Surface, reference, max_bytes: int,
                        tried: list, out: list, share: float, bendings: tuple = (None,)) -> float:
    """The displaced candidates with the base in ``share`` of the budget (one for each of ``bendings``, as
    for :func:`_displaced_for_bytes`), decoded and measured: their figures added to ``tried``, ``(candidate,
    full, base, share)`` to ``out``; the best one's PSNR (-inf where no such file fits).
    """
    best = -math.inf
    for bending, level, data in _displaced_for_bytes(full, base, surface, max_bytes, share, bendings):
        decoded = decode(data)
        db = _error_db(reference, decoded)
        n = full.shape[0]
        fitted = {} if bending is None else {"fitted": bending}
        tried.append({"resolution": n, "base": base.shape[0], "share": share, "bytes": len(data),
                      "psnr_db": round(db, 2), "level": round(level, 2), **fitted})
        out.append((Compressed(data, decoded, n, float(level), float(db), base=base.shape[0]), full, base, share))
        best = max(best, db)
    return best


def _walk_shares(attempt: Callable[[float], float]) -> None:
    """Each of :data:`DISPLACED_SHARES`, then steps of :data:`SHARE_STEP` on from the better of the last two
    (away from the worse) while each gains, within :data:`SHARE_RANGE`: ``attempt(share)`` measures one.

    >>> seen = []
    >>> _walk_shares(lambda share: seen.append(share) or -(share - 0.7) ** 2)
    >>> seen
    [0.4, 0.5, 0.6, 0.7, 0.8]
    """
    shares = [float(x) for x in DISPLACED_SHARES]
    scores = [attempt(x) for x in shares]
    step = SHARE_STEP if scores[-1] >= scores[-2] else -SHARE_STEP
    at, best = (shares[-1], scores[-1]) if step > 0 else (shares[-2], scores[-2])
    while True:
        nxt = round(at + step, 6)
        if not SHARE_RANGE[0] <= nxt <= SHARE_RANGE[1]:
            return
        got = attempt(nxt)
        if not got > best:
            return
        at, best = nxt, got


def _displaced_candidates(images: list[GeometryImage], surface: _Surface, reference, max_bytes: int, tried: list,
                          say: Callable[[str], None]) -> list[tuple]:
    """Displaced files (:mod:`geoimg.image._displacement`) within ``max_bytes``: each image of at least
    :data:`DISPLACED_FROM` pixels a side on each smaller one of 1/2 and 1/4 its side, the base coded in the
    shares of the budget that :func:`_walk_shares` tries; each decoded and measured, its figures added to
    ``tried``: ``(candidate, full, base, share)`` each.
    """
    out: list[tuple] = []
    for full in images:
        n = full.shape[0]
        if n < DISPLACED_FROM or not full.valid.all():
            continue
        for base in images:
            if (base.shape[0] not in ((n - 1) // 2 + 1, (n - 1) // 4 + 1) or base.domain != full.domain
                    or not base.valid.all()):
                continue
            base = dataclasses.replace(base, mask=None)          # every pixel valid: a displaced file has no mask
            say(f"searching a displaced image at {n} x {full.shape[1]} on {base.shape[0]} x {base.shape[1]}")
            _walk_shares(functools.partial(_measured_displaced, full, base, surface, reference, max_bytes, tried, out))
    return out


def _displaced_for_psnr(images: list[GeometryImage], surface: _Surface, reference, target: float,
                        plain_bytes: int, tried: list, say: Callable[[str], None]) -> list[Compressed]:
    """Displaced files that reach ``target`` dB in fewer bytes than the plain file's ``plain_bytes``: the
    displaced search at that size, then the budget of its best candidate's image, base and share bisected
    down to a 50th of it (:data:`PSNR_BUDGET_STEPS` steps at most). Those that reach ``target``.
    """
    probes = _displaced_candidates(images, surface, reference, plain_bytes, tried, say)
    reaching = [c for c, *_ in probes if c.psnr_db >= target]
    if not reaching:
        return []
    _, full, base, share = max(probes, key=lambda p: p[0].psnr_db)
    lo, hi = plain_bytes // 4, min(c.nbytes for c in reaching)
    say(f"searching the fewest bytes of a displaced image at {full.shape[0]} x {full.shape[1]} on "
        f"{base.shape[0]} x {base.shape[1]}")
    for _ in range(PSNR_BUDGET_STEPS):
        if hi - lo <= plain_bytes // 50:
            break
        mid = (lo + hi) // 2
        out: list = []
        if _measured_displaced(full, base, surface, reference, mid, tried, out, share) >= target:
            reaching.append(out[0][0])
            hi = out[0][0].nbytes
        else:
            lo = mid
    return reaching


def _level_for_psnr(image: GeometryImage, reference, target: float,
                    channels: dict) -> tuple[float, bytes, float] | float:
    """The lowest level whose decoded shape reaches ``target`` dB, its file and PSNR; or the best PSNR this
    image can reach (lossless), when that falls short.
    """
    lossless = encode(image, LOSSLESS, **channels)
    top = _error_db(reference, decode(lossless))
    if top < target:
        return top
    lo, hi = LEVELS
    best: tuple[float, bytes, float] = (float(LOSSLESS), lossless, top)
    for _ in range(SEARCH_STEPS):
        mid = 0.5 * (lo + hi)
        data = encode(image, mid, **channels)
        got = _error_db(reference, decode(data))
        if got >= target:
            hi = mid
            if len(data) < len(best[1]):
                best = (mid, data, got)
        else:
            lo = mid
    return best


@fixed_order
def compress(source: Any, path: Any = None, *, max_bytes: int | None = None, psnr: float | None = None,
             resolutions: Any = None, colors: bool = False, normals: bool = False, overwrite: bool = False,
             progress: Progress | None = None) -> Compressed:
    """Compress a shape into a JPEG 2000 geometry image of at most ``max_bytes`` bytes with the least error,
    or of the fewest bytes that reach ``psnr`` dB.

    A mesh is converted (the faithful default, one map: the prefilter or the mesh resampled as it is,
    whichever lies closer, as ``geoimg image`` does) at each of ``resolutions``; masked pixels are set to the
    smooth continuation of the valid ones (:func:`geoimg.image._jp2.continue_masked`); for each the coder's
    rate is searched (bisection on its target PSNR; lossless when that fits), and every candidate is decoded
    and measured against the mesh (exact two-sided RMS; PSNR = 20 log10(diagonal / RMS)): the best is kept.
    With a byte budget, a mesh is also tried as *displaced* files (:mod:`geoimg.image._displacement`: each
    image of at least :data:`DISPLACED_FROM` a side on a base of 1/2 and of 1/4 its side, coded in 40 % and
    50 % of the budget and on in steps of 10 % while that gains, and one channel of offsets along the base's
    normals for the rest), which at low rates hold 1-9 dB more; the best of them is tried again with its
    offsets fitted to the mesh in least squares (:mod:`geoimg._offset_fit`, each of its ``BENDINGS``). With a
    PSNR target, the plain files' search comes first; then the displaced search at the plain file's size, and
    the budget of its best candidate bisected down (its offsets where each line meets the mesh). An image is
    coded at its own size and measured against its own pixels.

    Parameters
    ----------
    source : Mesh, GeometryImage or path-like
        The shape: a mesh (or mesh file), or a geometry image (or image file).
    path : path-like, optional
        Write the ``.jp2`` file here (atomically).
    max_bytes : int, optional
        The budget: the file is at most this many bytes.
    psnr : float, optional
        The error to reach instead, in dB.
    resolutions : sequence of int, optional
        The sides to try for a mesh (default :data:`DEFAULT_RESOLUTIONS`).
    colors : bool, default False
        Also code the shape's colours (a textured or coloured mesh's, or the image's), within the same
        budget: three more channels at the coder's level.
    normals : bool, default False
        Also code the surface's exact normals (two more channels, their octahedral encoding), within the same
        budget; without them a reader computes normals from the decoded grid.
    overwrite : bool
        Replace an existing file.
    progress : callable, optional
        Called with a short message at each stage.

    Returns
    -------
    Compressed
        The file's bytes, the decoded image, the resolution, the level, the PSNR and every candidate's figures.

    Raises
    ------
    InputError
        Neither or both targets, a budget below what any image takes (the message says the least that works), a
        PSNR no candidate reaches.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
    >>> c = compress(ball, max_bytes=1500)
    >>> c.nbytes <= 1500, c.psnr_db > 50
    (True, True)
    """
    _check_target(max_bytes, psnr)
    if path is not None:
        path = Path(path)
        if path.suffix.lower() != ".jp2":
            raise InputError(f"{path}: compressed geometry images are JPEG 2000 files; use a .jp2 name")
        if path.exists() and not overwrite:
            raise FileExistsError(f"{path} exists (overwrite to replace it)")
    images, reference = _candidates(source, resolutions, progress)
    if isinstance(source, (str, Path)) and isinstance(reference, Mesh):
        for image in images:
            image.metadata["source"] = Path(source).name
    mesh = reference if isinstance(reference, Mesh) else None
    if mesh is not None:                         # the mesh's samples and tree, made once for every candidate
        reference = ReferenceDistances(mesh, SAMPLES)
    say = progress or (lambda message: None)
    channels = {"colors": bool(colors), "normals": bool(normals)}
    tried: list[dict] = []
    found: list[Compressed] = []
    for image in images:
        n = image.shape[0]
        say(f"searching the rate at {n} x {image.shape[1]}")
        if max_bytes is not None:
            got = _level_for_bytes(image, int(max_bytes), channels)
            if isinstance(got, int):
                tried.append({"resolution": n, "least_bytes": got})
                continue
            level, data = got
            decoded = decode(data)
            db = _error_db(reference, decoded)
        else:
            got2 = _level_for_psnr(image, reference, float(psnr or 0.0), channels)
            if isinstance(got2, float):
                tried.append({"resolution": n, "best_psnr_db": round(got2, 2)})
                continue
            level, data, db = got2
            decoded = decode(data)
        tried.append({"resolution": n, "bytes": len(data), "psnr_db": round(db, 2), "level": round(level, 2)})
        found.append(Compressed(data, decoded, n, float(level), float(db)))
    if mesh is not None and not (colors or normals):
        surface = _Surface(mesh)                 # its tree built at the first displaced candidate, if any
        if max_bytes is not None:
            displaced = _displaced_candidates(images, surface, reference, int(max_bytes), tried, say)
            found += [c for c, *_ in displaced]
            if displaced:            # the best again with its offsets fitted to the mesh: kept where it is closer
                _, full, base, share = max(displaced, key=lambda d: d[0].psnr_db)
                say(f"fitting the offsets of the best displaced image ({full.shape[0]} on {base.shape[0]})")
                refit: list[tuple] = []
                _measured_displaced(full, base, surface, reference, int(max_bytes), tried, refit, share, BENDINGS)
                found += [c for c, *_ in refit]
        elif found:
            found += _displaced_for_psnr(images, surface, reference, float(psnr or 0.0),
                                         min(c.nbytes for c in found), tried, say)
    if not found:
        if max_bytes is not None:
            smallest = min(tried, key=lambda t: t["least_bytes"])
            raise InputError(f"max_bytes: {max_bytes} bytes hold no geometry image of this shape; the least that "
                             f"works is {smallest['least_bytes']} bytes (at {smallest['resolution']} x "
                             f"{smallest['resolution']})")
        best_db = max(t["best_psnr_db"] for t in tried)
        raise InputError(f"psnr: no image of the sizes tried reaches {psnr} dB (the best, lossless, "
                         f"{best_db} dB); try a larger resolution")
    # the least error within the budget, or the fewest bytes that reach the error (ties: the first, smallest side)
    best = max(found, key=(lambda c: (c.psnr_db, -c.nbytes)) if max_bytes is not None else
               (lambda c: (-c.nbytes, c.psnr_db)))
    if path is not None:
        with atomic_path(path, overwrite) as tmp:
            tmp.write_bytes(best.data)
    return Compressed(best.data, best.image, best.resolution, best.level, best.psnr_db, tried, best.base)
