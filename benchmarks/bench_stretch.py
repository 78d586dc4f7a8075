"""The L2 stretch of geoimg's maps (issue 29's stretch figure), beside each image's PSNR at 257²: how much a
map stretches the surface, and the share of the surface it starves of parameter area.

    python benchmarks/bench_stretch.py [--res 257]

Sphere maps are measured on the sphere (before the octahedral image's own distortion), disk and cut-open
maps in their square. Meshes from ../shared/data.
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import geoimg
from geoimg.parametrization import map_stretch

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes"
MESHES = ["closed_genus0/bunny.obj", "closed_genus0/armadillo.obj", "closed_genus0/spot.obj",
          "closed_genus0/human_man.obj", "polygonal/sword-quad-dominant.obj", "polygonal/horse_quad.obj",
          "open_disk/camelhead.off", "open_disk/hemisphere.off", "closed_higher_genus/bob_tri.obj",
          "closed_higher_genus/torus.obj"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--res", type=int, default=257)
    args = ap.parse_args()
    print(f"| mesh | faces | map | L2 stretch | worst triangle | starved share | PSNR at {args.res}² (dB) "
          "| seconds (stretch) |")
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    for rel in MESHES:
        mesh = geoimg.load_mesh(DATA / rel)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            param = geoimg.parametrize(mesh)
            t0 = time.perf_counter()
            out = map_stretch(mesh, param)
            dt = time.perf_counter() - t0
            image = geoimg.mesh_to_image(mesh, args.res, parametrization=param)
        print(f"| {Path(rel).name} | {mesh.n_faces} | {param.method} | {out['l2']:.3f} | {out['worst']:.1f} | "
              f"{100 * out['starved']:.2f} % | {image.metadata['psnr_db']:.2f} | {dt:.3f} |", flush=True)


if __name__ == "__main__":
    main()
