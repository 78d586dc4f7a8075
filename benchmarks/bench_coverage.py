"""Speed of the coverage-weighted sampling (the default) against the paper's rational Gaussians at s = 1 on the
same images: a regular terrain grid and an irregular TIN (planar), and meshes on the sphere (octahedral), each
timed after a warm-up call, best of three, in one process. The last column divides a row's coverage time per
face by the terrain grid's at the same size, for rows of about the terrain's face count: a regular mesh on the
sphere (a cube of 6 x 64 x 64 quads split in two, projected onto the sphere and bumped by 5 %, mapped by its own
directions) compares the two domains at equal face count.

    python benchmarks/bench_coverage.py [--res 257 513] [--repeat 3]
    python benchmarks/bench_coverage.py --interleave 20     # only the terrain against the cube, alternating

``--interleave N`` times the terrain grid's and the cube's ``sample(res)`` alternately N times (after one
warm-up each) and keeps each one's best: the octahedral-over-planar figure per face, with machine noise hitting
both alike.
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


def cube_sphere(k: int = 64, bump: float = 0.05):
    """A cube of 6 x k x k quads, each split in two, projected onto the sphere and bumped radially
    (``r = 1 + bump sin 5x sin 4y``), outward-facing; and its vertices' directions.
    """
    import numpy as np
    t = np.linspace(-1.0, 1.0, k + 1)
    pts, faces = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            a, b = np.meshgrid(t, t, indexing="ij")
            p = np.empty((k + 1, k + 1, 3))
            p[..., axis] = sign
            p[..., (axis + 1) % 3] = a
            p[..., (axis + 2) % 3] = b
            idx = sum(len(x) for x in pts) + np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
            pts.append(p.reshape(-1, 3))
            q0, q1, q2, q3 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
            tri = np.concatenate([np.stack([q0, q1, q2], -1).reshape(-1, 3), np.stack([q0, q2, q3], -1).reshape(-1, 3)])
            faces.append(tri if sign > 0 else tri[:, ::-1])
    pts = np.concatenate(pts)
    _, first, inverse = np.unique(np.round(pts, 9), axis=0, return_index=True, return_inverse=True)
    d = pts[first] / np.linalg.norm(pts[first], axis=1, keepdims=True)
    r = 1.0 + bump * np.sin(5 * d[:, 0]) * np.sin(4 * d[:, 1])
    return geoimg.Mesh(d * r[:, None], inverse.ravel()[np.concatenate(faces)]), d


def interleaved(resolutions, runs: int) -> int:
    """The terrain grid and the cube on the sphere sampled alternately ``runs`` times at each size, best kept."""
    import numpy as np
    terrain = geoimg.load_mesh(ROOT / "geoimg" / "data" / "mountain.obj")
    cube, directions = cube_sphere()
    pairs = [(terrain, geoimg.parametrize(terrain, "heightfield")),
             (cube, geoimg.Parametrization(directions, (1.0, 1.0), "octahedral", "sphere"))]
    print("| res | terrain grid (s) | cube on the sphere (s) | octahedral / planar per face |")
    print("|---:|---:|---:|---:|")
    for res in resolutions:
        cases = []
        for mesh, param in pairs:
            base = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
            size = base.domain.round_resolution(res)
            cases.append((base.with_s(prefilter_s(base, size)), size, mesh.n_faces))
        best = np.full(2, np.inf)
        for run in range(runs + 1):
            for k, (cover, size, _) in enumerate(cases):
                t0 = time.perf_counter()
                cover.with_s(cover.s).sample(size)          # cells rebuilt, as a conversion does
                if run:                                     # the first round warms up
                    best[k] = min(best[k], time.perf_counter() - t0)
        per_face = (best[1] / cases[1][2]) / (best[0] / cases[0][2])
        print(f"| {res} | {best[0]:.4f} | {best[1]:.4f} | {per_face:.2f} |", flush=True)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--res", type=int, nargs="+", default=[257, 513])
    ap.add_argument("--repeat", type=int, default=3, help="timings per case, the best kept")
    ap.add_argument("--interleave", type=int, default=0, metavar="N",
                    help="only the terrain grid against the cube on the sphere, N alternating timings each")
    args = ap.parse_args(argv)
    if args.interleave < 0 or args.repeat < 1 or min(args.res) < 3:
        ap.error("--interleave must be 0 or more, --repeat 1 or more, and every --res 3 or more")
    warnings.simplefilter("ignore")
    if args.interleave:
        return interleaved(args.res, args.interleave)
    sys.path.insert(0, str(ROOT / "tests"))
    from meshes import cap
    tin = cap(80.0, rings=120, segments=180)  # irregular: rings of varying triangles
    cases = [
        ("terrain grid (mountain.obj)", geoimg.load_mesh(ROOT / "geoimg" / "data" / "mountain.obj"), "heightfield"),
        ("TIN (cap, rings)", geoimg.Mesh(tin.vertices, tin.triangulate()[0]), "heightfield"),
    ]
    cube, directions = cube_sphere()
    cases.append(("cube on the sphere", cube, geoimg.Parametrization(directions, (1.0, 1.0), "octahedral", "sphere")))
    for rel in ("closed_genus0/bunny.obj", "closed_genus0/bunny.off"):
        if (SHARED / rel).is_file():
            cases.append((rel.split("/")[1], geoimg.load_mesh(SHARED / rel), "sphere"))
    print("| mesh | faces | res | domain | paper s=1 (s) | coverage default (s) | ratio | per face, over the grid's |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    grid = {}
    for name, mesh, method in cases:
        param = geoimg.parametrize(mesh, method) if isinstance(method, str) else method
        paper = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights())
        base = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
        for res in args.res:
            res = paper.domain.round_resolution(res)
            cover = base.with_s(prefilter_s(base, res))
            tp = _best(lambda: paper.sample(res), args.repeat)
            # cells rebuilt each time, as a conversion does
            tc = _best(lambda: cover.with_s(cover.s).sample(res), args.repeat)
            grid.setdefault(res, (mesh.n_faces, tc))
            faces, t_grid = grid[res]
            equal = abs(mesh.n_faces / faces - 1.0) < 0.1       # only about equal face counts compare
            ratio = f"{tc / mesh.n_faces / (t_grid / faces):.2f}" if equal else ""
            print(f"| {name} | {mesh.n_faces} | {res} | {paper.domain.kind} | {tp:.3f} | {tc:.3f} | {tc / tp:.2f} "
                  f"| {ratio} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
