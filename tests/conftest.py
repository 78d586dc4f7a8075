"""Fixtures shared by the tests (helpers live in helpers.py).

tests/test_shared_data.py runs the checks that need the larger third-party meshes of ../shared/data
(not bundled: their licences do not allow it, or they are large); without that folder beside the checkout
it is skipped with the reason shown (one skip), and the report's header says which.
"""
import pytest

import geoimg

from helpers import MOUNTAIN, SHARED

def pytest_report_header(config):
    if SHARED.is_dir():
        return f"shared data: {SHARED} (tests/test_shared_data.py collected)"
    return f"shared data: {SHARED} absent, so tests/test_shared_data.py is skipped (bundled data only)"


@pytest.fixture(scope="session")
def mountain():
    return geoimg.load_mesh(MOUNTAIN)


@pytest.fixture(scope="session")
def mountain_surface(mountain):
    return geoimg.fit_surface(mountain, geoimg.parametrize(mountain, "heightfield", axis="y"), s=2.0)
