"""
What sticks out of a disk: balancing a disk map
===============================================

What sticks out of a disk: Spot (from tests/data) opened at the belly, mapped onto the square by mean-value
coordinates alone (`--balance none`), relaxed by SLIM with the boundary held (`--balance slim`) and area-balanced
with the boundary sliding along the square's sides (`--balance area`, the default).

    python samples/balanced_disk.py [OUT_DIR] [--res 129]

Left to right: the input (a hole of radius 0.15 at the belly, so it is a disk); the quad mesh of a 65 x 65
image of the plain mean-value map with its grid lines (the legs, head and tail, squeezed into a few pixels,
are cut off by the grid); the same after SLIM; the same after area balancing. The PSNRs are those of the `--res`
images' quad meshes.
Writes OUT_DIR/balanced_disk.png.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.animation import Renderer
from geoimg.mesh import surface_distance

from _common import TEST_DATA, caption, sample_main, save, sheet

BELLY = np.array([0.0, -0.4815, 0.2562])      # the lowest point of Spot's body between its legs
HOLE = 0.15


def open_at_the_belly() -> geoimg.Mesh:
    """Spot without the faces whose centres lie within HOLE of its belly: one boundary loop."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                  # the file's UV seams are not read
        mesh = geoimg.load_mesh(TEST_DATA / "spot.obj")
    f = mesh.faces[np.linalg.norm(mesh.vertices[mesh.faces].mean(axis=1) - BELLY, axis=1) > HOLE]
    used = np.unique(f)
    index = np.full(mesh.n_vertices, -1)
    index[used] = np.arange(len(used))
    return geoimg.Mesh(mesh.vertices[used], index[f])


def run(out_dir: Path, res: int = 129, size=(360, 300)) -> dict:
    mesh = open_at_the_belly()
    stats, row = {}, []
    with Renderer(*size) as r:
        cam = r.camera_for(mesh, azimuth=35, elevation=10)
        row.append(caption(r.render(mesh, cam), f"input: {mesh.n_faces} triangles, open at the belly"))
        for balance in ("none", "slim", "area"):
            p = geoimg.parametrize(mesh, "disk", balance=balance)
            quads = geoimg.mesh_to_image(mesh, res, parametrization=p).to_mesh()
            d = surface_distance(mesh, quads, n=50000)
            coarse = geoimg.mesh_to_image(mesh, 65, parametrization=p).to_mesh()
            stats[balance] = {"area_log_rms": p.info["area_log_rms"], "folds": p.flipped_faces,
                              "psnr_db": d["psnr_db"], "hausdorff": d["hausdorff"] / d["diagonal"]}
            label = {"none": "mean-value map", "slim": "after SLIM", "area": "area-balanced"}[balance]
            row.append(caption(r.render(coarse, cam, edges=coarse, edge_color=(0.2, 0.2, 0.6)),
                               f"{label}: log-RMS {p.info['area_log_rms']:.1f}, {d['psnr_db']:.1f} dB"))
    stats["png"] = str(save(sheet([row]), Path(out_dir) / "balanced_disk.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=129)


if __name__ == "__main__":
    main()
