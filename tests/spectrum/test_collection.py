"""Coefficient tables and shape spaces: rows that round-trip bit for bit, principal components that find the
directions a collection varies along, and bad rows and settings refused."""
import numpy as np
import pytest

from geoimg.spectrum import (Harmonics, ShapeSpace, coefficient_columns, coefficient_row, harmonics_from_row,
                             shape_space)


def _coeffs(lmax, seed):
    c = np.random.default_rng(seed).normal(size=(3, 2, lmax + 1, lmax + 1))
    c *= np.tril(np.ones((lmax + 1, lmax + 1)))[None, None]
    c[:, 1, :, 0] = 0.0
    return c


def test_columns_are_named_like_aicsshparams_and_rows_round_trip():
    names = coefficient_columns(3)
    assert len(names) == 3 * 16 == len(set(names))
    assert names[:4] == ["x_shcoeffs_L0M0C", "x_shcoeffs_L1M0C", "x_shcoeffs_L1M1C", "x_shcoeffs_L1M1S"]
    assert "y_shcoeffs_L3M3S" in names and "x_shcoeffs_L2M0S" not in names       # sine of order 0: always 0
    h = Harmonics(_coeffs(3, 0))
    row = coefficient_row(h)
    assert list(row) == names
    assert np.array_equal(harmonics_from_row({"input": "a.obj", "psnr_db": 70.0, **row}).coeffs, h.coeffs)


def test_the_shape_space_finds_the_directions_a_collection_varies_along():
    mean, u, v = _coeffs(4, 2), _coeffs(4, 3), _coeffs(4, 4)
    u /= np.linalg.norm(u)
    v -= (v * u).sum() * u
    v /= np.linalg.norm(v)
    turn = 2 * np.pi * np.arange(20) / 20
    a, b = 3.0 * np.cos(turn), np.sin(turn)                  # uncorrelated, of spreads 3 : 1
    shapes = [Harmonics(mean + x * u + y * v) for x, y in zip(a, b)]
    space = shape_space(shapes, 3)
    assert isinstance(space, ShapeSpace) and space.modes.shape == (3, 3, 2, 5, 5)
    assert space.explained[:2].sum() > 1 - 1e-9 and space.explained[2] < 1e-9
    assert abs(abs((space.modes[0] * u).sum()) - 1) < 1e-9             # the wider spread first
    assert abs(abs((space.modes[1] * v).sum()) - 1) < 1e-9
    assert np.allclose(space.mean.coeffs, mean + a.mean() * u + b.mean() * v)
    assert np.allclose(space.sigma[:2], [np.std(a), np.std(b)])
    moved = space.shape([1.0, -2.0]).coeffs - space.mean.coeffs
    assert np.allclose(moved, space.sigma[0] * space.modes[0] - 2 * space.sigma[1] * space.modes[1])
    lower = shape_space(shapes + [Harmonics(_coeffs(2, 9))], 2)           # truncated to the least degree
    assert lower.mean.lmax == 2


@pytest.mark.parametrize("call, message", [
    (lambda: harmonics_from_row({"input": "a.obj"}), "no coefficient column"),
    (lambda: harmonics_from_row({"x_shcoeffs_L0M0C": 1.0}), "degree 0 only"),
    (lambda: harmonics_from_row({k: 0.0 for k in coefficient_columns(2)[:-1]}), "1 of the degree-2"),
    (lambda: coefficient_row(np.zeros((3, 2, 2, 2))), "expected Harmonics"),
    (lambda: shape_space([Harmonics(np.zeros((3, 2, 2, 2)))]), "two or more"),
    (lambda: shape_space([Harmonics(np.zeros((3, 2, 2, 2)))] * 3, 3), "modes"),
    (lambda: shape_space([Harmonics(np.zeros((3, 2, 2, 2)))] * 3, True), "modes"),
    (lambda: shape_space([Harmonics(np.zeros((3, 2, 2, 2))), "b"]), "two or more"),
    (lambda: shape_space([Harmonics(_coeffs(2, s)) for s in range(3)], 1).shape([1.0, 2.0]), "at most 1"),
    (lambda: shape_space([Harmonics(_coeffs(2, s)) for s in range(3)], 1).shape([np.nan]), "finite"),
])
def test_bad_rows_and_settings_are_refused(call, message):
    with pytest.raises((ValueError, TypeError), match=message):
        call()
