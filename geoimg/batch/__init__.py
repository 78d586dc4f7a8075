"""Collections of meshes to geometry images on Dask (``geoimg batch``): resumable, with a manifest, on an
embedded local cluster or an existing one. Needs ``pip install 'geoimg[batch]'`` (dask, distributed, zarr,
pandas); importing this package does not import them.

>>> from geoimg import batch
>>> batch.BatchOptions(resolution=65, steps=[("gaussian", [1.5])]).steps
(('gaussian', (1.5,)),)
"""
import warnings

from ._engine import MANIFEST_NAME, convert
from ._inputs import find_inputs, output_stems
from ._manifest import COLUMNS, STAGES, STATUSES, read_manifest
from ._options import QUAD_FORMATS, BatchOptions
from ._store import read_item, store_records

__all__ = ["convert", "BatchOptions", "QUAD_FORMATS", "find_inputs", "output_stems", "COLUMNS", "STAGES",
           "STATUSES", "MANIFEST_NAME", "read_manifest", "read_item", "store_records"]


def __getattr__(name: str):
    if name == "ConvertOptions":          # its name until 2026-12-06, one letter from geoimg.ConversionOptions
        warnings.warn("geoimg.batch.ConvertOptions is now geoimg.batch.BatchOptions; the old name goes in the next "
                      "release", DeprecationWarning, stacklevel=2)
        return BatchOptions
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
