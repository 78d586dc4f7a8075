"""Convert a collection of meshes on Dask: an embedded local cluster by default, or any existing one; skips what
an earlier run with the same options finished, records every input in the manifest, and stops cleanly.
"""
from __future__ import annotations

import contextlib
import fnmatch
import logging
import os
import time
import uuid
from pathlib import Path
from typing import Any

from .._optional import require
from ..errors import InputError, InputTypeError
from ._inputs import find_inputs, output_stems
from ._manifest import ManifestLog, read_manifest, write_manifest
from ._options import BatchOptions
from ._store import open_store, store_records, write_records
from ._spectra import write_table
from ._task import SPECTRUM_SUFFIX, Job, run_job
from .._types import PathLike, Progress

__all__ = ["convert", "MANIFEST_NAME"]

MANIFEST_NAME = "manifest.csv"
RECORDS_EVERY = 5.0          # seconds between writes of the Zarr store's item records
PROGRESS_EVERY = 0.5         # seconds between calls of the progress callback
CONNECT_TIMEOUT = 30         # seconds to reach a scheduler given by its address


def _finished(row: dict | None, job: Job, records) -> bool:
    """Whether an earlier run's row says this job's outputs exist, made with the same options from the same
    file, or that it refused this very file with these options (a refusal is decided by the file and the
    options alone; a failure may be passing, and is tried again).
    """
    if not row or row.get("status") not in ("ok", "poor", "refused") or row.get("options_hash") != job.options_hash:
        return False
    if row.get("input_size") != str(job.input_size) or row.get("input_mtime_ns") != str(job.input_mtime_ns):
        return False
    for out in filter(None, row.get("outputs", "").split(";")):
        if "#" in out and job.store is not None:
            if records[job.index] is None:
                return False
        elif not Path(out).is_file():
            return False
    return True


def _partials(jobs, store) -> list[Path]:
    """Temporary files that an interrupted run may have left beside its outputs (ours and Zarr's): each
    output folder is listed once, whatever the number of inputs in it.
    """
    names: dict[Path, list[str]] = {}
    for job in jobs:
        stem = Path(job.stem)
        names.setdefault(stem.parent, []).append("." + stem.name)
    found: set[Path] = set()
    for folder, prefixes in names.items():
        if folder.is_dir():
            found.update(p for p in folder.glob(".*.tmp*")          # few: only what a killed run left
                         if any(fnmatch.fnmatchcase(p.name, f"{prefix}*.tmp*") for prefix in prefixes))
    if store is not None and Path(store).is_dir():
        found.update(Path(store).rglob("*.partial"))
    return sorted(found)


def _remove_partials(jobs, store) -> None:
    for p in _partials(jobs, store):
        p.unlink(missing_ok=True)


def _threads_per_worker(workers: int) -> int:
    """Numba threads for each of ``workers`` worker processes on this machine: its cores shared out."""
    return max(1, (os.cpu_count() or 1) // workers)


def _worker_env(workers: int, memory_limit) -> dict:
    """Environment of the local cluster's workers: numba threads shared out between them, and geoimg's
    memory budget within each worker's limit (so that a too-large input is refused, not killed).
    """
    dask_utils = require("dask.utils", "geoimg batch")
    psutil = require("psutil", "geoimg batch")
    total = psutil.virtual_memory().total
    per = total / workers if memory_limit in (None, "auto") else dask_utils.parse_bytes(str(memory_limit))
    return {"NUMBA_NUM_THREADS": str(_threads_per_worker(workers)),
            "OMP_NUM_THREADS": "1", "GEOIMG_MAX_MEMORY": str(int(0.8 * per))}


class _Cluster:
    """The Dask client to run on: the one given, one connected to ``scheduler``, or an embedded local cluster
    of worker processes (closed again on exit).
    """

    def __init__(self, client, scheduler, workers, memory_limit):
        self.client, self.scheduler, self.workers, self.memory_limit = client, scheduler, workers, memory_limit
        self.owned = []

    def __enter__(self):
        if self.client is not None:
            return self.client
        distributed = require("distributed", "geoimg batch")
        dask = require("dask", "geoimg batch")
        if self.scheduler:
            self.client = distributed.Client(self.scheduler, timeout=CONNECT_TIMEOUT)
            self.owned = [self.client]
            return self.client
        n = self.workers or os.cpu_count() or 1
        with dask.config.set({"distributed.scheduler.allowed-failures": 0}):   # a crashing input fails once
            cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                               memory_limit=self.memory_limit, dashboard_address=None,
                                               silence_logs=logging.CRITICAL, preload=["geoimg.batch._worker"],
                                               env=_worker_env(n, self.memory_limit))
        self.client = distributed.Client(cluster)
        self.owned = [self.client, cluster]
        return self.client

    def __exit__(self, *exc):
        for thing in self.owned:
            try:
                thing.close()
            except Exception:                   # closing after an interrupt may find it half-gone
                pass


def _counts(rows: dict, total: int, before: list[str], t0: float) -> dict:
    """Counts of a batch: ``rows`` finished in this run, ``before`` the statuses (ok or refused) of the inputs an
    earlier run finished and this one skipped, which count as what they were.
    """
    statuses = [r["status"] for r in rows.values()]
    done = len(statuses)
    elapsed = time.perf_counter() - t0
    rate = done / elapsed if elapsed > 0 and done else 0.0
    left = total - len(before) - done
    statuses += before
    return {"done": done + len(before), "ok": statuses.count("ok"), "poor": statuses.count("poor"),
            "refused": statuses.count("refused"),
            "failed": statuses.count("failed"), "skipped": len(before), "total": total, "elapsed": elapsed,
            "per_minute": 60 * rate, "eta": left / rate if rate else None}


def convert(inputs: Any, out: PathLike, client: Any = None, *, zarr: PathLike | None = None,
            manifest: PathLike | None = None, workers: int | None = None, memory_limit: str | int | None = "auto",
            scheduler: str | None = None, force: bool = False, progress: Progress | None = None, **options: Any) -> Any:
    """Convert every mesh of ``inputs`` into a geometry image, on Dask.

    Parameters
    ----------
    inputs : path or sequence of paths
        Files, folders (their mesh files, recursively) and glob patterns.
    out : path
        Output folder: one ``NAME.exr`` per input (``NAME_K.exr`` per piece of a mesh of several), named by
        the input's path below the inputs' common folder; the quad meshes with ``quads=True``; the manifest.
    client : dask.distributed.Client, optional
        Run on this client's cluster. Default: ``scheduler``'s, else an embedded local cluster of
        ``workers`` processes (default: one per core) with ``memory_limit`` each, the cores shared out
        between their numba threads. On a cluster of your own, set ``NUMBA_NUM_THREADS`` in each worker's
        environment to the cores it may use: workers that each run a thread per core slow each other down
        many times over.
    zarr : path, optional
        Write the images into this Zarr store instead of EXR files (one item per input: the largest piece
        unless ``component`` says otherwise; needs ``resolution``).
    manifest : path, optional
        The manifest (CSV, one row per input); default ``out/manifest.csv``.
    workers : int, optional
        Worker processes of the embedded cluster (default: one per core).
    memory_limit : str or int, optional
        Memory of each embedded worker (``"4GB"``, bytes, or ``"auto"``: the machine's memory shared out).
    scheduler : str, optional
        The address of an existing Dask scheduler (``tcp://HOST:8786``) to run on.
    force : bool
        Redo every input, and write into a folder (or replace a store) that holds something else. Without
        it, an input is skipped when an earlier run with the same options converted it (its outputs still
        there) or refused it, and the file has not changed since.
    progress : callable, optional
        Called every half second with counts: ``done, ok, poor, refused, failed, skipped, total, elapsed,
        per_minute, eta``. ``ok``, ``poor`` and ``refused`` include the ``skipped`` inputs, as an earlier run
        recorded them: a refusal stays a refusal on every rerun.
    **options
        Those of :class:`BatchOptions`: ``resolution, weights, method, axis, boundary, balance, component,
        normals, colors, steps, mode, nsr, quads, quads_format, psnr, min_psnr, max_hausdorff, harmonics``
        (the flat ``s, n, tol, sliver_rule`` of earlier releases still work, deprecated). With
        ``harmonics=L`` each input's coefficients go beside its image (``NAME_sh.npz``) and the batch's
        table of them, normalized, into ``out/harmonics.csv`` and ``out/harmonics.parquet`` (see
        :func:`geoimg.spectrum.coefficient_columns`).

    Returns
    -------
    pandas.DataFrame
        The manifest rows of ``inputs`` (see :data:`geoimg.batch.COLUMNS`); ``attrs["summary"]`` holds the
        final counts and ``attrs["manifest"]`` the manifest's path. Skipped inputs keep their rows.

    Raises
    ------
    InputError, FileNotFoundError, FileExistsError
        Bad options, missing inputs, an output folder or store that holds something else: before any work.

    Examples
    --------
    >>> import tempfile, pathlib, distributed, geoimg
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0.2], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> (folder / "meshes").mkdir()
    >>> _ = geoimg.save_mesh(m, folder / "meshes" / "quad.obj")
    >>> with distributed.Client(processes=False, n_workers=1, dashboard_address=None) as client:
    ...     table = convert([folder / "meshes"], folder / "images", client, resolution=9, method="heightfield",
    ...                     axis="z")
    >>> table["status"].tolist(), (folder / "images" / "quad.exr").exists()
    (['ok'], True)
    """
    pandas = require("pandas", "geoimg batch")
    if zarr is not None:
        options.setdefault("component", "largest")
    try:
        opts = BatchOptions.create(caller="convert", stacklevel=4, **options)
    except TypeError as e:
        raise InputTypeError(f"convert: {e}") from None
    if zarr is not None and opts.resolution is None:
        raise InputError("a Zarr store holds same-size images: give the resolution (--res)")
    if opts.harmonics is not None:
        require("pyarrow", "the harmonics table's Parquet file")
        if zarr is not None:
            raise InputError("harmonics: the coefficient files go beside EXR images, not into a Zarr store")
    if zarr is not None and opts.component == "all":
        raise InputError("a Zarr store holds one image per input: component 'largest' or a piece number")
    if memory_limit not in (None, "auto"):
        try:
            require("dask.utils", "geoimg batch").parse_bytes(str(memory_limit))
        except ValueError:
            raise InputError(f"memory_limit: expected a size such as 4GB or auto, got {memory_limit!r}") from None
    files = find_inputs(inputs)
    out = Path(out)
    for spec in [inputs] if isinstance(inputs, (str, os.PathLike)) else inputs:
        if Path(spec).is_dir() and out.resolve().is_relative_to(Path(spec).resolve()):
            raise InputError(f"the output folder {out} is inside the input folder {spec}: the outputs would be "
                             "inputs of the next run; choose another output folder")
    manifest = Path(manifest) if manifest is not None else out / MANIFEST_NAME
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"{out} is a file, not an output folder")
    if out.is_dir() and any(out.iterdir()) and not manifest.exists() and not force:
        raise FileExistsError(f"{out} holds files that no geoimg batch wrote (no {manifest.name}); choose another "
                              "folder or --force to write into it")
    keys = [os.path.abspath(f) for f in files]
    stems = [str(out.resolve() / s) for s in output_stems(files)]
    if zarr is not None:
        zarr = str(Path(zarr).resolve())
    digest = opts.digest("zarr" if zarr else "exr", opts.resolution if zarr else "")
    # numba threads per task: the cores shared out between the local cluster's workers; a cluster of someone
    # else's keeps its own settings
    threads = _threads_per_worker(workers or os.cpu_count() or 1) if client is None and not scheduler else None
    jobs = []
    for i, (key, stem) in enumerate(zip(keys, stems)):
        st = os.stat(key)
        jobs.append(Job(key, stem, opts, digest, st.st_size, st.st_mtime_ns, zarr, i, threads))
    names = {str(Path(key).resolve()) for key in keys}
    for stem in stems:
        if any(str(Path(stem + ext)) in names for ext in (".exr", f"_quads.{opts.quads_format}", SPECTRUM_SUFFIX)):
            raise FileExistsError(f"{stem}: an output would replace an input; choose another output folder")
    old = {} if force else read_manifest(manifest)
    records: list[dict | None] = [None] * len(jobs)
    reused = zarr is not None and Path(zarr).exists() and not force
    resolution = int(opts.resolution or 0)          # checked: a Zarr store needs one
    if reused:                                      # refused here if it holds another batch
        assert zarr is not None
        open_store(zarr, keys, resolution, opts.normals, digest, colors=opts.colors)
        records = store_records(zarr)
    todo = [job for job in jobs if not _finished(old.get(job.input), job, records)]
    pending = {job.input for job in todo}
    skipped = [old[job.input]["status"] for job in jobs if job.input not in pending]
    rows: dict[str, dict] = {}
    pending_records: dict[int, dict] = {}
    say = progress or (lambda counts: None)
    t0 = time.perf_counter()
    started = False
    try:
        # the cluster first: a scheduler that cannot be reached (or a cluster that cannot start) leaves nothing
        with _Cluster(client, scheduler, workers, memory_limit) if todo else contextlib.nullcontext() as dask_client:
            out.mkdir(parents=True, exist_ok=True)
            if zarr is not None and not reused:
                open_store(zarr, keys, resolution, opts.normals, digest, force=force, colors=opts.colors)
            write_manifest(manifest, old.values())  # compacted (and in this version's columns) before appending
            _remove_partials(jobs, zarr)            # left by a run that was killed
            started = True
            say(_counts(rows, len(jobs), skipped, t0))
            if todo:
                _run(dask_client, todo, rows, pending_records, manifest, zarr, say, skipped, len(jobs), t0)
    finally:                                        # after the cluster has closed: no worker is writing now
        if started:
            if zarr is not None and pending_records:
                write_records(zarr, pending_records)
            _remove_partials(todo, zarr)
            merged = {**old, **rows}
            these = set(keys)
            write_manifest(manifest, [merged[k] for k in keys if k in merged] +
                           [r for k, r in merged.items() if k not in these])
    say(_counts(rows, len(jobs), skipped, t0))
    if opts.harmonics is not None:
        merged = {**old, **rows}
        write_table(out, [merged[k] for k in keys if k in merged], opts.harmonics)
    table = pandas.read_csv(manifest)                  # one parse for old and new rows: the same types
    present = set(table["input"])
    table = table.set_index("input").reindex([k for k in keys if k in present]).reset_index()
    table.attrs["summary"] = _counts(rows, len(jobs), skipped, t0)
    table.attrs["manifest"] = str(manifest)
    return table


def _run(client, todo, rows, pending_records, manifest, zarr, say, skipped, total, t0) -> None:
    """Submit ``todo`` to ``client`` (small inputs first, so that a few large ones do not hold up the many small
    ones), collect rows as they finish, and cancel what is left on any interruption.
    """
    distributed = require("distributed", "geoimg batch")
    with ManifestLog(manifest) as log:
        order = sorted(todo, key=lambda job: job.input_size)
        run = uuid.uuid4().hex[:8]
        futures = {client.submit(run_job, job, key=f"geoimg-{run}-{job.index}", pure=False,
                                 priority=len(order) - rank): job for rank, job in enumerate(order)}

        def collect(fut) -> None:
            """The finished task's row: into the manifest, its item record queued for the store."""
            job = futures.pop(fut)
            if fut.status == "finished":
                row = fut.result()
            else:                                      # the worker died (a crash, or killed for memory)
                err = fut.exception()
                row = {"input": job.input, "status": "failed", "options_hash": job.options_hash,
                       "input_size": job.input_size, "input_mtime_ns": job.input_mtime_ns,
                       "message": f"{type(err).__name__}: {' '.join(str(err).split())[:300]}"}
            fut.release()
            item = row.pop("record", None)
            if item is not None:
                pending_records[job.index] = item
            rows[job.input] = row       # kept first: an interrupt after the log has it must not lose it in the
            log.add(row)                # compaction, which rewrites the manifest from these rows

        try:
            ac = distributed.as_completed(list(futures))
            last_progress = last_records = time.perf_counter()
            while not ac.is_empty():
                batch = ac.next_batch(block=False)
                if not batch:
                    time.sleep(0.05)
                for fut in batch:
                    collect(fut)
                now = time.perf_counter()
                if zarr is not None and pending_records and now - last_records > RECORDS_EVERY:
                    write_records(zarr, pending_records)
                    pending_records.clear()
                    last_records = now
                if now - last_progress > PROGRESS_EVERY:
                    say(_counts(rows, total, skipped, t0))
                    last_progress = now
        except BaseException:
            for fut in [f for f in futures if f.status == "finished"]:    # done before the stop: recorded
                collect(fut)
            client.cancel(list(futures), force=True)
            raise
