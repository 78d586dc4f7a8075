"""The decimated copy of a large mesh (issue 53): geoimg's edge collapses (numba, no GIL) against libigl's
``decimate`` on the same meshes, to the coarse copy's 8,000 triangles: time (best of ``--rounds``) and whether the
two coarse meshes are the same bit for bit; then, with ``--overlap``, the copy made while the fine mesh's Sobolev
factor is made in a thread (what ``sphere_coords`` does) against the two one after the other. The ways
alternate round by round (``bench_profile.best_alternating``).

    python benchmarks/bench_decimate.py MESH ...
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import igl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_profile import best_alternating  # noqa: E402

import geoimg  # noqa: E402
from geoimg.parametrization._balance import sobolev_factor, sobolev_factor_later  # noqa: E402
from geoimg.parametrization._decimate import decimate  # noqa: E402
from geoimg.parametrization._multilevel import COARSE_TRIANGLES  # noqa: E402


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
        used = np.ones(len(x), bool)

        def beside():
            cache = sobolev_factor_later(x, tris, used)       # the factor in its thread while the copy is made
            copy = decimate(x, tris, COARSE_TRIANGLES)
            return copy, sobolev_factor(x, tris, used, cache=cache)

        decimate(x, tris, COARSE_TRIANGLES)                       # compiled or loaded before timing
        ways = {"libigl": lambda: igl.decimate(x, tris.astype(np.int32), COARSE_TRIANGLES)[:2],
                "geoimg": lambda: decimate(x, tris, COARSE_TRIANGLES)}
        if args.overlap:
            ways.update(serial=lambda: (sobolev_factor(x, tris, used), decimate(x, tris, COARSE_TRIANGLES)),
                        beside=beside)
        best = best_alternating(args.rounds, ways)
        (U, G), (u, g) = best["libigl"][1], best["geoimg"][1]
        same = np.asarray(U).shape == u.shape and np.array_equal(U, u) and np.array_equal(G, g)
        row = (f"| {path.rsplit('/', 1)[-1]} ({len(tris)}) | {best['libigl'][0]:.3f} s | {best['geoimg'][0]:.3f} s | "
               f"{'yes' if same else 'NO'} |")
        if args.overlap:
            row += f" {best['serial'][0]:.3f} s | {best['beside'][0]:.3f} s |"
        print(row, flush=True)


if __name__ == "__main__":
    main()
