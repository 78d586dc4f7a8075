"""The commands of the ``geoimg`` command line, a function ``cmd_NAME(args)`` per command: :mod:`geoimg.cli`
parses the arguments (with nothing but the option vocabularies) and imports this module only to run one,
so that ``geoimg --help`` starts in a fraction of a second.
"""
from __future__ import annotations

import dataclasses
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import filters
from ._choices import COMPRESSED_FORMATS, DEFAULT_CURVATURE_SCALE, READ_IMAGE_FORMATS
from ._atomic import check_writable, write_all
from ._budget import check_memory
from ._optional import MissingDependency, require
from .errors import InputError
from .image import (IMAGE_FORMATS, grid_normals, image_curvature, image_region,
                    load_image, load_mask, save_colormap, save_normal_map, save_scalar, uv_region)
from .mesh import MESH_FORMATS, load_mesh, mesh_file_jobs, save_mesh

SAMPLE_MESH = Path(__file__).resolve().parent / "data" / "mountain.obj"    # package data: works from a wheel
DEMO_MARKER = ".geoimg-demo"
BATCH_PROBLEMS_SHOWN = 10         # refused or failed inputs listed on stderr after a batch (all in the manifest)


class Progress:
    """Stage messages with timings on stderr: on a terminal, or anywhere with ``always`` (--progress); never
    when quiet.
    """

    def __init__(self, quiet: bool = False, stream=None, always: bool = False):
        self.stream = stream or sys.stderr
        self.on = not quiet and (always or self.stream.isatty())
        self.t0 = time.perf_counter()

    def __call__(self, message: str) -> None:
        if self.on:
            print(f"[{time.perf_counter() - self.t0:6.1f}s] {message}", file=self.stream, flush=True)


class ProgressBar:
    """``[#####.....] 12/30 what`` on stderr, redrawn in place on a terminal; with ``always`` (--progress) off a
    terminal, a line at each tenth of the way (logs, CI). Nothing when quiet.
    """

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
    """A geometry image, read as the command's --assume, --approximate (and --bytes) say."""
    return load_image(path, assume=args.assume, approximate=args.approximate, max_bytes=getattr(args, "bytes", None))


def _load_shape(path, args):
    """A mesh file or a geometry image (.exr, .npz, or a preview .png with --approximate)."""
    return _read_image(path, args) if Path(path).suffix.lower() in READ_IMAGE_FORMATS else load_mesh(path)


def _numbered(path, k: int, many: bool) -> Path | None:
    """``NAME.ext`` for a single image, ``NAME_K.ext`` for piece K of several."""
    if path is None:
        return None
    path = Path(path)
    return path.with_name(f"{path.stem}_{k}{path.suffix}") if many else path


def _check_outputs(force: bool, *outputs) -> None:
    """Before any work: each ``(path, suffixes, what)`` with a path given must end in one of ``suffixes``, its
    folder must exist, and it must not exist unless ``force``.
    """
    for path, suffixes, what in outputs:
        if path is None:
            continue
        if Path(path).suffix.lower() not in suffixes:
            raise InputError(f"{path}: {what} must be named {' or '.join(f'*{x}' for x in suffixes)}")
        check_writable(path, force)


def _conversion_options(args, cls=None, **values):
    """The conversion's options from the command line: each field of ``cls`` from the flag of its name (a new
    option is a field and a flag, nothing here), the weights from ``--weights``, ``--s``, ``--n``, ``--tol``
    and ``--sliver-rule``, then ``values`` (``cls``: :class:`~geoimg.ConversionOptions` unless given).
    """
    from ._options import ConversionOptions
    from .surface import make_weights
    cls = ConversionOptions if cls is None else cls
    flags = {f.name: getattr(args, f.name) for f in dataclasses.fields(cls) if hasattr(args, f.name)}
    flags.pop("component", None)
    weights = make_weights(args.weights, s=args.s, n=args.n, tol=args.tol, sliver_rule=args.sliver_rule)
    component = {} if getattr(args, "component", None) is None else {"component": _component(args.component)}
    return cls(**{**flags, "weights": weights, "resolution": args.res, "colors": not args.no_colors,
                  **component, **values})


def cmd_image(args) -> int:
    from ._convert import mesh_to_images
    _check_outputs(args.force, (args.output, IMAGE_FORMATS, "the geometry image"),
                   (args.preview, (".png",), "the preview"))
    progress = Progress(args.quiet, always=args.progress)
    options = _conversion_options(args)
    images = mesh_to_images(args.mesh, options=options, backend=args.backend, progress=progress)
    many = len(images) > 1
    outputs = [(img, _numbered(args.output, img.metadata.get("component", 0), many),
                _numbered(args.preview, img.metadata.get("component", 0), many)) for img in images]
    jobs: list = []
    for image, out, preview in outputs:
        jobs += image.save_jobs(out, args.layout)         # type: ignore[arg-type]   # out is given: -o is required
        if preview:
            jobs.append((preview, lambda tmp, image=image: image.preview(tmp, overwrite=True)))
    write_all(jobs, overwrite=args.force)                  # all or none
    for image, out, _ in outputs:
        if not args.quiet:
            H, W = image.shape
            piece = f" (piece {image.metadata['component']} of {image.metadata['components']})" if many else ""
            m = image.metadata
            stages = f" ({m['map_stages']})" if "map_stages" in m else ""
            print(f"wrote {out}: {W} x {H} {image.domain.kind} geometry image{piece}, {int(image.valid.sum())} "
                  f"valid pixels; to the mesh: PSNR {m['psnr_db']:.1f} dB, Hausdorff {100 * m['hausdorff']:.2g} % "
                  f"of the diagonal ({m['weights']} weights, s = {m['s']:.3g}); the map{stages}: L2 stretch "
                  f"{m['map_stretch']:.3g}, {100 * m['starved']:.2g} % of the surface starved")
    return 0


def cmd_harmonics(args) -> int:
    from ._convert import measure_fidelity
    from .spectrum import harmonics
    from .spectrum._harmonics import IMAGE_SUFFIXES
    from .spectrum._transform import check_lmax
    check_lmax(args.lmax)                                       # before any work or file
    _check_outputs(args.force, (args.output, (".npz",), "the coefficients"),
                   (args.mesh, MESH_FORMATS, "the rebuilt mesh"), (args.image, IMAGE_FORMATS, "the rebuilt image"))
    progress = Progress(args.quiet, always=args.progress)
    source = Path(args.input)
    mesh = None if source.suffix.lower() in IMAGE_SUFFIXES else load_mesh(source)   # read once: analysed, measured
    h = harmonics(source if mesh is None else mesh, args.lmax, resolution=args.res, progress=progress)
    h.metadata["source"] = source.name
    jobs: list = [(args.output, lambda tmp: h.save(tmp, overwrite=True))]
    rebuilt = None
    if args.mesh or args.image:
        progress("rebuilding the shape from the coefficients")
        rebuilt = h.to_image(args.res)
        if mesh is not None:                                    # a mesh: measured as geoimg image measures
            progress("measuring the rebuilt shape against the mesh")
            with warnings.catch_warnings():     # a low degree is far from the mesh by design: the line says how far
                warnings.simplefilter("ignore")
                measure_fidelity(rebuilt, mesh)
        if args.image:
            jobs += rebuilt.save_jobs(args.image, "geoimg")
        if args.mesh:
            jobs += mesh_file_jobs(rebuilt.to_mesh(), args.mesh)
    write_all(jobs, overwrite=args.force)
    if not args.quiet:
        m = h.metadata
        made = f" from a {m['resolution']} x {m['resolution']} octahedral image"
        if "psnr_db" in m:
            made += f" (its PSNR to the mesh {m['psnr_db']:.1f} dB)"
        print(f"wrote {args.output}: coefficients of x, y, z to degree {h.lmax}{made}")
        if rebuilt is not None and "psnr_db" in rebuilt.metadata:
            r = rebuilt.metadata
            print(f"rebuilt at degree {h.lmax}, {rebuilt.shape[0]} x {rebuilt.shape[0]}: to the mesh: PSNR "
                  f"{r['psnr_db']:.1f} dB, Hausdorff {100 * r['hausdorff']:.2g} % of the diagonal")
        for path in (args.image, args.mesh):
            if path:
                print(f"wrote {path}")
    return 0


def cmd_compress(args) -> int:
    from ._compress import compress
    if (args.bytes is None) == (args.psnr is None):
        raise InputError("give --bytes N (a budget) or --psnr DB (an error to reach), one of the two")
    _check_outputs(args.force, (args.output, COMPRESSED_FORMATS, "the compressed image"))
    progress = Progress(args.quiet, always=args.progress)
    source = Path(args.input)
    made = compress(source, args.output, max_bytes=args.bytes, psnr=args.psnr, resolutions=args.res,
                    colors=args.colors, normals=args.normals, overwrite=args.force, progress=progress)
    if not args.quiet:
        n = made.image.shape
        against = "the input image" if source.suffix.lower() in READ_IMAGE_FORMATS else "the mesh"
        budget = f" (budget {args.bytes})" if args.bytes else ""
        extra = [what for what, got in (("colours", made.image.colors), ("normals", made.image.normals))
                 if got is not None]
        tint = f", with its {' and '.join(extra)}" if extra else ""
        on = f" displaced on a {made.base} x {made.base} base" if made.base else ""
        print(f"wrote {args.output}: {made.nbytes} bytes{budget}, a {n[1]} x {n[0]} {made.image.domain.kind} "
              f"image{on}{tint}, PSNR to {against} {made.psnr_db:.1f} dB")
        for t in made.tried:
            what = (f"{t['bytes']} bytes, {t['psnr_db']} dB" if "bytes" in t else
                    f"needs at least {t['least_bytes']} bytes" if "least_bytes" in t else
                    f"at best {t['best_psnr_db']} dB")
            fit = f", offsets fitted, bending {t['fitted']}" if "fitted" in t else ""
            base = f" on {t['base']} x {t['base']} ({t['share']:.0%} of the budget{fit})" if "base" in t else ""
            print(f"  {t['resolution']} x {t['resolution']}{base}: {what}")
    return 0


def _component(text: str) -> str | int:
    from ._convert import COMPONENT_CHOICES
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
        levels, offsets = image.metadata.get("jpeg2000_levels"), image.metadata.get("jpeg2000_offset_levels")
        held = ([f"{levels} wavelet levels"] if levels else []) + (
            ["no offsets (the base alone)" if offsets == "none" else f"the offsets' {offsets} wavelet levels"]
            if offsets else [])
        part = f"; from its first {image.metadata['jpeg2000_bytes']} bytes: {', '.join(held)}" if held else ""
        print(f"wrote {out}: {mesh.n_vertices} vertices, {mesh.n_faces} quads{also}{part}")
    return 0


def cmd_landmarks(args) -> int:
    from .animation import Renderer, label_points, save_png
    _check_outputs(args.force, (args.output, (".csv",), "the landmarks"), (args.picture, (".png",), "the picture"))
    if args.picture:
        require("moderngl", "rendering")
        require("imageio", "writing pictures")
    mesh = load_mesh(args.mesh)
    from .mesh import suggest_landmarks
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


def _point(p) -> str:
    """``[x, y, z]`` with 6 significant digits (rounding by scaling would overflow near 1e308)."""
    return "[" + ", ".join(f"{float(x):.6g}" for x in p) + "]"


def cmd_info(args) -> int:
    from .mesh import topology
    path = Path(args.file)
    if path.suffix.lower() in READ_IMAGE_FORMATS:
        img = _read_image(path, args)
        H, W = img.shape
        print(
            f"{path}: geometry image {W} x {H}, domain {img.domain.kind}, {int(img.valid.sum())} valid pixels, "
            f"normals {'yes' if img.normals is not None else 'no'}, colours {'yes' if img.colors is not None else 'no'}"
        )
        lo, hi = img.pixels[img.valid].min(axis=0), img.pixels[img.valid].max(axis=0)
        print(f"  bounding box {_point(lo)} .. {_point(hi)}")
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
    print(f"  bounding box {_point(v.min(axis=0))} .. {_point(v.max(axis=0))}, "
          f"diagonal {mesh.bounding_box_diagonal():.6g}")
    print(f"  per-vertex UVs: {'yes' if mesh.uv is not None else 'no'}")
    t = topology(mesh)
    print(f"  topology: {t.describe()}; Euler characteristic {t.euler}, {t.boundary_edges} boundary edges")
    return 0


def _curvature_title(name: str, scale: float) -> str:
    """The title of a curvature picture: which curvature, at what smoothing scale."""
    if not scale:
        return f"{name} curvature, no smoothing"
    return f"{name} curvature at {100 * scale:g}% of the diagonal"


def _demo_pictures(image, stem: Path, progress) -> list:
    """A rendering of the quad mesh, of it mean-filtered, and a mean-curvature map; none when there is
    no headless OpenGL (the reason is printed).
    """
    from .animation import RenderError, Renderer, save_png
    scale = DEFAULT_CURVATURE_SCALE
    written = [save_colormap(image_curvature(image, scale)[1], stem.with_name(stem.name + "_mean_curvature.png"),
                             image.valid, overwrite=True, title=_curvature_title("mean", scale))]
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
    from ._convert import mesh_to_image
    from .surface import CoverageWeights
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
    image = mesh_to_image(mesh, args.res, weights=CoverageWeights(s=args.s), progress=progress)
    image.metadata["source"] = src.name
    t1 = time.perf_counter()
    stem = src.stem
    files = [image.save(out / f"{stem}.exr", overwrite=True),
             image.preview(out / f"{stem}_preview.png", overwrite=True)]
    quads = load_image(files[0]).to_mesh()
    files.append(save_mesh(quads, out / f"{stem}_quads.obj", overwrite=True))
    files += _demo_pictures(image, out / stem, progress)
    H, W = image.shape
    if args.quiet:
        return 0
    m = image.metadata                                  # how far the result lies from what it approximates
    print(f"geoimg demo on {src.name}: {mesh.n_vertices} vertices, {mesh.n_faces} faces")
    print(f"  surface ({m['weights']} weights, s = {m['s']:.3g}): {W} x {H} geometry image in {t1 - t0:.2f} s "
          f"(first run includes numba compilation, cached afterwards)")
    print(f"  quad mesh to input mesh: PSNR {m['psnr_db']:.1f} dB, Hausdorff {m['hausdorff']:.2e} of the "
          "bounding-box diagonal")
    print(f"  quad mesh: {quads.n_vertices} vertices, {quads.n_faces} quads")
    for f in files:
        print(f"  wrote {f}")
    return 0


def cmd_filter(args) -> int:
    from ._steps import apply_steps
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
    stem = Path(args.output)
    if stem.is_dir() or not stem.name or str(args.output).endswith(("/", os.sep)):    # a folder: the input's name
        stem = stem / Path(args.image).stem
    image = _read_image(args.image, args)
    K, H = image_curvature(image, args.scale)
    jobs: list = []
    for name, values in (("gaussian", K), ("mean", H)):
        title = _curvature_title(name, args.scale)
        jobs.append((stem.with_name(f"{stem.name}_{name}.exr"),
                     lambda tmp, v=values, n=name: save_scalar(v, tmp, n, overwrite=True)))
        jobs.append((stem.with_name(f"{stem.name}_{name}.png"),
                     lambda tmp, v=values, t=title: save_colormap(v, tmp, image.valid, overwrite=True, title=t)))
    normals = image.normals if image.normals is not None else grid_normals(image.pixels, image.domain.orientation)
    jobs.append((stem.with_name(f"{stem.name}_normals.png"),
                 lambda tmp: save_normal_map(normals, tmp, image.valid, overwrite=True)))
    written = write_all(jobs, overwrite=args.force)
    if not args.quiet:
        for f in written:
            print(f"wrote {f}")
    return 0


def cmd_render(args) -> int:
    from .animation import Renderer, save_png
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
    is not numbers, a header, is skipped), as an (L, keys) int array.
    """
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
    from .animation import Renderer, frame_jobs, morph, save_animation, save_glb
    from .spectrum._transform import check_lmax
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
    if args.spectral is not None:
        check_lmax(args.spectral)                     # before any work
        if args.landmarks is not None:
            raise InputError("--spectral and --landmarks: the harmonics' ellipsoids make the correspondence; give "
                             "one or the other")
    landmarks = args.landmarks if args.landmarks in (None, "auto") else read_landmarks(args.landmarks,
                                                                                      len(args.shapes))
    shapes = []
    for f in args.shapes:
        progress(f"loading {f}")
        shapes.append(_load_shape(f, args))
    m = morph(*shapes, frames=args.frames, easing=args.easing, align=args.align, rotate=not args.no_rotate,
              resolution=args.res, resample=True, landmarks=landmarks, spectral=args.spectral, progress=progress)
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
            if "sphere_turn_deg" in entry:
                parts.append(f"sphere turned {entry['sphere_turn_deg']:.1f} deg")
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
    (logs, CI); nothing when quiet.
    """

    def __init__(self, quiet: bool = False, every: float = 5.0, stream=None, width: int = 30):
        self.stream = stream or sys.stderr
        self.quiet, self.every, self.width = quiet, every, width
        self.tty = self.stream.isatty()
        self.last = None

    @staticmethod
    def _describe(c: dict) -> str:
        eta = "" if c["eta"] is None or c["done"] >= c["total"] else f", {_duration(c['eta'])} left"
        skipped = f" ({c['skipped']} done before)" if c["skipped"] else ""
        return (f"{c['done']}/{c['total']} done{skipped}, {c['poor']} poor, {c['refused']} refused, "
                f"{c['failed']} failed, "
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
    from .batch._options import BatchOptions
    from .batch import convert as convert_batch
    opts = _conversion_options(args, BatchOptions, normals=not args.no_normals, steps=args.ops or (),
                               quads=args.quads is not None, quads_format=args.quads or "obj", psnr=not args.no_psnr)
    options = {f.name: getattr(opts, f.name) for f in dataclasses.fields(opts)}
    if args.component is None:
        del options["component"]                # the batch's own default (largest piece, for a Zarr store)
    table = convert_batch(args.inputs, args.output, zarr=args.zarr, manifest=args.manifest, workers=args.workers,
                          memory_limit=args.memory_limit, scheduler=args.scheduler, force=args.force,
                          progress=BatchProgress(args.quiet, args.progress_every), **options)
    c = table.attrs["summary"]
    bad = c["poor"] + c["refused"] + c["failed"]
    spectra = Path(args.output) / "harmonics.csv"
    if args.harmonics is not None and not args.quiet and spectra.is_file():
        print(f"coefficient table (normalized, degree {args.harmonics}): {spectra} and .parquet")
    if not args.quiet:
        skipped = f" ({c['skipped']} of these finished by an earlier run)" if c["skipped"] else ""
        print(
            f"{c['total']} inputs: {c['ok'] + c['poor']} converted ({c['poor']} of them poor), {c['refused']} "
            f"refused, {c['failed']} failed{skipped} in {_duration(c['elapsed'])}; manifest {table.attrs['manifest']}"
        )
    if bad:
        print(f"geoimg batch: {bad} of {c['total']} inputs were not converted, or converted poorly (all reasons in "
              f"{table.attrs['manifest']}):", file=sys.stderr)
        failed = table[table["status"] != "ok"]
        for _, row in failed.head(BATCH_PROBLEMS_SHOWN).iterrows():
            print(f"  {row['input']}: {row['status']}: {row['message']}", file=sys.stderr)
        if len(failed) > BATCH_PROBLEMS_SHOWN:
            print(f"  ... and {len(failed) - BATCH_PROBLEMS_SHOWN} more", file=sys.stderr)
    return 1 if bad else 0

