"""
Fig. 9: multiresolution
=======================

Paper Fig. 9: multiresolution. One shape at five s values, each sampled on the grid its smoothness
asks for (the paper's spacing: coarser for larger s), 13² to 193² for an octahedral image.

    python samples/fig9_multires.py [OUT_DIR] [--finest 193]

Spot (low resolution) through the sphere; the quad meshes with their grid lines. Writes
OUT_DIR/fig9_multires.png.
"""
from __future__ import annotations

from pathlib import Path

import geoimg
from geoimg.animation import Renderer

from _common import DATA, caption, sample_main, save, sheet

PAIRS = ((8.0, 13), (4.0, 25), (2.0, 49), (1.0, 97), (0.5, 193))


def run(out_dir: Path, finest: int = 193, size=(240, 220)) -> dict:
    mesh = geoimg.load_mesh(DATA / "spot_low_resolution.obj")
    param = geoimg.parametrize(mesh, "sphere")
    scale = (finest - 1) / (PAIRS[-1][1] - 1)
    row, stats = [], {}
    with Renderer(*size) as r:
        cam = r.camera_for(mesh, azimuth=-50, elevation=15)
        for s, n in PAIRS:
            n = max(5, int(round((n - 1) * scale)) + 1) | 1
            quads = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s)).sample(n).to_mesh()
            stats[s] = n
            row.append(caption(r.render(quads, cam, edges=quads if n <= 49 else None,
                                        edge_color=(0.2, 0.2, 0.6)), f"s = {s:g}, {n} x {n}"))
    stats["png"] = str(save(sheet([row]), Path(out_dir) / "fig9_multires.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, finest=193)


if __name__ == "__main__":
    main()
