"""Spherical harmonics of closed genus-0 meshes: geoimg (x, y, z over its balanced sphere map) against
aicsshparam (the radial function of a voxelized shape about its centroid), both rebuilt and measured
against the mesh with the exact metric (two-sided RMS by an AABB tree, PSNR = 20 log10(diagonal / RMS)).

    python benchmarks/bench_harmonics.py [--lmax 8 16 32 64] [--anchor 16 32] [--json out.json] [MESH ...]
    python benchmarks/bench_harmonics.py --speed [MESH]      # L = 64 against the conversion; L = 256 end to end

geoimg: ``geoimg.harmonics(mesh, max L)`` once (its 2^k + 1 image), rebuilt at each L as a 513^2 octahedral
image. aicsshparam 0.1.11 (bench extra): the mesh voxelized (trimesh, filled) with 128 voxels along its
longest side, ``get_shcoeffs(alignment_2d=False)``, its reconstruction mesh scaled back to the mesh's
units. Also the time of the coefficients to L = 64 against the mesh's ``mesh_to_image`` at the same side.
"""
from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.mesh import surface_distance
from geoimg.spectrum import default_resolution, harmonics

from _sheet import render_sheet          # noqa: E402  (benchmarks/, the script's own folder)

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes" / "closed_genus0"
SAMPLES = 100_000


def default_meshes() -> list[Path]:
    out = [ROOT / "tests" / "data" / "spot.obj", ROOT / "tests" / "data" / "fish.obj"]
    out += [SHARED / n for n in ("bunny.obj", "armadillo.obj", "human_man.obj", "bumpy.off") if (SHARED / n).exists()]
    return out


def psnr(mesh, other) -> float:
    return round(float(surface_distance(mesh, other, n=SAMPLES)["psnr_db"]), 2)


def anchor(mesh: geoimg.Mesh, lmax: int, voxels: int = 128):
    """The anchor's (aicsshparam's) reconstruction at ``lmax`` of ``mesh`` voxelized, in the mesh's units."""
    import trimesh
    from aicsshparam import shparam, shtools
    from vtk.util import numpy_support

    tm = trimesh.Trimesh(mesh.vertices, mesh.triangulate()[0], process=False)
    pitch = float(np.ptp(mesh.vertices, axis=0).max()) / voxels
    grid = tm.voxelized(pitch).fill()
    image = np.pad(grid.matrix.astype(np.uint8), 4).transpose(2, 1, 0)          # ZYX, a margin around
    (_, grid_rec), (_, _, _, transform) = shparam.get_shcoeffs(image=image, lmax=lmax, alignment_2d=False)
    rec = shtools.get_reconstruction_from_grid(grid_rec, centroid=transform[:3])
    points = numpy_support.vtk_to_numpy(rec.GetPoints().GetData()).astype(np.float64)   # XYZ voxel indices
    cells = numpy_support.vtk_to_numpy(rec.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    world = (points - 4) @ grid.transform[:3, :3].T + grid.transform[:3, 3]
    return geoimg.Mesh(world, cells)


def figure(mesh_path: Path, out: Path, degrees=(4, 8, 16, 32, 64)) -> None:
    """The shape rebuilt at each degree, side by side, and the mesh itself last, rendered alike."""
    mesh = geoimg.load_mesh(mesh_path)
    h = harmonics(mesh, max(degrees))
    shapes = [(f"L = {L}", h.to_image(257, lmax=L)) for L in degrees] + [("mesh", mesh)]
    render_sheet([shapes], mesh, out)


def speed(path: Path) -> None:
    """The coefficients to L = 64 against ``mesh_to_image`` at the same side (513), twice each, alternating,
    after a warm-up; then L = 256 end to end: coefficients (a 2049^2 image), the rebuilt image and its PSNR.
    """
    mesh = geoimg.load_mesh(path)
    small = geoimg.load_mesh(ROOT / "tests" / "data" / "spot.obj")
    harmonics(small, 8, resolution=65)                       # compile and warm up
    geoimg.mesh_to_image(small, 65, method="sphere")
    times: dict = {"coefficients": [], "image": []}
    for _ in range(2):
        t0 = time.perf_counter()
        h = harmonics(mesh, 64)
        times["coefficients"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        geoimg.mesh_to_image(mesh, default_resolution(64), method="sphere")
        times["image"].append(time.perf_counter() - t0)
    c, i = min(times["coefficients"]), min(times["image"])
    print(f"| {path.name} | {mesh.n_faces} | L = 64 coefficients {c:.1f} s | mesh_to_image 513^2 {i:.1f} s | "
          f"ratio {c / i:.2f} | runs {[round(t, 1) for t in times['coefficients']]} / "
          f"{[round(t, 1) for t in times['image']]} |", flush=True)
    t0 = time.perf_counter()
    h = harmonics(small, 256)
    t_coeffs = time.perf_counter() - t0
    t0 = time.perf_counter()
    rebuilt = h.to_image()
    t_image = time.perf_counter() - t0
    print(f"| spot.obj | L = 256 | coefficients ({h.metadata['resolution']}^2 image) {t_coeffs:.1f} s | rebuilt "
          f"{rebuilt.shape[0]}^2 {t_image:.1f} s | PSNR {psnr(small, rebuilt.to_mesh())} dB | image's own PSNR "
          f"{h.metadata.get('psnr_db')} dB |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--lmax", nargs="+", type=int, default=[8, 16, 32, 64])
    ap.add_argument("--anchor", nargs="*", type=int, default=[8, 16, 32])
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--figure", type=Path, default=None, help="only draw the first mesh rebuilt at L = 4 ... 64")
    ap.add_argument("--speed", action="store_true", help="only the timings (default mesh: bunny.off, 69.7k faces)")
    args = ap.parse_args()
    if args.speed:
        warnings.simplefilter("ignore")
        speed(args.meshes[0] if args.meshes else SHARED / "bunny.off")
        return
    if min(args.lmax) < 1 or (args.anchor and min(args.anchor) < 1):
        ap.error("degrees: at least 1")
    warnings.simplefilter("ignore")
    if args.figure:
        figure((args.meshes or default_meshes())[0], args.figure)
        return
    rows = []
    header = " | ".join(f"L={L}" for L in args.lmax)
    anchors = " | ".join(f"aics L={L}" for L in args.anchor)
    print(f"| mesh | faces | {header} | {anchors} | coeffs s | image s |")
    print("|---" * (4 + len(args.lmax) + len(args.anchor)) + "|")
    for path in args.meshes or default_meshes():
        mesh = geoimg.load_mesh(path)
        top = max(args.lmax)
        t0 = time.perf_counter()
        h = harmonics(mesh, top)
        t_coeffs = time.perf_counter() - t0
        t0 = time.perf_counter()
        geoimg.mesh_to_image(mesh, default_resolution(top), method="sphere")
        t_image = time.perf_counter() - t0
        ours = {L: psnr(mesh, h.to_image(513, lmax=L).to_mesh()) for L in args.lmax}
        theirs = {}
        for L in args.anchor:
            try:
                theirs[L] = psnr(mesh, anchor(mesh, L))
            except Exception as e:   # noqa: BLE001 - the anchor's own failures are reported, not hidden
                theirs[L] = f"failed: {type(e).__name__}"
        row = {"mesh": path.name, "faces": mesh.n_faces, "geoimg": ours, "aicsshparam": theirs,
               "image_psnr": h.metadata.get("psnr_db"), "coeffs_s": round(t_coeffs, 2), "image_s": round(t_image, 2)}
        rows.append(row)
        print(f"| {path.name} | {mesh.n_faces} | " + " | ".join(str(ours[L]) for L in args.lmax) + " | "
              + " | ".join(str(theirs[L]) for L in args.anchor) + f" | {t_coeffs:.1f} | {t_image:.1f} |", flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
