"""
Fig. 10: partial smoothing, in the surface and in the image
===========================================================

Partial smoothing two ways (paper 4.5, Fig. 10): in the surface domain (a smoothness s(u, v) that
varies with the point) and in the image domain (a masked, feathered Gaussian filter of the geometry
image); a region smoothed, and everything but the region smoothed.

    python samples/partial_smoothing.py [OUT_DIR] [--res 257]

The bundled mountain at s = 2, the region a disk round its summit in the parameter domain. Writes
OUT_DIR/partial_smoothing.png
(hillshades, and the height change of each below it; surface domain from exact normals, image domain
from grid normals) and prints how far each moved the surface inside the region and away from it.

What it shows: the image-domain versions leave the untouched part bit for bit as it was, with grid
normals; the surface-domain versions are the s = 2 or s = 8 surface itself wherever s(u, v) is, with
exact normals and a smooth blend between. (An s per face, `regions.smoothness_field`, cannot keep a
region sharp inside a smoothed surrounding: the wide Gaussians of the faces around reach into it.)
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import filters
import geoimg
from geoimg.image import diverging_colors
from geoimg.image import ball_weights
from geoimg.surface import uv_smoothness

from _common import MOUNTAIN, caption, gray, hillshade, sample_main, save, sheet


def run(out_dir: Path, res: int = 257) -> dict:
    mesh = geoimg.load_mesh(MOUNTAIN)
    param = geoimg.parametrize(mesh, "heightfield", axis="y")
    diag = mesh.bounding_box_diagonal()
    centre = param.coords[np.argmax(mesh.vertices[:, 1])]           # the summit, in the parameter domain
    radius, feather = 0.18, 0.12                                      # parameter units (longer side 1)
    base = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=2.0)).sample(res)
    u, v = base.parameter_grid()
    uv = np.stack(np.meshgrid(u, v), axis=-1)
    region = ball_weights(uv, centre, radius, feather)                # the same disk for both domains
    sigma = 6.0 * 128 / (res - 1) + 0.5
    orientation = base.domain.orientation

    def surface(inside, outside):
        img = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=uv_smoothness(centre, radius, inside, outside,
                                                                                     feather))).sample(res)
        return img, img.normals

    def image(mask):
        img = base.apply(filters.gaussian_filter, sigma, mask=mask, feather=0)
        return img, geoimg.grid_normals(img.pixels, orientation)

    versions = [("fitted, s = 2", base, base.normals),
                ("surface domain, s = 8", *surface(8.0, 2.0)),
                ("image domain, masked", *image(region)),
                ("surface domain, all but the region", *surface(2.0, 8.0)),
                ("image domain, all but the region", *image(1.0 - region))]
    far = region == 0
    inside = region == 1
    spacing = diag / np.sqrt(2) / (res - 1)     # about one pixel, in the mesh's units
    stats, top, bottom = {}, [], []
    for name, img, normals in versions:
        delta = img.pixels[..., 1].astype(np.float64) - base.pixels[..., 1]
        stats[name] = {"inside_rms": float(np.sqrt(np.mean(delta[inside] ** 2)) / diag),
                       "far_max": float(np.abs(delta[far]).max() / diag)}
        top.append(caption(gray(hillshade(normals, up="y")), name.replace("surface domain", "surface")
                           .replace("image domain", "image")))
        bottom.append(diverging_colors(delta, scale=20 * spacing))
    stats["png"] = str(save(sheet([top, bottom]), Path(out_dir) / "partial_smoothing.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=257)


if __name__ == "__main__":
    main()
