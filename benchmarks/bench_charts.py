"""One cut-open chart against the multi-chart map (issue 29): each mesh through ``geoimg.mesh_to_image`` with
``method="cut"`` and ``method="charts"`` at one resolution, scored by the exact metric (200,000 area samples
a side), with the map's starved share, the quad mesh's topology and the seconds of the whole conversion.

    python benchmarks/bench_charts.py MESH [MESH ...] [--res 257] [--charts 8] [--samples 200000]
"""
from __future__ import annotations

import argparse
import time
import warnings

import geoimg
from geoimg.mesh import surface_distance, topology
from geoimg.parametrization._parametrize import _charts, _cut


def one(mesh, method: str, res: int, charts: int, samples: int) -> str:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        param = _cut(mesh) if method == "cut" else _charts(mesh, charts=charts)
        img = geoimg.mesh_to_image(mesh, res, parametrization=param)
    seconds = time.perf_counter() - t0
    quads = img.to_mesh()
    d = surface_distance(mesh, quads, samples)
    t = topology(quads)
    shape = f"closed, genus {t.genus}" if t.closed else t.describe()
    extra = f"{param.info['charts']} charts" if method == "charts" else f"{param.info['segments']} segments"
    return (f"| {method} ({extra}) | {img.shape[0]} x {img.shape[1]} | {100 * param.info['starved_share']:.1f} % | "
            f"{d['psnr_db']:.2f} | {100 * d['hausdorff_rel']:.2f} | {shape} | {seconds:.1f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="+")
    ap.add_argument("--res", type=int, default=257)
    ap.add_argument("--charts", type=int, default=8)
    ap.add_argument("--samples", type=int, default=200000)
    args = ap.parse_args()
    print("| mesh | map | image | starved | PSNR (dB) | Hausdorff (%) | quad mesh | seconds |")
    print("|---|---|---|---:|---:|---:|---|---:|")
    for path in args.meshes:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = geoimg.load_mesh(path)
        for method in ("cut", "charts"):
            print(f"| {path.rsplit('/', 1)[-1]} " + one(mesh, method, args.res, args.charts, args.samples), flush=True)


if __name__ == "__main__":
    main()
