"""The same conversions under 1, 2 and 16 threads of BLAS, OpenMP and numba, each in a fresh process: their
bytes (sha256 of pixels, normals and mask) and wall times.

    python benchmarks/bench_determinism.py [--res 65] [MESH ...]

Default meshes: a sphere map (the bundled fish, 10,786 vertices, and ../shared's armadillo when present), a
cut-open map (Bob) and a disk map (../shared's camelhead when present, else the bundled Demosthenes scan).
Prints one row per mesh: its domain, whether every thread count gave the same bytes, and each run's seconds.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
THREADS = (1, 2, 16)
VARIABLES = ("NUMBA_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
CODE = """
import hashlib, json, sys, time, warnings
import numpy as np
import geoimg
warnings.simplefilter("ignore")
t0 = time.perf_counter()
img = geoimg.mesh_to_image(geoimg.load_mesh(sys.argv[1]), int(sys.argv[2]))
digest = hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes() for a in (img.pixels, img.normals, img.valid)))
print(json.dumps([type(img.domain).__name__, digest.hexdigest()[:16], time.perf_counter() - t0]))
"""


def default_meshes() -> list[Path]:
    data = ROOT / "tests" / "data"
    out = [data / "fish.obj", data / "bob_tri.obj"]
    for rel in ("closed_genus0/armadillo.obj", "open_disk/camelhead.off"):
        if (SHARED / rel).exists():
            out.append(SHARED / rel)
    if not (SHARED / "open_disk/camelhead.off").exists():
        out.append(data / "demosthenes-low-res.obj")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--res", type=int, default=65)
    args = ap.parse_args()
    if args.res < 3:
        ap.error("--res: at least 3")
    print("| mesh | domain | same bytes at " + ", ".join(map(str, THREADS)) + " threads | seconds |")
    print("|---|---|---|---|")
    for mesh in args.meshes or default_meshes():
        runs = []
        for t in THREADS:
            env = {**os.environ, **{k: str(t) for k in VARIABLES}}
            t0 = time.perf_counter()
            done = subprocess.run([sys.executable, "-c", CODE, str(mesh), str(args.res)], env=env, capture_output=True,
                                  text=True, check=True)
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]) + [time.perf_counter() - t0])
        same = len({r[1] for r in runs}) == 1
        times = " / ".join(f"{r[2]:.1f}" for r in runs)
        print(f"| {mesh.name} | {runs[0][0]} | {'yes' if same else 'NO: ' + ', '.join(r[1] for r in runs)} | "
              f"{times} |", flush=True)


if __name__ == "__main__":
    main()
