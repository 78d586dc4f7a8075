"""Partial smoothing two ways (paper 4.5, Fig. 10): in the surface domain (a larger s on the faces near a
point) and in the image domain (a masked, feathered Gaussian filter of the geometry image).

    python samples/partial_smoothing.py [OUT_DIR] [--res 257]

Writes OUT_DIR/partial_smoothing.png: hillshades of the terrain as fitted (s = 2), smoothed around its
summit in the surface domain (s = 8 there, exact normals), and smoothed there in the image domain (grid
normals), with the change in height of each below. Prints how far each moved the surface, inside the
region and away from it.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

import filters
import geoimg
from geoimg.regions import image_region, smoothness_field

HERE = Path(__file__).resolve().parent
LIGHT = np.array([-0.45, 0.77, -0.45]) / np.linalg.norm([-0.45, 0.77, -0.45])   # sun 50 degrees up; y up


def hillshade(normals: np.ndarray) -> np.ndarray:
    return 0.5 + 0.5 * np.clip(normals @ LIGHT, -1.0, 1.0)      # half-Lambert: slopes facing away stay visible


def labelled(gray: np.ndarray, text: str) -> np.ndarray:
    img = cv2.cvtColor(np.round(gray * 255).astype(np.uint8), cv2.COLOR_GRAY2BGR)
    cv2.putText(img, text, (6, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 200), 1, cv2.LINE_AA)
    return img


def change_map(delta: np.ndarray, scale: float) -> np.ndarray:
    from geoimg.image_io import diverging_colors

    rgb = diverging_colors(np.clip(delta / scale, -1, 1) * 100)   # full colour at +-scale
    return rgb[..., ::-1].copy()


def run(out_dir: Path, res: int = 257) -> dict:
    out_dir.mkdir(parents=True, exist_ok=True)
    mesh = geoimg.load_mesh(HERE / "data" / "mountain.obj")
    param = geoimg.parametrize(mesh, "heightfield", axis="y")
    summit = mesh.vertices[np.argmax(mesh.vertices[:, 1])]
    diag = mesh.bounding_box_diagonal()
    radius, feather = 0.12 * diag, 0.08 * diag

    base = geoimg.fit_surface(mesh, param, s=2.0).sample(res)
    s_face = smoothness_field(mesh, summit, radius, inside=8.0, outside=2.0, feather=feather)
    surface_domain = geoimg.fit_surface(mesh, param, s=s_face).sample(res)
    region = image_region(base, summit, radius, feather)
    spacing = diag / np.sqrt(2) / (res - 1)     # about one pixel, in the mesh's units
    image_domain = base.apply(filters.gaussian_filter, 6.0 * 128 / (res - 1) + 0.5, mask=region, feather=0)

    far = image_region(base, summit, radius + 2 * feather) == 0
    inside = region == 1
    stats = {}
    panels, changes = [], []
    for name, img, normals in (("fitted, s = 2", base, base.normals),
                               ("surface domain, s = 8", surface_domain, surface_domain.normals),
                               ("image domain, masked", image_domain,
                                geoimg.grid_normals(image_domain.pixels, int(base.metadata["orientation"])))):
        delta = img.pixels[..., 1].astype(np.float64) - base.pixels[..., 1]
        stats[name] = {"inside_rms": float(np.sqrt(np.mean(delta[inside] ** 2)) / diag),
                       "far_max": float(np.abs(delta[far]).max() / diag)}
        panels.append(labelled(hillshade(np.asarray(normals, np.float64)), name))
        changes.append(change_map(delta, 20 * spacing))
    sheet = np.vstack([np.hstack(panels), np.hstack(changes)])
    path = out_dir / "partial_smoothing.png"
    cv2.imwrite(str(path), sheet)
    stats["png"] = str(path)
    return stats


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir", nargs="?", default="samples-out")
    ap.add_argument("--res", type=int, default=257)
    args = ap.parse_args(argv)
    stats = run(Path(args.out_dir), args.res)
    for name, st in stats.items():
        if name != "png":
            print(f"{name:40s} height change inside the region: RMS {st['inside_rms']:.2e} of the diagonal; "
                  f"away from it: max {st['far_max']:.2e}")
    print(f"wrote {stats['png']}")


if __name__ == "__main__":
    main()
