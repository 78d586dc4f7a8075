"""A warp of the sphere that brings landmarks onto targets: the alignment of landmarked morphs (issue 17).

The warp is a smooth map of the sphere, carried by any set of points (in a morph, the directions of an
image's pixels): so it is checked for folds on that set's triangulation, never on a mesh's own sphere map,
whose long slivers (a region the area balancing squeezed) would turn over under any smooth step.

First the rotation that best matches the landmarks (Kabsch on their directions). Then a flow of small
steps: each step moves every point by a smooth tangent field, a sum of Gaussians centred on the landmarks
whose weights make the landmarks move (nearly) a fraction of the way to their targets; a step is accepted only when
no triangle of the carried set turns over (so the map stays one-to-one) and is halved otherwise. A
composition of such small, smooth, fold-free steps is the warp. When no fold-free step is left (landmarks
whose paths must cross, or that squeeze a region below the set's resolution) it stops and says how far the
landmarks still are (``met`` False).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..parametrization._orientation import chord_orientation
from .._threads import fixed_order

__all__ = ["warp_sphere", "best_rotation", "WARP_TOLERANCE"]

WARP_TOLERANCE = 1e-4      # radians left between each landmark and its target (1e-4 of a unit sphere)
STEP = 0.25                # fraction of the way each step tries to move the landmarks
MAX_STEPS = 400
WIDTH = 2.0                # each landmark's Gaussian: this many times the distance to its nearest landmark ...
MAX_WIDTH = 0.5            # ... at most this (radians)
RIDGE = 1e-3               # regularization of the landmarks' kernel system (close landmarks, wide Gaussians)


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
    tangent plane of each point.
    """
    d2 = np.maximum((x * x).sum(axis=1)[:, None] + (centres * centres).sum(axis=1)[None, :] - 2.0 * x @ centres.T,
                    0.0)
    v = np.exp(-d2 / (2.0 * width[None, :] ** 2)) @ weights
    return v - np.einsum("ij,ij->i", v, x)[:, None] * x


def _unit(name: str, a: ArrayLike) -> np.ndarray:
    x = np.array(a, np.float64)
    if x.ndim != 2 or x.shape[1] != 3 or not np.isfinite(x).all() or np.any(np.linalg.norm(x, axis=1) == 0):
        raise InputError(f"{name}: expected finite non-zero vectors of shape (N, 3), got shape {x.shape}")
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def _area_log_rms(before: np.ndarray, after: np.ndarray) -> float:
    """Area log-RMS of the warp: RMS of ``log(area after / area before)``, weighted by the area before."""
    keep = (before > 0) & (after > 0)
    if not keep.any():
        return 0.0
    log = np.log(after[keep] / before[keep])
    return float(np.sqrt(np.average(log ** 2, weights=before[keep])))


@fixed_order
def warp_sphere(points: ArrayLike, tris: ArrayLike, sources: ArrayLike, targets: ArrayLike, *,
                tol: float = WARP_TOLERANCE, max_steps: int = MAX_STEPS) -> tuple[np.ndarray, dict]:
    """Warp the sphere so that the landmark directions ``sources`` land on ``targets``, carrying ``points``
    along with no triangle of ``tris`` turned over.

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Directions the warp carries (normalized here), e.g. the pixel directions of an octahedral image.
    tris : array_like, shape (T, 3)
        A triangulation of ``points`` covering the sphere, checked for folds: a triangle folds when its
        orientation on the sphere turns (triangles flat at the start, to rounding, are not checked).
    sources, targets : array_like, shape (L, 3)
        Landmark directions and where they must go (normalized here); distinct.

    Returns
    -------
    points : numpy.ndarray (N, 3)
        The warped directions.
    info : dict
        ``rotation`` (3 x 3, applied first), ``steps``, ``residual`` (the largest angle in radians left
        between a landmark and its target), ``folded`` (triangles turned over: 0), ``met`` (every landmark
        within ``tol``), ``landmarks`` (where the sources went), ``area_log_rms`` (the warp's own area
        distortion on ``tris``: RMS of the log area ratio, weighted by area).

    Raises
    ------
    InputError
        If the directions are not finite non-zero vectors, the counts differ, two landmarks (or two targets)
        are at the same place, or ``tris`` names points that do not exist.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.spatial import ConvexHull
    >>> d = np.random.default_rng(0).normal(size=(2000, 3))
    >>> d /= np.linalg.norm(d, axis=1, keepdims=True)
    >>> tris = ConvexHull(d).simplices
    >>> marks = d[:4]
    >>> out, info = warp_sphere(d, tris, marks, marks + 0.2 * np.eye(4, 3))
    >>> info["met"], info["folded"]
    (True, 0)
    """
    x = _unit("points", points)
    t = np.asarray(tris)
    if t.ndim != 2 or t.shape[1] != 3 or not np.issubdtype(t.dtype, np.integer) or \
            (t.size and (t.min() < 0 or t.max() >= len(x))):
        raise InputError(f"tris: expected (T, 3) indices of the {len(x)} points")
    a, b = _unit("sources", sources), _unit("targets", targets)
    if len(a) == 0 or b.shape != a.shape:
        raise InputError(f"targets: expected one target per landmark ({len(a)}), got {len(b)}")
    for name, pts in (("sources", a), ("targets", b)):
        gap = np.linalg.norm(pts[:, None] - pts[None], axis=2) + np.eye(len(pts)) * 9.0
        if gap.min() < 1e-9:
            raise InputError(f"{name}: two landmarks are at the same place")
    rotation = best_rotation(a, b) if len(a) > 1 else np.eye(3)
    x, p = x @ rotation.T, a @ rotation.T
    start = chord_orientation(x, t)
    checked = np.abs(start) > 1e-10 * np.abs(start).max(initial=0.0)    # flat ones (rounding's sign) aside
    sign = np.sign(start[checked])
    steps, fraction = 0, STEP
    while steps < max_steps:
        err = _log(p, b)
        if np.linalg.norm(err, axis=1).max() < tol:
            break
        # each landmark's Gaussian: twice as wide as the distance to its nearest landmark, at most half a
        # radian, so that the field reaches between landmarks (the regions between them move with them) yet
        # landmarks going different ways each move their own surroundings; the ridge keeps the weights of
        # close landmarks bounded (a step then moves them only nearly ``fraction`` of the way: the flow goes on)
        gap = np.linalg.norm(p[:, None] - p[None], axis=2) + np.eye(len(p)) * 9.0
        width = np.clip(WIDTH * gap.min(axis=1), 1e-6, MAX_WIDTH) if len(p) > 1 else np.array([MAX_WIDTH])
        kernel = np.exp(-((p[:, None] - p[None]) ** 2).sum(axis=2) / (2.0 * width[None, :] ** 2))
        weights = np.linalg.solve(kernel + RIDGE * np.eye(len(p)), fraction * err)
        trial = x + _field(x, p, weights, width)
        trial /= np.linalg.norm(trial, axis=1, keepdims=True)
        if np.any(np.sign(chord_orientation(trial, t)[checked]) != sign):
            fraction *= 0.5                               # too far for one fold-free step: a smaller one
            if fraction < 1e-6:
                break
            continue
        moved = p + _field(p, p, weights, width)
        x, p, steps = trial, moved / np.linalg.norm(moved, axis=1, keepdims=True), steps + 1
        fraction = min(STEP, 2.0 * fraction)
    end = chord_orientation(x, t)
    residual = float(np.linalg.norm(_log(p, b), axis=1).max())
    return x, {
        "rotation": rotation,
        "steps": steps,
        "residual": residual,
        "folded": int(np.sum(np.sign(end[checked]) != sign)),
        "met": bool(residual < tol),
        "landmarks": p,
        "area_log_rms": _area_log_rms(np.abs(start), np.abs(end) * (np.sign(end) == np.sign(start))),
    }
