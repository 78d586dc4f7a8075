"""Plain vectorized numpy versions of the kernels: the benchmark baseline and the tests' oracle.

Slow but simple; they compute exactly the sums the numba kernels compute.
"""
from __future__ import annotations

import numpy as np

__all__ = ["sample_grid_numpy", "evaluate_exact_numpy"]


def sample_grid_numpy(u, v, centres, sigma, radius, C, A, B):
    """Truncated rational-Gaussian surface on the grid ``u`` x ``v``, one row at a time.

    Same truncation box as :func:`geoimg.kernels.sample_grid_gaussian`. Returns (P (H, W, 3), S (H, W)).
    """
    H, W = len(v), len(u)
    P = np.zeros((H, W, 3))
    S = np.zeros((H, W))
    inv2s = 0.5 / sigma ** 2
    for i in range(H):
        dv = v[i] - centres[:, 1]
        rows = np.flatnonzero(np.abs(dv) <= radius)
        if rows.size == 0:
            continue
        du = u[None, :] - centres[rows, 0][:, None]                      # (n, W)
        inside = np.abs(du) <= radius[rows][:, None]
        g = np.exp(-(du ** 2 + dv[rows][:, None] ** 2) * inv2s[rows][:, None]) * inside
        s = g.sum(axis=0)
        n = (g.T @ (C[rows] + B[rows] * dv[rows][:, None])) + np.einsum("fw,fw,fc->wc", g, du, A[rows])
        S[i] = s
        P[i] = n / np.where(s > 0, s, 1.0)[:, None]
    return P, S


def evaluate_exact_numpy(pts, centres, sigma, C, A, B):
    """Exact (untruncated) rational-Gaussian surface at points (k, 2), in the log domain."""
    pts = np.asarray(pts, np.float64)
    du = pts[:, None, 0] - centres[None, :, 0]
    dv = pts[:, None, 1] - centres[None, :, 1]
    e = -(du ** 2 + dv ** 2) / (2.0 * sigma ** 2)
    w = np.exp(e - e.max(axis=1, keepdims=True))
    w /= w.sum(axis=1, keepdims=True)
    return (np.einsum("kf,fc->kc", w, C) + np.einsum("kf,kf,fc->kc", w, du, A)
            + np.einsum("kf,kf,fc->kc", w, dv, B))
