"""The inputs of a batch: files, folders (searched recursively) and glob patterns, and the output names that
keep equal file names from different folders apart.
"""
from __future__ import annotations

import glob
import os
from pathlib import Path, PurePath
from typing import Any

from ..errors import InputError
from ..mesh import MESH_READ_FORMATS

__all__ = ["find_inputs", "output_stems"]


def _mesh_files(folder: Path) -> list[Path]:
    """The mesh files under ``folder``, recursively, leaving out hidden files and folders."""
    found = []
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        found += [Path(root, f) for f in sorted(files)
                  if not f.startswith(".") and Path(f).suffix.lower() in MESH_READ_FORMATS]
    return found


def find_inputs(specs: Any) -> list[Path]:
    """The input files named by ``specs``: a file as it is (whatever its extension: a wrong one is refused
    when it is read), a folder's mesh files recursively, a glob pattern's matches (``**`` for any depth).
    Each file once, in the order given, folders and patterns sorted.

    Raises
    ------
    FileNotFoundError
        A name that is neither a file nor a folder and matches nothing.
    InputError
        No input at all.

    Parameters
    ----------
    specs : path or sequence of paths
        Files, folders and glob patterns.

    Returns
    -------
    list of pathlib.Path
        The files, each once.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> for name in ("a/x.obj", "b/x.obj", "b/notes.txt", "b/.hidden.obj"):
    ...     (d / name).parent.mkdir(exist_ok=True); _ = (d / name).write_text("")
    >>> [str(p.relative_to(d)) for p in find_inputs([d, d / "a" / "x.obj"])]
    ['a/x.obj', 'b/x.obj']
    """
    if isinstance(specs, (str, os.PathLike)):
        specs = [specs]
    seen, found = set(), []
    for spec in specs:
        path = Path(spec)
        if path.is_dir():
            matches = _mesh_files(path)
        elif path.is_file():
            matches = [path]
        elif glob.has_magic(str(spec)):
            matches = []
            for name in sorted(glob.glob(str(spec), recursive=True)):
                hit = Path(name)
                matches += _mesh_files(hit) if hit.is_dir() else [hit] if hit.is_file() else []
        else:
            raise FileNotFoundError(f"{spec}: no such file or folder")
        for m in matches:
            key = m.resolve()
            if key not in seen:
                seen.add(key)
                found.append(m)
    if not found:
        raise InputError(
            f"no mesh files ({', '.join(MESH_READ_FORMATS)}) in {', '.join(map(str, specs)) or 'the inputs'}"
        )
    return found


def output_stems(inputs: Any) -> list[PurePath]:
    """For each input, its output name without extension, relative to the output folder: the input's path
    below the inputs' common folder, so that equal names in different folders stay apart; inputs that differ
    only in their extension keep it in the name (``x_obj``, ``x_ply``).

    Parameters
    ----------
    inputs : sequence of paths
        The input files, as :func:`find_inputs` gives them.

    Returns
    -------
    list of pathlib.PurePath
        One relative name per input, in order.

    Examples
    --------
    >>> [str(p) for p in output_stems(["/d/a/x.obj", "/d/b/x.obj", "/d/b/y.obj", "/d/b/y.ply"])]
    ['a/x', 'b/x', 'b/y_obj', 'b/y_ply']
    >>> [str(p) for p in output_stems(["/d/a/x.obj"])]
    ['x']
    """
    paths = [Path(os.path.abspath(p)) for p in inputs]
    root = Path(os.path.commonpath([p.parent for p in paths])) if paths else Path()
    rel = [p.relative_to(root) for p in paths]
    stems = [r.with_suffix("") for r in rel]
    count: dict[Path, int] = {}
    for s in stems:
        count[s] = count.get(s, 0) + 1
    return [r.with_name(r.name.replace(".", "_")) if count[s] > 1 else s for r, s in zip(rel, stems)]
