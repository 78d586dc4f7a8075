"""The README's picture of the sphere's area balancing (issue 18): the armadillo (../shared/data) mapped to the
sphere, its quad mesh from a 97 x 97 octahedral image of the conformal starting map (no balancing steps) and of
the balanced map (the default steps), with the grid lines, seen from two sides.

    python benchmarks/sphere_balance_strip.py [OUT.png]

Prints each map's area log-RMS and the PSNR of its 257² image's quad mesh; writes the picture (default
docs/gallery/sphere_balance.png).
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

import geoimg
from geoimg.animation import Renderer
from geoimg.mesh import surface_distance
from geoimg.parametrization import Parametrization
from geoimg.parametrization._sphere import sphere_coords

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "samples"))
from _common import caption, save, sheet  # noqa: E402
from make_gallery import shrink  # noqa: E402

MESH = HERE.parents[1] / "shared" / "data" / "meshes" / "closed_genus0" / "armadillo.obj"
VIEWS = ((200.0, 10.0), (250.0, 30.0))        # (azimuth, elevation): two sides


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else HERE.parent / "docs" / "gallery" / "sphere_balance.png"
    mesh = geoimg.load_mesh(MESH)
    rows = []
    with warnings.catch_warnings(), Renderer(300, 300) as r:
        warnings.simplefilter("ignore")
        for label, steps in (("conformal start", 0), ("balanced", None)):
            s, info = sphere_coords(mesh, steps=steps)
            p = Parametrization(s, (1.0, 1.0), "octahedral", "sphere", info["flipped_triangles"], 0, info)
            d = surface_distance(mesh, geoimg.mesh_to_image(mesh, 257, parametrization=p).to_mesh(), n=50000)
            coarse = geoimg.mesh_to_image(mesh, 97, parametrization=p).to_mesh()
            print(f"{label}: area log-RMS {info['area_log_rms']:.2f}, least area ratio {info['area_ratio_min']:.1e}, "
                  f"{info['flipped_triangles']} folded, PSNR at 257² {d['psnr_db']:.1f} dB", flush=True)
            row = []
            for azimuth, elevation in VIEWS:
                cam = r.camera_for(mesh, azimuth=azimuth, elevation=elevation, up="y")
                row.append(caption(r.render(coarse, cam, edges=coarse, edge_color=(0.2, 0.2, 0.6)),
                                   f"{label}: log-RMS {info['area_log_rms']:.1f}, {d['psnr_db']:.1f} dB"
                                   if azimuth == VIEWS[0][0] else "97 x 97 quads"))
            rows.append(row)
    out = save(sheet(rows), out)
    shrink(out, out, 900)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
