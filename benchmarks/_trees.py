"""Another checkout timed beside this one (``--tree``): a script run by this interpreter in a fresh process,
with the checkout first on the path, reporting JSON on its standard output.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path


def check_tree(ap: argparse.ArgumentParser, tree: Path | None) -> None:
    """Refuse (``ap.error``, exit 2) a ``--tree`` that is not a checkout of geoimg."""
    if tree is not None and not (tree / "geoimg" / "__init__.py").is_file():
        ap.error(f"--tree: {tree} is not a checkout of geoimg")


def run_json(tree: Path, script: str, args: list) -> dict:
    """``python -c script *args`` in ``tree`` with ``tree`` on the path; the JSON it prints."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    run = subprocess.run([sys.executable, "-c", script, *map(str, args)], cwd=tree, env=env, check=True,
                         capture_output=True, text=True)
    return json.loads(run.stdout)
