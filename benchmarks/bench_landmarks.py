"""Landmark-aligned morphs against the rigid turn of the sphere (issue 17), with ground truth.

    python benchmarks/bench_landmarks.py [--res 129] [--counts 5 8 10 12]

`human_man` and `human_woman` (../shared/data) have the same vertices in the same order. The woman is
remeshed by splitting every triangle in four (her vertices keep their indices; the new ones sit on her
edges), so the two keys no longer share a parametrization. Key 0: the man; key 1: the remeshed woman.
Each man vertex is sent by the morph to key 1's image at the pixel of its own sphere direction; the truth
is the woman's vertex of the same index. The table gives the RMS and largest of those distances, per cent
of the woman's bounding-box diagonal, for the rigid turn (today's default) and for landmarks suggested on
the man (`suggest_landmarks(man, count, spread=True)`: his extremities, then the points farthest from those)
with their ground-truth partners, then for 8-11 "joints" (the extremities, the centre, the midpoints of the
paths from the centre to them); and what the warp reports. "Landmarks meet": the largest distance, on key 1's
mesh, between the point where the warp sends key 0's landmark direction and key 1's landmark vertex (the
same warp the morph made, again); "as imaged": key 1 as the morph shows it at key 0's landmark directions
against key 1's own image at its landmarks' directions (both interpolated: this one is limited by the
pixels, where the warp stretches a squeezed part of key 1's sphere). "Key 1's pixels": how evenly key 1's
image samples her surface, before the warp (her own grid) and after (the warped directions): the
area-weighted RMS of the log of each grid triangle's area on her mesh over the mean.
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.animation import morph
from geoimg.animation._morph import _grid_triangles, _landmark_warp, _octahedral_sampler
from geoimg.parametrization import grid_directions
from geoimg.surface._attributes import locate
from geoimg.mesh import suggest_landmarks
from geoimg.mesh._landmarks import SOURCES, _average_distance, _edge_graph
from scipy.sparse.csgraph import dijkstra
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


def joints(mesh: geoimg.Mesh, count: int) -> np.ndarray:
    """Landmarks as an animator might pick them on a figure: the extremities, the centre (least average
    geodesic distance), then the midpoints of the edge paths from the centre to each extremity (knees,
    elbows, neck), ``count`` in all.
    """
    g = _edge_graph(mesh)
    agd = _average_distance(mesh, g, SOURCES)
    ends = suggest_landmarks(mesh, count).tolist()
    centre = int(np.nanargmin(agd))
    _, pred = dijkstra(g, indices=centre, return_predecessors=True)
    middles = []
    for e in ends:
        path = [e]
        while path[-1] != centre:
            path.append(int(pred[path[-1]]))
        steps = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(mesh.vertices[path], axis=0), axis=1))])
        middles.append(path[int(np.argmin(np.abs(steps - 0.5 * steps[-1])))])
    return np.array((ends + [centre] + middles)[:count], np.int64)


def pixel_area_log_rms(mesh: geoimg.Mesh, coords: np.ndarray, directions: np.ndarray) -> float:
    """How evenly an octahedral image whose pixels sit at ``directions`` (n, n, 3) samples the mesh (sphere
    map ``coords``): the area-weighted RMS of the log of each grid triangle's area on the mesh over the mean.
    """
    n = directions.shape[0]
    tri = mesh.faces[:, :3]
    t, bary = locate(directions.reshape(-1, 3), coords[tri])
    x = np.einsum("pk,pkd->pd", bary, mesh.vertices[tri[t]])
    cells = _grid_triangles(n)
    area = 0.5 * np.linalg.norm(np.cross(x[cells[:, 1]] - x[cells[:, 0]], x[cells[:, 2]] - x[cells[:, 0]]), axis=1)
    keep = area > 0
    log = np.log(area[keep] / np.average(area[keep], weights=area[keep]))
    return float(np.sqrt(np.average(log ** 2, weights=area[keep])))


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
        print(
            f"man {man.n_vertices} vertices; remeshed woman {woman.n_vertices} ({own.method}, "
            f"{own.flipped_faces} folded faces); {args.res}² images\n"
        )
        before = pixel_area_log_rms(woman, own.coords, grid_directions(args.res))
        print("| alignment | RMS (% diag) | largest (% diag) | landmarks meet (% diag, largest) | as imaged "
              f"| key 1's pixels: area log-RMS (before: {before:.2f}) | seconds | warp |")
        print("|---|---:|---:|---:|---:|---:|---:|---|")
        runs = [("rigid turn of the sphere", None)] + [
            (f"{c} landmarks (spread)", suggest_landmarks(man, c, spread=True)) for c in args.counts
        ]
        runs += [(f"{c} landmarks (extremities, centre, joints)", joints(man, c)) for c in args.counts if 5 < c <= 11]
        for name, marks in runs:
            kw = {} if marks is None else {"landmarks": [(int(i), int(i)) for i in marks]}
            t = time.perf_counter()
            m = morph(man, woman, frames=2, resolution=args.res, align="none", **kw)
            dt = time.perf_counter() - t
            err = np.linalg.norm(sent(m, directions, args.res) - truth, axis=1) / diag * 100
            w = m.report[1].get("landmarks")
            warp = off = meet = after = ""
            if w is not None:
                warp = (f"met {w['met']}, residual {w['residual_rad']:.1e} rad, {w['folded']} folded, {w['steps']} "
                        f"steps, area log-RMS {w['area_log_rms']:.2f}")
                again = _landmark_warp(directions[marks], own.coords[marks], args.res, 1)
                sent_to = again["landmarks"]
                after = f"{pixel_area_log_rms(woman, own.coords, again['directions']):.2f}"
                tri = woman.faces[:, :3]
                t, bary = locate(sent_to, own.coords[tri])
                on_mesh = np.einsum("pk,pkd->pd", bary, woman.vertices[tri[t]])
                meet = f"{(np.linalg.norm(on_mesh - woman.vertices[marks], axis=1) / diag * 100).max():.4f}"
                shown = _octahedral_sampler(m.keys[1].pixels, m.keys[1].domain)(directions[marks])
                off = f"{(np.linalg.norm(shown - at_own(own.coords[marks]), axis=1) / diag * 100).max():.3f}"
            print(
                f"| {name} | {np.sqrt((err**2).mean()):.2f} | {err.max():.1f} | {meet} | {off} | {after} "
                f"| {dt:.1f} | {warp} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
