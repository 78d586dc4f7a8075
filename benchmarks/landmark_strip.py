"""The README's landmark-morph picture (issue 17): frames of two morphs from one camera, the rigid turn of the
sphere against landmarks, for Spot -> the Stanford bunny and human_man -> the armadillo (../shared/data).

    python benchmarks/landmark_strip.py [OUT.png] [--res 257]

Landmarks are picked by hand from `geoimg landmarks` suggestions (vertex indices below): Spot's horns, nose,
tail and front hooves onto the bunny's ears, nose, tail and front paws; the man's feet, hands and head onto
the armadillo's. Prints what the warps report and writes the picture (default docs/gallery/landmark_morph.png).
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path


import geoimg
from geoimg.animation import Renderer, morph

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "samples"))
from _common import caption, save, sheet  # noqa: E402
from make_gallery import shrink  # noqa: E402

SHARED = HERE.parents[1] / "shared" / "data" / "meshes" / "closed_genus0"
PAIRS = {
    "Spot -> bunny": ("spot.obj", "bunny.obj",
                      # horns -> ears, nose, tail, front hooves -> front paws
                      [(384, 3294), (2582, 3248), (64, 3055), (474, 129), (2204, 1707), (1075, 1971)], 120.0),
    "man -> armadillo": ("human_man.obj", "armadillo.obj",
                         # feet, hands, head
                         [(6615, 10077), (3218, 9912), (2445, 14523), (5906, 14583), (411, 12889)], 200.0),
}
TIMES = (0.0, 0.25, 0.5, 0.75, 1.0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("out", nargs="?", default=str(HERE.parent / "docs" / "gallery" / "landmark_morph.png"))
    ap.add_argument("--res", type=int, default=257)
    args = ap.parse_args(argv)
    rows = []
    with warnings.catch_warnings(), Renderer(260, 260) as r:
        warnings.simplefilter("ignore")
        for title, (a_name, b_name, pairs, azimuth) in PAIRS.items():
            a, b = geoimg.load_mesh(SHARED / a_name), geoimg.load_mesh(SHARED / b_name)
            for how, kw in (("rigid turn", {}), (f"{len(pairs)} landmarks", {"landmarks": pairs})):
                m = morph(a, b, frames=len(TIMES), resolution=args.res, **kw)
                w = m.report[1].get("landmarks")
                print(f"{title}, {how}: " + ("" if w is None else
                      f"met {w['met']}, residual {w['residual_rad']:.1e} rad, {w['folded']} folded, "
                      f"area log-RMS {w['area_log_rms']:.2f}"), flush=True)
                frames = [m.frame(t * (len(m.keys) - 1)).to_mesh() for t in TIMES]
                cam = r.camera_for(*frames, azimuth=azimuth, elevation=15.0, up="y")
                rows.append([caption(r.render(f, cam), f"{title}: {how}" if t == 0 else f"t = {t:g}")
                             for f, t in zip(frames, TIMES)])
    out = save(sheet(rows), Path(args.out))
    shrink(out, out, 900)                              # a small palette PNG, as the gallery's
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
