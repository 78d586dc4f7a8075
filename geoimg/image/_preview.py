"""16-bit PNG previews of geometry images: X, Y, Z each stretched over its range on the valid pixels to the
levels 1 to 65535, masked pixels 0; each channel's offset and step and the image's record in the text attribute
``geoimg:preview``, so that a preview can be read back as approximate geometry when asked.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._raster import UINT16, read_raster, write_raster
from ..errors import ImageFileError

__all__ = ["PREVIEW_LEVELS", "write_preview", "read_preview"]

PREVIEW_LEVELS = 65534                # a preview's valid pixels take the levels 1 to 65535; 0 is masked


def write_preview(tmp: Path, levels: np.ndarray, offset: np.ndarray, step: np.ndarray, record: dict) -> None:
    """Write the levels (H, W, 3) with each axis' offset and step and the image's record."""
    text = json.dumps({**record, "preview_offset": offset.tolist(), "preview_step": step.tolist()}, sort_keys=True)
    write_raster(tmp, levels.astype(np.uint16), ["R", "G", "B"], UINT16, [("geoimg:preview", text)])


def read_preview(path, approximate: bool) -> tuple[np.ndarray, np.ndarray, dict]:
    """A preview decoded back to coordinates: pixels (H, W, 3) float32, the valid pixels and the record, with
    ``approximate`` saying how far the coordinates may be off.

    Raises
    ------
    ImageFileError
        Not a geoimg preview, not asked for approximately, or damaged.
    """
    data, _, attrs = read_raster(path, ("geoimg:preview",))
    if attrs[0] is None:
        raise ImageFileError(f"{path}: its pixels are integers, not coordinates, and it is not a geoimg preview: a "
                             "picture cannot become geometry (geometry images are float EXR or .npz files)")
    if not approximate:
        raise ImageFileError(f"{path}: a 16-bit preview, its coordinates rounded to 1/{PREVIEW_LEVELS} of each "
                             "axis' range; to read it as approximate geometry, say so: load_image(path, "
                             "approximate=True) (--approximate on the command line)")
    try:
        record = json.loads(attrs[0])
        offset = np.asarray(record.pop("preview_offset"), np.float64)
        step = np.asarray(record.pop("preview_step"), np.float64)
        if offset.shape != (3,) or step.shape != (3,) or not (np.isfinite(offset).all() and np.isfinite(step).all()):
            raise ValueError("offset and step must be 3 finite numbers each")
    except (json.JSONDecodeError, KeyError, TypeError, ValueError, AttributeError) as e:
        raise ImageFileError(f"{path}: geoimg:preview is damaged ({e})") from None
    if data.ndim != 3 or data.shape[2] != 3:
        raise ImageFileError(f"{path}: a preview has 3 channels, this file {data.shape[-1]}")
    q = np.round(data.astype(np.float64) * (PREVIEW_LEVELS + 1))             # the 16-bit levels 0 .. 65535
    valid = q.min(axis=2) >= 1
    pixels = np.where(valid[..., None], offset + (q - 1.0) * step, offset).astype(np.float32)
    record["approximate"] = f"read from a 16-bit preview; within half a step {step.tolist()} of the original"
    return pixels, valid, record
