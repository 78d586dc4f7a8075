"""One input of a batch, on a worker: load, convert, filter, write, measure; every outcome is a manifest row
(a refusal or a crash is a row too, never an exception that stops the batch).
"""
from __future__ import annotations

import dataclasses
import datetime
import os
import socket
import time
import warnings
from pathlib import Path

import numba
import numpy as np

from .._atomic import write_all
from .._convert import _timed, mesh_to_images, poor_reason
from .._steps import apply_steps
from ..errors import GeoimgError, MeshError
from ..image import OctahedralDomain
from ..spectrum import harmonics
from ..spectrum._harmonics import require_sphere_topology
from ..mesh import Mesh, load_mesh, mesh_file_jobs, surface_distance, topology
from ._options import BatchOptions
from ._store import write_item

__all__ = ["Job", "run_job", "warnings_cell", "PSNR_SAMPLES", "WARNINGS_CELL", "SPECTRUM_SUFFIX"]

SPECTRUM_SUFFIX = "_sh.npz"    # an input's harmonics, beside its image

PSNR_SAMPLES = 10000          # area samples on each surface for the quad mesh's distance to the input: ±0.2 dB,
                              # but up to 1.2 dB where the error sits in a few spikes (trimesh's mode5.gltf)


@dataclasses.dataclass(frozen=True)
class Job:
    """One input: its path, where its outputs go (``stem`` + extension, numbered per piece) or which item
    of the Zarr store, the options and their hash, and the input's size and time stamp (to recognize it).
    """

    input: str
    stem: str
    options: BatchOptions
    options_hash: str
    input_size: int
    input_mtime_ns: int
    store: str | None = None
    index: int = 0
    threads: int | None = None


def _share_threads(threads: int | None) -> None:
    """Use at most ``threads`` numba threads in this task. Worker processes that share a machine must not each
    run a thread per core: OpenMP's spinning threads then take turns and every parallel call waits
    milliseconds (measured: 5 us per call alone, 65-90 us with two such workers). Set here, in the task,
    because a worker may have imported numba, and so read NUMBA_NUM_THREADS, before its environment was set.
    """
    if threads:
        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))   # type: ignore[attr-defined]


WARNINGS_CELL = 2000          # characters of warnings a manifest row keeps


def warnings_cell(messages, limit: int = WARNINGS_CELL) -> str:
    r"""The warnings of one input as one manifest cell: each once (with how many times it came when more than
    once), each on one line, cut at ``limit`` characters with a count of what was left out.

    Examples
    --------
    >>> warnings_cell(["far from its mesh", "joined 3\n vertices", "far from its mesh"])
    'far from its mesh (x2) | joined 3 vertices'
    >>> warnings_cell(["a" * 30, "b" * 30, "c"], limit=40)
    'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaa | ... (2 more warnings)'
    """
    counts: dict[str, int] = {}
    for m in messages:
        text = " ".join(m.split())
        counts[text] = counts.get(text, 0) + 1
    parts = [t if n == 1 else f"{t} (x{n})" for t, n in counts.items()]
    out: list[str] = []
    for part in parts:
        if len(" | ".join(out + [part])) > limit:
            if not out:          # the first one alone is too long: its start
                out.append(part[:limit - 30] + "...")
            break
        out.append(part)
    left = len(parts) - len(out)
    if left:
        out.append(f"... ({left} more warning{'s' if left > 1 else ''})")
    return " | ".join(out)


def _one_line(error: BaseException) -> str:
    text = " ".join(str(error).split()) or type(error).__name__
    return text if isinstance(error, GeoimgError) else f"{type(error).__name__}: {text}"


def _joined(meshes: list[Mesh]) -> Mesh:
    """Several quad meshes as one (their vertices side by side)."""
    offsets = np.cumsum([0] + [m.n_vertices for m in meshes[:-1]])
    faces = [np.where(m.faces >= 0, m.faces + o, -1) for m, o in zip(meshes, offsets)]
    return Mesh(np.vstack([m.vertices for m in meshes]), np.vstack(faces))


def _outputs(job: Job, images) -> list[tuple[Path, object]]:
    """(path, writer) of every file of one input: NAME.exr, or NAME_K.exr for piece K of several; the quad
    meshes beside them.
    """
    many = len(images) > 1
    jobs = []
    for image in images:
        name = job.stem + (f"_{image.metadata.get('component', 0)}" if many else "")
        if job.store is None:
            jobs += image.save_jobs(Path(name + ".exr"))
        if job.options.quads:
            jobs += mesh_file_jobs(image.to_mesh(), Path(f"{name}_quads.{job.options.quads_format}"))
    return jobs


def _harmonics(images, lmax: int | None, timings: dict):
    """The harmonics of a batch input's one octahedral image (None when not asked for)."""
    if lmax is None:
        return None
    if len(images) != 1 or not isinstance(images[0].domain, OctahedralDomain):
        raise MeshError(f"harmonics need one closed genus-0 piece, mapped onto the sphere; this input gave "
                        f"{' and '.join(img.domain.kind for img in images)} images")
    with _timed(timings, "harmonics"):
        return harmonics(images[0], lmax)                  # its metadata names the image's source


def run_job(job: Job) -> dict:
    """Convert one input as ``job`` says and return its manifest row (see :data:`COLUMNS`)."""
    opts = job.options
    _share_threads(job.threads)
    row: dict = {"input": job.input, "options_hash": job.options_hash, "input_size": job.input_size,
           "input_mtime_ns": job.input_mtime_ns, "worker": f"{socket.gethostname()}:{os.getpid()}"}
    timings: dict = {}
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            with _timed(timings, "load"):
                mesh = load_mesh(job.input)
            top = topology(mesh)
            row.update(vertices=mesh.n_vertices, faces=mesh.n_faces, topology=top.describe())
            if opts.harmonics and opts.component == "all":
                require_sphere_topology(top)                    # refused before the conversion
            images = mesh_to_images(mesh, options=opts.conversion(), timings=timings)
            for image in images:
                image.metadata["source"] = Path(job.input).name
            spectra = _harmonics(images, opts.harmonics, timings)      # of the shape, before any filter step
            if opts.steps:
                with _timed(timings, "filter"):
                    images = [apply_steps(img, opts.steps, mode=opts.mode, nsr=opts.nsr) for img in images]
            with _timed(timings, "write"):
                Path(job.stem).parent.mkdir(parents=True, exist_ok=True)
                outputs = _outputs(job, images)
                if spectra is not None:
                    outputs.append((Path(job.stem + SPECTRUM_SUFFIX), lambda tmp: spectra.save(tmp, overwrite=True)))
                files = write_all(outputs, overwrite=True)             # all of this input's files, or none
                if job.store is not None:
                    write_item(job.store, job.index, images[0])
            row.update(
                pieces=images[0].metadata.get("components", 1),
                domain=" ".join(img.domain.kind for img in images),
                image_size=" ".join(f"{img.shape[1]}x{img.shape[0]}" for img in images),
                # each piece's map: its L2 stretch and the share of the surface it starves (when measured)
                map_stretch=" ".join(str(img.metadata.get("map_stretch", "")) for img in images).strip(),
                starved=" ".join(str(img.metadata.get("starved", "")) for img in images).strip(),
            )
            row["outputs"] = ";".join([str(f) for f in files] + ([f"{job.store}#{job.index}"] if job.store else []))
            if opts.psnr and (opts.component == "all" or row["pieces"] == 1):
                with _timed(timings, "psnr"):
                    dist = surface_distance(mesh, _joined([img.to_mesh() for img in images]), n=PSNR_SAMPLES)
                row.update(psnr_db=round(dist["psnr_db"], 2), hausdorff=float(f"{dist['hausdorff_rel']:.4g}"))
            if job.store is not None:
                row["record"] = {"source": job.input, "shape": list(images[0].shape),
                                 "domain": images[0].domain.kind,
                                 "metadata": images[0].metadata_record(), "normals": images[0].normals is not None,
                                 "colors": images[0].colors is not None,
                                 "psnr_db": row.get("psnr_db"), "options_hash": job.options_hash,
                                 "timings": {k: round(v, 4) for k, v in timings.items()}}
            poor = poor_reason(row["psnr_db"], row["hausdorff"], opts.min_psnr, opts.max_hausdorff) \
                if "psnr_db" in row else ""
            row.update(status="poor" if poor else "ok", message=f"far from the input: {poor}" if poor else "")
        except GeoimgError as e:
            row.update(status="refused", message=_one_line(e))
        except Exception as e:               # a bug or a system error: recorded, and the batch goes on
            row.update(status="failed", message=_one_line(e))
    row["warnings"] = warnings_cell(str(w.message) for w in caught)
    for stage, seconds in timings.items():
        row[f"t_{stage}"] = round(seconds, 4)
    row["t_total"] = round(time.perf_counter() - t0, 4)
    row["finished"] = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    if job.store is not None and "record" in row:
        row["record"]["timings"]["total"] = row["t_total"]
    return row
