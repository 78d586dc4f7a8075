"""Batches (issue 15): files per minute for a shell loop of `geoimg image` against `geoimg batch` with 1 and 2
local workers, in one run, on a collection of 200+ meshes made from the shared data (decimations to 250, 500, 1,000,
2,000 and 4,000 triangles by libigl, the originals up to 15,000 faces, and jittered copies of all: closed,
open, higher-genus, several-piece and polygonal meshes; .obj, .ply and .off).

    python benchmarks/bench_batch.py [--loop-every 4] [--res 129]

The shell loop runs on every k-th input (the same mix, a quarter of the time); its rate is files per minute
as for the others. Also: the per-task overhead (wall time x workers / inputs minus the mean time inside the
task), the cluster's start-up, and the throughput per worker core.
"""
from __future__ import annotations

import argparse
import csv
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import igl
import numpy as np

import geoimg
from geoimg.batch import STAGES

SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes"
TARGETS = (250, 500, 1000, 2000, 4000)
MAX_ORIGINAL = 15000
FORMATS = (".obj", ".ply", ".off")


def collection(folder: Path) -> list[Path]:
    """Write the benchmark's meshes into ``folder`` (sub-folders by source kind) and return their paths."""
    rng = np.random.default_rng(0)
    made = []
    sources = sorted(p for p in SHARED.rglob("*") if p.suffix in FORMATS)
    for k, src in enumerate(sources):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = geoimg.load_mesh(src)
        tris, _ = mesh.triangulate()
        V = np.asarray(mesh.vertices, np.float64)
        variants = [(mesh, "orig")] if mesh.n_faces <= MAX_ORIGINAL else []
        for target in TARGETS:
            if target >= len(tris):
                continue
            try:
                U, G, _, _ = igl.decimate(V, tris.astype(np.int32), target)
            except Exception:                       # libigl refuses some non-manifold inputs
                continue
            if len(G):
                variants.append((geoimg.Mesh(U, G), f"d{target}"))
        for m, tag in list(variants):
            diag = m.bounding_box_diagonal()
            variants.append((geoimg.Mesh(m.vertices + rng.normal(scale=2e-3 * diag, size=m.vertices.shape),
                                         m.faces), tag + "_jitter"))
        for m, tag in variants:
            out = folder / src.parent.name / f"{src.stem}_{src.suffix[1:]}_{tag}{FORMATS[(k + len(made)) % 3]}"
            out.parent.mkdir(parents=True, exist_ok=True)
            geoimg.save_mesh(m, out, overwrite=True)
            made.append(out)
    return made


def timed_run(cmd) -> tuple[float, int]:
    t0 = time.perf_counter()
    code = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    return time.perf_counter() - t0, code


def manifest_times(path: Path) -> tuple[np.ndarray, dict, dict]:
    """Seconds inside each task, the statuses, and the mean seconds per stage."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    statuses = {}
    for r in rows:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1
    stages = {s: np.mean([float(r[f"t_{s}"] or 0) for r in rows]) for s in STAGES}
    return np.array([float(r["t_total"] or 0) for r in rows]), statuses, stages


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--loop-every", type=int, default=4)
    ap.add_argument("--res", type=int, default=129)
    args = ap.parse_args()
    geoimg_cmd = [sys.executable, "-m", "geoimg"]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        t0 = time.perf_counter()
        files = collection(tmp / "in")
        print(f"{len(files)} inputs written in {time.perf_counter() - t0:.1f} s "
              f"({sum(f.stat().st_size for f in files) / 1e6:.1f} MB)")

        loop = files[::args.loop_every]
        (tmp / "loop").mkdir()
        t0 = time.perf_counter()
        codes = [subprocess.run(geoimg_cmd + ["image", str(f), "-o", str(tmp / "loop" / f"{i}.exr"), "--res",
                                              str(args.res), "-q"], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL).returncode for i, f in enumerate(loop)]
        t_loop = time.perf_counter() - t0
        loop_rate = 60 * len(loop) / t_loop
        print(f"shell loop: {len(loop)} inputs in {t_loop:.1f} s ({sum(c != 0 for c in codes)} refused): "
              f"{loop_rate:.1f} files/min")

        rows = []
        for workers, extra in ((1, []), (2, []), (2, ["--no-psnr"])):
            out = tmp / f"batch{workers}{''.join(extra)}"
            wall, code = timed_run(geoimg_cmd + ["batch", str(tmp / "in"), "-o", str(out), "--res", str(args.res),
                                                 "--workers", str(workers), "-q"] + extra)
            inside, statuses, stages = manifest_times(out / "manifest.csv")
            print(f"batch, {workers} worker(s) {' '.join(extra)}: mean seconds per stage: "
                  + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()))
            rate = 60 * len(files) / wall
            overhead = wall * workers / len(files) - inside.mean()
            rows.append((workers, " ".join(extra) or "(PSNR measured)", wall, rate, rate / loop_rate,
                         inside.mean(), overhead, rate / workers, statuses))
            shutil.rmtree(out)
        start, _ = timed_run(geoimg_cmd + ["batch", str(files[0]), "-o", str(tmp / "one"), "--res", "17",
                                           "--workers", "2", "--no-psnr", "-q"])
        again, _ = timed_run(geoimg_cmd + ["batch", str(files[0]), "-o", str(tmp / "one"), "--res", "17",
                                           "--workers", "2", "--no-psnr", "-q"])

    print()
    print("| run | inputs | wall (s) | files/min | x shell loop | mean s inside a task | overhead per task (s) "
          "| files/min per worker | statuses |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    print(f"| shell loop of `geoimg image` | {len(loop)} | {t_loop:.1f} | {loop_rate:.1f} | 1.0 | | | | |")
    for workers, what, wall, rate, speedup, inside, overhead, per, statuses in rows:
        st = ", ".join(f"{v} {k}" for k, v in sorted(statuses.items()))
        print(f"| `geoimg batch --workers {workers}` {what} | {len(files)} | {wall:.1f} | {rate:.1f} | {speedup:.1f} "
              f"| {inside:.3f} | {overhead:.3f} | {per:.1f} | {st} |")
    print(f"\none tiny input through `geoimg batch` (import, cluster start and stop): {start:.1f} s; "
          f"again, skipped: {again:.1f} s")


if __name__ == "__main__":
    main()
