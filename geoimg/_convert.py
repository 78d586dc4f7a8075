"""Mesh to geometry image in one call: load, repair, parametrize, fit the weighted-mean surface, sample."""
from __future__ import annotations

import numbers
import time
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from ._choices import COMPONENT_CHOICES, POOR_HAUSDORFF, POOR_PSNR_DB
from ._options import ConversionOptions
from .errors import InputTypeError, MeshError, ParametrizationError
from .image import GeometryImage
from .mesh import Mesh, load_mesh, repair, surface_distance
from .mesh._metrics import ReferenceDistances
from .parametrization import Parametrization, map_stretch, parametrize
from .surface import CoverageWeights, SmoothnessMap, fit_surface
from .surface._coverage import prefilter_s
from .surface._attributes import sample_colors
from .surface._base import check_backend
from ._types import Progress
from ._threads import fixed_order

__all__ = ["mesh_to_image", "mesh_to_images", "measure_fidelity", "poor_reason", "COMPONENT_CHOICES",
           "FIDELITY_SAMPLES", "LIMIT_S", "POOR_PSNR_DB", "POOR_HAUSDORFF"]

FIDELITY_SAMPLES = 20000     # area samples a side for the fidelity every conversion reports (about 0.1 dB)
LIMIT_S = 1e-4               # coverage weights this narrow: the mesh resampled as it is (the limit s -> 0)



@contextmanager
def _timed(timings: dict | None, stage: str):
    """Add the seconds spent in the block to ``timings[stage]`` (when timings are asked for)."""
    t0 = time.perf_counter()
    try:
        yield
    finally:
        if timings is not None:
            timings[stage] = timings.get(stage, 0.0) + time.perf_counter() - t0


def _s_in_its_old_place(options, option_values: dict):
    """``options``, or None with ``option_values["s"]`` set when it is the number (or per-face values) that
    earlier releases took in its place (deprecated; :meth:`ConversionOptions.create` says so).
    """
    if isinstance(options, (numbers.Real, np.ndarray, list, tuple, SmoothnessMap)) and not isinstance(options, bool):
        option_values["s"] = options
        return None
    return options


def _load(mesh_or_path, say) -> tuple[Mesh, str]:
    if isinstance(mesh_or_path, Mesh):
        return mesh_or_path, ""
    if isinstance(mesh_or_path, (str, Path)):
        say(f"loading {mesh_or_path}")
        return load_mesh(mesh_or_path), Path(mesh_or_path).name
    raise InputTypeError(f"mesh_or_path: expected a geoimg.Mesh or a file path, got {type(mesh_or_path).__name__}")


@fixed_order
def mesh_to_images(mesh_or_path: Any, resolution: int | None = None, options: ConversionOptions | None = None, *,
                   backend: str = "cpu", progress: Progress | None = None, timings: dict | None = None,
                   fidelity: bool = True, **option_values: Any) -> list[GeometryImage]:
    """The geometry images of a mesh's pieces, largest first, after the repairs of
    :func:`geoimg.mesh.repair` (pinch vertices split, non-manifold edges separated, faces oriented, each
    announced with a warning): one image per piece, or only the ``"largest"`` or the ``K``-th
    (``component``). The options (and ``timings``) are :func:`mesh_to_image`'s; for a mesh of several pieces,
    ``metadata["component"]`` is the piece's number and ``metadata["components"]`` how many there were.
    A piece whose map is refused (a lone triangle has no four corners for a square) is left out with a
    warning, the others converted; when every piece is refused, the first refusal is raised.

    Parameters
    ----------
    mesh_or_path : Mesh or path-like
        The mesh, or a mesh file (read by :func:`geoimg.load_mesh`).
    resolution : int or None
        Pixels along the longer side (see :func:`mesh_to_image`).
    options : ConversionOptions, optional
        The conversion's options; ``options.component`` says which pieces: all of them, the largest, or the
        K-th (0: the largest).
    backend, progress, fidelity
        As :func:`mesh_to_image` takes them.
    timings : dict or None
        Filled with seconds per stage, summed over the pieces.
    **option_values
        Fields of :class:`~geoimg.ConversionOptions` (``component``, ``method``, ``weights``, ...), replacing
        those of ``options``.

    Returns
    -------
    list of GeometryImage
        One image per piece converted, largest first.

    Raises
    ------
    ParametrizationError
        When every piece's map is refused.
    InputError
        On bad options.

    Examples
    --------
    >>> import geoimg, warnings
    >>> quad = [[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]]
    >>> m = geoimg.Mesh(quad + [[x + 3, y, z] for x, y, z in quad], [[0, 1, 2, 3], [4, 5, 6, 7]])
    >>> with warnings.catch_warnings(record=True):
    ...     images = mesh_to_images(m, 5, method="heightfield", axis="z", weights=geoimg.CoverageWeights(s=2.0))
    >>> [img.metadata["component"] for img in images], images[1].pixels[0, 0, 0].item()
    ([0, 1], 3.0)
    """
    check_backend(backend)       # before the work: a GPU asked for and missing is said at once, and the options
    options = _s_in_its_old_place(options, option_values)
    if resolution is not None:
        option_values["resolution"] = resolution
    opts = ConversionOptions.create(options, caller="mesh_to_images", stacklevel=4, **option_values)
    component = opts.component
    say = progress or (lambda message: None)
    with _timed(timings, "load"):
        mesh, source = _load(mesh_or_path, say)
    with _timed(timings, "repair"):
        pieces = repair(mesh)
    if component == "largest":
        chosen = [0]
    elif component == "all":
        chosen = list(range(len(pieces)))
    elif isinstance(component, int) and not isinstance(component, bool) and 0 <= component < len(pieces):
        chosen = [component]
    else:
        raise MeshError(f"component: expected 'all', 'largest' or a piece number from 0 to {len(pieces) - 1}, "
                        f"got {component!r}")
    images, refused = [], []
    for k in chosen:
        if len(pieces) > 1:
            say(f"piece {k} of {len(pieces)}: {pieces[k].mesh.n_faces} faces")
        try:
            image = mesh_to_image(pieces[k].mesh, options=opts, backend=backend, progress=progress,
                                  timings=timings, fidelity=fidelity)
        except ParametrizationError as e:
            if len(chosen) == 1:
                raise
            refused.append((k, e))          # one piece that cannot be mapped (a lone triangle) spoils no other
            continue
        image.metadata["source"] = source
        if len(pieces) > 1:
            image.metadata.update(component=k, components=len(pieces))
        images.append(image)
    if refused and not images:
        raise refused[0][1]
    if refused:
        first, why = refused[0]
        warnings.warn(f"{len(refused)} of {len(pieces)} pieces left out, their map refused (piece {first}, "
                      f"{pieces[first].mesh.n_faces} faces: {why})", stacklevel=2)
    return images


@fixed_order
def mesh_to_image(mesh_or_path: Any, resolution: int | None = None, options: ConversionOptions | None = None, *,
                  backend: str = "cpu", parametrization: Parametrization | None = None,
                  progress: Progress | None = None, timings: dict | None = None,
                  fidelity: bool = True, **option_values: Any) -> GeometryImage:
    """The geometry image of a mesh: :func:`~geoimg.parametrize`, :func:`~geoimg.fit_surface` and
    :meth:`~geoimg.Surface.sample` in one call. A mesh of several pieces, or one that needs repairs
    before it can be parametrized, goes through :func:`mesh_to_images`.

    By default the image is as close to the mesh as its resolution allows: coverage weights whose width is
    0.4 of a pixel spacing (:func:`geoimg.surface.prefilter_s`), a prefilter for the grid rather than a
    smoothing of the shape; with ``fidelity`` the mesh resampled as it is (width :data:`LIMIT_S`) is measured
    too, and taken where it lies closer (maps made of slivers, where the prefilter's rounding costs more than
    it gains). Smoothing is asked for with the weights' ``s`` (or filters afterwards).

    Parameters
    ----------
    mesh_or_path : Mesh or str or path-like
        A mesh, or a mesh file (see :func:`geoimg.load_mesh`).
    resolution : int, optional
        Pixels along the longer side; default from the weights' width
        (:meth:`~geoimg.Surface.auto_resolution`). A cut-open image (meshes with handles or several boundary
        loops) needs N - 1 a multiple of 64 (65, 129, 257, 513, ...).
    options : ConversionOptions, optional
        The conversion's options (:class:`~geoimg.ConversionOptions`): the weights (default
        ``CoverageWeights()``: the width that serves the resolution, ``sigma`` 0.4 of a pixel spacing;
        ``CoverageWeights(s=...)`` or ``GaussianWeights(s=...)`` smooth), the parametrization's ``method,
        axis, boundary, balance`` (ignored when ``parametrization`` is given), ``normals`` (exact normals
        stored) and ``colors`` (the mesh's texture or vertex colours, each pixel's interpolated in the face
        that holds it, :mod:`geoimg.surface._attributes`).
    **option_values
        Fields of :class:`~geoimg.ConversionOptions` by name (``method="sphere"``,
        ``weights=GaussianWeights(s=2)``, ...), replacing those of ``options``. The flat ``s``, ``n``,
        ``tol``, ``sliver_rule`` and ``weights`` as a name of earlier releases still work, deprecated.
    backend : {"cpu", "cuda"}, default "cpu"
        Where the sampling's Gaussian sums run (see :meth:`~geoimg.Surface.sample`).
    parametrization : Parametrization, optional
        Use this one (for example shared by meshes with the same faces) instead of making one.
    progress : callable, optional
        Called with a short message at each stage.
    timings : dict, optional
        Seconds spent per stage are added to it (``load``, ``repair``, ``parametrize``, ``fit``,
        ``sample``, ``colors``, ``fidelity``; summed over pieces).
    fidelity : bool, default True
        Measure the image's quad mesh against the mesh (:func:`geoimg.mesh.surface_distance` with
        :data:`FIDELITY_SAMPLES` samples a side) into ``metadata["psnr_db"]`` and ``metadata["hausdorff"]``
        (relative to the bounding-box diagonal), with a warning when the image is far from the mesh (below
        :data:`POOR_PSNR_DB` or above :data:`POOR_HAUSDORFF`); and the map's L2 stretch and starved share
        (:func:`geoimg.parametrization.map_stretch`) into ``metadata["map_stretch"]`` and
        ``metadata["starved"]``. The map's stages (``info["stages"]``) go into ``metadata["map_stages"]``
        either way.

    Returns
    -------
    GeometryImage
        Its metadata records the source file's name (``source``) and the parametrization method.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> img = mesh_to_image(m, 9, method="heightfield", axis="z", weights=geoimg.CoverageWeights(s=2.0))
    >>> img.shape, img.metadata["parametrization"]
    ((9, 9), 'heightfield')
    """
    check_backend(backend)
    options = _s_in_its_old_place(options, option_values)
    if resolution is not None:
        option_values["resolution"] = resolution
    opts = ConversionOptions.create(options, caller="mesh_to_image", stacklevel=4, **option_values)  # before the work
    resolution, weights, normals = opts.resolution, opts.weights, opts.normals
    method = opts.method
    say = progress or (lambda message: None)
    with _timed(timings, "load"):
        mesh, source = _load(mesh_or_path, say)
    if parametrization is None:
        say(f"{mesh.n_vertices} vertices, {mesh.n_faces} faces; parametrizing ({method})")
        with _timed(timings, "parametrize"):
            parametrization = parametrize(mesh, method, axis=opts.axis, boundary=opts.boundary,
                                          balance=opts.balance, progress=progress)
    serve = isinstance(weights, CoverageWeights) and weights.s is None       # the width that serves the resolution
    say(f"parametrized by {parametrization.method}; fitting the surface "
        f"({'s for the resolution' if serve else f's={weights.s}'}, {weights.kind} weights)")
    with _timed(timings, "fit"):
        surface = fit_surface(mesh, parametrization, weights)
    res = surface.auto_resolution() if resolution is None else surface.domain.round_resolution(resolution)
    if resolution is not None and res != resolution:
        warnings.warn(f"resolution {resolution}: {surface.domain.size_rule()}; sampled at {res}", stacklevel=2)
    if serve:
        surface = surface.with_s(prefilter_s(surface, res))     # type: ignore[attr-defined,arg-type]   # coverage
    say(f"sampling {res} pixels along the longer side")
    with _timed(timings, "sample"):
        image = surface.sample(res, normals=normals, backend=backend)
    measured = None
    if serve and fidelity:      # the prefilter, or the mesh resampled as it is, whichever lies closer to it
        say("measuring the image against the mesh, and the mesh resampled as it is")
        with _timed(timings, "fidelity"):
            against = ReferenceDistances(mesh, FIDELITY_SAMPLES)     # the mesh's samples and tree, made once
            plain = surface.with_s(LIMIT_S).sample(res, normals=normals)        # type: ignore[attr-defined]
            k, measured = against.closest([image.to_mesh(), plain.to_mesh()])    # the prefilter's on a tie
            image = (image, plain)[k]
    if opts.colors and (mesh.colors is not None or mesh.texture is not None):
        say("sampling the colours")
        with _timed(timings, "colors"):
            rgb = sample_colors(mesh, parametrization, image.domain, image.shape, image.valid)
        image = image if rgb is None else GeometryImage(image.pixels, image.mask, image.domain, image.normals,
                                                        image.metadata, colors=rgb)
    image.metadata["source"] = source
    image.metadata["parametrization"] = parametrization.method
    stages = parametrization.info.get("stages")
    if stages:              # a sphere map: which stages ran, the folds each left; a disk or cut map: its start
        image.metadata["map_stages"] = "; ".join(stages)
    normal = parametrization.info.get("normal")
    if normal is not None:                       # a terrain's up axis, for pictures
        image.metadata["up"] = "xyz"[int(np.argmax(np.abs(normal)))]
    if fidelity:
        say("measuring the image against the mesh")
        with _timed(timings, "fidelity"):
            measure_fidelity(image, mesh, measured, smoothed=not serve)
            stretch = map_stretch(mesh, parametrization)         # where the map squeezes, before it shows
            image.metadata.update(map_stretch=round(stretch["l2"], 3), starved=round(stretch["starved"], 4))
    return image


def _distance(image: GeometryImage, mesh: Mesh) -> dict:
    return surface_distance(mesh, image.to_mesh(), n=FIDELITY_SAMPLES)


def measure_fidelity(image: GeometryImage, mesh: Mesh, measured: dict | None = None, *,
                     smoothed: bool = False) -> dict:
    """How close ``image``'s quad mesh lies to ``mesh``: ``psnr_db`` and ``hausdorff`` (relative to the
    mesh's bounding-box diagonal) from :func:`geoimg.mesh.surface_distance` with :data:`FIDELITY_SAMPLES`
    area samples a side (or ``measured``, its result already), recorded in ``image.metadata``; a warning says
    when the image is far from the mesh (PSNR below :data:`POOR_PSNR_DB` or Hausdorff above
    :data:`POOR_HAUSDORFF`), and names the smoothing asked for (``smoothed``) as a cause.
    """
    d = measured if measured is not None else _distance(image, mesh)
    record = {"psnr_db": round(float(d["psnr_db"]), 2), "hausdorff": float(f"{d['hausdorff_rel']:.4g}")}
    image.metadata.update(record)
    why = poor_reason(record["psnr_db"], record["hausdorff"], POOR_PSNR_DB, POOR_HAUSDORFF)
    if why:
        cause = (f"the smoothing asked for (s = {image.metadata.get('s')}) rounds it that far, or its map squeezes "
                 "part of the shape; try a smaller --s" if smoothed else
                 "its map squeezes or folds part of the shape; see the map's stretch in the parametrization, or try "
                 "another --method")
        warnings.warn(f"the image is far from its mesh ({why}): {cause}", stacklevel=3)
    return record


def poor_reason(psnr_db: float, hausdorff: float, min_psnr: float = POOR_PSNR_DB,
                max_hausdorff: float = POOR_HAUSDORFF) -> str:
    """Why an image at ``psnr_db`` and relative ``hausdorff`` from its mesh is poor ('' when it is not)."""
    reasons = []
    if psnr_db < min_psnr:
        reasons.append(f"PSNR {psnr_db:.1f} dB < {min_psnr:g}")
    if hausdorff > max_hausdorff:
        reasons.append(f"Hausdorff {100 * hausdorff:.1f} % > {100 * max_hausdorff:g} % of the diagonal")
    return ", ".join(reasons)
