"""Domains: what differs between kinds of geometry image.

A :class:`Domain` owns the image grid's relation to the parameter space (which parameter point each
pixel samples), the boundary rules that filters use at the image's edges, the glue map (which pixels
are the same point of the surface), mask symmetrization, averaging of glued pixels and the welding
of glued pixels into one vertex of the quad mesh. Code outside this module asks the domain; it never
tests a domain's name. A new kind of geometry image is a new subclass, in a module of its own.

Kinds: :class:`~geoimg.PlanarDomain` (``_planar_domain.py``: a parameter rectangle, nothing glued),
:class:`~geoimg.OctahedralDomain` (``_octahedral_domain.py``: the unit sphere unfolded onto an odd square
whose sides are glued to themselves), :class:`~geoimg.CutDomain` (``_cut_domain.py``: a square glued
along a cut) and :class:`~geoimg.ChartsDomain` (``_charts_domain.py``: squares packed in one image, their
sides glued to each other, the gaps between them masked).
"""
from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

import filters
from ..errors import GeoimgError, ImageError
from ..mesh import Mesh
from ..parametrization._octahedral import group_means

__all__ = ["Domain", "grid_normals", "DOMAIN_KINDS"]

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


@functools.lru_cache(maxsize=8)
def _shared_of(domain: Domain, shape: tuple) -> tuple[np.ndarray, np.ndarray]:
    """The pixels in groups of two or more of a domain's glue (ascending) and their groups renumbered from 0."""
    glue = domain.glue(shape)
    if glue is None:                    # asked only of a domain that glues pixels
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    group = glue[1]
    shared = np.flatnonzero(np.bincount(group)[group] > 1)
    local = np.unique(group[shared], return_inverse=True)[1].ravel()
    for a in (shared, local):
        a.setflags(write=False)
    return shared, local


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
    coverage_only : bool (class attribute)
        Whether only the coverage weights can sample it: the paper's Gaussians reach from one chart across
        the gutter into the next.

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
    coverage_only: ClassVar[bool] = False

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

        Parameters
        ----------
        kind : str
            The kind's name.
        **fields
            The kind's fields (``orientation``, ``extent``, ...).

        Returns
        -------
        Domain
            The domain.

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

        Parameters
        ----------
        kind : str
            The kind's name (``"planar"``, ``"octahedral"``, ``"cut"``).
        metadata : dict
            A file's metadata.

        Examples
        --------
        >>> Domain.from_metadata("planar", {"extent": [1.0, 0.5]})
        PlanarDomain(orientation=1, extent=(1.0, 0.5))
        """
        if kind not in DOMAIN_KINDS:
            raise ImageError(f"domain: expected one of {tuple(DOMAIN_KINDS)}, got {kind!r}")
        return DOMAIN_KINDS[kind]._from_fields(metadata)

    @classmethod
    def _from_fields(cls, metadata: dict) -> Domain:
        return cls(orientation=metadata.get("orientation", 1))

    def to_metadata(self) -> dict:
        """The fields to record in a file (JSON types), read back by :meth:`from_metadata`.

        Returns
        -------
        dict
            The fields by name.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain(extent=(1.0, 0.5)).to_metadata()["extent"]
        [1.0, 0.5]
        """
        return {"domain": self.kind, "extent": [float(e) for e in self.extent], "orientation": self.orientation}

    METADATA_KEYS: ClassVar[tuple] = ("domain", "extent", "orientation")

    def same_kind(self, other: Domain) -> bool:
        """Whether two images are of the same kind (and so can be blended pixel for pixel).

        Parameters
        ----------
        other : Domain
            Another image's domain.

        Returns
        -------
        bool
            Whether they blend pixel for pixel.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> OctahedralDomain().same_kind(PlanarDomain())
        False
        """
        return type(self) is type(other)

    # ------------------------------------------------------------------ grid and parameters
    @property
    def extent(self) -> tuple:
        """Size of the parameter rectangle the image spans (the longer side 1).

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain(extent=(1.0, 0.5)).extent, OctahedralDomain().extent
        ((1.0, 0.5), (1.0, 1.0))
        """
        return (1.0, 1.0)

    @abstractmethod
    def check_shape(self, shape: tuple[int, int]) -> None:
        """Raise :class:`~geoimg.GeoimgError` when an image of ``shape`` (H, W) cannot be of this domain.

        Parameters
        ----------
        shape : tuple of int
            (H, W).

        Raises
        ------
        GeoimgError
            When the size does not fit this kind of image.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> OctahedralDomain().check_shape((5, 5))             # odd and square: fine
        """

    def check_mask(self, mask: np.ndarray | None) -> None:  # noqa: B027   (a hook: any mask, unless a kind says)
        """Raise when a validity mask cannot belong to an image of this domain.

        Parameters
        ----------
        mask : numpy.ndarray or None
            (H, W) booleans, or None.

        Raises
        ------
        ImageError
            When this kind of image takes no such mask.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> OctahedralDomain().check_mask(None)              # a sphere image takes no mask
        """

    @abstractmethod
    def grid_shape(self, resolution: int) -> tuple[int, int]:
        """(H, W) of an image with ``resolution`` pixels along its longer side.

        Parameters
        ----------
        resolution : int
            Pixels along the longer side.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain(extent=(1.0, 0.5)).grid_shape(9)
        (5, 9)
        """

    def round_resolution(self, resolution: int) -> int:
        """The nearest resolution at or above ``resolution`` that this kind of image can have.

        Parameters
        ----------
        resolution : int
            A resolution asked for.

        Returns
        -------
        int
            The one used.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> OctahedralDomain().round_resolution(64), PlanarDomain().round_resolution(64)
        (65, 64)
        """
        return int(resolution)

    def size_rule(self) -> str:
        """Which sizes this kind of image can have, in words.

        Returns
        -------
        str
            The rule.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> "odd" in OctahedralDomain().size_rule()
        True
        """
        return "any size"

    def pixel_uv(self, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """Image coordinates of the columns (u) and rows (v), from 0 to the extent.

        Parameters
        ----------
        shape : tuple of int
            The image's (H, W).

        Returns
        -------
        u, v : numpy.ndarray
            (W,) and (H,).

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain().pixel_uv((2, 3))[0].tolist()
        [0.0, 0.5, 1.0]
        """
        h, w = shape
        return np.linspace(0.0, self.extent[0], w), np.linspace(0.0, self.extent[1], h)

    def parameter_points(self, shape: tuple[int, int]) -> np.ndarray:
        """The parameter of every pixel, row by row, in the space of a parametrization's ``coords``:
        (H * W, 2) image coordinates (u, v) here.

        Parameters
        ----------
        shape : tuple of int
            The image's (H, W).

        Returns
        -------
        numpy.ndarray
            (H * W, 2) or (H * W, 3).

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain().parameter_points((2, 3)).shape, OctahedralDomain().parameter_points((5, 5)).shape
        ((6, 2), (25, 3))
        """
        u, v = self.pixel_uv(shape)
        uu, vv = np.meshgrid(u, v)
        return np.stack([uu.ravel(), vv.ravel()], axis=1)

    # ------------------------------------------------------------------ glue
    def glue(self, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray] | None:
        """Groups of pixels that are one point of the surface: each group's first pixel (flat index) and
        each pixel's group number (read-only, kept for the next call), or None when no pixels are glued.

        Parameters
        ----------
        shape : tuple of int
            The image's (H, W).

        Returns
        -------
        tuple of numpy.ndarray, or None
            ``(first, group)``: each group's first pixel, each pixel's group.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain().glue((3, 3)) is None, int(OctahedralDomain().glue((5, 5))[1].max()) + 1
        (True, 18)
        """
        return _glue_of(self, (int(shape[0]), int(shape[1])))

    def _make_glue(self, shape) -> tuple[np.ndarray, np.ndarray] | None:
        """What :meth:`glue` returns, computed (a kind that glues pixels says which)."""
        return None

    def average_glued(self, pixels: np.ndarray) -> np.ndarray:
        """Each group of glued pixels replaced by its mean (the input when nothing is glued).

        Parameters
        ----------
        pixels : numpy.ndarray
            (H, W, C) values per pixel.

        Returns
        -------
        numpy.ndarray
            The pixels with each glued group's mean.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> px = np.arange(75, dtype=np.float64).reshape(5, 5, 3)
        >>> out = OctahedralDomain().average_glued(px)
        >>> bool((out[0, 1] == out[0, 3]).all())              # glued: one point
        True
        """
        a = np.asarray(pixels)
        glue = self.glue(a.shape[:2])
        if glue is None:
            return a
        shared, local = _shared_of(self, (int(a.shape[0]), int(a.shape[1])))
        out = a + a.dtype.type(0)           # a copy; a lone pixel's mean is itself (-0 becomes 0, as its sum)
        if not len(shared):
            return out
        flat = out.reshape(len(glue[1]), -1)
        # the shared groups' sums over the same pixels in the same order as over the whole image
        flat[shared] = group_means(a.reshape(len(glue[1]), -1)[shared], local)[local].astype(a.dtype)
        return out

    def symmetric_mask(self, weights: np.ndarray) -> np.ndarray:
        """The largest weight of each group of glued pixels, given to all of them.

        Parameters
        ----------
        weights : numpy.ndarray
            (H, W) weights.

        Returns
        -------
        numpy.ndarray
            (H, W) weights, equal over each glued group.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> w = np.zeros((5, 5)); w[0, 1] = 1.0
        >>> OctahedralDomain().symmetric_mask(w)[0, 3].item()      # its glued twin
        1.0
        """
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

        Parameters
        ----------
        array : numpy.ndarray
            (H, W) or (H, W, C).
        width : int
            Pixels added on each side.

        Returns
        -------
        numpy.ndarray
            (H + 2 width, W + 2 width[, C]).

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain().pad(np.zeros((3, 4)), 2).shape
        (7, 8)
        """
        assert self.boundary is not None, f"{self.kind}: a domain without a filters rule overrides pad"
        return filters.pad(array, width, self.boundary)

    def estimate_normals(self, pixels: np.ndarray) -> np.ndarray | None:
        """Normals from the grid for a quad mesh, where the image carries no exact ones (None: none).

        Parameters
        ----------
        pixels : numpy.ndarray
            (H, W, C) values per pixel.

        Returns
        -------
        numpy.ndarray or None
            (H, W, 3) unit normals, or None.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> u, v = np.meshgrid(np.arange(3.0), np.arange(3.0))
        >>> PlanarDomain().estimate_normals(np.dstack([u, v, np.zeros((3, 3))]))[1, 1].tolist()
        [0.0, 0.0, 1.0]
        """
        return grid_normals(pixels, self.orientation)

    def ghosts(self, centres: np.ndarray, reach: np.ndarray, size: np.ndarray | None = None) -> list:
        """Faces that a surface over this domain sees beyond the image's edges, as
        ``(face indices, R (2, 2), b (2,))``: copies of those faces (by their parametric ``centres``
        (F, 2)) with parameters ``R uv + b``, for faces whose weights reach an edge within ``reach`` (F,).
        Empty for a domain whose edges are the surface's own.

        Parameters
        ----------
        centres : numpy.ndarray
            (F, 2) the faces' parametric centres.
        reach : numpy.ndarray
            (F,) how far each face's weights reach.
        size : numpy.ndarray or None
            (F,) each face's own size (its enclosing radius): a face within it of a twin piece's end is not
            copied (its copy would spill beside the next piece). None: no margin (the paper's weights, whose
            surface at s = 1 needs the copies up to the ends).

        Returns
        -------
        list
            ``(face indices, R, b)`` per copy (empty when nothing is seen beyond the edges).

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> PlanarDomain().ghosts(np.zeros((1, 2)), np.ones(1))
        []
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

        Parameters
        ----------
        pixels : numpy.ndarray
            (H, W, 3) positions.
        valid : numpy.ndarray
            (H, W) booleans.
        normals : numpy.ndarray or None
            (H, W, 3) exact normals, or None (estimated).
        colors : numpy.ndarray or None
            (H, W, C) colours, or None.

        Returns
        -------
        Mesh
            The quad mesh.

        Examples
        --------
        >>> from geoimg import OctahedralDomain, PlanarDomain
        >>> q = OctahedralDomain().quad_mesh(np.zeros((5, 5, 3)), np.ones((5, 5), bool), None, None)
        >>> q.n_vertices, q.n_faces
        (18, 16)
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
