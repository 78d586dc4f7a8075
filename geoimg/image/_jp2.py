"""Geometry images in JPEG 2000 files (``.jp2``): X, Y, Z quantized to 16 bits over one step for all three
axes (so that the error is the same in every direction), coded by OpenJPEG through ``imagecodecs``, and
geoimg's record in a ``uuid`` box before the codestream (standard decoders skip it): the quantization, the
mask, the domain and the little metadata worth its bytes (:data:`KEPT`), as zlib-compressed JSON. Any JPEG
2000 decoder opens the pixels; geoimg reads them back as coordinates and welds what the domain glues (lossy
coding moves glued seam pixels apart).

Progressive: the codestream holds the coarsest wavelet level first, then each finer one; the first k bytes of a
file decode to the shape as far as its whole levels go (:func:`decode` with ``max_bytes``, a truncated file
likewise, with a warning; see :mod:`geoimg.image._j2k_packets`).

Displaced files (:mod:`geoimg.image._displacement`): the codestream is a coarse base's X, Y, Z, and a second
codestream box after it holds one channel of offsets along the upsampled base's normals (its quantization in
the record's ``offsets``). JPEG 2000 readers use the first codestream of a JP2 file and skip the others, so
any of them shows the base; geoimg's reader displaces it. A prefix holds the base first, then the offsets'
levels.

Why ``imagecodecs`` and not OpenImageIO (which geoimg reads its other images with): OpenImageIO's JPEG 2000
writer has no rate control, and rate is what compression is for.

Examples
--------
>>> import geoimg
>>> d = geoimg.OctahedralDomain()
>>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
>>> data = encode(ball, 80)
>>> back = decode(data)
>>> back.domain.kind, float(np.abs(back.pixels - ball.pixels).max()) < 1e-3
('octahedral', True)
"""
from __future__ import annotations

import base64
import dataclasses
import json
import struct
import warnings
import zlib
from pathlib import Path

import numpy as np

from .._optional import require
from ..errors import ImageError, ImageFileError, InputError
from ..parametrization._octahedral import sphere_to_square, square_to_sphere
from ._displacement import area_weights, base_frame, displace
from ._domain import Domain
from ._image import GeometryImage
from ._j2k_packets import cut_after, read_layout, resolution_ends, without_comments

__all__ = ["encode", "decode", "read_jp2", "offsets_codestream", "continue_masked", "RECORD_UUID", "HEADROOM", "TOP"]

SIGNATURE = b"\x00\x00\x00\x0cjP  \r\n\x87\n"      # the JP2 signature box
RECORD_UUID = bytes.fromhex("9c0e6e2d4a3b4f1ca1d76765_6f696d67".replace("_", ""))   # ends in "geoimg"
HEADROOM = 2048          # levels left free at both ends: lossy coding overshoots, and some coders wrap past 65535
TOP = 65535 - 2 * HEADROOM
LOSSLESS = 0             # the level that asks the coder for reversible coding
# colours on 12 bits' levels of the 16: at the coder's level for the shape, an error of a few levels of 4095
# (a fraction of 8-bit colour's step) instead of spending the budget on colour the eye cannot see
COLOR_TOP = 4095
# normals as two channels (the octahedral encoding of a unit vector) on 12 bits' levels: a level is 1/2048 of
# the square, a few hundredths of a degree
NORMAL_TOP = 4095
# the record's format: 1, DEFLATE with this dictionary (fixed for good: files carry no copy of it); the first
# files' records, zlib'd JSON, begin with 0x78 and are read too
RECORD_VERSION = b"\x01"
RECORD_DICTIONARY = (b'"parametrization":"heightfield","disk","cut","charts","uv","planar",'
                     b'"components":1,"component":0,'
                     b'"harmonics_lmax":"normals":2,"colors":3,"mask":1,"up":"z","segments":[[0,'
                     b'{"headroom":2048,"meta":{"domain":"octahedral","extent":[1.0,1.0],"orientation":1,'
                     b'"parametrization":"sphere","source":""},"offset":[0.,-0.,"step":0.0000')
# the metadata a compressed file keeps besides the domain's fields (every byte counts at a few kilobytes)
KEPT = ("source", "parametrization", "up", "component", "components", "harmonics_lmax")


def _codec():
    return require("imagecodecs", "JPEG 2000 geometry images")


def _boxes(data: bytes) -> list[tuple[bytes, int, int]]:
    """The top-level boxes of a JP2 file: (type, start of the box, end of the box)."""
    out, at = [], 0
    while at + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        header = 8
        if length == 1:                                   # a 64-bit length follows
            if at + 16 > len(data):
                break
            length, header = struct.unpack(">Q", data[at + 8:at + 16])[0], 16
        elif length == 0:                                 # to the end of the file
            length = len(data) - at
        if length < header:
            raise ImageFileError(f"a JPEG 2000 box of {length} bytes at byte {at}: not a JP2 file")
        out.append((kind, at, min(at + length, len(data))))
        at += length
    return out


def _quantized(image: GeometryImage) -> tuple[np.ndarray, dict]:
    """The pixels as uint16 levels (one step for all axes, HEADROOM free at both ends), and the record that
    turns them back into coordinates.
    """
    p = np.asarray(image.pixels, np.float64)
    valid = image.valid
    if not np.isfinite(p[valid]).all():
        raise ImageError("pixels: NaN or infinite coordinates cannot be coded")
    shape = p[valid]
    lo, step = _grid(shape.min(axis=0), float((shape.max(axis=0) - shape.min(axis=0)).max()))
    q = _to_levels(p, lo, step)           # a masked pixel too: a reader skips it (see continue_masked)
    kept = {k: v for k, v in image.metadata_record().items() if k in KEPT or k in type(image.domain).METADATA_KEYS}
    record = {"offset": lo.tolist(), "step": step, "headroom": HEADROOM, "meta": kept}
    if image.mask is not None:
        record["mask"] = np.packbits(image.mask.ravel()).tobytes()
    return q.astype(np.uint16), record


def continue_masked(image: GeometryImage) -> GeometryImage:
    """The image with each masked pixel set to the smooth continuation of the valid ones (their biharmonic
    inpainting, scikit-image), the mask kept: what a wavelet coder codes in fewest bytes where a reader reads
    nothing. A constant in the holes makes a step at every chart's edge that the coder pays for at every level
    (a 129² multi-chart image of an 11-hole beetle at the coder's same target: 6,472 bytes and 56.2 dB from
    its pixels with the holes constant, 3,501 bytes and 55.4 dB continued). An image without a mask comes back as it is.

    Examples
    --------
    >>> import geoimg
    >>> u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 9))
    >>> mask = np.ones((9, 9), bool); mask[3:6, 3:6] = False
    >>> img = geoimg.GeometryImage(np.dstack([u, v, u * v]).astype(np.float32), mask)
    >>> out = continue_masked(img)
    >>> bool(np.array_equal(out.pixels[mask], img.pixels[mask])), round(float(out.pixels[4, 4, 0]), 3)
    (True, 0.5)
    """
    if image.mask is None or image.valid.all() or not image.valid.any():
        return image
    from skimage.restoration import inpaint_biharmonic      # here: reading a file starts without scikit-image

    valid = image.valid
    known = np.where(valid[..., None], np.asarray(image.pixels, np.float64), 0.0)
    filled = inpaint_biharmonic(known, ~valid, channel_axis=-1)
    pixels = np.where(valid[..., None], image.pixels, filled.astype(np.float32))
    return dataclasses.replace(image, pixels=pixels)


def _grid(lo: np.ndarray, span: float) -> tuple[np.ndarray, float]:
    """The quantization of values from ``lo`` (per channel) over ``span``: its offset and its step (``span``
    over :data:`TOP` levels), each with as few digits as keep it within 1/64 of a step (both quantize with what
    is written).
    """
    step = max(span, 1e-300) / TOP
    step = _short(step, step / 64 / TOP)
    return np.array([_short(x, step / 64) for x in np.atleast_1d(lo)]), step


def _to_levels(values: np.ndarray, lo, step: float) -> np.ndarray:
    """``values`` as levels of :func:`_grid`'s quantization, :data:`HEADROOM` free at both ends (float)."""
    return np.clip(np.round((values - lo) / step) + HEADROOM, 0, 65535)


def _from_levels(q: np.ndarray, lo, step: float, headroom: float) -> np.ndarray:
    """Levels back to values (float64): the inverse of :func:`_to_levels`."""
    return (q.astype(np.float64) - headroom) * step + lo


def _wavelet_levels(shape: tuple) -> int:
    """The codestream's resolutions for an image of ``shape``: as many as its size allows, at most 6."""
    return int(max(1, min(6, np.floor(np.log2(min(shape[:2]))))))


def _short(x: float, within: float) -> float:
    """``x`` with the fewest significant digits that stay ``within`` of it."""
    for digits in range(4, 17):
        y = float(f"{x:.{digits}g}")
        if abs(y - x) <= within:
            return y
    return float(x)


def _pack_record(record: dict) -> bytes:
    """The record box's payload after the UUID: version 1, raw DEFLATE with :data:`RECORD_DICTIONARY` of the
    record's JSON, a NUL, and the mask's packed bits (about 70 bytes without a mask, where zlib'd JSON with the
    mask in base64 took 170 and more).
    """
    fields = {k: v for k, v in record.items() if k != "mask"}
    mask = record.get("mask")
    if mask is not None:
        fields["mask"] = 1
    text = json.dumps(fields, separators=(",", ":"), sort_keys=True).encode()
    packer = zlib.compressobj(9, zlib.DEFLATED, -15, 9, zlib.Z_DEFAULT_STRATEGY, RECORD_DICTIONARY)
    return RECORD_VERSION + packer.compress(text + b"\0" + (mask or b"")) + packer.flush()


def _unpack_record(payload: bytes) -> dict:
    """A record from its payload: version 1 (:func:`_pack_record`), or the first files' zlib'd JSON (mask in
    base64); the mask as packed bits. Raises zlib.error or ValueError on damage.
    """
    if payload[:1] == RECORD_VERSION:
        unpacker = zlib.decompressobj(-15, RECORD_DICTIONARY)
        raw = unpacker.decompress(payload[1:], 1 << 24)
        if unpacker.unconsumed_tail or b"\0" not in raw:
            raise ValueError("a record that does not end where its box does")
        text, _, mask = raw.partition(b"\0")
        record = json.loads(text)
        if isinstance(record, dict) and "mask" in record:
            record["mask"] = mask
        return record
    unpacker = zlib.decompressobj()
    record = json.loads(unpacker.decompress(payload, 1 << 24))
    if isinstance(record, dict) and isinstance(record.get("mask"), str):
        record["mask"] = zlib.decompressobj().decompress(base64.b64decode(record["mask"]), 1 << 24)
    return record


def encode(image: GeometryImage, level: float, *, resolutions: int | None = None, colors: bool = False,
           normals: bool = False, offsets: np.ndarray | None = None, offsets_level: float | None = None,
           offsets_weights: np.ndarray | None = None) -> bytes:
    """A JP2 file of ``image``: coded to about ``level`` dB of the coder's own PSNR (over the 16-bit range;
    ``0``: reversible, lossless after the quantization), geoimg's record in a box before the codestream.

    Parameters
    ----------
    image : GeometryImage
        The image (X, Y, Z; its mask and metadata are recorded; normals are not coded).
    level : float
        The coder's target PSNR in dB, or 0 for reversible coding.
    resolutions : int, optional
        Wavelet levels (default: as many as the image's size allows, at most 6).
    colors : bool, default False
        Also code the image's colours (three more channels, on :data:`COLOR_TOP` levels, at the same level),
        when it has them.
    normals : bool, default False
        Also code the image's normals (two more channels: the octahedral encoding of each unit normal, on
        :data:`NORMAL_TOP` levels), when it has them; otherwise a reader computes them from the grid.
    offsets : numpy.ndarray, optional
        (H, W) distances along the normals of ``image`` upsampled to H x W (see
        :mod:`geoimg.image._displacement`): ``image`` is then the base of a displaced image, and the offsets
        are coded as one 16-bit channel in a second codestream box after the base's (a JPEG 2000 reader that
        knows only the first shows the base).
    offsets_level : float, optional
        The coder's target PSNR for the offsets (0: reversible); ``level`` by default.
    offsets_weights : numpy.ndarray, optional
        (H, W): the offsets coded multiplied by these weights, which the reader divides by (see
        :func:`offsets_codestream`); none by default.

    Returns
    -------
    bytes
        The file's bytes.

    Examples
    --------
    >>> import geoimg
    >>> img = geoimg.GeometryImage(np.random.default_rng(0).random((9, 9, 3)).astype(np.float32))
    >>> len(encode(img, 60)) < len(encode(img, 0))
    True
    """
    q, record = _quantized(image)
    if colors and image.colors is not None:
        rgb = np.round(np.clip(np.asarray(image.colors[..., :3], np.float64), 0.0, 1.0) * COLOR_TOP).astype(np.uint16)
        q = np.concatenate([q, rgb], axis=2)
        record["colors"] = 3
    if normals and image.normals is not None:
        square = sphere_to_square(np.asarray(image.normals, np.float64))      # the octahedral map, in [0, 1]^2
        q = np.concatenate([q, np.round(square * NORMAL_TOP).astype(np.uint16)], axis=2)
        record["normals"] = 2
    if offsets is not None and (image.mask is not None or q.shape[2] != 3):
        raise ImageError("offsets: a displaced image has no mask, no coded colours and no coded normals")
    if offsets is not None and np.ndim(offsets) == 2:
        image.domain.check_shape(np.shape(offsets))          # the displaced image is of the base's domain
    if resolutions is None:
        resolutions = _wavelet_levels(q.shape)
    codec = _codec()
    if level == LOSSLESS:
        data = codec.jpeg2k_encode(q, codecformat="jp2", reversible=True, mct=False, resolutions=resolutions)
    else:
        data = codec.jpeg2k_encode(q, level=float(level), codecformat="jp2", reversible=False, mct=False,
                                   resolutions=resolutions)
    after = b""
    if offsets is not None:
        cs, record["offsets"] = offsets_codestream(offsets, level if offsets_level is None else offsets_level,
                                                   offsets_weights)
        after = struct.pack(">I4s", 8 + len(cs), b"jp2c") + cs
    return _with_record(bytes(data), record, after)


def offsets_codestream(offsets: np.ndarray, level: float, weights: np.ndarray | None = None) -> tuple[bytes, dict]:
    """The offsets (H, W) of a displaced image as one channel of 16-bit levels coded at ``level`` (a raw
    codestream without the coder's comment), and the record that turns the levels back into distances.

    Parameters
    ----------
    offsets : numpy.ndarray
        (H, W) distances, finite.
    level : float
        The coder's target PSNR in dB, or 0 for reversible coding.
    weights : numpy.ndarray, optional
        (H, W), positive: the offsets are coded multiplied by them, and the record says ``"weighted":
        "area"``: a reader divides by :func:`geoimg.image._displacement.area_weights` of the upsampled base,
        which these must be (the coder's error is then least in the surface's measure).

    Returns
    -------
    bytes, dict
        The codestream, and ``{"shape", "offset", "step"}`` (and ``"weighted"``).

    Examples
    --------
    >>> cs, fields = offsets_codestream(np.linspace(-1, 1, 64).reshape(8, 8), 60)
    >>> cs[:2].hex(), fields["shape"]                      # a codestream begins with SOC, 0xff4f
    ('ff4f', [8, 8])
    """
    h = np.asarray(offsets, np.float64)
    if h.ndim != 2 or min(h.shape) < 2:
        raise ImageError(f"offsets: expected an (H, W) array of at least 2 x 2, got shape {h.shape}")
    if not np.isfinite(h).all():
        raise ImageError("offsets: NaN or infinite distances cannot be coded")
    fields: dict = {}
    if weights is not None:
        w = np.asarray(weights, np.float64)
        if w.shape != h.shape:
            raise ImageError(f"offsets: expected {h.shape} positive finite weights, got shape {w.shape}")
        bad = int(np.sum(~(np.isfinite(w) & (w > 0))))
        if bad:
            raise ImageError(f"offsets: expected {h.shape} positive finite weights; {bad} of them are 0 or less, "
                             "NaN or infinite")
        h, fields = h * w, {"weighted": "area"}
    lows, step = _grid(np.array([h.min()]), float(np.ptp(h)))
    lo = float(lows[0])
    q = _to_levels(h, lo, step).astype(np.uint16)
    cs = _codec().jpeg2k_encode(q, level=float(level), codecformat="j2k", reversible=level == LOSSLESS,
                                resolutions=_wavelet_levels(q.shape))
    return without_comments(bytes(cs)), {"shape": list(q.shape), "offset": lo, "step": step, **fields}


def _with_record(data: bytes, record: dict, after: bytes = b"") -> bytes:
    """``data`` (a JP2 file) with a ``uuid`` box holding ``record`` before its codestream box, the
    codestream without the coder's comment, and the boxes ``after`` right after it.
    """
    payload = RECORD_UUID + _pack_record(record)
    box = struct.pack(">I4s", 8 + len(payload), b"uuid") + payload
    for kind, start, end in _boxes(data):
        if kind == b"jp2c":
            header = 16 if struct.unpack(">I", data[start:start + 4])[0] == 1 else 8
            cs = without_comments(data[start + header:end])
            return data[:start] + box + struct.pack(">I4s", 8 + len(cs), b"jp2c") + cs + after + data[end:]
    raise ImageError("the coder wrote no JPEG 2000 codestream box")


def _record(data: bytes, where: str) -> dict:
    """The geoimg record of a JP2 file's bytes, or an ImageFileError saying what the file is."""
    if not data.startswith(SIGNATURE):
        if 0 < len(data) < len(SIGNATURE) and SIGNATURE.startswith(data):
            raise ImageFileError(f"{where}: it ends after {len(data)} bytes, inside the JP2 signature; read more of "
                                 "the file")
        what = "a raw JPEG 2000 codestream (.j2k)" if data.startswith(b"\xff\x4f\xff\x51") else "not a JP2 file"
        raise ImageFileError(f"{where}: {what}; geoimg reads the JP2 files that geoimg compress writes")
    boxes = _boxes(data)
    for kind, start, end in boxes:
        if kind == b"uuid" and data[start + 8:start + 24] == RECORD_UUID:
            if start + struct.unpack(">I", data[start:start + 4])[0] > len(data):
                raise ImageFileError(f"{where}: it ends after {len(data)} bytes, inside geoimg's record; read more "
                                     "of the file")
            try:
                record = _unpack_record(data[start + 24:end])
            except (zlib.error, ValueError) as e:
                raise ImageFileError(f"{where}: geoimg's record is damaged ({type(e).__name__})") from None
            if not isinstance(record, dict) or not {"offset", "step", "headroom", "meta"} <= set(record):
                raise ImageFileError(f"{where}: geoimg's record lacks the quantization or the metadata")
            return record
    if not any(kind == b"jp2c" for kind, _, _ in boxes):
        raise ImageFileError(f"{where}: it ends after {len(data)} bytes, before geoimg's record and the codestream; "
                             "read more of the file")
    raise ImageFileError(f"{where}: a JPEG 2000 file without geoimg's record: its pixels are a picture, not "
                         "coordinates (geoimg compress writes geometry images)")


def _prefix(data: bytes, max_bytes: int | None, where: str) -> tuple[bytes, str | None, bytes | None, str | None]:
    """The whole file to decode and, when it is not all of ``data``, how many resolution levels it holds of
    how many: the first ``max_bytes`` (or a truncated file's bytes, with a warning), its codestream cut after
    the last resolution level they hold whole. Then a displaced image's offsets codestream (the second
    codestream box) likewise, or None where those bytes hold none of its levels whole.
    """
    asked = max_bytes is not None
    head = data[:max_bytes] if asked else data
    what = f"the first {len(head)} bytes hold" if asked else f"truncated after {len(data)} bytes, it holds"
    found = [(start, end) for kind, start, end in _boxes(head) if kind == b"jp2c"]
    if not found:
        raise ImageFileError(f"{where}: {what} no JPEG 2000 codestream (geoimg's record and the header come "
                             "first); read more of the file")
    (start, end), second = found[0], (found[1] if len(found) > 1 else None)
    cs, levels = _whole_levels(head, start, where, what)
    if levels is not None and not asked:
        warnings.warn(f"{where}: truncated after {len(data)} bytes: decoded its first {levels} resolution levels",
                      stacklevel=4)
    used = head[:end] if levels is None else head[:start] + struct.pack(">I4s", 8 + len(cs), b"jp2c") + cs
    offsets, offset_levels = None, None
    if second is not None:
        try:
            offsets, offset_levels = _whole_levels(head, second[0], where, what)
        except ImageFileError:
            if not asked:
                raise
        if offset_levels is not None and not asked:
            warnings.warn(f"{where}: truncated after {len(data)} bytes: decoded its offsets' first {offset_levels} "
                          "resolution levels", stacklevel=4)
    return used, levels, offsets, offset_levels


def _whole_levels(head: bytes, start: int, where: str, what: str) -> tuple[bytes, str | None]:
    """The codestream of the box at ``start`` in ``head``: whole, or cut after the last resolution level it
    holds whole, and then how many levels of how many.
    """
    length = struct.unpack(">I", head[start:start + 4])[0]
    if length == 0 or start + length <= len(head):          # the codestream is whole (a box to the end: as given)
        return head[start + 8:(start + length) if length else len(head)], None
    cs = head[start + 8:]
    try:
        layout, ends = read_layout(cs), resolution_ends(cs)
    except ImageFileError as e:
        raise ImageFileError(f"{where}: {what} no whole resolution level ({e}); read more of the file") from None
    if not ends:
        raise ImageFileError(f"{where}: {what} no whole resolution level (the coarsest needs more); read more "
                             "of the file")
    r = len(ends) - 1
    return cut_after(cs, r, ends), f"{r + 1} of {layout.levels + 1}"


def decode(data: bytes, where: str = "data", *, max_bytes: int | None = None) -> GeometryImage:
    """The geometry image of a JP2 file's bytes written by :func:`encode`: the levels back to coordinates,
    glued pixels welded (each group set to its mean), the mask and metadata restored.

    Parameters
    ----------
    data : bytes
        The file's bytes.
    where : str
        What to call the data in errors (a path).
    max_bytes : int, optional
        Decode only the first ``max_bytes`` bytes: the shape as far as the whole wavelet levels they hold go
        (a coarser shape, at the same resolution); ``metadata["jpeg2000_levels"]`` says how many of how many.
        Of a displaced file, the base (at its own size, ``metadata["jpeg2000_offset_levels"]`` ``"none"``)
        until the offsets' first level is whole, then the offsets' whole levels. A truncated file is decoded so
        too, with a warning.

    Returns
    -------
    GeometryImage
        The image, float32.

    Raises
    ------
    ImageFileError
        When the bytes are not such a file: another JPEG 2000 image, a truncated or damaged one.

    Examples
    --------
    >>> decode(b"not an image")
    Traceback (most recent call last):
    ...
    geoimg.errors.ImageFileError: data: not a JP2 file; geoimg reads the JP2 files that geoimg compress writes
    """
    data = bytes(data)
    record = _record(data, where)
    if max_bytes is not None and (isinstance(max_bytes, bool) or not isinstance(max_bytes, (int, np.integer))
                                  or max_bytes < 1):
        raise InputError(f"max_bytes: expected a whole number of bytes, got {max_bytes!r}")
    used, levels, offsets, offset_levels = _prefix(data, max_bytes, where)
    try:
        q = np.asarray(_codec().jpeg2k_decode(used))
    except Exception as e:                   # imagecodecs' own error type: a truncated or damaged codestream
        raise ImageFileError(f"{where}: the JPEG 2000 codestream cannot be decoded, truncated or damaged "
                             f"({' '.join(str(e).split())[:120]})") from None
    colored, normal = bool(record.get("colors")), bool(record.get("normals"))
    channels = 3 + 3 * colored + 2 * normal
    if q.ndim != 3 or q.shape[2] != channels or q.dtype != np.uint16:
        raise ImageFileError(f"{where}: pixels of shape {q.shape} and type {q.dtype}; its record asks for "
                             f"{channels} 16-bit channels")
    colors = np.clip(q[..., 3:6].astype(np.float32) / COLOR_TOP, 0.0, 1.0) if colored else None
    normals = None
    if normal:
        normals = square_to_sphere(np.clip(q[..., channels - 2:].astype(np.float64) / NORMAL_TOP, 0.0, 1.0))
    q = q[..., :3]
    meta = dict(record["meta"])
    try:
        step, offset = float(record["step"]), np.asarray(record["offset"], np.float64).reshape(3)
        domain = Domain.from_metadata(meta.pop("domain", "planar"), meta)
        mask = None
        if "mask" in record:
            bits = np.frombuffer(record["mask"], np.uint8)
            mask = np.unpackbits(bits)[: q.shape[0] * q.shape[1]].reshape(q.shape[:2]).astype(bool)
        pixels = _from_levels(q, offset, step, float(record["headroom"]))
        pixels = domain.average_glued(pixels)
        if "offsets" in record:
            if mask is not None or colored or normal:
                raise ValueError("a displaced image with a mask, colours or normals")
            if offsets is not None:
                meta["jpeg2000_base"] = f"{pixels.shape[1]} x {pixels.shape[0]}"     # what geoimg info shows
                pixels = _displaced(pixels, domain, record["offsets"], offsets, float(record["headroom"]), where)
                if offset_levels is not None:
                    meta["jpeg2000_offset_levels"] = offset_levels
            else:
                meta["jpeg2000_offset_levels"] = "none"
        if normals is not None:                  # glued normals: one direction, the group's mean
            normals = domain.average_glued(normals)
            normals = (normals / np.maximum(np.linalg.norm(normals, axis=-1, keepdims=True), 1e-300)).astype(np.float32)
        meta.update(jpeg2000_bytes=min(len(data), max_bytes or len(data)))
        if levels is not None:
            meta["jpeg2000_levels"] = levels
        return GeometryImage(pixels.astype(np.float32), mask, domain, normals=normals, metadata=meta, colors=colors)
    except ImageFileError:                   # the offsets' codestream: said in its own words
        raise
    except (TypeError, ValueError, zlib.error) as e:
        raise ImageFileError(f"{where}: geoimg's record does not fit its pixels ({' '.join(str(e).split())[:120]})"
                             ) from None


def _displaced(base: np.ndarray, domain: Domain, fields: dict, cs: bytes, headroom: float, where: str) -> np.ndarray:
    """A displaced image's pixels: the decoded ``base`` upsampled, moved along its normals by the offsets that
    the codestream ``cs`` holds (quantized as ``fields`` say), glued pixels welded.
    """
    shape = tuple(int(k) for k in fields["shape"])
    if len(shape) != 2 or not 2 <= min(shape) <= max(shape) <= 1 << 16 or min(base.shape[:2]) < 2:
        raise ValueError(f"an offsets image of shape {shape} on a base of {base.shape[:2]}")
    try:
        q = np.asarray(_codec().jpeg2k_decode(cs))
    except Exception as e:                   # imagecodecs' own error type: a truncated or damaged codestream
        raise ImageFileError(f"{where}: the offsets' JPEG 2000 codestream cannot be decoded, truncated or damaged "
                             f"({' '.join(str(e).split())[:120]})") from None
    if q.shape != shape or q.dtype != np.uint16:
        raise ImageFileError(f"{where}: offsets of shape {q.shape} and type {q.dtype}; its record asks for {shape} "
                             "16-bit levels")
    weighted = fields.get("weighted")
    if weighted not in (None, "area"):
        raise ValueError(f"offsets weighted by {str(weighted)[:40]!r}, which this reader does not know")
    distances = _from_levels(q, float(fields["offset"]), float(fields["step"]), headroom)
    points, normals = base_frame(base, domain, shape)
    if weighted is not None:
        distances = distances / area_weights(points, domain)
    return displace(points, normals, distances, domain)


def read_jp2(path, max_bytes: int | None = None) -> GeometryImage:
    r"""The geometry image of a ``.jp2`` file written by ``geoimg compress`` (see :func:`decode`).

    Parameters
    ----------
    path : path-like
        The file.
    max_bytes : int, optional
        Read only its first bytes (see :func:`decode`): what a viewer streaming the file has so far.

    Returns
    -------
    GeometryImage
        The image.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "x.jp2"
    >>> _ = p.write_bytes(b"\x00" * 20)
    >>> read_jp2(p)
    Traceback (most recent call last):
    ...
    geoimg.errors.ImageFileError: ...x.jp2: not a JP2 file; geoimg reads the JP2 files that geoimg compress writes
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    if max_bytes is not None and not isinstance(max_bytes, bool) and isinstance(max_bytes, (int, np.integer)):
        with open(path, "rb") as f:                   # no more than the file holds, however many are asked
            return decode(f.read(max(min(int(max_bytes), path.stat().st_size), 0)), str(path), max_bytes=max_bytes)
    return decode(path.read_bytes(), str(path), max_bytes=max_bytes)
