"""
Figs. 3, 6, 7, 8: small meshes at increasing s
==============================================

Paper Figs. 3, 6, 7, 8: small meshes and their weighted-mean surfaces at increasing s, mesh overlaid.

    python samples/fig3_small_meshes.py [OUT_DIR] [--res 129]

Rows: triangles (a coarse grid of the Mount St. Helens crater), triangles and quads and pentagons (Spot's
control mesh, closed, through the sphere), an irregular mesh (a Delaunay TIN of scattered DEM points).
Columns: s = 0.5, 1, 2. Writes OUT_DIR/fig3_small_meshes.png.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

import geoimg
from geoimg.animation import Renderer
from geoimg.mesh import load_dem

from _common import CELL, DATA, caption, sample_main, save, sheet, st_helens

S_VALUES = (0.5, 1.0, 2.0)


def irregular_tin(n_points: int = 90, seed: int = 3) -> geoimg.Mesh:
    h = load_dem(DATA / "msh_nad83_27_2007-07-05.tif")[100:300, 60:260]
    rng = np.random.default_rng(seed)
    rows, cols = rng.integers(0, 200, n_points), rng.integers(0, 200, n_points)
    corners = np.array([[0, 0], [0, 199], [199, 0], [199, 199]])
    rc = np.vstack([corners, np.stack([rows, cols], 1)])
    xy = np.stack([rc[:, 1] * CELL, -rc[:, 0] * CELL], 1)
    return geoimg.Mesh(np.column_stack([xy, h[rc[:, 0], rc[:, 1]]]), Delaunay(xy).simplices)


def cases():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")             # its texture seams: the UVs are not needed here
        spot = geoimg.load_mesh(DATA / "spot_control_mesh.obj")
    return [("triangles", st_helens(2007, 16, (60, 300, 40, 280)), "heightfield", "z", 15.0),
            ("triangles, quads, pentagons", spot, "sphere", "y", -60.0),
            ("irregular TIN", irregular_tin(), "heightfield", "z", 15.0)]


def run(out_dir: Path, res: int = 129, size=(300, 240)) -> dict:
    rows, stats = [], {}
    with Renderer(*size) as r:
        for name, mesh, method, up, azimuth in cases():
            param = geoimg.parametrize(mesh, method, axis="z" if method == "heightfield" else None)
            cam = r.camera_for(mesh, azimuth=azimuth, elevation=35 if up == "z" else 15, up=up)
            row = [caption(r.render(mesh, cam, edges=mesh), f"{name}: the mesh")]
            for s in S_VALUES:
                surface = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s))
                quads = surface.sample(res | 1 if method == "sphere" else res).to_mesh()
                row.append(caption(r.render(quads, cam, edges=mesh), f"s = {s:g}"))
            rows.append(row)
            stats[name] = {"faces": mesh.n_faces, "sizes": sorted(set(mesh.face_sizes.tolist()))}
    stats["png"] = str(save(sheet(rows), Path(out_dir) / "fig3_small_meshes.png"))
    return stats


def main(argv=None):
    sample_main(run, __doc__, argv, res=129)


if __name__ == "__main__":
    main()
