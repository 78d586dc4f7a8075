"""Gauss-Newton descent of the planar area-balancing energy: a few sparse solves where the Sobolev steps of
:mod:`._balance` take hundreds.

The energy is :mod:`._balance`'s, ``E = sum_t a_t [log(A_t / a_t)^2 + beta (D_t / A_t - 2)]``. Each step
solves ``M d = -grad E`` with the Gauss-Newton metric

    ``M = sum_t 2 a_t / A_t^2 grad A_t grad A_t^T + beta a_t / A_t H_t``

(the log term's Gauss-Newton part and the angle term's convex part, ``H_t`` the triangle's cotangent
stencil: positive semi-definite triangle by triangle, so nothing is clamped). It grows like ``1 / A^2``
where the map squeezes, which is what the Sobolev steps' squeeze scaling imitates. The area term's coupling
of u and v is left out, so u and v are two scalar systems: a vertex held does not move, one sliding along a
side of the square (axis-aligned) moves in one of them. The metric is assembled in numba into the mesh's
fixed sparsity pattern and factored by SuperLU. Every accepted step keeps every triangle positive and lowers
the energy (the step halved from the full one until it does).

Far from a balanced map (a CAD fan squeezed to 1e-9 of the square, a triangle of no area) the quadratic
model is poor and the steps short: a step shorter than :data:`SHORTEST_STEP` of the full one, or an energy
that is not finite, *stalls* the descent, and the caller goes back to the Sobolev steps and single-vertex
sweeps, which open such maps.

Examples
--------
A square's four triangles round a centre pulled towards one corner: a few steps move it back.

>>> x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]])
>>> tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
>>> start = x.copy(); start[4, :2] = 0.3
>>> moves = np.array([False, False, False, False, True])
>>> out, steps, (e0, e1), stalled = newton_balance(start, x, tris, moves, np.zeros((5, 3)))
>>> stalled, steps <= 5, np.round(out[4], 4).tolist()
(False, True, [0.5, 0.5, 0.0])
"""
from __future__ import annotations

import numpy as np
from concurrent.futures import ThreadPoolExecutor

from scipy import sparse

from ._balance import lower_along, target_shares
from ._balance_kernels import balance_energy, balance_gradient, gauss_newton_metric
from ._laplacian import corner_cotangents, factor_symmetric

__all__ = ["newton_balance", "slides_on_axes", "NEWTON_STEPS", "NEWTON_TOLERANCE", "SHORTEST_STEP"]

NEWTON_STEPS = 40          # steps at most
NEWTON_TOLERANCE = 1e-3    # ... stopping once a step lowers the energy by less than this share of it
SHORTEST_STEP = 1 / 256    # a step shorter than this share of the full one stalls the descent
FLOOR = 1e-9               # an energy this low is 0 (a balanced map's; rounding makes it -1e-17)
RIDGE = 1e-10              # each metric's diagonal raised by this share of its mean: a solve where it is flat


def slides_on_axes(along: np.ndarray) -> bool:
    """Whether every sliding direction (a row of ``along`` that is not zero) is the u or the v axis, so that
    u and v are separate systems.

    >>> slides_on_axes(np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, 0]])), slides_on_axes(np.array([[0.6, 0.8, 0]]))
    (True, False)
    """
    on = np.asarray(along, np.float64)[:, :2] != 0.0
    return bool((on.sum(axis=1) <= 1).all())


def _pattern(tris: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sparsity pattern (CSR ``indptr, indices``) of the n x n matrices with an entry for every two
    corners of a triangle, and ``slot`` (T, 3, 3): where each (corner, corner) entry is in the values.
    """
    rows = np.repeat(tris, 3, axis=1).ravel()
    cols = np.tile(tris, (1, 3)).ravel()
    m = sparse.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    m.sum_duplicates()
    m.sort_indices()
    keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(m.indptr)) * n + m.indices
    slot = np.searchsorted(keys, rows.astype(np.int64) * n + cols)
    return m.indptr, m.indices, slot.reshape(-1, 3, 3)


def _block(indptr: np.ndarray, indices: np.ndarray, keep: np.ndarray, n: int):
    """The pattern (CSC ``indptr, indices``) of the block of rows and columns ``keep``, and where its
    values are in the whole matrix's (so each step takes them without indexing a matrix).
    """
    numbered = sparse.csr_matrix((np.arange(1.0, len(indices) + 1.0), indices, indptr), shape=(n, n))
    block = numbered[keep][:, keep].tocsc()
    block.sort_indices()
    return block.indptr, block.indices, block.data.astype(np.int64) - 1


def _solve(block, values: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve the block of the metric with the given values for ``rhs``."""
    indptr, indices, take = block
    k = len(rhs)
    m = sparse.csc_matrix((values[take], indices, indptr), shape=(k, k))
    m = m + RIDGE * max(float(m.diagonal().mean()), 1e-300) * sparse.identity(k, format="csc")
    return factor_symmetric(m).solve(rhs)


def newton_balance(s, x, tris, moves, along, *, beta: float = 0.3, shares=None, steps: int = NEWTON_STEPS,
                   tolerance: float | None = None, progress=None, cache: dict | None = None):
    """Gauss-Newton descent of the planar balancing energy from ``s`` (points ``(u, v, 0)``).

    Parameters
    ----------
    s : (n, 3) float
        The map, counter-clockwise; left as it is.
    x, tris : the mesh's vertices (n, 3) and triangles (T, 3).
    moves : (n,) bool
        The vertices that move.
    along : (n, 3) float
        A direction per vertex that may only slide along it, the u or the v axis (zero rows move freely;
        see :func:`slides_on_axes`).
    beta, shares : as for :func:`._balance.balance`.
    steps : int
        Steps at most; the descent stops sooner once a step lowers the energy by less than ``tolerance``
        (:data:`NEWTON_TOLERANCE` by default) of itself.
    progress : callable, optional
        Hears each step's energy.
    cache : dict, optional
        Keeps the mesh's sparsity pattern for the next call with the same triangles (a disk's starts and
        their relaxing go on one mesh), as :func:`._balance.balance` keeps its Sobolev factor.

    Returns
    -------
    s, steps taken, (energy at the start, energy at the end), stalled
        ``stalled``: the energy was not finite, or a step had to be shorter than :data:`SHORTEST_STEP` of
        the full one while the quadratic model promised more than ``tolerance`` of the energy (the map so
        far is returned; the caller goes back to the Sobolev steps).
    """
    s = np.array(s, dtype=np.float64)
    tris = np.ascontiguousarray(tris, np.int64)
    tolerance = NEWTON_TOLERANCE if tolerance is None else float(tolerance)
    moves = np.asarray(moves, bool)
    along = np.asarray(along, np.float64)
    if not slides_on_axes(along):
        raise ValueError("along: every sliding direction must be the u or the v axis")
    n = len(s)
    a, cot = target_shares(x, tris, shares), corner_cotangents(x, tris)
    e, state = balance_energy(s, tris, a, cot, beta, True)
    e_start = e
    if not np.isfinite(e):
        return s, 0, (e, e), True
    slides = np.any(along[:, :2] != 0.0, axis=1)
    unknowns = [np.flatnonzero(moves & (~slides | (along[:, c] != 0.0))) for c in range(2)]
    if steps <= 0 or not any(len(k) for k in unknowns):
        return s, 0, (e, e), False
    cache = {} if cache is None else cache
    if "newton_pattern" not in cache:
        cache["newton_pattern"] = _pattern(tris, n)
    indptr, indices, slot = cache["newton_pattern"]
    blocks = [_block(indptr, indices, k, n) for k in unknowns]
    values = [np.empty(len(indices)), np.empty(len(indices))]
    # u and v factored side by side: SuperLU lets go of the interpreter while it factors (the pair 1.3-1.8x
    # faster on two cores; each factor the same bits as alone)
    with ThreadPoolExecutor(max_workers=2) as pool:
        for step in range(steps):
            g = balance_gradient(s, tris, a, cot, beta, state)
            gauss_newton_metric(s, tris, a, cot, float(beta), slot, values[0], values[1])
            d = np.zeros_like(s)
            solving = [(c, pool.submit(_solve, blocks[c], values[c], -g[unknowns[c], c])) for c in range(2)
                       if len(unknowns[c])]
            for c, job in solving:
                d[unknowns[c], c] = job.result()
            found = lower_along(s, d, 1.0, e, tris, a, cot, beta, True, above=SHORTEST_STEP / 2)
            if found is None:        # no lower energy: at the minimum (the model's decrease is tiny), or stalled
                predicted = -0.5 * float(np.add.reduce((g[:, :2] * d[:, :2]).ravel()))
                return s, step, (e_start, e), not predicted < tolerance * max(e, FLOOR)
            converged = e - found[1] < tolerance * max(e, FLOOR)
            s, e, state, _ = found
            if progress is not None:
                progress(f"Gauss-Newton step {step}: energy {e:.4f}")
            if converged:
                return s, step + 1, (e_start, e), False
        return s, steps, (e_start, e), False
