"""Real-world files (issue 32): every mesh file of a folder through ``geoimg batch`` as a new user would run it,
and the table the issue asks for (file, status, pieces, PSNR, Hausdorff, seconds), with the counts, the median
PSNR of converted rows and the wall time.

The corpus is the trimesh project's test models (MIT; ``models/`` of https://github.com/mikedh/trimesh, 116
OBJ, PLY, STL, GLB, glTF and OFF files with their materials, textures and buffers); it is not bundled:

    git clone --depth 1 https://github.com/mikedh/trimesh /tmp/trimesh
    python benchmarks/bench_corpus.py /tmp/trimesh/models --out /tmp/corpus [--res 129] [--workers 2]

The batch's own manifest is read back for the table (``--manifest`` reads an earlier run's instead, to
tabulate it without converting; ``--before`` adds a table of an earlier run's manifest beside it). ``--renders K``
shades the quad meshes of the K worst converted rows to PNG
beside the table (needs the ``render`` extra).
"""
from __future__ import annotations

import argparse
import csv
import statistics
import subprocess
import sys
import time
from pathlib import Path


def run_batch(models: Path, out: Path, res: int, workers: int) -> float:
    """``geoimg batch models -o out --res res --quads --workers workers --force``; its wall time."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "geoimg", "batch", str(models), "-o", str(out), "--res", str(res),
                    "--quads", "--workers", str(workers), "--force", "--quiet"], check=False)
    return time.perf_counter() - t0


def table(manifest: Path, root: Path | None) -> tuple[list[str], dict]:
    """Markdown rows of the manifest, and its summary."""
    rows = list(csv.DictReader(open(manifest, newline="", encoding="utf-8")))
    lines = ["| file | status | pieces | domain | PSNR (dB) | Hausdorff (% diag) | seconds | note |",
             "|---|---|---:|---|---:|---:|---:|---|"]
    for r in rows:
        name = r["input"]
        if root is not None and name.startswith(str(root)):
            name = name[len(str(root)):].lstrip("/")
        haus = f"{100 * float(r['hausdorff']):.2f}" if r["hausdorff"] else ""
        domains = sorted(set(r["domain"].split()))
        note = r["message"] if r["status"] != "ok" else ""
        seconds = f"{float(r['t_total']):.1f}" if r["t_total"] else ""      # a killed worker's row has none
        note = note.replace("|", "/")
        lines.append(f"| {name} | {r['status']} | {r['pieces']} | {' '.join(domains)} | {r['psnr_db']} | {haus} | "
                     f"{seconds} | {note[:110]} |")
    converted = [float(r["psnr_db"]) for r in rows if r["status"] in ("ok", "poor") and r["psnr_db"]]
    summary = {s: sum(r["status"] == s for r in rows) for s in ("ok", "poor", "refused", "failed")}
    summary.update(inputs=len(rows), median_psnr=statistics.median(converted) if converted else None,
                   under_40=sum(p < 40 for p in converted), under_45=sum(p < 45 for p in converted))
    return lines, summary


def comparison(before: Path, after: Path, root: Path) -> list[str]:
    """Markdown rows of two manifests side by side, by input path below ``root`` (an input one run did not
    find, a .gltf before it was read, shows as 'not found').
    """
    def rows(path):
        return {r["input"][len(str(root)):].lstrip("/") if r["input"].startswith(str(root)) else r["input"]: r
                for r in csv.DictReader(open(path, newline="", encoding="utf-8"))}
    b, a = rows(before), rows(after)
    lines = ["| file | before | pieces | PSNR | after | pieces | domain | PSNR (dB) | Hausdorff (%) | s |",
             "|---|---|---:|---:|---|---:|---|---:|---:|---:|"]
    for name in sorted(set(a) | set(b), key=str.lower):
        x, y = b.get(name), a.get(name)
        left = f"{x['status']} | {x['pieces']} | {x['psnr_db']}" if x else "not found | | "
        if y:
            haus = f"{100 * float(y['hausdorff']):.2f}" if y["hausdorff"] else ""
            secs = f"{float(y['t_total']):.1f}" if y["t_total"] else ""
            right = (f"{y['status']} | {y['pieces']} | {' '.join(sorted(set(y['domain'].split())))} | "
                     f"{y['psnr_db']} | {haus} | {secs}")
        else:
            right = "not found | | | | |"
        lines.append(f"| {name} | {left} | {right} |")
    return lines


def render_outputs(outputs: str, png: Path) -> bool:
    """Shade every piece's quad mesh of one manifest row (its ``outputs`` cell) together into ``png``."""
    import tempfile
    import warnings

    import geoimg
    from geoimg.batch._task import _joined
    quads = [q for q in outputs.split(";") if "_quads." in q and Path(q).suffix in (".obj", ".ply", ".off")]
    if not quads:
        return False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        joined = _joined([geoimg.load_mesh(q, weld=False) for q in quads])
        with tempfile.TemporaryDirectory() as tmp:
            geoimg.save_mesh(joined, Path(tmp) / "joined.ply")
            subprocess.run([sys.executable, "-m", "geoimg", "render", str(Path(tmp) / "joined.ply"), "-o", str(png),
                            "--force", "-q", "--width", "400", "--height", "300"], check=False)
    return png.exists()


def render_worst(manifest: Path, out: Path, k: int) -> list[Path]:
    """Shade the quad meshes of the ``k`` converted rows of lowest PSNR, each to ``out/worst_NAME.png``."""
    rows = [r for r in csv.DictReader(open(manifest, newline="", encoding="utf-8"))
            if r["status"] in ("ok", "poor") and r["psnr_db"]]
    rows.sort(key=lambda r: float(r["psnr_db"]))
    made = []
    for r in rows[:k]:
        png = out / f"worst_{Path(r['input']).name.replace('.', '_')}.png"
        if render_outputs(r["outputs"], png):
            made.append(png)
    return made


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", type=Path, help="the folder of mesh files (trimesh's models/)")
    ap.add_argument("--out", type=Path, default=Path("corpus-out"))
    ap.add_argument("--res", type=int, default=129)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--manifest", type=Path, help="tabulate this manifest instead of running the batch")
    ap.add_argument("--renders", type=int, default=0)
    ap.add_argument("--before", type=Path, help="an earlier run's manifest: print both side by side")
    args = ap.parse_args()
    wall = None
    manifest = args.manifest
    if manifest is None:
        wall = run_batch(args.models, args.out, args.res, args.workers)
        manifest = args.out / "manifest.csv"
    lines, summary = table(manifest, args.models.resolve())
    print("\n".join(lines))
    print()
    print(f"{summary['inputs']} inputs: {summary['ok']} ok, {summary['poor']} poor, {summary['refused']} refused, "
          f"{summary['failed']} failed; median PSNR of converted rows {summary['median_psnr']:.2f} dB, "
          f"{summary['under_40']} under 40 dB, {summary['under_45']} under 45 dB"
          + (f"; wall time {wall:.0f} s" if wall is not None else ""))
    if args.before is not None:
        print()
        print("\n".join(comparison(args.before, manifest, args.models.resolve())))
    if args.renders:
        for png in render_worst(manifest, args.out, args.renders):
            print("rendered", png)


if __name__ == "__main__":
    main()
