import numpy as np
import pytest

from filters import pad


def test_reflect_and_wrap():
    a = np.arange(12.0).reshape(3, 4, 1)
    r = pad(a, 2, "reflect")
    assert r.shape == (7, 8, 1) and np.array_equal(r[2:-2, 2:-2], a)
    assert np.array_equal(r[:, 1], r[:, 2]) and np.array_equal(r[1], r[2])
    w = pad(a, 1, "wrap")
    assert np.array_equal(w[0, 1:-1], a[-1]) and np.array_equal(w[1:-1, 0], a[:, -1])


def test_input_unchanged_and_errors():
    a = np.ones((3, 3))
    pad(a, 1)
    assert np.array_equal(a, np.ones((3, 3)))
    with pytest.raises(ValueError, match="mode"):
        pad(a, 1, "octahedral-ish")
    with pytest.raises(ValueError, match="width"):
        pad(a, -1)
    with pytest.raises(ValueError, match="image"):
        pad(np.ones(3), 1)
