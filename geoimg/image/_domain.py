"""Domains: what differs between kinds of geometry image.

A :class:`Domain` owns the image grid's relation to the parameter space (which parameter point each
pixel samples), the boundary rules that filters use at the image's edges, the glue map (which pixels
are the same point of the surface), mask symmetrization, averaging of glued pixels and the welding
of glued pixels into one vertex of the quad mesh. Code outside this module asks the domain; it never
tests a domain's name. A new kind of geometry image is a new subclass here.

Kinds: :class:`PlanarDomain` (a parameter rectangle; nothing glued) and :class:`OctahedralDomain`
(the unit sphere unfolded onto an odd square whose sides are glued to themselves).
"""
from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.sparse.csgraph import connected_components

import filters
from ..errors import GeoimgError, ImageError
from ..mesh import Mesh
from ..parametrization import grid_directions, perimeter_point
from ..parametrization._octahedral import check_size, glued_groups, group_means

__all__ = ["Domain", "PlanarDomain", "OctahedralDomain", "CutDomain", "grid_normals", "DOMAIN_KINDS"]

DOMAIN_KINDS: dict = {}      # kind name -> Domain subclass, filled as subclasses are defined


def grid_normals(pixels: np.ndarray, orientation: int = 1) -> np.ndarray:
    """Unit normals of a geometry image from central differences of the grid (one-sided at the edges).

    Parameters
    ----------
    pixels : numpy.ndarray
        (H, W, 3) positions.
    orientation : int
        +1 or -1: the sign of ``P_u x P_v``.

    Returns
    -------
    numpy.ndarray
        (H, W, 3) unit normals (float32 for float32 pixels).

    Examples
    --------
    >>> u, v = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 3))
    >>> img = np.stack([u, v, 0 * u], axis=-1)
    >>> grid_normals(img)[1, 1].tolist()
    [0.0, 0.0, 1.0]
    """
    p = np.asarray(pixels, dtype=np.float64)
    pv, pu = np.gradient(p, axis=(0, 1))
    n = np.cross(pu, pv) * orientation
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)


@functools.lru_cache(maxsize=8)
def _glue_of(domain: Domain, shape: tuple) -> tuple[np.ndarray, np.ndarray] | None:
    """A domain's glue for one image size, made once: sampling, each filter and the quad mesh ask again."""
    glue = domain._make_glue(shape)
    if glue is not None:
        for a in glue:
            a.setflags(write=False)
    return glue


def _check_orientation(value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or int(value) not in (-1, 1):
        raise ImageError(f"orientation: expected +1 or -1, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Domain(ABC):
    """The kind of a geometry image and everything that depends on it (see the module's description).

    Parameters
    ----------
    orientation : int
        +1 when ``dP/du x dP/dv`` (u along columns, v along rows) points along the mesh's face normals,
        else -1: quads of the quad mesh are wound to match.

    Attributes
    ----------
    kind : str (class attribute)
        The name written to files (``geoimg:domain``).
    boundary : str or None (class attribute)
        The :mod:`filters` boundary rule (``mode=``) for this kind of image: what filters and Fourier
        operations see beyond the image's edges; None when no rule of :mod:`filters` fits and the domain
        pads images itself (:meth:`pad`).
    extension : str (class attribute)
        The rule that continues the surface smoothly beyond the edges, for derivatives and
        interpolation (curvature from the grid, resizing).
    parameter_dim : int (class attribute)
        2 for (u, v) in a rectangle, 3 for unit directions on the sphere.
    rotations : bool (class attribute)
        Whether the parameter space can turn onto itself (the sphere), so that two images can be
        aligned by a rotation of it.

    Examples
    --------
    >>> Domain.named("octahedral")
    OctahedralDomain(orientation=1)
    """

    orientation: int = 1

    kind: ClassVar[str] = ""
    boundary: ClassVar[str | None] = "reflect"
    extension: ClassVar[str] = "linear"
    parameter_dim: ClassVar[int] = 2
    rotations: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.kind:
            DOMAIN_KINDS[cls.kind] = cls

    def __post_init__(self):
        object.__setattr__(self, "orientation", _check_orientation(self.orientation))

    # ------------------------------------------------------------------ naming and files
    @staticmethod
    def named(kind: str, **fields) -> Domain:
        """The domain of a kind name (``"planar"``, ``"octahedral"``) with the given fields.

        Examples
        --------
        >>> Domain.named("planar", extent=(1.0, 0.5))
        PlanarDomain(orientation=1, extent=(1.0, 0.5))
        """
        if kind not in DOMAIN_KINDS:
            raise ImageError(f"domain: expected one of {tuple(DOMAIN_KINDS)}, got {kind!r}")
        return DOMAIN_KINDS[kind](**fields)

    @classmethod
    def from_metadata(cls, kind: str, metadata: dict) -> Domain:
        """The domain recorded in a file's metadata (keys ``orientation``, ``extent``); missing keys take
        their defaults.
        """
        if kind not in DOMAIN_KINDS:
            raise ImageError(f"domain: expected one of {tuple(DOMAIN_KINDS)}, got {kind!r}")
        return DOMAIN_KINDS[kind]._from_fields(metadata)

    @classmethod
    def _from_fields(cls, metadata: dict) -> Domain:
        return cls(orientation=metadata.get("orientation", 1))

    def to_metadata(self) -> dict:
        """The fields to record in a file (JSON types), read back by :meth:`from_metadata`."""
        return {"domain": self.kind, "extent": [float(e) for e in self.extent], "orientation": self.orientation}

    METADATA_KEYS: ClassVar[tuple] = ("domain", "extent", "orientation")

    def same_kind(self, other: Domain) -> bool:
        """Whether two images are of the same kind (and so can be blended pixel for pixel)."""
        return type(self) is type(other)

    # ------------------------------------------------------------------ grid and parameters
    @property
    def extent(self) -> tuple:
        """Size of the parameter rectangle the image spans (the longer side 1)."""
        return (1.0, 1.0)

    @abstractmethod
    def check_shape(self, shape: tuple[int, int]) -> None:
        """Raise :class:`~geoimg.GeoimgError` when an image of ``shape`` (H, W) cannot be of this domain."""

    def check_mask(self, mask: np.ndarray | None) -> None:  # noqa: B027   (a hook: any mask, unless a kind says)
        """Raise when a validity mask cannot belong to an image of this domain."""

    @abstractmethod
    def grid_shape(self, resolution: int) -> tuple[int, int]:
        """(H, W) of an image with ``resolution`` pixels along its longer side."""

    def round_resolution(self, resolution: int) -> int:
        """The nearest resolution at or above ``resolution`` that this kind of image can have."""
        return int(resolution)

    def size_rule(self) -> str:
        """Which sizes this kind of image can have, in words."""
        return "any size"

    def pixel_uv(self, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """Image coordinates of the columns (u) and rows (v), from 0 to the extent."""
        h, w = shape
        return np.linspace(0.0, self.extent[0], w), np.linspace(0.0, self.extent[1], h)

    def parameter_points(self, shape: tuple[int, int]) -> np.ndarray:
        """The parameter of every pixel, row by row, in the space of a parametrization's ``coords``:
        (H * W, 2) image coordinates (u, v) here.
        """
        u, v = self.pixel_uv(shape)
        uu, vv = np.meshgrid(u, v)
        return np.stack([uu.ravel(), vv.ravel()], axis=1)

    # ------------------------------------------------------------------ glue
    def glue(self, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray] | None:
        """Groups of pixels that are one point of the surface: each group's first pixel (flat index) and
        each pixel's group number (read-only, kept for the next call), or None when no pixels are glued.
        """
        return _glue_of(self, (int(shape[0]), int(shape[1])))

    def _make_glue(self, shape) -> tuple[np.ndarray, np.ndarray] | None:
        """What :meth:`glue` returns, computed (a kind that glues pixels says which)."""
        return None

    def average_glued(self, pixels: np.ndarray) -> np.ndarray:
        """Each group of glued pixels replaced by its mean (the input when nothing is glued)."""
        a = np.asarray(pixels)
        glue = self.glue(a.shape[:2])
        if glue is None:
            return a
        group = glue[1]
        return group_means(a, group)[group].reshape(a.shape).astype(a.dtype)

    def symmetric_mask(self, weights: np.ndarray) -> np.ndarray:
        """The largest weight of each group of glued pixels, given to all of them."""
        w = np.asarray(weights, dtype=np.float64)
        glue = self.glue(w.shape)
        if glue is None:
            return w
        group = glue[1]
        best = np.zeros(len(glue[0]))
        np.maximum.at(best, group, w.ravel())
        return best[group].reshape(w.shape)

    # ------------------------------------------------------------------ boundary
    def pad(self, array: np.ndarray, width: int) -> np.ndarray:
        """``array`` (H, W[, C]) padded by ``width`` pixels on each side with the domain's boundary rule (a
        kind without a :mod:`filters` rule pads itself).
        """
        assert self.boundary is not None, f"{self.kind}: a domain without a filters rule overrides pad"
        return filters.pad(array, width, self.boundary)

    def estimate_normals(self, pixels: np.ndarray) -> np.ndarray | None:
        """Normals from the grid for a quad mesh, where the image carries no exact ones (None: none)."""
        return grid_normals(pixels, self.orientation)

    def ghosts(self, centres: np.ndarray, reach: np.ndarray) -> list:
        """Faces that a surface over this domain sees beyond the image's edges, as
        ``(face indices, R (2, 2), b (2,))``: copies of those faces (by their parametric ``centres``
        (F, 2)) with parameters ``R uv + b``, for faces whose weights reach an edge within ``reach`` (F,).
        None for a domain whose edges are the surface's own.
        """
        return []

    # ------------------------------------------------------------------ quad mesh
    def quad_mesh(self, pixels: np.ndarray, valid: np.ndarray, normals: np.ndarray | None,
                  colors: np.ndarray | None = None) -> Mesh:
        """The regular quad mesh of an image: a quad per 2 x 2 block of valid pixels, a vertex per group of
        glued pixels that a quad uses (welded by index; its position the group's mean), wound by
        :attr:`orientation`. Vertices carry their pixel's image coordinates and a normal; with ``colors``
        (H, W, C) also the group's mean colour, and the mesh gets the colours as its texture, each quad
        corner the texture coordinates of its own pixel's centre.

        Raises
        ------
        GeoimgError
            If no 2 x 2 block of valid pixels exists.
        """
        H, W = valid.shape
        keep = valid[:-1, :-1] & valid[:-1, 1:] & valid[1:, 1:] & valid[1:, :-1]
        if not keep.any():
            raise GeoimgError("to_mesh: the image has no 2 x 2 block of valid pixels, so no quad")
        glue = self.glue((H, W))
        reps, group = (np.arange(H * W), np.arange(H * W)) if glue is None else glue
        used = np.zeros((H, W), bool)
        used[:-1, :-1] |= keep
        used[:-1, 1:] |= keep
        used[1:, 1:] |= keep
        used[1:, :-1] |= keep
        group_used = np.zeros(len(reps), bool)
        group_used[group[used.ravel()]] = True
        index = np.full(len(reps), -1, np.int64)
        index[group_used] = np.arange(int(group_used.sum()))
        grid = index[group].reshape(H, W)
        pixel = np.arange(H * W).reshape(H, W)
        corner_pixels = np.stack([pixel[:-1, :-1][keep], pixel[:-1, 1:][keep], pixel[1:, 1:][keep],
                                  pixel[1:, :-1][keep]], axis=1)
        if self.orientation < 0:
            corner_pixels = corner_pixels[:, ::-1]
        quads = grid.ravel()[corner_pixels]
        u, v = self.pixel_uv((H, W))
        uu, vv = np.meshgrid(u, v)
        uv = np.stack([uu.ravel(), vv.ravel()], axis=1)[reps[group_used]]
        if normals is None:
            normals = self.estimate_normals(pixels)
        if glue is None:
            flat = used.ravel()
            xyz = np.asarray(pixels, np.float64).reshape(-1, 3)[flat]
            nrm = None if normals is None else np.asarray(normals, np.float64).reshape(-1, 3)[flat]
        else:
            xyz = group_means(pixels, group)[group_used]
            nrm = None
            if normals is not None:
                nrm = group_means(normals, group)[group_used]
                nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
        if colors is None:
            return Mesh(xyz, quads, uv=uv, normals=nrm)
        rows, cols = np.divmod(corner_pixels, W)                # OBJ's texture coordinates: (0, 0) bottom-left
        face_uv = np.stack([(cols + 0.5) / W, 1.0 - (rows + 0.5) / H], axis=-1)
        rgb = np.asarray(colors, np.float64)
        rgb = rgb.reshape(H * W, -1)[used.ravel()] if glue is None else group_means(rgb, group)[group_used]
        texture = np.round(np.clip(colors, 0, 1) * 255).astype(np.uint8)
        return Mesh(xyz, quads, uv=uv, normals=nrm, colors=np.clip(rgb, 0, 1), face_uv=face_uv, texture=texture)


@dataclass(frozen=True)
class PlanarDomain(Domain):
    """A parameter rectangle ``[0, extent[0]] x [0, extent[1]]``, u along columns and v along rows.

    Nothing is glued; filters reflect at the edges (``mode="linear"`` keeps a border in place), and
    derivatives continue the surface linearly. Pixels outside the parametrized region are masked.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    extent : tuple of float
        The parameter rectangle's width and height (the longer side 1).

    Examples
    --------
    >>> d = PlanarDomain(extent=(1.0, 0.5))
    >>> d.grid_shape(5), d.glue((3, 5)) is None
    ((3, 5), True)
    """

    extent: tuple = (1.0, 1.0)

    kind: ClassVar[str] = "planar"

    def __post_init__(self):
        super().__post_init__()
        try:
            ext = tuple(float(e) for e in self.extent)
        except (TypeError, ValueError):
            raise ImageError(f"extent: expected two positive numbers, got {self.extent!r}") from None
        if len(ext) != 2 or not all(np.isfinite(e) and e > 0 for e in ext):
            raise ImageError(f"extent: expected two positive finite numbers, got {self.extent!r}")
        object.__setattr__(self, "extent", ext)

    @classmethod
    def _from_fields(cls, metadata: dict) -> PlanarDomain:
        return cls(orientation=metadata.get("orientation", 1), extent=tuple(metadata.get("extent", (1.0, 1.0))))

    def check_shape(self, shape: tuple[int, int]) -> None:
        pass

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        """The shorter side gets the count that keeps pixels nearly square; corners sit on the rectangle's
        corners (spacing ``extent / (count - 1)``, as the paper's increments of 1/255 for 256 samples).
        """
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ImageError(f"resolution: expected an integer >= 2, got {resolution!r}")
        big = max(self.extent)
        w, h = (max(2, int(round((resolution - 1) * e / big)) + 1) for e in self.extent)
        return h, w


@dataclass(frozen=True)
class OctahedralDomain(Domain):
    """The unit sphere unfolded onto an odd ``N x N`` square by the octahedral map (Praun & Hoppe 2003).

    Each side of the square is glued to itself, mirrored about its midpoint, and the four corners are
    one point (see :mod:`geoimg.parametrization._octahedral`): filters continue across the sides by a
    half-turn, glued pixels are averaged after a filter, and the quad mesh welds them by index into a
    closed genus-0 surface. The image covers the whole sphere, so it takes no mask.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).

    Examples
    --------
    >>> d = OctahedralDomain()
    >>> reps, group = d.glue((5, 5))
    >>> len(reps), int(group[4]), int(group[24])     # the corners are one point
    (18, 0, 0)
    """

    kind: ClassVar[str] = "octahedral"
    boundary: ClassVar[str] = "octahedral"
    extension: ClassVar[str] = "octahedral"
    parameter_dim: ClassVar[int] = 3
    rotations: ClassVar[bool] = True

    def check_shape(self, shape: tuple[int, int]) -> None:
        if shape[0] != shape[1]:
            raise ImageError(f"pixels: an octahedral image must be square, got {tuple(shape)}")
        check_size(shape[0])

    def check_mask(self, mask: ArrayLike | None) -> None:
        if mask is not None and not np.all(mask):
            raise ImageError("mask: an octahedral image covers the whole sphere; it takes no mask")

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        n = check_size(resolution)
        return n, n

    def round_resolution(self, resolution: int) -> int:
        return int(resolution) + 1 - int(resolution) % 2

    def size_rule(self) -> str:
        return "an octahedral image has an odd side (its glued sides pair up pixel for pixel)"

    def directions(self, n: int) -> np.ndarray:
        """Unit directions (n, n, 3) of the pixels, computed so that glued pixels get identical ones."""
        return grid_directions(n)

    def parameter_points(self, shape: tuple[int, int]) -> np.ndarray:
        """The pixels' unit directions on the sphere, (H * W, 3)."""
        self.check_shape(shape)
        return self.directions(shape[0]).reshape(-1, 3)

    def _make_glue(self, shape):
        self.check_shape(shape)
        return glued_groups(shape[0])

    def estimate_normals(self, pixels: ArrayLike) -> np.ndarray | None:
        return None


@dataclass(frozen=True)
class CutDomain(Domain):
    """The unit square whose boundary is glued to itself along a cut (Gu, Gortler & Hoppe 2002): the
    image of a mesh of any genus and any number of boundary loops, cut open into one disk (see
    :mod:`geoimg.parametrization._cut`).

    The perimeter, counter-clockwise from pixel (0, 0) along row 0, is laid out in ``4 * quantum``
    quanta: ``segments`` are ``(start, length, twin)`` in quanta, ``twin`` the segment on the other side
    of the cut (-1: the mesh's own boundary, left open). Offset ``j`` along a segment is offset
    ``length - j`` along its twin, so on an ``N x N`` image with ``N - 1`` a multiple of ``quantum`` every
    boundary pixel on one side of a cut has an exact twin. Twins are glued (averaged after filters, welded
    in the quad mesh, which then has the mesh's genus and boundary loops), and filters see across a cut
    the twin's side of it.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    quantum : int
        Quanta per side of the square; an image's ``N - 1`` is a multiple of it.
    segments : tuple
        ``(start, length, twin)`` of each perimeter segment, in quanta.

    Examples
    --------
    >>> d = CutDomain(quantum=4, segments=((0, 4, 2), (4, 4, 3), (8, 4, 0), (12, 4, 1)))   # a torus
    >>> reps, group = d.glue((5, 5))
    >>> len(reps), int(group[0]) == int(group[4]) == int(group[20]) == int(group[24])    # 4 x 4 quads + 0
    (16, True)
    """

    quantum: int = 64
    segments: tuple = ()

    kind: ClassVar[str] = "cut"
    boundary: ClassVar[str | None] = None        # no filters rule: the domain pads itself (pad)

    def __post_init__(self):
        super().__post_init__()
        q = self.quantum
        if isinstance(q, bool) or not isinstance(q, (int, np.integer)) or q < 1:
            raise ImageError(f"quantum: expected a positive integer, got {q!r}")
        try:
            segs = tuple((int(a), int(n), int(t)) for a, n, t in self.segments)
        except (TypeError, ValueError):
            raise ImageError(f"segments: expected (start, length, twin) triples, got {self.segments!r:.80}") from None
        total = 4 * int(q)
        ok = len(segs) > 0 and segs[0][0] == 0 and all(n >= 1 for _, n, _ in segs) \
            and all(a + n == b for (a, n, _), (b, _, _) in zip(segs, segs[1:])) and segs[-1][0] + segs[-1][1] == total
        ok = ok and all(t == -1 or (0 <= t < len(segs) and segs[t][2] == i and segs[t][1] == n)
                        for i, (_, n, t) in enumerate(segs))
        if not ok:
            raise ImageError("segments: expected consecutive (start, length, twin) segments from 0 around the "
                             f"{total} quanta of the perimeter, twins of equal length naming each other")
        object.__setattr__(self, "quantum", int(q))
        object.__setattr__(self, "segments", segs)

    @classmethod
    def _from_fields(cls, metadata: dict) -> CutDomain:
        return cls(orientation=metadata.get("orientation", 1), quantum=metadata.get("quantum", 64),
                   segments=tuple(tuple(s) for s in metadata.get("segments", ())))

    def to_metadata(self) -> dict:
        return {**super().to_metadata(), "quantum": self.quantum, "segments": [list(s) for s in self.segments]}

    METADATA_KEYS: ClassVar[tuple] = Domain.METADATA_KEYS + ("quantum", "segments")

    def same_kind(self, other: Domain) -> bool:
        """Cut-open images pair up pixel for pixel only when their cuts are laid out alike (the same mesh's
        faces, or the same layout).
        """
        return type(self) is type(other) and (self.quantum, self.segments) == (other.quantum, other.segments)

    def check_shape(self, shape: tuple[int, int]) -> None:
        h, w = shape
        if h != w or (h - 1) % self.quantum:
            raise ImageError(f"pixels: a cut-open image is N x N with N - 1 a multiple of {self.quantum} (so that "
                             f"the two sides of the cut pair up pixel for pixel, e.g. "
                             f"{self.round_resolution(max(h, w))}), got {h} x {w}")

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ImageError(f"resolution: expected an integer >= 2, got {resolution!r}")
        self.check_shape((resolution, resolution))
        return int(resolution), int(resolution)

    def round_resolution(self, resolution: int) -> int:
        q = self.quantum
        return int(-(-(max(int(resolution), 2) - 1) // q) * q + 1)

    def size_rule(self) -> str:
        return (f"a cut-open image is N x N with N - 1 a multiple of {self.quantum} (the two sides of the cut pair "
                "up pixel for pixel)")

    def _perimeter_pixels(self, n: int) -> np.ndarray:
        """Flat pixel index of each perimeter position 0 .. 4 (n - 1) (the last one is pixel 0 again)."""
        m = n - 1
        t = np.arange(4 * m + 1)
        side, f = np.minimum(t // m, 3), t - np.minimum(t // m, 3) * m
        row = np.choose(side, [np.zeros_like(f), f, np.full_like(f, m), m - f])
        col = np.choose(side, [f, np.full_like(f, m), m - f, np.zeros_like(f)])
        return row * n + col

    def _twin_pairs(self, n: int):
        """Perimeter positions ``(p, p')`` of twin pixels (both directions), in pixels."""
        scale = (n - 1) // self.quantum
        ps, qs = [], []
        for a, length, t in self.segments:
            if t < 0:
                continue
            j = np.arange(length * scale + 1)
            ps.append(a * scale + j)
            qs.append(self.segments[t][0] * scale + length * scale - j)
        if not ps:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        return np.concatenate(ps), np.concatenate(qs)

    def _make_glue(self, shape):
        self.check_shape(shape)
        n = shape[0]
        per = self._perimeter_pixels(n)
        p, q = self._twin_pairs(n)
        rows, cols = per[p], per[q]
        graph = sparse.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n * n, n * n))
        _, label = connected_components(graph, directed=False)
        first = np.full(label.max() + 1, n * n, np.int64)
        np.minimum.at(first, label, np.arange(n * n))
        return np.unique(first[label], return_inverse=True)

    def _pieces(self):
        """Straight pieces of the twinned segments: ``(a, b, a', b')`` perimeter positions (quanta) of a
        piece on one side of a cut and of its twin on the other (``a`` pairs with ``a'``).
        """
        q = self.quantum
        corners = np.arange(0, 4 * q + 1, q)
        out = []
        for start, length, t in self.segments:
            if t < 0:
                continue
            tstart = self.segments[t][0]
            cuts = {0, length}
            cuts.update(int(c - start) for c in corners if start < c < start + length)
            cuts.update(int(tstart + length - c) for c in corners if tstart < c < tstart + length)
            cuts = sorted(cuts)
            for o1, o2 in zip(cuts[:-1], cuts[1:]):
                out.append((start + o1, start + o2, tstart + length - o1, tstart + length - o2))
        return out

    def ghosts(self, centres: np.ndarray, reach: np.ndarray) -> list:
        """Across each cut, the faces near its other side, turned and moved rigidly onto this side's
        outside: the weighted mean at a cut then sees the surface continue, as inside. Each face goes
        with the straight piece of a cut nearest to it, if its weights reach that far.
        """
        c = np.asarray(centres, np.float64)
        reach = np.minimum(np.asarray(reach, np.float64), 0.5)
        pieces = self._pieces()
        if not pieces:
            return []
        dist = np.empty((len(pieces), len(c)))
        maps = []
        for k, (a, b, ta, tb) in enumerate(pieces):
            (p0, p1), (q0, q1) = perimeter_point([a, b], self.quantum), perimeter_point([ta, tb], self.quantum)
            ds, dt = p1 - p0, q1 - q0
            length2 = float(dt @ dt)
            along = np.clip((c - q0) @ dt / max(length2, 1e-300), 0.0, 1.0)
            dist[k] = np.linalg.norm(c - (q0 + along[:, None] * dt), axis=1)    # to the twin piece
            cos, sin = (dt @ ds) / max(length2, 1e-300), (dt[0] * ds[1] - dt[1] * ds[0]) / max(length2, 1e-300)
            R = np.array([[cos, -sin], [sin, cos]])
            maps.append((R, p0 - R @ q0))
        nearest = np.argmin(dist, axis=0)
        out = []
        for k, (R, b) in enumerate(maps):
            take = np.flatnonzero((nearest == k) & (dist[k] < reach))
            if len(take):
                out.append((take, R, b))
        return out

    def pad(self, array: np.ndarray, width: int) -> np.ndarray:
        """Reflected at the mesh's own boundary; across a cut, the pixels inward of the twin, so a filter
        sees the surface continue (exact along straight stretches of a side, approximate at the corners).
        """
        a = np.asarray(array)
        out = filters.pad(a, width, "reflect")
        if width == 0:
            return out
        n = a.shape[0]
        m = n - 1
        p, q = self._twin_pairs(n)
        inward = np.array([[1, 0], [0, -1], [-1, 0], [0, 1]])     # (row, col) steps into the image, by side
        per = self._perimeter_pixels(n)
        side_p, side_q = np.minimum(p // m, 3), np.minimum(q // m, 3)
        keep = (p % m != 0) & (q % m != 0)          # corners have two sides: leave them reflected
        p, q, side_p, side_q = p[keep], q[keep], side_p[keep], side_q[keep]
        rp, cp = per[p] // n, per[p] % n
        rq, cq = per[q] // n, per[q] % n
        for k in range(1, width + 1):
            src_r = np.clip(rq + k * inward[side_q, 0], 0, m)
            src_c = np.clip(cq + k * inward[side_q, 1], 0, m)
            dst_r = rp - k * inward[side_p, 0] + width
            dst_c = cp - k * inward[side_p, 1] + width
            out[dst_r, dst_c] = a[src_r, src_c]
        return out
