"""Plain vectorized numpy versions of the kernels: the benchmark baseline and the tests' oracle.

Slow but simple; they compute exactly the sums the numba kernels compute.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
from scipy import sparse

from geoimg.parametrization._laplacian import corner_cotangents

__all__ = ["sample_grid_numpy", "evaluate_exact_numpy", "AreaBalanceNumpy", "point_triangle_distance", "place_numpy"]


def sample_grid_numpy(u, v, centres, sigma, radius, C, A, B):
    """Truncated rational-Gaussian surface on the grid ``u`` x ``v``, one row at a time.

    Same truncation box as :func:`geoimg.surface._gaussian_kernels.sample_grid_gaussian`.
    Returns (P (H, W, 3), S (H, W)).
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


class AreaBalanceNumpy:
    """Energy ``sum_t a_t [log(r_t)^2 + beta (D_t / A_t - 2)]`` of points on the sphere (or, ``planar``, of
    points ``(u, v, 0)`` seen from +z) and its gradient (numpy; the kernels are in
    :mod:`geoimg.parametrization._balance_kernels`).

    ``a_t`` are the mesh's triangle areas (normalized to sum 1), ``A_t`` the sphere's chord-triangle areas
    (signed: projected on the triangle's mean direction) scaled to sum 1, ``r_t = A_t / a_t`` and ``D_t``
    the Dirichlet energy of the triangle's affine map (cotangent formula with the mesh's angles).
    """

    def __init__(self, x, tris, n, beta, planar=False):
        self.tris, self.beta, self.planar = tris, beta, planar
        p = x[tris]
        a3 = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
        self.a = a3 / a3.sum()
        self.cot = corner_cotangents(x, tris)
        rows = tris.T.ravel()       # scatter of per-corner vectors to vertices
        self.scatter = sparse.csr_matrix((np.ones(len(rows)), (rows, np.arange(len(rows)))), shape=(n, len(rows)))

    def energy(self, s):
        p = s[self.tris]
        u = np.broadcast_to([0.0, 0.0, 1.0], p[:, 0].shape) if self.planar else p.sum(axis=1)   # seen from
        u = u / np.linalg.norm(u, axis=1, keepdims=True)
        area = 0.5 * np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), u)
        if not (area > 0).all():
            return np.inf, None
        lam = 1.0 / area.sum()
        opp = np.roll(p, -1, axis=1) - np.roll(p, 1, axis=1)          # edge facing corner k
        dirichlet = 0.5 * lam * (self.cot * (opp ** 2).sum(axis=2)).sum(axis=1)
        ay = lam * area
        lr = np.where(self.a > 0, np.log(ay / np.maximum(self.a, 1e-300)), 0.0)   # faces of no area: no term
        e = self.a @ lr ** 2 + self.beta * (self.a @ (dirichlet / ay - 2.0))
        return float(e), (p, u, ay, lam, lr, dirichlet)

    def gradient(self, state):
        p, u, ay, lam, lr, dirichlet = state
        f_d = (self.beta * self.a / ay * lam)[:, None]
        shift = 2.0 * lam * float(self.a @ lr)           # through lam = 1 / sum(area)
        f_a = ((2.0 * self.a * lr / ay - self.beta * self.a * dirichlet / ay ** 2) * lam - shift)[:, None]
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        if self.planar:                                     # the plane's direction +z does not turn
            turn = np.zeros_like(n)
        else:
            turn = 0.5 * (n - np.einsum("ij,ij->i", n, u)[:, None] * u) / np.linalg.norm(p.sum(axis=1), axis=1)[:, None]
        parts = []
        for k in range(3):
            k1, k2 = (k + 1) % 3, (k + 2) % 3
            g = (0.5 * np.cross(u, p[:, k2] - p[:, k1]) + turn) * f_a
            g += f_d * (self.cot[:, k2, None] * (p[:, k] - p[:, k1]) + self.cot[:, k1, None] * (p[:, k] - p[:, k2]))
            parts.append(g)
        return self.scatter @ np.concatenate(parts)


def point_triangle_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to triangles ``(a, b, c)`` (all (..., 3), broadcast; Ericson's regions).

    """
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
    bp = p - b
    d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
    cp = p - c
    d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v_in = vb / denom
        w_in = vc / denom
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    q = a + v_in[..., None] * ab + w_in[..., None] * ac
    q = np.where(((vc <= 0) & (d1 >= 0) & (d3 <= 0))[..., None], a + t_ab[..., None] * ab, q)
    q = np.where(((vb <= 0) & (d2 >= 0) & (d6 <= 0))[..., None], a + t_ac[..., None] * ac, q)
    q = np.where(((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0))[..., None], b + t_bc[..., None] * (c - b), q)
    q = np.where(((d6 >= 0) & (d5 <= d6))[..., None], c, q)
    q = np.where(((d3 >= 0) & (d4 <= d3))[..., None], b, q)
    q = np.where(((d1 <= 0) & (d2 <= 0))[..., None], a, q)
    q = np.where(np.isfinite(q), q, a)
    n = np.cross(ab, ac)
    flat = (n * n).sum(-1) <= 1e-24 * (ab * ab).sum(-1) * (ac * ac).sum(-1)     # no area: its edges
    edges = np.minimum(np.minimum(segment_distance(p, a, b), segment_distance(p, b, c)), segment_distance(p, c, a))
    return np.where(flat, edges, np.linalg.norm(p - q, axis=-1))


def segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to segments ``a``-``b`` (a point where a == b), broadcast."""
    d, q = b - a, p - a
    dd = (d * d).sum(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(dd > 0, np.clip((q * d).sum(-1) / dd, 0.0, 1.0), 0.0)
    return np.linalg.norm(q - t[..., None] * d, axis=-1)


def _fused_dot(a, b) -> float:
    """``a . b`` of 3-vectors with each product-and-add rounded once (exact fractions, rounded to float)."""
    acc = float(Fraction(a[0]) * Fraction(b[0]))
    for k in (1, 2):
        acc = float(Fraction(a[k]) * Fraction(b[k]) + Fraction(acc))
    return acc


def place_numpy(s, v, u, faces, n_changed):
    """The coarse-to-fine map's placement of a returning vertex (``_progressive._place``), in numpy: the
    same candidates (neighbours' mean, changed faces' centroids, the wedge, 48 directions, 40 halvings),
    the one whose smallest chord-triangle orientation is largest (the first of equals) wins. Returns
    whether it is positive; ``s[v]`` is set (to ``s[u]`` when not)."""
    ring = np.unique(faces)
    su = s[u].copy()
    others = s[ring[(ring != v) & (ring != u)]]
    targets = [others.mean(axis=0)]
    for f in faces[len(faces) - n_changed:]:
        targets.append(s[np.where(f == v, u, f)].mean(axis=0))
    reach = float(np.linalg.norm(others - su, axis=1).mean())
    t1 = np.cross(su, [1.0, 0.0, 0.0] if abs(su[0]) < 0.9 else [0.0, 1.0, 0.0])
    t1 /= np.sqrt(_fused_dot(t1, t1))
    t2 = np.cross(su, t1)
    ang = np.linspace(0.0, 2 * np.pi, 48, endpoint=False)
    wedge = np.zeros(3)
    for f in faces:
        if u in f:
            j = int(np.flatnonzero(f == v)[0])
            g = np.cross(s[f[(j + 1) % 3]], s[f[(j + 2) % 3]])
            g -= _fused_dot(g, su) * su
            wedge += g / max(np.sqrt(_fused_dot(g, g)), 1e-300)
    ends = np.vstack([targets, su + reach * wedge / max(np.sqrt(_fused_dot(wedge, wedge)), 1e-300),
                      su + reach * (np.cos(ang)[:, None] * t1 + np.sin(ang)[:, None] * t2)])
    cand = (su + (ends - su)[:, None, :] * (0.5 ** np.arange(40))[None, :, None]).reshape(-1, 3)
    size = np.linalg.norm(cand, axis=1, keepdims=True)
    cand = np.where(size > 0, cand / np.where(size > 0, size, 1.0), su)    # a candidate at the centre: u itself
    p = np.where((faces == v)[None, :, :, None], cand[:, None, None, :], s[faces][None])     # (cand, face, 3, 3)
    det = (p[..., 0, 0] * (p[..., 1, 1] * p[..., 2, 2] - p[..., 1, 2] * p[..., 2, 1])
           - p[..., 0, 1] * (p[..., 1, 0] * p[..., 2, 2] - p[..., 1, 2] * p[..., 2, 0])
           + p[..., 0, 2] * (p[..., 1, 0] * p[..., 2, 1] - p[..., 1, 1] * p[..., 2, 0]))
    score = det.min(axis=1)
    best = int(np.argmax(score))
    s[v] = cand[best] if score[best] > 0 else su
    return bool(score[best] > 0)


def coverage_numpy(pts: np.ndarray, E: np.ndarray, K: np.ndarray, w: np.ndarray, sigma: float) -> np.ndarray:
    """The coverage-weighted surface at homogeneous points ``pts`` (k, 3), summed over every triangle in plain
    numpy (weights ``prod Phi(E_k . p / sigma)``, maps ``K p / (w . p)``; triangles with ``w . p <= 1/2`` left
    out, as the kernel does): the twin of ``geoimg.surface._coverage_kernels``."""
    from scipy.special import ndtr
    z = np.einsum("tkc,pc->ptk", E, pts) / sigma
    F = ndtr(z).prod(axis=2)
    wp = pts @ w.T
    F = np.where(wp > 0.5, F, 0.0)
    P = np.einsum("tic,pc->pti", K, pts) / np.where(wp > 0.5, wp, 1.0)[..., None]
    return (F[..., None] * P).sum(axis=1) / F.sum(axis=1)[:, None]
