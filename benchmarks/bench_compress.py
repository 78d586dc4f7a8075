"""Shapes compressed: geoimg's JPEG 2000 geometry images (``geoimg.compress``) against Google's Draco
(DracoPy, compression level 10) on the same meshes, both measured exactly against the mesh (two-sided RMS by
an AABB tree, 100,000 samples a side; PSNR = 20 log10(diagonal / RMS)).

    python benchmarks/bench_compress.py [--kb 2 4 8 16] [--json out.json] [MESH ...]

For each mesh: Draco at 8, 10 and 11 quantization bits (its size and PSNR); geoimg at Draco q8's size and at
each budget of ``--kb`` (resolution and rate chosen by ``compress``); the decoded quad mesh's boundary loops
and genus against the input's (closed in, closed out).
"""
from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import geoimg
from geoimg.mesh import surface_distance, topology

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
SAMPLES = 100_000


def default_meshes() -> list[Path]:
    names = [SHARED / "closed_genus0" / "bunny.obj", SHARED / "closed_genus0" / "bunny.off",
             ROOT / "tests" / "data" / "spot.obj",
             SHARED / "closed_genus0" / "armadillo.obj", SHARED / "open_disk" / "camelhead.off",
             SHARED / "open_disk" / "hemisphere.off", ROOT / "tests" / "data" / "bob_tri.obj"]
    return [p for p in names if p.exists()]


def draco(mesh: geoimg.Mesh, bits: int) -> tuple[int, float]:
    import DracoPy
    tri = mesh.triangulate()[0]
    data = DracoPy.encode(np.asarray(mesh.vertices, np.float32), tri.astype(np.uint32), quantization_bits=bits,
                          compression_level=10)
    back = DracoPy.decode(data)
    faces = np.asarray(back.faces).reshape(-1, 3)
    decoded = geoimg.Mesh(np.asarray(back.points, np.float64).reshape(-1, 3), faces)
    return len(data), float(surface_distance(mesh, decoded, n=SAMPLES)["psnr_db"])


def ours(mesh: geoimg.Mesh, budget: int) -> dict:
    t0 = time.perf_counter()
    try:
        c = geoimg.compress(mesh, max_bytes=budget)
    except geoimg.GeoimgError as e:
        return {"budget": budget, "refused": str(e)}
    quads = c.image.to_mesh()
    return {"budget": budget, "bytes": c.nbytes, "resolution": c.resolution,
            "psnr_db": round(float(surface_distance(mesh, quads, n=SAMPLES)["psnr_db"]), 2),
            "boundary_loops": int(topology(quads).boundary_loops), "genus": int(topology(quads).genus),
            "seconds": round(time.perf_counter() - t0, 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--kb", nargs="*", type=float, default=[2, 4, 8, 16])
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    rows = []
    print("| mesh | V | topology | Draco q8 | q10 | q11 | geoimg at q8's size | " +
          " | ".join(f"geoimg {kb:g} KB" for kb in args.kb) + " | boundary loops, genus: in -> out |")
    print("|---" * (8 + len(args.kb)) + "|")
    for path in args.meshes or default_meshes():
        mesh = geoimg.load_mesh(path)
        top = topology(mesh)
        d = {bits: draco(mesh, bits) for bits in (8, 10, 11)}
        at_q8 = ours(mesh, d[8][0])
        budgets = [ours(mesh, int(kb * 1000)) for kb in args.kb]
        cells = [f"{b['bytes']} B {b['psnr_db']} ({b['resolution']}²)" if "bytes" in b else "too small"
                 for b in budgets]
        row = {"mesh": path.name, "vertices": mesh.n_vertices, "topology": top.describe(),
               "draco": {b: {"bytes": s, "psnr_db": round(p, 2)} for b, (s, p) in d.items()},
               "geoimg_at_q8": at_q8, "geoimg": budgets}
        rows.append(row)
        gain = at_q8.get("psnr_db", float("nan")) - d[8][1]
        print(f"| {path.name} | {mesh.n_vertices} | {'closed' if top.closed else 'open'}, genus {top.genus} | "
              + " | ".join(f"{s} B {p:.1f}" for s, p in d.values())
              + f" | {at_q8.get('bytes')} B {at_q8.get('psnr_db')} ({gain:+.1f}) | " + " | ".join(cells)
              + f" | {top.boundary_loops}, {top.genus} -> {at_q8.get('boundary_loops')}, {at_q8.get('genus')} |",
              flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
