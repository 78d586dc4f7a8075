"""Start-up times (issue 14): `import geoimg`, `import filters`, `geoimg --help`, a small mesh through
one CLI call, and `geoimg mesh` of a 513^2 image into each mesh format (issue 53), each the median of several
fresh processes.

    python benchmarks/bench_startup.py [--tree PATH] [--runs 7]
    python benchmarks/bench_startup.py --ratio MESH [--tree PATH] [--runs 7]

``--tree`` measures another checkout of the project (e.g. a `git worktree` of an older commit) with the same
interpreter, for a baseline in the same run. ``--ratio`` (issue 53) times ``geoimg image MESH --res 257`` in
fresh processes (this checkout and ``--tree`` alternating) against one linear sphere map of the mesh
(``bench_profile.linear_map``, best of 5 before and 5 after, in this process): best and median of each.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def timed(args, tree: Path, runs: int) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree))
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run(args, cwd=tree, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def ratio(mesh_path: Path, trees: list[Path], runs: int) -> None:
    """Fresh conversions of ``mesh_path`` at 257² in each tree, alternating, against the linear sphere map."""
    sys.path.insert(0, str(HERE))
    import geoimg
    from bench_profile import linear_map

    mesh = geoimg.load_mesh(mesh_path)
    linear = [linear_map(mesh, False) for _ in range(5)]
    times: dict[Path, list[float]] = {tree: [] for tree in trees}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(runs):
            for tree in trees:
                out = Path(tmp) / "b.exr"
                out.unlink(missing_ok=True)
                env = dict(os.environ, PYTHONPATH=str(tree))
                t = time.perf_counter()
                subprocess.run([sys.executable, "-m", "geoimg.cli", "image", str(mesh_path), "--res", "257", "-o",
                                str(out), "-q"], cwd=tree, env=env, check=True)
                times[tree].append(time.perf_counter() - t)
    linear += [linear_map(mesh, False) for _ in range(5)]
    base = min(linear)
    print(f"{mesh_path.name}: one linear sphere map {base:.3f} s (best of 10; median {statistics.median(linear):.3f})")
    print("| tree | fresh `geoimg image --res 257`, best / median | ratio to the linear map, best / median |")
    print("|---|---:|---:|")
    for tree, t in times.items():
        print(f"| {tree} | {min(t):.2f} / {statistics.median(t):.2f} s | {min(t) / base:.1f}x / "
              f"{statistics.median(t) / statistics.median(linear):.1f}x |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--tree", type=Path, default=HERE.parent)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--ratio", type=Path, default=None, help="a mesh: its fresh conversion against one linear map")
    args = ap.parse_args(argv)
    tree = args.tree.resolve()
    py = sys.executable
    if args.ratio is not None:
        trees = [HERE.parent] + ([tree] if tree != HERE.parent else [])
        ratio(args.ratio.resolve(), trees, args.runs)
        return
    with tempfile.TemporaryDirectory() as tmp:
        cases = {
            "python -c pass (the interpreter alone)": [py, "-c", "pass"],
            "import numpy": [py, "-c", "import numpy"],
            "import geoimg": [py, "-c", "import geoimg"],
            "import filters": [py, "-c", "import filters"],
            "geoimg --help": [py, "-m", "geoimg.cli", "--help"],
            "geoimg image --help": [py, "-m", "geoimg.cli", "image", "--help"],
            "geoimg info sphere.obj": [
                py,
                "-m",
                "geoimg.cli",
                "info",
                str(HERE.parent / "tests" / "data" / "sphere.obj"),
            ],
            "geoimg image sphere.obj --res 33": [
                py,
                "-m",
                "geoimg.cli",
                "image",
                str(HERE.parent / "tests" / "data" / "sphere.obj"),
                "-o",
                str(Path(tmp) / "s.exr"),
                "--res",
                "33",
                "--force",
            ],
        }
        image = Path(tmp) / "spot513.exr"          # made once, by this checkout: the same image for both trees
        subprocess.run([py, "-m", "geoimg.cli", "image", str(HERE.parent / "tests" / "data" / "spot.obj"), "-o",
                        str(image), "--res", "513", "-q"], cwd=HERE.parent, check=True)
        for ext in ("obj", "ply", "stl", "glb"):
            cases[f"geoimg mesh 513² image -> .{ext}"] = [py, "-m", "geoimg.cli", "mesh", str(image), "-o",
                                                         str(Path(tmp) / f"q.{ext}"), "--force", "-q"]
        print(f"tree {tree}; median of {args.runs} fresh processes\n")
        print("| what | seconds |")
        print("|---|---:|")
        for name, cmd in cases.items():
            print(f"| {name} | {timed(cmd, tree, args.runs):.3f} |", flush=True)


if __name__ == "__main__":
    main()
