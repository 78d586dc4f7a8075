"""The house rules of the package layout: imports run one way (no cycles between modules, filters never
imports geoimg), imports sit at the top of modules except for optional dependencies, and every public
name a package exports exists."""
import ast
import importlib
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = {"moderngl", "imageio", "imageio.v3", "pygltflib", "imageio_ffmpeg", "dask", "dask.utils", "distributed",
            "zarr", "pandas", "psutil"}


def _modules(package: str) -> dict:
    out = {}
    for f in (ROOT / package).rglob("*.py"):
        parts = f.relative_to(ROOT).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = f
    return out


MODULES = {**_modules("geoimg"), **_modules("filters")}


def _imports(name: str, path: Path):
    """(target module, at top level?) for each import statement of a module."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    top = set(map(id, tree.body))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, id(node) in top
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([node.module] if node.module else []))
            submodules = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in MODULES]
            yield from ((m, id(node) in top) for m in submodules)
            if len(submodules) < len(node.names):
                yield base, id(node) in top


def _graph():
    return {name: {t for t, _ in _imports(name, path) if t in MODULES and t != name} for name, path in MODULES.items()}


def test_no_import_cycles():
    graph = _graph()
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                pytest.fail("import cycle: " + " -> ".join(stack[stack.index(nxt):] + [nxt]))
            if nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


def test_imports_are_at_the_top_except_optional_dependencies():
    inside = [(name, target) for name, path in MODULES.items() for target, top in _imports(name, path)
              if not top and target not in OPTIONAL]
    assert inside == []


def test_filters_knows_nothing_of_geoimg():
    assert not any(t.startswith("geoimg") for name, ts in _graph().items() if name.startswith("filters") for t in ts)


def test_a_cycle_is_found(monkeypatch):
    """The cycle check can fail: two modules importing each other are reported."""
    fake = {"a": {"b"}, "b": {"a"}}
    monkeypatch.setattr(sys.modules[__name__], "_graph", lambda: fake)
    with pytest.raises(pytest.fail.Exception, match="import cycle: a -> b -> a"):
        test_no_import_cycles()


@pytest.mark.parametrize("package", ["geoimg", "geoimg.mesh", "geoimg.parametrization", "geoimg.surface",
                                     "geoimg.image", "geoimg.animation", "filters"])
def test_public_names_exist_and_private_modules_stay_private(package):
    module = importlib.import_module(package)
    assert all(hasattr(module, n) for n in module.__all__)
    assert not any(n.startswith("_") for n in module.__all__)
