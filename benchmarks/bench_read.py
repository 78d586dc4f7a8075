"""Reading mesh files: `geoimg.load_mesh` on OBJ files of several sizes and forms, best of several reads after
a warm-up, in a fresh process per checkout.

    python benchmarks/bench_read.py [--tree PATH] [--repeat 5]

``--tree`` adds a column for another checkout (e.g. a `git worktree` of an older commit), run by the same
interpreter in the same run, so that the two are compared on the same machine at the same time. The files are
the bundled ones and, where ``../shared/data`` is beside the checkout, its larger OBJ files.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from _trees import check_tree, run_json

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SHARED = ROOT.parent / "shared" / "data" / "meshes"
FILES = [ROOT / "tests" / "data" / "spot.obj", ROOT / "tests" / "data" / "sword-quad-dominant.obj",
         ROOT / "geoimg" / "data" / "mountain.obj"] + [SHARED / rel for rel in (
    "closed_genus0/bunny.obj", "closed_genus0/armadillo.obj", "polygonal/horse_quad.obj",
    "open_other/stanford-bunny.obj")]

TIMER = """
import json, sys, time, warnings
import geoimg
out = {}
for path in sys.argv[2:]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = geoimg.load_mesh(path)
        best = float("inf")
        for _ in range(int(sys.argv[1])):
            t = time.perf_counter()
            geoimg.load_mesh(path)
            best = min(best, time.perf_counter() - t)
    out[path] = (best, mesh.n_vertices, mesh.n_faces, sorted(set(mesh.face_sizes.tolist())))
print(json.dumps(out))
"""


def timings(tree: Path, files: list, repeat: int) -> dict:
    return run_json(tree, TIMER, [repeat, *files])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--tree", type=Path, help="another checkout to time beside this one")
    ap.add_argument("--repeat", type=int, default=5, help="reads a file, the best kept (default 5)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat: at least 1")
    check_tree(ap, args.tree)
    files = [f for f in FILES if f.is_file()]
    here = timings(ROOT, files, args.repeat)
    there = timings(args.tree.resolve(), files, args.repeat) if args.tree is not None else None
    print(f"{'file':<28} {'vertices':>9} {'faces':>8} {'sizes':<10} {'this tree':>10}"
          + (f" {'--tree':>10} {'ratio':>6}" if there else ""))
    for f in files:
        best, nv, nf, sizes = here[str(f)]
        line = f"{f.name:<28} {nv:>9,} {nf:>8,} {','.join(map(str, sizes)):<10} {best:>9.3f}s"
        if there:
            line += f" {there[str(f)][0]:>9.3f}s {there[str(f)][0] / best:>5.1f}x"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
