"""Geometry images: a regular grid of surface points stored as an (H, W, 3) float image of X, Y, Z."""
from __future__ import annotations

import inspect
import json
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

import filters
from .._choices import EXR_LAYOUTS, IMAGE_FORMATS
from .._atomic import atomic_path, write_all
from ..errors import GeoimgError, ImageError, ImageFileError, InputError, InputTypeError
from ..mesh import Mesh
from ._domain import Domain
from ._exr import write_exr
from ._npy import npy_jobs
from ._npz import write_npz
from ._preview import PREVIEW_LEVELS, write_preview
from ._tiff import write_tiff
from .._types import PathLike, as_path

__all__ = ["GeometryImage", "DEFAULT_PAD", "EXR_LAYOUTS", "IMAGE_FORMATS", "COLOR_CHANNELS"]

DEFAULT_PAD = 16
COLOR_CHANNELS = ("color.R", "color.G", "color.B", "color.A")


def _boundary_aware(op):
    """The parameters of a :mod:`filters` operation (array in, array out, the boundary rule as
    ``mode=``), or None for any other callable.
    """
    module = getattr(op, "__module__", None) or ""
    if module != "filters" and not module.startswith("filters."):
        return None
    try:
        params = inspect.signature(op).parameters
    except (TypeError, ValueError):
        return None
    return params if "mode" in params else None


@dataclass(frozen=True, eq=False)
class GeometryImage:
    """A geometry image.

    Parameters
    ----------
    pixels : numpy.ndarray, shape (H, W, 3)
        X, Y, Z of the surface at each grid point (float32 or float64, kept as given).
    mask : numpy.ndarray of bool, shape (H, W), or None
        Pixels inside the parametrized region (None: all valid).
    domain : Domain
        What kind of image it is (:class:`~geoimg.PlanarDomain`, :class:`~geoimg.OctahedralDomain`):
        how pixels map to parameters, which pixels are glued, what filters see beyond the edges. A
        kind name (``"planar"``, ``"octahedral"``) is accepted too; its fields (``extent``,
        ``orientation``) are then taken from ``metadata``, where they are not kept.
    normals : numpy.ndarray, shape (H, W, 3), or None
        Exact unit normals from the surface's derivatives, when known.
    metadata : dict
        How the image was made (s, weights, resolution, source, ...).
    colors : numpy.ndarray, shape (H, W, 3) or (H, W, 4), or None
        RGB(A) in [0, 1] per pixel (float32): the mesh's vertex colours or texture resampled. They belong to
        the pixels, so filters of the geometry keep them as they are; the quad mesh carries them as vertex
        colours and as a texture over its texture coordinates.

    Raises
    ------
    ImageError
        When the pixels, mask, normals or colours are malformed (shapes, NaN, a mask that selects
        nothing) or the metadata contradicts the domain.
    InputTypeError
        When an array is of the wrong type or the domain is not a Domain or a kind's name.

    Examples
    --------
    >>> img = GeometryImage(np.zeros((4, 5, 3), np.float32))
    >>> img.shape, img.domain.kind, img.to_mesh().n_faces
    ((4, 5), 'planar', 12)
    """

    pixels: np.ndarray
    mask: np.ndarray | None = None
    domain: Domain = "planar"             # type: ignore[assignment]   # a kind name is made a Domain
    normals: np.ndarray | None = None
    metadata: dict = field(default_factory=dict)
    colors: np.ndarray | None = None

    if TYPE_CHECKING:        # what the constructor takes (the fields hold them converted and checked)
        def __init__(self, pixels: ArrayLike, mask: ArrayLike | None = None, domain: Domain | str = "planar",
                     normals: ArrayLike | None = None, metadata: dict | None = None,
                     colors: ArrayLike | None = None) -> None: ...

    def __post_init__(self):
        p = np.asarray(self.pixels)
        if p.ndim != 3 or p.shape[2] != 3 or p.shape[0] < 2 or p.shape[1] < 2:
            raise ImageError(f"pixels: expected shape (H, W, 3) with H, W >= 2, got {p.shape}")
        if p.dtype not in (np.float32, np.float64):
            raise InputTypeError(f"pixels: expected float32 or float64, got {p.dtype}")
        if not np.isfinite(p).all():
            raise ImageError("pixels: contain NaN or infinite values")
        p = p.copy()
        p.setflags(write=False)
        object.__setattr__(self, "pixels", p)
        if self.mask is not None:
            m = np.asarray(self.mask)
            if m.shape != p.shape[:2]:
                raise ImageError(f"mask: expected shape {p.shape[:2]}, got {m.shape}")
            if m.dtype != bool:
                raise InputTypeError(f"mask: expected a boolean array, got {m.dtype}")
            if not m.any():
                raise ImageError("mask: selects no pixel; an image without valid pixels holds no surface")
            m = m.copy()
            m.setflags(write=False)
            object.__setattr__(self, "mask", m)
        if self.normals is not None:
            n = np.asarray(self.normals)
            if n.shape != p.shape:
                raise ImageError(f"normals: expected shape {p.shape}, got {n.shape}")
            if not np.issubdtype(n.dtype, np.floating):
                raise InputTypeError(f"normals: expected a float array, got {n.dtype}")
            if not np.isfinite(n).all():
                raise ImageError("normals: contain NaN or infinite values")
            n = n.copy()
            n.setflags(write=False)
            object.__setattr__(self, "normals", n)
        if self.colors is not None:
            c = np.array(self.colors, dtype=np.float32, copy=True)
            if c.ndim != 3 or c.shape[:2] != p.shape[:2] or c.shape[2] not in (3, 4):
                raise ImageError(f"colors: expected shape {p.shape[:2] + (3,)} or {p.shape[:2] + (4,)}, got "
                                 f"{c.shape}")
            if not np.isfinite(c).all() or c.min() < 0 or c.max() > 1:
                raise ImageError("colors: expected values in [0, 1]")
            c.setflags(write=False)
            object.__setattr__(self, "colors", c)
        if not isinstance(self.metadata, Mapping):
            raise InputTypeError(f"metadata: expected a dict, got {type(self.metadata).__name__}")
        meta = dict(self.metadata)
        domain = self.domain
        if isinstance(domain, str):
            domain = Domain.from_metadata(domain, meta)
        elif not isinstance(domain, Domain):
            raise InputTypeError(f"domain: expected a geoimg Domain or a kind name, got {type(domain).__name__}")
        own = domain.to_metadata()
        for key in own:                        # the domain's own fields live in the domain
            if key in meta and meta.pop(key) != own[key]:
                raise ImageError(f"metadata: {key}={self.metadata[key]!r} contradicts the domain's {own[key]!r} "
                                 "(the domain's fields belong to the domain)")
        domain.check_shape(p.shape[:2])
        domain.check_mask(self.mask)
        object.__setattr__(self, "domain", domain)
        object.__setattr__(self, "metadata", meta)

    def __repr__(self) -> str:
        extras = [f"{int(self.valid.sum())} valid pixels"] if self.mask is not None else []
        extras += ["normals"] if self.normals is not None else []
        extras += ["colors"] if self.colors is not None else []
        return (f"GeometryImage({self.shape[1]} x {self.shape[0]} {self.pixels.dtype}, {self.domain!r}"
                + "".join(f", {e}" for e in extras) + f", metadata keys {sorted(self.metadata)})")

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W).

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> img.shape
        (3, 4)
        """
        return self.pixels.shape[:2]

    @property
    def valid(self) -> np.ndarray:
        """The mask, or all True when there is none.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> bool(img.valid.all()), img.valid.shape
        (True, (3, 4))
        """
        return np.ones(self.shape, bool) if self.mask is None else self.mask

    def parameter_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The image coordinates (u, v) of the columns and rows (0 to the domain's extent).

        Returns
        -------
        u, v : numpy.ndarray
            (W,) and (H,) coordinates.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> u, v = img.parameter_grid()
        >>> u.shape, v.shape
        ((4,), (3,))
        """
        return self.domain.pixel_uv(self.shape)

    def to_mesh(self) -> Mesh:
        """The regular quad mesh: a quad per 2x2 block of valid pixels, a vertex per pixel of a quad, glued
        pixels welded by index into one vertex (their mean), so an octahedral image gives a closed
        genus-0 mesh. (A valid pixel that no quad uses, e.g. an isolated one, gives no vertex.)

        Quads are oriented like the source mesh (``domain.orientation``). Vertices carry the pixel's
        (u, v) and a normal: the exact one when the image has ``normals``, else one from the grid
        (planar images). An image with ``colors`` gives vertex colours, and the colours as the mesh's
        texture with texture coordinates per corner at the pixels' centres (glued pixels welded into one
        vertex keep each side's own texture coordinates).

        Returns
        -------
        Mesh
            (H - 1)(W - 1) quads when every pixel is valid.

        Raises
        ------
        GeoimgError
            If no 2 x 2 block of valid pixels exists.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> q = img.to_mesh()
        >>> q.n_vertices, q.n_faces
        (12, 6)
        """
        return self.domain.quad_mesh(self.pixels, self.valid, self.normals, self.colors)

    def with_pixels(self, pixels: ArrayLike, *, mask: Any = ..., metadata: dict | None = None,
                    colors: Any = ...) -> GeometryImage:
        """A new image of the same domain with other pixels (no exact normals: they belong to the old
        surface); ``mask``, ``metadata`` and ``colors`` are kept unless given.

        Parameters
        ----------
        pixels : array_like
            (H, W, 3) new positions.
        mask : array_like or None
            A new mask (the old one by default).
        metadata : dict or None
            New metadata (the old one by default).
        colors : array_like or None
            New colours (the old ones by default).

        Returns
        -------
        GeometryImage
            The new image.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> img.with_pixels(np.ones((3, 4, 3), np.float32)).pixels.max().item()
        1.0
        """
        return GeometryImage(pixels, self.mask if mask is ... else mask, self.domain,
                             metadata=dict(self.metadata) if metadata is None else metadata,
                             colors=self.colors if colors is ... else colors)

    @property
    def boundary_mode(self) -> str | None:
        """The :mod:`filters` boundary rule of the image's domain (``reflect``, ``octahedral``; None for a
        domain that pads images itself).

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> img.boundary_mode
        'reflect'
        """
        return self.domain.boundary

    def apply(self, op: Callable[..., Any], *args: Any, pad: int | None = None, **kwargs: Any) -> GeometryImage:
        """Run an operation on the pixels with the domain's boundary rule; a new image.

        Two kinds of operation are accepted:

        - a :mod:`filters` function (array first, array out, the boundary rule as ``mode=``): it gets
          ``mode=`` the domain's rule unless the call gives one (on a domain without a :mod:`filters`
          rule, such as a cut-open image, it is padded as below);
        - any other callable on an (H, W, 3) array returning an array of the same shape, e.g.
          ``cv2.GaussianBlur``, ``scipy.ndimage.median_filter`` or
          ``skimage.restoration.denoise_tv_chambolle``: it runs on the pixels padded by ``pad`` pixels
          (default :data:`DEFAULT_PAD`) with the domain's rule, and the result is cropped back, so it
          sees across an octahedral image's glued sides as a filters function does. Give a larger
          ``pad`` for wider operations.

        Geometry images among the arguments (to blend or composite) stand for their pixels (padded
        too, for other callables) and must share domain and size; glued pixels of the result are
        averaged so they stay identical. The image's colours are kept as they are (they belong to the
        pixels, whatever moves them). ``mask=`` and ``feather=`` restrict any operation to a region
        (through its own mask argument, or by blending its result in); a mask is first made symmetric
        over glued pixels. The exact normals are dropped (the filtered image is no longer the surface);
        the operation is recorded in ``metadata['filters']``.

        Parameters
        ----------
        op : callable
            The operation: ``op(pixels, *args, **kwargs)`` returns an array of the pixels' shape.
        *args
            Its further arguments (geometry images stand for their pixels).
        pad : int or None
            Pixels of padding for a callable that is not a :mod:`filters` function.
        **kwargs
            Its keyword arguments; ``mask=`` and ``feather=`` restrict it to a region.

        Returns
        -------
        GeometryImage
            A new image with the result (its glued pixels averaged, no exact normals).

        Examples
        --------
        >>> img = GeometryImage(np.random.default_rng(0).normal(size=(5, 5, 3)), domain="octahedral")
        >>> out = img.apply(filters.mean_filter, 3)
        >>> out.metadata["filters"], out.domain.kind
        (['mean_filter(3, mode=octahedral)'], 'octahedral')
        >>> from scipy import ndimage
        >>> out = img.apply(ndimage.uniform_filter, size=(3, 3, 1), pad=2)
        >>> bool(np.array_equal(out.pixels[0, 1], out.pixels[0, 3]))     # glued pixels agree
        True
        """
        try:
            return self._apply(op, args, pad, kwargs)
        except GeoimgError:
            raise
        except (ValueError, TypeError) as e:
            if _boundary_aware(op) is None and not _raised_by_filters(e):
                raise                                   # another library's error: as it is
            raise InputError(f"{getattr(op, '__name__', 'op')}: {e}") from None

    def _apply(self, op, args, pad, kwargs) -> GeometryImage:
        params = _boundary_aware(op)
        direct = params is not None and self.domain.boundary is not None    # a filters function, given mode=
        width = 0
        if not direct:
            width = DEFAULT_PAD if pad is None else int(filters.positive(pad, "pad", integer=True, allow_zero=True))
        elif pad is not None:
            raise ImageError(f"pad: {getattr(op, '__name__', op)} meets the image's edges through its mode; "
                             "pad is for other callables")

        def pixels_of(x):
            if isinstance(x, GeometryImage):
                if not x.domain.same_kind(self.domain) or x.shape != self.shape:
                    raise ImageError(f"image: expected a {self.domain.kind} {self.shape} geometry image, got a "
                                     f"{x.domain.kind} {x.shape} one (resample it with filters.resize first)")
                return x.pixels if direct else self.domain.pad(x.pixels, width)
            return x

        args = [pixels_of(a) for a in args]
        kwargs = {k: pixels_of(v) for k, v in kwargs.items()}
        if params is not None and "mode" not in kwargs:     # on a padded image, the rule beyond the pad
            kwargs["mode"] = self.boundary_mode if direct else "reflect"
        mask, feather = kwargs.get("mask"), kwargs.get("feather", 0.0)
        if mask is not None:
            mask = kwargs["mask"] = self.domain.symmetric_mask(filters.as_weights(mask, self.shape))
        if mask is not None and not (direct and "mask" in params):   # any operation can be masked
            kwargs.pop("mask")
            kwargs.pop("feather", None)
            weights = filters.feather(mask, feather, kwargs.get("mode", self.boundary_mode or "reflect"))
            out = filters.apply_masked(self.pixels, self._run(op, args, kwargs, direct, width), weights)
            kwargs.update(mask=mask, feather=feather)
        else:
            out = self._run(op, args, kwargs, direct, width)
        out = self.domain.average_glued(out)
        shown = [repr(a) if np.ndim(a) == 0 else f"<array {np.shape(a)}>" for a in args]
        shown += [f"{k}={v}" if isinstance(v, str) or np.ndim(v) == 0 else f"{k}=<array>" for k, v in kwargs.items()]
        if not direct:
            shown.append(f"pad={width}")
        meta = dict(self.metadata)
        meta["filters"] = list(meta.get("filters", [])) + [f"{getattr(op, '__name__', 'op')}({', '.join(shown)})"]
        return self.with_pixels(out.astype(self.pixels.dtype), metadata=meta)

    def _run(self, op, args, kwargs, direct: bool, width: int) -> np.ndarray:
        """``op`` on the pixels: directly for a filters function with the domain's mode, else padded by the
        domain's rule and cropped back.
        """
        name = getattr(op, "__name__", op)
        out = op(self.pixels if direct else self.domain.pad(self.pixels, width), *args, **kwargs)
        out = np.asarray(out[0] if isinstance(out, tuple) else out)
        H, W = self.shape
        expected = (H + 2 * width, W + 2 * width, 3)
        if out.shape != expected:
            raise ImageError(f"{name}: returned shape {out.shape}, expected {expected} (an array like its input)")
        out = out[width:width + H, width:width + W]
        if not np.isfinite(out).all():
            raise ImageError(f"{name}: returned NaN or infinite values")
        return out

    def save(self, path: PathLike, *, overwrite: bool = False, layout: str = "geoimg") -> Path:
        """Write the image, float32, lossless, with its metadata, atomically, in the format of the name.

        - ``.exr``: channels ``R, G, B`` (X, Y, Z), ``mask`` (1 valid, 0 not) when the image has a mask,
          ``N.X, N.Y, N.Z`` when it has normals and ``color.R, color.G, color.B`` (``color.A``) when it has
          colours; the metadata and the domain's fields as JSON in ``geoimg:metadata``, the domain's kind
          also in ``geoimg:domain``. ``layout="rgba"`` names the mask ``A`` instead and always writes it (1
          everywhere for an image without a mask), which compositing tools take as alpha.
        - ``.npz``: arrays ``positions``, ``mask``, ``normals``, ``colors`` and the same JSON as
          ``metadata`` (:mod:`geoimg.image._npz`).
        - ``.tif`` / ``.tiff``: four float32 channels X, Y, Z and the mask as alpha (OpenCV,
          scikit-image/tifffile, GIMP read it), the same JSON in the ImageDescription tag; normals and
          colours are not kept (a warning says so; use .exr or .npz for them).
        - ``.npy``: one float32 (H, W, C) array, the EXR's channels in its order (X, Y, Z first), and beside
          it ``NAME.npy.json`` with the channel names, the domain and the metadata (both files or neither).

        float32 pixels round-trip bit for bit (:func:`geoimg.load_image`).

        Returns
        -------
        pathlib.Path

        Parameters
        ----------
        path : path-like
            ``.exr``, ``.npz``, ``.tif``/``.tiff`` or ``.npy``.
        overwrite : bool
            Replace the file if it exists.
        layout : {"geoimg", "rgba"}
            EXR channels: geoimg's (R, G, B, mask, normals) or the mask as alpha.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> p = img.save(pathlib.Path(tempfile.mkdtemp()) / "flat.npz")
        >>> p.suffix
        '.npz'
        """
        return write_all(self.save_jobs(path, layout), overwrite=overwrite)[0]

    def save_jobs(self, path: PathLike, layout: str = "geoimg") -> list:
        """``(path, write)`` for every file that :meth:`save` makes (a ``.npy`` and its sidecar), for
        :func:`geoimg._atomic.write_all`, which writes them all or none.

        Parameters
        ----------
        path : path-like
            The image file.
        layout : {"geoimg", "rgba"}
            EXR channels (see :meth:`save`).

        Returns
        -------
        list of tuple
            ``(path, write)`` pairs.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> [p.name for p, _ in img.save_jobs("flat.npy")]
        ['flat.npy', 'flat.npy.json']
        """
        if layout not in EXR_LAYOUTS:
            raise InputError(f"layout: expected one of {', '.join(EXR_LAYOUTS)}, got {layout!r}")
        path = as_path(path)
        suffix = path.suffix.lower()
        if suffix not in IMAGE_FORMATS:
            raise ImageFileError(f"{path}: geometry images are saved as {', '.join(IMAGE_FORMATS)}; use one of those "
                                 "names (previews: GeometryImage.preview)")
        record, kind = self.metadata_record(), self.domain.kind
        if suffix == ".npz":
            return [(path, lambda tmp: write_npz(tmp, self.pixels, self.mask, self.normals, record, self.colors))]
        if suffix in (".tif", ".tiff"):
            dropped = [name for name, value in (("normals", self.normals), ("colours", self.colors))
                       if value is not None]
            if dropped:
                warnings.warn(f"{path}: a TIFF keeps X, Y, Z and the mask; the {' and '.join(dropped)} are not "
                              "written (.exr and .npz keep them)", stacklevel=3)
            data, names = self._channels("rgba")
            return [(path, lambda tmp: write_tiff(tmp, data, names, record, kind))]
        data, names = self._channels(layout)
        if suffix == ".npy":
            return npy_jobs(path, data, names, record, kind)
        return [(path, lambda tmp: write_exr(tmp, data, names, record, kind))]

    def _channels(self, layout: str) -> tuple[np.ndarray, list]:
        """The image's planes stacked (H, W, C) float32 and their channel names."""
        planes, names = [self.pixels.astype(np.float32)], ["R", "G", "B"]
        if self.mask is not None or layout == "rgba":
            planes.append(self.valid.astype(np.float32)[..., None])
            names.append("A" if layout == "rgba" else "mask")
        if self.normals is not None:
            planes.append(np.asarray(self.normals, np.float32))
            names += ["N.X", "N.Y", "N.Z"]
        if self.colors is not None:
            planes.append(self.colors)
            names += list(COLOR_CHANNELS[: self.colors.shape[2]])
        return np.concatenate(planes, axis=2), names

    def metadata_record(self) -> dict:
        """The metadata and the domain's fields as plain JSON types: what files record and
        :meth:`Domain.from_metadata` reads back.

        Raises
        ------
        ImageError
            If some metadata value cannot be written as JSON.

        Returns
        -------
        dict
            JSON-ready metadata, the domain's kind and fields included.

        Examples
        --------
        >>> img = GeometryImage(np.zeros((3, 4, 3), np.float32))
        >>> img.metadata_record()["domain"]
        'planar'
        """
        record = {**self.metadata, **self.domain.to_metadata()}
        try:
            return json.loads(json.dumps(record, sort_keys=True, default=_plain))
        except (TypeError, ValueError) as e:
            raise ImageError(f"metadata: cannot be written as JSON ({e})") from None

    def _levels(self, top: int):
        """X, Y, Z each stretched over its range on the valid pixels to the levels 1 to ``top`` (masked pixels
        0); with each axis' offset and step.
        """
        valid = self.valid
        p = np.asarray(self.pixels, np.float64)
        lo = p[valid].min(axis=0)
        step = np.maximum(p[valid].max(axis=0) - lo, 1e-300) / (top - 1)
        q = np.clip(1.0 + np.round((p - lo) / step), 1, top)
        q[~valid] = 0
        return q, lo, step

    def _repr_png_(self) -> bytes:
        """A notebook's picture of the image: X, Y, Z as red, green, blue (masked pixels black); a small image
        enlarged a whole number of times to at least 256 pixels (nearest pixel, so the grid stays visible), a
        large one shrunk to 512.
        """
        import cv2          # here: a notebook's picture alone needs OpenCV (0.03 s of every first conversion)

        q = self._levels(255)[0].astype(np.uint8)
        H, W = self.shape
        scale = 512 / max(H, W) if max(H, W) > 512 else -(-256 // max(H, W))
        size = (max(1, round(W * scale)), max(1, round(H * scale)))
        ok, png = cv2.imencode(".png", cv2.resize(q[..., ::-1], size, interpolation=cv2.INTER_NEAREST))
        return png.tobytes()

    def preview(self, path: PathLike, *, overwrite: bool = False) -> Path:
        """Write a 16-bit PNG: X, Y, Z each stretched over its range on the valid pixels to the levels 1 to
        65535, masked pixels black (0). The PNG records each channel's offset and step and the image's
        metadata (text attribute ``geoimg:preview``), so that ``load_image(path, approximate=True)`` can
        read it back as geometry, to within half a step (1/131068 of each axis' range).

        Parameters
        ----------
        path : path-like
            The ``.png`` file.
        overwrite : bool
            Replace the file if it exists.

        Returns
        -------
        pathlib.Path
            The file written.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> img = GeometryImage(np.random.default_rng(0).random((3, 4, 3)).astype(np.float32))
        >>> img.preview(pathlib.Path(tempfile.mkdtemp()) / "p.png").name
        'p.png'
        """
        path = _suffixed(path, ".png", "previews are PNG; use a .png name")
        q, lo, step = self._levels(PREVIEW_LEVELS + 1)
        with atomic_path(path, overwrite) as tmp:
            write_preview(tmp, q, lo, step, self.metadata_record())
        return path


def _plain(value):
    """Numpy scalars and arrays in metadata as plain numbers and lists."""
    if isinstance(value, (np.generic, np.ndarray)):
        return value.tolist()
    raise InputTypeError(f"a {type(value).__name__} is not a number, string, list or dict")


def _raised_by_filters(error: BaseException) -> bool:
    """Whether an exception comes from the filters package (its argument checks)."""
    tb = error.__traceback__
    while tb is not None:
        module = tb.tb_frame.f_globals.get("__name__", "")
        if module == "filters" or module.startswith("filters."):
            return True
        tb = tb.tb_next
    return False


def _suffixed(path, suffix: str, message: str) -> Path:
    path = Path(path)
    if path.suffix.lower() != suffix:
        raise ImageFileError(f"{path}: {message}")
    return path
