"""Geometry-image files: :func:`load_image` and :func:`save_image` over the formats, each in a module of its own
that reads and writes it (``_exr.py``, ``_npz.py``, ``_npy.py``, ``_tiff.py``, ``_jp2.py``, ``_preview.py`` for
16-bit PNG previews; see :meth:`GeometryImage.save`), the image assembled here from what a file holds; and
scalar, colour and normal maps.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from .._choices import ASSUMABLE_DOMAINS
from .._atomic import atomic_path
from .._raster import FLOAT, UINT8, write_raster
from ..errors import GeoimgError, ImageFileError, InputError, InputTypeError
from ._domain import Domain
from ._exr import read_exr
from ._image import COLOR_CHANNELS, IMAGE_FORMATS, GeometryImage
from ._jp2 import read_jp2
from ._npy import read_npy_image
from ._npz import read_npz
from ._preview import read_preview
from ._tiff import read_tiff
from .._types import PathLike, as_path

__all__ = ["IMAGE_FORMATS", "ASSUMABLE_DOMAINS", "save_image", "load_image", "save_preview", "save_scalar",
           "save_colormap", "diverging_colors", "save_normal_map"]




def save_image(image: GeometryImage, path: PathLike, *, overwrite: bool = False) -> Path:
    """Write a geometry image to OpenEXR, NumPy ``.npz`` or ``.npy``, or a float TIFF, atomically (see
    :meth:`GeometryImage.save`).

    Parameters
    ----------
    image : GeometryImage
    path : str or path-like
        Ending in one of :data:`IMAGE_FORMATS`.
    overwrite : bool, default False

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputTypeError
        When ``image`` is not a GeometryImage.
    ImageFileError
        When the extension is not a geometry-image format.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.exr"
    >>> img = GeometryImage(np.arange(24, dtype=np.float32).reshape(2, 4, 3))
    >>> bool(np.array_equal(load_image(save_image(img, p)).pixels, img.pixels))
    True
    """
    if not isinstance(image, GeometryImage):
        raise InputTypeError(f"image: expected a GeometryImage, got {type(image).__name__}")
    return image.save(path, overwrite=overwrite)




def _unmarked(path, assume: str | None) -> str:
    """The domain of a file that has no geoimg metadata: refused, unless the caller names one (then read with a
    warning).
    """
    if assume is None:
        raise ImageFileError(f"{path}: has no geoimg metadata (it was not written by geoimg), so its domain is "
                             "unknown; name it to read the file anyway: load_image(path, assume='planar') "
                             "(--assume planar on the command line)")
    if assume not in ASSUMABLE_DOMAINS:
        raise InputError(f"assume: expected one of {', '.join(ASSUMABLE_DOMAINS)}, got {assume!r} (a cut-open "
                         "image needs the layout geoimg records)")
    warnings.warn(f"{path}: no geoimg metadata; read as a geometry image of the {assume} domain, as asked",
                  stacklevel=3)
    return assume


def _load_preview(path, approximate: bool) -> GeometryImage:
    """A 16-bit preview (:meth:`GeometryImage.preview`) decoded back to coordinates, when asked."""
    pixels, valid, record = read_preview(path, approximate)
    return _image_of_file(path, pixels, None if valid.all() else valid, record.get("domain", "planar"), None, record)


def _image_of_file(path, pixels, mask, domain, normals, metadata, colors=None) -> GeometryImage:
    """The GeometryImage of a file's arrays; what the image refuses is the file's fault, said with its name."""
    try:
        return GeometryImage(pixels, mask, domain=domain, normals=normals, metadata=metadata, colors=colors)
    except (GeoimgError, ValueError) as e:
        raise ImageFileError(f"{path}: {e}") from None


def load_image(path: PathLike, *, assume: str | None = None, approximate: bool = False,
               max_bytes: int | None = None) -> GeometryImage:
    """Read a geometry image written by :func:`save_image` (see :meth:`GeometryImage.save` for the
    formats): OpenEXR, a NumPy ``.npz`` archive, a float TIFF or a ``.npy`` array with its ``.npy.json``
    sidecar. The mask is the ``mask`` channel, or ``A`` (the RGBA layout, and TIFF's alpha). A file without
    geoimg's metadata (an EXR or TIFF from another program, arrays saved by hand) is refused unless ``assume`` names
    its domain (``"planar"`` or
    ``"octahedral"``); it is then read with a warning. A 16-bit PNG preview written by geoimg is read,
    as approximate geometry (its recorded offset and step), only with ``approximate=True``. A ``.jp2`` file
    written by :func:`geoimg.compress` is read through its recorded quantization, its glued pixels welded
    (needs ``imagecodecs``, the ``compress`` extra).

    Raises
    ------
    FileNotFoundError
        If there is no such file.
    ImageFileError
        If the file cannot be read, has no R, G, B channels, has no geoimg metadata and no ``assume``, or
        is not a geoimg archive.

    Parameters
    ----------
    path : path-like
        An ``.exr``, ``.npz``, ``.tif``/``.tiff`` or ``.npy`` file (or a geoimg ``.png`` preview, or a
        compressed ``.jp2``).
    assume : {"planar", "octahedral"} or None
        The domain of a file without geoimg's metadata.
    approximate : bool
        Read a 16-bit PNG preview as approximate geometry.
    max_bytes : int, optional
        A ``.jp2`` file's first bytes only: the shape as far as its whole wavelet levels go (a coarser shape at
        the same resolution), as a viewer streaming the file has it (``metadata["jpeg2000_levels"]``); of a
        displaced file, its base, then the offsets' whole levels (``metadata["jpeg2000_offset_levels"]``).

    Returns
    -------
    GeometryImage
        The image, bit for bit as it was saved, domain included.

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np
    >>> from geoimg import GeometryImage, save_image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "flat.exr"
    >>> _ = save_image(GeometryImage(np.zeros((3, 4, 3), np.float32)), p)
    >>> load_image(p).shape, load_image(p).domain.kind
    ((3, 4), 'planar')
    """
    path = as_path(path)
    suffix = path.suffix.lower()
    if max_bytes is not None and suffix != ".jp2":
        raise InputError(f"max_bytes: only a compressed .jp2 geometry image decodes from its first bytes, not {path}")
    if suffix == ".npz":
        return _load_npz(path, assume)
    if suffix == ".png":
        return _load_preview(path, approximate)
    if suffix == ".jp2":
        return read_jp2(path, max_bytes)
    read = {".npy": read_npy_image, ".tif": read_tiff, ".tiff": read_tiff}.get(suffix, read_exr)
    return _from_channels(path, *read(path), assume)


def _from_channels(path, data, names, meta, domain, assume) -> GeometryImage:
    """The image of a file's named channels (R, G, B; mask or A; N.X, N.Y, N.Z; color.R ...), its parsed
    metadata and its domain kind (both None: a file without geoimg's metadata, read only with ``assume``).
    """
    if meta is None and domain is None:
        domain, meta = _unmarked(path, assume), {}
    domain = domain or "planar"

    def channels(keys):
        if all(k in names for k in keys):
            return np.stack([data[..., names.index(k)] for k in keys], axis=2)
        return None

    xyz = channels(["R", "G", "B"])
    if xyz is None:
        raise ImageFileError(f"{path}: no R, G, B channels (found {', '.join(names)})")
    mask = channels(["mask"])
    if mask is None and "A" in names:              # the RGBA layout: all valid reads as no mask
        mask = channels(["A"])
        mask = None if np.all(mask > 0.5) else mask
    normals = channels(["N.X", "N.Y", "N.Z"])
    colors = channels(list(COLOR_CHANNELS))
    colors = channels(list(COLOR_CHANNELS[:3])) if colors is None else colors
    if not isinstance(meta, dict):
        raise ImageFileError(f"{path}: geoimg:metadata is not a JSON object")
    try:
        dom = Domain.from_metadata(domain, meta)
    except ValueError as e:
        raise ImageFileError(f"{path}: {e}") from None
    return _image_of_file(path, xyz, None if mask is None else mask[..., 0] > 0.5, dom, normals, meta, colors)


def _load_npz(path, assume: str | None) -> GeometryImage:
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no such file")
    positions, mask, normals, record, colors = read_npz(path)
    domain = record.get("domain") or (_unmarked(path, assume) if not record else "planar")
    return _image_of_file(path, positions, mask, domain, normals, record, colors)


def save_preview(image: GeometryImage, path: PathLike, *, overwrite: bool = False) -> Path:
    """Write a 16-bit RGB PNG: X, Y, Z each stretched to [0, 65535] over the valid pixels, masked pixels
    black (see :meth:`GeometryImage.preview`).

    Parameters
    ----------
    image : GeometryImage
        The image to show.
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
    >>> from geoimg import GeometryImage
    >>> img = GeometryImage(np.random.default_rng(0).random((4, 4, 3)).astype(np.float32))
    >>> save_preview(img, pathlib.Path(tempfile.mkdtemp()) / "preview.png").name
    'preview.png'
    """
    return image.preview(path, overwrite=overwrite)


def save_scalar(values: np.ndarray, path: PathLike, name: str = "Y", *, overwrite: bool = False) -> Path:
    """Write an (H, W) float map (a curvature, a mask) to a one-channel float32 OpenEXR.

    Parameters
    ----------
    values : numpy.ndarray
        (H, W) floats.
    path : path-like
        The ``.exr`` file.
    name : str
        The channel's name.
    overwrite : bool
        Replace the file if it exists.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ImageFileError
        When the name is not a ``.exr``.
    InputError
        When ``values`` is not (H, W).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> save_scalar(np.zeros((2, 3)), pathlib.Path(tempfile.mkdtemp()) / "k.exr", "K").name
    'k.exr'
    """
    path = Path(path)
    if path.suffix.lower() != ".exr":
        raise ImageFileError(f"{path}: scalar maps are written as OpenEXR; use a .exr name")
    a = np.asarray(values, np.float32)
    if a.ndim != 2:
        raise InputError(f"values: expected shape (H, W), got {a.shape}")
    with atomic_path(path, overwrite) as tmp:
        write_raster(tmp, a[..., None], [name], FLOAT)
    return path


def diverging_colors(values: np.ndarray, valid: np.ndarray | None = None, scale: float | None = None) -> np.ndarray:
    """8-bit RGB (H, W, 3) of a signed map: blue (negative), white (0), red (positive), full colour at
    ``|value| = scale`` (default: the 99th percentile of ``|value|`` over valid pixels); invalid pixels black.

    Parameters
    ----------
    values : numpy.ndarray
        (H, W) signed values.
    valid : numpy.ndarray or None
        (H, W) booleans: the pixels that hold a value.
    scale : float or None
        The magnitude drawn in full colour.

    Returns
    -------
    numpy.ndarray
        (H, W, 3) uint8.

    Examples
    --------
    >>> diverging_colors(np.array([[-1.0, 0.0, 1.0]]))[0].tolist()
    [[59, 76, 192], [255, 255, 255], [180, 4, 38]]
    """
    v = np.asarray(values, np.float64)
    valid = np.ones(v.shape, bool) if valid is None else np.asarray(valid, bool)
    if scale is None:
        scale = np.percentile(np.abs(v[valid]), 99) if valid.any() else 1.0
    t = np.clip(v / max(scale, 1e-300), -1.0, 1.0)[..., None]
    white, blue, red = np.array([255.0, 255, 255]), np.array([59.0, 76, 192]), np.array([180.0, 4, 38])
    rgb = np.where(t < 0, white + (-t) * (blue - white), white + t * (red - white))
    rgb = np.round(rgb).astype(np.uint8)
    rgb[~valid] = 0
    return rgb


def save_colormap(values: np.ndarray, path: PathLike, valid: np.ndarray | None = None, *,
                  overwrite: bool = False, title: str | None = None) -> Path:
    """Write a signed (H, W) map as an 8-bit PNG with :func:`diverging_colors`, with ``title`` written in
    its top left corner when given.

    Parameters
    ----------
    values : numpy.ndarray
        (H, W) signed values.
    path : path-like
        The ``.png`` file.
    valid : numpy.ndarray or None
        (H, W) booleans: the pixels that hold a value.
    overwrite : bool
        Replace the file if it exists.
    title : str, optional
        A line of text drawn on the picture (what it shows, at what scale).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ImageFileError
        When the name is not a ``.png``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> save_colormap(np.linspace(-1, 1, 6).reshape(2, 3), pathlib.Path(tempfile.mkdtemp()) / "k.png").name
    'k.png'
    """
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ImageFileError(f"{path}: colour maps are PNG; use a .png name")
    rgb = diverging_colors(values, valid)
    if title:
        picture = Image.fromarray(np.ascontiguousarray(rgb))
        ImageDraw.Draw(picture).text((4, 4), title, fill=(0, 0, 0), stroke_width=2, stroke_fill=(255, 255, 255))
        rgb = np.asarray(picture)
    with atomic_path(path, overwrite) as tmp:
        write_raster(tmp, rgb, ["R", "G", "B"], UINT8)
    return path


def save_normal_map(normals: np.ndarray, path: PathLike, valid: np.ndarray | None = None, *,
                    overwrite: bool = False) -> Path:
    """Write unit normals (H, W, 3) as an 8-bit PNG normal map, ``(n + 1) / 2`` per channel; invalid black.

    Parameters
    ----------
    normals : numpy.ndarray
        (H, W, 3) unit normals.
    path : path-like
        The ``.png`` file.
    valid : numpy.ndarray or None
        (H, W) booleans: the pixels that hold a normal.
    overwrite : bool
        Replace the file if it exists.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ImageFileError
        When the name is not a ``.png``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> up = np.zeros((2, 2, 3)); up[..., 2] = 1
    >>> save_normal_map(up, pathlib.Path(tempfile.mkdtemp()) / "n.png").suffix
    '.png'
    """
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ImageFileError(f"{path}: normal maps are PNG; use a .png name")
    n = np.asarray(normals, np.float64)
    rgb = np.round(np.clip(n * 0.5 + 0.5, 0, 1) * 255).astype(np.uint8)
    if valid is not None:
        rgb[~np.asarray(valid, bool)] = 0
    with atomic_path(path, overwrite) as tmp:
        write_raster(tmp, rgb, ["R", "G", "B"], UINT8)
    return path
