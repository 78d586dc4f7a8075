"""The planar sampling kernel on a CUDA GPU against the CPU kernel (issue 14): a 4096² image of a
1M-face mesh, positions only and with normals, s = 1 and 2.

    python benchmarks/bench_cuda.py                 (needs a CUDA GPU; --faces/--res to shrink it)
    python benchmarks/bench_cuda.py --check-only    (the agreement checks alone)

Mesh: a bumpy Delaunay TIN of random points (irregular), parametrized by its (x, y). First the two
kernels are compared on small images (float64 outputs, fresh random TINs, s from 0.2 to 3, where the
smallest s leaves pixels uncertified); then each is timed on the large one after a warm-up call.
The CPU kernel runs once per case on all the machine's cores (numba's threads); the GPU kernel's time is the
best of 3 and is split into the host's work (truncation boxes and tile lists), the transfers and the
kernel. ``sample()`` is also timed whole for both backends (masks, normals and the float32 image
included).
"""
from __future__ import annotations

import argparse
import json
import os
import time
import warnings

import numpy as np
from scipy.spatial import Delaunay

import geoimg
from geoimg.surface import _gaussian_kernels as kernels



def tin(n_faces: int, seed: int):
    rng = np.random.default_rng(seed)
    pts = np.vstack([rng.random((n_faces // 2 - 1, 2)), [[0, 0], [1, 0], [0, 1], [1, 1]]])
    tri = Delaunay(pts).simplices
    z = 0.05 * np.sin(9 * pts[:, 0]) * np.cos(7 * pts[:, 1]) + 0.002 * rng.random(len(pts))
    return geoimg.Mesh(np.column_stack([pts, z]), tri), geoimg.Parametrization(pts, (1.0, 1.0))


def kernel_args(surf, res):
    return surf._grid_arguments(*surf.grid(res)), dict(log_g_ref=surf.log_g_ref)


CHECKS = [(400, 129, 0.2), (2000, 257, 1.0), (2000, 200, 2.0), (6000, 257, 3.0)]
TINY_CHECKS = [(60, 17, 0.2), (100, 20, 1.0), (100, 18, 3.0)]     # for numba's CUDA simulator


def check(cu, cases) -> list[dict]:
    """Both kernels on small random TINs: largest difference over the surface's size, certificates."""
    rows = []
    for seed, (faces, res, s) in enumerate(cases):
        mesh, param = tin(faces, 100 + seed)
        surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s))
        args, kw = kernel_args(surf, res)
        a = kernels.sample_grid_gaussian(*args, derivatives=True, **kw)
        b = cu.sample_grid_gaussian_cuda(*args, derivatives=True, **kw)
        ok = a[3] & b[3]
        rows.append({"faces": int(mesh.n_faces), "res": res, "s": s,
                     "certified_cpu": int(a[3].sum()), "certificates_equal": bool((a[3] == b[3]).all()),
                     "max_dP": float(np.abs(a[0] - b[0])[ok].max()),
                     "max_dPu": float(np.abs(a[1] - b[1])[ok].max() / np.abs(a[1][ok]).max()),
                     "max_dPv": float(np.abs(a[2] - b[2])[ok].max() / np.abs(a[2][ok]).max())})
        img_a = surf.sample(res)
        img_b = surf.sample(res, backend="cuda")
        rows[-1]["image_equal"] = bool(np.array_equal(img_a.pixels, img_b.pixels)
                                       and np.array_equal(img_a.mask, img_b.mask))
        rows[-1]["image_max_d"] = float(np.abs(img_a.pixels - img_b.pixels).max())
        print(json.dumps(rows[-1]), flush=True)
    return rows


def timed(fn, *a, **kw):
    t = time.perf_counter()
    out = fn(*a, **kw)
    return time.perf_counter() - t, out


def bench(cu, n_faces: int, res: int, s_values) -> list[dict]:
    from numba import cuda
    t_mesh, (mesh, param) = timed(tin, n_faces, 0)
    print(f"mesh {mesh.n_faces} faces in {t_mesh:.1f} s", flush=True)
    rows = []
    default = cu.PINNED
    for s in s_values:
        t_fit, surf = timed(geoimg.fit_surface, mesh, param, s)
        args, kw = kernel_args(surf, res)
        for derivs in (False, True):
            warm = kernel_args(surf, 17)[0]
            kernels.sample_grid_gaussian(*warm, derivatives=derivs, **kw)
            cu.sample_grid_gaussian_cuda(*warm, derivatives=derivs, **kw)
            t_cpu, a = timed(kernels.sample_grid_gaussian, *args, derivatives=derivs, **kw)
            best = {}
            for pinned in (False, True):
                cu.PINNED = pinned
                gpu = []
                for _ in range(3):
                    prof: dict = {}
                    cuda.synchronize()
                    t, b = timed(cu.sample_grid_gaussian_cuda, *args, derivatives=derivs, profile=prof, **kw)
                    gpu.append((t, prof))
                best[pinned] = min(gpu, key=lambda x: x[0])
            cu.PINNED = default
            t_gpu, prof = best[False]
            prof["gpu_pinned_s"] = best[True][0]
            prof["download_pinned_s"] = best[True][1]["download_s"]
            ok = a[3] & b[3]
            row = {"faces": int(mesh.n_faces), "res": res, "s": s, "normals": derivs, "fit_s": t_fit,
                   "cpu_s": t_cpu, "gpu_s": t_gpu, "speedup": t_cpu / t_gpu, **prof,
                   "candidates_per_pixel": prof.get("tile_entries", 0) * 256 / (res * res),
                   "max_dP": float(np.abs(a[0] - b[0])[ok].max()),
                   "certificates_equal": bool((a[3] == b[3]).all())}
            del a, b
            rows.append(row)
            print(json.dumps(row), flush=True)
        for backend in ("cpu", "cuda", "cuda"):
            t, img = timed(surf.sample, res, backend=backend)
            rows.append({"faces": int(mesh.n_faces), "res": res, "s": s, "whole_sample": backend, "seconds": t})
            print(json.dumps(rows[-1]), flush=True)
            del img
    return rows


def transfer_probe(res: int) -> dict:
    """Seconds to download one (res, res, 3) float64 image into pageable memory, and into page-locked
    memory (its allocation timed apart).
    """
    from numba import cuda
    d = cuda.to_device(np.random.default_rng(0).random((res, res, 3)))
    out = {"mb": d.nbytes / 2**20}
    for name, alloc in (("pageable", lambda: np.empty((res, res, 3))),
                        ("pinned", lambda: cuda.pinned_array((res, res, 3)))):
        times = []
        for _ in range(3):
            t_alloc, host = timed(alloc)
            t_copy, _ = timed(d.copy_to_host, host)
            times.append((t_alloc + t_copy, t_alloc, t_copy))
            del host
        best = min(times)
        out[f"{name}_alloc_s"], out[f"{name}_copy_s"] = best[1], best[2]
    print(json.dumps(out), flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=1_000_000)
    ap.add_argument("--res", type=int, default=4096)
    ap.add_argument("--s", type=float, nargs="+", default=[1.0, 2.0])
    ap.add_argument("--check-only", action="store_true")
    ap.add_argument("--tiny", action="store_true", help="tiny checks, for NUMBA_ENABLE_CUDASIM=1 (no GPU)")
    ap.add_argument("--out", default=None, help="write the rows as JSON here")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    import numba
    from numba import cuda

    from geoimg.surface import _gaussian_cuda_kernels as cu
    why = cu.cuda_unavailable()
    if why is not None:
        raise SystemExit(f"bench_cuda: {why}; it needs a CUDA GPU (or NUMBA_ENABLE_CUDASIM=1 with --tiny)")
    gpu = "simulator" if numba.config.ENABLE_CUDASIM else cuda.get_current_device().name
    print(f"numba {numba.__version__}, {numba.config.NUMBA_NUM_THREADS} CPU threads, GPU {gpu}, "
          f"cpus {os.cpu_count()}", flush=True)
    rows = check(cu, TINY_CHECKS if args.tiny else CHECKS)
    if not args.check_only:
        rows.append(transfer_probe(args.res))
        rows += bench(cu, args.faces, args.res, args.s)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
