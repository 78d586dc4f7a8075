"""Sphere maps balanced by Gauss-Newton steps against the Sobolev steps and sweeps (issue 53): each closed
genus-0 mesh mapped both ways in one process, alternating, against one linear map of the same mesh.

    python benchmarks/bench_sphere_newton.py [--rounds 2] [--res 257 513] [--only] [extra meshes ...]

Prints a markdown row per mesh: the linear map (one sparse cotangent solve, best of 3), each way's seconds
(``parametrize`` only, best of ``--rounds``) and ratio to the linear map, its stages and balancing steps,
whether Gauss-Newton steps made the final map (``gn``), and the image's PSNR at each of ``--res`` (resampled
linearly through the map, 50,000 area samples a side against the mesh). The Sobolev way is the map before
the Gauss-Newton steps to the bit (``NEWTON_VERTICES = -1``: no Gauss-Newton steps, no conformal folds
opened). With ``--progressive`` they differ only in how a coarse-to-fine map is balanced at every size: 30
Sobolev steps and 60 sweeps (``PROGRESSIVE_NEWTON = False``) or at most 4 Gauss-Newton steps (the default).
With ``--multilevel`` they differ only in how the map from a decimated copy (meshes of 20,000 triangles and
more) is balanced on the fine mesh: 10 Sobolev steps, 60 sweeps and 10 steps again (before, 2026-12-07:
``MULTILEVEL_STEPS = 10``, ``MULTILEVEL_SWEEP_ROUNDS = 1``) or at most 30 steps, not swept (the default).
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import geoimg
import geoimg.parametrization._sphere as sphere
from geoimg.mesh._metrics import ReferenceDistances

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_profile import best_alternating, image_psnr, linear_map, map_cell, with_attribute  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
MESHES = [ROOT / "tests" / "data" / "spot.obj", SHARED / "closed_genus0" / "bunny.obj",
          SHARED / "closed_genus0" / "bumpy.off", ROOT / "tests" / "data" / "fish.obj",
          SHARED / "closed_genus0" / "armadillo.obj", SHARED / "closed_genus0" / "human_man.obj",
          SHARED / "closed_genus0" / "human_woman.obj", ROOT / "tests" / "data" / "scorpion_low_resolution.obj",
          SHARED / "polygonal" / "horse_quad.obj", SHARED / "closed_genus0" / "bunny.off"]


PROGRESSIVE = False     # --progressive: the two ways differ only in the coarse-to-fine map's balancing
MULTILEVEL = False      # --multilevel: ... only in the fine balancing of the map from the decimated copy


def run(path: Path, rounds: int, sizes: list[int]) -> None:
    mesh = geoimg.load_mesh(path)
    base = min(linear_map(mesh, False) for _ in range(3))
    ref = ReferenceDistances(mesh, 50_000)
    def mapped():
        return geoimg.parametrize(mesh, "sphere")

    if MULTILEVEL:
        def before():
            return with_attribute(sphere, "MULTILEVEL_STEPS", 10,
                                  lambda: with_attribute(sphere, "MULTILEVEL_SWEEP_ROUNDS", 1, mapped))
    else:
        changed = ("PROGRESSIVE_NEWTON", False) if PROGRESSIVE else ("NEWTON_VERTICES", -1)
        def before():
            return with_attribute(sphere, *changed, mapped)
    best = best_alternating(rounds, {"sobolev": before, "gauss-newton": mapped})
    cells = [map_cell(wall, p, base, [image_psnr(mesh, p, res, ref) for res in sizes], stages=True)
             for wall, p in (best["sobolev"], best["gauss-newton"])]
    print(f"| {path.name} ({mesh.n_faces}) | {base:.3f} s | {' | '.join(cells)} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--res", type=int, nargs="+", default=[257, 513])
    ap.add_argument("--only", action="store_true", help="only the extra meshes")
    ap.add_argument("--progressive", action="store_true",
                    help="before: the coarse-to-fine map balanced by Sobolev steps and sweeps at every size")
    ap.add_argument("--multilevel", action="store_true",
                    help="before: the map from the decimated copy balanced by steps, sweeps and steps again")
    ap.add_argument("extra", nargs="*", help="more closed genus-0 meshes")
    args = ap.parse_args()
    global PROGRESSIVE, MULTILEVEL
    PROGRESSIVE, MULTILEVEL = args.progressive, args.multilevel
    warnings.simplefilter("ignore")
    geoimg.parametrize(geoimg.load_mesh(ROOT / "tests" / "data" / "spot.obj"), "sphere")      # numba compiled
    ways = ("steps, sweeps, steps (before)", "30 steps (now)") if MULTILEVEL else (
        "Sobolev steps and sweeps (before)", "Gauss-Newton first (now)")
    print(f"| mesh (faces) | linear map | {ways[0]} | {ways[1]} "
          f"[PSNR at {' / '.join(map(str, args.res))}] |\n|---|---:|---|---|")
    for path in [*([] if args.only else MESHES), *map(Path, args.extra)]:
        run(path, args.rounds, args.res)


if __name__ == "__main__":
    main()
