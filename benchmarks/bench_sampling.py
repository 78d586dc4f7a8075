"""Speed of sampling the truncated rational-Gaussian surface: numba kernel vs a plain numpy baseline.

A 69,938-triangle height field (a 188 x 188 window of the Jacksboro DEM, 3-arc-second cells of about
74.5 m x 92.5 m) sampled at 256 x 256 for s = 1, 2, 4, positions only (the sum the numpy baseline also
computes) and with exact normals. The numba compile time is measured in a fresh process with an empty
numba cache, and the cache-load time in a second process that reuses it.

Run: python benchmarks/bench_sampling.py  (about 3 minutes on 2 cores)
     python benchmarks/bench_sampling.py --tin  (s = 2 only, the grid and a Delaunay TIN of random points over
     the same window, about as many triangles, heights interpolated from the DEM; no compile timing)
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))   # the numpy twins live with the tests

import numpy as np
import geoimg

DEM = Path(__file__).resolve().parents[2] / "shared" / "data" / "dem" / "jacksboro_fault_dem.npz"
RES = 256


def terrain():

    z = np.load(DEM)["elevation"][:188, :188].astype(np.float64)
    mesh = geoimg.grid_mesh(z, spacing=(74.5, 92.5))
    return mesh, geoimg.parametrize(mesh, "heightfield")


def tin(seed: int = 0):
    """A Delaunay TIN of random points over the terrain's window (as many triangles as the grid, about),
    heights bilinear in the DEM.
    """
    from scipy.interpolate import RegularGridInterpolator
    from scipy.spatial import Delaunay

    z = np.load(DEM)["elevation"][:188, :188].astype(np.float64)
    x, y = np.arange(188) * 74.5, np.arange(188) * 92.5
    rng = np.random.default_rng(seed)
    corners = np.array([[0, 0], [x[-1], 0], [x[-1], y[-1]], [0, y[-1]]])
    pts = np.vstack([corners, rng.uniform([0, 0], [x[-1], y[-1]], size=(188 * 188 - 4, 2))])
    h = RegularGridInterpolator((y, x), z)(pts[:, ::-1])
    mesh = geoimg.Mesh(np.column_stack([pts, h]), Delaunay(pts).simplices)
    return mesh, geoimg.parametrize(mesh, "heightfield")


def first_call() -> dict:
    """In a fresh process: time of the first sample (compile or cache load) and of the next one."""
    mesh, param = terrain()
    surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=2.0))
    t = time.perf_counter()
    surf.sample(RES, normals=True)
    first = time.perf_counter() - t
    t = time.perf_counter()
    surf.sample(RES, normals=True)
    return {"first": first, "warm": time.perf_counter() - t}


def main(with_tin: bool = False):
    if with_tin:
        print(
            "| mesh | triangles | s | numpy baseline (s) | numba, positions (s) | speed-up "
            "| numba, positions + normals (s) | max abs diff |"
        )
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for name, (mesh, param) in (("grid", terrain()), ("TIN", tin())):
            compare(mesh, param, (2.0,), f"| {name} | {mesh.n_faces} ")
        return
    cache = tempfile.mkdtemp(prefix="numba-cache-")
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    runs = [json.loads(subprocess.run([sys.executable, __file__, "--first-call"], env=env, check=True,
                                      capture_output=True, text=True).stdout) for _ in range(2)]
    compile_s = runs[0]["first"] - runs[0]["warm"]
    cache_s = runs[1]["first"] - runs[1]["warm"]

    mesh, param = terrain()
    print(f"terrain: {mesh.n_vertices} vertices, {mesh.n_faces} triangles, {RES} x {RES} samples")
    print(f"numba: compile {compile_s:.1f} s (fresh cache), cache load {cache_s:.2f} s (second process)")
    print(
        "| s | numpy baseline (s) | numba, positions (s) | speed-up | numba, positions + normals (s) | max abs diff |"
    )
    print("|---:|---:|---:|---:|---:|---:|")
    compare(mesh, param, (1.0, 2.0, 4.0))


def compare(mesh, param, values, row: str = ""):
    """Table rows: the numpy baseline against the numba kernel, for each s in ``values``."""
    from geoimg.surface import _gaussian_kernels as kernels
    from reference import sample_grid_numpy   # the plain-numpy twin, in tests/

    for s in values:
        surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s))
        args = surf._grid_arguments(*surf.grid(RES))
        kernels.sample_grid_gaussian(*args, derivatives=True, log_g_ref=surf.log_g_ref)   # warm-up
        tn = []
        for _ in range(5):
            t = time.perf_counter()
            P, _, _, ok = kernels.sample_grid_gaussian(*args, derivatives=False, log_g_ref=surf.log_g_ref)
            tn.append(time.perf_counter() - t)
        td = []
        for _ in range(3):
            t = time.perf_counter()
            kernels.sample_grid_gaussian(*args, derivatives=True, log_g_ref=surf.log_g_ref)
            td.append(time.perf_counter() - t)
        t = time.perf_counter()
        P_np, _ = sample_grid_numpy(*args)
        tb = time.perf_counter() - t
        diff = np.abs(P - P_np)[ok].max()
        print(
            f"{row}| {s:g} | {tb:.2f} | {np.median(tn):.3f} | {tb / np.median(tn):.0f}x | {np.median(td):.3f} "
            f"| {diff:.1e} |",
            flush=True,
        )


if __name__ == "__main__":
    if "--first-call" in sys.argv:
        print(json.dumps(first_call()))
    else:
        main(with_tin="--tin" in sys.argv)
