"""A resource budget: large allocations are estimated first and refused with the estimate and the limit
(``GEOIMG_MAX_MEMORY``, or 80 % of the machine's memory; see :func:`filters.memory_limit`).
"""
from __future__ import annotations

import filters

from .errors import ResourceError

__all__ = ["ResourceError", "check_memory"]


def check_memory(n_bytes: float, what: str) -> None:
    """Raise :class:`ResourceError` when ``what`` would take more than the memory limit, saying both.

    Examples
    --------
    >>> check_memory(1e30, "a galaxy")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    geoimg.errors.ResourceError: a galaxy would need about 931322574615478534144.0 GiB; the limit is ...
    """
    filters.check_memory(n_bytes, what, error=ResourceError)
