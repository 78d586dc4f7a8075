"""Geometry images as OpenEXR: channels ``R, G, B`` (X, Y, Z), ``mask`` (or ``A``), ``N.X, N.Y, N.Z`` and
``color.R ...`` float32, zip-compressed; the metadata and the domain's fields as JSON in ``geoimg:metadata``, the
domain's kind also in ``geoimg:domain`` (through OpenImageIO).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._raster import FLOAT, read_raster, write_raster
from ..errors import ImageFileError

__all__ = ["write_exr", "read_exr", "FLOATS_ONLY"]

FLOATS_ONLY = ("its pixels are integers, not coordinates: a preview or picture cannot become geometry (geometry "
               "images are float files written by geoimg)")


def write_exr(tmp: Path, data: np.ndarray, names: list, record: dict, domain: str) -> None:
    """Write the planes ``data`` (H, W, C) named ``names`` with geoimg's record."""
    attrs = [("geoimg:domain", domain), ("geoimg:metadata", json.dumps(record, sort_keys=True)),
             ("compression", "zip")]
    write_raster(tmp, data, names, FLOAT, attrs)


def read_exr(path) -> tuple[np.ndarray, list, dict | None, str | None]:
    """The planes, their names, the metadata and the domain's kind (both None: no geoimg record).

    Raises
    ------
    ImageFileError
        Not a float image, or a damaged record.
    """
    data, names, attrs = read_raster(path, ("geoimg:metadata", "geoimg:domain"), integers=FLOATS_ONLY)
    for name, value in zip(("geoimg:metadata", "geoimg:domain"), attrs):
        if value is not None and not isinstance(value, str):
            raise ImageFileError(f"{path}: its {name} attribute is not text but {type(value).__name__} "
                                 f"{str(value)[:60]}")
    meta = _parsed_metadata(path, attrs[0]) if attrs[0] is not None else None if attrs[1] is None else {}
    return data, names, meta, attrs[1]


def _parsed_metadata(path, text: str):
    """An EXR's ``geoimg:metadata`` attribute, parsed (empty: no fields)."""
    try:
        return json.loads(text) if text else {}
    except json.JSONDecodeError as e:
        raise ImageFileError(f"{path}: geoimg:metadata is not valid JSON ({e})") from None
