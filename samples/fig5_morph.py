"""
Fig. 5: a terrain morph, Mount St. Helens 2004 to 2007
======================================================

Paper Fig. 5: a terrain morph by blending geometry images, Mount St. Helens 2004 -> 2007 (the lava dome
grew by up to 208 m), at blend ratios 3:1, 1:1, 1:3, with the per-vertex blend as ground truth.

    python samples/fig5_morph.py [OUT_DIR] [--res 257] [--step 1]

Writes OUT_DIR/fig5_morph.png (hillshades and the height change from 2004) and prints each frame's
distance to the per-vertex blend of the two DEM meshes.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import geoimg
from geoimg.image import diverging_colors
from geoimg.mesh import surface_distance
from geoimg.animation import morph

from _common import caption, gray, hillshade, sample_main, save, sheet, st_helens

FRAMES = ((0.0, "2004-10-04"), (0.25, "3:1"), (0.5, "1:1"), (0.75, "1:3"), (1.0, "2007-07-05"))


def run(out_dir: Path, res: int = 257, step: int = 1) -> dict:
    a, b = st_helens(2004, step), st_helens(2007, step)
    m = morph(a, b, frames=5, easing="linear", align="none", resolution=res)
    top, bottom, stats = [], [], {}
    base = m.frame(0.0)
    for t, name in FRAMES:
        frame = m.frame(t)
        truth = geoimg.Mesh((1 - t) * a.vertices + t * b.vertices, a.faces)
        stats[name] = surface_distance(truth, frame.to_mesh(), n=20000)["psnr_db"]
        normals = geoimg.grid_normals(frame.pixels)
        top.append(caption(gray(hillshade(normals)), name))
        dz = frame.pixels[..., 2].astype(np.float64) - base.pixels[..., 2]
        bottom.append(caption(diverging_colors(dz, frame.valid, scale=100.0), f"change: {dz.max():+.0f} m max"))
    stats["png"] = str(save(sheet([top, bottom]), Path(out_dir) / "fig5_morph.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=257, step=1)


if __name__ == "__main__":
    main()
