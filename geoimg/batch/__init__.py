"""Collections of meshes to geometry images on Dask (``geoimg batch``): resumable, with a manifest, on an
embedded local cluster or an existing one. Needs ``pip install 'geoimg[batch]'`` (dask, distributed, zarr,
pandas); importing this package does not import them.

>>> from geoimg import batch
>>> batch.ConvertOptions(resolution=65, steps=[("gaussian", [1.5])]).steps
(('gaussian', (1.5,)),)
"""
from ._engine import MANIFEST_NAME, convert
from ._inputs import find_inputs, output_stems
from ._manifest import COLUMNS, STAGES, STATUSES, read_manifest
from ._options import QUAD_FORMATS, ConvertOptions
from ._store import read_item, store_records

__all__ = ["convert", "ConvertOptions", "QUAD_FORMATS", "find_inputs", "output_stems", "COLUMNS", "STAGES",
           "STATUSES", "MANIFEST_NAME", "read_manifest", "read_item", "store_records"]
