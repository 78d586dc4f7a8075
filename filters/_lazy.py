"""Names of a package imported when first used (PEP 562), so that importing the package is quick: what
``filters`` and ``geoimg`` do with their exported names."""
from __future__ import annotations

import importlib
import sys
from typing import Any, Callable

__all__ = ["lazy_names"]


def lazy_names(package: str, where: dict[str, str],
               submodules: tuple[str, ...]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package``: ``where`` maps each exported name to the relative
    module that defines it (all the names of a module are bound together when one is first used, so a name
    equal to a module's never gets the module instead); ``submodules`` are imported by name.

    Examples
    --------
    >>> import filters
    >>> filters.mean_filter.__module__
    'filters.smoothing'
    """
    def __getattr__(name: str) -> Any:
        if name in submodules:
            return importlib.import_module("." + name, package)
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(where[name], package)
        namespace = vars(sys.modules[package])
        namespace.update({n: getattr(module, n) for n, m in where.items() if m == where[name]})
        return namespace[name]

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where) | set(submodules))

    return __getattr__, __dir__
