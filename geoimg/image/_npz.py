"""Geometry images as NumPy ``.npz`` archives: ``positions`` (H, W, 3) float32, ``mask`` (H, W) bool and
``normals`` (H, W, 3) and ``colors`` (H, W, 3 or 4) float32 when the image has them, and ``metadata``: the metadata
and the domain's
fields as JSON text (the same record the EXR keeps). Plain arrays, no pickles: ``np.load(path)`` reads
them anywhere, and :func:`geoimg.load_image` reads them back bit for bit.
"""
from __future__ import annotations

import json
import zipfile
import zlib
from pathlib import Path

import numpy as np

from .._budget import check_memory
from ..errors import ImageFileError

__all__ = ["write_npz", "read_npz", "read_arrays", "NPZ_ARRAYS"]

NPZ_ARRAYS = ("positions", "mask", "normals", "metadata", "colors")
_SHAPES = {"positions": 3, "normals": 3, "mask": 2, "metadata": 0, "colors": 3}
MAX_DIMENSION = 1 << 31   # no geometry image has a side, or channels, beyond this
DAMAGED_ZIP = (zlib.error, EOFError, OSError, NotImplementedError, RuntimeError)   # what zipfile raises besides
_KINDS = {"positions": "f", "normals": "f", "mask": "b", "metadata": "U", "colors": "f"}


def write_npz(path: Path, pixels: np.ndarray, mask, normals, record: dict, colors=None) -> None:
    """Write the arrays and the metadata ``record`` (plain JSON types) to ``path`` (compressed)."""
    arrays = {"positions": np.asarray(pixels, np.float32), "metadata": np.array(json.dumps(record, sort_keys=True))}
    if mask is not None:
        arrays["mask"] = np.asarray(mask, bool)
    if normals is not None:
        arrays["normals"] = np.asarray(normals, np.float32)
    if colors is not None:
        arrays["colors"] = np.asarray(colors, np.float32)
    with open(path, "wb") as f:
        np.savez_compressed(f, **arrays)       # type: ignore[arg-type]   # numpy's stub: allow_pickle


def _header(f) -> tuple[tuple, np.dtype]:
    """(shape, dtype) of the array in an open ``.npy`` stream, read from its header alone (nothing unpacked)."""
    try:
        version = np.lib.format.read_magic(f)
        read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
        shape, _, dtype = read(f)
    except ValueError:
        raise
    except Exception as e:     # noqa: BLE001 - numpy parses the header's text with tokenize and literal_eval,
        # which raise TokenError, SyntaxError, MemoryError, RecursionError ... on a damaged one
        raise ValueError(f"a damaged .npy header ({type(e).__name__}: {e})") from None
    if any(d > MAX_DIMENSION for d in shape):       # numpy's reader overflows on such a size, even with a 0 beside it
        raise ValueError(f"a .npy header declaring shape {shape}: a size beyond {MAX_DIMENSION}")
    return shape, dtype


def read_arrays(path, kinds: dict[str, tuple[str, int]], required: str, what: str) -> dict[str, np.ndarray]:
    """The arrays of a ``.npz`` archive whose members are named in ``kinds`` (``name -> (dtype kind,
    dimensions)``), ``required`` among them, each member's header checked (kind, dimensions, the memory it
    would take) before anything is read; no pickles. ``what`` names such a file in the errors.

    Raises
    ------
    ImageFileError
        Not a zip archive of arrays, pickled objects, a missing or unknown member, wrong kinds or dimensions.
    """
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as archive:
            names = {n[:-4] for n in archive.namelist() if n.endswith(".npy")}
            unknown = sorted(set(archive.namelist()) - {n + ".npy" for n in kinds})
            if unknown or required not in names:
                others = ", ".join(n for n in kinds if n != required)
                raise ImageFileError(f"{path}: not a {what} (members: "
                                     f"{', '.join(sorted(archive.namelist())) or 'none'}; expected {required} and "
                                     f"optionally {others})")
            for name in names:
                with archive.open(name + ".npy") as f:
                    shape, dtype = _header(f)
                kind, dims = kinds[name]
                if dtype.kind != kind or len(shape) != dims:
                    raise ImageFileError(f"{path}: {name} is a {len(shape)}-D {dtype} array; expected "
                                         f"{dims}-D of kind {kind!r}")
                check_memory(float(np.prod(shape, dtype=np.float64)) * dtype.itemsize, f"{path}: {name}")
    except zipfile.BadZipFile as e:
        raise ImageFileError(f"{path}: not a .npz archive ({e})") from None
    except ImageFileError:
        raise
    except ValueError as e:                         # a corrupt .npy header
        raise ImageFileError(f"{path}: {e}") from None
    except DAMAGED_ZIP as e:                        # a member that does not inflate, an unknown compression ...
        raise ImageFileError(f"{path}: a damaged .npz archive ({type(e).__name__}: {e})") from None
    try:
        with np.load(path, allow_pickle=False) as data:
            return {name: data[name] for name in names}
    except (ValueError, zipfile.BadZipFile, *DAMAGED_ZIP) as e:
        raise ImageFileError(f"{path}: cannot be read ({e})") from None


def read_npz(path) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, dict, np.ndarray | None]:
    """``(positions, mask, normals, record, colors)`` of a file written by :func:`write_npz`, each array's header
    checked (kind, dimensions, the memory it would take) before it is read (:func:`read_arrays`).

    Raises
    ------
    ImageFileError
        Not a zip archive of arrays, pickled objects, a missing or unknown member, wrong kinds or shapes,
        metadata that is not a JSON object.
    """
    path = Path(path)
    arrays = read_arrays(path, {name: (_KINDS[name], _SHAPES[name]) for name in NPZ_ARRAYS}, "positions",
                         "geoimg .npz geometry image")
    record = {}
    if "metadata" in arrays:
        try:
            record = json.loads(str(arrays["metadata"]))
        except json.JSONDecodeError as e:
            raise ImageFileError(f"{path}: metadata is not valid JSON ({e})") from None
        if not isinstance(record, dict):
            raise ImageFileError(f"{path}: metadata is not a JSON object")
    return arrays["positions"], arrays.get("mask"), arrays.get("normals"), record, arrays.get("colors")


