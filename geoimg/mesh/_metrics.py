"""How far apart two surfaces are: exact point-to-mesh distances, Hausdorff distance and PSNR."""
from __future__ import annotations

import igl
import numpy as np

from ..errors import InputError, InputTypeError
from ._mesh import Mesh

__all__ = ["point_mesh_distance", "sample_surface", "surface_distance"]


def point_mesh_distance(points: np.ndarray, mesh: Mesh) -> np.ndarray:
    """Exact distance from each point (k, 3) to a mesh: the closest point on any of its triangles, found
    with libigl's AABB tree (quads split along their shorter diagonal, as geometry images are drawn;
    larger polygons fanned).

    Parameters
    ----------
    points : numpy.ndarray
        (k, 3) points.
    mesh : Mesh
        The mesh.

    Returns
    -------
    numpy.ndarray
        (k,) distances, in the mesh's units.

    Raises
    ------
    InputTypeError
        When ``mesh`` is not a Mesh.
    InputError
        When a point holds NaN or infinity.

    Examples
    --------
    >>> square = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> point_mesh_distance(np.array([[0.5, 0.5, 2.0], [-3.0, -4.0, 0.0]]), square).tolist()
    [2.0, 5.0]
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    tris, _ = mesh.triangulate(quads="shorter")
    pts = np.ascontiguousarray(np.asarray(points, np.float64).reshape(-1, 3))
    if not np.isfinite(pts).all():
        raise InputError("points: contain NaN or infinite values")
    if len(pts) == 0:
        return np.zeros(0)
    d2, _, _ = igl.point_mesh_squared_distance(pts, np.ascontiguousarray(mesh.vertices, np.float64),
                                               np.ascontiguousarray(tris, np.int64))
    return np.sqrt(np.maximum(d2, 0.0))


def sample_surface(mesh: Mesh, n: int, seed: int = 0) -> np.ndarray:
    """``n`` points spread uniformly over the mesh's area (quads split along their shorter diagonal),
    followed by its vertices.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    n : int
        How many area samples.
    seed : int
        The random generator's seed (the same seed, the same points).

    Returns
    -------
    numpy.ndarray
        (n + N, 3) points.

    Examples
    --------
    >>> import geoimg
    >>> square = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> sample_surface(square, 100).shape
    (104, 3)
    """
    tris, _ = mesh.triangulate(quads="shorter")
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
    """Two-sided distances between two surfaces, by exact closest points (:func:`point_mesh_distance`).

    Returns, in the meshes' units, ``hausdorff`` (the largest distance over the samples and both meshes'
    vertices), ``rms`` (over both directions' ``n`` samples pooled, spread by area: an estimate of the
    mean over the surfaces, whatever their vertex counts), each side's ``rms``, ``diagonal`` (the
    reference's bounding-box diagonal), and relative to it ``psnr_db = 20 log10(diagonal / rms)`` and
    ``hausdorff_rel = hausdorff / diagonal``. This is Praun and Hoppe's measure (``MeshDistance -bothdir 1``).

    Parameters
    ----------
    reference : Mesh
        The mesh measured against (its diagonal is the scale).
    other : Mesh
        The other mesh (a geometry image's quad mesh).
    n : int
        Area samples on each side.

    Returns
    -------
    dict
        ``hausdorff, rms, rms_ab, rms_ba, diagonal, psnr_db, hausdorff_rel`` (floats).

    Raises
    ------
    InputTypeError
        When either mesh is not a Mesh.

    Examples
    --------
    >>> a = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> b = Mesh(a.vertices + [0, 0, 0.01], a.faces)
    >>> d = surface_distance(a, b, n=1000)
    >>> round(d["rms"], 12), round(d["hausdorff_rel"], 6), round(d["psnr_db"], 3)
    (0.01, 0.007071, 43.01)
    """
    for name, value in (("reference", reference), ("other", other)):
        if not isinstance(value, Mesh):
            raise InputTypeError(f"{name}: expected a geoimg.Mesh, got {type(value).__name__}")
    diag = reference.bounding_box_diagonal()
    ab = point_mesh_distance(sample_surface(reference, n), other)
    ba = point_mesh_distance(sample_surface(other, n), reference)
    rms_ab, rms_ba = float(np.sqrt(np.mean(ab[:n] ** 2))), float(np.sqrt(np.mean(ba[:n] ** 2)))
    rms = float(np.sqrt(0.5 * (rms_ab ** 2 + rms_ba ** 2)))
    hausdorff = float(max(ab.max(), ba.max()))
    return {
        "diagonal": diag,
        "hausdorff": hausdorff,
        "rms": rms,
        "hausdorff_rel": hausdorff / diag if diag > 0 else 0.0,
        "rms_ref_to_other": rms_ab,
        "rms_other_to_ref": rms_ba,
        "psnr_db": float(20 * np.log10(diag / rms)) if rms > 0 else float("inf"),
    }
