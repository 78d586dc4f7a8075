"""How far apart two surfaces are: point-to-triangle distances, Hausdorff distance and PSNR."""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ._mesh import Mesh

__all__ = ["point_triangle_distance", "point_mesh_distance", "sample_surface", "surface_distance"]


def point_triangle_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to triangles ``(a, b, c)`` (all (..., 3), broadcast; Ericson's regions).

    Examples
    --------
    >>> t = np.eye(3)
    >>> float(point_triangle_distance(np.zeros(3), t[0], t[1], t[2]).round(6))
    0.57735
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
    return np.linalg.norm(p - q, axis=-1)


def point_mesh_distance(points: np.ndarray, mesh: Mesh, k: int = 16, chunk: int = 20000) -> np.ndarray:
    """Distance from each point to a mesh: exact point-triangle distances over the ``k`` triangles whose
    centroids are nearest (enough on any mesh whose triangles are not far larger than their neighbours)."""
    tris, _ = mesh.triangulate()
    v = mesh.vertices
    tree = cKDTree(v[tris].mean(axis=1))
    k = min(k, len(tris))
    out = np.empty(len(points))
    for lo in range(0, len(points), chunk):
        p = points[lo:lo + chunk]
        _, idx = tree.query(p, k=k)
        idx = idx.reshape(len(p), k)
        t = tris[idx]
        out[lo:lo + chunk] = point_triangle_distance(p[:, None], v[t[..., 0]], v[t[..., 1]], v[t[..., 2]]).min(axis=1)
    return out


def sample_surface(mesh: Mesh, n: int, seed: int = 0) -> np.ndarray:
    """``n`` points spread uniformly over the mesh's area (plus its vertices)."""
    tris, _ = mesh.triangulate()
    p = mesh.vertices[tris]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    rng = np.random.default_rng(seed)
    t = rng.choice(len(tris), size=n, p=area / area.sum())
    r1, r2 = rng.random(n), rng.random(n)
    flip = r1 + r2 > 1
    r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
    pts = p[t, 0] + r1[:, None] * (p[t, 1] - p[t, 0]) + r2[:, None] * (p[t, 2] - p[t, 0])
    return np.vstack([pts, mesh.vertices[mesh.referenced_vertices()]])


def surface_distance(reference: Mesh, other: Mesh, n: int = 200000) -> dict:
    """Two-sided distances between two surfaces, relative to the reference's bounding-box diagonal.

    Returns ``hausdorff``, ``rms`` (over both directions' samples), each side's ``rms`` and ``max``, and
    ``psnr_db = 20 log10(diagonal / rms)``.
    """
    diag = reference.bounding_box_diagonal()
    ab = point_mesh_distance(sample_surface(reference, n), other)
    ba = point_mesh_distance(sample_surface(other, n), reference)
    rms = float(np.sqrt(np.mean(np.concatenate([ab, ba]) ** 2)))
    return {"diagonal": diag, "hausdorff": float(max(ab.max(), ba.max())), "rms": rms,
            "rms_ref_to_other": float(np.sqrt(np.mean(ab ** 2))), "rms_other_to_ref": float(np.sqrt(np.mean(ba ** 2))),
            "psnr_db": float(20 * np.log10(diag / rms)) if rms > 0 else float("inf")}
