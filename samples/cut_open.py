"""
A mesh with a handle, cut open
==============================

A mesh with a handle, cut open (Gu, Gortler & Hoppe 2002): Keenan Crane's Bob (genus 1) as a cut-open
geometry image and back as a closed genus-1 quad mesh.

    python samples/cut_open.py [OUT_DIR] [--res 257]

Left to right: the input; its geometry image (X, Y, Z as colours), each cut drawn on the border in one
colour on both of its sides (the twin pixels glued together); the quad mesh of the image, welded along
the cut; a coarse 65^2 version with its grid lines. Writes OUT_DIR/cut_open.png.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.animation import Renderer
from geoimg.mesh import surface_distance, topology

from _common import TEST_DATA, caption, sample_main, save, sheet

PALETTE = np.array([[230, 25, 75], [60, 180, 75], [0, 130, 200], [245, 130, 48], [145, 30, 180], [70, 240, 240],
                    [240, 50, 230], [210, 245, 60]], np.uint8)


def image_picture(image: geoimg.GeometryImage, size: int) -> np.ndarray:
    """X, Y, Z stretched to colours; the border coloured by cut (a segment and its twin alike)."""
    p = image.pixels.astype(np.float64)
    rgb = np.round((p - p.min((0, 1))) / np.ptp(p, axis=(0, 1)) * 255).astype(np.uint8)
    d = image.domain
    n = image.shape[0]
    per = geoimg.image.perimeter_pixels(n)
    scale = (n - 1) // d.quantum
    colour = 0
    for k, (_start, _length, twin) in enumerate(d.segments):
        if twin < 0 or twin < k:
            continue
        for seg in (k, twin):
            a, m = d.segments[seg][0] * scale, d.segments[seg][1] * scale
            idx = per[a:a + m + 1]
            rows, cols = idx // n, idx % n
            for dr in range(-1, 2):                       # a band 3 pixels wide
                for dc in range(-1, 2):
                    rgb[np.clip(rows + dr, 0, n - 1), np.clip(cols + dc, 0, n - 1)] = PALETTE[colour % len(PALETTE)]
        colour += 1
    reps = np.clip((np.arange(size) * n) // size, 0, n - 1)
    return rgb[reps][:, reps]


def run(out_dir: Path, res: int = 257, size=(360, 300)) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                  # the file's UV seams are not read
        mesh = geoimg.load_mesh(TEST_DATA / "bob_tri.obj")
    image = geoimg.mesh_to_image(mesh, res)
    coarse = geoimg.mesh_to_image(mesh, 65, weights=geoimg.CoverageWeights(s=2.0))
    quads, coarse_quads = image.to_mesh(), coarse.to_mesh()
    t_in, t_out = topology(mesh), topology(quads)
    stats = {"domain": image.domain.kind, "genus in": t_in.genus, "genus out": t_out.genus,
             "closed out": t_out.closed, "psnr_db": surface_distance(mesh, quads, n=50000)["psnr_db"],
             "glue_spread / diagonal": image.metadata["glue_spread"] / mesh.bounding_box_diagonal()}
    with Renderer(*size) as r:
        cam = r.camera_for(mesh, azimuth=35, elevation=30)
        row = [caption(r.render(mesh, cam), f"input: genus {t_in.genus}, {mesh.n_faces} triangles"),
               caption(image_picture(image, size[1]), f"cut-open image {res} x {res}"),
               caption(r.render(quads, cam), f"quad mesh: closed, genus {t_out.genus}, {stats['psnr_db']:.1f} dB"),
               caption(r.render(coarse_quads, cam, edges=coarse_quads, edge_color=(0.2, 0.2, 0.6)),
                       "65 x 65, s = 2, welded along the cut")]
    stats["png"] = str(save(sheet([row]), Path(out_dir) / "cut_open.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=257)


if __name__ == "__main__":
    main()
