"""Every mesh of ../shared/data through mesh -> image -> quad mesh, whatever its topology (the any-mesh issue).

Per piece (after geoimg.mesh.repair): the domain auto picks, genus and boundary loops of the input and of
the quad mesh, folded faces, the cut's length over sqrt(area) (cut domain), the area distortion of the
map (log-RMS of each triangle's share of the parameter area over its share of the surface area; sphere:
as the sphere map reports it), the largest distance between twin pixels before they are averaged
(relative to the diagonal), PSNR at 257^2 and 513^2 (s = 1) and the parametrization's time. Then the
time of the cut parametrization of 100,000- and 171,000-face genus-1 meshes.

    python benchmarks/bench_cut.py [--shared ../shared/data] [--quick]
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import trimesh

import geoimg
from geoimg.mesh import repair, surface_distance, topology
from geoimg.parametrization._slim import area_log_rms as planar_area_log_rms

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
import meshes  # noqa: E402  (the tests' synthetic meshes)


def area_log_rms(param, mesh) -> float:
    if param.domain == "octahedral":
        return float(param.info.get("area_log_rms", np.nan))
    mesh = param.mesh if param.mesh is not None else mesh
    tris, _ = mesh.triangulate()
    v = mesh.vertices
    a3 = 0.5 * np.linalg.norm(np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]]), axis=1)
    return planar_area_log_rms(a3, param.coords, tris)


def row(name: str, piece: geoimg.Mesh, n_samples: int) -> str:
    t0 = time.perf_counter()
    param = geoimg.parametrize(piece)
    t_param = time.perf_counter() - t0
    topo_in = topology(piece)
    surf = geoimg.fit_surface(piece, param, geoimg.GaussianWeights())
    psnr, spread, topo_out = [], "", None
    for res in (257, 513):
        image = surf.sample(res)
        quads = image.to_mesh()
        psnr.append(surface_distance(piece, quads, n=n_samples)["psnr_db"])
        topo_out = topology(quads)
        if "glue_spread" in image.metadata and res == 513:
            spread = f"{image.metadata['glue_spread'] / piece.bounding_box_diagonal():.1e}"
    cut = ""
    if param.domain == "cut":
        tris, _ = piece.triangulate()
        v = piece.vertices
        area = (
            0.5 * np.linalg.norm(np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]]), axis=1).sum()
        )
        cut = f"{param.info['cut_length'] / np.sqrt(area):.2f}"
    kept = (topo_out.genus, topo_out.boundary_loops) == (topo_in.genus, topo_in.boundary_loops)
    return (f"| {name} | {piece.n_faces} | {image.domain.kind} | {topo_in.genus} / {topo_in.boundary_loops} | "
            f"{topo_out.genus} / {topo_out.boundary_loops}{'' if kept else ' (!)'} | {param.flipped_faces} | {cut} | "
            f"{area_log_rms(param, piece):.2f} | {spread} | {psnr[0]:.1f} | {psnr[1]:.1f} | {t_param:.2f} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shared", default=str(ROOT.parent / "shared" / "data"))
    ap.add_argument("--quick", action="store_true", help="fewer distance samples, no large timing meshes")
    args = ap.parse_args()
    n_samples = 50_000 if args.quick else 200_000
    print("| mesh | faces | domain | genus / loops in | out | folds | cut / sqrt(area) | area log-RMS | "
          "twin spread / diag | PSNR 257^2 (dB) | PSNR 513^2 (dB) | parametrization (s) |")
    print("|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for path in sorted(Path(args.shared, "meshes").rglob("*")):
        if path.suffix not in (".obj", ".off", ".ply"):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                pieces = repair(geoimg.load_mesh(path))
            except geoimg.GeoimgError as e:
                print(f"| {path.name} | refused: {e} |")
                continue
            for k, piece in enumerate(pieces):
                name = path.name if len(pieces) == 1 else f"{path.name} piece {k}"
                print(row(name, piece.mesh, n_samples), flush=True)
    if args.quick:
        return
    print("\nCut parametrization of large genus-1 meshes (time of parametrize(mesh, 'cut'), best of 2):")
    big = {"torus grid 250 x 200 (100,000 faces)": meshes.torus_grid(250, 200)}
    bob = trimesh.Trimesh(*(lambda m: (m.vertices, m.faces))(geoimg.load_mesh(ROOT / "tests/data/bob_tri.obj")),
                          process=False)
    for _ in range(2):
        bob = bob.subdivide()
    big["bob_tri.obj subdivided twice (171,008 faces)"] = geoimg.Mesh(bob.vertices, bob.faces)
    for name, mesh in big.items():
        times = []
        for _ in range(2):
            t0 = time.perf_counter()
            p = geoimg.parametrize(mesh, "cut")
            times.append(time.perf_counter() - t0)
        print(f"  {name}: {min(times):.2f} s, {p.flipped_faces} folds, balancing steps {p.info['balance_steps']}, "
              f"area log-RMS {area_log_rms(p, mesh):.2f}")


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        main()
