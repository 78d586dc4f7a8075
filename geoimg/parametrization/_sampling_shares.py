"""The share of a geometry image each triangle of a mesh deserves: more where the surface bends.

An image resamples a piecewise-linear surface on a grid; where the grid's samples lie ``h`` apart on the
surface, the resampled surface errs by about ``kappa h^2`` (``kappa`` the curvature at the scale of a pixel),
so the mean squared error is about ``sum_t A_t kappa_t^2 h_t^4``. With ``rho_t`` samples per unit area,
``h_t^2 = 1 / rho_t``, and with the image's samples fixed (``sum_t A_t rho_t = N``), the error is least where
``rho_t`` grows as ``kappa_t^(2/3)`` (Lagrange: ``A kappa^2 / rho^3`` the same everywhere). A flat part would
then get no samples at all, which no map can give and no image needs to be faithful there only by luck: the
curvature is floored at a share of its mean (:data:`FLOOR`), so the flattest parts get about
``FLOOR^(1/3)`` of the density of a part of average bending.

``kappa^2`` of a triangle is that of the mesh's vertex normals interpolated across it (the Dirichlet energy of
the normal field, cotangent formula with cotangents clamped to ``[0, COT_CAP]`` so that a sliver adds no more
than a fair triangle), averaged over the neighbouring triangles (:data:`SMOOTHING` rounds through the
vertices, weighted by area): the bending at the scale of a few triangles, not of one edge.

Examples: :func:`bending` (an icosahedron, where every face gets its share of the area) and
:func:`sampling_shares` (a flat half beside a bent half).
"""
from __future__ import annotations

import numpy as np

from ._laplacian import corner_cotangents, triangle_areas, vertex_shares

__all__ = ["sampling_shares", "bending", "bending_weight", "FLOOR", "SMOOTHING", "COT_CAP"]

FLOOR = 0.1          # curvature^2 floored at this share of its mean over the surface (bench_fidelity: the sword
                     # at 257^2, linear resampling, 84.2 dB at 0.1, 83.7 at 0.3, 83.3 at 1.0; 81.3 unweighted)
SMOOTHING = 3        # rounds of averaging the bending through the vertices (face -> vertex -> face)
COT_CAP = 10.0       # a corner's cotangent counts at most this much (a sliver's angles near 0 and 180 degrees)


def bending(x: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Each triangle's squared curvature ``kappa_1^2 + kappa_2^2`` at the scale of a few triangles (T,): the
    Dirichlet energy of the vertex normals over the triangle, divided by its area, averaged with its neighbours'
    (:data:`SMOOTHING` rounds, weighted by area). 0 for a triangle of no area with no neighbours of any.

    Examples
    --------
    On a unit sphere both curvatures are 1: about 2 everywhere, so every face of an icosahedron gets its share
    of the area.

    >>> t = (1 + 5 ** 0.5) / 2
    >>> v = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
    ...               [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]])
    >>> f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
    ...               [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
    ...               [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    >>> k2 = bending(v / np.linalg.norm(v, axis=1, keepdims=True), f)
    >>> bool(np.allclose(k2, k2[0])), round(float(k2[0]), 1)
    (True, 2.0)
    >>> bool(np.allclose(sampling_shares(v, f), 1 / 20))
    True
    """
    x = np.asarray(x, np.float64)
    tris = np.asarray(tris, np.int64)
    n = len(x)
    p = x[tris]
    face_normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    area = triangle_areas(x, tris)
    corner_normal = np.repeat(face_normal, 3, axis=0)      # area-weighted, summed per vertex in order (np.add.at's)
    normal: np.ndarray = np.stack([np.bincount(tris.ravel(), corner_normal[:, c], minlength=n) for c in range(3)],
                                  axis=1)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    cot = np.clip(corner_cotangents(x, tris), 0.0, COT_CAP)
    energy = np.zeros(len(tris))                    # twice the normals' Dirichlet energy over each triangle
    for k in range(3):
        jump = normal[tris[:, (k + 1) % 3]] - normal[tris[:, (k + 2) % 3]]
        energy += cot[:, k] * np.einsum("ij,ij->i", jump, jump)
    energy[~(area > 1e-14 * max(float(area.max(initial=0.0)), 1e-300))] = 0.0   # no area: no bending to speak of
    around = np.maximum(vertex_shares(area, tris, n), 1e-300)
    for _ in range(max(SMOOTHING, 1)):
        per_vertex = vertex_shares(energy, tris, n) / around          # energy per area around each vertex
        per_area = per_vertex[tris].mean(axis=1)
        energy = per_area * area
    return per_area / 2.0


def bending_weight(x: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Each triangle's squared curvature over its mean over the surface (weighted by area), plus :data:`FLOOR`
    (T,): how much resampling errs there, per unit area and per ``h^4``, relative to a part of average
    bending (:func:`bending`). All ones on a flat mesh.

    >>> v = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    >>> bending_weight(v, np.array([[0, 1, 2], [0, 2, 3]])).tolist()
    [1.0, 1.0]
    """
    area = triangle_areas(np.asarray(x, np.float64), np.asarray(tris, np.int64))
    k2 = bending(x, tris)
    mean = float(area @ k2) / max(float(area.sum()), 1e-300)
    if not mean > 0.0:                  # flat, or of no area: alike everywhere
        return np.ones(len(k2))
    return k2 / mean + FLOOR


def sampling_shares(x: np.ndarray, tris: np.ndarray, weight: np.ndarray | None = None) -> np.ndarray:
    """The share of an image's samples each triangle of the mesh ``x, tris`` deserves (T,, summing to 1): its
    area times the cube root of its :func:`bending_weight` (``weight``, when already computed). Triangles of
    no area get none.

    Examples
    --------
    A flat half of a square beside a bent half (``z = 4 (x - 1/2)^2`` for ``x > 1/2``): per column of the grid,
    each triangle's share over its share of the area is highest where the bend begins.

    >>> u = np.linspace(0, 1, 11)
    >>> X, Y = np.meshgrid(u, u)
    >>> v = np.column_stack([X.ravel(), Y.ravel(), np.maximum(X.ravel() - 0.5, 0) ** 2 * 4])
    >>> i = np.arange(121).reshape(11, 11)
    >>> f = np.concatenate([np.stack([i[:-1, :-1], i[:-1, 1:], i[1:, 1:]], -1).reshape(-1, 3),
    ...                     np.stack([i[:-1, :-1], i[1:, 1:], i[1:, :-1]], -1).reshape(-1, 3)])
    >>> ratio = sampling_shares(v, f) / (triangle_areas(v, f) / triangle_areas(v, f).sum())
    >>> [round(float(ratio[f[:, 0] % 11 == c].mean()), 1) for c in range(10)]
    [0.5, 0.6, 0.8, 1.3, 1.7, 1.8, 1.6, 1.2, 0.8, 0.6]
    """
    area = triangle_areas(np.asarray(x, np.float64), np.asarray(tris, np.int64))
    weight = bending_weight(x, tris) if weight is None else weight
    share = area * np.cbrt(weight)
    total = float(share.sum())
    return share / total if total > 0 else np.full(len(area), 1.0 / max(len(area), 1))
