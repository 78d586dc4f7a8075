"""The octahedral map (Praun & Hoppe 2003): the unit sphere unfolded onto the square.

A direction ``p`` is pushed onto the octahedron ``|x| + |y| + |z| = 1``; the upper half (z >= 0) is the
diamond ``|a| + |b| <= 1`` of the square ``[-1, 1]^2`` (``a = x, b = y``), and each lower face is folded
out over the diamond's edge into a corner triangle. Image coordinates are ``u = (a + 1) / 2`` (columns)
and ``v = (b + 1) / 2`` (rows), both in ``[0, 1]``.

Seams: each side of the square is glued to itself, mirrored about its midpoint, and all four corners
are the south pole. On an ``N x N`` grid whose samples include the sides (``N`` odd), pixel
``(0, j)`` is pixel ``(0, N-1-j)``, pixel ``(i, 0)`` is pixel ``(N-1-i, 0)`` (and likewise on the last
row and column): :func:`weld_index` lists these pairs, so a quad mesh welds them by index. An even
``N`` would put the two ends of each side's middle edge on one point, which is why it is refused.

The map preserves orientation: ``d p / d u x d p / d v`` points out of the sphere everywhere.
"""
from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError

__all__ = [
    "directions",
    "sampling_rotation",
    "square_to_sphere",
    "sphere_to_square",
    "check_size",
    "weld_index",
    "area_ratio",
    "grid_directions",
    "square_jacobian",
    "glued_groups",
    "group_means",
    "average_glued",
]


def _unfold(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    z = 1.0 - np.abs(a) - np.abs(b)
    lower = z < 0
    x = np.where(lower, np.copysign(1.0 - np.abs(b), a), a)
    y = np.where(lower, np.copysign(1.0 - np.abs(a), b), b)
    return np.stack([x, y, z], axis=-1)


def square_jacobian(uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives ``dq/du`` and ``dq/dv`` (..., 3) of the unit direction at image points ``uv``
    (one-sided on the creases, where the map bends).

    Parameters
    ----------
    uv : numpy.ndarray
        (..., 2) image points in ``[0, 1]^2``.

    Returns
    -------
    dq_du, dq_dv : numpy.ndarray
        (..., 3) each.

    Examples
    --------
    >>> du, dv = square_jacobian(np.array([[0.5, 0.5]]))
    >>> bool(abs(du @ [0, 0, 1]).max() < 1e-12)         # at the north pole the derivatives are tangent
    True
    """
    uv = np.asarray(uv, dtype=np.float64)
    a = 2.0 * uv[..., 0] - 1.0
    b = 2.0 * uv[..., 1] - 1.0
    p = _unfold(a, b)
    norm = np.linalg.norm(p, axis=-1, keepdims=True)
    q = p / norm
    sa, sb = np.where(a < 0, -1.0, 1.0), np.where(b < 0, -1.0, 1.0)
    lower = (1.0 - np.abs(a) - np.abs(b)) < 0
    zero = np.zeros_like(a)
    dpa = np.where(lower[..., None], np.stack([zero, -sa * sb, -sa], -1), np.stack([zero + 1, zero, -sa], -1))
    dpb = np.where(lower[..., None], np.stack([-sa * sb, zero, -sb], -1), np.stack([zero, zero + 1, -sb], -1))
    out = []
    for dp in (dpa, dpb):
        dq = (dp - q * (q * dp).sum(-1, keepdims=True)) / norm
        out.append(2.0 * dq)
    return out[0], out[1]


def grid_directions(n: int) -> np.ndarray:
    """Unit directions of the ``n x n`` octahedral grid (rows v, columns u), computed from integers so
    that glued pixels get bit-identical directions.

    Parameters
    ----------
    n : int
        The image's side, odd.

    Returns
    -------
    numpy.ndarray
        (n, n, 3) float64 unit directions.

    Examples
    --------
    >>> d = grid_directions(5)
    >>> d.shape, d[2, 2].tolist(), bool((d[0, 1] == d[0, 3] * [-1, 1, 1]).all() or (d[0, 1] == d[0, 3]).all())
    ((5, 5, 3), [0.0, 0.0, 1.0], True)
    """
    n = check_size(n)
    from ._octahedral_kernels import grid_unit     # numba: imported where a grid is made, not with the domains
    out = np.empty((n, n, 3))
    grid_unit(n, out)
    return out


def square_to_sphere(uv: np.ndarray) -> np.ndarray:
    """Unit directions of image points ``uv`` (..., 2) in ``[0, 1]^2``.

    Parameters
    ----------
    uv : numpy.ndarray
        (..., 2) image points.

    Returns
    -------
    numpy.ndarray
        (..., 3) unit directions.

    Examples
    --------
    >>> square_to_sphere(np.array([[0.5, 0.5], [1.0, 0.5], [0.0, 0.0]])).round(12) + 0.0
    array([[ 0.,  0.,  1.],
           [ 1.,  0.,  0.],
           [ 0.,  0., -1.]])
    """
    uv = np.asarray(uv, dtype=np.float64)
    p = _unfold(2.0 * uv[..., 0] - 1.0, 2.0 * uv[..., 1] - 1.0)
    return p / np.linalg.norm(p, axis=-1, keepdims=True)


def directions(p: ArrayLike, name: str = "p") -> np.ndarray:
    """Vectors ``p`` (..., 3) as float64, refused when one is not finite or is zero (it has no direction),
    or so long that the sum of its components' sizes overflows.

    Examples
    --------
    >>> directions([[0.0, 0.0, 0.0]])
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: p: 1 of 1 vectors have length 0, and no direction
    """
    p = np.asarray(p, dtype=np.float64)
    if p.ndim < 1 or p.shape[-1] != 3:
        raise InputError(f"{name}: expected vectors of shape (..., 3), got {p.shape}")
    if not np.isfinite(p).all():
        raise InputError(f"{name}: contains NaN or infinite values")
    size = np.abs(p).max(axis=-1)
    zero = size == 0
    if zero.any():
        raise InputError(f"{name}: {int(zero.sum())} of {zero.size} vectors have length 0, and no direction")
    if size.max() > 1e300:
        raise InputError(f"{name}: vectors of length {size.max():.3g}; scale them below 1e300")
    return p


def sphere_to_square(p: np.ndarray) -> np.ndarray:
    """Image points ``uv`` in ``[0, 1]^2`` of directions ``p`` (..., 3) (need not be unit length).

    Parameters
    ----------
    p : numpy.ndarray
        (..., 3) directions, not zero.

    Returns
    -------
    numpy.ndarray
        (..., 2) image points.

    Examples
    --------
    >>> q = square_to_sphere(np.array([[0.3, 0.9], [0.8, 0.6]]))
    >>> sphere_to_square(q).round(12).tolist()
    [[0.3, 0.9], [0.8, 0.6]]
    """
    p = directions(p)
    q = p / np.abs(p).sum(axis=-1, keepdims=True)
    x, y, z = q[..., 0], q[..., 1], q[..., 2]
    lower = z < 0
    a = np.where(lower, np.copysign(1.0 - np.abs(y), x), x)
    b = np.where(lower, np.copysign(1.0 - np.abs(x), y), y)
    return np.stack([(a + 1.0) / 2.0, (b + 1.0) / 2.0], axis=-1)


def area_ratio(p: np.ndarray) -> np.ndarray:
    """Square area per sphere area at directions ``p`` (..., 3): ``1 / (|x| + |y| + |z|)^3`` for unit ``p``
    (in the ``[-1, 1]^2`` square's units; between ``3^-1.5`` and 1).

    Parameters
    ----------
    p : numpy.ndarray
        (..., 3) directions.

    Returns
    -------
    numpy.ndarray
        (...,) the ratio.

    Examples
    --------
    >>> float(area_ratio(np.array([0.0, 0.0, 1.0])))
    1.0
    """
    p = directions(p)
    p = p / np.linalg.norm(p, axis=-1, keepdims=True)
    return 1.0 / np.abs(p).sum(axis=-1) ** 3


def check_size(n) -> int:
    """Validate the side of an octahedral image: an odd integer >= 3 (so glued pixels pair up)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 3 or n % 2 == 0:
        hint = f" (for example {int(n) + 1})" if isinstance(n, (int, np.integer)) and n >= 2 and n % 2 == 0 else ""
        raise InputError(f"resolution: an octahedral image needs an odd side >= 3, so that the glued boundary "
                         f"pixels pair up exactly{hint}; got {n!r}")
    return int(n)


def weld_index(n: int) -> np.ndarray:
    """For each pixel of an ``n x n`` octahedral image, the flat index of the pixel it is glued to
    (the smallest index of its group; itself for interior pixels).

    Examples
    --------
    >>> w = weld_index(5)
    >>> int(w[0, 4]), int(w[4, 4]), int(w[3, 0]), int(w[2, 0])
    (0, 0, 5, 10)
    >>> len(np.unique(w))   # (n - 1)^2 + 2 vertices: a closed genus-0 quad mesh
    18
    """
    n = check_size(n)
    idx = np.arange(n * n).reshape(n, n)
    rev = np.arange(n)[::-1]
    for side in (idx[0], idx[-1], idx[:, 0], idx[:, -1]):  # views: fold each side onto itself
        side[:] = np.minimum(side, side[rev])
    idx[0, 0] = idx[0, -1] = idx[-1, 0] = idx[-1, -1] = 0
    return idx


def glued_groups(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The groups of glued pixels of an ``n x n`` octahedral image: the flat index of each group's first
    pixel, and each pixel's group number (flat order). ``(n - 1)^2 + 2`` groups.

    Examples
    --------
    >>> reps, group = glued_groups(5)
    >>> len(reps), int(group[4]), int(group[24])     # the corners are one group
    (18, 0, 0)
    """
    return np.unique(weld_index(n).ravel(), return_inverse=True)


def group_means(values: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Mean of ``values`` (n, n, C) or (n * n, C) over each group of :func:`glued_groups`, shape (G, C)."""
    flat = np.asarray(values, np.float64).reshape(len(group), -1)
    counts = np.bincount(group).astype(np.float64)[:, None]
    return np.stack([np.bincount(group, flat[:, c]) for c in range(flat.shape[1])], axis=1) / counts


def average_glued(pixels: np.ndarray) -> np.ndarray:
    """Each group of glued pixels of an ``n x n (x C)`` octahedral image replaced by its mean, so glued
    pixels hold identical values (a filter keeps them equal only up to rounding).

    Examples
    --------
    >>> a = np.zeros((3, 3)); a[0, 0] = 4.0          # the four corners are one point
    >>> float(average_glued(a)[2, 2])
    1.0
    """
    a = np.asarray(pixels)
    _, group = glued_groups(a.shape[0])
    return group_means(a, group)[group].reshape(a.shape).astype(a.dtype)


SAMPLING_ROTATIONS = 256        # rotations tried by sampling_rotation (a fixed set: the same on every machine)
SAMPLING_TRIANGLES = 20000      # at most this many triangles (evenly spaced) rank them


@functools.cache
def _sampling_turns() -> np.ndarray:
    """The identity and :data:`SAMPLING_ROTATIONS` fixed rotations, (R + 1, 3, 3): unit quaternions of normal
    samples (numpy's ``RandomState(0)``), as matrices. The same bits as scipy's ``Rotation.random(R,
    random_state=0).as_matrix()`` (tested), without importing ``scipy.spatial`` (0.2 s of a first conversion).
    """
    q = np.random.RandomState(0).normal(size=(SAMPLING_ROTATIONS, 4))
    x, y, z, w = (q / np.sqrt(q[:, 0] * q[:, 0] + q[:, 1] * q[:, 1] + q[:, 2] * q[:, 2] + q[:, 3] * q[:, 3])[:, None]).T
    xx, yy, zz, ww = x * x, y * y, z * z, w * w
    xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
    turns = np.empty((SAMPLING_ROTATIONS + 1, 3, 3))
    turns[0] = np.eye(3)
    turns[1:] = np.stack([np.stack([xx - yy - zz + ww, 2 * (xy - zw), 2 * (xz + yw)], axis=1),
                          np.stack([2 * (xy + zw), -xx + yy - zz + ww, 2 * (yz - xw)], axis=1),
                          np.stack([2 * (xz - yw), 2 * (yz + xw), -xx - yy + zz + ww], axis=1)], axis=1)
    turns.flags.writeable = False
    return turns


def sampling_rotation(s: np.ndarray, x: np.ndarray, tris: np.ndarray,
                      bend: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """The turn of a sphere map ``s`` (unit vectors of the mesh ``x, tris``) whose octahedral image samples
    the mesh best, and how much better than no turn it is, in dB of the proxy.

    An octahedral image of side N gives a triangle of the mesh about ``N^2 a_t r(c_t) / 4`` samples, ``a_t``
    its area on the sphere, ``r`` the octahedral map's area ratio at its centre (between ``3^-1.5`` and 1), so
    the samples lie ``h_t^2 ~ A_t / (a_t r(c_t))`` apart on it (``A_t`` its area in space). Resampling errs
    there by about ``kappa_t h_t^2``, and the mean squared error over the surface is about
    ``sum_t A_t kappa_t^2 h_t^4 = sum_t kappa_t^2 A_t^3 / (a_t r(c_t))^2``, with ``kappa_t^2`` relative to its
    mean given by ``bend`` (:func:`._sampling_shares.bending_weight`; 1 everywhere when None). Of the identity
    and :data:`SAMPLING_ROTATIONS` fixed rotations, the one that makes this least is returned. Over twenty
    random turns of the map of ``bumpy.off``, the images' PSNR at 257^2 ranks with this at a Spearman
    correlation of 0.88, and at -0.87 without the curvature (which picked a turn 0.7 dB below the best); on
    the horse's, 0.64 against 0.48.

    Examples
    --------
    >>> t = (1 + 5 ** 0.5) / 2
    >>> v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
    ...               [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]])
    >>> f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
    ...               [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
    ...               [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    >>> R, gain = sampling_rotation(v / np.linalg.norm(v, axis=1, keepdims=True), v, f)
    >>> bool(np.allclose(R @ R.T, np.eye(3))), gain >= 0
    (True, True)
    """
    every = max(1, len(tris) // SAMPLING_TRIANGLES)
    tris = np.asarray(tris)[::every]
    area = 0.5 * np.linalg.norm(np.cross(x[tris[:, 1]] - x[tris[:, 0]], x[tris[:, 2]] - x[tris[:, 0]]), axis=1)
    on_sphere = 0.5 * np.linalg.norm(np.cross(s[tris[:, 1]] - s[tris[:, 0]], s[tris[:, 2]] - s[tris[:, 0]]), axis=1)
    ok = on_sphere > 0
    weight = area[ok] ** 3 / on_sphere[ok] ** 2
    if bend is not None:
        weight = weight * np.asarray(bend, np.float64)[::every][ok]
    c = s[tris[ok]].mean(axis=1)
    c /= np.maximum(np.linalg.norm(c, axis=1, keepdims=True), 1e-300)
    from ._octahedral_kernels import turned_errors
    turns = _sampling_turns()
    error = np.empty(len(turns))            # 1 / r(q) = (|x| + |y| + |z|)^3 for unit q
    turned_errors(np.ascontiguousarray(c), np.ascontiguousarray(weight, np.float64), turns, error)
    best = int(np.argmin(error))
    return turns[best].copy(), float(10.0 * np.log10(error[0] / error[best])) if error[best] > 0 else 0.0
