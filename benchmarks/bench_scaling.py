"""How sampling scales (issue 14): seconds against faces at a fixed image size, and against pixels at a fixed
face count, for the planar and the octahedral domain; and the peak memory of a 250k-face mesh to a 1025²
image. Each case runs in a fresh process (so peak RSS is its own), after a warm-up call that loads the
numba cache; the time is fit + sample, positions only, s = 1. `--compare`: the octahedral kernel with and without
normals against the planar one, at 513² to 2049².

    python benchmarks/bench_scaling.py          (about 5 minutes on 2 cores)

Meshes: planar, a bumpy random-point Delaunay TIN (irregular) parametrized by its (x, y); octahedral, a
bumpy subdivided icosahedron parametrized by its own vertex directions (exact, so the parametrization's
cost is left out: it is measured in bench_sphere.py). The slope is the least-squares exponent of time
against faces (or pixels) over the sweep: 1 is linear.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CASE = r'''
import json, resource, sys, time, warnings
import numpy as np
from scipy.spatial import Delaunay
import geoimg
warnings.simplefilter("ignore")
kind, faces, res, normals = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[5] == "1"
rng = np.random.default_rng(0)
if kind == "planar":
    pts = rng.random((faces // 2 + 2, 2))
    tri = Delaunay(pts).simplices
    z = 0.05 * np.sin(9 * pts[:, 0]) * np.cos(7 * pts[:, 1]) + 0.01 * rng.random(len(pts))
    mesh = geoimg.Mesh(np.column_stack([pts, z]), tri)
    param = geoimg.Parametrization(pts, (1.0, 1.0))
else:
    sys.path.insert(0, sys.argv[4])
    import meshes
    k = int(round(np.log(faces / 20) / np.log(4)))
    ball = meshes.icosphere(k)
    d = ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True)
    r = 1 + 0.1 * np.sin(5 * d[:, 0]) * np.sin(4 * d[:, 1]) * np.sin(3 * d[:, 2])
    mesh = geoimg.Mesh(d * r[:, None], ball.faces)
    param = geoimg.Parametrization(d, (1.0, 1.0), "octahedral", "sphere")
warm = geoimg.fit_surface(mesh, param, 1.0).sample(17, normals=False)          # numba cache loaded
t = time.perf_counter()
img = geoimg.fit_surface(mesh, param, 1.0).sample(res, normals=normals)
dt = time.perf_counter() - t
print(json.dumps({"kind": kind, "faces": int(mesh.n_faces), "res": res, "seconds": dt,
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
'''


def run(kind: str, faces: int, res: int, normals: bool = False) -> dict:
    out = subprocess.run([sys.executable, "-c", CASE, kind, str(faces), str(res), str(ROOT / "tests"),
                          "1" if normals else "0"],
                         capture_output=True, text=True, timeout=1200, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def slope(x, y) -> float:
    import numpy as np
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def compare():
    """Octahedral positions alone against positions with exact normals (what the kernel summed before the
    positions-only path, whatever was asked), and the planar kernel at about the same face count."""
    print("| image | planar 99,971 faces, positions | octahedral 81,920, positions | octahedral, with normals |"
          " octahedral / planar (positions) |")
    print("|---|---:|---:|---:|---:|")
    for res in (513, 1025, 2049):
        pl, oc, on = run("planar", 100_000, res), run("octahedral", 81_920, res), run("octahedral", 81_920, res, True)
        print(f"| {res}² | {pl['seconds']:.2f} | {oc['seconds']:.2f} | {on['seconds']:.2f} | "
              f"{oc['seconds'] / pl['seconds']:.1f} |", flush=True)


def main():
    if "--compare" in sys.argv:
        compare()
        return
    rows = []
    sweeps = {"planar": ([10_000, 30_000, 100_000, 250_000], [129, 257, 513, 1025, 2049]),
              "octahedral": ([20 * 4 ** k for k in (5, 6, 7)], [129, 257, 513, 1025, 2049])}
    print("| domain | faces | image | seconds | peak RSS (MB) |")
    print("|---|---:|---:|---:|---:|")
    for kind, (face_sweep, res_sweep) in sweeps.items():
        by_faces = [run(kind, f, 513) for f in face_sweep]
        mid = face_sweep[len(face_sweep) // 2] if kind == "planar" else face_sweep[1]
        by_pixels = [run(kind, mid, r) for r in res_sweep]
        for r in by_faces + by_pixels:
            print(f"| {kind} | {r['faces']:,} | {r['res']}² | {r['seconds']:.2f} | {r['peak_mb']:.0f} |", flush=True)
        rows.append((kind, slope([r["faces"] for r in by_faces], [r["seconds"] for r in by_faces]),
                     slope([r["res"] ** 2 for r in by_pixels], [r["seconds"] for r in by_pixels])))
    big = run("octahedral", 327_680, 1025)
    print(f"\nA {big['faces']:,}-face octahedral mesh to a 1025² image: {big['seconds']:.1f} s, peak RSS "
          f"{big['peak_mb']:.0f} MB (fit and sample; the sphere parametrization is not included).")
    for kind, sf, sp in rows:
        print(f"{kind}: time ~ faces^{sf:.2f} at 513²; time ~ pixels^{sp:.2f} at a fixed mesh")


if __name__ == "__main__":
    main()
