"""A shape space of closed genus-0 meshes from their harmonics: ``geoimg batch --harmonics`` writes the
coefficient table, :func:`geoimg.spectrum.shape_space` takes its principal components, and the mean shape and
the first modes (at -2, 0 and +2 standard deviations) are rendered side by side.

    python benchmarks/shape_space.py OUT.png [--lmax 16] [--res 257] [--family N | MESH ...]

``--family N`` (the default, N = 12): Spot in N variants of known variation, two independent parameters drawn
at random: its body stretched along its length by exp(a) and tapered (its width scaled by 1 + b z / length);
the shape space should find two modes holding nearly all the variance. With meshes instead: a collection of
unlike shapes, each scaled to a longest semi-axis of 1 (a space of shapes, not of sizes). Prints each mode's
share of the variance.
"""
from __future__ import annotations

import argparse
import shutil
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

import geoimg
from geoimg.spectrum import harmonics_from_row, shape_space

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"


def default_meshes() -> list[Path]:
    tests = ROOT / "tests" / "data"
    out = [tests / n for n in ("spot.obj", "fish.obj", "scorpion_low_resolution.obj", "penguin_control_mesh.obj",
                               "fish_control_mesh.obj", "demosthenes-low-res.obj")]
    out += [SHARED / "closed_genus0" / n for n in ("bunny.obj", "armadillo.obj", "human_man.obj", "human_woman.obj",
                                                   "bumpy.off")]
    out += [SHARED / "polygonal" / n for n in ("horse_quad.obj", "cylinder.obj", "spot_control_mesh.obj")]
    return [p for p in out if p.exists()]


def variant(mesh: geoimg.Mesh, stretch: float, taper: float) -> geoimg.Mesh:
    """``mesh`` stretched by exp(stretch) along z (Spot's length) and tapered: x, y scaled by 1 + taper z / L."""
    v = np.array(mesh.vertices, np.float64)
    length = float(np.ptp(v[:, 2]))
    v[:, :2] *= 1.0 + taper * (v[:, 2:3] - v[:, 2].mean()) / length
    v[:, 2] *= np.exp(stretch)
    return geoimg.Mesh(v, mesh.faces)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("figure", type=Path)
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--lmax", type=int, default=16)
    ap.add_argument("--res", type=int, default=257)
    ap.add_argument("--family", type=int, default=12)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    work = Path(tempfile.mkdtemp())
    (work / "in").mkdir()
    if args.meshes:
        for k, path in enumerate(args.meshes):
            shutil.copy(path, work / "in" / f"{k:02d}_{path.name}")
    else:
        spot = geoimg.load_mesh(ROOT / "tests" / "data" / "spot.obj")
        rng = np.random.default_rng(1)
        params = {}
        for k, (a, b) in enumerate(zip(rng.normal(0, 0.15, args.family), rng.normal(0, 0.4, args.family))):
            geoimg.save_mesh(variant(spot, a, b), work / "in" / f"spot_{k:02d}.obj")
            params[f"spot_{k:02d}.obj"] = (a, b)
    table = geoimg.batch.convert([work / "in"], work / "out", resolution=args.res, harmonics=args.lmax, psnr=False)
    print(table[["input", "status", "message"]].to_string())
    rows = pd.read_parquet(work / "out" / "harmonics.parquet")
    shapes = [harmonics_from_row(r) for r in rows.to_dict("records")]
    if args.meshes:
        shapes = [h.normalized(scale=True) for h in shapes]
    space = shape_space(shapes, 3)
    print(f"{len(shapes)} shapes, degree {args.lmax}; variance explained by modes 1-3: "
          + ", ".join(f"{100 * e:.1f} %" for e in space.explained))
    if not args.meshes:                          # how the modes' scores follow the known parameters
        x = np.stack([h.coeffs.ravel() for h in shapes]) - space.mean.coeffs.ravel()
        scores = x @ space.modes.reshape(len(space.modes), -1).T
        known = np.array([params[Path(p).name] for p in rows["input"]])
        for m in range(2):
            r = [abs(np.corrcoef(scores[:, m], known[:, j])[0, 1]) for j in range(2)]
            print(f"mode {m + 1}: |correlation| with the stretch {r[0]:.2f}, with the taper {r[1]:.2f}")
        both = np.linalg.lstsq(np.c_[scores[:, :2], np.ones(len(scores))], known, rcond=None)[0]
        fit = np.c_[scores[:, :2], np.ones(len(scores))] @ both
        r2 = 1 - ((known - fit) ** 2).sum(axis=0) / ((known - known.mean(axis=0)) ** 2).sum(axis=0)
        print(f"the stretch and the taper from modes 1-2 (linear): R^2 {r2[0]:.3f}, {r2[1]:.3f}")
    from PIL import Image, ImageDraw

    from geoimg.animation import Renderer
    size = 280
    grid = [[("mean", space.mean)]]
    for m in range(2):
        grid.append([(f"mode {m + 1}, {w:+d} sd", space.shape([0.0] * m + [float(w)])) for w in (-2, 0, 2)])
    with Renderer(size, size, background=(1.0, 1.0, 1.0)) as r:
        images = [[(title, h.to_image(129)) for title, h in row] for row in grid]
        cam = r.camera_for(*[img for row in images for _, img in row], azimuth=30, elevation=20)
        sheet = Image.new("RGB", (size * 3, size * len(images)), "white")
        for i, row in enumerate(images):
            for j, (title, img) in enumerate(row):
                tile = Image.fromarray(r.render(img, cam))
                ImageDraw.Draw(tile).text((8, 8), title, fill=(0, 0, 0))
                sheet.paste(tile, (size * (j + (1 if i == 0 else 0)), size * i))
    sheet.save(args.figure)
    print(f"wrote {args.figure}")
    np.save(work / "explained.npy", space.explained)


if __name__ == "__main__":
    main()
