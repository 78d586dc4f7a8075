"""A vectorizable exponential for the surface kernels (``math.exp`` is a scalar libm call in numba's
loops, and numba has no vector math library here).

``exp(x) = exp(r) 2^k`` with ``k`` the nearest integer to ``x / ln 2`` and ``|r| <= ln 2 / 2``: ``exp(r)``
is its Taylor polynomial of degree 13 (remainder below 1e-17 relative), ``2^k`` is built from its bits.
Within 4 ulp of libm for ``-708 <= x <= 0`` (tested); below -708 (and for -inf) it is 0, which the kernels'
certificates allow (they never trust a sum below 1e-250).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["exp_into", "exp_inplace", "plain_sum_floor", "MIN_PLAIN_SUM"]

MIN_PLAIN_SUM = 1e-250    # a plain sum of exponentials below this may have lost terms to underflow

_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01    # ln 2 split so that k * _LN2_HI is exact for |k| < 2^20
_LN2_LO = 1.90821492927058770002e-10
_ROUND = 6755399441055744.0             # 1.5 * 2^52: x + _ROUND - _ROUND rounds x to an integer
_EXP_FLOOR = -708.0                     # exp of less is taken as 0 (certified sums are >= 1e-250)
_C = tuple(1.0 / math.factorial(k) for k in range(14))


@njit(cache=True, inline="always")
def exp_into(x, out, bits):
    """``out = exp(x)`` (``x`` may be -inf), in two loops LLVM vectorizes; ``bits`` is int64 scratch as
    long as ``x``, ``out`` must not be ``x``.
    """
    scale = bits.view(np.float64)
    for p in range(x.shape[0]):
        y = x[p]
        y = y if y > _EXP_FLOOR else _EXP_FLOOR
        k = (y * _LOG2E + _ROUND) - _ROUND
        r = (y - k * _LN2_HI) - k * _LN2_LO
        e = _C[13]
        e = e * r + _C[12]
        e = e * r + _C[11]
        e = e * r + _C[10]
        e = e * r + _C[9]
        e = e * r + _C[8]
        e = e * r + _C[7]
        e = e * r + _C[6]
        e = e * r + _C[5]
        e = e * r + _C[4]
        e = e * r + _C[3]
        e = e * r + _C[2]
        e = e * r + 1.0
        out[p] = e * r + 1.0
        bits[p] = np.int64(k + 1023.0) << 52
    for p in range(x.shape[0]):
        out[p] = out[p] * scale[p] if x[p] >= _EXP_FLOOR else 0.0


@njit(parallel=True, cache=True, fastmath={"contract"})
def exp_inplace(x):
    """``x = exp(x)`` as :func:`exp_into` computes it, in parallel chunks; returns ``x``."""
    n = x.shape[0]
    chunk = 4096
    for c in prange(-(-n // chunk)):
        a, b = c * chunk, min(n, (c + 1) * chunk)
        exp_into(x[a:b].copy(), x[a:b], np.empty(b - a, np.int64))
    return x


def plain_sum_floor(log_g_ref: float) -> float:
    """The least plain (unshifted) Gaussian sum an image sampler trusts: ``g_ref`` (every skipped weight is
    then below ``tol``), and at least ``MIN_PLAIN_SUM`` (below it, terms may have underflowed); pixels under
    it are recomputed in the log domain.
    """
    return max(math.exp(log_g_ref), MIN_PLAIN_SUM)
