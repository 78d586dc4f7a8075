"""
Denoising a terrain through its geometry image
==============================================

Denoising a mesh through its geometry image: the bundled terrain with scanner-like noise, cleaned by
non-local means on its image, next to mesh-space Taubin smoothing (trimesh).

    python samples/denoise.py [OUT_DIR] [--res 161]

Left to right: the clean terrain; the noise (each vertex moved along its normal by a Gaussian of 0.25 % of
the diagonal, 0.5 % of them by 8 times that: a scanner's outliers); the noisy mesh's 161 x 161 geometry
image (s = 0.5; about a pixel a vertex, so the noise stays white) denoised by `geoimg filter --median 3
--nlmeans H` (h = sigma), the best image route of the benchmark on this mesh, as its quad mesh; trimesh's Taubin filter
(50 iterations) on the noisy triangles. Captions give the RMS distance to the clean mesh (per mille of the
diagonal). benchmarks/bench_denoise.py measures more meshes and denoisers. Writes OUT_DIR/denoise.png.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import trimesh

import geoimg
from geoimg._steps import apply_steps
from geoimg.animation import Renderer
from geoimg.mesh import surface_distance

from _common import MOUNTAIN, caption, sample_main, save, sheet

SIGMA, OUTLIERS, OUTLIER_SIZE = 0.0025, 0.005, 8.0     # of the diagonal; the share of outliers; their size


def noisy_copy(mesh: geoimg.Mesh, seed: int = 0) -> tuple[geoimg.Mesh, float]:
    """The mesh with scanner-like noise along its vertex normals, and the noise's sigma."""
    rng = np.random.default_rng(seed)
    sigma = SIGMA * mesh.bounding_box_diagonal()
    step = rng.normal(0.0, sigma, mesh.n_vertices)
    spikes = rng.random(mesh.n_vertices) < OUTLIERS
    step[spikes] = rng.choice([-1.0, 1.0], int(spikes.sum())) * OUTLIER_SIZE * sigma
    return geoimg.Mesh(mesh.vertices + mesh.vertex_normals() * step[:, None], mesh.faces), sigma


def per_mille(clean: geoimg.Mesh, out: geoimg.Mesh) -> float:
    d = surface_distance(clean, out, n=60000)
    return 1e3 * d["rms"] / d["diagonal"]


def run(out_dir: Path, res: int = 161, size=(360, 270)) -> dict:
    clean = geoimg.load_mesh(MOUNTAIN)
    noisy, sigma = noisy_copy(clean)
    t = time.perf_counter()
    image = geoimg.mesh_to_image(noisy, res, normals=False, weights=geoimg.CoverageWeights(s=0.5))
    quads = apply_steps(image, [("median", [3]), ("nlmeans", [sigma])]).to_mesh()
    t_image = time.perf_counter() - t
    tm = trimesh.Trimesh(noisy.vertices, noisy.faces, process=False)
    t = time.perf_counter()
    trimesh.smoothing.filter_taubin(tm, iterations=50)
    t_mesh = time.perf_counter() - t
    taubin = geoimg.Mesh(tm.vertices, tm.faces)
    stats = {"noisy": per_mille(clean, noisy), "image_nlmeans": per_mille(clean, quads),
             "mesh_taubin": per_mille(clean, taubin), "seconds_image_route": t_image, "seconds_taubin": t_mesh}
    with Renderer(*size) as r:
        cam = r.camera_for(clean, azimuth=30, elevation=35, up="y")
        row = [caption(r.render(clean, cam), "clean terrain"),
               caption(r.render(noisy, cam), f"noisy: {stats['noisy']:.2f} per mille"),
               caption(r.render(quads, cam), f"image + median + nlmeans: {stats['image_nlmeans']:.2f}"),
               caption(r.render(taubin, cam), f"mesh Taubin: {stats['mesh_taubin']:.2f}")]
    stats["png"] = str(save(sheet([row]), Path(out_dir) / "denoise.png"))
    return stats


def main():
    sample_main(run, __doc__, None, res=161)


if __name__ == "__main__":
    main()
