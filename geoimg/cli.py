"""The ``geoimg`` command line: ``image``, ``mesh``, ``filter``, ``curvature``, ``render``, ``morph``, ``batch``,
``landmarks``, ``harmonics``, ``info`` and ``demo``. The parser needs only the option vocabularies
(:mod:`geoimg._choices`); the commands themselves are in :mod:`geoimg._commands`, imported when one runs.
"""
from __future__ import annotations

import argparse
import difflib
import os
import signal
import sys
import threading
import warnings
from dataclasses import dataclass, field
from typing import Any

from filters.padding import PAD_MODES

from . import __version__
from ._atomic import OutputExists
from ._choices import (
    ALIGNMENTS,
    ASSUMABLE_DOMAINS,
    AXES,
    BACKENDS,
    DEFAULT_CURVATURE_SCALE,
    DEFAULT_DISK_BALANCE,
    DISK_BALANCES,
    DISK_BOUNDARIES,
    EASINGS,
    EXR_LAYOUTS,
    FILTER_STEPS,
    FRAME_FORMATS,
    IMAGE_FORMATS,
    MESH_READ_FORMATS,
    POOR_HAUSDORFF,
    POOR_PSNR_DB,
    PARAMETRIZATION_METHODS,
    QUAD_FORMATS,
    SLIVER_RULES,
    UP_AXES,
    WEIGHTS,
)
from .errors import GeoimgError


_IMAGES = ", ".join(f for f in IMAGE_FORMATS if f != ".tiff")


class _Op(argparse.Action):
    """Collects filter options in the order they are given."""

    def __call__(self, parser, namespace, values, option_string=None):
        kinds = FILTER_STEPS[self.dest][1]
        values = values if isinstance(values, list) else [values]
        try:
            parsed = [k(v) for k, v in zip(kinds, values)]
        except ValueError:
            parser.error(f"{option_string}: expected {' '.join(k.__name__ for k in kinds)}, got {' '.join(values)}")
        ops = list(getattr(namespace, "ops", None) or [])
        ops.append((self.dest, parsed))
        namespace.ops = ops


def _positive(kind):
    def check(text):
        try:
            value = kind(text)
        except ValueError:           # argparse would say "invalid check value": the function's name
            value = None
        if value is None or not value > 0:
            raise argparse.ArgumentTypeError(f"expected a positive number, got {text}")
        return value
    return check


EXAMPLES = {
    "image": [
        "geoimg image terrain.obj -o terrain.exr --res 257 --s 2 --preview terrain.png",
        "geoimg image spot.obj -o spot.exr --res 257          # closed: an octahedral image, colours kept",
        "geoimg image scan.ply -o scan.npz --res 513 --no-colors",
    ],
    "mesh": [
        "geoimg mesh terrain.exr -o terrain_quads.obj",
        "geoimg mesh spot.exr -o spot.glb   # with its texture",
        "geoimg mesh other.exr -o q.ply --assume planar",
        "geoimg mesh bunny.jp2 -o coarse.obj --bytes 2000   # the first 2 KB of a compressed shape",
    ],
    "filter": [
        "geoimg filter terrain.exr -o smooth.exr --mean 5 --sharpen 3",
        "geoimg filter scan.exr -o clean.exr --median 3 --nlmeans 0.002 --mesh clean.obj",
        "geoimg filter spot.exr -o head.exr --gaussian 3 --region 0.1 0.4 0.5 0.2 --feather 8",
    ],
    "curvature": ["geoimg curvature terrain.exr -o terrain_curv"],
    "render": [
        "geoimg render spot.exr -o spot.png --azimuth 60",
        "geoimg render terrain.exr -o terrain.png --elevation 35 --transparent",
    ],
    "morph": [
        "geoimg morph spot.obj bunny.obj --frames 30 -o morph.glb --gif morph.gif",
        "geoimg morph spot.obj bunny.obj --landmarks pairs.csv -o morph.glb   # features meet",
        "geoimg morph a.exr b.exr c.exr --frames-dir frames --frame-format ply",
    ],
    "batch": [
        "geoimg batch meshes/ -o out --res 257 --quads",
        "geoimg batch 'scans/*.ply' -o out --res 129 --zarr data.zarr",
    ],
    "info": ["geoimg info spot.exr", "geoimg info scan.ply"],
    "harmonics": [
        "geoimg harmonics spot.obj --lmax 32 -o spot_sh.npz --mesh spot_l32.obj",
        "geoimg harmonics spot.exr --lmax 16 -o sh.npz --image spot_l16.exr --res 257",
    ],
    "compress": [
        "geoimg compress bunny.obj -o bunny.jp2 --bytes 4000      # the least error in 4,000 bytes",
        "geoimg compress spot.obj -o spot.jp2 --psnr 65 --res 129 257   # the fewest bytes for 65 dB",
    ],
    "landmarks": [
        "geoimg landmarks spot.obj -o spot_points.csv --picture spot_points.png",
        "geoimg landmarks armadillo.obj -o points.csv --count 12 --azimuth 180",
        "geoimg landmarks human.obj -o points.csv --count 10 --spread   # extremities, then spread",
    ],
    "demo": ["geoimg demo", "geoimg demo -o here --res 129"],
}


class _Parser(argparse.ArgumentParser):
    """argparse's parser, its errors one line (as every error of geoimg's), not the usage and then the line;
    the subcommands' parsers are of the same class.
    """

    commands: Any = None    # on the top-level parser: the subcommands (an unknown option is theirs to explain)

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    def parse_args(self, args=None, namespace=None):  # type: ignore[override]
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            command = self.commands.choices.get(getattr(parsed, "command", None), self) if self.commands else self
            known = [o for action in command._actions for o in action.option_strings]
            close = difflib.get_close_matches(extras[0].split("=")[0], known, n=1)
            hint = f"; did you mean {close[0]}?" if close and extras[0].startswith("-") else ""
            command.error(f"unrecognized arguments: {' '.join(extras)}{hint}")
        return parsed


def arg(*flags: str, **options: Any) -> tuple:
    """One argument of a command, as :meth:`argparse.ArgumentParser.add_argument` takes it."""
    return flags, options


# Arguments that several commands share (argparse's parents).
GROUPS: dict[str, list] = {
    "common": [
        arg("--quiet", "-q", action="store_true", help="print nothing but errors"),
        arg(
            "--progress",
            action="store_true",
            help="show progress off a terminal too (logs, CI); on a terminal it is always shown",
        ),
    ],
    "conversion": [
        arg("--res", type=_positive(int), default=None, help="pixels along the longer side (default: from s)"),
        arg(
            "--s",
            type=_positive(float),
            default=None,
            help="smoothness s: the weights' width over the mean face size (sigma = s d); default: "
            "the width that serves --res, 0.4 of a pixel (a prefilter for the grid, not a "
            "smoothing: the image as close to the mesh as its resolution allows); 1 with "
            "--weights gaussian or local",
        ),
        arg("--method", choices=PARAMETRIZATION_METHODS, default="auto", help="parametrization (default auto)"),
        arg("--axis", choices=AXES, default=None, help="up axis of a height field"),
        arg(
            "--boundary",
            choices=DISK_BOUNDARIES,
            default="square",
            help="disk meshes: boundary on the unit square (default) or kept (a convex planar outline)",
        ),
        arg(
            "--balance",
            choices=DISK_BALANCES,
            default=DEFAULT_DISK_BALANCE,
            help="disk and cut-open meshes: balance the mean-value map's area, a disk's boundary "
            "sliding along the square's sides (default area), relax it with SLIM, the boundary "
            "held (slim), or keep it (none); either balancing opens up squeezed parts",
        ),
        arg(
            "--weights",
            choices=WEIGHTS,
            default="coverage",
            help="the weight of each face: the share of a Gaussian footprint it covers (default "
            "coverage: the surface tends to the mesh as s falls), the paper's rational "
            "Gaussian of the distance to its centre (gaussian), or local (its n nearest face "
            "centres)",
        ),
        arg("--n", type=int, default=10, help="face centres per local weight (--weights local; default 10)"),
        arg("--tol", type=float, default=1e-10, help="truncation tolerance; 0 = exact sum (default 1e-10)"),
        arg(
            "--sliver-rule",
            choices=SLIVER_RULES,
            default="robust",
            help="long thin faces: a smaller Gaussian and the plane of their neighbours (default "
            "robust), or the paper's enclosing circle (paper)",
        ),
        arg(
            "--component",
            default=None,
            metavar="all|largest|K",
            help="a mesh of several pieces gives NAME_0.exr, NAME_1.exr, ... (largest first; "
            "the default, all), or keep one (the default with --zarr: largest)",
        ),
        arg(
            "--no-colors",
            action="store_true",
            help="leave out the mesh's colours (an OBJ's texture, PLY or OBJ vertex colours), which "
            "are resampled into the image by default",
        ),
    ],
    "steps": [
        *(
            arg(
                f"--{name}",
                dest=name,
                action=_Op,
                nargs=len(kinds) if len(kinds) > 1 else None,
                metavar=metavar,
                help=text,
            )
            for name, (_, kinds, metavar, text) in FILTER_STEPS.items()
        ),
        arg(
            "--nsr",
            type=_positive(float),
            default=1e-3,
            help="Wiener noise-to-signal ratio of --sharpen (default 0.001)",
        ),
        arg(
            "--mode",
            choices=PAD_MODES,
            default=None,
            help="boundary rule (default: octahedral for spherical images, reflect for planar ones)",
        ),
    ],
    "reading": [
        arg(
            "--assume",
            choices=ASSUMABLE_DOMAINS,
            default=None,
            help="read an image without geoimg metadata (from another program) as this domain (default: refuse it)",
        ),
        arg(
            "--approximate",
            action="store_true",
            help="read a 16-bit PNG preview written by geoimg as geometry, to within half of its "
            "1/65534 steps (default: refuse it)",
        ),
    ],
    "writing": [
        arg(
            "--layout",
            choices=EXR_LAYOUTS,
            default="geoimg",
            help="EXR channels: R, G, B, mask, N.X, N.Y, N.Z (geoimg, the default) or the mask as A "
            "(rgba: alpha for compositing tools)",
        ),
    ],
    "view": [
        arg("--width", type=_positive(int), default=800, help="picture width in pixels (default 800)"),
        arg("--height", type=_positive(int), default=600, help="picture height in pixels (default 600)"),
        arg("--azimuth", type=float, default=30.0, help="degrees about the up axis (default 30)"),
        arg("--elevation", type=float, default=20.0, help="degrees above the horizon (default 20)"),
        arg(
            "--up",
            choices=UP_AXES,
            default=None,
            help="the shape's up axis (default: the one a geometry image records, a terrain's; else y)",
        ),
    ],
}


@dataclass(frozen=True)
class Command:
    """A command's declaration: its one-line help, the shared groups it takes, its own arguments, and its
    description and defaults; :func:`build_parser` makes its parser from this, with :data:`EXAMPLES` below.
    """

    help: str
    groups: tuple[str, ...]
    args: list
    description: str | None = None
    defaults: dict = field(default_factory=dict)


COMMANDS: dict[str, Command] = {
    "image": Command(
        "mesh -> geometry image (OpenEXR)",
        ("common", "conversion", "writing"),
        [
            arg("mesh", help=f"input mesh ({', '.join(MESH_READ_FORMATS)})"),
            arg(
                "-o",
                "--output",
                required=True,
                help=f"output geometry image ({_IMAGES}: OpenEXR, NumPy arrays, float TIFF, one NumPy array)",
            ),
            arg("--preview", default=None, help="also write a 16-bit PNG preview"),
            arg("--force", action="store_true", help="overwrite existing files"),
            arg(
                "--backend",
                choices=BACKENDS,
                default="cpu",
                help="where planar images' Gaussian sums run: the CPU's cores (default) or a CUDA GPU "
                "through numba.cuda (cuda)",
            ),
        ],
    ),
    "mesh": Command(
        "geometry image -> quad mesh",
        ("common", "reading"),
        [
            arg("image", help=f"input geometry image ({_IMAGES})"),
            arg("-o", "--output", required=True, help="output mesh (.obj/.ply/.off keep quads)"),
            arg("--force", action="store_true", help="overwrite an existing file"),
            arg("--bytes", type=_positive(int), default=None, metavar="K",
                help="a .jp2 from geoimg compress: decode only its first K bytes, the shape as far as they go "
                     "(what a viewer streaming the file shows)"),
        ],
    ),
    "filter": Command(
        "smooth, sharpen or Fourier-filter a geometry image",
        ("common", "steps", "reading", "writing"),
        [
            arg("image", help=f"input geometry image ({_IMAGES})"),
            arg("-o", "--output", required=True, help=f"output geometry image ({_IMAGES})"),
            arg("--mask", default=None, help="image file (same size): where to filter, 0..1"),
            arg(
                "--region",
                type=float,
                nargs=4,
                metavar=("X", "Y", "Z", "R"),
                default=None,
                help="filter within distance R of the point (X, Y, Z) of the surface",
            ),
            arg(
                "--uv-region",
                type=float,
                nargs=3,
                metavar=("U", "V", "R"),
                default=None,
                help="filter within the disk of radius R around (U, V) of the image, in [0, 1]",
            ),
            arg("--feather", type=float, default=4.0, help="mask transition width in pixels (default 4)"),
            arg("--preview", default=None, help="also write a 16-bit PNG preview"),
            arg("--mesh", default=None, help="also write the quad mesh"),
            arg("--force", action="store_true", help="overwrite existing files"),
        ],
        description="Operations run in the order given; a mask restricts every one of them.",
        defaults=dict(ops=None),
    ),
    "curvature": Command(
        "Gaussian and mean curvature maps and a normal map of a geometry image",
        ("common", "reading"),
        [
            arg("image", help=f"input geometry image ({_IMAGES})"),
            arg(
                "-o",
                "--output",
                required=True,
                help="output stem: writes STEM_gaussian.exr/.png, STEM_mean.exr/.png, STEM_normals.png "
                "(a folder: the input's name in it)",
            ),
            arg(
                "--scale",
                type=float,
                default=DEFAULT_CURVATURE_SCALE,
                metavar="FRACTION",
                help="smooth the surface by a Gaussian of this share of the bounding-box diagonal first, so that "
                "the maps show features of that size, not the mesh's facets "
                f"(default {DEFAULT_CURVATURE_SCALE:g}; 0: the grid as it is)",
            ),
            arg("--force", action="store_true", help="overwrite existing files"),
        ],
    ),
    "render": Command(
        "shade a mesh or geometry image to PNG (headless)",
        ("common", "view", "reading"),
        [
            arg("file", help=f"mesh or geometry image ({_IMAGES})"),
            arg("-o", "--output", required=True, help="output .png"),
            arg("--force", action="store_true", help="overwrite an existing file"),
            arg(
                "--transparent",
                action="store_true",
                help="a transparent background (an RGBA PNG) instead of white (default: white)",
            ),
        ],
    ),
    "morph": Command(
        "morph between shapes: glTF with morph targets, GIF/MP4, frame files",
        ("common", "view", "reading"),
        [
            arg("shapes", nargs="+", help=f"two or more meshes or geometry images ({_IMAGES}), in order"),
            arg("-o", "--output", default=None, help="output .glb (morph targets + weights animation)"),
            arg("--frames", type=int, default=30, help="frames in all (default 30)"),
            arg("--fps", type=_positive(float), default=24.0, help="frames per second (default 24)"),
            arg(
                "--easing",
                default="smoothstep",
                choices=tuple(EASINGS),
                help="how the blend moves between keys (default smoothstep)",
            ),
            arg(
                "--align",
                choices=ALIGNMENTS,
                default="similarity",
                help="bring shapes 2.. onto shape 1: centre, centre and scale (similarity, the default), or none",
            ),
            arg("--no-rotate", action="store_true", help="spherical images: keep the spheres as they are"),
            arg(
                "--landmarks",
                default=None,
                metavar="CSV",
                help="corresponding features: a row per feature, a vertex index of each key's mesh per column "
                "(see geoimg landmarks), or 'auto' (suggested extremities matched on the turned spheres); "
                "each later key is resampled through a fold-free warp of the sphere that makes them meet "
                "(default: none, only the best turn of the sphere)",
            ),
            arg(
                "--spectral",
                type=int,
                default=None,
                metavar="L",
                help="blend the shapes' spherical harmonics to degree L (each normalized in its first-order "
                "ellipsoid's frame) instead of their images: closed genus-0 meshes or octahedral images; the "
                "ellipsoids make the correspondence (no sphere turn, no landmarks)",
            ),
            arg("--res", type=_positive(int), default=129, help="pixels per side for meshes (default 129)"),
            arg("--gif", default=None, help="also render an animated GIF"),
            arg("--mp4", default=None, help="also render an MP4 (needs imageio-ffmpeg)"),
            arg("--frames-dir", default=None, help="also write every frame to this folder"),
            arg(
                "--frame-format",
                choices=FRAME_FORMATS,
                default="obj",
                help="file format of --frames-dir's frames (default obj)",
            ),
            arg("--force", action="store_true", help="overwrite existing files"),
        ],
    ),
    "batch": Command(
        "many meshes -> geometry images on Dask (resumable, with a manifest)",
        ("common", "conversion", "steps"),
        [
            arg("inputs", nargs="+", help="mesh files, folders (searched recursively) and glob patterns"),
            arg(
                "-o",
                "--output",
                required=True,
                help="output folder: NAME.exr per input (its path below the inputs' common folder), the manifest",
            ),
            arg(
                "--zarr",
                default=None,
                metavar="STORE",
                help="write the images into this Zarr store instead: (N, R, R, 3) float32, mask, normals, colors "
                "(needs --res; one image per input, the largest piece unless --component K)",
            ),
            arg(
                "--quads",
                nargs="?",
                const="obj",
                default=None,
                choices=QUAD_FORMATS,
                help="also write the quad mesh, NAME_quads.obj (or .ply, .off)",
            ),
            arg(
                "--harmonics",
                type=int,
                default=None,
                metavar="L",
                help="also expand each image in spherical harmonics to degree L: NAME_sh.npz beside it, and a "
                "table of all (normalized; columns x_shcoeffs_L{l}M{m}{C|S}, ...) in OUTPUT/harmonics.csv and "
                ".parquet; closed genus-0 inputs only (others refused)",
            ),
            arg("--no-normals", action="store_true", help="leave out the exact normals"),
            arg("--no-psnr", action="store_true", help="do not measure the quad mesh against the input"),
            arg(
                "--min-psnr",
                type=float,
                default=POOR_PSNR_DB,
                metavar="DB",
                help="below this PSNR to the input an image is marked poor, and the exit status is 1 "
                f"(default {POOR_PSNR_DB:g})",
            ),
            arg(
                "--max-hausdorff",
                type=float,
                default=POOR_HAUSDORFF,
                metavar="FRACTION",
                help="above this Hausdorff distance to the input, as a fraction of its bounding-box diagonal, an "
                f"image is marked poor (default {POOR_HAUSDORFF:g})",
            ),
            arg("--manifest", default=None, metavar="CSV", help="manifest CSV (default OUTPUT/manifest.csv)"),
            arg(
                "--workers",
                type=_positive(int),
                default=None,
                metavar="N",
                help="local worker processes (default: one per core)",
            ),
            arg(
                "--memory-limit",
                default="auto",
                metavar="SIZE",
                help="memory per local worker, e.g. 4GB (default: shared out)",
            ),
            arg(
                "--scheduler",
                default=None,
                metavar="ADDRESS",
                help="run on this existing Dask scheduler (e.g. tcp://host:8786) instead of a local cluster",
            ),
            arg(
                "--progress-every",
                type=_positive(float),
                default=5.0,
                metavar="SECONDS",
                help="off a terminal: a progress line every SECONDS (default 5)",
            ),
            arg(
                "--force",
                action="store_true",
                help="redo every input; write into a folder (or replace a store) that holds something else",
            ),
        ],
        description="Convert every mesh of the inputs, on an embedded local Dask cluster or an "
        "existing one.\nA second run skips what the first finished with the same "
        "options; refused or failed inputs are listed\nin the manifest and never stop "
        "the batch (exit status 1 when there are some).",
        defaults=dict(ops=None),
    ),
    "landmarks": Command(
        "suggest landmarks: a mesh's extremities (tips of limbs, ears, tail)",
        ("common", "view"),
        [
            arg("mesh", help="a mesh file of one piece"),
            arg("-o", "--output", required=True, help="output .csv: index,x,y,z per landmark, most extreme first"),
            arg("--count", type=_positive(int), default=8, help="how many landmarks at most (default 8)"),
            arg(
                "--spread",
                action="store_true",
                help="exactly --count: after the extremities, the points farthest from those picked",
            ),
            arg("--picture", default=None, help="also draw them numbered on a render (.png)"),
            arg("--force", action="store_true", help="overwrite existing files"),
        ],
    ),
    "harmonics": Command(
        "spherical harmonics of a closed genus-0 shape (coefficients of x, y, z)",
        ("common",),
        [
            arg("input", help=f"a closed genus-0 mesh, or an octahedral geometry image ({_IMAGES})"),
            arg("--lmax", type=int, required=True, help="the largest degree L (1 to 1024)"),
            arg("-o", "--output", required=True,
                help="output .npz: coeffs (3, 2, L + 1, L + 1; real, 4pi-normalized, as pyshtools), invariants "
                "(L + 1) and metadata"),
            arg("--mesh", default=None, help="also write the shape rebuilt from the coefficients as a quad mesh"),
            arg("--image", default=None, help=f"also write it as an octahedral geometry image ({_IMAGES})"),
            arg("--res", type=_positive(int), default=None,
                help="side of the image analysed (for a mesh) and rebuilt (default: the smallest 2^k + 1 of at "
                "least max(257, 8 L))"),
            arg("--force", action="store_true", help="overwrite existing files"),
        ],
    ),
    "compress": Command(
        "a shape as a JPEG 2000 geometry image: the least error in N bytes",
        ("common",),
        [
            arg("input", help=f"a mesh, or a geometry image ({_IMAGES}: coded at its own size)"),
            arg("-o", "--output", required=True, help="output .jp2 (read back by geoimg mesh, info, load_image)"),
            arg("--bytes", type=_positive(int), default=None, metavar="N", help="the budget: at most N bytes"),
            arg("--psnr", type=_positive(float), default=None, metavar="DB",
                help="instead: the fewest bytes whose shape is DB dB from the input"),
            arg("--res", type=_positive(int), nargs="+", default=None, metavar="R",
                help="the sides to try for a mesh (default 33 65 129 257 513); the best is kept"),
            arg("--colors", action="store_true",
                help="also code the colours (a textured or coloured mesh's), within the same budget"),
            arg("--normals", action="store_true",
                help="also code the surface's exact normals (two more channels), within the same budget; without "
                     "them a reader computes normals from the grid"),
            arg("--force", action="store_true", help="overwrite an existing file"),
        ],
    ),
    "info": Command(
        "describe a mesh or geometry-image file",
        ("common", "reading"),
        [
            arg("file", help=f"a mesh file or a geometry image ({_IMAGES})"),
        ],
    ),
    "demo": Command(
        "run the whole pipeline on the bundled terrain",
        ("common",),
        [
            arg("-o", "--output", default="geoimg-demo", help="output folder (default ./geoimg-demo)"),
            arg("--res", type=_positive(int), default=256, help="pixels along the longer side (default 256)"),
            arg("--s", type=_positive(float), default=None, help="smoothness s (default: the width that serves --res)"),
            arg("--mesh", default=None, help="another mesh instead of the bundled sample"),
            arg(
                "--force",
                action="store_true",
                help="write into a folder that an earlier demo did not make (its files are replaced)",
            ),
        ],
    ),
}


def build_parser() -> argparse.ArgumentParser:
    """The ``geoimg`` command line's parser, built from :data:`COMMANDS`, :data:`GROUPS` and :data:`EXAMPLES`."""
    top = _Parser(prog="geoimg", description="Polygon meshes to geometry images and back.")
    top.add_argument("--version", action="version", version=f"geoimg {__version__}")
    sub = top.add_subparsers(dest="command", required=True)
    top.commands = sub
    shared: dict[str, _Parser] = {}
    for name, declared in GROUPS.items():
        shared[name] = _Parser(add_help=False)
        for flags, options in declared:
            shared[name].add_argument(*flags, **options)
    for name, command in COMMANDS.items():
        parser = sub.add_parser(
            name,
            help=command.help,
            parents=[shared[g] for g in command.groups],
            description=command.description,
            formatter_class=argparse.RawDescriptionHelpFormatter,
            epilog="examples:\n" + "\n".join(f"  {e}" for e in EXAMPLES[name]),
        )
        for flags, options in command.args:
            parser.add_argument(*flags, **options)
        parser.set_defaults(**command.defaults)
    return top


def _one_line_warning(command: str):
    """Warnings shown as ``geoimg COMMAND: warning: message`` on stderr (not Python's file, line and source)."""
    def show(message, category, filename, lineno, file=None, line=None):
        print(f"geoimg {command}: warning: {message}", file=file or sys.stderr)
    return show


def _terminated(signum, frame):
    """SIGTERM (what `timeout` and process managers send) ends the command like Ctrl-C does, so that files
    being written are removed, not left half-written.
    """
    raise SystemExit(128 + signum)


def _run(args) -> int:
    """Run the parsed command: its module, with everything it needs, is imported only now."""
    from . import _commands           # heavy (numpy, scipy, numba, OpenImageIO...): not needed for --help
    return getattr(_commands, "cmd_" + args.command)(args)


def main(argv=None) -> int:
    """Run the ``geoimg`` command line on ``argv`` (``sys.argv[1:]`` by default); return its exit status."""
    args = build_parser().parse_args(argv)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminated)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore" if getattr(args, "quiet", False) else "default")
            warnings.showwarning = _one_line_warning(args.command)
            return _run(args)
    except KeyboardInterrupt:               # Ctrl-C: what was being written has been removed on the way out
        print(f"geoimg {args.command}: interrupted", file=sys.stderr)
        return 128 + signal.SIGINT
    except BrokenPipeError:                 # the reader of our output went away (geoimg info x | head)
        try:                                # so that the interpreter's last flush does not complain either
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (AttributeError, OSError, ValueError):
            pass
        return 0
    except (GeoimgError, OSError) as e:   # refusals, and missing, existing or unwritable paths; a bug still shows
        text = f"{e.filename} exists; add --force to replace it" if isinstance(e, OutputExists) else str(e)
        print(f"geoimg {args.command}: error: {text}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

