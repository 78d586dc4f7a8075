"""Morphs against ground truth, alignment, file sizes and rendering speed.

Run by hand:  python benchmarks/bench_morph.py     (prints markdown tables for benchmarks/README.md)
              python benchmarks/bench_morph.py --spectral [--figure strip.png]   (spectral against image blend)
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


def spectral(figure: Path | None = None, degrees=(16, 32, 64)) -> None:
    """The spectral morph (the keys' normalized harmonics blended) against the image blend, on pairs whose
    in-betweens are known: human_man -> human_woman (same faces: the per-vertex interpolation is the truth).
    The image morphs: the shared map (the vertices' own correspondence, the best any morph can do) and two
    maps made apart (the woman's faces stored in another order, so nothing is shared; the sphere turn found
    by search). The spectral morphs: the same two maps made apart, each shape's harmonics normalized.
    """
    man = geoimg.load_mesh(DATA / "meshes/closed_genus0/human_man.obj")
    woman = geoimg.load_mesh(DATA / "meshes/closed_genus0/human_woman.obj")
    order = np.random.default_rng(0).permutation(woman.n_faces)
    apart = geoimg.Mesh(woman.vertices, woman.faces[order])
    print("| morph of human_man -> human_woman | t = 0.25 | 0.5 | 0.75 | keys' PSNR | time s |")
    print("|---|---:|---:|---:|---:|---:|")
    runs = [("image blend, shared map (vertex correspondence)", woman, {}),
            ("image blend, maps made apart (turn by search)", apart, {})]
    runs += [(f"spectral, L = {L}, maps made apart", apart, {"spectral": L}) for L in degrees]
    made = {}
    for name, other, kw in runs:
        t0 = time.perf_counter()
        m = morph(man, other, frames=5, easing="linear", align="none", resolution=257, **kw)
        seconds = time.perf_counter() - t0
        made[name] = m
        cells = []
        for t in (0.25, 0.5, 0.75):
            truth = geoimg.Mesh((1 - t) * man.vertices + t * woman.vertices, man.faces)
            cells.append(f"{surface_distance(truth, m.frame(t).to_mesh(), n=50000)['psnr_db']:.1f}")
        keys = " / ".join(f"{surface_distance(s, m.frame(t).to_mesh(), n=50000)['psnr_db']:.1f}"
                          for s, t in ((man, 0.0), (woman, 1.0)))
        print(f"| {name} | " + " | ".join(cells) + f" | {keys} | {seconds:.1f} |", flush=True)
    if figure:
        from PIL import Image, ImageDraw
        shown = [runs[1][0], runs[2][0]]
        with Renderer(300, 420, background=(1.0, 1.0, 1.0)) as r:
            cam = r.camera_for(man, woman, azimuth=25, elevation=5)
            rows = []
            for name in shown:
                tiles = [Image.fromarray(r.render(made[name].frame(t), cam)) for t in (0.0, 0.25, 0.5, 0.75, 1.0)]
                ImageDraw.Draw(tiles[0]).text((8, 8), name, fill=(0, 0, 0))
                rows.append(tiles)
        sheet = Image.new("RGB", (300 * 5, 420 * len(rows)), "white")
        for i, tiles in enumerate(rows):
            for j, tile in enumerate(tiles):
                sheet.paste(tile, (300 * j, 420 * i))
        sheet.save(figure)


def main():
    import sys
    if "--spectral" in sys.argv:
        warnings.simplefilter("ignore")
        fig = sys.argv[sys.argv.index("--figure") + 1] if "--figure" in sys.argv else None
        spectral(Path(fig) if fig else None)
        return
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
