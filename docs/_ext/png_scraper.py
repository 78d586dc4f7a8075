"""The gallery's pictures: each sample script writes PNGs into the output folder given as its argument
(``reset_argv``); after each code block, the PNGs it wrote there are moved into the gallery.
"""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from sphinx_gallery.scrapers import figure_rst

_OUT: dict[str, Path] = {}          # script -> its output folder
_SEEN: dict[str, set[str]] = {}     # script -> pictures already shown


def argv(gallery_conf, script_vars) -> list[str]:
    """The script's arguments: a fresh output folder of its own."""
    out = Path(tempfile.mkdtemp(prefix="geoimg-gallery-"))
    _OUT[str(script_vars["src_file"])] = out
    return [str(out)]


def scrape(block, block_vars, gallery_conf, **kwargs) -> str:
    """The reST of the pictures the script wrote since the last block."""
    src = str(block_vars["src_file"])
    out = _OUT.get(src)
    if out is None:
        return ""
    seen = _SEEN.setdefault(src, set())
    shown = []
    for png in sorted(out.rglob("*.png")):
        if png.name in seen:
            continue
        seen.add(png.name)
        target = Path(next(block_vars["image_path_iterator"]))
        shutil.copyfile(png, target)
        shown.append(str(target))
    return figure_rst(shown, gallery_conf["src_dir"])
