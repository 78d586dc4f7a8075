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
