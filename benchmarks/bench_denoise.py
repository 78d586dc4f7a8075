"""Denoising a mesh through its geometry image (issue 16) against mesh-space smoothing (trimesh's Laplacian
and Taubin filters), in one run, on meshes with scanner-like noise.

    python benchmarks/bench_denoise.py [--res 513]

Noise: every vertex moved along its normal by a Gaussian of sigma = 0.25 % of the bounding-box diagonal,
and 0.5 % of the vertices by +-8 sigma (a scanner's outliers); seeded. Image route: the noisy mesh
parametrized as a user would (`auto`), sampled at s = 0.5 (little smoothing of its own) at --res and at
about one pixel a vertex, denoised by `geoimg filter` steps, turned into its quad mesh. The clean mesh's
image on the same parametrization is the floor of each resolution. Mesh route: trimesh.smoothing on the noisy triangles.
Each method is swept over a few strengths; the table gives its best RMS distance to the clean mesh (two
sided, area-sampled, per mille of the diagonal), the Hausdorff distance of that result and its time (the
denoising step alone; the image route's conversion time, parametrization included, is in its own row).
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import trimesh

import geoimg
from geoimg._steps import apply_steps
from geoimg.mesh import surface_distance

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "samples"))
from denoise import noisy_copy                # noqa: E402  (the sample's noise, the same seed)

SHARED = ROOT.parent / "shared" / "data" / "meshes"
MESHES = [("bunny.off (closed)", SHARED / "closed_genus0" / "bunny.off"),
          ("spot.obj (closed)", ROOT / "tests" / "data" / "spot.obj"),
          ("camelhead.off (disk)", SHARED / "open_disk" / "camelhead.off"),
          ("mountain.obj (terrain)", ROOT / "geoimg" / "data" / "mountain.obj")]
def image_steps(sigma: float):
    """(label, steps) of the image-route sweep; strengths in pixels or in units of the noise's sigma."""
    return ([(f"gaussian {g}", [("gaussian", [g])]) for g in (1.0, 2.0, 3.0, 5.0)]
            + [(f"median {k}", [("median", [k])]) for k in (3, 5)]
            + [(f"median 3 + gaussian {g}", [("median", [3]), ("gaussian", [g])]) for g in (1.0, 2.0)]
            + [(f"bilateral 2, {r} sigma", [("bilateral", [2.0, r * sigma])]) for r in (2, 4)]
            + [(f"tv {w} sigma", [("tv", [w * sigma])]) for w in (1, 3, 10, 30)]
            + [(f"nlmeans {h} sigma", [("nlmeans", [h * sigma])]) for h in (1, 2, 4, 8)]
            + [(f"median 3 + nlmeans {h} sigma", [("median", [3]), ("nlmeans", [h * sigma])]) for h in (1, 2)])


def family(label: str) -> str:
    return label.rsplit(" ", 2)[0] if "sigma" in label else label.rsplit(" ", 1)[0]


def score(clean: geoimg.Mesh, out: geoimg.Mesh) -> tuple[float, float]:
    d = surface_distance(clean, out, n=60000)
    return 1e3 * d["rms"] / d["diagonal"], 1e3 * d["hausdorff"] / d["diagonal"]


def vertex_resolution(mesh: geoimg.Mesh, param) -> int:
    """About one pixel a vertex: the noise stays white in the image (one vertex's step is one pixel's)."""
    side = int(np.sqrt(mesh.n_vertices / (param.extent[0] * param.extent[1]))) + 1
    return side | 1 if param.domain == "octahedral" else side


def run_mesh(name: str, path: Path, res: int) -> list:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        clean = geoimg.load_mesh(path)
        noisy, sigma = noisy_copy(clean)
        rows = [(name, "noisy input", *score(clean, noisy), 0.0)]
        t = time.perf_counter()
        param = geoimg.parametrize(noisy)
        t_param = time.perf_counter() - t
        best = {}
        for size in sorted({res, vertex_resolution(noisy, param)}):
            t = time.perf_counter()
            image = geoimg.mesh_to_image(noisy, size, normals=False, parametrization=param,
                                         weights=geoimg.CoverageWeights(s=0.5))
            convert = t_param + time.perf_counter() - t
            floor = geoimg.mesh_to_image(clean, size, normals=False, parametrization=param,
                                         weights=geoimg.CoverageWeights(s=0.5))
            rows.append((name, f"{size}²: the clean mesh's own image ({image.domain.kind}; the floor)",
                         *score(clean, floor.to_mesh()), 0.0))
            rows.append((name, f"{size}²: the noisy image, not denoised (conversion time)",
                         *score(clean, image.to_mesh()), convert))
            for label, steps in image_steps(sigma):
                t = time.perf_counter()
                out = apply_steps(image, steps)
                dt = time.perf_counter() - t
                rms, haus = score(clean, out.to_mesh())
                key = f"image {size}²: " + family(label)
                if key not in best or rms < best[key][1]:
                    best[key] = (label, rms, haus, dt)
        tm = trimesh.Trimesh(noisy.vertices, noisy.triangulate()[0], process=False)
        for kind, sweep in (("laplacian", (1, 2, 5, 10, 20)), ("taubin", (5, 10, 20, 50, 100))):
            for it in sweep:
                m = tm.copy()
                t = time.perf_counter()
                if kind == "laplacian":
                    trimesh.smoothing.filter_laplacian(m, lamb=0.5, iterations=it)
                else:
                    trimesh.smoothing.filter_taubin(m, iterations=it)
                dt = time.perf_counter() - t
                rms, haus = score(clean, geoimg.Mesh(m.vertices, m.faces))
                key = f"mesh: trimesh {kind}"
                if key not in best or rms < best[key][1]:
                    best[key] = (f"{kind} {it} iterations", rms, haus, dt)
        for key, (label, rms, haus, dt) in sorted(best.items(), key=lambda kv: kv[1][1]):
            rows.append((name, f"{key} (best: {label})", rms, haus, dt))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--res", type=int, default=513)
    args = ap.parse_args(argv)
    print("| mesh | method | RMS to clean (‰ diag) | Hausdorff (‰ diag) | seconds |")
    print("|---|---|---:|---:|---:|")
    for name, path in MESHES:
        if not path.is_file():
            print(f"| {name} | missing: {path} | | | |")
            continue
        for row in run_mesh(name, path, args.res):
            print(f"| {row[0]} | {row[1]} | {row[2]:.3f} | {row[3]:.2f} | {row[4]:.2f} |", flush=True)


if __name__ == "__main__":
    main()
