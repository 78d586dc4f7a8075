"""Closed genus-0 meshes through the octahedral domain: parametrization and sampling time, distortion,
Hausdorff distance and PSNR between the input and the reconstructed quad mesh (s = 1).

Run by hand:  python benchmarks/bench_sphere.py [mesh ...]   (paths relative to ../shared/data/meshes;
              NAME+sub: subdivided once)
              python benchmarks/bench_sphere.py --ratios [mesh ...]   (time over the linear map only)
Also writes the bunny's octahedral image, its quad mesh rendering and a distortion map to benchmarks/.
"""
from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.sparse.linalg import splu

import geoimg
from geoimg.mesh import surface_distance
from geoimg.parametrization import area_ratio
from geoimg.mesh import topology
from geoimg.parametrization._laplacian import cotangent_weights, laplacian

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "meshes"
MESHES = ["closed_genus0/sphere.obj", "closed_genus0/bumpy.off", "closed_genus0/spot_low_resolution.obj",
          "closed_genus0/spot.obj", "closed_genus0/bunny.obj", "closed_genus0/armadillo.obj",
          "closed_genus0/human_man.obj", "closed_genus0/bunny.off", "polygonal/horse_quad.obj",
          "polygonal/chamfer-cube.off", "polygonal/spot_control_mesh.obj", "polygonal/cylinder.obj",
          "polygonal/sword-quad-dominant.obj"]
SIZES = (129, 257, 513)


def samples_per_area(mesh, s):
    """Octahedral-grid samples per unit of surface area, per triangle, relative to the mean: (min, max, p1, p99)."""
    tris, _ = mesh.triangulate()
    p3, p2 = mesh.vertices[tris], s[tris]
    a3 = 0.5 * np.linalg.norm(np.cross(p3[:, 1] - p3[:, 0], p3[:, 2] - p3[:, 0]), axis=1)
    a2 = 0.5 * np.linalg.norm(np.cross(p2[:, 1] - p2[:, 0], p2[:, 2] - p2[:, 0]), axis=1)
    dens = a2 * area_ratio(p2.mean(axis=1)) / np.maximum(a3, 1e-300)
    dens /= (dens * a3).sum() / a3.sum()
    return dens.min(), dens.max(), np.percentile(dens, 1), np.percentile(dens, 99)


def linear_map_time(mesh) -> float:
    """One linear conformal map with plain scipy: the cotangent Laplacian, one vertex pinned, one sparse LU solve
    (COLAMD) for a dipole at a face; what issues 14 and 18 compare the parametrization's time with.
    """
    t0 = time.perf_counter()
    tris, _ = mesh.triangulate()
    L = laplacian(cotangent_weights(mesh.vertices, tris))
    keep = np.flatnonzero(mesh.referenced_vertices())[1:]
    rhs = np.zeros((len(keep), 2))
    rhs[:3] = [[1.0, 0.0], [-1.0, 1.0], [0.0, -1.0]]
    splu(L[keep][:, keep].tocsc(), permc_spec="COLAMD").solve(rhs)
    return time.perf_counter() - t0


def load(name: str):
    """A mesh of ../shared/data/meshes; ``NAME+sub`` subdivides it once (Loop, trimesh): 4x the faces."""
    mesh = geoimg.load_mesh(DATA / name.replace("+sub", ""))
    if name.endswith("+sub"):
        import trimesh
        v, f = trimesh.remesh.subdivide(mesh.vertices, mesh.triangulate()[0])
        mesh = geoimg.Mesh(v, f)
    return mesh


def ratios(names):
    """The sphere parametrization's time over the linear map's, alternating in one process: best of 2 and
    of 3, after a warm-up on a small mesh.
    """
    warnings.simplefilter("ignore")
    geoimg.parametrize(geoimg.load_mesh(DATA / "closed_genus0/spot_low_resolution.obj"), "sphere")
    print("| mesh | faces | linear map s | sphere map s | ratio | start | area log-RMS |")
    print("|---|---:|---:|---:|---:|---|---:|")
    for name in names:
        mesh = load(name)
        lin, par = [], []
        for k in range(3):
            lin.append(linear_map_time(mesh))
            if k < 2:
                t = time.perf_counter()
                param = geoimg.parametrize(mesh, "sphere")
                par.append(time.perf_counter() - t)
        print(f"| {name} | {mesh.n_faces} | {min(lin):.3f} | {min(par):.2f} | {min(par) / min(lin):.1f}x | "
              f"{param.info['start']} | {param.info['area_log_rms']:.2f} |", flush=True)


def main(names):
    warnings.simplefilter("ignore")
    print("| mesh | faces | param s | x linear map | flips | area log-RMS | samples/area min..max (p1..p99) | N | "
          "sample s | closed | Hausdorff/diag | PSNR dB |")
    print("|---|---:|---:|---:|---:|---:|---|---:|---:|:--:|---:|---:|")
    for name in names:
        mesh = load(name)
        t = time.perf_counter()
        param = geoimg.parametrize(mesh, "sphere")
        t_param = time.perf_counter() - t
        t_linear = min(linear_map_time(mesh) for _ in range(3))
        lo, hi, p1, p99 = samples_per_area(mesh, param.coords)
        surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights())
        surf.sample(9)   # compile / warm the cells
        for n in SIZES:
            t = time.perf_counter()
            img = surf.sample(n)
            t_sample = time.perf_counter() - t
            quads = img.to_mesh()
            topo = topology(quads)
            d = surface_distance(mesh, quads, n=100000)
            print(f"| {name.split('/')[-1]} | {mesh.n_faces} | {t_param:.2f} | {t_param / t_linear:.0f} | "
                  f"{param.flipped_faces} | {param.info['area_log_rms']:.2f} | "
                  f"{lo:.3f}..{hi:.2f} ({p1:.2f}..{p99:.2f}) | {n} | {t_sample:.2f} | "
                  f"{'yes' if topo.closed and topo.genus == 0 else 'NO'} | {d['hausdorff'] / d['diagonal']:.2e} | "
                  f"{d['psnr_db']:.1f} |", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--ratios"]:
        ratios(sys.argv[2:] or ["closed_genus0/bunny.off", "closed_genus0/armadillo.obj+sub",
                                "closed_genus0/bunny.off+sub"])
    else:
        main(sys.argv[1:] or MESHES)
