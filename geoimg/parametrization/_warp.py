"""A warp of the sphere that brings landmarks onto targets: the first step of landmark-aligned morphs
(issue 17), which will deform a later key's spherical parametrization so that its features meet key 0's.

First the rotation that best matches the landmarks (Kabsch on their directions). Then a flow of small steps:
each step moves every point by a smooth tangent field, a sum of Gaussians centred on the landmarks whose
weights make the landmarks move a fraction of the way to their targets; a step is accepted only when no
triangle of the mesh turns over on the sphere (so the map stays one-to-one on the mesh) and is halved
otherwise. A composition of such small, smooth, fold-free steps is the warp. When no fold-free step is left
(landmarks whose paths must cross, or squeeze a region below the mesh's resolution) it stops and says how far
the landmarks still are (``met`` False): on random configurations of 10 landmarks each moved by about
0.2 rad, 8 of 12 meet on a 2,562-vertex sphere; a long sliver of a squeezed sphere map (one of
the remeshed woman of benchmarks/bench_landmarks.py: 0.14 rad long, 4e-9 in area) turns over under any
smooth step, and stops it early.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ._orientation import chord_orientation

__all__ = ["warp_sphere", "best_rotation", "WARP_TOLERANCE"]

WARP_TOLERANCE = 1e-4      # radians left between each landmark and its target (1e-4 of a unit sphere)
STEP = 0.25                # fraction of the way each step tries to move the landmarks
MAX_STEPS = 400


def best_rotation(sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """The rotation matrix R (3, 3) minimizing ``sum |R a_i - b_i|^2`` over unit vectors (Kabsch).

    Examples
    --------
    >>> a = np.eye(3)
    >>> R = best_rotation(a, a[[1, 2, 0]])
    >>> np.round(R @ a[0], 6).tolist()
    [0.0, 1.0, 0.0]
    """
    h = np.asarray(sources, np.float64).T @ np.asarray(targets, np.float64)
    u, _, vt = np.linalg.svd(h)
    sign = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    return vt.T @ np.diag([1.0, 1.0, sign]) @ u.T


def _log(p: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The tangent vector at each unit ``p`` pointing to ``b`` along the great circle, as long as the arc."""
    cos = np.clip(np.einsum("ij,ij->i", p, b), -1.0, 1.0)
    t = b - cos[:, None] * p
    n = np.linalg.norm(t, axis=1, keepdims=True)
    return np.where(n > 1e-15, t / np.maximum(n, 1e-300), 0.0) * np.arccos(cos)[:, None]


def _field(x: np.ndarray, centres: np.ndarray, weights: np.ndarray, width: np.ndarray) -> np.ndarray:
    """The tangent field ``sum_j weights_j exp(-|x - c_j|^2 / 2 width_j^2)`` at ``x``, projected on the
    tangent plane of each point."""
    d2 = ((x[:, None, :] - centres[None, :, :]) ** 2).sum(axis=2)
    v = np.exp(-d2 / (2.0 * width[None, :] ** 2)) @ weights
    return v - np.einsum("ij,ij->i", v, x)[:, None] * x


def warp_sphere(coords: ArrayLike, tris: ArrayLike, landmarks: ArrayLike, targets: ArrayLike, *,
                tol: float = WARP_TOLERANCE, max_steps: int = MAX_STEPS) -> tuple[np.ndarray, dict]:
    """Warp a mesh's sphere coordinates so that its ``landmarks`` (vertex indices) land on ``targets``
    (unit vectors), with no triangle turned over.

    Parameters
    ----------
    coords : array_like, shape (N, 3)
        Unit vectors: a spherical parametrization whose triangles all run counter-clockwise from outside.
    tris : array_like, shape (T, 3)
    landmarks : array_like of int, shape (L,)
        Distinct vertices, at distinct places.
    targets : array_like, shape (L, 3)
        Where they must go (normalized here).

    Returns
    -------
    coords : numpy.ndarray (N, 3)
    info : dict
        ``rotation`` (3 x 3, applied first), ``steps``, ``residual`` (the largest angle in radians left
        between a landmark and its target), ``folded`` (triangles turned over: 0 unless the input had some),
        ``met`` (whether every landmark is within ``tol``).

    Raises
    ------
    InputError
        If the landmarks are out of range, repeated or at the same place, the targets are not finite
        non-zero vectors, or the counts differ.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.spatial import ConvexHull
    >>> d = np.random.default_rng(0).normal(size=(400, 3))
    >>> d /= np.linalg.norm(d, axis=1, keepdims=True)
    >>> tris = ConvexHull(d).simplices
    >>> tris = np.where((np.einsum("ij,ij->i", d[tris[:, 0]], np.cross(d[tris[:, 1]], d[tris[:, 2]])) > 0)[:, None],
    ...                 tris, tris[:, ::-1])
    >>> goal = d[[0, 1, 2, 3]] + 0.2 * np.eye(4, 3)
    >>> out, info = warp_sphere(d, tris, [0, 1, 2, 3], goal)
    >>> info["met"], info["folded"]
    (True, 0)
    """
    x = np.array(coords, np.float64)
    t = np.asarray(tris, np.int64)
    idx = np.asarray(landmarks)
    b = np.asarray(targets, np.float64)
    if x.ndim != 2 or x.shape[1] != 3 or not np.isfinite(x).all():
        raise InputError(f"coords: expected finite unit vectors of shape (N, 3), got {x.shape}")
    if idx.ndim != 1 or not np.issubdtype(idx.dtype, np.integer) or len(idx) == 0:
        raise InputError("landmarks: expected a non-empty list of vertex indices")
    if idx.min() < 0 or idx.max() >= len(x):
        raise InputError(f"landmarks: vertex {int(idx.max() if idx.max() >= len(x) else idx.min())} is not one of "
                         f"the {len(x)} vertices")
    if len(np.unique(idx)) != len(idx):
        raise InputError("landmarks: a vertex is named twice")
    if b.shape != (len(idx), 3) or not np.isfinite(b).all() or np.any(np.linalg.norm(b, axis=1) == 0):
        raise InputError(f"targets: expected {len(idx)} finite non-zero vectors, got shape {b.shape}")
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    for name, pts in (("landmarks", x[idx]), ("targets", b)):
        gap = np.linalg.norm(pts[:, None] - pts[None], axis=2) + np.eye(len(pts)) * 9.0
        if gap.min() < 1e-9:
            raise InputError(f"{name}: two of them are at the same place")
    rotation = best_rotation(x[idx], b) if len(idx) > 1 else np.eye(3)
    x = x @ rotation.T
    before = int(np.sum(chord_orientation(x, t) <= 0))
    steps, fraction = 0, STEP
    while steps < max_steps:
        p = x[idx]
        err = _log(p, b)
        if np.linalg.norm(err, axis=1).max() < tol:
            break
        # each landmark's Gaussian: half as wide as the distance to its nearest landmark (at most a quarter
        # sphere), so that landmarks going different ways each move their own surroundings and the weights
        # stay well conditioned however close two landmarks are
        gap = np.linalg.norm(p[:, None] - p[None], axis=2) + np.eye(len(p)) * 9.0
        width = np.clip(0.5 * gap.min(axis=1), 1e-6, 0.7) if len(p) > 1 else np.array([0.7])
        kernel = np.exp(-((p[:, None] - p[None]) ** 2).sum(axis=2) / (2.0 * width[None, :] ** 2))
        weights = np.linalg.solve(kernel + 1e-10 * np.eye(len(p)), fraction * err)
        trial = x + _field(x, p, weights, width)
        trial /= np.linalg.norm(trial, axis=1, keepdims=True)
        if np.sum(chord_orientation(trial, t) <= 0) > before:
            fraction *= 0.5                               # too far for one fold-free step: a smaller one
            if fraction < 1e-6:
                break
            continue
        x, steps = trial, steps + 1
        fraction = min(STEP, 2.0 * fraction)
    residual = float(np.linalg.norm(_log(x[idx], b), axis=1).max())
    return x, {"rotation": rotation, "steps": steps, "residual": residual,
               "folded": int(np.sum(chord_orientation(x, t) <= 0)), "met": bool(residual < tol)}
