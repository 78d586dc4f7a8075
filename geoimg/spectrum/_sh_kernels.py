"""numba kernels of the spherical-harmonic transform: 4pi-normalized associated Legendre functions by the
standard three-term recursion, analysis on a Gauss-Legendre grid (rows in a fixed order: the same bytes on
any thread count) and synthesis at arbitrary directions (one point a thread).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange


def recursion_tables(lmax: int) -> tuple[np.ndarray, np.ndarray]:
    """The three-term recursion's factors ``a[deg, m]``, ``b[deg, m]`` (for ``deg >= m + 2``) of
    :func:`legendre_bar`, and ``a[m, m]`` the diagonal's (``P_mm = a[m, m] sin(theta) P_(m-1)(m-1)``) and
    ``b[m, m]`` the first step's (``P_(m+1)m = b[m, m] cos(theta) P_mm``).
    """
    deg = np.arange(lmax + 1, dtype=np.float64)[:, None]
    m = np.arange(lmax + 1, dtype=np.float64)[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.sqrt((4 * deg * deg - 1) / (deg * deg - m * m))
        b = np.sqrt((2 * deg + 1) * ((deg - 1) ** 2 - m * m) / ((2 * deg - 3) * (deg * deg - m * m)))
    a, b = np.where(deg >= m + 2, a, 0.0), np.where(deg >= m + 2, b, 0.0)
    k = np.arange(lmax + 1, dtype=np.float64)
    diag = np.sqrt((2 * k + 1) / np.maximum(2 * k, 1))
    diag[1] = np.sqrt(3.0)
    a[np.arange(lmax + 1), np.arange(lmax + 1)] = diag
    b[np.arange(lmax + 1), np.arange(lmax + 1)] = np.sqrt(2 * k + 3)
    return np.ascontiguousarray(a), np.ascontiguousarray(b)


@njit(cache=True)
def legendre_bar(x, a, b, out):
    """4pi-normalized associated Legendre functions without the Condon-Shortley phase at ``x = cos(theta)``
    into ``out[deg, m]`` for ``m <= deg`` (entries above the diagonal are not written): ``P_00 = 1``,
    ``P_11 = sqrt(3) sin(theta)`` (pyshtools' PlmBar); ``a``, ``b`` from :func:`recursion_tables`.
    """
    lmax = out.shape[0] - 1
    s = math.sqrt(max(0.0, 1.0 - x * x))
    pmm = 1.0
    for m in range(0, lmax + 1):
        if m > 0:
            pmm = pmm * a[m, m] * s
        out[m, m] = pmm
        if m + 1 <= lmax:
            out[m + 1, m] = b[m, m] * x * pmm
        for deg in range(m + 2, lmax + 1):
            out[deg, m] = a[deg, m] * x * out[deg - 1, m] - b[deg, m] * out[deg - 2, m]


@njit(cache=True)
def analyze_rows(x, w, re, im, a, b, out):
    """Coefficients ``out[k, 0 | 1, deg, m]`` (cosine | sine) of ``k`` functions from their longitude sums
    ``re[k, j, m] = sum_i f cos(m phi_i) dphi / 4pi`` and ``im`` (the sine sums) on rows ``x[j]`` of
    Gauss-Legendre weights ``w[j]``; rows are added in order.
    """
    lmax = out.shape[2] - 1
    p = np.empty((lmax + 1, lmax + 1))
    out[:] = 0.0
    for j in range(x.shape[0]):
        legendre_bar(x[j], a, b, p)
        for k in range(re.shape[0]):
            for m in range(lmax + 1):
                cr = w[j] * re[k, j, m]
                ci = w[j] * im[k, j, m]
                for deg in range(m, lmax + 1):
                    out[k, 0, deg, m] += cr * p[deg, m]
                    out[k, 1, deg, m] += ci * p[deg, m]


@njit(cache=True, parallel=True)
def synthesize_points(coeffs, x, phi, a, b, out):
    """``out[n, k] = sum_lm coeffs[k, 0, deg, m] P_lm(x_n) cos(m phi_n) + coeffs[k, 1, deg, m] P_lm(x_n)
    sin(m phi_n)`` for every point ``n`` (one point a thread: no shared sums).
    """
    lmax = coeffs.shape[2] - 1
    for n in prange(x.shape[0]):
        p = np.empty((lmax + 1, lmax + 1))
        legendre_bar(x[n], a, b, p)
        for k in range(coeffs.shape[0]):
            total = 0.0
            for m in range(lmax + 1):
                c, s = math.cos(m * phi[n]), math.sin(m * phi[n])
                for deg in range(m, lmax + 1):
                    total += (coeffs[k, 0, deg, m] * c + coeffs[k, 1, deg, m] * s) * p[deg, m]
            out[n, k] = total


@njit(cache=True, parallel=True)
def row_sums(coeffs, x, a, b, out):
    """``out[j, k, m, 0 | 1] = sum_deg coeffs[k, 0 | 1, deg, m] P_deg,m(x[j])``: each row's Fourier
    coefficients in longitude (one row a thread: no shared sums).
    """
    lmax = coeffs.shape[2] - 1
    for j in prange(x.shape[0]):
        p = np.empty((lmax + 1, lmax + 1))
        legendre_bar(x[j], a, b, p)
        for k in range(coeffs.shape[0]):
            for m in range(lmax + 1):
                sa = 0.0
                sb = 0.0
                for deg in range(m, lmax + 1):
                    sa += coeffs[k, 0, deg, m] * p[deg, m]
                    sb += coeffs[k, 1, deg, m] * p[deg, m]
                out[j, k, m, 0] = sa
                out[j, k, m, 1] = sb
