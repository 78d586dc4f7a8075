"""The ``geoimg`` command line: ``image``, ``mesh``, ``filter``, ``curvature``, ``render``, ``morph``, ``batch``,
``info`` and ``demo``."""
from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np

import filters
from ._convert import COMPONENT_CHOICES, mesh_to_image, mesh_to_images
from ._atomic import check_writable, write_all
from ._budget import check_memory
from ._steps import FILTER_STEPS, apply_steps
from .batch import QUAD_FORMATS, convert as convert_batch
from ._optional import MissingDependency, require
from .animation import ALIGNMENTS, EASINGS, FRAME_FORMATS, UP_AXES, RenderError, Renderer, frame_jobs, morph, \
    label_points, save_animation, save_glb, save_png
from . import __version__
from .errors import GeoimgError, InputError
from .image import (ASSUMABLE_DOMAINS, EXR_LAYOUTS, IMAGE_FORMATS, grid_normals, image_curvature, image_region,
                    load_image, load_mask, save_colormap, save_normal_map, save_scalar, uv_region)
from .mesh import MESH_FORMATS, load_mesh, mesh_file_jobs, save_mesh, suggest_landmarks, surface_distance, topology
from .parametrization import AXES, DISK_BALANCES, DISK_BOUNDARIES, PARAMETRIZATION_METHODS
from .surface import SLIVER_RULES, WEIGHTS

SAMPLE_MESH = Path(__file__).resolve().parent / "data" / "mountain.obj"    # package data: works from a wheel
DEMO_MARKER = ".geoimg-demo"
BATCH_PROBLEMS_SHOWN = 10         # refused or failed inputs listed on stderr after a batch (all in the manifest)


class Progress:
    """Stage messages with timings on stderr: on a terminal, or anywhere with ``always`` (--progress); never
    when quiet."""

    def __init__(self, quiet: bool = False, stream=None, always: bool = False):
        self.stream = stream or sys.stderr
        self.on = not quiet and (always or self.stream.isatty())
        self.t0 = time.perf_counter()

    def __call__(self, message: str) -> None:
        if self.on:
            print(f"[{time.perf_counter() - self.t0:6.1f}s] {message}", file=self.stream, flush=True)


class ProgressBar:
    """``[#####.....] 12/30 what`` on stderr, redrawn in place on a terminal; with ``always`` (--progress) off a
    terminal, a line at each tenth of the way (logs, CI). Nothing when quiet."""

    def __init__(self, what: str, quiet: bool = False, stream=None, width: int = 30, always: bool = False):
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.on = not quiet and (always or self.tty)
        self.what, self.width = what, width
        self.shown = -1

    def __call__(self, done: int, total: int) -> None:
        if not self.on:
            return
        if not self.tty:
            tenth = 10 * done // max(total, 1)
            if tenth > self.shown:
                self.shown = tenth
                print(f"{done}/{total} {self.what}", file=self.stream, flush=True)
            return
        print(f"\r{_bar(done, total, self.width)} {done}/{total} {self.what}", end="\n" if done >= total else "",
              file=self.stream, flush=True)


def _bar(done: int, total: int, width: int) -> str:
    """``[#####.....]``: ``done`` of ``total`` in ``width`` characters."""
    fill = int(width * done / max(total, 1))
    return f"[{'#' * fill}{'.' * (width - fill)}]"


def _read_image(path, args):
    """A geometry image, read as the command's --assume and --approximate say."""
    return load_image(path, assume=args.assume, approximate=args.approximate)


def _load_shape(path, args):
    """A mesh file or a geometry image (.exr, .npz, or a preview .png with --approximate)."""
    return _read_image(path, args) if Path(path).suffix.lower() in IMAGE_FORMATS + (".png",) else load_mesh(path)


def _numbered(path, k: int, many: bool) -> Path | None:
    """``NAME.ext`` for a single image, ``NAME_K.ext`` for piece K of several."""
    if path is None:
        return None
    path = Path(path)
    return path.with_name(f"{path.stem}_{k}{path.suffix}") if many else path


def _check_outputs(force: bool, *outputs) -> None:
    """Before any work: each ``(path, suffixes, what)`` with a path given must end in one of ``suffixes``, its
    folder must exist, and it must not exist unless ``force``."""
    for path, suffixes, what in outputs:
        if path is None:
            continue
        if Path(path).suffix.lower() not in suffixes:
            raise InputError(f"{path}: {what} must be named {' or '.join(f'*{x}' for x in suffixes)}")
        check_writable(path, force)


def cmd_image(args) -> int:
    _check_outputs(args.force, (args.output, IMAGE_FORMATS, "the geometry image"),
                   (args.preview, (".png",), "the preview"))
    progress = Progress(args.quiet, always=args.progress)
    component = _component(args.component or "all")
    images = mesh_to_images(args.mesh, args.res, args.s, args.method, component=component, axis=args.axis,
                            boundary=args.boundary, balance=args.balance, weights=args.weights, n=args.n,
                            tol=args.tol, sliver_rule=args.sliver_rule, colors=not args.no_colors, progress=progress)
    many = len(images) > 1
    outputs = [(img, _numbered(args.output, img.metadata.get("component", 0), many),
                _numbered(args.preview, img.metadata.get("component", 0), many)) for img in images]
    jobs: list = []
    for image, out, preview in outputs:
        jobs += image.save_jobs(out, args.layout)         # type: ignore[arg-type]   # out is given: -o is required
        if preview:
            jobs.append((preview, lambda tmp, image=image: image.preview(tmp, overwrite=True)))
    write_all(jobs, overwrite=args.force)                  # all or none
    for image, out, preview in outputs:
        if not args.quiet:
            H, W = image.shape
            piece = f" (piece {image.metadata['component']} of {image.metadata['components']})" if many else ""
            print(f"wrote {out}: {W} x {H} {image.domain.kind} geometry image{piece}, {int(image.valid.sum())} "
                  f"valid pixels ({image.metadata['exact_pixels']} evaluated exactly)")
    return 0


def _component(text: str) -> str | int:
    if text in COMPONENT_CHOICES:
        return text
    try:
        return int(text)
    except ValueError:
        raise InputError(f"--component: expected all, largest or a piece number, got {text!r}") from None


def cmd_mesh(args) -> int:
    _check_outputs(args.force, (args.output, MESH_FORMATS, "the quad mesh"))
    image = _read_image(args.image, args)
    mesh = image.to_mesh()
    out, *beside = write_all(mesh_file_jobs(mesh, args.output), overwrite=args.force)
    if not args.quiet:
        also = f" (its material {beside[0].name} and texture {beside[1].name} beside it)" if beside else ""
        print(f"wrote {out}: {mesh.n_vertices} vertices, {mesh.n_faces} quads{also}")
    return 0


def cmd_landmarks(args) -> int:
    _check_outputs(args.force, (args.output, (".csv",), "the landmarks"), (args.picture, (".png",), "the picture"))
    if args.picture:
        require("moderngl", "rendering")
        require("imageio", "writing pictures")
    mesh = load_mesh(args.mesh)
    index = suggest_landmarks(mesh, args.count, spread=args.spread)
    points = mesh.vertices[index]
    rows = "".join(f"{i},{x!r},{y!r},{z!r}\n" for i, (x, y, z) in zip(index.tolist(), points.tolist()))
    jobs: list = [(Path(args.output), lambda tmp: tmp.write_text("index,x,y,z\n" + rows))]
    if args.picture:
        with Renderer(args.width, args.height) as r:
            cam = r.camera_for(mesh, azimuth=args.azimuth, elevation=args.elevation, up=args.up)
            rgb = label_points(r.render(mesh, cam), points, cam)
        jobs.append((Path(args.picture), lambda tmp: save_png(rgb, tmp, overwrite=True)))
    written = write_all(jobs, overwrite=args.force)
    if not args.quiet:
        kind = "extremities first, then spread" if args.spread else "extremities, most extreme first"
        print(f"{len(index)} landmarks ({kind}): vertices {', '.join(map(str, index))}")
        for f in written:
            print(f"wrote {f}")
    return 0


def cmd_info(args) -> int:
    path = Path(args.file)
    if path.suffix.lower() in IMAGE_FORMATS + (".png",):
        img = _read_image(path, args)
        H, W = img.shape
        print(f"{path}: geometry image {W} x {H}, domain {img.domain.kind}, {int(img.valid.sum())} valid pixels, "
              f"normals {'yes' if img.normals is not None else 'no'}, colours {'yes' if img.colors is not None else 'no'}")
        lo, hi = img.pixels[img.valid].min(axis=0), img.pixels[img.valid].max(axis=0)
        print(f"  bounding box {np.round(lo, 6).tolist()} .. {np.round(hi, 6).tolist()}")
        for key, value in sorted(img.metadata.items()):
            print(f"  {key}: {value}")
        return 0
    mesh = load_mesh(path)
    sizes, counts = np.unique(mesh.face_sizes, return_counts=True)
    kinds = ", ".join(f"{c} {'tri' if k == 3 else 'quad' if k == 4 else f'{k}-gon'}" for k, c in zip(sizes, counts))
    used = mesh.referenced_vertices()
    print(f"{path}: {mesh.n_vertices} vertices ({int((~used).sum())} unreferenced), {mesh.n_faces} faces ({kinds})")
    look = [name for name, value in (("vertex colours", mesh.colors), ("texture coordinates", mesh.face_uv))
            if value is not None]
    look += [f"a {mesh.texture.shape[1]} x {mesh.texture.shape[0]} texture"] if mesh.texture is not None else []
    if look:
        print(f"  {', '.join(look)}")
    v = mesh.vertices[used]
    print(f"  bounding box {np.round(v.min(axis=0), 6).tolist()} .. {np.round(v.max(axis=0), 6).tolist()}, "
          f"diagonal {mesh.bounding_box_diagonal():.6g}")
    print(f"  per-vertex UVs: {'yes' if mesh.uv is not None else 'no'}")
    t = topology(mesh)
    print(f"  topology: {t.describe()}; Euler characteristic {t.euler}, {t.boundary_edges} boundary edges")
    return 0


def _demo_pictures(image, stem: Path, progress) -> list:
    """A rendering of the quad mesh, of it mean-filtered, and a mean-curvature map; none when there is
    no headless OpenGL (the reason is printed)."""
    written = [save_colormap(image_curvature(image)[1], stem.with_name(stem.name + "_mean_curvature.png"),
                             image.valid, overwrite=True)]
    try:
        r = Renderer(800, 600)
    except (RenderError, MissingDependency) as e:
        print(f"  pictures skipped: {e}")
        return written
    with r:
        progress("rendering")
        smooth = image.apply(filters.mean_filter, 5, iterations=3, mode="linear")
        cam = r.camera_for(image, elevation=35)
        for name, img in (("render", image), ("smoothed_render", smooth)):
            written.append(save_png(r.render(img, cam), stem.with_name(f"{stem.name}_{name}.png"), overwrite=True))
    return written


def cmd_demo(args) -> int:
    progress = Progress(args.quiet, always=args.progress)
    src = Path(args.mesh) if args.mesh else SAMPLE_MESH
    if not src.is_file():
        raise FileNotFoundError(f"sample mesh {src} not found: run from a source checkout (pip install -e .) "
                                "or pass --mesh")
    out = Path(args.output)
    marker = out / DEMO_MARKER          # the demo replaces only what an earlier demo wrote in its own folder
    if out.exists() and not args.force and not marker.exists() and (not out.is_dir() or any(out.iterdir())):
        raise FileExistsError(f"{out} exists and was not written by geoimg demo; choose another folder with -o, "
                              "or --force to write into it")
    out.mkdir(parents=True, exist_ok=True)
    marker.touch()
    progress(f"loading {src}")
    mesh = load_mesh(src)
    t0 = time.perf_counter()
    image = mesh_to_image(mesh, args.res, args.s, progress=progress)
    image.metadata["source"] = src.name
    t1 = time.perf_counter()
    stem = src.stem
    files = [image.save(out / f"{stem}.exr", overwrite=True),
             image.preview(out / f"{stem}_preview.png", overwrite=True)]
    quads = load_image(files[0]).to_mesh()
    files.append(save_mesh(quads, out / f"{stem}_quads.obj", overwrite=True))
    files += _demo_pictures(image, out / stem, progress)
    progress("measuring the quad mesh against the input")
    dist = surface_distance(mesh, quads, n=50000)       # how far the result lies from what it approximates
    H, W = image.shape
    if args.quiet:
        return 0
    print(f"geoimg demo on {src.name}: {mesh.n_vertices} vertices, {mesh.n_faces} faces")
    print(f"  surface s={args.s}: {W} x {H} geometry image in {t1 - t0:.2f} s "
          f"(first run includes numba compilation, cached afterwards)")
    print(f"  quad mesh to input mesh: PSNR {dist['psnr_db']:.1f} dB, Hausdorff "
          f"{dist['hausdorff'] / dist['diagonal']:.2e} of the bounding-box diagonal")
    print(f"  quad mesh: {quads.n_vertices} vertices, {quads.n_faces} quads")
    for f in files:
        print(f"  wrote {f}")
    return 0


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


def cmd_filter(args) -> int:
    if not getattr(args, "ops", None):
        raise InputError("no operation given: add e.g. --mean 5 or --sharpen 3 (see geoimg filter --help)")
    _check_outputs(args.force, (args.output, IMAGE_FORMATS, "the geometry image"),
                   (args.preview, (".png",), "the preview"), (args.mesh, MESH_FORMATS, "the quad mesh"))
    image = _read_image(args.image, args)
    given = [m for m in (args.mask, args.region, args.uv_region) if m is not None]
    if len(given) > 1:
        raise InputError("give one of --mask, --region, --uv-region")
    mask = None
    if args.mask is not None:
        mask = load_mask(args.mask, image.shape)
    elif args.region is not None:
        mask = image_region(image, args.region[:3], args.region[3])
    elif args.uv_region is not None:
        mask = uv_region(image.shape, args.uv_region[:2], args.uv_region[2])
    if mask is not None and not np.any(mask > 0):
        raise InputError("the mask selects no pixel")
    out = apply_steps(image, args.ops, mode=args.mode, nsr=args.nsr, mask=mask, feather=args.feather)
    out.metadata["source"] = Path(args.image).name
    jobs = out.save_jobs(args.output, args.layout)
    if args.preview:
        jobs.append((args.preview, lambda tmp: out.preview(tmp, overwrite=True)))
    if args.mesh:
        jobs += mesh_file_jobs(out.to_mesh(), args.mesh)
    written = write_all(jobs, overwrite=args.force)
    if not args.quiet:
        change = np.abs(out.pixels.astype(np.float64) - image.pixels)[image.valid]
        print(f"applied {'; '.join(out.metadata['filters'][-len(args.ops):])}")
        print(f"  largest change {change.max():.4g}, mean {change.mean():.4g} (coordinate units)")
        for f in written:
            print(f"  wrote {f}")
    return 0


def cmd_curvature(args) -> int:
    image = _read_image(args.image, args)
    K, H = image_curvature(image)
    stem = Path(args.output)
    jobs: list = []
    for name, values in (("gaussian", K), ("mean", H)):
        jobs.append((stem.with_name(f"{stem.name}_{name}.exr"),
                     lambda tmp, v=values, n=name: save_scalar(v, tmp, n, overwrite=True)))
        jobs.append((stem.with_name(f"{stem.name}_{name}.png"),
                     lambda tmp, v=values: save_colormap(v, tmp, image.valid, overwrite=True)))
    normals = image.normals if image.normals is not None else grid_normals(image.pixels, image.domain.orientation)
    jobs.append((stem.with_name(f"{stem.name}_normals.png"),
                 lambda tmp: save_normal_map(normals, tmp, image.valid, overwrite=True)))
    written = write_all(jobs, overwrite=args.force)
    if not args.quiet:
        for f in written:
            print(f"wrote {f}")
    return 0


def cmd_render(args) -> int:
    _check_outputs(args.force, (args.output, (".png",), "the picture"))
    shape = _load_shape(args.file, args)
    with Renderer(args.width, args.height, background=None if args.transparent else (1.0, 1.0, 1.0)) as r:
        rgb = r.render(shape, r.camera_for(shape, azimuth=args.azimuth, elevation=args.elevation, up=args.up))
    out = save_png(rgb, args.output, overwrite=args.force)
    if not args.quiet:
        print(f"wrote {out}: {args.width} x {args.height}")
    return 0


def read_landmarks(path, keys: int) -> np.ndarray:
    """A landmarks CSV: a row per feature, a vertex index of each key's mesh per column (a first line that
    is not numbers, a header, is skipped), as an (L, keys) int array."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such landmarks file")
    rows = [line.split(",") for line in path.read_text(encoding="utf-8-sig").splitlines() if line.strip()]
    if rows and not rows[0][0].strip().lstrip("-").isdigit():
        rows = rows[1:]
    lengths = sorted({len(row) for row in rows})
    if lengths != [keys]:
        raise InputError(f"{path}: expected rows of {keys} vertex indices (one per key), got "
                         f"{'no rows' if not rows else 'rows of ' + ' and '.join(map(str, lengths)) + ' values'}")
    try:
        table = np.array([[int(v) for v in row] for row in rows], np.int64)
    except ValueError as e:
        raise InputError(f"{path}: landmarks are whole vertex indices, one column per key ({e})") from None
    return table


def cmd_morph(args) -> int:
    progress = Progress(args.quiet, always=args.progress)
    if not (args.output or args.gif or args.mp4 or args.frames_dir):
        raise InputError("nothing to write: give -o OUT.glb, --gif, --mp4 or --frames-dir")
    # what the outputs need, checked before any work: the packages and the paths
    if args.output:
        require("pygltflib", "writing a glTF morph")
    if args.gif or args.mp4:
        require("moderngl", "rendering")
        require("imageio", "writing animations")
    if args.mp4:
        require("imageio_ffmpeg", "MP4 (GIF needs nothing more)")
    if args.gif or args.mp4:                          # the pictures are held until they are written
        check_memory(float(args.frames) * args.width * args.height * 3, f"{args.frames} pictures of "
                     f"{args.width} x {args.height}")
    _check_outputs(args.force, (args.output, (".glb",), "the glTF morph"), (args.gif, (".gif",), "the GIF"),
                   (args.mp4, (".mp4",), "the MP4"))
    if args.frames_dir and not args.force:
        taken = sorted(Path(args.frames_dir).glob(f"frame_*.{args.frame_format}"))
        if taken:
            raise FileExistsError(f"{args.frames_dir} already holds {len(taken)} frame files (use --force to "
                                  "replace them)")
    landmarks = args.landmarks if args.landmarks in (None, "auto") else read_landmarks(args.landmarks,
                                                                                      len(args.shapes))
    shapes = []
    for f in args.shapes:
        progress(f"loading {f}")
        shapes.append(_load_shape(f, args))
    m = morph(*shapes, frames=args.frames, easing=args.easing, align=args.align, rotate=not args.no_rotate,
              resolution=args.res, resample=True, landmarks=landmarks, progress=progress)
    if "auto_landmarks" in m.report[0] and not args.quiet:
        print(f"auto landmarks: {len(m.report[0]['auto_landmarks'])} matched (vertex of each key per feature: "
              f"{m.report[0]['auto_landmarks']})")
    for entry in m.report[1:]:
        if "landmarks" in entry and not args.quiet:
            w = entry["landmarks"]
            print(f"shape {entry['shape']}: landmarks warped onto shape 0's in {w['steps']} steps, within "
                  f"{w['residual_rad']:.1e} rad, {w['folded']} folded triangles, area log-RMS of the warp "
                  f"{w['area_log_rms']:.2f}")
    jobs = []
    if args.output:
        jobs.append((args.output, lambda tmp: save_glb(m, tmp, fps=args.fps, overwrite=True)))
    written = []
    if args.frames_dir:                               # written with the rest: all or none
        Path(args.frames_dir).mkdir(parents=True, exist_ok=True)
        jobs += frame_jobs(m, args.frames_dir, args.frame_format,
                           ProgressBar(f"{args.frame_format} frames", args.quiet, always=args.progress))
        written.append(Path(args.frames_dir))
    animations = [path for path in (args.gif, args.mp4) if path]
    if animations:                                   # rendered once, written in each format asked for
        with Renderer(args.width, args.height) as r:
            cam = r.camera_for(*m.keys, azimuth=args.azimuth, elevation=args.elevation, up=args.up)
            bar = ProgressBar("pictures", args.quiet, always=args.progress)
            pictures = []
            for i, frame in enumerate(m.frames()):
                pictures.append(r.render(frame, cam))
                bar(i + 1, len(m))
        for path in animations:
            jobs.append((path, lambda tmp: save_animation(pictures, tmp, fps=args.fps, overwrite=True)))
    done = write_all(jobs, overwrite=args.force)
    frames_dir = Path(args.frames_dir) if args.frames_dir else None
    written = [p for p in done if p.parent != frames_dir] + written       # the frames: their folder, once
    if not args.quiet:
        print(f"morph of {len(m.keys)} shapes, {len(m)} frames ({args.easing})")
        for entry in m.report[1:]:
            parts = [f"shape {entry['shape']}: {entry['parametrization']}"]
            if "scale" in entry:
                parts.append(f"scaled by {entry['scale']:.4g}, moved by {np.round(entry['translation'], 6).tolist()}")
            if "rms_before" in entry:
                parts.append(f"sphere turned {entry['rotation_deg']:.1f} deg (RMS {entry['rms_before']:.3g} -> "
                             f"{entry['rms_after']:.3g} of the radius)")
            elif "rotation_from" in entry:
                parts.append(f"sphere turned as shape {entry['rotation_from']}'s ({entry['rotation_deg']:.1f} deg)")
            print("  " + "; ".join(parts))
        for f in written:
            print(f"  wrote {f}")
    return 0


class BatchProgress:
    """Counts of a batch on stderr: a bar redrawn in place on a terminal, else a line every ``every`` seconds
    (logs, CI); nothing when quiet."""

    def __init__(self, quiet: bool = False, every: float = 5.0, stream=None, width: int = 30):
        self.stream = stream or sys.stderr
        self.quiet, self.every, self.width = quiet, every, width
        self.tty = self.stream.isatty()
        self.last = None

    @staticmethod
    def _describe(c: dict) -> str:
        eta = "" if c["eta"] is None or c["done"] >= c["total"] else f", {_duration(c['eta'])} left"
        skipped = f" ({c['skipped']} done before)" if c["skipped"] else ""
        return (f"{c['done']}/{c['total']} done{skipped}, {c['refused']} refused, {c['failed']} failed, "
                f"{c['per_minute']:.1f}/min{eta}")

    def __call__(self, counts: dict) -> None:
        if self.quiet:
            return
        finished = counts["done"] >= counts["total"]
        if self.tty:
            print(f"\r{_bar(counts['done'], counts['total'], self.width)} {self._describe(counts)}\x1b[K",
                  end="\n" if finished else "", file=self.stream, flush=True)
        elif self.last is None or finished or counts["elapsed"] - self.last >= self.every:
            self.last = counts["elapsed"]
            print(f"[{_duration(counts['elapsed'])}] {self._describe(counts)}", file=self.stream, flush=True)


def _duration(seconds: float) -> str:
    seconds = int(round(seconds))
    return f"{seconds // 3600}h{seconds // 60 % 60:02d}m" if seconds >= 3600 else \
        f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"


def cmd_batch(args) -> int:
    options = dict(resolution=args.res, s=args.s, method=args.method, axis=args.axis, boundary=args.boundary,
                   balance=args.balance,
                   weights=args.weights, n=args.n, tol=args.tol, sliver_rule=args.sliver_rule,
                   normals=not args.no_normals, colors=not args.no_colors, steps=args.ops or (), mode=args.mode,
                   nsr=args.nsr,
                   quads=args.quads is not None, quads_format=args.quads or "obj", psnr=not args.no_psnr)
    if args.component is not None:
        options["component"] = _component(args.component)
    table = convert_batch(args.inputs, args.output, zarr=args.zarr, manifest=args.manifest, workers=args.workers,
                          memory_limit=args.memory_limit, scheduler=args.scheduler, force=args.force,
                          progress=BatchProgress(args.quiet, args.progress_every), **options)
    c = table.attrs["summary"]
    bad = c["refused"] + c["failed"]
    if not args.quiet:
        skipped = f", {c['skipped']} of them done before" if c["skipped"] else ""
        print(f"{c['total']} inputs: {c['ok'] + c['skipped']} converted{skipped}, {c['refused']} refused, "
              f"{c['failed']} failed in {_duration(c['elapsed'])}; manifest {table.attrs['manifest']}")
    if bad:
        print(f"geoimg batch: {bad} of {c['total']} inputs were not converted (all reasons in "
              f"{table.attrs['manifest']}):", file=sys.stderr)
        failed = table[table["status"] != "ok"]
        for _, row in failed.head(BATCH_PROBLEMS_SHOWN).iterrows():
            print(f"  {row['input']}: {row['status']}: {row['message']}", file=sys.stderr)
        if len(failed) > BATCH_PROBLEMS_SHOWN:
            print(f"  ... and {len(failed) - BATCH_PROBLEMS_SHOWN} more", file=sys.stderr)
    return 1 if bad else 0


def _positive(kind):
    def check(text):
        value = kind(text)
        if value <= 0:
            raise argparse.ArgumentTypeError(f"expected a positive number, got {text}")
        return value
    return check


EXAMPLES = {
    "image": ["geoimg image terrain.obj -o terrain.exr --res 257 --s 2 --preview terrain.png",
              "geoimg image spot.obj -o spot.exr --res 257          # closed: an octahedral image, colours kept",
              "geoimg image scan.ply -o scan.npz --res 513 --no-colors"],
    "mesh": ["geoimg mesh terrain.exr -o terrain_quads.obj", "geoimg mesh spot.exr -o spot.glb   # with its texture",
             "geoimg mesh other.exr -o q.ply --assume planar"],
    "filter": ["geoimg filter terrain.exr -o smooth.exr --mean 5 --sharpen 3",
               "geoimg filter scan.exr -o clean.exr --median 3 --nlmeans 0.002 --mesh clean.obj",
               "geoimg filter spot.exr -o head.exr --gaussian 3 --region 0.1 0.4 0.5 0.2 --feather 8"],
    "curvature": ["geoimg curvature terrain.exr -o terrain_curv"],
    "render": ["geoimg render spot.exr -o spot.png --azimuth 60",
               "geoimg render terrain.exr -o terrain.png --elevation 35 --transparent"],
    "morph": ["geoimg morph spot.obj bunny.obj --frames 30 -o morph.glb --gif morph.gif",
              "geoimg morph a.exr b.exr c.exr --frames-dir frames --frame-format ply"],
    "batch": ["geoimg batch meshes/ -o out --res 257 --quads", "geoimg batch 'scans/*.ply' -o out --res 129 --zarr data.zarr"],
    "info": ["geoimg info spot.exr", "geoimg info scan.ply"],
    "landmarks": ["geoimg landmarks spot.obj -o spot_points.csv --picture spot_points.png",
                  "geoimg landmarks armadillo.obj -o points.csv --count 12 --azimuth 180"],
    "demo": ["geoimg demo", "geoimg demo -o here --res 129"],
}


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="geoimg", description="Polygon meshes to geometry images and back.")
    p.add_argument("--version", action="version", version=f"geoimg {__version__}")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--quiet", "-q", action="store_true", help="print nothing but errors")
    common.add_argument("--progress", action="store_true",
                        help="show progress off a terminal too (logs, CI); on a terminal it is always shown")
    sub = p.add_subparsers(dest="command", required=True)

    conversion = argparse.ArgumentParser(add_help=False)        # mesh -> image: geoimg image and geoimg batch
    conversion.add_argument("--res", type=_positive(int), default=None,
                            help="pixels along the longer side (default: from s)")
    conversion.add_argument("--s", type=_positive(float), default=1.0, help="smoothness s (sigma_i = s d_i), default 1")
    conversion.add_argument("--method", choices=PARAMETRIZATION_METHODS, default="auto",
                            help="parametrization (default auto)")
    conversion.add_argument("--axis", choices=AXES, default=None, help="up axis of a height field")
    conversion.add_argument("--boundary", choices=DISK_BOUNDARIES, default="square",
                            help="disk meshes: boundary on the unit square (default) or kept (a convex planar outline)")
    conversion.add_argument("--balance", choices=DISK_BALANCES, default="slim",
                            help="disk meshes: relax the mean-value map with SLIM, opening up squeezed parts "
                                 "(default slim), or keep it (none)")
    conversion.add_argument("--weights", choices=WEIGHTS, default="gaussian",
                            help="the weight of each face: rational Gaussian (default gaussian) or local (its n "
                                 "nearest face centres)")
    conversion.add_argument("--n", type=int, default=10,
                            help="face centres per local weight (--weights local; default 10)")
    conversion.add_argument("--tol", type=float, default=1e-10,
                            help="truncation tolerance; 0 = exact sum (default 1e-10)")
    conversion.add_argument("--sliver-rule", choices=SLIVER_RULES, default="robust",
                            help="long thin faces: a smaller Gaussian and the plane of their neighbours (default "
                                 "robust), or the paper's enclosing circle (paper)")
    conversion.add_argument("--component", default=None, metavar="all|largest|K",
                            help="a mesh of several pieces gives NAME_0.exr, NAME_1.exr, ... (largest first; "
                                 "the default, all), or keep one (the default with --zarr: largest)")
    conversion.add_argument("--no-colors", action="store_true",
                            help="leave out the mesh's colours (an OBJ's texture, PLY or OBJ vertex colours), which "
                                 "are resampled into the image by default")
    steps = argparse.ArgumentParser(add_help=False)             # filter steps: geoimg filter and geoimg batch
    for name, (_, kinds, metavar, text) in FILTER_STEPS.items():
        steps.add_argument(f"--{name}", dest=name, action=_Op, nargs=len(kinds) if len(kinds) > 1 else None,
                           metavar=metavar, help=text)
    steps.add_argument("--nsr", type=_positive(float), default=1e-3,
                       help="Wiener noise-to-signal ratio of --sharpen (default 0.001)")
    steps.add_argument("--mode", choices=filters.PAD_MODES, default=None,
                       help="boundary rule (default: octahedral for spherical images, reflect for planar ones)")

    reading = argparse.ArgumentParser(add_help=False)           # commands that read geometry images
    reading.add_argument("--assume", choices=ASSUMABLE_DOMAINS, default=None,
                         help="read an image without geoimg metadata (from another program) as this domain "
                              "(default: refuse it)")
    reading.add_argument("--approximate", action="store_true",
                         help="read a 16-bit PNG preview written by geoimg as geometry, to within half of its "
                              "1/65534 steps (default: refuse it)")
    writing = argparse.ArgumentParser(add_help=False)           # commands that write geometry images
    writing.add_argument("--layout", choices=EXR_LAYOUTS, default="geoimg",
                         help="EXR channels: R, G, B, mask, N.X, N.Y, N.Z (geoimg, the default) or the mask as A "
                              "(rgba: alpha for compositing tools)")

    im = sub.add_parser("image", help="mesh -> geometry image (OpenEXR)", parents=[common, conversion, writing])
    im.add_argument("mesh", help=f"input mesh ({', '.join(MESH_FORMATS)})")
    im.add_argument("-o", "--output", required=True, help="output .exr (or .npz: NumPy arrays)")
    im.add_argument("--preview", default=None, help="also write a 16-bit PNG preview")
    im.add_argument("--force", action="store_true", help="overwrite existing files")
    im.set_defaults(func=cmd_image)

    me = sub.add_parser("mesh", help="geometry image -> quad mesh", parents=[common, reading])
    me.add_argument("image", help="input geometry image (.exr, .npz)")
    me.add_argument("-o", "--output", required=True, help="output mesh (.obj/.ply/.off keep quads)")
    me.add_argument("--force", action="store_true", help="overwrite an existing file")
    me.set_defaults(func=cmd_mesh)

    fi = sub.add_parser("filter", help="smooth, sharpen or Fourier-filter a geometry image",
                        parents=[common, steps, reading, writing],
                        description="Operations run in the order given; a mask restricts every one of them.")
    fi.add_argument("image", help="input geometry image (.exr, .npz)")
    fi.add_argument("-o", "--output", required=True, help="output .exr or .npz")
    fi.add_argument("--mask", default=None, help="image file (same size): where to filter, 0..1")
    fi.add_argument("--region", type=float, nargs=4, metavar=("X", "Y", "Z", "R"), default=None,
                    help="filter within distance R of the point (X, Y, Z) of the surface")
    fi.add_argument("--uv-region", type=float, nargs=3, metavar=("U", "V", "R"), default=None,
                    help="filter within the disk of radius R around (U, V) of the image, in [0, 1]")
    fi.add_argument("--feather", type=float, default=4.0, help="mask transition width in pixels (default 4)")
    fi.add_argument("--preview", default=None, help="also write a 16-bit PNG preview")
    fi.add_argument("--mesh", default=None, help="also write the quad mesh")
    fi.add_argument("--force", action="store_true", help="overwrite existing files")
    fi.set_defaults(func=cmd_filter, ops=None)

    cu = sub.add_parser("curvature", help="Gaussian and mean curvature maps and a normal map of a geometry image",
                        parents=[common, reading])
    cu.add_argument("image", help="input geometry image (.exr, .npz)")
    cu.add_argument("-o", "--output", required=True,
                    help="output stem: writes STEM_gaussian.exr/.png, STEM_mean.exr/.png, STEM_normals.png")
    cu.add_argument("--force", action="store_true", help="overwrite existing files")
    cu.set_defaults(func=cmd_curvature)

    view = argparse.ArgumentParser(add_help=False)
    view.add_argument("--width", type=_positive(int), default=800, help="picture width in pixels (default 800)")
    view.add_argument("--height", type=_positive(int), default=600, help="picture height in pixels (default 600)")
    view.add_argument("--azimuth", type=float, default=30.0, help="degrees about the up axis (default 30)")
    view.add_argument("--elevation", type=float, default=20.0, help="degrees above the horizon (default 20)")
    view.add_argument("--up", choices=UP_AXES, default=None,
                      help="the shape's up axis (default: the one a geometry image records, a terrain's; else y)")

    re_ = sub.add_parser("render", help="shade a mesh or geometry image to PNG (headless)",
                         parents=[common, view, reading])
    re_.add_argument("file", help="mesh or geometry image (.exr, .npz)")
    re_.add_argument("-o", "--output", required=True, help="output .png")
    re_.add_argument("--force", action="store_true", help="overwrite an existing file")
    re_.add_argument("--transparent", action="store_true",
                     help="a transparent background (an RGBA PNG) instead of white (default: white)")
    re_.set_defaults(func=cmd_render)

    mo = sub.add_parser("morph", help="morph between shapes: glTF with morph targets, GIF/MP4, frame files",
                        parents=[common, view, reading])
    mo.add_argument("shapes", nargs="+", help="two or more meshes or geometry images (.exr, .npz), in order")
    mo.add_argument("-o", "--output", default=None, help="output .glb (morph targets + weights animation)")
    mo.add_argument("--frames", type=int, default=30, help="frames in all (default 30)")
    mo.add_argument("--fps", type=_positive(float), default=24.0, help="frames per second (default 24)")
    mo.add_argument("--easing", default="smoothstep", choices=tuple(EASINGS),
                    help="how the blend moves between keys (default smoothstep)")
    mo.add_argument("--align", choices=ALIGNMENTS, default="similarity",
                    help="bring shapes 2.. onto shape 1: centre, centre and scale (similarity, the default), "
                         "or none")
    mo.add_argument("--no-rotate", action="store_true", help="spherical images: keep the spheres as they are")
    mo.add_argument("--landmarks", default=None, metavar="CSV",
                    help="corresponding features: a row per feature, a vertex index of each key's mesh per column "
                         "(see geoimg landmarks), or 'auto' (suggested extremities matched on the turned spheres); "
                         "each later key is resampled through a fold-free warp of the sphere that makes them meet "
                         "(default: none, only the best turn of the sphere)")
    mo.add_argument("--res", type=_positive(int), default=129, help="pixels per side for meshes (default 129)")
    mo.add_argument("--gif", default=None, help="also render an animated GIF")
    mo.add_argument("--mp4", default=None, help="also render an MP4 (needs imageio-ffmpeg)")
    mo.add_argument("--frames-dir", default=None, help="also write every frame to this folder")
    mo.add_argument("--frame-format", choices=FRAME_FORMATS, default="obj",
                    help="file format of --frames-dir's frames (default obj)")
    mo.add_argument("--force", action="store_true", help="overwrite existing files")
    mo.set_defaults(func=cmd_morph)

    ba = sub.add_parser("batch", help="many meshes -> geometry images on Dask (resumable, with a manifest)",
                        parents=[common, conversion, steps], formatter_class=argparse.RawDescriptionHelpFormatter,
                        description="Convert every mesh of the inputs, on an embedded local Dask cluster or an "
                                    "existing one.\nA second run skips what the first finished with the same "
                                    "options; refused or failed inputs are listed\nin the manifest and never stop "
                                    "the batch (exit status 1 when there are some).",
                        epilog="examples:\n"
                               "  geoimg batch meshes/ -o images --res 257\n"
                               "  geoimg batch 'scans/**/*.ply' -o out --zarr out/data.zarr --res 129 --gaussian 1\n"
                               "  geoimg batch meshes/ -o images --scheduler tcp://10.0.0.5:8786")
    ba.add_argument("inputs", nargs="+", help="mesh files, folders (searched recursively) and glob patterns")
    ba.add_argument("-o", "--output", required=True,
                    help="output folder: NAME.exr per input (its path below the inputs' common folder), the manifest")
    ba.add_argument("--zarr", default=None, metavar="STORE",
                    help="write the images into this Zarr store instead: (N, R, R, 3) float32, mask, normals, colors "
                         "(needs --res; one image per input, the largest piece unless --component K)")
    ba.add_argument("--quads", nargs="?", const="obj", default=None, choices=QUAD_FORMATS,
                    help="also write the quad mesh, NAME_quads.obj (or .ply, .off)")
    ba.add_argument("--no-normals", action="store_true", help="leave out the exact normals")
    ba.add_argument("--no-psnr", action="store_true", help="do not measure the quad mesh against the input")
    ba.add_argument("--manifest", default=None, metavar="CSV", help="manifest CSV (default OUTPUT/manifest.csv)")
    ba.add_argument("--workers", type=_positive(int), default=None, metavar="N",
                    help="local worker processes (default: one per core)")
    ba.add_argument("--memory-limit", default="auto", metavar="SIZE",
                    help="memory per local worker, e.g. 4GB (default: shared out)")
    ba.add_argument("--scheduler", default=None, metavar="ADDRESS",
                    help="run on this existing Dask scheduler (e.g. tcp://host:8786) instead of a local cluster")
    ba.add_argument("--progress-every", type=_positive(float), default=5.0, metavar="SECONDS",
                    help="off a terminal: a progress line every SECONDS (default 5)")
    ba.add_argument("--force", action="store_true",
                    help="redo every input; write into a folder (or replace a store) that holds something else")
    ba.set_defaults(func=cmd_batch, ops=None)

    lm = sub.add_parser("landmarks", help="suggest landmarks: a mesh's extremities (tips of limbs, ears, tail)",
                        parents=[common, view])
    lm.add_argument("mesh", help="a mesh file of one piece")
    lm.add_argument("-o", "--output", required=True, help="output .csv: index,x,y,z per landmark, most extreme first")
    lm.add_argument("--count", type=_positive(int), default=8, help="how many landmarks at most (default 8)")
    lm.add_argument("--spread", action="store_true",
                    help="exactly --count: after the extremities, the points farthest from those picked")
    lm.add_argument("--picture", default=None, help="also draw them numbered on a render (.png)")
    lm.add_argument("--force", action="store_true", help="overwrite existing files")
    lm.set_defaults(func=cmd_landmarks)

    info = sub.add_parser("info", help="describe a mesh or geometry-image file", parents=[common, reading])
    info.add_argument("file", help="a mesh file or a geometry image (.exr, .npz)")
    info.set_defaults(func=cmd_info)

    demo = sub.add_parser("demo", help="run the whole pipeline on the bundled terrain", parents=[common])
    demo.add_argument("-o", "--output", default="geoimg-demo", help="output folder (default ./geoimg-demo)")
    demo.add_argument("--res", type=_positive(int), default=256, help="pixels along the longer side (default 256)")
    demo.add_argument("--s", type=_positive(float), default=2.0, help="smoothness s (default 2)")
    demo.add_argument("--mesh", default=None, help="another mesh instead of the bundled sample")
    demo.add_argument("--force", action="store_true",
                      help="write into a folder that an earlier demo did not make (its files are replaced)")
    demo.set_defaults(func=cmd_demo)
    for name, examples in EXAMPLES.items():          # a few examples under each command's help
        sub.choices[name].epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples)
        sub.choices[name].formatter_class = argparse.RawDescriptionHelpFormatter
    return p


def _one_line_warning(command: str):
    """Warnings shown as ``geoimg COMMAND: warning: message`` on stderr (not Python's file, line and source)."""
    def show(message, category, filename, lineno, file=None, line=None):
        print(f"geoimg {command}: warning: {message}", file=file or sys.stderr)
    return show


def _terminated(signum, frame):
    """SIGTERM (what `timeout` and process managers send) ends the command like Ctrl-C does, so that files
    being written are removed, not left half-written."""
    raise SystemExit(128 + signum)


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminated)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore" if getattr(args, "quiet", False) else "default")
            warnings.showwarning = _one_line_warning(args.command)
            return args.func(args)
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
        print(f"geoimg {args.command}: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
