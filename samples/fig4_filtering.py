"""
Fig. 4: filtering a closed shape's octahedral image
===================================================

Paper Fig. 4: a closed genus-0 shape as an octahedral geometry image, mean-filtered, inverse-filtered
and partially smoothed, with the quad meshes they give.

    python samples/fig4_filtering.py [OUT_DIR] [--res 129]

Spot (low resolution), s = 1. Top: the images (X, Y, Z as R, G, B); bottom: the welded quad meshes.
Writes OUT_DIR/fig4_filtering.png and prints how far each moved the surface.
"""
from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

import filters
import geoimg
from geoimg.image import image_region
from geoimg.animation import Renderer

from _common import DATA, caption, sample_main, save, sheet


def to_rgb(image) -> np.ndarray:
    p = image.pixels.astype(np.float64)
    lo, hi = p.min(axis=(0, 1)), p.max(axis=(0, 1))
    return np.round((p - lo) / np.maximum(hi - lo, 1e-300) * 255).astype(np.uint8)


def run(out_dir: Path, res: int = 129, size=(240, 240)) -> dict:
    mesh = geoimg.load_mesh(DATA / "spot_low_resolution.obj")
    image = geoimg.fit_surface(mesh, geoimg.parametrize(mesh, "sphere"), geoimg.GaussianWeights()).sample(res | 1)
    head = mesh.vertices[np.argmax(mesh.vertices[:, 2])]               # the snout's tip
    region = image_region(image, head, 0.35, 0.15)
    versions = [("geometry image", image),
                ("mean filter 5x5, twice", image.apply(filters.mean_filter, 5, iterations=2)),
                ("inverse filter", image.apply(filters.inverse_filter, "mean", 3, nsr=3e-3)),
                ("head smoothed only", image.apply(filters.gaussian_filter, 3.0, mask=region, feather=4))]
    with Renderer(*size) as r:
        cam = r.camera_for(mesh, azimuth=-50, elevation=15)
        side = size[1]
        top = [caption(cv2.resize(to_rgb(img), (side, side), interpolation=cv2.INTER_NEAREST), name)
               for name, img in versions]
        bottom = [r.render(img.to_mesh(), cam) for _, img in versions]
    stats = {name: float(np.abs(img.pixels - image.pixels).max()) for name, img in versions}
    stats["png"] = str(save(sheet([top, bottom]), Path(out_dir) / "fig4_filtering.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=129)


if __name__ == "__main__":
    main()
