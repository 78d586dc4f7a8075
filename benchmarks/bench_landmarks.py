"""Landmark-aligned morphs against the rigid turn of the sphere (issue 17), with ground truth.

    python benchmarks/bench_landmarks.py [--res 129] [--counts 5 8 10 12]

`human_man` and `human_woman` (../shared/data) have the same vertices in the same order. The woman is
remeshed by splitting every triangle in four (her vertices keep their indices; the new ones sit on her
edges), so the two keys no longer share a parametrization. Key 0: the man; key 1: the remeshed woman.
Each man vertex is sent by the morph to key 1's image at the pixel of its own sphere direction; the truth
is the woman's vertex of the same index. The table gives the RMS and largest of those distances, per cent
of the woman's bounding-box diagonal, for the rigid turn (today's default) and for landmarks suggested on
the man (`suggest_landmarks(man, count, spread=True)`: his extremities, then the points farthest from those)
with their ground-truth partners; and what the warp reports. "Landmarks meet": the largest distance, on key 1's
mesh, between the point where the warp sends key 0's landmark direction and key 1's landmark vertex (the
same warp the morph made, again); "as imaged": key 1 as the morph shows it at key 0's landmark directions
against key 1's own image at its landmarks' directions (both interpolated: this one is limited by the
pixels, where the warp stretches a squeezed part of key 1's sphere).
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.animation import morph
from geoimg.animation._morph import _landmark_warp, _octahedral_sampler
from geoimg.surface._attributes import locate
from geoimg.mesh import suggest_landmarks
from geoimg.parametrization import sphere_to_square

SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes" / "closed_genus0"


def split_in_four(mesh: geoimg.Mesh) -> geoimg.Mesh:
    """Every triangle split into four at its edge midpoints; the vertices keep their indices."""
    tris = mesh.faces[:, :3]
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    uniq, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = mesh.n_vertices + inverse.reshape(3, -1).T                  # (T, 3): midpoints of ab, bc, ca
    v = np.vstack([mesh.vertices, mesh.vertices[uniq].mean(axis=1)])
    a, b, c = tris.T
    ab, bc, ca = mid.T
    faces = np.concatenate([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1), np.stack([ca, bc, c], 1),
                            np.stack([ab, bc, ca], 1)])
    return geoimg.Mesh(v, faces)


def sent(m, directions: np.ndarray, n: int) -> np.ndarray:
    uv = sphere_to_square(directions)
    rows, cols = np.round(uv[:, 1] * (n - 1)).astype(int), np.round(uv[:, 0] * (n - 1)).astype(int)
    return m.keys[1].pixels[rows, cols].astype(np.float64)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--res", type=int, default=129)
    ap.add_argument("--counts", type=int, nargs="+", default=[5, 8, 10, 12])
    args = ap.parse_args(argv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        man = geoimg.load_mesh(SHARED / "human_man.obj")
        woman = split_in_four(geoimg.load_mesh(SHARED / "human_woman.obj"))
        directions = geoimg.parametrize(man).coords
        own = geoimg.parametrize(woman)
        woman_image = geoimg.mesh_to_image(woman, args.res, parametrization=own)
        at_own = _octahedral_sampler(woman_image.pixels, woman_image.domain)
        truth = woman.vertices[: man.n_vertices]
        diag = woman.bounding_box_diagonal()
        print(f"man {man.n_vertices} vertices; remeshed woman {woman.n_vertices} ({own.method}, {own.flipped_faces} folded "
              f"faces); {args.res}² images\n")
        print("| alignment | RMS (% diag) | largest (% diag) | landmarks meet (% diag, largest) | as imaged "
              "| seconds | warp |")
        print("|---|---:|---:|---:|---:|---:|---|")
        runs = [("rigid turn of the sphere", None)] + [(f"{c} landmarks", suggest_landmarks(man, c, spread=True))
                                                         for c in args.counts]
        for name, marks in runs:
            kw = {} if marks is None else {"landmarks": [(int(i), int(i)) for i in marks]}
            t = time.perf_counter()
            m = morph(man, woman, frames=2, resolution=args.res, align="none", **kw)
            dt = time.perf_counter() - t
            err = np.linalg.norm(sent(m, directions, args.res) - truth, axis=1) / diag * 100
            w = m.report[1].get("landmarks")
            warp = off = meet = ""
            if w is not None:
                warp = (f"met {w['met']}, residual {w['residual_rad']:.1e} rad, {w['folded']} folded, {w['steps']} "
                        f"steps, area log-RMS {w['area_log_rms']:.2f}")
                sent_to = _landmark_warp(directions[marks], own.coords[marks], args.res, 1)["landmarks"]
                tri = woman.faces[:, :3]
                t, bary = locate(sent_to, own.coords[tri])
                on_mesh = np.einsum("pk,pkd->pd", bary, woman.vertices[tri[t]])
                meet = f"{(np.linalg.norm(on_mesh - woman.vertices[marks], axis=1) / diag * 100).max():.4f}"
                shown = _octahedral_sampler(m.keys[1].pixels, m.keys[1].domain)(directions[marks])
                off = f"{(np.linalg.norm(shown - at_own(own.coords[marks]), axis=1) / diag * 100).max():.3f}"
            print(f"| {name} | {np.sqrt((err ** 2).mean()):.2f} | {err.max():.1f} | {meet} | {off} | {dt:.1f} | {warp} |",
                  flush=True)


if __name__ == "__main__":
    main()
