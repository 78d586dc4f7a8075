"""Maps of one tree, for comparing two commits (issue 53): each mesh's ``parametrize`` (best of ``--rounds``), its
ratio to one linear map, whether Gauss-Newton steps made it, its steps and folds, the image's PSNR at 257²
(linear resampling, 50,000 samples a side) and a hash of the map. Run once per tree, the same hour:

    python benchmarks/bench_maps.py PATH@METHOD ...                          # this checkout
    cd /tmp/base && PYTHONPATH=/tmp/base python /abs/benchmarks/bench_maps.py /abs/PATH@METHOD ...

``METHOD`` is ``sphere``, ``disk`` or ``cut``.
"""
from __future__ import annotations

import argparse
import hashlib
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_profile import image_psnr, linear_map  # noqa: E402

import geoimg  # noqa: E402
from geoimg.mesh._metrics import ReferenceDistances  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("meshes", nargs="+", help="PATH@METHOD")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    for arg in args.meshes:
        path, method = arg.rsplit("@", 1)
        mesh = geoimg.load_mesh(path)
        base = min(linear_map(mesh, method == "disk") for _ in range(2))
        best = None
        for _ in range(args.rounds):
            t0 = time.perf_counter()
            p = geoimg.parametrize(mesh, method)
            wall = time.perf_counter() - t0
            if best is None or wall < best[0]:
                best = (wall, p)
        wall, p = best
        psnr = image_psnr(mesh, p, 257, ReferenceDistances(mesh, 50_000))
        print(f"{Path(path).name:28s} {method:6s} {wall:6.2f} s {wall / base:5.0f}x  gn={p.info.get('gauss_newton')} "
              f"steps={p.info.get('balance_steps')} flips={p.flipped_faces} {psnr:.2f} dB  "
              f"{hashlib.sha256(p.coords.tobytes()).hexdigest()[:8]}", flush=True)


if __name__ == "__main__":
    main()
