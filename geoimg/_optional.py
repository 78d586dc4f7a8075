"""Optional dependencies: imported when first needed, with a one-line error naming what to install."""
from __future__ import annotations

import importlib

from .errors import MissingDependency

__all__ = ["require", "MissingDependency"]

EXTRAS = {"moderngl": "render", "imageio": "render", "pygltflib": "render", "imageio_ffmpeg": "video",
          "dask": "batch", "distributed": "batch", "zarr": "batch", "pandas": "batch", "psutil": "batch",
          "pyarrow": "batch", "imagecodecs": "compress"}


def require(module: str, what: str):
    """The module ``module``, or :class:`MissingDependency` saying that ``what`` needs it and how to
    install it (``pip install 'geoimg[EXTRA]'``).

    Examples
    --------
    >>> require("math", "arithmetic").sqrt(4.0)
    2.0
    >>> require("no_such_module_here", "flying")
    Traceback (most recent call last):
    ...
    geoimg.errors.MissingDependency: flying needs the no_such_module_here package: pip install no_such_module_here
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        extra = EXTRAS.get(module.split(".")[0])
        how = f"pip install 'geoimg[{extra}]'" if extra else f"pip install {module}"
        raise MissingDependency(f"{what} needs the {module} package: {how}") from None
