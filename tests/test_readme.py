"""Every command the README and the documentation's pages show runs as written on the bundled data: each page's
``bash`` and ``python`` blocks, in the page's order, in a fresh folder of its own that holds the package and the
bundled data (``geoimg``, ``samples``, ``tests/data``) where a clone has them. The set-up commands of the quick
start (a virtual environment, pip) are left to CI, which runs them; ``geoimg demo``, the first one's last step,
runs here. ``text`` blocks (the documentation's own build command, which CI runs) are not run.

A block of plain ``geoimg`` commands (no pipes, redirections, variables or globs for the shell to expand) runs
them through :func:`geoimg.cli.main`, the function the ``geoimg`` program calls, in this process: the same
command, without a new interpreter's imports and kernel loads each time (the program itself is run as a process
by tests/test_cli.py). Any other block runs in ``bash``, as written."""
from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from geoimg.cli import main

pytestmark = pytest.mark.slow           # a page, a sample, a batch, a fuzzing run or a real mesh: the full run

ROOT = Path(__file__).resolve().parents[1]
SET_UP = ("python3 -m venv", ". .venv/bin/activate", "pip install", "python -m pytest", "python -m mypy")
GUIDES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs" / "guide").glob("*.md"))
PAGES = ["README.md", "docs/getting_started.md", *GUIDES]
# What a page's commands must leave behind (a command can exit 0 and write nothing).
OUTPUTS = {
    "README.md": ["mountain.exr", "smooth_quads.obj", "smooth_py.obj", "morph.gif"],
    "docs/getting_started.md": ["geoimg-demo/mountain.exr", "mountain_quads.obj"],
    "docs/guide/converting.md": ["mountain_quads.obj"],
    "docs/guide/filtering.md": ["smooth.obj", "part.exr", "clean.obj", "mountain_curv_mean.exr"],
    "docs/guide/morphs.md": ["morph.gif", "frames", "landmarked.glb", "points.csv"],
    "docs/guide/batch.md": ["images/manifest.csv", "run/data.zarr", "from_python/manifest.csv"],
    "docs/guide/formats.md": ["mountain.npz", "rgba.exr", "approx.obj", "spot.glb"],
    "docs/guide/python.md": ["terrain_quads.obj", "terrain_morph.gif"],
    "docs/guide/resolution.md": ["faithful.exr", "smooth.exr", "paper.exr"],
    "docs/guide/harmonics.md": ["spot_sh.npz", "spot_l16.obj", "run/harmonics.parquet"],
    "docs/guide/compress.md": ["spot.jp2", "spot_from_jp2.obj", "spot55.jp2", "spot_py.jp2"],
}


def blocks(text: str) -> list[tuple[str, str]]:
    """``(language, code)`` of every ``bash`` and ``python`` block, in order; the set-up steps of a
    command chained with ``&&`` left out."""
    found = []
    for lang, code in re.findall(r"^```(bash|python)\n(.*?)^```", text, flags=re.S | re.M):
        if lang == "bash":
            lines = []
            for line in code.splitlines():
                steps = [p.strip() for p in line.split("&&")]
                kept = [p for p in steps if not p.startswith(SET_UP)]
                lines.append(" && ".join(kept) if len(steps) > 1 else line)
            code = "\n".join(lines)
        found.append((lang, code))
    return found


def geoimg_commands(code: str) -> list[list[str]] | None:
    """The arguments of each command of a ``bash`` block when every command is a plain ``geoimg`` one (what
    the shell would pass on: quotes removed, comments and line continuations handled); None otherwise."""
    commands = []
    for line in code.replace("\\\n", " ").splitlines():
        unquoted = re.sub(r"'[^']*'|\"[^\"]*\"", "", line).split("#")[0]
        if not unquoted.strip():
            continue
        if re.search(r"[|&;<>()$`*?\[\]{}~=\\]", unquoted):          # for the shell to read: not plain
            return None
        argv = shlex.split(line, comments=True)
        if argv[0] != "geoimg":
            return None
        commands.append(argv[1:])
    return commands


def test_plain_geoimg_commands_are_told_from_the_rest():
    assert geoimg_commands("geoimg demo\ngeoimg image a.obj -o 'b c.exr'   # a comment\n\n# only a comment\n"
                           "geoimg morph a.obj b.obj \\\n    --frames 3") == [
        ["demo"], ["image", "a.obj", "-o", "b c.exr"], ["morph", "a.obj", "b.obj", "--frames", "3"]]
    assert geoimg_commands("geoimg batch d 'x/sp*.obj' -o i") == [["batch", "d", "x/sp*.obj", "-o", "i"]]
    for shell in ("geoimg info a.exr | head", "geoimg info a.exr > out.txt", "geoimg batch d x/*.obj",
                  "printf 'a' > p.csv\ngeoimg info p.csv", "geoimg info $HOME/a.exr", "X=1 geoimg info a.exr",
                  "geoimg info a.exr && geoimg info b.exr", "geoimg info ~/a.exr", "cd x; geoimg info a.exr"):
        assert geoimg_commands(shell) is None, shell


def run_in_process(argv: list[str], cwd: Path) -> tuple[int, str]:
    """``geoimg ARGV`` run by :func:`geoimg.cli.main` in ``cwd``: its exit status and what it wrote on stderr."""
    err, here, sigterm = io.StringIO(), Path.cwd(), signal.getsignal(signal.SIGTERM)
    try:
        os.chdir(cwd)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            try:
                status = main(argv)
            except SystemExit as e:                 # argparse refused the command line
                status = e.code
    finally:
        os.chdir(here)
        signal.signal(signal.SIGTERM, sigterm)
    return status, err.getvalue()


def test_the_blocks_are_found():
    readme = (ROOT / "README.md").read_text()
    found = blocks(readme)
    assert sum(lang == "bash" for lang, _ in found) >= 3 and sum(lang == "python" for lang, _ in found) >= 1
    assert any(code.strip() == "geoimg demo" for _, code in found)           # the quick start's demo
    assert not any("pip install" in code for _, code in found)
    assert len(readme.splitlines()) <= 150
    assert set(OUTPUTS) <= set(PAGES) and len(PAGES) >= 10
    for page in PAGES:                                                       # every link between pages holds
        for target in re.findall(r"\]\(([^)#:]+\.md)\)", (ROOT / page).read_text()):
            assert (ROOT / page).parent.joinpath(target).exists(), f"{page}: {target}"


def test_ci_runs_the_readme_test_command_and_stops_at_its_first_failing_step():
    """``.ci/run`` runs the README's test command one step a line under ``set -e``: a step that fails inside an
    ``a && b && c`` list does not stop a ``set -e`` script (the tests failed and CI went on to build the site)."""
    steps = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()
             if line.strip() and not line.lstrip().startswith("#")]
    assert steps[0] == "set -euo pipefail"
    assert not [line for line in steps if re.search(r"&&|\|\||;", line)]
    quick_start = next(code for _, code in re.findall(r"^```(bash)\n(.*?)^```", (ROOT / "README.md").read_text(),
                                                       flags=re.S | re.M) if '".[test]"' in code)
    wanted = [step.strip() for step in quick_start.strip().split("&&")]
    assert wanted[-2:] == ["python -m pytest -q", "python -m mypy"] and wanted[-3] == 'pip install -e ".[test]"'
    at = steps.index('python -m pip install -q -e ".[test]"')
    assert steps[at + 1:at + 3] == wanted[-2:]


@pytest.mark.parametrize("page", PAGES)
def test_every_command_of_a_page_runs_as_written(page, tmp_path):
    pytest.importorskip("moderngl")
    pytest.importorskip("distributed")
    for rel in ("geoimg", "samples", "tests/data"):        # as in a clone (python -c imports ./geoimg)
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).symlink_to(ROOT / rel, target_is_directory=True)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    for k, (lang, code) in enumerate(blocks((ROOT / page).read_text())):
        commands = geoimg_commands(code) if lang == "bash" else None
        if commands is not None:
            for argv in commands:
                status, err = run_in_process(argv, tmp_path)
                assert status == 0, f"{page} block {k}: geoimg {shlex.join(argv)} failed:\n{err[-3000:]}"
            continue
        argv = ["bash", "-euo", "pipefail", "-c", code] if lang == "bash" else [sys.executable, "-c", code]
        run = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, f"{page} block {k} ({lang}) failed:\n{code}\n{run.stderr[-3000:]}"
        assert "Traceback" not in run.stderr, run.stderr[-3000:]
    for name in OUTPUTS.get(page, []):
        assert (tmp_path / name).exists(), f"{page}: {name}"
