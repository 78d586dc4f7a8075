"""Pictures of a corpus run's worst rows before and after a change: for the K converted rows of lowest PSNR
in the *before* manifest, the input, the before image's quad mesh and the after image's, shaded side by side
with their status and PSNR (issue 29's "worst five before and after").

    python benchmarks/corpus_strip.py BEFORE/manifest.csv AFTER/manifest.csv MODELS -o strip.png [--k 5]

Needs the ``bench`` extra (``pip install -e ".[bench]"``: matplotlib and the renderer).
"""
from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_corpus import render_outputs  # noqa: E402


def rows_of(manifest: Path, models: Path) -> dict:
    """The manifest's rows by input path relative to ``models``."""
    out = {}
    for r in csv.DictReader(open(manifest, newline="", encoding="utf-8")):
        out[str(Path(r["input"]).resolve().relative_to(models))] = r
    return out


def caption(tag: str, r: dict | None) -> str:
    """A picture's caption: the row's status, pieces, PSNR and Hausdorff distance."""
    if r is None:
        return f"{tag}: not run"
    if r["status"] in ("ok", "poor") and r["psnr_db"]:
        psnr, haus = float(r["psnr_db"]), float(r["hausdorff"]) * 100
        return f"{tag}: {r['status']}, {r['pieces']} piece(s), {psnr:.1f} dB, {haus:.1f} %"
    return f"{tag}: {r['status']}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("models", type=Path)
    ap.add_argument("-o", "--out", type=Path, required=True)
    ap.add_argument("--k", type=int, default=5)
    args = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    models = args.models.resolve()
    before, after = rows_of(args.before, models), rows_of(args.after, models)
    worst = sorted((k for k, r in before.items() if r["status"] in ("ok", "poor") and r["psnr_db"]),
                   key=lambda k: float(before[k]["psnr_db"]))[:args.k]
    fig, axes = plt.subplots(len(worst), 3, figsize=(12, 3.2 * len(worst)), squeeze=False)
    with tempfile.TemporaryDirectory() as tmp:
        for i, name in enumerate(worst):
            pngs = [Path(tmp) / f"{i}_{j}.png" for j in range(3)]
            subprocess.run([sys.executable, "-m", "geoimg", "render", str(models / name), "-o", str(pngs[0]), "--force",
                            "-q", "--width", "400", "--height", "300"], check=False)
            for j, r in ((1, before.get(name)), (2, after.get(name))):
                if r is not None and r["outputs"]:
                    render_outputs(r["outputs"], pngs[j])
            texts = [f"{name}: input", caption("before", before.get(name)), caption("after", after.get(name))]
            for j in range(3):
                ax = axes[i, j]
                if pngs[j].exists():
                    ax.imshow(plt.imread(pngs[j]))
                ax.set_axis_off()
                ax.set_title(texts[j], fontsize=9, loc="left")
        fig.tight_layout()
        fig.savefig(args.out, dpi=80)
    print("wrote", args.out, "with", ", ".join(worst))


if __name__ == "__main__":
    main()
