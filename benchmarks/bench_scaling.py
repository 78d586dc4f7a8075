"""How sampling scales (issue 14): seconds against faces at a fixed image size, and against pixels at a fixed
face count, for the planar and the octahedral domain; and the peak memory of a 250k-face mesh to a 1025²
image. Each case runs in a fresh process (so peak RSS is its own), after a warm-up call that loads the
numba cache; the time is fit + sample, positions only, s = 1. `--compare`: the octahedral kernel with and without
normals against the planar one, at 513² to 2049².

    python benchmarks/bench_scaling.py          (about 5 minutes on 2 cores; also draws scaling.png, log-log)
    python benchmarks/bench_scaling.py --compare

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
    """The octahedral kernel against the planar one at about the same face count, positions alone and with
    exact normals, best of 3 fresh processes each (this machine's timings vary by tens of per cent).
    """
    print("| image | planar 99,971 faces: positions / with normals | octahedral 81,920: positions / with normals |"
          " octahedral / planar: positions / with normals |")
    print("|---|---:|---:|---:|")
    for res in (513, 1025, 2049):
        t = {(kind, nrm): min(run(kind, faces, res, nrm)["seconds"] for _ in range(3))
             for kind, faces in (("planar", 100_000), ("octahedral", 81_920)) for nrm in (False, True)}
        print(f"| {res}² | {t['planar', False]:.2f} / {t['planar', True]:.2f} | {t['octahedral', False]:.2f} / "
              f"{t['octahedral', True]:.2f} | {t['octahedral', False] / t['planar', False]:.2f} / "
              f"{t['octahedral', True] / t['planar', True]:.2f} |", flush=True)


def plot(sweeps: dict, path: Path) -> None:
    """A log-log picture of the two sweeps (seconds against faces at 513², against pixels at a fixed mesh),
    drawn with OpenCV: one panel each, planar in blue, octahedral in orange, a dashed slope-1 guide.
    """
    import cv2
    import numpy as np

    W, H, pad = 520, 400, 60
    img = np.full((H, 2 * W, 3), 255, np.uint8)
    colours = {"planar": (200, 90, 30), "octahedral": (30, 130, 240)}
    for panel, (key, label) in enumerate((("faces", "faces (513^2 image)"), ("pixels", "pixels (fixed mesh)"))):
        x0 = panel * W
        pts = [(r[key], r["seconds"]) for rows in sweeps.values() for r in rows[key]]
        lx = np.log10([p[0] for p in pts])
        ly = np.log10([p[1] for p in pts])
        xlo, xhi = np.floor(lx.min()), np.ceil(lx.max())
        ylo, yhi = np.floor(ly.min()), np.ceil(ly.max())

        def at(x, y):
            return (int(x0 + pad + (np.log10(x) - xlo) / (xhi - xlo) * (W - 2 * pad)),
                    int(H - pad - (np.log10(y) - ylo) / (yhi - ylo) * (H - 2 * pad)))

        cv2.rectangle(img, (x0 + pad, pad), (x0 + W - pad, H - pad), (0, 0, 0), 1)
        for e in range(int(xlo), int(xhi) + 1):
            cv2.putText(img, f"1e{e}", at(10.0 ** e, 10.0 ** ylo)[:1] + (H - pad + 18,), cv2.FONT_HERSHEY_SIMPLEX,
                        0.4, (0, 0, 0), 1, cv2.LINE_AA)
        for e in range(int(ylo), int(yhi) + 1):
            cv2.putText(img, f"1e{e} s", (x0 + 8, at(10.0 ** xlo, 10.0 ** e)[1] + 4), cv2.FONT_HERSHEY_SIMPLEX,
                        0.4, (0, 0, 0), 1, cv2.LINE_AA)
        cv2.putText(img, label, (x0 + pad, H - 12), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
        for kind, rows in sweeps.items():
            xy = [at(r[key], r["seconds"]) for r in rows[key]]
            for a, b in zip(xy, xy[1:]):
                cv2.line(img, a, b, colours[kind], 2, cv2.LINE_AA)
            for c in xy:
                cv2.circle(img, c, 4, colours[kind], -1, cv2.LINE_AA)
            first = rows[key][0]
            for k in range(20):              # slope 1 through the first point, dashed
                f0, f1 = k / 20, (k + 0.5) / 20
                xa = first[key] * (10.0 ** xhi / first[key]) ** f0
                xb = first[key] * (10.0 ** xhi / first[key]) ** f1
                if first["seconds"] * xb / first[key] < 10.0 ** yhi:
                    cv2.line(
                        img,
                        at(xa, first["seconds"] * xa / first[key]),
                        at(xb, first["seconds"] * xb / first[key]),
                        tuple(int(0.5 * c + 127) for c in colours[kind]),
                        1,
                        cv2.LINE_AA,
                    )
        for k, kind in enumerate(sweeps):
            cv2.putText(img, kind, (x0 + pad + 10, pad + 20 + 18 * k), cv2.FONT_HERSHEY_SIMPLEX, 0.5,
                        colours[kind], 1, cv2.LINE_AA)
        cv2.putText(img, "dashed: slope 1 (linear)", (x0 + pad + 10, pad + 20 + 18 * len(sweeps)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.5, (120, 120, 120), 1, cv2.LINE_AA)
    cv2.imwrite(str(path), img)


def main():
    if "--compare" in sys.argv:
        compare()
        return
    rows = []
    sweeps = {"planar": ([10_000, 30_000, 100_000, 250_000], [129, 257, 513, 1025, 2049]),
              "octahedral": ([20 * 4 ** k for k in (5, 6, 7)], [129, 257, 513, 1025, 2049])}
    measured = {}
    print("| domain | faces | image | seconds | peak RSS (MB) |")
    print("|---|---:|---:|---:|---:|")
    for kind, (face_sweep, res_sweep) in sweeps.items():
        by_faces = [run(kind, f, 513) for f in face_sweep]
        mid = face_sweep[len(face_sweep) // 2] if kind == "planar" else face_sweep[1]
        by_pixels = [run(kind, mid, r) for r in res_sweep]
        for r in by_faces + by_pixels:
            r["pixels"] = r["res"] ** 2
            print(f"| {kind} | {r['faces']:,} | {r['res']}² | {r['seconds']:.2f} | {r['peak_mb']:.0f} |", flush=True)
        measured[kind] = {"faces": by_faces, "pixels": by_pixels}
        rows.append((kind, slope([r["faces"] for r in by_faces], [r["seconds"] for r in by_faces]),
                     slope([r["pixels"] for r in by_pixels], [r["seconds"] for r in by_pixels])))
    big = run("octahedral", 327_680, 1025)
    print(f"\nA {big['faces']:,}-face octahedral mesh to a 1025² image: {big['seconds']:.1f} s, peak RSS "
          f"{big['peak_mb']:.0f} MB (fit and sample; the sphere parametrization is not included).")
    for kind, sf, sp in rows:
        print(f"{kind}: time ~ faces^{sf:.2f} at 513²; time ~ pixels^{sp:.2f} at a fixed mesh")
    plot(measured, ROOT / "benchmarks" / "scaling.png")
    print("log-log plot: benchmarks/scaling.png")


if __name__ == "__main__":
    main()
