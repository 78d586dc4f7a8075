"""Libraries' log records kept off the user's terminal: a logged traceback looks like a crash.

trimesh logs a traceback when it cannot read an ASCII STL's normals (which geoimg never uses) and then
reads the file well; Python's last-resort handler prints such records to stderr in full. Inside
:func:`library_logs`, the named loggers' records are held back from the handlers: those of level ERROR
and above become one geoimg warning line each (their message, no traceback), the others are dropped.

Examples
--------
>>> import logging, warnings
>>> with warnings.catch_warnings(record=True) as seen:
...     warnings.simplefilter("always")
...     with library_logs("trimesh", about="reading x.stl"):
...         logging.getLogger("trimesh").warning("failed to extract face_normals")
...         logging.getLogger("trimesh").error("bad header")
>>> [str(w.message) for w in seen]
['reading x.stl: trimesh reported: bad header']
"""
from __future__ import annotations

import logging
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["library_logs"]


class _Collect(logging.Handler):
    def __init__(self) -> None:
        super().__init__(level=logging.ERROR)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        try:
            message = record.getMessage()
        except Exception:   # noqa: BLE001 - a record whose arguments do not fit its format
            message = str(record.msg)
        self.messages.append(f"{record.name.split('.')[0]} reported: {' '.join(message.split())[:300]}")


@contextmanager
def library_logs(*names: str, about: str) -> Iterator[None]:
    """Hold the loggers ``names`` back from every handler within the block (see the module's text);
    ``about`` says what geoimg was doing, at the start of each warning.
    """
    collect = _Collect()
    saved = []
    for name in names:
        logger = logging.getLogger(name)
        saved.append((logger, logger.propagate, list(logger.handlers)))
        logger.handlers = [collect]
        logger.propagate = False
    try:
        yield
    finally:
        for logger, propagate, handlers in saved:
            logger.handlers = handlers
            logger.propagate = propagate
        for message in dict.fromkeys(collect.messages):        # each message once, in order
            warnings.warn(f"{about}: {message}", stacklevel=3)
