"""Sums over every triangle: the default conversion where many pixels lie far from the mesh (a charts image's
gutters, summed exactly in the log domain because the truncated sum cannot certify them there), and exact
point evaluation, in a fresh process per checkout; best of several runs after a warm-up.

    python benchmarks/bench_exact_sums.py [--tree PATH] [--repeat 3] [--res 257 513] [--meshes PATH ...]

``--tree`` adds a column for another checkout (e.g. a `git worktree` of an older commit), run by the same
interpreter in the same run, and says whether the two give the same bytes (pixels and normals). The meshes
are bundled ones by default (a cut map, a disk, a sphere); held-out meshes whose default map is charts show
the gutters (``--meshes``).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from _trees import check_tree, run_json

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MESHES = [ROOT / "tests" / "data" / name for name in ("plate_holes.STL", "bob_tri.obj", "demosthenes-low-res.obj")] \
    + [ROOT / "samples" / "data" / "spot_low_resolution.obj"]

TIMER = """
import hashlib, json, sys, time, warnings
import numpy as np
import geoimg
repeat, resolutions, paths = int(sys.argv[1]), [int(r) for r in sys.argv[2].split(",")], sys.argv[3:]
out = {}
warnings.simplefilter("ignore")
for path in paths:
    mesh = geoimg.load_mesh(path)
    param = geoimg.parametrize(mesh)
    for res in resolutions:
        geoimg.mesh_to_image(mesh, res, parametrization=param)           # warm-up (and the kernels compiled)
        best = float("inf")
        for _ in range(repeat):
            t = time.perf_counter()
            img = geoimg.mesh_to_image(mesh, res, parametrization=param)
            best = min(best, time.perf_counter() - t)
        digest = hashlib.sha256(img.pixels.tobytes() + img.normals.tobytes()).hexdigest()[:16]
        out[f"{path}|{res}"] = (param.method, mesh.n_faces, best, digest, int(img.metadata["exact_pixels"]))
    try:                                        # typed weights since 2026-12-06; the flat keywords before
        surf = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=0.05))
    except AttributeError:
        surf = geoimg.fit_surface(mesh, param, 0.05, weights="coverage")
    lo, hi = np.zeros(2), np.asarray(surf.domain.extent, float) if param.method != "sphere" else None
    rng = np.random.default_rng(0)
    if hi is None:
        pts = rng.normal(size=(2000, 3))
        run = lambda: surf.evaluate_directions(pts, exact=True)[0]
    else:
        uv = lo + rng.uniform(-0.05, 1.05, (2000, 2)) * hi
        run = lambda: surf.evaluate(uv, exact=True)
    run()
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        P = run()
        best = min(best, time.perf_counter() - t)
    out[f"{path}|exact"] = (param.method, mesh.n_faces, best, hashlib.sha256(P.tobytes()).hexdigest()[:16], 2000)
print(json.dumps(out))
"""


def timings(tree: Path, files: list, repeat: int, resolutions: list) -> dict:
    return run_json(tree, TIMER, [repeat, ",".join(map(str, resolutions)), *files])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--tree", type=Path, help="another checkout to time beside this one")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each, the best kept (default 3)")
    ap.add_argument("--res", type=int, nargs="+", default=[257, 513])
    ap.add_argument("--meshes", type=Path, nargs="+", default=None, help="mesh files (default: bundled ones)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat: at least 1")
    if min(args.res) < 3:
        ap.error("--res: at least 3 pixels a side")
    check_tree(ap, args.tree)
    files = [f.resolve() for f in (args.meshes or MESHES)]
    missing = [str(f) for f in files if not f.is_file()]
    if missing:
        ap.error(f"no such mesh file: {', '.join(missing)}")
    here = timings(ROOT, files, args.repeat, args.res)
    there = timings(args.tree.resolve(), files, args.repeat, args.res) if args.tree is not None else None
    print("| mesh | map | faces | what | exact pixels or points | this tree (s) |"
          + (" --tree (s) | speed-up | same bytes |" if there else ""))
    print("|---|---|---:|---|---:|---:|" + ("---:|---:|---|" if there else ""))
    for key, (method, faces, best, digest, exact) in here.items():
        path, what = key.split("|")
        what = "exact points" if what == "exact" else f"default image {what}²"
        line = f"| {Path(path).name} | {method} | {faces} | {what} | {exact} | {best:.3f} |"
        if there:
            other = there[key]
            line += f" {other[2]:.3f} | {other[2] / best:.1f}x | {'yes' if other[3] == digest else 'NO'} |"
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
