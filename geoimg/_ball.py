"""Weights of a ball: 1 inside, a smoothstep falloff over a feather width outside, 0 beyond."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from filters import positive

from .errors import InputError

__all__ = ["ball_weights", "checked_positive"]


def checked_positive(value, name, allow_zero=False) -> float:
    """``value`` as a float when it is a positive (or, allowed, zero) finite number; else ValueError."""
    return float(positive(value, name, allow_zero=allow_zero))


def ball_weights(points: ArrayLike, centre: ArrayLike, radius: float, feather: float = 0.0) -> np.ndarray:
    """Weights of points (..., D) for the ball ``|p - centre| <= radius``, falling off smoothly
    (smoothstep) over ``feather`` beyond it.

    Parameters
    ----------
    points : array_like
        (..., D) points.
    centre : array_like
        (D,) the ball's centre.
    radius : float
        The ball's radius (weight 1 within it), at least 0.
    feather : float
        The width of the falloff beyond the radius, at least 0.

    Returns
    -------
    numpy.ndarray
        Weights in [0, 1] of shape ``points.shape[:-1]``.

    Raises
    ------
    InputError
        When the centre is not finite or not of the points' dimension.
    ValueError
        When the radius or feather is negative.

    Examples
    --------
    >>> ball_weights(np.array([[0.0], [1.5], [2.0], [3.0]]), [0.0], 1.0, 2.0).tolist()
    [1.0, 0.84375, 0.5, 0.0]
    """
    p = np.asarray(points, dtype=np.float64)
    c = np.asarray(centre, dtype=np.float64)
    if c.shape != p.shape[-1:] or not np.isfinite(c).all():
        raise InputError(f"centre: expected {p.shape[-1]} finite coordinates, got {centre!r}")
    radius, feather = (
        checked_positive(radius, "radius", allow_zero=True),
        checked_positive(feather, "feather", allow_zero=True),
    )
    d = np.linalg.norm(p - c, axis=-1) - radius
    if feather == 0:
        return (d <= 0).astype(np.float64)
    t = np.clip(1.0 - d / feather, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


