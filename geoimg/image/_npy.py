"""Geometry images as a NumPy ``.npy`` array and its sidecar: one float32 (H, W, C) array, the EXR's channels in
its order (X, Y, Z first), and beside it ``NAME.npy.json`` with the channel names, the domain and the metadata
(both files or neither). No pickles: ``np.load(path)`` reads the array anywhere.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .._budget import check_memory
from ..errors import ImageFileError
from ._npz import _header

__all__ = ["NPY_SIDECAR", "npy_jobs", "read_npy", "read_npy_image"]

NPY_SIDECAR = ".json"                 # x.npy's channel names and metadata are in x.npy.json


def npy_jobs(path: Path, data: np.ndarray, names: list, record: dict, domain: str) -> list:
    """``(path, write)`` for the array and its sidecar (see :func:`geoimg._atomic.write_all`)."""
    sidecar = json.dumps({"channels": names, "domain": domain, "metadata": record}, sort_keys=True)
    return [(path, lambda tmp: _save(tmp, data)),
            (path.with_name(path.name + NPY_SIDECAR), lambda tmp: tmp.write_text(sidecar + "\n"))]


def _save(tmp: Path, data: np.ndarray) -> None:
    with open(tmp, "wb") as f:
        np.save(f, data, allow_pickle=False)


def read_npy(path) -> np.ndarray:
    """A ``.npy`` file's (H, W, C) float array, its header checked (kind, dimensions, the memory it would
    take) before it is read; no pickles.

    Raises
    ------
    ImageFileError
        Not a ``.npy`` file, or not a float array of 3 dimensions with at least 3 channels.
    """
    path = Path(path)
    try:
        with open(path, "rb") as f:
            shape, dtype = _header(f)
    except (ValueError, OSError, EOFError) as e:
        raise ImageFileError(f"{path}: not a .npy array ({e})") from None
    if dtype.kind != "f" or len(shape) != 3 or shape[2] < 3:
        raise ImageFileError(f"{path}: a {len(shape)}-D {dtype} array of shape {shape}; a geometry image is an "
                             "(H, W, C) float array with X, Y, Z first")
    check_memory(float(np.prod(shape, dtype=np.float64)) * dtype.itemsize, str(path))
    try:
        return np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError, OverflowError) as e:
        raise ImageFileError(f"{path}: cannot be read ({e})") from None


def read_npy_image(path) -> tuple[np.ndarray, list, dict | None, str | None]:
    """The array, its channel names, metadata and domain kind from the sidecar; without a sidecar an (H, W, 3)
    array of X, Y, Z with no metadata and no domain (read only when the caller assumes one).

    Raises
    ------
    FileNotFoundError
        No such file.
    ImageFileError
        Not a geometry image's array, or a damaged sidecar.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    data = read_npy(path)
    sidecar = path.with_name(path.name + NPY_SIDECAR)
    if not sidecar.is_file():
        if data.shape[2] != 3:
            raise ImageFileError(f"{path}: {data.shape[2]} channels and no {sidecar.name} naming them; an array "
                                 "without geoimg's sidecar must be (H, W, 3): X, Y, Z")
        return data, ["R", "G", "B"], None, None
    try:
        record = json.loads(sidecar.read_text(encoding="utf-8"))
        names, domain, meta = record["channels"], record["domain"], record["metadata"]
        if not (isinstance(names, list) and len(names) == data.shape[2] and all(isinstance(n, str) for n in names)):
            raise ValueError(f"channels must name the array's {data.shape[2]} channels")
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError, ValueError) as e:
        raise ImageFileError(f"{sidecar}: not a geoimg sidecar ({type(e).__name__}: {e})") from None
    return data, names, meta, domain
