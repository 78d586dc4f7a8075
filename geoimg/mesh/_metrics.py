"""How far apart two surfaces are: point-to-triangle distances, Hausdorff distance and PSNR."""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputTypeError
from ._distance_kernels import nearest_triangle_distances
from ._mesh import Mesh

__all__ = ["point_mesh_distance", "sample_surface", "surface_distance"]


def point_mesh_distance(points: np.ndarray, mesh: Mesh, k: int = 16, chunk: int = 20000) -> np.ndarray:
    """Distance from each point to a mesh: exact point-triangle distances (numba) over the ``k`` triangles whose
    centroids are nearest (enough on any mesh whose triangles are not far larger than their neighbours)."""
    tris, _ = mesh.triangulate()
    v = np.ascontiguousarray(mesh.vertices, np.float64)
    tris = np.ascontiguousarray(tris, np.int64)
    points = np.ascontiguousarray(points, np.float64).reshape(-1, 3)
    tree = cKDTree(v[tris].mean(axis=1))
    k = min(k, len(tris))
    out = np.empty(len(points))
    for lo in range(0, len(points), chunk):
        p = points[lo:lo + chunk]
        _, idx = tree.query(p, k=k, workers=-1)
        out[lo:lo + chunk] = nearest_triangle_distances(p, v, tris, np.ascontiguousarray(idx.reshape(len(p), k),
                                                                                       np.int64))
    return out


def sample_surface(mesh: Mesh, n: int, seed: int = 0) -> np.ndarray:
    """``n`` points spread uniformly over the mesh's area, followed by its vertices."""
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

    Returns ``hausdorff`` (over the samples and both meshes' vertices), ``rms`` (over both directions'
    ``n`` samples, spread by area: an estimate of the mean over the surfaces, whatever their vertex
    counts), each side's ``rms``, and ``psnr_db = 20 log10(diagonal / rms)``.
    """
    for name, value in (("reference", reference), ("other", other)):
        if not isinstance(value, Mesh):
            raise InputTypeError(f"{name}: expected a geoimg.Mesh, got {type(value).__name__}")
    diag = reference.bounding_box_diagonal()
    ab = point_mesh_distance(sample_surface(reference, n), other)
    ba = point_mesh_distance(sample_surface(other, n), reference)
    rms_ab, rms_ba = float(np.sqrt(np.mean(ab[:n] ** 2))), float(np.sqrt(np.mean(ba[:n] ** 2)))
    rms = float(np.sqrt(0.5 * (rms_ab ** 2 + rms_ba ** 2)))
    return {"diagonal": diag, "hausdorff": float(max(ab.max(), ba.max())), "rms": rms,
            "rms_ref_to_other": rms_ab, "rms_other_to_ref": rms_ba,
            "psnr_db": float(20 * np.log10(diag / rms)) if rms > 0 else float("inf")}
