"""The numba kernel of the octahedral grid's directions (apart, so that the domains import without numba)."""
import math

from numba import njit, prange

__all__ = ["grid_unit"]


@njit(parallel=True, cache=True)
def grid_unit(n, out):
    """``grid_directions`` (:mod:`._octahedral`) into ``out`` (n, n, 3), rows in parallel: the arithmetic of
    its ``_unfold`` and of dividing by the norm, in the same order (the same bits as numpy's, 8 times faster at
    513^2).
    """
    m = n - 1
    for i in prange(n):
        b = (2.0 * i - m) / m
        for j in range(n):
            a = (2.0 * j - m) / m
            z = 1.0 - abs(a) - abs(b)
            if z < 0:
                x = math.copysign(1.0 - abs(b), a)
                y = math.copysign(1.0 - abs(a), b)
            else:
                x, y = a, b
            r = math.sqrt(x * x + y * y + z * z)
            out[i, j, 0], out[i, j, 1], out[i, j, 2] = x / r, y / r, z / r
