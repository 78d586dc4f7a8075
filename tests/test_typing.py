"""The public API is annotated (every parameter and return of what the packages export), and both
packages say so to type checkers (py.typed); `python -m mypy` (in the README's test command) checks the
annotations against the code."""
import importlib
import inspect
from pathlib import Path

import pytest

PUBLIC = ["geoimg", "geoimg.mesh", "geoimg.parametrization", "geoimg.surface", "geoimg.image", "geoimg.animation",
          "geoimg.batch", "filters"]


def _public_functions():
    seen = {}
    for name in PUBLIC:
        module = importlib.import_module(name)
        for attr in module.__all__:
            obj = getattr(module, attr)
            if inspect.isfunction(obj):
                seen.setdefault(id(obj), (f"{name}.{attr}", obj))
            elif inspect.isclass(obj):
                for member, f in vars(obj).items():
                    if inspect.isfunction(f) and (not member.startswith("_") or member == "__init__"):
                        seen.setdefault(id(f), (f"{name}.{attr}.{member}", f))
    return list(seen.values())


def test_every_public_function_is_annotated():
    missing = []
    for qualname, f in _public_functions():
        sig = inspect.signature(f)
        bare = [p.name for p in sig.parameters.values()
                if p.name not in ("self", "cls") and p.annotation is inspect.Parameter.empty]
        if bare or (sig.return_annotation is inspect.Signature.empty and f.__name__ != "__init__"):
            missing.append(f"{qualname}({', '.join(bare)})")
    assert len(_public_functions()) > 150 and not missing, missing


@pytest.mark.parametrize("package", ["geoimg", "filters"])
def test_packages_are_marked_typed(package):
    assert (Path(importlib.import_module(package).__file__).parent / "py.typed").is_file()
