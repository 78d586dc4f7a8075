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

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

import filters
from ..errors import GeoimgError, ImageError
from ..mesh import Mesh
from ..parametrization import grid_directions
from ..parametrization._octahedral import check_size, glued_groups, group_means

__all__ = ["Domain", "PlanarDomain", "OctahedralDomain", "grid_normals", "DOMAIN_KINDS"]

DOMAIN_KINDS: dict = {}      # kind name -> Domain subclass, filled as subclasses are defined


def grid_normals(pixels: np.ndarray, orientation: int = 1) -> np.ndarray:
    """Unit normals of a geometry image from central differences of the grid (one-sided at the edges).

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


def _check_orientation(value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or int(value) not in (-1, 1):
        raise ImageError(f"orientation: expected +1 or -1, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Domain(ABC):
    """The kind of a geometry image and everything that depends on it (see the module's description).

    Attributes
    ----------
    orientation : int
        +1 when ``dP/du x dP/dv`` (u along columns, v along rows) points along the mesh's face normals,
        else -1: quads of the quad mesh are wound to match.
    kind : str (class attribute)
        The name written to files (``geoimg:domain``).
    boundary : str (class attribute)
        The :mod:`filters` boundary rule (``mode=``) for this kind of image: what filters and Fourier
        operations see beyond the image's edges.
    extension : str (class attribute)
        The rule that continues the surface smoothly beyond the edges, for derivatives and
        interpolation (curvature from the grid, resizing).
    parameter_dim : int (class attribute)
        2 for (u, v) in a rectangle, 3 for unit directions on the sphere.
    rotations : bool (class attribute)
        Whether the parameter space can turn onto itself (the sphere), so that two images can be
        aligned by a rotation of it.
    """

    orientation: int = 1

    kind: ClassVar[str] = ""
    boundary: ClassVar[str] = "reflect"
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
    def named(kind: str, **fields) -> "Domain":
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
    def from_metadata(cls, kind: str, metadata: dict) -> "Domain":
        """The domain recorded in a file's metadata (keys ``orientation``, ``extent``); missing keys take
        their defaults."""
        if kind not in DOMAIN_KINDS:
            raise ImageError(f"domain: expected one of {tuple(DOMAIN_KINDS)}, got {kind!r}")
        return DOMAIN_KINDS[kind]._from_fields(metadata)

    @classmethod
    def _from_fields(cls, metadata: dict) -> "Domain":
        return cls(orientation=metadata.get("orientation", 1))

    def to_metadata(self) -> dict:
        """The fields to record in a file (JSON types), read back by :meth:`from_metadata`."""
        return {"domain": self.kind, "extent": [float(e) for e in self.extent], "orientation": self.orientation}

    METADATA_KEYS: ClassVar[tuple] = ("domain", "extent", "orientation")

    def same_kind(self, other: "Domain") -> bool:
        """Whether two images are of the same kind (and so can be blended pixel for pixel)."""
        return type(self) is type(other)

    # ------------------------------------------------------------------ grid and parameters
    @property
    def extent(self) -> tuple:
        """Size of the parameter rectangle the image spans (the longer side 1)."""
        return (1.0, 1.0)

    @abstractmethod
    def check_shape(self, shape) -> None:
        """Raise :class:`~geoimg.GeoimgError` when an image of ``shape`` (H, W) cannot be of this domain."""

    def check_mask(self, mask: np.ndarray | None) -> None:
        """Raise when a validity mask cannot belong to an image of this domain."""

    @abstractmethod
    def grid_shape(self, resolution) -> tuple[int, int]:
        """(H, W) of an image with ``resolution`` pixels along its longer side."""

    def pixel_uv(self, shape) -> tuple[np.ndarray, np.ndarray]:
        """Image coordinates of the columns (u) and rows (v), from 0 to the extent."""
        h, w = shape
        return np.linspace(0.0, self.extent[0], w), np.linspace(0.0, self.extent[1], h)

    # ------------------------------------------------------------------ glue
    def glue(self, shape) -> tuple[np.ndarray, np.ndarray] | None:
        """Groups of pixels that are one point of the surface: each group's first pixel (flat index) and
        each pixel's group number, or None when no pixels are glued."""
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
        """``array`` (H, W[, C]) padded by ``width`` pixels on each side with the domain's boundary rule."""
        return filters.pad(array, width, self.boundary)

    def estimate_normals(self, pixels: np.ndarray) -> np.ndarray | None:
        """Normals from the grid for a quad mesh, where the image carries no exact ones (None: none)."""
        return grid_normals(pixels, self.orientation)

    # ------------------------------------------------------------------ quad mesh
    def quad_mesh(self, pixels: np.ndarray, valid: np.ndarray, normals: np.ndarray | None) -> Mesh:
        """The regular quad mesh of an image: a quad per 2 x 2 block of valid pixels, a vertex per group of
        glued pixels that a quad uses (welded by index; its position the group's mean), wound by
        :attr:`orientation`. Vertices carry their pixel's image coordinates and a normal.

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
        quads = np.stack([grid[:-1, :-1][keep], grid[:-1, 1:][keep], grid[1:, 1:][keep], grid[1:, :-1][keep]], axis=1)
        if self.orientation < 0:
            quads = quads[:, ::-1]
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
        return Mesh(xyz, quads, uv=uv, normals=nrm)


@dataclass(frozen=True)
class PlanarDomain(Domain):
    """A parameter rectangle ``[0, extent[0]] x [0, extent[1]]``, u along columns and v along rows.

    Nothing is glued; filters reflect at the edges (``mode="linear"`` keeps a border in place), and
    derivatives continue the surface linearly. Pixels outside the parametrized region are masked.

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
    def _from_fields(cls, metadata: dict) -> "PlanarDomain":
        return cls(orientation=metadata.get("orientation", 1), extent=tuple(metadata.get("extent", (1.0, 1.0))))

    def check_shape(self, shape) -> None:
        pass

    def grid_shape(self, resolution) -> tuple[int, int]:
        """The shorter side gets the count that keeps pixels nearly square; corners sit on the rectangle's
        corners (spacing ``extent / (count - 1)``, as the paper's increments of 1/255 for 256 samples)."""
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

    def check_shape(self, shape) -> None:
        if shape[0] != shape[1]:
            raise ImageError(f"pixels: an octahedral image must be square, got {tuple(shape)}")
        check_size(shape[0])

    def check_mask(self, mask) -> None:
        if mask is not None and not np.all(mask):
            raise ImageError("mask: an octahedral image covers the whole sphere; it takes no mask")

    def grid_shape(self, resolution) -> tuple[int, int]:
        n = check_size(resolution)
        return n, n

    def directions(self, n: int) -> np.ndarray:
        """Unit directions (n, n, 3) of the pixels, computed so that glued pixels get identical ones."""
        return grid_directions(n)

    def glue(self, shape):
        self.check_shape(shape)
        return glued_groups(shape[0])

    def estimate_normals(self, pixels):
        return None
