"""A Zarr store of same-size geometry images for learning pipelines: ``positions`` (N, R, R, 3) float32,
``mask`` (N, R, R) bool and, when asked, ``normals`` (N, R, R, 3) and ``colors`` (N, R, R, 3: RGB in [0, 1],
NaN for an item without colours), one chunk per item, each written by the
worker that made it; one metadata record per item in the group's attributes, written by the batch's driver
when the item is complete (an item without a record is not there: it is redone on the next run).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .._optional import require
from ..errors import InputError
from ..image import Domain, GeometryImage
from .._types import PathLike

__all__ = ["open_store", "write_item", "write_records", "read_item", "store_records"]

KEY = "geoimg"


def _zarr():
    return require("zarr", "geoimg batch --zarr")


def open_store(path, sources: list[str], resolution: int, normals: bool, options_hash: str, *,
               force: bool = False, colors: bool = False):
    """Create the store for ``sources`` (one item each) at ``resolution`` pixels a side, or open the one a
    previous run of the same batch made. A store made from other inputs or options is refused unless
    ``force`` (then it is replaced).
    """
    zarr = _zarr()
    path = Path(path)
    if path.exists() and not force:
        try:
            group = zarr.open_group(str(path), mode="r+")
            info = dict(group.attrs).get(KEY)
        except Exception as e:               # not a Zarr group at all: zarr raises several kinds
            raise InputError(f"{path} exists and is not a geoimg Zarr store ({type(e).__name__}); choose "
                             "another --zarr path or --force to replace it") from None
        if not info or info.get("sources") != sources or info.get("options_hash") != options_hash:
            raise InputError(f"{path} holds another batch (other inputs or options); choose another --zarr path "
                             "or --force to replace it")
        return group
    group = zarr.open_group(str(path), mode="w")
    n, r = len(sources), resolution
    group.create_array("positions", shape=(n, r, r, 3), chunks=(1, r, r, 3), dtype="float32", fill_value=np.nan)
    group.create_array("mask", shape=(n, r, r), chunks=(1, r, r), dtype="bool", fill_value=False)
    if normals:
        group.create_array("normals", shape=(n, r, r, 3), chunks=(1, r, r, 3), dtype="float32", fill_value=np.nan)
    if colors:                       # chunks of items without colours are never written: they take no room
        group.create_array("colors", shape=(n, r, r, 3), chunks=(1, r, r, 3), dtype="float32", fill_value=np.nan)
    group.attrs[KEY] = {"sources": sources, "resolution": r, "options_hash": options_hash, "items": [None] * n}
    return group


def write_item(path, index: int, image: GeometryImage) -> None:
    """Write one image into item ``index`` (top-left corner; the rest masked out)."""
    group = _zarr().open_group(str(path), mode="r+")
    r = group["positions"].shape[1]
    H, W = image.shape
    if H > r or W > r:
        raise InputError(f"a {W} x {H} image does not fit the store's {r} x {r} items")
    pos = np.full((r, r, 3), np.nan, np.float32)
    pos[:H, :W] = image.pixels
    mask = np.zeros((r, r), bool)
    mask[:H, :W] = image.valid
    group["positions"][index] = pos
    group["mask"][index] = mask
    if "normals" in group:
        nrm = np.full((r, r, 3), np.nan, np.float32)
        if image.normals is not None:
            nrm[:H, :W] = image.normals
        group["normals"][index] = nrm
    if "colors" in group and image.colors is not None:
        rgb = np.full((r, r, 3), np.nan, np.float32)
        rgb[:H, :W] = image.colors[..., :3]
        group["colors"][index] = rgb


def write_records(path, records: dict[int, dict]) -> None:
    """Record the items in ``records`` (index -> record) as complete."""
    group = _zarr().open_group(str(path), mode="r+")
    info = dict(group.attrs[KEY])
    items = list(info["items"])
    for i, rec in records.items():
        items[i] = rec
    info["items"] = items
    group.attrs[KEY] = info


def store_records(path: PathLike) -> list[dict | None]:
    """Each item's record, None for an item not written.

    Parameters
    ----------
    path : path-like
        The Zarr store.

    Returns
    -------
    list of dict or None
        One record per item: source, shape, domain, metadata, PSNR and timings.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from geoimg.batch._store import open_store                 # what convert does first
    >>> store = pathlib.Path(tempfile.mkdtemp()) / "data.zarr"
    >>> _ = open_store(store, ["a.obj", "b.obj"], 5, normals=True, options_hash="x")
    >>> store_records(store)                                     # nothing written yet
    [None, None]
    """
    return list(dict(_zarr().open_group(str(path), mode="r").attrs)[KEY]["items"])


def read_item(path: PathLike, index: int) -> GeometryImage:
    """Item ``index`` of a store as a GeometryImage (its domain and metadata from the item's record).

    Raises
    ------
    InputError
        If the item was not written.

    Parameters
    ----------
    path : path-like
        The Zarr store :func:`convert` wrote.
    index : int
        The item's number (the input's row in the store's order).

    Returns
    -------
    GeometryImage
        The item's image, mask and normals.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from geoimg import GeometryImage
    >>> from geoimg.batch._store import open_store, write_item, write_records   # what convert's workers do
    >>> store = pathlib.Path(tempfile.mkdtemp()) / "data.zarr"
    >>> _ = open_store(store, ["a.obj"], 3, normals=False, options_hash="x")
    >>> write_item(store, 0, GeometryImage(np.ones((3, 3, 3), np.float32)))
    >>> write_records(store, {0: {"source": "a.obj", "domain": "planar", "shape": [3, 3], "metadata": {}}})
    >>> read_item(store, 0).pixels.sum().item(), store_records(store)[0]["source"]
    (27.0, 'a.obj')
    """
    group = _zarr().open_group(str(path), mode="r")
    records = dict(group.attrs)[KEY]["items"]
    if not 0 <= index < len(records):
        raise InputError(f"index: expected 0 to {len(records) - 1}, got {index}")
    rec = records[index]
    if rec is None:
        raise InputError(f"item {index} of {path} was not written")
    H, W = rec["shape"]
    meta = rec["metadata"]
    normals = group["normals"][index, :H, :W] if "normals" in group and rec.get("normals") else None
    colors = group["colors"][index, :H, :W] if "colors" in group and rec.get("colors") else None
    return GeometryImage(group["positions"][index, :H, :W], group["mask"][index, :H, :W],
                         domain=Domain.from_metadata(rec["domain"], meta), normals=normals, metadata=meta,
                         colors=colors)
