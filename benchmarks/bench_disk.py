"""Disk maps before and after SLIM and area balancing (issue 18, the disk part): area distortion, folds, PSNR and
Hausdorff of the quad mesh at 513², and time against one sparse solve, on the open disks of ../shared/data, a quad
disk, Spot opened at the belly (samples/balanced_disk.py) and a synthetic finger (tests/meshes.py).

    python benchmarks/bench_disk.py [--res 513]

Area log-RMS here is area-weighted (each triangle's log of its parameter-area share over its surface-area
share, RMS weighted by surface area, as the sphere path reports it); info["area_log_rms"] of a disk
parametrization is the unweighted RMS over triangles, which is what SLIM's stopping rule watches.
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

import geoimg
from geoimg.mesh import boundary_loops, surface_distance
from geoimg.parametrization._laplacian import mean_value_weights

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "samples")]
import meshes                    # noqa: E402  (the test's synthetic meshes)
from balanced_disk import open_at_the_belly          # noqa: E402


def weighted_log_rms(mesh: geoimg.Mesh, uv: np.ndarray) -> float:
    tris, _ = mesh.triangulate()
    p = mesh.vertices[tris]
    a3 = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    e1, e2 = uv[tris[:, 1]] - uv[tris[:, 0]], uv[tris[:, 2]] - uv[tris[:, 0]]
    a2 = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    ok = (a3 > 0) & (a2 > 0)
    w = a3[ok] / a3[ok].sum()
    return float(np.sqrt(w @ np.log((a2[ok] / a2[ok].sum()) / w) ** 2))


def linear_solve_time(mesh: geoimg.Mesh) -> float:
    """One sparse LU solve of the mean-value system (the interior given the boundary): the 'linear map'."""
    tris, _ = mesh.triangulate()
    W = mean_value_weights(mesh.vertices, tris).tocsr()
    loop = boundary_loops(mesh)[0]
    free = np.setdiff1d(np.flatnonzero(mesh.referenced_vertices()), loop)
    t0 = time.perf_counter()
    A = (W[free][:, free]).tocsc()
    deg = np.asarray(W[free].sum(axis=1)).ravel()
    A = (A - sparse.diags(deg)).tocsc()
    lu = splu(A, permc_spec="COLAMD")
    lu.solve(np.ones((len(free), 2)))
    return time.perf_counter() - t0


def cases():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in ("camelhead.off", "hemisphere.off", "cube_no_bottom.obj", "mountain.obj"):
            if (SHARED / "open_disk" / name).is_file():
                yield name, geoimg.load_mesh(SHARED / "open_disk" / name)
        quad = SHARED / "polygonal" / "inspired_mesh_quads_Conjugate.off"
        if quad.is_file():
            yield quad.name, geoimg.load_mesh(quad)
    yield "Spot open at the belly", open_at_the_belly()
    yield "finger (synthetic)", meshes.finger()


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--res", type=int, default=513)
    args = ap.parse_args()
    print(f"| mesh | faces | map | area log-RMS (weighted) | folds | time (s) | x one solve | PSNR at {args.res}² (dB) "
          "| Hausdorff / diagonal |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    with warnings.catch_warnings():              # load libigl and the kernels before any timing
        warnings.simplefilter("ignore")
        for balance in ("slim", "area"):
            geoimg.parametrize(meshes.finger(rows=6), "disk", balance=balance)
    for name, mesh in cases():
        solve = min(linear_solve_time(mesh) for _ in range(3))
        for balance in ("none", "slim", "area"):
            t0 = time.perf_counter()
            p = geoimg.parametrize(mesh, "disk", balance=balance)
            t = time.perf_counter() - t0
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                quads = geoimg.mesh_to_image(mesh, args.res, parametrization=p).to_mesh()
            d = surface_distance(mesh, quads, n=100000)
            label = {"none": "mean-value", "slim": f"+ SLIM ({p.info['slim_steps']} steps)",
                     "area": f"+ area balancing ({p.info['balance_steps']} steps)"}[balance]
            print(f"| {name} | {mesh.n_faces} | {label} | {weighted_log_rms(mesh, p.coords):.2f} | {p.flipped_faces} "
                  f"| {t:.2f} | {t / solve:.0f} | {d['psnr_db']:.1f} | {d['hausdorff'] / d['diagonal']:.4f} |",
                  flush=True)


if __name__ == "__main__":
    main()
