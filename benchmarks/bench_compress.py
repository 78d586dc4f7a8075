"""Shapes compressed: geoimg's JPEG 2000 geometry images (``geoimg.compress``) against Google's Draco
(DracoPy, compression level 10) on the same meshes, both measured exactly against the mesh (two-sided RMS by
an AABB tree, 100,000 samples a side; PSNR = 20 log10(diagonal / RMS)).

    python benchmarks/bench_compress.py [--kb 2 4 8 16] [--json out.json] [--curve curve.png] [MESH ...]
    python benchmarks/bench_compress.py --stream MESH [--kb 1 2 4 8 16] [--picture stream.png]
    python benchmarks/bench_compress.py --bunny9k      # bunny.off decimated to 8,902 vertices, at 3,000 bytes
    python benchmarks/bench_compress.py --normals MESH [--kb 4 8 16]    # what coding the normals costs
    python benchmarks/bench_compress.py --weights-ab [MESH ...]     # offsets area-weighted or not, both ways

For each mesh: Draco at 8, 10 and 11 quantization bits (its size and PSNR); geoimg at Draco q8's size and at
each budget of ``--kb`` (resolution and rate chosen by ``compress``); the decoded quad mesh's boundary loops
and genus against the input's (closed in, closed out). ``--curve`` draws PSNR against bytes for both.

``--stream``: one file of the largest budget, and what its first k bytes decode to (``load_image(...,
max_bytes=k)``: the shape as far as its whole wavelet levels go) against a file compressed to k bytes;
``--picture`` renders both rows.

``--weights-ab``: each mesh at Draco q8's size and 10 % above it, compressed with a displaced file's offsets
coded as they are (before 2026-12-07: every weight 1) and area-weighted (now), in one process, alternating.
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

from _sheet import render_sheet          # noqa: E402  (benchmarks/, the script's own folder)

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
    return {"budget": budget, "bytes": c.nbytes, "resolution": c.resolution, "base": c.base,
            "psnr_db": round(float(surface_distance(mesh, quads, n=SAMPLES)["psnr_db"]), 2),
            "boundary_loops": int(topology(quads).boundary_loops), "genus": int(topology(quads).genus),
            "seconds": round(time.perf_counter() - t0, 1)}


def where(row: dict) -> str:
    """A file's resolution, and its base's where it is displaced: ``257²`` or ``257² on 65²``."""
    if "resolution" not in row:
        return "refused"
    return f"{row['resolution']}²" + (f" on {row['base']}²" if row.get("base") else "")


def stream(path: Path, kbs: list[float], picture: Path | None) -> None:
    """The first k bytes of one file against a file of k bytes, for each k of ``kbs`` (the file: the largest)."""
    import tempfile
    mesh = geoimg.load_mesh(path)
    whole = geoimg.compress(mesh, max_bytes=int(max(kbs) * 1000))
    file = Path(tempfile.mkdtemp()) / "stream.jp2"
    file.write_bytes(whole.data)
    print(f"{path.name}: one file of {whole.nbytes} bytes, "
          f"{where({'resolution': whole.resolution, 'base': whole.base})}")
    print("| first k bytes | wavelet levels held | PSNR (dB) | a file of k bytes: PSNR (dB), resolution |")
    print("|---:|---|---:|---|")
    first, alone = [], []
    for kb in kbs:
        k = int(kb * 1000)
        part = geoimg.load_image(file, max_bytes=k)
        own = geoimg.compress(mesh, max_bytes=k)
        p1 = surface_distance(mesh, part.to_mesh(), n=SAMPLES)["psnr_db"]
        p2 = surface_distance(mesh, own.image.to_mesh(), n=SAMPLES)["psnr_db"]
        held = part.metadata.get("jpeg2000_levels", "all")
        if "jpeg2000_offset_levels" in part.metadata:      # a displaced file: the base's levels, then the offsets'
            held = f"base {held}, offsets {part.metadata['jpeg2000_offset_levels']}"
        elif whole.base:
            held = "base all, offsets all"
        print(f"| {k} | {held} | {p1:.1f} | {p2:.1f} ({where({'resolution': own.resolution, 'base': own.base})}) |",
              flush=True)
        first.append((f"first {kb:g} KB of one file: {p1:.1f} dB", part))
        alone.append((f"a {kb:g} KB file: {p2:.1f} dB", own.image))
    if picture:
        render_sheet([first, alone], mesh, picture, size=300)
        print(f"wrote {picture}")


def normals_cost(path: Path, kbs: list[float]) -> None:
    """Shape alone (normals from the decoded grid) against shape and coded normals, at each budget: PSNR and
    the mean angle to the surface's exact normals at the image's pixels.
    """
    mesh = geoimg.load_mesh(path)
    exact: dict = {}
    print("| budget | shape only: PSNR, grid normals | with --normals: PSNR, coded normals |\n|---|---|---|")
    for kb in kbs:
        cells = []
        for coded in (False, True):
            c = geoimg.compress(mesh, max_bytes=int(kb * 1000), normals=coded)
            psnr = surface_distance(mesh, c.image.to_mesh(), n=SAMPLES)["psnr_db"]
            ref = exact.setdefault(c.resolution, geoimg.mesh_to_image(mesh, c.resolution, fidelity=False).normals)
            got = c.image.normals if coded else geoimg.grid_normals(c.image.pixels, c.image.domain.orientation)
            angle = float(np.degrees(np.arccos(np.clip((got * ref).sum(-1), -1, 1))).mean())
            cells.append(f"{psnr:.1f} dB ({c.resolution}²), {angle:.2f}°")
        print(f"| {kb:g} KB | " + " | ".join(cells) + " |", flush=True)


def curve(rows: list[dict], out: Path) -> None:
    """PSNR against bytes, geoimg's budgets and Draco's bit depths, one panel per mesh."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = min(4, len(rows))
    nrows = -(-len(rows) // cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(3.4 * cols, 3.0 * nrows), sharey=True, squeeze=False)
    ticks = [1000, 2000, 4000, 8000, 16000, 32000]
    for ax, row in zip(axes.ravel(), rows):
        ours_ = sorted((b["bytes"], b["psnr_db"]) for b in row["geoimg"] + [row["geoimg_at_q8"]] if "bytes" in b)
        drc = sorted((d["bytes"], d["psnr_db"]) for d in row["draco"].values())
        ax.plot(*zip(*ours_), "o-", label="geoimg (JPEG 2000)")
        ax.plot(*zip(*drc), "s--", label="Draco q8, q10, q11")
        ax.set_xscale("log")
        ax.set_xticks(ticks, [f"{t // 1000}K" for t in ticks])
        ax.minorticks_off()
        ax.set_xlim(900, 50000)
        ax.set_title(f"{row['mesh']} ({row['vertices']} vertices)", fontsize=9)
        ax.set_xlabel("bytes")
        ax.grid(alpha=0.3)
    for ax in axes.ravel()[len(rows):]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel("PSNR (dB)")
    axes[0, 0].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


def weights_ab(paths: list[Path]) -> None:
    """Each mesh at Draco q8's size and 10 % above it, its offsets unweighted (before) and area-weighted (now)."""
    import geoimg._compress as compressing
    import geoimg.image._jp2 as jp2

    def unweighted(points, domain):
        return np.ones(np.shape(points)[:2])

    weighted = jp2.area_weights
    print("| mesh | before, q8's size | now | gain | before, 10 % more | now | gain |\n|---|---|---|---:|---|---|---:|")
    for path in paths:
        mesh = geoimg.load_mesh(path)
        q8 = draco(mesh, 8)[0]
        cells = []
        for budget in (q8, int(1.1 * q8)):
            got = []
            for weights in (unweighted, weighted):
                compressing.area_weights = jp2.area_weights = weights     # the writer's and the reader's alike
                got.append(ours(mesh, budget))
            compressing.area_weights = jp2.area_weights = weighted
            cells += [f"{g['bytes']} B {g['psnr_db']} ({where(g)})" for g in got]
            cells.append(f"{got[1]['psnr_db'] - got[0]['psnr_db']:+.2f}")
        print(f"| {path.name} | " + " | ".join(cells) + " |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--kb", nargs="*", type=float, default=None)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--curve", type=Path, default=None, help="draw PSNR against bytes to this PNG")
    ap.add_argument("--from-json", type=Path, default=None, help="draw --curve from an earlier run's --json")
    ap.add_argument("--stream", type=Path, default=None, help="one mesh: what the first bytes of a file give")
    ap.add_argument("--picture", type=Path, default=None, help="with --stream: render the shapes to this PNG")
    ap.add_argument("--bunny9k", action="store_true", help="a 9k-vertex bunny (bunny.off decimated) at 3,000 B")
    ap.add_argument("--normals", type=Path, default=None, help="one mesh: what coding its normals costs")
    ap.add_argument("--weights-ab", action="store_true", help="the offsets area-weighted against unweighted")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    if args.bunny9k:
        import igl
        full = geoimg.load_mesh(SHARED / "closed_genus0" / "bunny.off")
        out = igl.decimate(full.vertices, full.triangulate()[0], 17800)
        mesh = geoimg.Mesh(out[0], out[1])           # V, F, then the kept faces and vertices
        print(f"bunny.off decimated to {mesh.n_vertices} vertices, {mesh.n_faces} faces:", ours(mesh, 3000))
        return
    if args.stream:
        stream(args.stream, args.kb or [1, 2, 4, 8, 16], args.picture)
        return
    if args.normals:
        normals_cost(args.normals, args.kb or [4, 8, 16])
        return
    if args.weights_ab:
        weights_ab(args.meshes or default_meshes())
        return
    if args.from_json:
        curve(json.loads(args.from_json.read_text()), args.curve or Path("compress_curve.png"))
        return
    args.kb = args.kb or [2, 4, 8, 16]
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
        cells = [f"{b['bytes']} B {b['psnr_db']} ({where(b)})" if "bytes" in b else "too small" for b in budgets]
        row = {"mesh": path.name, "vertices": mesh.n_vertices, "topology": top.describe(),
               "draco": {b: {"bytes": s, "psnr_db": round(p, 2)} for b, (s, p) in d.items()},
               "geoimg_at_q8": at_q8, "geoimg": budgets}
        rows.append(row)
        gain = at_q8.get("psnr_db", float("nan")) - d[8][1]
        print(f"| {path.name} | {mesh.n_vertices} | {'closed' if top.closed else 'open'}, genus {top.genus} | "
              + " | ".join(f"{s} B {p:.1f}" for s, p in d.values())
              + f" | {at_q8.get('bytes')} B {at_q8.get('psnr_db')} ({gain:+.1f}; {where(at_q8)}) | " + " | ".join(cells)
              + f" | {top.boundary_loops}, {top.genus} -> {at_q8.get('boundary_loops')}, {at_q8.get('genus')} |",
              flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    if args.curve:
        curve(rows, args.curve)


if __name__ == "__main__":
    main()
