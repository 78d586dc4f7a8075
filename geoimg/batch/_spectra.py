"""The coefficient table of a batch run with ``harmonics``: a row per shape, its normalized coefficients in
columns named like aicsshparam's (:func:`geoimg.spectrum.coefficient_columns`), as CSV and Parquet beside the
manifest.
"""
from __future__ import annotations

from pathlib import Path

from .._atomic import write_all
from .._optional import require
from ..spectrum import coefficient_row, load_harmonics
from ._task import SPECTRUM_SUFFIX

__all__ = ["TABLE_NAME", "write_table"]

TABLE_NAME = "harmonics"       # harmonics.csv and harmonics.parquet


def _spectrum_file(row: dict) -> Path | None:
    for out in filter(None, str(row.get("outputs") or "").split(";")):
        if out.endswith(SPECTRUM_SUFFIX):
            return Path(out)
    return None


def write_table(folder: Path, rows: list[dict], lmax: int) -> list[Path]:
    """Write ``folder/harmonics.csv`` and ``.parquet``: for each manifest row (in order) whose input was
    converted and expanded, ``input``, ``lmax``, ``psnr_db`` (the image's, to the mesh) and its coefficients
    normalized in the first-order ellipsoid's frame (:meth:`geoimg.Harmonics.normalized`, no scaling), so
    that the rows compare term by term. Both files or neither; none when no row has coefficients.

    Parameters
    ----------
    folder : pathlib.Path
        The batch's output folder.
    rows : list of dict
        Manifest rows.
    lmax : int
        The degree asked for (files of another degree are left out).

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    pandas = require("pandas", "the harmonics table")
    records = []
    for row in rows:
        path = _spectrum_file(row)
        if row.get("status") not in ("ok", "poor") or path is None or not path.is_file():
            continue
        h = load_harmonics(path)
        if h.lmax != lmax:                       # not this run's (its options hash would differ): left out
            continue
        records.append({"input": row["input"], "lmax": h.lmax, "psnr_db": h.metadata.get("psnr_db"),
                        **coefficient_row(h.normalized())})
    if not records:
        return []
    table = pandas.DataFrame.from_records(records)
    base = Path(folder) / TABLE_NAME
    return write_all([(base.with_suffix(".csv"), lambda tmp: table.to_csv(tmp, index=False)),
                      (base.with_suffix(".parquet"), lambda tmp: table.to_parquet(tmp, index=False))], overwrite=True)
