"""The API reference, written from the packages' ``__all__`` at each build: a page per package, a page per
public function and class (autosummary), each documented once, on the page of the package that defines it;
the names a package re-exports link there.
"""
from __future__ import annotations

import importlib
import inspect
from pathlib import Path

PACKAGES = ["geoimg", "geoimg.mesh", "geoimg.parametrization", "geoimg.surface", "geoimg.image",
            "geoimg.animation", "geoimg.spectrum", "geoimg.batch", "geoimg.errors", "filters"]


def _exports(package: str) -> dict[str, object]:
    module = importlib.import_module(package)
    return {name: getattr(module, name) for name in module.__all__
            if not inspect.ismodule(getattr(module, name))}


def _home(obj, exported_by: list[str]) -> str:
    """The package whose page documents ``obj``: the deepest one it is defined in, else the first to export it."""
    where = getattr(obj, "__module__", "") or ""
    inside = [p for p in exported_by if where == p or where.startswith(p + ".")]
    return max(inside, key=len) if inside else exported_by[0]


def homes() -> dict[int, str]:
    """``id(obj) -> package`` for every exported function and class."""
    exported_by: dict[int, list[str]] = {}
    objects = {}
    for package in PACKAGES:
        for obj in _exports(package).values():
            if inspect.isfunction(obj) or inspect.isclass(obj):
                exported_by.setdefault(id(obj), []).append(package)
                objects[id(obj)] = obj
    return {key: _home(objects[key], packages) for key, packages in exported_by.items()}


def _page(package: str, home: dict[int, str]) -> str:
    title = f"``{package}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {package}", "   :no-members:", ""]
    own, elsewhere, data = [], [], []
    for name, obj in _exports(package).items():
        if inspect.isfunction(obj) or inspect.isclass(obj):
            (own if home[id(obj)] == package else elsewhere).append((name, obj))
        else:
            data.append((name, obj))
    for heading, kind in (("Classes", inspect.isclass), ("Functions", inspect.isfunction)):
        names = [n for n, o in own if kind(o)]
        if names:
            lines += [heading, "-" * len(heading), "", ".. autosummary::", "   :toctree: generated", ""]
            lines += [f"   {n}" for n in names] + [""]
    if elsewhere:
        lines += ["Also exported here", "------------------", ""]
        lines += [f"- :{'class' if inspect.isclass(o) else 'func'}:`{package}.{n} <{home[id(o)]}.{n}>`"
                  for n, o in elsewhere] + [""]
    pkg = importlib.import_module(package)
    modules = [name for name in pkg.__all__ if inspect.ismodule(getattr(pkg, name))]
    if modules:
        lines += ["Modules", "-------", ""]
        for name in modules:
            module = getattr(pkg, name)
            summary = (inspect.getdoc(module) or "").split("\n\n")[0].replace("\n", " ")
            target = f":mod:`{package}.{name}`" if f"{package}.{name}" in PACKAGES else f"``{package}.{name}``"
            lines += [f"- {target}: {summary}"]
        lines += [""]
    if data:
        lines += ["Constants", "---------", ""]
        for n, o in data:
            lines += [f".. py:data:: {package}.{n}", f"   :value: {o!r}".replace("\n", " "), ""]
    return "\n".join(lines)


def write(folder: Path) -> None:
    """Write ``index.rst`` and one page per package into ``folder`` (only files whose text changed)."""
    folder.mkdir(exist_ok=True)
    home = homes()
    pages = {"index": "\n".join(["API reference", "=============", "",
                                 "Every public name, by the package that exports it.", "",
                                 ".. toctree::", "   :maxdepth: 1", ""] + [f"   {p}" for p in PACKAGES] + [""])}
    pages.update({package: _page(package, home) for package in PACKAGES})
    for name, text in pages.items():
        path = folder / f"{name}.rst"
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
