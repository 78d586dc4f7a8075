"""Geometry images as float TIFF: four float32 channels X, Y, Z and the mask as alpha (OpenCV,
scikit-image/tifffile and GIMP read it), geoimg's record as JSON in the ImageDescription tag; no normals or
colours (.exr and .npz keep them).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._raster import FLOAT, read_raster, write_raster
from ..errors import ImageFileError
from ._exr import FLOATS_ONLY

__all__ = ["write_tiff", "read_tiff", "TIFF_DESCRIPTION"]

TIFF_DESCRIPTION = "geoimg"           # the key of the record a TIFF keeps in its ImageDescription tag


def write_tiff(tmp: Path, data: np.ndarray, names: list, record: dict, domain: str) -> None:
    """Write the first four planes (X, Y, Z, alpha) with geoimg's record."""
    description = json.dumps({TIFF_DESCRIPTION: {"domain": domain, "metadata": record}}, sort_keys=True)
    write_raster(tmp, data[..., :4], names[:4], FLOAT,      # zip without a float predictor: tifffile reads it
                 [("ImageDescription", description), ("compression", "zip"), ("tiff:Predictor", 1)])


def read_tiff(path) -> tuple[np.ndarray, list, dict | None, str | None]:
    """The planes, their names (R, G, B, A with a record), the metadata and the domain's kind (both None: no
    geoimg record).

    Raises
    ------
    ImageFileError
        Not a float image, or a damaged record.
    """
    data, names, attrs = read_raster(path, ("ImageDescription",), integers=FLOATS_ONLY)
    record = _record(path, attrs[0])
    if record is None:
        return data, names, None, None
    return data, ["R", "G", "B", "A"][: data.shape[2]], record.get("metadata", {}), record.get("domain")


def _record(path, description):
    """The geoimg record of a TIFF's ImageDescription, or None when it has none."""
    try:
        record = json.loads(description) if description else None
    except json.JSONDecodeError:
        return None                                     # another program's description
    if not isinstance(record, dict) or TIFF_DESCRIPTION not in record:
        return None
    if not isinstance(record[TIFF_DESCRIPTION], dict):
        raise ImageFileError(f"{path}: its geoimg record is not a JSON object")
    return record[TIFF_DESCRIPTION]
