"""Fixtures shared by the tests (helpers live in helpers.py).

tests/test_real_meshes.py runs its checks on the bundled real meshes, and on the larger third-party meshes
of ../shared/data too (not bundled: their licences do not allow it) where that folder is beside the
checkout; the report's header says which.
"""
import os

import pytest

import geoimg

from helpers import MOUNTAIN, SHARED


def pytest_configure(config):
    """A worker of pytest-xdist (the suite runs on ``-n auto`` workers, see pyproject.toml) runs its kernels on
    its share of the cores: the workers run side by side, and numba's threads of several processes on the same
    cores wait on each other. (Only the number in use is set: ``NUMBA_NUM_THREADS`` must not change once
    numba has started its threads, or the next compilation fails.)"""
    workers = os.environ.get("PYTEST_XDIST_WORKER_COUNT")
    if workers:
        import numba
        numba.set_num_threads(max(1, min(numba.config.NUMBA_NUM_THREADS, (os.cpu_count() or 1) // int(workers))))


# Meshes converted at 33^2 before the workers start, two lists side by side (see pytest_sessionstart).
WARM_UP = (["geoimg/data/mountain.obj", "tests/data/torus.obj"],
           ["tests/data/spot.obj", "tests/data/cube_no_bottom.obj", "tests/data/multibody.stl"])
_CONVERT = ("import sys, warnings, geoimg\nwarnings.simplefilter('ignore')\n"
            "for path in sys.argv[1:]:\n    geoimg.mesh_to_images(path, 33)\n")


def pytest_sessionstart(session):
    """On a run with pytest-xdist workers, the controller compiles the kernels first: it converts a few small
    meshes (planar, octahedral, disk, cut, pieces) in two processes side by side, which write numba's cache
    (``cache=True``), so that the workers load the kernels instead of each compiling all of them at once. Best
    effort: a failure here is left for the tests to find."""
    config = session.config
    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None):
        return
    import subprocess
    import sys
    from helpers import ROOT
    runs = [subprocess.Popen([sys.executable, "-c", _CONVERT, *paths], cwd=ROOT, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for paths in WARM_UP]
    for run in runs:
        run.wait()


def pytest_report_header(config):
    if SHARED.is_dir():
        return f"shared data: {SHARED} (tests/test_real_meshes.py runs on its meshes too)"
    return f"shared data: {SHARED} absent (tests/test_real_meshes.py runs on the bundled meshes only)"


@pytest.fixture(scope="session")
def mountain():
    return geoimg.load_mesh(MOUNTAIN)


@pytest.fixture(scope="session")
def mountain_surface(mountain):
    return geoimg.fit_surface(mountain, geoimg.parametrize(mountain, "heightfield", axis="y"),
                              geoimg.GaussianWeights(s=2.0))
