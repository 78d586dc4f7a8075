"""Every command the README shows runs as written on the bundled data: its ``bash`` and ``python`` blocks, in the
README's order, in one fresh folder that holds the package and the bundled data (``geoimg``, ``samples``,
``tests/data``) where a clone has them. The set-up commands of the quick start (a virtual environment, pip) are left
to CI, which runs them; ``geoimg demo``, the first one's last step, runs here."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SET_UP = ("python3 -m venv", ". .venv/bin/activate", "pip install", "python -m pytest", "python -m mypy")


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


def test_the_blocks_are_found():
    found = blocks((ROOT / "README.md").read_text())
    assert sum(lang == "bash" for lang, _ in found) >= 8 and sum(lang == "python" for lang, _ in found) >= 3
    assert any(code.strip() == "geoimg demo" for _, code in found)           # the quick start's demo
    assert not any("pip install" in code for _, code in found)


def test_every_readme_command_runs_as_written(tmp_path):
    pytest.importorskip("moderngl")
    pytest.importorskip("distributed")
    for rel in ("geoimg", "samples", "tests/data"):        # as in a clone (python -c imports ./geoimg)
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).symlink_to(ROOT / rel, target_is_directory=True)
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    for k, (lang, code) in enumerate(blocks((ROOT / "README.md").read_text())):
        argv = ["bash", "-euo", "pipefail", "-c", code] if lang == "bash" else [sys.executable, "-c", code]
        run = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, f"README block {k} ({lang}) failed:\n{code}\n{run.stderr[-3000:]}"
        assert "Traceback" not in run.stderr, run.stderr[-3000:]
    for name in ("geoimg-demo/mountain.exr", "mountain_quads.obj", "clean.obj", "spot.glb", "morph.gif",
                 "frames", "landmarked.glb", "images/manifest.csv", "run/data.zarr", "from_python/manifest.csv",
                 "terrain_morph.gif"):
        assert (tmp_path / name).exists(), name
