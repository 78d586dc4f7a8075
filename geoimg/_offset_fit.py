"""A displaced image's offsets fitted to its mesh in least squares, not only where each line meets it.

The offsets where the line along each normal crosses the mesh (``_compress._Surface.offsets``) put every pixel
on the mesh, but not what lies between the pixels: where a crease or a crevice runs between two lines, the quad
across it cuts the corner, or neighbouring lines land on the two walls of a fold and the quad between them
bridges it (a penguin's flippers: a hundredth of the quads' samples held 84 % of their squared error). Here
the offsets are moved, each along its own line, so that the grid's pixels, edge midpoints and cell centres
lie closest to the mesh in the mean (Gauss-Newton rounds on their squared distances, each point's distance
linearized along the direction to its closest point), with a bending term on the offsets' second differences
(a slope costs nothing, a spike does: it holds a line nearly tangent to the surface, which no residual pins,
in line with its neighbours), each round's moves damped (Levenberg) and kept within a share of the pixel
spacing.

The linear solves are conjugate gradients with sums in a fixed order (``np.add.reduce``, no BLAS), so that
a file's bytes do not depend on the machine.

Examples
--------
A plane at z = 0.3 over a flat grid, the offsets started 0.05 short: the fit takes them to it.

>>> import geoimg
>>> from geoimg._compress import _Surface
>>> u, v = np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9))
>>> points = np.dstack([u, v, 0 * u]); normals = np.zeros_like(points); normals[..., 2] = 1
>>> plane = geoimg.Mesh([[-2, -2, 0.3], [2, -2, 0.3], [2, 2, 0.3], [-2, 2, 0.3]], [[0, 1, 2, 3]])
>>> h = fit_offsets(np.full((9, 9), 0.25), points, normals, _Surface(plane).closest)
>>> float(np.abs(h - 0.3).max()) < 1e-4
True
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy import sparse

__all__ = ["fit_offsets", "FIT_ROUNDS", "BENDINGS", "DAMPING", "FLOOR", "REACH"]

FIT_ROUNDS = 4         # Gauss-Newton rounds
# the bending's weights tried (a share of the mean of the normal equations' diagonal): little keeps the fit to
# the mesh (a ridge between two columns: the quads' RMS distance 29 % lower), more smooths what lines that miss
# a fold leave and codes in fewer bytes (the penguin at Draco q8's size +0.5 dB at 0.3, nothing at 0.03)
BENDINGS = (0.03, 0.3)
DAMPING = 0.1          # each offset's damping, a share of its own diagonal entry
FLOOR = 1e-3           # ... and a share of the diagonal's mean (a line no residual pins stays where it is)
REACH = 0.5            # a round moves an offset by at most this share of the pixel spacing around it
CG_TOLERANCE, CG_STEPS = 1e-3, 200     # the solves: residual relative to the right side, iterations at most


def _stencils(height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """The points the fit measures, as up to four pixels (flat indices, (m, 4)) and their weights (m, 4):
    each pixel, each edge's midpoint, each cell's centre.
    """
    idx = np.arange(height * width).reshape(height, width)
    parts = [(idx.reshape(-1, 1), [1.0]),
             (np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], axis=1), [0.5, 0.5]),
             (np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], axis=1), [0.5, 0.5]),
             (np.stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()],
                       axis=1), [0.25] * 4)]
    corners = np.concatenate([np.pad(c, ((0, 0), (0, 4 - c.shape[1]))) for c, _ in parts])
    weights = np.concatenate([np.tile(np.pad(w, (0, 4 - len(w))), (len(c), 1)) for c, w in parts])
    return corners, weights


def _bending(height: int, width: int) -> sparse.csr_matrix:
    """The grid's bending: ``h^T B h`` sums the squared second differences along rows and along columns (zero
    for offsets that change linearly: a slope is not penalized, a spike is).
    """
    idx = np.arange(height * width).reshape(height, width)
    triples = [(idx[:, :-2].ravel(), idx[:, 1:-1].ravel(), idx[:, 2:].ravel()),
               (idx[:-2, :].ravel(), idx[1:-1, :].ravel(), idx[2:, :].ravel())]
    a, b, c = (np.concatenate(k) for k in zip(*triples))
    rows = np.arange(len(a))
    d = sparse.csr_matrix((np.r_[np.ones(len(a)), -2.0 * np.ones(len(a)), np.ones(len(a))],
                           (np.r_[rows, rows, rows], np.r_[a, b, c])), shape=(len(a), height * width))
    return (d.T @ d).tocsr()


def _spacing(points: np.ndarray) -> np.ndarray:
    """The mean length of the grid edges at each pixel (H * W,)."""
    across = np.linalg.norm(np.diff(points, axis=1), axis=-1)
    down = np.linalg.norm(np.diff(points, axis=0), axis=-1)
    total, count = np.zeros(points.shape[:2]), np.zeros(points.shape[:2])
    for edges, (first, second) in ((across, (np.s_[:, :-1], np.s_[:, 1:])), (down, (np.s_[:-1, :], np.s_[1:, :]))):
        for side in (first, second):
            total[side] += edges
            count[side] += 1
    return (total / np.maximum(count, 1)).ravel()


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """``a . b`` summed in a fixed order (pairwise, no BLAS): the same bits on any machine."""
    return float(np.add.reduce(a * b))


def _solve(a: sparse.csr_matrix, b: np.ndarray) -> np.ndarray:
    """``a^-1 b`` for a symmetric positive definite ``a`` by conjugate gradients, Jacobi preconditioned, to
    :data:`CG_TOLERANCE` of ``b`` or :data:`CG_STEPS` steps.
    """
    diagonal = a.diagonal()
    inverse_diagonal = np.divide(1.0, diagonal, out=np.zeros_like(diagonal), where=diagonal > 0)
    x = np.zeros_like(b)
    r = b.copy()
    z = inverse_diagonal * r
    p = z.copy()
    rz = _dot(r, z)
    stop = (CG_TOLERANCE ** 2) * _dot(b, b)
    for _ in range(CG_STEPS):
        if _dot(r, r) <= stop:
            break
        q = a @ p
        curvature = _dot(p, q)
        if not curvature > 0.0:
            break
        alpha = rz / curvature
        x += alpha * p
        r -= alpha * q
        z = inverse_diagonal * r
        rz, before = _dot(r, z), rz
        p = z + (rz / before) * p
    return x


def fit_offsets(start: np.ndarray, points: np.ndarray, normals: np.ndarray,
                closest: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]],
                bending: float = BENDINGS[0], rounds: int = FIT_ROUNDS) -> np.ndarray:
    """Offsets (H, W) along ``normals`` from ``points`` (each (H, W, 3)) that bring the displaced grid closest
    to a mesh in least squares, from the offsets ``start`` (H, W) (see the module's text).

    Parameters
    ----------
    start : numpy.ndarray
        (H, W) offsets to start from: where each line meets the mesh.
    points, normals : numpy.ndarray
        (H, W, 3) the upsampled base and its unit normals (:func:`geoimg.image._displacement.base_frame`).
    closest : callable
        ``closest(q)`` for points q (m, 3): their squared distances (m,), the closest faces' unit normals
        (m, 3) and the closest points (m, 3) on the mesh.
    bending : float
        The weight of the offsets' squared second differences, a share of the mean of the normal equations'
        diagonal (see :data:`BENDINGS`).
    rounds : int
        Gauss-Newton rounds.

    Returns
    -------
    numpy.ndarray
        (H, W) float64 offsets.
    """
    height, width = start.shape
    n = height * width
    corners, weights = _stencils(height, width)
    rows = np.repeat(np.arange(len(corners)), 4)
    bend = _bending(height, width)
    reach = REACH * _spacing(np.asarray(points, np.float64))
    p, nrm = np.asarray(points, np.float64).reshape(-1, 3), np.asarray(normals, np.float64).reshape(-1, 3)
    h = np.asarray(start, np.float64).ravel().copy()
    for _ in range(rounds):
        moved = p + h[:, None] * nrm
        q = np.einsum("mk,mkc->mc", weights, moved[corners])
        squared, face_normals, on = closest(q)
        gap = q - on
        length = np.sqrt(squared)
        away = np.divide(gap, length[:, None], out=face_normals.copy(), where=length[:, None] > 1e-12)
        residual = np.einsum("mc,mc->m", gap, away)
        jacobian = sparse.csr_matrix(((weights * np.einsum("mkc,mc->mk", nrm[corners], away)).ravel(),
                                      (rows, corners.ravel())), shape=(len(corners), n))
        normal = (jacobian.T @ jacobian).tocsr()
        diagonal = normal.diagonal()
        mean = float(np.add.reduce(diagonal)) / n
        if not mean > 0.0:           # no offset moves a point nearer or farther (normals all zero): as they are
            break
        weight = bending * mean
        system = (normal + weight * bend + sparse.diags(DAMPING * diagonal + FLOOR * mean)).tocsr()
        step = _solve(system, -(jacobian.T @ residual) - weight * (bend @ h))
        h += np.clip(step, -reach, reach)
    return h.reshape(height, width)
