"""Names for the types of the public API's annotations (nothing here runs)."""
from __future__ import annotations

import os
from typing import Any, Callable, Union

__all__ = ["PathLike", "Progress"]

PathLike = Union[str, "os.PathLike[str]"]     # a file or folder name
Progress = Callable[..., Any]                  # called with a message (or a count and a total)
