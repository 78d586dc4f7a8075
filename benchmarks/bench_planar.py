"""Planar maps by Gauss-Newton steps against the Sobolev steps and sweeps (issue 53): disk and cut maps,
each mesh mapped both ways in one process, alternating, against one linear map of the same mesh.

    python benchmarks/bench_planar.py [--rounds 2] [--res 257] [extra meshes as PATH@METHOD ...]

Prints a markdown row per mesh: the linear map (the harmonic disk map, best of 3), each way's seconds
(``parametrize`` only, best of ``--rounds``) and ratio to the linear map, its balancing steps, whether the
Gauss-Newton steps made the map (``gn``) or stalled and handed over, and the image's PSNR at ``--res``
(resampled linearly through the map, 50,000 area samples a side against the mesh).
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

import geoimg
import geoimg.parametrization._disk as disk
from geoimg.mesh._metrics import ReferenceDistances

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_profile import best_alternating, image_psnr, linear_map, map_cell, with_attribute  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
MESHES = [
    (SHARED / "open_disk" / "camelhead.off", "disk"),
    (ROOT / "tests" / "data" / "demosthenes-low-res.obj", "disk"),
    (ROOT / "geoimg" / "data" / "mountain.obj", "disk"),
    (SHARED / "open_disk" / "hemisphere.off", "disk"),
    (SHARED / "open_disk" / "alligator.obj", "disk"),
    (ROOT / "tests" / "data" / "bob_tri.obj", "cut"),
    (ROOT / "tests" / "data" / "torus.obj", "cut"),
    (ROOT / "tests" / "data" / "plate_holes.STL", "cut"),
]


def _stalled(s, *args, **kwargs):
    """A Gauss-Newton descent that stalls at once: the Sobolev steps and sweeps map every start."""
    return np.array(s, dtype=np.float64), 0, (np.nan, np.nan), True


def run(path: Path, method: str, rounds: int, res: int) -> None:
    mesh = geoimg.load_mesh(path)
    topo = geoimg.mesh.topology(mesh)
    if topo.nonmanifold_vertices or topo.nonmanifold_edges:        # a CAD file: its largest piece, repaired
        mesh = max((piece.mesh for piece in geoimg.mesh.repair(mesh)), key=lambda m: m.n_faces)
    base = min(linear_map(mesh, method == "disk") for _ in range(3))
    ref = ReferenceDistances(mesh, 50_000)

    def mapped():
        return geoimg.parametrize(mesh, method)

    best = best_alternating(rounds, {"sobolev": lambda: with_attribute(disk, "newton_balance", _stalled, mapped),
                                     "gauss-newton": mapped})
    cells = [map_cell(wall, p, base, [image_psnr(mesh, p, res, ref)])
             for wall, p in (best["sobolev"], best["gauss-newton"])]
    print(f"| {path.name} {method} ({mesh.n_faces}) | {base:.3f} s | {' | '.join(cells)} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--res", type=int, default=257)
    ap.add_argument("extra", nargs="*", help="more meshes, PATH@METHOD (disk or cut)")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    geoimg.parametrize(geoimg.load_mesh(ROOT / "tests" / "data" / "cube_no_bottom.obj"), "disk")   # warm-up
    geoimg.parametrize(geoimg.load_mesh(ROOT / "tests" / "data" / "torus.obj"), "cut")
    print("| mesh (faces) | linear map | Sobolev steps and sweeps | Gauss-Newton first |\n|---|---:|---|---|")
    todo = MESHES + [(Path(p), m) for p, m in (e.rsplit("@", 1) for e in args.extra)]
    for path, method in todo:
        if path.exists():
            run(path, method, args.rounds, args.res)


if __name__ == "__main__":
    main()
