"""The manifest of a batch: one CSV row per input (status, message, topology, sizes, PSNR, times per stage,
outputs, options hash), appended as inputs finish and compacted at the end, so that an interrupted batch
knows what it finished.
"""
from __future__ import annotations

import csv
import os
from pathlib import Path

from .._atomic import atomic_path
from .._types import PathLike

__all__ = ["COLUMNS", "STAGES", "STATUSES", "read_manifest", "ManifestLog", "write_manifest"]

STATUSES = ("ok", "poor", "refused", "failed")      # poor: converted, but far from the input (see BatchOptions)
STAGES = ("load", "repair", "parametrize", "fit", "sample", "harmonics", "filter", "write", "psnr")
COLUMNS = ("input", "status", "message", "warnings", "outputs", "vertices", "faces", "topology", "pieces",
           "domain", "image_size", "psnr_db", "hausdorff", "map_stretch", "starved") + tuple(
           f"t_{s}" for s in STAGES) + (
           "t_total", "worker", "options_hash", "input_size", "input_mtime_ns", "finished")


def _row(row: dict) -> dict:
    return {c: "" if row.get(c) is None else row.get(c) for c in COLUMNS}


def read_manifest(path: PathLike) -> dict[str, dict]:
    """The rows of a manifest by input (the last row of an input wins); empty when there is no file.

    Parameters
    ----------
    path : path-like
        The manifest (CSV).

    Returns
    -------
    dict
        ``input path -> row`` (a dict of the columns' text).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "manifest.csv"
    >>> with ManifestLog(p) as log:
    ...     log.add({"input": "a.obj", "status": "failed"}); log.add({"input": "a.obj", "status": "ok"})
    >>> read_manifest(p)["a.obj"]["status"]
    'ok'
    """
    path = Path(path)
    if not path.is_file():
        return {}
    with open(path, newline="", encoding="utf-8") as f:
        return {row["input"]: row for row in csv.DictReader(f) if row.get("input")}


def write_manifest(path, rows) -> Path:
    """Write ``rows`` (dicts) as the whole manifest, atomically."""
    with atomic_path(path, overwrite=True) as tmp:
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            w = csv.DictWriter(f, COLUMNS)
            w.writeheader()
            w.writerows(_row(r) for r in rows)
    return Path(path)


class ManifestLog:
    """Rows appended to the manifest as inputs finish, each flushed to disk at once."""

    def __init__(self, path):
        self.path = Path(path)

    def __enter__(self):
        new = not self.path.exists() or self.path.stat().st_size == 0
        self.file = open(self.path, "a", newline="", encoding="utf-8")
        self.writer = csv.DictWriter(self.file, COLUMNS)
        if new:
            self.writer.writeheader()
        return self

    def add(self, row: dict) -> None:
        self.writer.writerow(_row(row))
        self.file.flush()
        os.fsync(self.file.fileno())

    def __exit__(self, *exc):
        self.file.close()
