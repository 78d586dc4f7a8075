"""The same bytes on any machine: BLAS on one thread inside geoimg's maps, fits and morphs.

OpenBLAS splits a long dot product or matrix product between its threads and adds the parts in an order
that depends on how many there are; an iterative map (area balancing, fold repair) carries a difference in
the last bit of one step into every later one, until two machines with different core counts give maps
0.8 % of the shape apart. Inside :func:`fixed_order`, every BLAS library loaded in the process (numpy's,
scipy's, OpenCV's) runs on one thread, so that each sum has one order. geoimg's numba kernels sum in
fixed chunks whatever their thread count (see ``parametrization/_balance_kernels.py``), so they keep
their threads.

The limit is process-wide (BLAS libraries hold one thread count); it is set when the first caller enters
and restored when the last one leaves, so nested and concurrent calls share it.

Examples
--------
>>> import numpy as np
>>> @fixed_order
... def total(x):
...     return float(x @ x)
>>> total(np.arange(4.0))
14.0
"""
from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

import scipy.linalg  # noqa: F401   (loads scipy's own BLAS before any limit is set, so that it is limited too)
from threadpoolctl import threadpool_limits

__all__ = ["fixed_order", "blas_in_order"]

F = TypeVar("F", bound=Callable[..., Any])

_lock = threading.Lock()
_depth = 0
_limits: Any = None


@contextmanager
def blas_in_order() -> Iterator[None]:
    """Every loaded BLAS library on one thread within the block (see the module's text).

    Examples
    --------
    >>> import numpy as np
    >>> with blas_in_order():
    ...     float(np.ones(3) @ np.ones(3))
    3.0
    """
    global _depth, _limits
    with _lock:
        if _depth == 0:
            _limits = threadpool_limits(limits=1, user_api="blas")
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                _limits.restore_original_limits()
                _limits = None


def fixed_order(func: F) -> F:
    """Decorate ``func`` to run inside :func:`blas_in_order`.

    Examples
    --------
    >>> fixed_order(sum)([1, 2])
    3
    """
    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with blas_in_order():
            return func(*args, **kwargs)
    return wrapper  # type: ignore[return-value]
