"""Fixtures shared by the tests (helpers live in helpers.py)."""
import pytest

import geoimg

from helpers import SAMPLES


@pytest.fixture(scope="session")
def mountain():
    return geoimg.load_mesh(SAMPLES / "mountain.obj")


@pytest.fixture(scope="session")
def mountain_surface(mountain):
    return geoimg.fit_surface(mountain, geoimg.parametrize(mountain, "heightfield", axis="y"), s=2.0)
