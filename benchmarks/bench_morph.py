"""Morphs against ground truth, alignment, file sizes and rendering speed.

Run by hand:  python benchmarks/bench_morph.py     (prints markdown tables for benchmarks/README.md)
- human_man -> human_woman share faces and vertex order: the per-vertex interpolation is the truth.
- Mount St. Helens crater 2004-10-04 -> 2007-07-05 (same 10 m grid): the per-vertex interpolation of the
  two grid meshes is the truth; the paper's blend ratios 3:1, 1:1, 1:3.
"""
from __future__ import annotations

import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.animation import save_glb
from geoimg.mesh import surface_distance
from geoimg.animation import morph
from geoimg.animation import Renderer, save_animation
from geoimg.mesh import grid_mesh, load_dem

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"


def against_truth(name, a, b, resolution, ts=(0.0, 0.25, 0.5, 0.75, 1.0)):
    t0 = time.perf_counter()
    m = morph(a, b, frames=len(ts), easing="linear", align="none", resolution=resolution)
    t_morph = time.perf_counter() - t0
    for t in ts:
        truth = geoimg.Mesh((1 - t) * a.vertices + t * b.vertices, a.faces)
        t1 = time.perf_counter()
        frame = m.frame(float(t)).to_mesh()
        t_frame = time.perf_counter() - t1
        d = surface_distance(truth, frame, n=50000)
        print(f"| {name} | {m.keys[0].shape[0]}x{m.keys[0].shape[1]} | {t:.2f} | {d['rms'] / d['diagonal']:.2e} | "
              f"{d['hausdorff'] / d['diagonal']:.2e} | {d['psnr_db']:.1f} | {t_morph:.2f} | {t_frame * 1e3:.0f} |")
    return m


def main():
    warnings.simplefilter("ignore")
    print("| pair | image | t | RMS / diag | Hausdorff / diag | PSNR dB | morph s | frame + quads ms |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    man = geoimg.load_mesh(DATA / "meshes/closed_genus0/human_man.obj")
    woman = geoimg.load_mesh(DATA / "meshes/closed_genus0/human_woman.obj")
    for n in (129, 257):
        m_h = against_truth("human_man -> human_woman", man, woman, n)
    d04 = load_dem(DATA / "dem/msh_nad83_2_2004-10-04.tif")
    d07 = load_dem(DATA / "dem/msh_nad83_27_2007-07-05.tif")
    a, b = grid_mesh(d04, (10.0, 10.0)), grid_mesh(d07, (10.0, 10.0))
    changed = np.abs(d07 - d04) > 1.0
    for n in (257, 513):
        m_t = against_truth("St. Helens 2004 -> 2007", a, b, n, ts=(0.0, 0.25, 0.5, 0.75, 1.0))
    print(f"\nSt. Helens: {changed.mean() * 100:.1f} % of the cells changed by more than 1 m; the largest change "
          f"{np.abs(d07 - d04).max():.0f} m.")

    print("\n| pair | resolution | sphere turn found (deg) | RMS to shape 0 before / after (of its radius) | time s |")
    print("|---|---:|---:|---|---:|")
    for x, y in (("spot_low_resolution.obj", "spot.obj"), ("bunny.obj", "bunny.off"), ("spot.obj", "bunny.obj")):
        ma, mb = (geoimg.load_mesh(DATA / "meshes/closed_genus0" / f) for f in (x, y))
        t = time.perf_counter()
        mm = morph(ma, mb, frames=2, resolution=129)
        r = mm.report[1]
        print(f"| {x} -> {y} | 129 | {r['rotation_deg']:.1f} | {r['rms_before']:.3f} / {r['rms_after']:.3f} | "
              f"{time.perf_counter() - t:.2f} |")

    out = Path(tempfile.mkdtemp())
    print("\n| output | frames | size | time s |")
    print("|---|---:|---:|---:|")
    for name, mm in (("human 257^2, 2 keys", m_h), ("St. Helens 513^2 (masked grid), 2 keys", m_t)):
        mm = morph(*mm.keys, frames=30, align="none")
        t = time.perf_counter()
        p = save_glb(mm, out / "m.glb", overwrite=True)
        print(f"| GLB, {name} | 30 | {p.stat().st_size / 1e6:.1f} MB | {time.perf_counter() - t:.2f} |")
    r = Renderer(800, 600)
    cam = r.camera_for(*m_h.keys, azimuth=20, elevation=10)
    mm = morph(*m_h.keys, frames=30, align="none")
    r.render(mm.frame(0.0), cam)
    t = time.perf_counter()
    pics = [r.render(f, cam) for f in mm.frames()]
    t_render = time.perf_counter() - t
    t = time.perf_counter()
    p = save_animation(pics, out / "m.gif")
    print(f"| 800x600 pictures of the human morph (257^2, 131k triangles) | 30 | - | {t_render:.2f} "
          f"({t_render / 30 * 1e3:.0f} ms a frame, quads included) |")
    print(f"| GIF of them | 30 | {p.stat().st_size / 1e6:.1f} MB | {time.perf_counter() - t:.2f} |")
    r.release()


if __name__ == "__main__":
    main()
