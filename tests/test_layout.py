"""The house rules of the package layout: imports run one way (no cycles between modules, filters never
imports geoimg), imports sit at the top of modules except for optional dependencies and the command line's
commands, and every public name a package exports exists, whether imported at once or when first used."""
import ast
import fnmatch
import re
import importlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = {"moderngl", "imageio", "imageio.v3", "pygltflib", "imageio_ffmpeg", "dask", "dask.utils", "distributed",
            "zarr", "pandas", "psutil"}
DEFERRED = {("geoimg.cli", "geoimg._commands"),     # the parser runs without the commands' heavy imports
            ("geoimg.surface._base", "geoimg.surface._gaussian_cuda_kernels"),    # numba.cuda: backend="cuda" alone
            ("geoimg.surface._gaussian_planar", "geoimg.surface._gaussian_cuda_kernels"),
            ("geoimg.mesh._trimesh_io", "trimesh"),     # STL and GLB alone: OBJ, OFF and PLY load without it
            ("geoimg._commands", "*"),        # each command imports the stages it runs: geoimg mesh starts without
                                              # the conversion's (issue 53: a 513^2 quad mesh in 1.5 s)
            ("geoimg.mesh._weld", "scipy*"),                 # reading and writing meshes start without scipy
            ("geoimg.image._perimeter", "scipy*"),           # reading an image starts without scipy
            ("geoimg.image._displacement", "scipy*"),        # ... a displaced one's splines need it
            ("geoimg.image._jp2", "skimage*"),               # ... its masked pixels continued only when coding
            ("geoimg.parametrization._layout", "scipy*"),    # the cut and charts domains: without scipy
            ("geoimg.parametrization._octahedral", "scipy*"),    # the octahedral domain: without scipy, numba
            ("geoimg.parametrization._octahedral", "geoimg.parametrization._octahedral_kernels"),
            # a first conversion starts without scipy.spatial and scipy.optimize (issue 53: 0.2 s of 3.5)
            ("geoimg.mesh._metrics", "scipy.spatial"),                 # boundary distances alone
            ("geoimg.surface._gaussian_planar", "scipy.spatial"),      # the paper's weights alone
            ("geoimg.surface._attributes", "scipy.spatial"),           # colours alone
            ("geoimg.parametrization._parametrize", "scipy.spatial"),  # a disk map's outline alone
            ("geoimg.parametrization._charts", "scipy.optimize"),      # charts alone
            ("geoimg.image._image", "cv2"),                            # a notebook's picture alone
            ("geoimg.surface._attributes", "cv2")}                     # a texture alone
HEAVY = ("numba", "trimesh", "scipy", "cv2", "OpenImageIO", "skimage", "igl", "PIL")


def _modules(package: str) -> dict:
    out = {}
    for f in (ROOT / package).rglob("*.py"):
        parts = f.relative_to(ROOT).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = f
    return out


MODULES = {**_modules("geoimg"), **_modules("filters")}


def _type_checking_only(tree) -> set:
    """ids of the statements inside ``if TYPE_CHECKING:`` blocks (read by type checkers, never run)."""
    inside = set()
    for node in tree.body:
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            inside |= {id(n) for n in node.body}
    return inside


def _imports(name: str, path: Path):
    """(target module, at top level?) for each import statement of a module (those only for type checkers
    count as at the top)."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    top = set(map(id, tree.body)) | _type_checking_only(tree)
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
              if not top and target not in OPTIONAL
              and not any(name == who and fnmatch.fnmatchcase(target, what) for who, what in DEFERRED)]
    assert inside == []


@pytest.mark.parametrize(
    "statement", ["import geoimg", "import filters", "import geoimg.cli; geoimg.cli.build_parser()"]
)
def test_the_packages_and_the_parser_import_nothing_heavy(statement):
    """``import geoimg`` and ``geoimg --help`` stay quick: the libraries behind the work are imported when
    first used (their names are looked up, not timed: the machines are shared)."""
    code = f"{statement}; import sys; print(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r})))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"


def test_a_quad_mesh_is_written_without_the_conversion_libraries(tmp_path):
    """``geoimg mesh`` (an image to a quad mesh) starts without numba, scipy, libigl or trimesh: half a second
    of imports of the one and a half it is given for a 513^2 image (issue 53)."""
    import geoimg
    d = geoimg.OctahedralDomain()
    geoimg.GeometryImage(d.directions(9).astype(np.float32), None, d).save(tmp_path / "o.exr")
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 9))
    geoimg.GeometryImage(np.dstack([u, v, u * v]).astype(np.float32)).save(tmp_path / "p.exr")
    code = ("import sys; from geoimg.cli import main; "
            f"[main(['mesh', {str(tmp_path)!r} + f'/{{k}}.exr', '-o', {str(tmp_path)!r} + f'/{{k}}.obj', '-q']) "
            "for k in 'op']; "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'numba', 'scipy', 'igl', 'trimesh', 'skimage'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]" and (tmp_path / "o.obj").exists() and (tmp_path / "p.obj").exists()


def test_obj_off_and_ply_load_without_trimesh(tmp_path):
    """trimesh (half a second to import) is for reading STL, GLB and glTF alone: geoimg writes STL and GLB."""
    stl = repr(str(tmp_path / "t.stl"))
    code = (
        "import sys, geoimg; from geoimg.mesh import Mesh; m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]); "
        f"[geoimg.load_mesh(geoimg.save_mesh(m, {str(tmp_path)!r} + '/t' + e)) for e in ('.obj', '.off', '.ply')]; "
        f"print('trimesh' in sys.modules); geoimg.save_mesh(m, {stl}); print('trimesh' in sys.modules); "
        f"geoimg.load_mesh({stl}); print('trimesh' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.split() == ["False", "False", "True"]


def test_names_imported_when_first_used_are_the_real_ones():
    import geoimg
    import filters
    from geoimg.mesh import Mesh
    from filters.smoothing import mean_filter
    assert geoimg.Mesh is Mesh and filters.mean_filter is mean_filter
    code = "import filters; filters.resize; print(callable(filters.blend))"    # a module's names come together
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          cwd=ROOT).stdout.strip() == "True"
    assert set(geoimg.__all__) <= set(dir(geoimg)) and set(filters.__all__) <= set(dir(filters))
    assert geoimg.mesh.topology is importlib.import_module("geoimg.mesh").topology
    with pytest.raises(AttributeError, match="nothing"):
        _ = geoimg.nothing
    with pytest.raises(AttributeError, match="nothing"):
        _ = filters.nothing


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


def test_ruff_check_is_clean():
    """The linter configured in pyproject.toml (style, bugs, docstrings of the public API) finds nothing."""
    pytest.importorskip("ruff")
    run = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", str(ROOT)], capture_output=True,
                         text=True, cwd=ROOT)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]


DOTTED = re.compile(r"(?<![\w./-])((?:geoimg|filters)(?:\.[A-Za-z_][A-Za-z0-9_]*)+)")


def _resolves(name: str) -> bool:
    """Whether ``name`` is a module, or an attribute reached from the longest importable module of it."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attribute in parts[i:]:
            if not hasattr(obj, attribute):
                return False
            obj = getattr(obj, attribute)
        return True
    return False


def test_every_dotted_name_in_the_docs_and_docstrings_resolves():
    """A name like geoimg.spectrum.shape_space in a page or a docstring is one a reader can import (the
    changelog, which is history, is left out)."""
    pages = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", *sorted((ROOT / "docs").glob("*.md")),
             *sorted((ROOT / "docs" / "guide").glob("*.md")), *sorted((ROOT / "geoimg").rglob("*.py")),
             *sorted((ROOT / "filters").rglob("*.py")), *sorted((ROOT / "samples").glob("*.py"))]
    found: dict[str, set] = {}
    for page in pages:
        for match in DOTTED.finditer(page.read_text(encoding="utf-8")):
            found.setdefault(match.group(1), set()).add(page.relative_to(ROOT).as_posix())
    assert len(found) > 50                                 # the scan sees the docs' names
    broken = {name: sorted(where) for name, where in found.items() if not _resolves(name)}
    assert broken == {}
