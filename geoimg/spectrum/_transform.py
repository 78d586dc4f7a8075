"""The real spherical-harmonic transform in the 4pi-normalized convention of pyshtools and aicsshparam.

A function on the unit sphere is ``f(theta, phi) = sum_l sum_m (C_lm cos(m phi) + S_lm sin(m phi)) P_lm(cos
theta)`` with ``P_lm`` 4pi-normalized (the mean of ``(P_lm cos m phi)^2`` over the sphere is 1) and without
the Condon-Shortley phase; ``theta`` is the colatitude from +z, ``phi`` the longitude from +x towards +y.
Coefficients are stored as pyshtools stores them: ``coeffs[0, l, m] = C_lm``, ``coeffs[1, l, m] = S_lm``
(``S_l0 = 0``; entries with ``m > l`` are 0).

Analysis samples the function on a Gauss-Legendre grid of ``2 L + 2`` rows and ``4 L + 4`` columns (twice
the rows a band limit of ``L`` needs, so that the degrees above ``L`` of a function that is not band-limited
alias less), an FFT along each row, then the quadrature in ``cos theta``. Synthesis on rows of one latitude
is exact: the Legendre sums of each row, then an inverse FFT along it (:func:`synthesize_rows`). At any
directions (:func:`synthesize`) the sum is evaluated point by point while that is cheap (``N (L + 1)^2`` up
to :data:`EXACT_TERMS`); beyond, the function is synthesized on an equiangular grid oversampled 8 times
(at least 128 rows) and interpolated by cubic splines, padded across the poles: within about 1e-6 of the
largest value for coefficients that decay like a shape's (2e-5 for coefficients that do not decay at all;
``tests/spectrum``), at a 2049^2 image and L = 256 seconds instead of an hour. The kernels run in numba
(``_sh_kernels.py``); the transform needs no package beyond scipy.

Examples
--------
>>> import numpy as np
>>> lmax = 4
>>> d = grid_directions(lmax)                           # (rows, columns, 3)
>>> c = analyze(d[..., 2:3], lmax)                      # the function z = cos(theta)
>>> round(float(c[0, 0, 1, 0]) * 3 ** 0.5, 12)         # z = P_10 / sqrt(3)
1.0
>>> float(np.abs(synthesize(c, d.reshape(-1, 3))[:, 0] - d[..., 2].ravel()).max()) < 1e-12
True
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..errors import InputError
from ._sh_kernels import analyze_rows, recursion_tables, row_sums, synthesize_points

__all__ = ["grid_directions", "grid_shape", "analyze", "synthesize", "synthesize_rows", "degree_power", "MAX_LMAX",
           "EXACT_TERMS"]

MAX_LMAX = 1024       # beyond this the recursion's diagonal underflows near the poles in float64
EXACT_TERMS = 20_000_000   # points x (L + 1)^2 up to which synthesize sums point by point (about a second)
OVERSAMPLE = 8             # the interpolated synthesis's grid: rows per degree
MIN_ROWS = 128
_POLE_PAD = 16             # rows and columns of padding around that grid (the spline's reach, many times over)


def check_lmax(lmax) -> int:
    """``lmax`` as an int from 1 to :data:`MAX_LMAX`, or an :class:`~geoimg.errors.InputError`."""
    if isinstance(lmax, bool) or not isinstance(lmax, (int, np.integer)) or not 1 <= int(lmax) <= MAX_LMAX:
        raise InputError(f"lmax: expected a whole number from 1 to {MAX_LMAX}, got {lmax!r}")
    return int(lmax)


def grid_shape(lmax: int) -> tuple[int, int]:
    """Rows and columns of the analysis grid for degree ``lmax``: ``(2 L + 2, 4 L + 4)``.

    Parameters
    ----------
    lmax : int
        The largest degree, L.

    Returns
    -------
    tuple of int
        (rows, columns).

    Examples
    --------
    >>> grid_shape(16)
    (34, 68)
    """
    rows = 2 * check_lmax(lmax) + 2
    return rows, 2 * rows


def _rows(lmax: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(grid_shape(lmax)[0])
    return x[::-1].copy(), w[::-1].copy()          # from the north pole down


def grid_directions(lmax: int) -> np.ndarray:
    """Unit directions (rows, columns, 3) of the analysis grid of degree ``lmax`` (rows from north to south,
    columns at longitudes ``2 pi k / columns``).

    Parameters
    ----------
    lmax : int
        The largest degree, L.

    Returns
    -------
    numpy.ndarray
        (2 L + 2, 4 L + 4, 3) unit directions.

    Examples
    --------
    >>> grid_directions(2).shape
    (6, 12, 3)
    """
    x, _ = _rows(lmax)
    cols = grid_shape(lmax)[1]
    phi = 2 * np.pi * np.arange(cols) / cols
    s = np.sqrt(1 - x * x)
    return np.stack([s[:, None] * np.cos(phi)[None], s[:, None] * np.sin(phi)[None],
                     np.broadcast_to(x[:, None], (len(x), cols))], axis=-1)


def analyze(values: np.ndarray, lmax: int) -> np.ndarray:
    """Coefficients (K, 2, L + 1, L + 1) of ``K`` functions sampled on :func:`grid_directions` (``values``
    of shape (rows, columns, K)).

    Parameters
    ----------
    values : numpy.ndarray
        (rows, columns, K) samples on :func:`grid_directions` of ``lmax``.
    lmax : int
        The largest degree, L.

    Returns
    -------
    numpy.ndarray
        (K, 2, L + 1, L + 1) cosine and sine coefficients.

    Examples
    --------
    >>> c = analyze(np.ones(grid_shape(3) + (1,)), 3)
    >>> round(float(c[0, 0, 0, 0]), 12), round(float(np.abs(c).sum()), 12)
    (1.0, 1.0)
    """
    lmax = check_lmax(lmax)
    values = np.asarray(values, np.float64)
    if values.ndim != 3 or values.shape[:2] != grid_shape(lmax):
        raise InputError(f"values: expected shape {grid_shape(lmax) + ('K',)}, got {values.shape}")
    cols = values.shape[1]
    spectrum = np.fft.rfft(values, axis=1)[:, : lmax + 1] / cols      # (rows, L + 1, K): means over phi of
    # f cos(m phi) (the real part) and f sin(m phi) (minus the imaginary part); the coefficient is the mean
    # over the sphere of f times the harmonic, whose mean square is 1
    re = np.ascontiguousarray(np.moveaxis(spectrum.real, 2, 0))
    im = np.ascontiguousarray(np.moveaxis(-spectrum.imag, 2, 0))
    x, w = _rows(lmax)
    out = np.zeros((values.shape[2], 2, lmax + 1, lmax + 1))
    a, b = recursion_tables(lmax)
    analyze_rows(x, w / 2.0, re, im, a, b, out)           # the weights sum to 2 over cos theta in [-1, 1]
    out[:, 1, :, 0] = 0.0
    return out


def synthesize(coeffs: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Values (N, K) at unit ``directions`` (N, 3) of the functions whose coefficients are ``coeffs``
    (K, 2, L + 1, L + 1).

    Parameters
    ----------
    coeffs : numpy.ndarray
        (K, 2, L + 1, L + 1) cosine and sine coefficients.
    directions : numpy.ndarray
        (N, 3) directions, not zero (normalized here).

    Returns
    -------
    numpy.ndarray
        (N, K) values.

    Examples
    --------
    >>> c = np.zeros((1, 2, 2, 2)); c[0, 0, 1, 1] = 1.0 / 3 ** 0.5        # x = P_11 cos(phi) / sqrt(3)
    >>> synthesize(c, np.array([[1.0, 0, 0], [0, 1.0, 0], [0.6, 0, 0.8]])).ravel().round(12).tolist()
    [1.0, 0.0, 0.6]
    """
    coeffs = _checked(coeffs)
    d = np.asarray(directions, np.float64)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    if len(d) * coeffs.shape[2] ** 2 > EXACT_TERMS:
        return _interpolated(coeffs, d)
    x = np.clip(d[:, 2], -1.0, 1.0)
    phi = np.arctan2(d[:, 1], d[:, 0])
    a, b = recursion_tables(coeffs.shape[2] - 1)
    out = np.empty((len(d), coeffs.shape[0]))
    synthesize_points(coeffs, np.ascontiguousarray(x), np.ascontiguousarray(phi), a, b, out)
    return out


def degree_power(coeffs: np.ndarray) -> np.ndarray:
    """The power per degree of coefficients (..., 2, L + 1, L + 1), unchanged when the sphere is turned
    under the function: (..., L + 1), the sum over m of the squares of the cosine and sine coefficients.

    Parameters
    ----------
    coeffs : numpy.ndarray
        (..., 2, L + 1, L + 1) coefficients.

    Returns
    -------
    numpy.ndarray
        (..., L + 1) power per degree.

    Examples
    --------
    >>> c = np.zeros((2, 3, 3)); c[0, 1, 1] = 3.0; c[1, 1, 1] = 4.0
    >>> degree_power(c).tolist()
    [0.0, 25.0, 0.0]
    """
    c = np.asarray(coeffs, np.float64)
    return (c ** 2).sum(axis=(-3, -1))


def _checked(coeffs) -> np.ndarray:
    coeffs = np.ascontiguousarray(coeffs, np.float64)
    if coeffs.ndim != 4 or coeffs.shape[1] != 2 or coeffs.shape[2] != coeffs.shape[3]:
        raise InputError(f"coeffs: expected shape (K, 2, L + 1, L + 1), got {coeffs.shape}")
    return coeffs


def synthesize_rows(coeffs: np.ndarray, x: np.ndarray, columns: int) -> np.ndarray:
    """Values (rows, columns, K) on rows of latitude ``x = cos(theta)`` at longitudes ``2 pi j / columns``,
    exact (to rounding) when ``columns > 2 L``: each row's Legendre sums, then an inverse FFT along it.

    Parameters
    ----------
    coeffs : numpy.ndarray
        (K, 2, L + 1, L + 1) cosine and sine coefficients.
    x : numpy.ndarray
        (rows,) the rows' cos(theta).
    columns : int
        Longitudes per row, more than 2 L.

    Returns
    -------
    numpy.ndarray
        (rows, columns, K) values.

    Examples
    --------
    >>> c = np.zeros((1, 2, 3, 3)); c[0, 0, 1, 0] = 1.0 / 3 ** 0.5         # z
    >>> synthesize_rows(c, np.array([0.5, -1.0]), 6)[..., 0].round(12).tolist()
    [[0.5, 0.5, 0.5, 0.5, 0.5, 0.5], [-1.0, -1.0, -1.0, -1.0, -1.0, -1.0]]
    """
    coeffs = _checked(coeffs)
    lmax = coeffs.shape[2] - 1
    if columns <= 2 * lmax:
        raise InputError(f"columns: {columns} longitudes cannot hold degree {lmax} (more than {2 * lmax} needed)")
    x = np.ascontiguousarray(x, np.float64)
    sums = np.empty((len(x), coeffs.shape[0], lmax + 1, 2))
    a, b = recursion_tables(lmax)
    row_sums(coeffs, x, a, b, sums)
    spectrum = np.zeros((len(x), coeffs.shape[0], columns // 2 + 1), complex)
    # C cos(m phi) + S sin(m phi) = Re((C - iS) e^(i m phi)); irfft halves every term but the mean's
    spectrum[..., : lmax + 1] = (sums[..., 0] - 1j * sums[..., 1]) * (columns / 2)
    spectrum[..., 0] = sums[..., 0, 0] * columns
    return np.moveaxis(np.fft.irfft(spectrum, n=columns, axis=2), 1, 2)


def _interpolated(coeffs: np.ndarray, d: np.ndarray) -> np.ndarray:
    """:func:`synthesize` for many points: an oversampled equiangular grid (rows at ``theta = pi (i + 1/2) /
    rows``), padded across the poles (row ``-1 - i`` is row ``i`` half a turn round) and around in longitude,
    and cubic splines.
    """
    lmax = coeffs.shape[2] - 1
    rows = max(OVERSAMPLE * (lmax + 1), MIN_ROWS)
    cols = 2 * rows
    grid = synthesize_rows(coeffs, np.cos(np.pi * (np.arange(rows) + 0.5) / rows), cols)
    p = _POLE_PAD
    north = np.roll(grid[:p][::-1], cols // 2, axis=1)
    south = np.roll(grid[-p:][::-1], cols // 2, axis=1)
    padded = np.concatenate([north, grid, south], axis=0)
    padded = np.concatenate([padded[:, -p:], padded, padded[:, :p]], axis=1)
    theta = np.arccos(np.clip(d[:, 2], -1.0, 1.0))
    phi = np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
    where = [theta * (rows / np.pi) - 0.5 + p, phi * (cols / (2 * np.pi)) + p]
    out = np.empty((len(d), coeffs.shape[0]))
    for k in range(coeffs.shape[0]):
        out[:, k] = ndimage.map_coordinates(padded[..., k], where, order=3, mode="nearest")
    return out
