"""Speed of the coverage-weighted sampling (the default) against the paper's rational Gaussians at s = 1 on the
same images: a regular terrain grid and an irregular TIN (planar), and meshes on the sphere (octahedral), each
timed after a warm-up call, best of three, alternating, in one process.

    python benchmarks/bench_coverage.py [--res 257 513]
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path


import geoimg
from geoimg.surface._coverage import prefilter_s

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"


def _best(fn, k=3):
    fn()
    out = []
    for _ in range(k):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--res", type=int, nargs="+", default=[257, 513])
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    sys.path.insert(0, str(ROOT / "tests"))
    from meshes import cap
    tin = cap(80.0, rings=120, segments=180)  # irregular: rings of varying triangles
    cases = [
        ("terrain grid (mountain.obj)", geoimg.load_mesh(ROOT / "geoimg" / "data" / "mountain.obj"), "heightfield"),
        ("TIN (cap, rings)", geoimg.Mesh(tin.vertices, tin.triangulate()[0]), "heightfield"),
    ]
    for rel in ("closed_genus0/bunny.obj", "closed_genus0/bunny.off"):
        if (SHARED / rel).is_file():
            cases.append((rel.split("/")[1], geoimg.load_mesh(SHARED / rel), "sphere"))
    print("| mesh | faces | res | domain | paper s=1 (s) | coverage default (s) | ratio |")
    print("|---|---|---|---|---|---|---|")
    for name, mesh, method in cases:
        param = geoimg.parametrize(mesh, method)
        paper = geoimg.fit_surface(mesh, param, 1.0)
        base = geoimg.fit_surface(mesh, param, 1.0, weights="coverage")
        for res in args.res:
            res = paper.domain.round_resolution(res)
            cover = base.with_s(prefilter_s(base, res))
            tp = _best(lambda: paper.sample(res))
            tc = _best(lambda: cover.with_s(cover.s).sample(res))    # cells rebuilt each time, as a conversion does
            print(f"| {name} | {mesh.n_faces} | {res} | {paper.domain.kind} | {tp:.3f} | {tc:.3f} | {tc / tp:.2f} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
