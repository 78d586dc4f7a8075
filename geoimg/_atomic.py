"""Write a file completely or not at all: a temporary file beside the target, then a rename."""
from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path

from ._types import as_path

__all__ = ["OutputExists", "atomic_path", "check_writable", "write_all"]


class OutputExists(FileExistsError):
    """An output file exists and may not be replaced; ``filename`` is its path (the command line says
    ``--force`` where the API says ``overwrite=True``).
    """

    def __init__(self, path: Path):
        super().__init__(errno.EEXIST, "exists", str(path))

    def __str__(self) -> str:
        return f"{self.filename} exists; pass overwrite=True to replace it"


def check_writable(path, overwrite: bool) -> Path:
    """Return ``path`` as a Path after checking it may be written.

    Raises
    ------
    OutputExists
        If the file exists and ``overwrite`` is false.
    FileNotFoundError
        If the parent folder does not exist.
    InputTypeError
        If ``path`` is not a file name.
    """
    path = as_path(path)
    if path.exists() and not overwrite:
        raise OutputExists(path)
    if not path.parent.exists():
        raise FileNotFoundError(f"folder {path.parent} does not exist")
    return path


def _default_mode(path: Path) -> int:
    """The replaced file's mode, else what a newly created file gets under the process's umask."""
    if path.exists():
        return path.stat().st_mode & 0o7777
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextlib.contextmanager
def atomic_path(path, overwrite: bool = False):
    """Yield a temporary path in the target's folder; rename it onto ``path`` on success.

    On any exception the temporary file is removed and ``path`` is left untouched.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with atomic_path(d / "a.txt") as tmp:
    ...     _ = tmp.write_text("hi")
    >>> (d / "a.txt").read_text()
    'hi'
    """
    path = check_writable(path, overwrite)
    fd, tmp = tempfile.mkstemp(prefix="." + path.stem + ".", suffix=".tmp" + path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        os.chmod(tmp, _default_mode(path))      # mkstemp makes it private; give it a normal file's mode
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_all(jobs, overwrite: bool = False) -> list[Path]:
    """Write several files all or none: every path is checked first, each writer ``write(tmp)`` fills a
    temporary file beside its target, and only when all have succeeded are they renamed into place (on any
    failure every temporary file is removed and no target is touched).

    Parameters
    ----------
    jobs : sequence of (path, write)
        ``write(tmp_path)`` writes one file (with ``overwrite=True``: ``tmp_path`` exists).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> def boom(tmp):
    ...     raise OSError("disk full")
    >>> write_all([(d / "a.txt", lambda tmp: tmp.write_text("a")), (d / "b.txt", boom)])
    Traceback (most recent call last):
    ...
    OSError: disk full
    >>> sorted(p.name for p in d.iterdir())     # neither file, and no temporary left behind
    []
    """
    jobs = [(Path(path), write) for path, write in jobs]
    for path, _ in jobs:
        check_writable(path, overwrite)
    with contextlib.ExitStack() as stack:
        for path, write in jobs:
            write(stack.enter_context(atomic_path(path, overwrite)))
    return [path for path, _ in jobs]
