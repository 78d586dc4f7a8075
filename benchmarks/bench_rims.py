"""Rims that follow the mesh (issue 52): how far a planar image's quad mesh strays from the mesh's boundary,
with the rim pixels snapped onto the boundary (geoimg.surface._coverage_rim, the default) and without (the mask's
staircase, as before), in pixel spacings, on open meshes whose outline is not the image's rectangle.

    python benchmarks/bench_rims.py [--res 129] [--picture docs/gallery/rims_petal.png]

Distances (geoimg.mesh.boundary_distance, both boundaries sampled every 1/8 pixel): "quad -> mesh" from the
quad mesh's rim to the mesh's boundary (what a picture shows as a saw blade), "mesh -> quad" the other way;
a pixel spacing is the image's parameter spacing carried into space (the mesh's width over the image's width
for a height field). Also the image's PSNR against the mesh (geoimg.mesh.surface_distance, 100k samples).
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.mesh import boundary_distance, load_dem, surface_distance
from geoimg.surface import prefilter_s

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data"
sys.path.insert(0, str(ROOT / "tests"))
import meshes                    # noqa: E402  (the tests' synthetic meshes)


def coast(n: int = 4000) -> geoimg.Mesh:
    """A terrain cut to a coastline: the Mount St Helens DEM's heights over a wavy outline."""
    grid = load_dem(SHARED / "dem" / "msh_nad83_2_2004-10-04.tif")
    grid = np.where(np.isfinite(grid), grid, np.nanmin(grid))
    t = np.linspace(0.0, 2 * np.pi, 220, endpoint=False)
    r = 0.42 + 0.05 * np.sin(5 * t) + 0.03 * np.cos(11 * t)
    outline = np.column_stack([0.5 + r * np.cos(t), 0.5 + r * np.sin(t)])
    z = (grid - grid.min()) / np.ptp(grid) * 0.25

    def height(x, y):
        i = np.clip((y * (grid.shape[0] - 1)).round().astype(int), 0, grid.shape[0] - 1)
        j = np.clip((x * (grid.shape[1] - 1)).round().astype(int), 0, grid.shape[1] - 1)
        return z[i, j]
    return meshes.outline_sheet(outline, n, height, seed=3)


def cases():
    yield "flat disk (600-pt TIN)", meshes.flat_disk(), "heightfield"
    yield "petal (600-pt TIN)", meshes.petal(), "heightfield"
    yield "petal (6k-pt TIN)", meshes.petal(6000, seed=1), "heightfield"
    yield "coast terrain (4k-pt TIN)", coast(), "heightfield"
    yield "flat disk, disk map, own outline", meshes.flat_disk(2000, seed=2), "keep"
    yield "mountain.obj (rectangle)", geoimg.load_mesh(SHARED / "meshes/open_disk/mountain.obj"), "y"


def image(mesh, param, res, snap: bool):
    surf = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
    surf = surf.with_s(prefilter_s(surf, res))
    if not snap:
        surf = type(surf)(**{**surf.__dict__, "rim": None})
    return surf.sample(res, normals=False)


def spacing(img, mesh, param) -> float:
    """The parameter spacing in space: the mesh's size over its parameter size."""
    span = np.linalg.norm(np.ptp(mesh.vertices, axis=0))
    uv = param.coords
    return span / np.linalg.norm(np.ptp(uv, axis=0)) * max(param.extent) / (max(img.shape) - 1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=129)
    ap.add_argument("--picture", default=None, help="draw the petal's rim before and after to this PNG")
    args = ap.parse_args()
    print("| mesh | faces | rim | quad -> mesh max / p95 (px) | mesh -> quad max / p95 (px) | PSNR (dB) |")
    print("|---|---:|---|---|---|---:|")
    for name, mesh, how in cases():
        param = (geoimg.parametrize(mesh, "disk", boundary="keep") if how == "keep"
                 else geoimg.parametrize(mesh, "heightfield", axis="y" if how == "y" else "z"))
        for snap in (False, True):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                img = image(mesh, param, args.res, snap)
            quad = img.to_mesh()
            h = spacing(img, mesh, param)
            d = boundary_distance(mesh, quad, step=h / 8)
            psnr = surface_distance(mesh, quad, n=100000)["psnr_db"]
            print(f"| {name} | {mesh.n_faces} | {'snapped' if snap else 'staircase'} | "
                  f"{d['other_max'] / h:.2f} / {d['other_p95'] / h:.2f} | "
                  f"{d['reference_max'] / h:.2f} / {d['reference_p95'] / h:.2f} | {psnr:.1f} |", flush=True)
        if args.picture and name.startswith("petal (600"):
            draw(mesh, param, args.res, Path(args.picture))


def draw(mesh, param, res, path: Path) -> None:
    """The petal's outline and the quad mesh's rim, staircase and snapped, seen from above."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from geoimg.mesh._metrics import _boundary_segments

    fig, axes = plt.subplots(1, 2, figsize=(9, 5.2))
    for ax, snap in zip(axes, (False, True)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            quad = image(mesh, param, res, snap).to_mesh()
        ax.add_collection(LineCollection(_boundary_segments(quad)[:, :, :2], colors="tab:red", linewidths=1.2,
                                         label="the image's rim"))
        ax.add_collection(LineCollection(_boundary_segments(mesh)[:, :, :2], colors="k", linewidths=0.6,
                                         label="the mesh's boundary"))
        ax.set_aspect("equal")
        ax.set_xlim(-0.12, 0.47)
        ax.set_ylim(0.6, 1.02)
        ax.set_title(f"{'snapped onto the boundary' if snap else 'the mask staircase (before)'}, {res}²")
        ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
