"""Where the maps' seconds go (issue 53: profile first): cProfile of one sphere, disk and cut map each,
after a warm-up (numba compiled), against one linear map of the same mesh in the same run.

    python benchmarks/bench_profile.py [--top 12]
    python benchmarks/bench_profile.py --pieces 60      # a 60-piece assembly through mesh_to_images at 257^2
    python benchmarks/bench_profile.py --holed 2        # the 40k-face bunny with 5 holes, twice, fresh processes

Prints, per map: the wall time, the ratio to the linear map (one sparse cotangent solve: the spherical
conformal map's first step for the sphere, the harmonic disk map for disks), and the functions that take
most of it (cumulative seconds and calls).
"""
from __future__ import annotations

import argparse
import cProfile
import io
import pstats
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import geoimg
from geoimg.mesh import boundary_loops
from geoimg.parametrization._laplacian import cotangent_weights

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"


def linear_map(mesh: geoimg.Mesh, disk: bool) -> float:
    """Seconds of one sparse cotangent solve on the mesh: the harmonic disk map (boundary on a circle) or,
    for a closed mesh, the Laplacian with one vertex pinned (the cheapest map one could return).
    """
    tris = mesh.triangulate()[0]
    t0 = time.perf_counter()
    w = cotangent_weights(mesh.vertices, tris)
    L = sp.csr_matrix(w) if not sp.issparse(w) else w.tocsr()
    n = L.shape[0]
    L = sp.diags(np.asarray(L.sum(axis=1)).ravel()) - L
    fixed = np.zeros(n, bool)
    b = np.zeros((n, 2))
    if disk:
        loop = boundary_loops(mesh)[0]
        angle = 2 * np.pi * np.arange(len(loop)) / len(loop)
        fixed[loop] = True
        b[loop] = np.c_[np.cos(angle), np.sin(angle)]
    else:
        fixed[0] = True
    free = ~fixed
    rhs = -L[free][:, fixed] @ b[fixed]
    spla.splu(L[free][:, free].tocsc()).solve(rhs)
    return time.perf_counter() - t0


def best_alternating(rounds: int, ways: dict) -> dict:
    """Each of ``ways`` (a name and a call) run ``rounds`` times, the ways taking turns (a noisy machine slows
    them alike); per name, the fastest run's ``(seconds, result)``.
    """
    best: dict = {}
    for _ in range(rounds):
        for name, call in ways.items():
            t0 = time.perf_counter()
            out = call()
            wall = time.perf_counter() - t0
            if name not in best or wall < best[name][0]:
                best[name] = (wall, out)
    return best


def with_attribute(owner, name: str, value, call):
    """``call()`` with ``owner.name`` set to ``value`` for the while (a module's constant or function)."""
    kept = getattr(owner, name)
    setattr(owner, name, value)
    try:
        return call()
    finally:
        setattr(owner, name, kept)


def map_cell(wall: float, parametrization, base: float, psnr: list[float], *, stages: bool = False) -> str:
    """One way's table cell: its seconds and ratio to the linear map ``base``, its stages (with ``stages``),
    balancing steps, whether Gauss-Newton steps made it (``gn``), its folds and its images' PSNR.
    """
    info = parametrization.info
    ran = f"{'+'.join(info['stages'])}, " if stages else ""
    gn = "gn" if info.get("gauss_newton") else "-"
    return (f"{wall:.2f} s, {wall / base:.0f}x, {ran}{info.get('balance_steps')} steps {gn}, "
            f"{parametrization.flipped_faces} flips, {' / '.join(f'{v:.2f}' for v in psnr)} dB")


def image_psnr(mesh: geoimg.Mesh, parametrization, res: int, reference) -> float:
    """The PSNR of the mesh's image at ``res`` through the given map (linear resampling, no fidelity check)
    against ``reference`` (:class:`geoimg.mesh._metrics.ReferenceDistances` of the mesh).
    """
    image = geoimg.mesh_to_image(mesh, res, parametrization=parametrization, fidelity=False)
    return reference.to(image.to_mesh(), vertices=False)["psnr_db"]


def profile(name: str, mesh: geoimg.Mesh, method: str, top: int) -> None:
    disk = method == "disk"
    base = min(linear_map(mesh, disk) for _ in range(3))
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    pr.enable()
    p = geoimg.parametrize(mesh, method)
    pr.disable()
    wall = time.perf_counter() - t0
    print(f"\n### {name} ({mesh.n_faces} faces), {method} map: {wall:.2f} s, {wall / base:.0f}x one linear map "
          f"({base:.3f} s); stages: {p.info.get('map_stages', p.info.get('stages', ''))}\n")
    out = io.StringIO()
    pstats.Stats(pr, stream=out).sort_stats("cumulative").print_stats(40)
    rows = [line for line in out.getvalue().splitlines() if "geoimg/" in line or "{" in line]
    print("| cumulative s | calls | function |\n|---:|---:|---|")
    for line in rows[:top]:
        parts = line.split()
        print(f"| {parts[3]} | {parts[0]} | {' '.join(parts[5:]).split('/work/main/')[-1]} |")


def assembly(count: int, seed: int = 0) -> geoimg.Mesh:
    """``count`` pieces in one mesh, as a CAD assembly or a vehicle model has them: boxes, closed cylinders,
    tori and icospheres in turn (trimesh.creation), of random sizes, scattered (seed 0).
    """
    import trimesh
    rng = np.random.default_rng(seed)
    parts = []
    for i in range(count):
        kind = i % 4
        if kind == 0:
            t = trimesh.creation.box(extents=rng.uniform(0.2, 2.0, 3))
        elif kind == 1:
            t = trimesh.creation.cylinder(radius=rng.uniform(0.1, 0.5), height=rng.uniform(0.5, 3), sections=24)
        elif kind == 2:
            t = trimesh.creation.torus(major_radius=0.5, minor_radius=0.15, major_sections=24, minor_sections=12)
        else:
            t = trimesh.creation.icosphere(subdivisions=2, radius=rng.uniform(0.2, 0.8))
        t.apply_translation(rng.uniform(-5, 5, 3))
        parts.append(t)
    whole = trimesh.util.concatenate(parts)
    return geoimg.Mesh(whole.vertices, whole.faces)


def pieces(count: int) -> None:
    """A ``count``-piece assembly through :func:`geoimg.mesh_to_images` at 257^2: seconds per stage, and one
    piece's fidelity measurement split into its parts.
    """
    from geoimg.mesh import point_mesh_distance, sample_surface
    mesh = assembly(count)
    timings: dict = {}
    t0 = time.perf_counter()
    images = geoimg.mesh_to_images(mesh, 257, timings=timings)
    wall = time.perf_counter() - t0
    print(f"{count} pieces, {mesh.n_faces} faces, {len(images)} images at 257²: {wall:.1f} s; stages (s): "
          + ", ".join(f"{k} {v:.2f}" for k, v in timings.items()))
    piece = geoimg.mesh.repair(mesh)[1].mesh
    quads = geoimg.mesh_to_image(piece, 257, fidelity=False).to_mesh()
    a, b = sample_surface(piece, 20_000), sample_surface(quads, 20_000)
    for name, fn in (("samples on the quad mesh", lambda: sample_surface(quads, 20_000)),
                     ("the piece's samples to the quad mesh (its AABB tree built)",
                      lambda: point_mesh_distance(a, quads)),
                     ("the quad mesh's samples and vertices to the piece", lambda: point_mesh_distance(b, piece))):
        fn()
        t0 = time.perf_counter()
        fn()
        print(f"  one piece ({piece.n_faces} faces, {quads.n_faces} quads): {name} {time.perf_counter() - t0:.3f} s")


def holed(runs: int) -> None:
    """The Stanford bunny's scan with its 5 holes (``open_other/stanford-bunny.obj``) decimated by libigl to
    40,000 faces (issue 53's cut map of a 40k-face mesh), through ``geoimg image --res 257`` in ``runs`` fresh
    processes: the wall time of each and the conversion's PSNR and stages.
    """
    import subprocess
    import sys
    import tempfile

    import igl
    mesh = geoimg.mesh.repair(geoimg.load_mesh(SHARED / "open_other" / "stanford-bunny.obj"))[0].mesh
    tris = mesh.triangulate()[0]
    U, G, _, _ = igl.decimate(np.asfortranarray(mesh.vertices), np.asfortranarray(tris, np.int32), 40_000)
    with tempfile.TemporaryDirectory() as tmp:
        src, out = Path(tmp) / "holed_bunny_40k.obj", Path(tmp) / "b.exr"
        geoimg.save_mesh(geoimg.Mesh(U, G), src)
        loops = len(boundary_loops(geoimg.load_mesh(src)))
        for _ in range(runs):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "geoimg.cli", "image", str(src), "-o", str(out), "--res", "257",
                            "-q", "--force"], check=True)
            wall = time.perf_counter() - t0
            meta = geoimg.load_image(out).metadata
            print(f"holed bunny ({len(G)} faces, {loops} boundary loops): {wall:.1f} s, {meta['psnr_db']} dB, "
                  f"{meta['parametrization']} map: {meta.get('map_stages')}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--top", type=int, default=12)
    ap.add_argument("--pieces", type=int, default=None, help="only a PIECES-piece assembly through mesh_to_images")
    ap.add_argument("--holed", type=int, default=None, help="only the 40k-face bunny with 5 holes, HOLED runs")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    if args.holed:
        holed(args.holed)
        return
    if args.pieces:
        pieces(args.pieces)
        return
    warm = geoimg.load_mesh(ROOT / "tests" / "data" / "spot.obj")
    geoimg.parametrize(warm, "sphere")
    geoimg.parametrize(geoimg.load_mesh(ROOT / "tests" / "data" / "cube_no_bottom.obj"), "disk")
    geoimg.parametrize(geoimg.load_mesh(ROOT / "tests" / "data" / "torus.obj"), "cut")
    for name, path, method in (("bunny.off", SHARED / "closed_genus0" / "bunny.off", "sphere"),
                               ("armadillo.obj", SHARED / "closed_genus0" / "armadillo.obj", "sphere"),
                               ("camelhead.off", SHARED / "open_disk" / "camelhead.off", "disk"),
                               ("mountain.obj", ROOT / "geoimg" / "data" / "mountain.obj", "disk"),
                               ("bob_tri.obj", ROOT / "tests" / "data" / "bob_tri.obj", "cut")):
        if path.exists():
            profile(name, geoimg.load_mesh(path), method, args.top)


if __name__ == "__main__":
    main()
