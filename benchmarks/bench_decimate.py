"""The decimated copy of a large mesh (issue 53): geoimg's edge collapses (numba, no GIL) against libigl's
``decimate`` on the same meshes, to the coarse copy's 8,000 triangles: time (best of ``--rounds``) and whether the
two coarse meshes are the same bit for bit; then, with ``--overlap``, the copy made while the fine mesh's Sobolev
factor is made in a thread (what ``sphere_coords`` does) against the two one after the other.

    python benchmarks/bench_decimate.py MESH ...
"""
from __future__ import annotations

import argparse
import time
import warnings

import igl
import numpy as np

import geoimg
from geoimg.parametrization._balance import sobolev_factor, sobolev_factor_later
from geoimg.parametrization._decimate import decimate
from geoimg.parametrization._multilevel import COARSE_TRIANGLES


def best(rounds: int, work) -> float:
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        work()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="+")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--overlap", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    print("| mesh (faces) | libigl | geoimg | same bits |" + (" factor, then copy | beside |" if args.overlap else ""))
    print("|---|---:|---:|---|" + ("---:|---:|" if args.overlap else ""))
    for path in args.meshes:
        mesh = geoimg.load_mesh(path)
        x, tris = mesh.vertices, np.asarray(mesh.triangulate()[0], np.int64)
        decimate(x, tris, COARSE_TRIANGLES)                       # compiled or loaded before timing
        theirs = best(args.rounds, lambda: igl.decimate(x, tris.astype(np.int32), COARSE_TRIANGLES))
        ours = best(args.rounds, lambda: decimate(x, tris, COARSE_TRIANGLES))
        U, G, _, _ = igl.decimate(x, tris.astype(np.int32), COARSE_TRIANGLES)
        u, g = decimate(x, tris, COARSE_TRIANGLES)
        same = np.asarray(U).shape == u.shape and np.array_equal(U, u) and np.array_equal(G, g)
        row = f"| {path.rsplit('/', 1)[-1]} ({len(tris)}) | {theirs:.3f} s | {ours:.3f} s | {'yes' if same else 'NO'} |"
        if args.overlap:
            used = np.ones(len(x), bool)
            serial = best(args.rounds, lambda: (sobolev_factor(x, tris, used), decimate(x, tris, COARSE_TRIANGLES)))
            beside = best(args.rounds, lambda: (decimate(x, tris, COARSE_TRIANGLES),
                                                sobolev_factor(x, tris, used, cache=cache))
                          if (cache := sobolev_factor_later(x, tris, used)) else None)
            row += f" {serial:.3f} s | {beside:.3f} s |"
        print(row, flush=True)


if __name__ == "__main__":
    main()
