"""Hostile inputs (issue 13): how fast the cases that used to hang or exhaust memory are now handled.

    python benchmarks/bench_hostile.py

Times: triangulating one large polygon, refusing a tiny PLY that declares a trillion items, refusing
absurd image, filter and morph requests through the CLI (each must end in one line, before any work).
"""
from __future__ import annotations

import io
import tempfile
import time
from contextlib import redirect_stderr
from pathlib import Path

import numpy as np

import geoimg
from geoimg.cli import main

MOUNTAIN = Path(geoimg.__file__).resolve().parent / "data" / "mountain.obj"


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main_quietly(argv):
    err = io.StringIO()
    with redirect_stderr(err):
        code = main(argv)
    return code, err.getvalue().strip()


def run():
    print("| case | time (s) | result |")
    print("|---|---:|---|")
    for k in (4_000, 100_000, 1_000_000):
        t = np.linspace(0, 2 * np.pi, k, endpoint=False)
        mesh = geoimg.Mesh(np.stack([np.cos(t), np.sin(t), 0 * t], 1), [list(range(k))])
        dt, (tris, _) = timed(mesh.triangulate)
        print(f"| triangulate one {k:,}-gon | {dt:.3f} | {len(tris):,} triangles |")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        ply = tmp / "junk.ply"
        ply.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                        b"property float z\nelement junk 1000000000000\nelement face 1\n"
                        b"property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
        dt, (code, err) = timed(lambda: main_quietly(["info", str(ply)]))
        print(f"| {ply.stat().st_size}-byte PLY declaring 10^12 items | {dt:.3f} | exit {code}: {err[:90]} |")
        exr = tmp / "m.exr"
        main_quietly(["image", str(MOUNTAIN), "-o", str(exr), "--res", "17", "-q"])
        for argv in (["image", str(MOUNTAIN), "-o", str(tmp / "x.exr"), "--res", "100000"],
                     ["filter", str(exr), "-o", str(tmp / "f.exr"), "--mean", "1000001"],
                     ["filter", str(exr), "-o", str(tmp / "f.exr"), "--gaussian", "1e6"],
                     ["morph", str(exr), str(exr), "--frames", "100000000", "--gif", str(tmp / "m.gif")]):
            dt, (code, err) = timed(lambda: main_quietly(argv))
            print(f"| geoimg {' '.join(a if '/' not in a else Path(a).name for a in argv)} | {dt:.3f} | "
                  f"exit {code}: {err[:110]} |")


if __name__ == "__main__":
    run()
