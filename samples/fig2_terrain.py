"""
Fig. 2: a terrain at s = 2, 4, 8 with its curvature
===================================================

Paper Fig. 2: a terrain's weighted-mean surface at s = 2, 4, 8 with its Gaussian and mean curvature.

    python samples/fig2_terrain.py [OUT_DIR] [--res 257] [--step 2]

The Mount St. Helens crater DEM of 2007 (10 m cells, every ``step``-th one) as a grid mesh; for each s
the hillshade from the surface's exact normals, and K and H from its exact derivatives (blue negative,
red positive). Writes OUT_DIR/fig2_terrain.png.
"""
from __future__ import annotations

import time
from pathlib import Path

import geoimg
from geoimg.surface import surface_curvature
from geoimg.image import diverging_colors

from _common import caption, gray, hillshade, sample_main, save, sheet, st_helens

S_VALUES = (2.0, 4.0, 8.0)


def run(out_dir: Path, res: int = 257, step: int = 2) -> dict:
    mesh = st_helens(2007, step)
    param = geoimg.parametrize(mesh, "heightfield", axis="z")
    rows, stats = [], {}
    for s in S_VALUES:
        t = time.perf_counter()
        surface = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s))
        image = surface.sample(res)
        K, H = surface_curvature(surface, res)
        stats[s] = {"seconds": time.perf_counter() - t, "K_range": (float(K.min()), float(K.max()))}
        rows.append([caption(gray(hillshade(image.normals)), f"s = {s:g}"),
                     caption(diverging_colors(K, image.valid), "K"),
                     caption(diverging_colors(H, image.valid), "H")])
    stats["png"] = str(save(sheet(rows), Path(out_dir) / "fig2_terrain.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=257, step=2)


if __name__ == "__main__":
    main()
