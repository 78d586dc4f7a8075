"""
A textured mesh through geometry images
=======================================

A textured mesh through geometry images: Spot with its texture (both in tests/data) to an octahedral
image whose colour channels hold the texture, smoothed, to a textured quad mesh and a GLB read back.

    python samples/textured.py [OUT_DIR] [--res 257]

Left to right: the input OBJ + MTL + PNG (5,856 triangles, UV seams); the image's colours (the texture
unfolded onto the octahedral square); the quad mesh of the image after a Gaussian filter of the geometry
(sigma 1.5 pixels: the shape smooths, the colours stay where they belong); that quad mesh written to GLB
(texture coordinates, the colours as its texture) and read back. Writes OUT_DIR/textured.png.
"""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

import filters
import geoimg
from geoimg.animation import Renderer

from _common import TEST_DATA, caption, fit_width, sample_main, save, sheet


def textured_spot(folder: Path) -> Path:
    """Spot as OBJ + MTL + PNG in ``folder`` (the bundled mesh and texture, a one-line material)."""
    shutil.copy(TEST_DATA / "spot_texture.png", folder / "spot_texture.png")
    (folder / "spot.mtl").write_text("newmtl spot\nKd 1 1 1\nmap_Kd spot_texture.png\n")
    obj = folder / "spot.obj"
    obj.write_text("mtllib spot.mtl\nusemtl spot\n" + (TEST_DATA / "spot.obj").read_text())
    return obj


def run(out_dir: Path, res: int = 257, size=(300, 300)) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        obj = textured_spot(Path(tmp))
        mesh = geoimg.load_mesh(obj)
        image = geoimg.mesh_to_image(mesh, res)
        smooth = image.apply(filters.gaussian_filter, 1.5)
        quads = smooth.to_mesh()
        glb = geoimg.load_mesh(geoimg.save_mesh(quads, Path(tmp) / "spot.glb"))
    d = geoimg.mesh.surface_distance(mesh, image.to_mesh(), n=50000)
    flat = np.round(image.colors * 255).astype(np.uint8)
    with Renderer(*size) as r:
        cam = r.camera_for(mesh, azimuth=-40, elevation=15)
        row = [caption(r.render(mesh, cam), f"input: {mesh.n_faces} triangles, textured"),
               caption(fit_width(flat, size[0]), f"the image's colours ({res} x {res})"),
               caption(r.render(quads, cam), "quad mesh, geometry smoothed"),
               caption(r.render(glb, cam), "its GLB, read back")]
    stats = {"psnr_db": d["psnr_db"], "texture": list(glb.texture.shape),
             "colours_kept": bool(np.array_equal(smooth.colors, image.colors))}
    stats["png"] = str(save(sheet([row]), Path(out_dir) / "textured.png"))
    return stats


def main():
    sample_main(run, __doc__, None, res=257)


if __name__ == "__main__":
    main()
