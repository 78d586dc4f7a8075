"""Run every sample at its default size and write the README's gallery: small palette PNGs in docs/gallery.

python samples/make_gallery.py            (about a minute and a half)
"""
from __future__ import annotations

import importlib
import sys
import tempfile
from pathlib import Path

from PIL import Image

HERE = Path(__file__).resolve().parent
GALLERY = HERE.parent / "docs" / "gallery"
SAMPLES = ["fig2_terrain", "fig3_small_meshes", "fig4_filtering", "fig5_morph", "fig9_multires",
           "partial_smoothing", "fig11_weights", "cut_open", "balanced_disk", "textured", "denoise"]
WIDTH = {"fig2_terrain": 420, "fig11_weights": 480}     # hillshades compress poorly: keep them small


def shrink(src: Path, dst: Path, width: int) -> int:
    img = Image.open(src).convert("RGB")
    if img.width > width:
        img = img.resize((width, round(img.height * width / img.width)), Image.LANCZOS)
    palette = img.quantize(colors=256, method=Image.Quantize.MEDIANCUT)     # 256 colours chosen for it,
    img.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG).save(dst, optimize=True)   # dithered
    return dst.stat().st_size


def main():
    sys.path.insert(0, str(HERE))
    GALLERY.mkdir(parents=True, exist_ok=True)
    total = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name in SAMPLES:
            stats = importlib.import_module(name).run(Path(tmp))
            size = shrink(Path(stats["png"]), GALLERY / f"{name}.png", WIDTH.get(name, 720))
            total += size
            print(f"{name}: {size / 1e3:.0f} kB")
    print(f"gallery: {total / 1e3:.0f} kB in {GALLERY}")


if __name__ == "__main__":
    main()
