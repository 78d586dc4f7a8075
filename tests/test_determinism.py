"""The same input and options give the same bytes on any number of threads: sphere, disk and cut-open maps
at 1, 2 and 16 threads of BLAS, OpenMP and numba (each in a process of its own, as a laptop, a server and a
Dask worker run them), and ``geoimg batch`` (a thread per worker) against ``geoimg image`` (every core)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import geoimg
from geoimg import cli
from helpers import DATA
from meshes import cap, write

pytestmark = pytest.mark.slow           # processes under many thread counts: the full run

RES = 65
THREAD_VARIABLES = ("NUMBA_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
HASHES = """
import hashlib, json, sys, warnings
import numpy as np
import geoimg

warnings.simplefilter("ignore")
out = {}
for path in sys.argv[1:]:
    img = geoimg.mesh_to_image(geoimg.load_mesh(path), %d)
    out[path] = [type(img.domain).__name__] + [hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()
                                               for a in (img.pixels, img.normals, img.valid)]
print(json.dumps(out))
""" % RES  # noqa: UP031   (the braces of the code inside rule out an f-string)


def _hashes(paths, threads: int) -> dict:
    env = {**os.environ, **{k: str(threads) for k in THREAD_VARIABLES}}
    done = subprocess.run([sys.executable, "-c", HASHES, *map(str, paths)], env=env, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """A sphere map (the fish, 10,786 vertices: enough that OpenBLAS splits its dot products between
    threads, and the map then differed at 1 and 2 BLAS threads), a balanced disk (a cap of 2,880 faces) and
    a cut-open torus (4,608 faces): each more triangles than one chunk of the balancing's sums."""
    folder = tmp_path_factory.mktemp("det")
    return [DATA / "fish.obj", write(cap(80.0, rings=30, segments=48), folder / "cap.obj"), DATA / "torus.obj"]


def test_every_map_gives_the_same_bytes_on_1_2_and_16_threads(meshes):
    runs = {t: _hashes(meshes, t) for t in (1, 2, 16)}
    domains = sorted(v[0] for v in runs[1].values())
    assert domains == ["CutDomain", "OctahedralDomain", "PlanarDomain"]
    assert runs[1] == runs[2] == runs[16]


def test_the_balancing_energy_does_not_depend_on_the_threads():
    """In one process: the energy and its normalization term summed on 1 and 2 threads, bit for bit, and
    equal to the chunked sum written out in numpy (the kernel's order of additions)."""
    numba = pytest.importorskip("numba")
    from geoimg.parametrization import _balance_kernels as bk
    rng = np.random.default_rng(1)
    n_t = 3 * bk.CHUNK + 17
    s = rng.normal(size=(n_t + 2, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    tris = np.stack([np.arange(n_t), np.arange(n_t) + 1, np.arange(n_t) + 2], axis=1)
    a = rng.random(n_t)
    a /= a.sum()
    cot = rng.random((n_t, 3))
    area = rng.random(n_t) + 0.1
    results, before = [], numba.get_num_threads()
    for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
        numba.set_num_threads(threads)
        try:
            results.append(bk._terms(s, tris, a, cot, area, 0.7, 0.3, np.empty(n_t)))
        finally:
            numba.set_num_threads(before)
    assert results[0] == results[-1]
    e, _ = results[0]
    d = np.empty(n_t)
    bk._terms(s, tris, a, cot, area, 0.7, 0.3, d)
    lr = np.log(0.7 * area / a)
    terms = a * lr * lr + 0.3 * a * (d / (0.7 * area) - 2.0)
    chunks = [sum(terms[c:c + bk.CHUNK].tolist()) for c in range(0, n_t, bk.CHUNK)]
    assert np.isclose(e, sum(chunks), rtol=1e-13, atol=0)


def test_batch_writes_the_bytes_that_geoimg_image_writes(tmp_path):
    pytest.importorskip("distributed")
    src = tmp_path / "in"
    src.mkdir()
    (src / "fish.obj").write_bytes((DATA / "fish.obj").read_bytes())     # BLAS splits its sums
    assert cli.main(["image", str(src / "fish.obj"), "-o", str(tmp_path / "one.exr"), "--res", str(RES), "-q",
                     "--no-colors"]) == 0
    assert cli.main(["batch", str(src), "-o", str(tmp_path / "out"), "--res", str(RES), "--workers", "2",
                     "--no-psnr", "--no-colors", "-q"]) == 0
    one = geoimg.load_image(tmp_path / "one.exr")
    many = geoimg.load_image(tmp_path / "out" / "fish.exr")
    assert one.pixels.tobytes() == many.pixels.tobytes()
    assert one.normals is not None and many.normals is not None
    assert one.normals.tobytes() == many.normals.tobytes()


def test_blas_runs_on_one_thread_inside_and_as_before_outside():
    threadpoolctl = pytest.importorskip("threadpoolctl")
    from geoimg._threads import blas_in_order

    def blas_threads():
        return [i["num_threads"] for i in threadpoolctl.threadpool_info() if i["user_api"] == "blas"]

    with threadpoolctl.threadpool_limits(2, "blas"):
        with blas_in_order():
            assert blas_threads() and set(blas_threads()) == {1}
            with blas_in_order():                       # nested: still one thread, and not restored early
                pass
            assert set(blas_threads()) == {1}
        assert set(blas_threads()) == {2}
