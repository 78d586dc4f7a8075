"""Compile time of a first conversion (issue 53): three 65^2 conversions (the terrain's planar image, Spot's
octahedral image, the open cube's disk image) in fresh processes with an empty numba cache, then the same
three again with the cache warm; each run prints the pixels' hash, so a baseline tree must give the same.

    python benchmarks/bench_compile.py [--tree PATH] [--base PATH] [--rounds 2]

``--base`` times another checkout (e.g. ``git worktree add /tmp/base HEAD~1``) alternating with ``--tree`` in
the same run, each with its own empty cache.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
CASES = [("geoimg/data/mountain.obj", "planar"), ("samples/data/spot_low_resolution.obj", "octahedral"),
         ("tests/data/cube_no_bottom.obj", "disk")]
CONVERT = ("import sys, hashlib, geoimg; m = geoimg.load_mesh(sys.argv[1]); "
           "img = geoimg.mesh_to_image(m, 65); print(hashlib.sha256(img.pixels.tobytes()).hexdigest()[:12])")


def run_all(tree: Path, cache: str) -> tuple[float, list[str]]:
    """Seconds for the three conversions in fresh processes with numba's cache at ``cache``, and their hashes."""
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_CACHE_DIR=cache)
    t = time.perf_counter()
    hashes = []
    for path, _ in CASES:
        out = subprocess.run([sys.executable, "-c", CONVERT, str(tree / path)], cwd=tree, env=env, check=True,
                             capture_output=True, text=True)
        hashes.append(out.stdout.strip())
    return time.perf_counter() - t, hashes


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--tree", type=Path, default=HERE.parent)
    ap.add_argument("--base", type=Path)
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args(argv)
    trees = {"tree": args.tree.resolve()} | ({"base": args.base.resolve()} if args.base else {})
    for r in range(args.rounds):
        for name, tree in trees.items():
            with tempfile.TemporaryDirectory() as cache:
                cold, h1 = run_all(tree, cache)
                warm, h2 = run_all(tree, cache)
            assert h1 == h2, (h1, h2)
            print(f"round {r} {name:5s} {tree}: cold {cold:6.1f} s, warm {warm:5.1f} s, pixels "
                  + " ".join(f"{kind}={h}" for (_, kind), h in zip(CASES, h1)), flush=True)


if __name__ == "__main__":
    main()
