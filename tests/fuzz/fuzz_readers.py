"""Coverage-guided fuzzing of geoimg's file readers with atheris (libFuzzer for Python).

One harness per format: ``python tests/fuzz/fuzz_readers.py FORMAT [libFuzzer options] [CORPUS ...]``,
FORMAT one of :data:`FORMATS`, or ``all``: every format in one process, the first byte of an input choosing
which (one start-up for the suite's short run instead of ten). Each input is written to a file of that
format's suffix and read by
:func:`geoimg.load_mesh` or :func:`geoimg.load_image`; the seeds are made from the bundled meshes by
geoimg's own writers (``--seeds DIR`` writes them and stops; an empty or missing corpus folder is filled
with them before the run). A clean :class:`geoimg.GeoimgError` (or a
file read well) is a pass; anything else is a finding: another exception, a library's log record with a
traceback, a crash, a hang past ``-timeout``, memory past ``-rss_limit_mb``. Findings land in
``crash-*`` / ``timeout-*`` / ``oom-*`` files in the working folder: each one becomes a regression test in
``tests/data/fuzz`` (read by ``tests/test_fuzz.py``).

The readers run under a 1 GiB memory budget (``GEOIMG_MAX_MEMORY``), so that a header that claims a huge
image is refused by geoimg before anything is allocated.

Examples
--------
Seconds of ``all`` for the CI (``tests/test_fuzz.py``), ten minutes a format for the record
(``benchmarks/bench_fuzz.py``)::

    python tests/fuzz/fuzz_readers.py obj -max_total_time=600 -rss_limit_mb=3072 -timeout=20 corpus/obj
"""
from __future__ import annotations

import logging
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

os.environ.setdefault("GEOIMG_MAX_MEMORY", "1G")

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
FORMATS = ("obj", "off", "ply", "stl", "glb", "gltf", "exr", "npz", "npy", "tif", "jp2")
IMAGES = ("exr", "npz", "npy", "tif", "jp2")
MIXED = "all"              # every format, the first byte of an input choosing which


def write_seeds(fmt: str, folder: Path) -> list[Path]:
    """Small valid files of format ``fmt`` in ``folder``, made from the bundled meshes: a quad, a polygon
    mesh, a textured or coloured mesh, a binary and an ASCII variant where the format has both. For
    ``all``: every format's, each behind the byte that chooses its format."""
    if fmt == MIXED:
        folder.mkdir(parents=True, exist_ok=True)
        mixed = []
        for k, one in enumerate(FORMATS):
            with tempfile.TemporaryDirectory() as tmp:
                for seed in write_seeds(one, Path(tmp)):
                    target = folder / f"{one}-{seed.name}"
                    target.write_bytes(bytes([k]) + seed.read_bytes())
                    mixed.append(target)
        return mixed
    import numpy as np

    import geoimg

    folder.mkdir(parents=True, exist_ok=True)
    written = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if fmt in IMAGES:
            from geoimg.image._jp2 import encode

            def save(img, path):
                if fmt != "jp2":
                    return geoimg.save_image(img, path, overwrite=True)
                path.write_bytes(encode(img, 60))               # lossy, as geoimg compress writes them
                return path

            mountain = geoimg.load_mesh(ROOT / "geoimg" / "data" / "mountain.obj")
            for res in (5, 9):
                img = geoimg.mesh_to_image(mountain, res, fidelity=False)
                written.append(save(img, folder / f"mountain{res}.{fmt}"))
            masked = geoimg.GeometryImage(img.pixels, np.arange(9)[:, None] + np.arange(9) < 12, img.domain)
            written.append(save(masked, folder / f"masked.{fmt}"))
            sphere = geoimg.mesh_to_image(geoimg.load_mesh(DATA / "sphere.obj"), 9, fidelity=False)
            written.append(save(sphere, folder / f"sphere.{fmt}"))
            if fmt == "jp2":                     # a displaced file: the 9^2 sphere as the base of offsets at 17^2
                from geoimg.image._displacement import area_weights, base_frame
                from geoimg.image._jp2 import decode
                points, _ = base_frame(decode(encode(sphere, 60)).pixels, sphere.domain, (17, 17))
                offsets = 1.0 - np.linalg.norm(points, axis=-1)           # area-weighted, as compress writes them
                (folder / "displaced.jp2").write_bytes(encode(sphere, 60, offsets=offsets, offsets_level=50,
                                                              offsets_weights=area_weights(points, sphere.domain)))
                written.append(folder / "displaced.jp2")
            return written
        quad = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
        polygons = geoimg.load_mesh(DATA / "polygonfaces.obj")
        cube = geoimg.load_mesh(DATA / "cube_no_bottom.obj")
        coloured = geoimg.Mesh(cube.vertices, cube.faces, colors=np.linspace(0, 1, 3 * cube.n_vertices)
                               .reshape(-1, 3))
        for name, mesh in (("quad", quad), ("polygons", polygons), ("cube", cube), ("coloured", coloured)):
            try:
                written.append(geoimg.save_mesh(mesh, folder / f"{name}.{fmt}", overwrite=True))
            except geoimg.GeoimgError:
                pass
        if fmt == "stl":
            for name in ("multibody.stl", "angle_block.STL"):
                (folder / name.lower()).write_bytes((DATA / name).read_bytes())
                written.append(folder / name.lower())
        if fmt == "ply":
            text = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
            (folder / "ascii.ply").write_text(text)
            written.append(folder / "ascii.ply")
        if fmt == "gltf":                        # geoimg writes GLB: small glTFs, their buffers inline
            for name, points, index, code in (
                    ("triangle", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.array([0, 1, 2], np.uint16), 5123),
                    ("quad", [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.array([0, 1, 2, 0, 2, 3], np.uint32),
                     5125),
                    ("unindexed", [[0, 0, 0], [1, 0, 0], [0, 1, 1]], None, 0)):
                written.append(_write_gltf(folder / f"{name}.gltf", np.array(points, np.float32), index, code))
        if fmt == "obj":
            text = ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                    "f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4 -2 -1\n")
            (folder / "uv.obj").write_text(text)
            written.append(folder / "uv.obj")
    return written


def _write_gltf(path: Path, points, index, code: int) -> Path:
    """A glTF 2.0 file of one mesh: ``points`` (float32), ``index`` (None: unindexed) of accessor type
    ``code``, its one buffer inline as a base64 data URI."""
    import base64
    import json

    blob = points.tobytes()
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(blob)}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": len(points), "type": "VEC3",
                  "min": points.min(axis=0).tolist(), "max": points.max(axis=0).tolist()}]
    primitive: dict = {"attributes": {"POSITION": 0}}
    if index is not None:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": index.nbytes})
        accessors.append({"bufferView": 1, "componentType": code, "count": len(index), "type": "SCALAR"})
        primitive["indices"] = 1
        blob += index.tobytes()
    blob += b"\0" * (-len(blob) % 4)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [primitive]}], "bufferViews": views, "accessors": accessors,
           "buffers": [{"byteLength": len(blob),
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]}
    path.write_text(json.dumps(doc))
    return path


def make_target(fmt: str):
    """The function that libFuzzer calls with each input: read it as a ``fmt`` file (for ``all``, as the
    format its first byte chooses, from the rest); raise on a finding."""
    import geoimg

    formats = FORMATS if fmt == MIXED else (fmt,)
    readers = {}
    for one in formats:
        folder = Path(tempfile.mkdtemp(prefix=f"geoimg-fuzz-{one}-"))
        readers[one] = (folder / f"input.{one}", geoimg.load_image if one in IMAGES else geoimg.load_mesh)
    logged: list[logging.LogRecord] = []

    class Traceback(logging.Handler):            # a library's logged traceback looks like a crash to a user
        def emit(self, record: logging.LogRecord) -> None:
            if record.exc_info or record.levelno >= logging.ERROR:
                logged.append(record)

    logging.getLogger().addHandler(Traceback())
    logging.lastResort = None

    def one_input(data: bytes) -> None:
        if fmt == MIXED:
            if not data:
                return
            one, data = formats[data[0] % len(formats)], data[1:]
        else:
            one = fmt
        path, read = readers[one]
        path.write_bytes(data)
        logged.clear()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                read(path)
            except geoimg.GeoimgError:
                pass
        if logged:
            record = logged[0]
            raise RuntimeError(f"a library logged {logging.getLevelName(record.levelno)} {record.name}: "
                               f"{record.getMessage()} (traceback: {bool(record.exc_info)}) reading a {one} file")

    return one_input


def main(argv: list[str]) -> None:
    if len(argv) < 2 or argv[1] not in FORMATS + (MIXED,):
        sys.exit(f"usage: {argv[0]} FORMAT [libFuzzer options] [CORPUS ...] | --seeds DIR; FORMAT one of "
                 f"{', '.join(FORMATS)}, or {MIXED}")
    fmt = argv[1]
    if len(argv) == 4 and argv[2] == "--seeds":
        print("\n".join(str(p) for p in write_seeds(fmt, Path(argv[3]))))
        return
    corpora = [a for a in argv[2:] if not a.startswith("-")]
    if corpora and (not Path(corpora[0]).exists() or not any(Path(corpora[0]).iterdir())):
        # an empty corpus starts from the seeds, written by another process: numba cannot compile the
        # kernels that seeding runs once atheris has instrumented geoimg's bytecode
        subprocess.run([sys.executable, __file__, fmt, "--seeds", corpora[0]], check=True, capture_output=True)
    import atheris

    with atheris.instrument_imports(include=["geoimg"]):     # geoimg's code guides the search, not numpy's
        import geoimg  # noqa: F401
        from geoimg.image import _io as _image_io  # noqa: F401   (the readers, imported here to be instrumented)
        from geoimg.mesh import _io as _mesh_io  # noqa: F401
        from geoimg.mesh import _obj, _off, _ply, _trimesh_io, _weld  # noqa: F401
        from geoimg import _raster  # noqa: F401
        from geoimg.image import _npz, _jp2  # noqa: F401
    atheris.Setup([argv[0]] + argv[2:], make_target(fmt))
    atheris.Fuzz()


if __name__ == "__main__":
    main(sys.argv)
