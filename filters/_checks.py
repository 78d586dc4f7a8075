"""Validation shared by the filters: images, masks and positive sizes, with messages that name the argument."""
from __future__ import annotations

import numbers
import os
from typing import Any

import numpy as np
from numpy.typing import ArrayLike


def as_image(image: ArrayLike, name: str = "image") -> np.ndarray:
    """A finite real (H, W) or (H, W, C) array as float32 (kept) or float64 (anything else); not a copy.

    Parameters
    ----------
    image : array_like
        (H, W) or (H, W, C) real numbers, all finite.
    name : str
        What the message of a refusal calls it.

    Returns
    -------
    numpy.ndarray
        The array itself when it is float32 or float64, else a float64 copy.

    Raises
    ------
    TypeError
        When the array is not real.
    ValueError
        When it is not 2-D or 3-D, or holds NaN or infinity.

    Examples
    --------
    >>> as_image([[1, 2], [3, 4]]).dtype
    dtype('float64')
    """
    a = np.asarray(image)
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool) \
            or np.issubdtype(a.dtype, np.complexfloating):
        raise TypeError(f"{name}: expected a real numeric array, got dtype {a.dtype}")
    if a.ndim not in (2, 3) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"{name}: expected shape (H, W) or (H, W, C), got {a.shape}")
    if a.dtype != np.float32:
        a = a.astype(np.float64, copy=False)
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: contains NaN or infinite values")
    return a


def as_weights(mask: ArrayLike | None, shape: tuple[int, ...], name: str = "mask") -> np.ndarray:
    """A mask as float64 weights in [0, 1] of shape ``shape`` (H, W): booleans, or numbers in [0, 1].

    Parameters
    ----------
    mask : array_like or None
        Booleans or numbers in [0, 1]; None means everywhere (all ones).
    shape : tuple of int
        The image's (H, W), which the mask must have.
    name : str
        What the message of a refusal calls it.

    Returns
    -------
    numpy.ndarray
        float64 weights of shape ``shape``.

    Raises
    ------
    ValueError
        When the shape differs or a value lies outside [0, 1].

    Examples
    --------
    >>> as_weights([[True, False]], (1, 2)).tolist()
    [[1.0, 0.0]]
    """
    m = np.asarray(mask)
    if m.dtype == object or not (np.issubdtype(m.dtype, np.number) or m.dtype == bool) \
            or np.issubdtype(m.dtype, np.complexfloating):
        raise TypeError(f"{name}: expected a boolean or real array, got dtype {m.dtype}")
    if m.shape != tuple(shape):
        raise ValueError(f"{name}: expected shape {tuple(shape)} (the image's H, W), got {m.shape}")
    m = m.astype(np.float64)
    if not np.isfinite(m).all() or m.min() < 0 or m.max() > 1:
        raise ValueError(f"{name}: values must lie in [0, 1]")
    return m


def positive(value: Any, name: str, *, integer: bool = False, odd: bool = False, allow_zero: bool = False) -> Any:
    """Validate a positive (or non-negative) number; odd integers where a kernel needs a centre.

    Parameters
    ----------
    value : number
        The value to check (a NumPy scalar is accepted and returned as a Python number).
    name : str
        The parameter's name, for the message.
    integer : bool
        Require a whole number (returned as ``int``).
    odd : bool
        Require an odd integer.
    allow_zero : bool
        Accept 0 as well.

    Returns
    -------
    int or float
        The value as a Python number.

    Raises
    ------
    ValueError
        When it is not a finite number of the kind asked for.

    Examples
    --------
    >>> positive(3, "size", integer=True, odd=True)
    3
    """
    ok_type = isinstance(value, numbers.Integral) if integer else isinstance(value, numbers.Real)
    if isinstance(value, bool) or not ok_type or not np.isfinite(value) or value < 0 or (value == 0 and not allow_zero):
        kind = "an integer" if integer else "a number"
        raise ValueError(f"{name}: expected {kind} {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    if odd and int(value) % 2 == 0:
        raise ValueError(f"{name}: expected an odd size (the kernel needs a centre pixel), got {value!r}")
    return value


MEMORY_ENV = "GEOIMG_MAX_MEMORY"      # a size such as 8G; default: 80 % of the machine's physical memory
_UNITS = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}


class TooLarge(ValueError, MemoryError):
    """An array the operation would make is larger than the memory limit allows.

    Examples
    --------
    >>> from filters import TooLarge, check_memory
    >>> try:
    ...     check_memory(1e30, "a 1e15 x 1e15 image")
    ... except TooLarge as e:
    ...     print(str(e).split(";")[0].split(" about")[0])
    a 1e15 x 1e15 image would need
    """


def memory_limit() -> int:
    """Bytes one array may take: ``GEOIMG_MAX_MEMORY`` (a number with an optional K/M/G/T suffix) or 80 % of
    the machine's physical memory.

    Returns
    -------
    int
        The limit in bytes.

    Raises
    ------
    ValueError
        When ``GEOIMG_MAX_MEMORY`` is not a size such as ``8G`` or ``512M``.

    Examples
    --------
    >>> os.environ[MEMORY_ENV] = "2G"
    >>> memory_limit()
    2147483648
    >>> del os.environ[MEMORY_ENV]
    """
    text = os.environ.get(MEMORY_ENV, "").strip().upper().removesuffix("B")
    if text:
        unit = text[-1] if text[-1] in _UNITS else ""
        try:
            return int(float(text[:-1] if unit else text) * _UNITS[unit])
        except ValueError:
            raise ValueError(
                f"{MEMORY_ENV}: expected a size such as 8G or 512M, got {os.environ[MEMORY_ENV]!r}"
            ) from None
    try:
        return int(0.8 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 16 << 30


def check_memory(n_bytes: float, what: str, error: type[Exception] = TooLarge) -> None:
    """Raise ``error`` when ``what`` would take more than :func:`memory_limit` bytes, saying both.

    Parameters
    ----------
    n_bytes : float
        The estimated size of what is about to be made.
    what : str
        What it is, for the message.
    error : type
        The exception to raise (:class:`TooLarge` by default; geoimg passes its ``ResourceError``).

    Raises
    ------
    TooLarge
        (or ``error``) when ``n_bytes`` exceeds :func:`memory_limit`.

    Examples
    --------
    >>> check_memory(1e6, "a small array")     # well within any limit: nothing happens
    """
    limit = memory_limit()
    if n_bytes > limit:
        raise error(f"{what} would need about {n_bytes / 2 ** 30:.1f} GiB; the limit is {limit / 2 ** 30:.1f} GiB "
                    f"({MEMORY_ENV} or 80 % of this machine's memory)")
