"""Sliver faces on a real Delaunay TIN: the paper's rule against the robust default.

A TIN of the Mount St. Helens 2007 DEM (10 m cells): 4,000 scattered grid points, Delaunay-
triangulated, as survey points would be (long thin triangles line the convex hull). The surface is sampled at
256 x 256 with both sliver rules, and compared in height with the TIN itself (its piecewise-linear
interpolation) at every pixel inside the hull. Writes benchmarks/slivers.png (hillshades).

Run: python benchmarks/bench_slivers.py
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.interpolate import LinearNDInterpolator
from scipy.spatial import Delaunay

import geoimg
from geoimg.surface._cells import enclosing_circle_radius
from geoimg.surface._gaussian_face_maps import SLIVER_RATIO

HERE = Path(__file__).resolve().parent
DEM = HERE.parents[1] / "shared" / "data" / "dem" / "msh_nad83_27_2007-07-05.tif"


def load_tin(n_points=4000, seed=0):
    import OpenImageIO as oiio

    z = oiio.ImageBuf(str(DEM)).get_pixels(oiio.FLOAT)[..., 0].astype(np.float64)
    H, W = z.shape
    rng = np.random.default_rng(seed)
    rows, cols = rng.integers(0, H, n_points), rng.integers(0, W, n_points)
    rc = np.unique(np.stack([rows, cols], 1), axis=0)
    xy = np.stack([rc[:, 1] * 10.0, -rc[:, 0] * 10.0], axis=1)
    tri = Delaunay(xy)
    verts = np.c_[xy, z[rc[:, 0], rc[:, 1]]]
    return geoimg.Mesh(verts, tri.simplices), tri


def main():
    mesh, tri = load_tin()
    param = geoimg.parametrize(mesh, "heightfield", axis="z")
    p = param.coords[mesh.faces]
    ratio = enclosing_circle_radius(p) / np.sqrt(np.abs(geoimg.parametrization.signed_face_areas(mesh, param.coords)))
    print(f"TIN: {mesh.n_vertices} vertices, {mesh.n_faces} triangles; {int((ratio > SLIVER_RATIO).sum())} "
          f"slivers (d > {SLIVER_RATIO:g} sqrt(area)), worst d / sqrt(area) = {ratio.max():.1f}")
    tin = LinearNDInterpolator(tri, mesh.vertices[:, 2])
    relief = np.ptp(mesh.vertices[:, 2])
    print(f"relief {relief:.0f} m; height error of the surface against the TIN, at 256 x 256 pixels inside the hull")
    print("| s | rule | RMS (m) | 99th pct (m) | max (m) | max / relief |")
    print("|---:|---|---:|---:|---:|---:|")
    shades = {}
    for s in (1.0, 2.0):
        for rule in ("paper", "robust"):
            surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s, sliver_rule=rule))
            img = surf.sample(256)
            P = img.pixels.astype(np.float64)
            ref = tin(P[..., 0], P[..., 1])
            inside = img.mask & np.isfinite(ref)
            err = np.abs(P[..., 2] - ref)[inside]
            print(f"| {s:g} | {rule} | {np.sqrt(np.mean(err ** 2)):.2f} | {np.percentile(err, 99):.2f} | "
                  f"{err.max():.1f} | {err.max() / relief:.3f} |")
            if s == 2.0:
                L = np.array([-0.5, 0.5, 0.7]) / np.linalg.norm([-0.5, 0.5, 0.7])
                shades[rule] = np.clip(img.normals @ L, 0, 1)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, (rule, sh) in zip(axes, shades.items()):
        ax.imshow(sh, cmap="gray")
        ax.set_title(f"sliver_rule={rule!r}, s=2 (hillshade, exact normals)")
        ax.axis("off")
    plt.tight_layout()
    plt.savefig(HERE / "slivers.png", dpi=80)


if __name__ == "__main__":
    main()
