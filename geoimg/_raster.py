"""Raster files through OpenImageIO: read any image as float arrays, write named channels.

The lowest layer under geometry-image files, masks and elevation grids; it knows nothing of meshes
or geometry images.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

import filters

from ._budget import check_memory
from .errors import ImageFileError

__all__ = ["read_raster", "write_raster", "FLOAT", "UINT16", "UINT8"]

FLOAT, UINT16, UINT8 = oiio.FLOAT, oiio.UINT16, oiio.UINT8
ERROR_LINES = 3        # of OpenImageIO's messages about one file, the first this many are shown


def _error(source) -> str:
    """OpenImageIO's last error message (of the library or of one file), whatever bytes it holds, on one line:
    its lines (often the same complaint in several words) joined, repeats and the file name left out.
    """
    try:
        text = source.geterror()
    except UnicodeDecodeError:
        return "an error message that is not valid UTF-8"
    lines: dict[str, None] = {}                  # in order, each once (a damaged file can give one per scanline)
    for line in text.splitlines():
        line = re.sub(r"^EXR Error \([^)]*\):\s*", "", line.strip())
        if line:
            lines[line] = None
    shown = list(lines)[:ERROR_LINES]
    more = f"; and {len(lines) - len(shown)} more messages" if len(lines) > len(shown) else ""
    return "; ".join(shown) + more if shown else "no reason given"


def _oiio_name(path) -> str:
    """The path as OpenImageIO takes it: text that is valid UTF-8."""
    name = str(path)
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        raise ImageFileError(f"{name.encode('utf-8', 'backslashreplace').decode()}: the file name is not valid "
                             "UTF-8, which OpenImageIO needs; rename the file") from None
    return name


def write_raster(path: Path, data: np.ndarray, names, fmt, attributes=()) -> None:
    """Write ``data`` (H, W, C) to ``path`` with channel ``names``, pixel format ``fmt`` (``FLOAT``,
    ``UINT16``, ``UINT8``) and ``(name, value)`` attributes; the format follows the file name.
    """
    name = _oiio_name(path)
    out = oiio.ImageOutput.create(name)
    if out is None:
        raise ImageFileError(f"{name}: OpenImageIO cannot write this format ({_error(oiio)})")
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], data.shape[2], fmt)
    spec.channelnames = tuple(names)
    for key, value in attributes:
        spec.attribute(key, value)
    if not out.open(name, spec) or not out.write_image(np.ascontiguousarray(data)):
        msg = _error(out)
        out.close()
        raise ImageFileError(f"{name}: writing failed ({msg})")
    out.close()


def _refusal(path: Path, reason: str) -> str:
    """Why OpenImageIO could not open ``path``, in geoimg's words where its words name its own settings: a
    header that claims more than the file can hold says the size it claims and the memory limit.
    """
    claim = re.search(r"claims an? (\d+(?:\.\d+)?) MB image from an? (\d+) byte file", reason)
    if claim:
        gib, size = float(claim.group(1)) / 1024, int(claim.group(2))
        limit = filters.memory_limit() / 2 ** 30
        over = (f"; it is also over the memory limit of {limit:.1f} GiB ({filters.MEMORY_ENV} raises it)"
                if gib > limit else "")
        return (f"{path}: its header declares an image of {gib:.1f} GiB in a file of {size} bytes: a damaged "
                f"or hostile header, not read{over}")
    if "limits:" in reason:          # another of OpenImageIO's limits (channels, resolution)
        reason = "; ".join(part for part in reason.split("; ") if "limits:" not in part and "attribute" not in part)
        return f"{path}: its header declares more than an image reader accepts ({reason}); not read"
    return f"{path}: cannot be read as an image ({reason})"


def _open_unlimited(name: str):
    """``ImageInput.open`` without OpenImageIO's own size limit (its refusal names an attribute of a library
    the user never called): the header's size is checked against geoimg's memory limit right after, in
    geoimg's words. The library's setting is restored.
    """
    before = oiio.get_int_attribute("limits:imagesize_MB", 0)
    oiio.attribute("limits:imagesize_MB", 1 << 30)
    try:
        return oiio.ImageInput.open(name)
    finally:
        oiio.attribute("limits:imagesize_MB", before)


def read_raster(path, attributes=(), what: str = "image", *, integers: str | None = None):
    """Pixels (H, W, C) float32 of any image OpenImageIO reads (integer formats scaled to [0, 1]), the
    channel names and the values of the named attributes (None where absent). With ``integers`` (a
    reason), an image whose pixels are integers (PNG, JPEG), not floating point, is refused with it.

    Raises
    ------
    FileNotFoundError
        If there is no such file.
    ImageFileError
        If it cannot be read, or is refused.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no {what} file at {path}")
    inp = _open_unlimited(_oiio_name(path))
    if inp is None:
        raise ImageFileError(_refusal(path, _error(oiio)))
    try:
        spec = inp.spec()
        if integers and spec.format.basetype not in (oiio.FLOAT, oiio.HALF, oiio.DOUBLE):
            raise ImageFileError(f"{path}: {integers}")
        # what its header declares, as float32, checked before anything is read (a hostile header)
        check_memory(4.0 * spec.width * spec.height * max(spec.nchannels, 1), f"{path}: {what} of "
                     f"{spec.width} x {spec.height} x {spec.nchannels}")
        data = inp.read_image(oiio.FLOAT)
        if data is None:
            raise ImageFileError(f"{path}: pixel data could not be read ({_error(inp)})")
        names = list(spec.channelnames)
        values = [spec.getattribute(a) for a in attributes]
    finally:
        inp.close()
    return np.asarray(data, np.float32).reshape(spec.height, spec.width, spec.nchannels), names, values
