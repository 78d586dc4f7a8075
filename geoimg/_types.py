"""Names for the types of the public API's annotations, and the check of a path argument."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Union
from collections.abc import Callable

from .errors import InputTypeError

__all__ = ["PathLike", "Progress", "as_path"]

PathLike = Union[str, "os.PathLike[str]"]     # a file or folder name
Progress = Callable[..., Any]                  # called with a message (or a count and a total)


def as_path(value: Any, name: str = "path") -> Path:
    """``value`` as a Path, or an :class:`~geoimg.InputTypeError` naming ``name`` when it is not a file name.

    Examples
    --------
    >>> as_path("a.obj").name
    'a.obj'
    >>> as_path(123, "mesh")
    Traceback (most recent call last):
    ...
    geoimg.errors.InputTypeError: mesh: expected a file name (str or path-like), got int
    """
    if isinstance(value, (str, os.PathLike)):
        return Path(value)
    raise InputTypeError(f"{name}: expected a file name (str or path-like), got {type(value).__name__}")
