"""
Fig. 11: rational Gaussian against locally supported weights
============================================================

Paper Fig. 11: rational Gaussian weights (s = 1, 2, 3) against locally supported weights (n = 5, 10, 15),
with the time each took.

    python samples/fig11_weights.py [OUT_DIR] [--res 257]

The bundled mountain terrain (50,562 triangles); hillshades from exact normals. Writes
OUT_DIR/fig11_weights.png and prints the times (fit + sample, after a warm-up).
"""
from __future__ import annotations

import time
from pathlib import Path

import geoimg

from _common import MOUNTAIN, caption, gray, hillshade, sample_main, save, sheet


def run(out_dir: Path, res: int = 257) -> dict:
    mesh = geoimg.load_mesh(MOUNTAIN)
    param = geoimg.parametrize(mesh, "heightfield", axis="y")
    geoimg.fit_surface(mesh, param, geoimg.GaussianWeights()).sample(9)      # compile / load the kernels first
    rows, stats = [], {}
    for kind, values in (("gaussian", (1.0, 2.0, 3.0)), ("local", (5, 10, 15))):
        row = []
        for value in values:
            t = time.perf_counter()
            if kind == "gaussian":
                image = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=value)).sample(res)
                label = f"rational Gaussian, s = {value:g}"
            else:
                image = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(n=value)).sample(res)
                label = f"local weights, n = {value}"
            seconds = time.perf_counter() - t
            stats[label] = seconds
            row.append(caption(gray(hillshade(image.normals, up="y")), f"{label}: {seconds:.2f} s"))
        rows.append(row)
    stats["png"] = str(save(sheet(rows), Path(out_dir) / "fig11_weights.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=257)


if __name__ == "__main__":
    main()
