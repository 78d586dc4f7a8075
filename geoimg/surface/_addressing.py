"""How a surface is addressed by image coordinates, once for every surface over each kind of domain: over a
plane from a ``_points(uv, exact)`` that gives ``P, P_u, P_v, status``; over the sphere from an
``evaluate_directions(q)`` that gives ``P`` and its derivatives along a tangent frame, through the octahedral
map. :class:`PlanarSurface` and the coverage-weighted surfaces share them, and the copies of faces beyond a
glued side that both fits over a plane make.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..mesh import Mesh
from ..parametrization import square_jacobian, square_to_sphere
from ._base import unit

__all__ = ["PlanarAddressing", "SphereAddressing", "with_ghosts", "MAX_PLANAR_RESOLUTION", "MAX_SPHERE_RESOLUTION"]

MAX_PLANAR_RESOLUTION = 4096      # the largest automatic resolution over a plane
MAX_SPHERE_RESOLUTION = 2049      # and over the sphere


class PlanarAddressing:
    """``evaluate``, ``derivatives`` and ``normals`` of a surface over a parameter rectangle."""

    orientation: int

    def _points(self, uv, exact):    # pragma: no cover - each surface has its own
        raise NotImplementedError

    def _uv(self, uv) -> np.ndarray:
        pts = np.asarray(uv, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise InputError(f"uv: expected parameter points of shape (k, 2), got {pts.shape}")
        if not np.isfinite(pts).all():
            raise InputError("uv: contains NaN or infinite values")
        return pts

    def evaluate(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Surface points at parameter points.

        Parameters
        ----------
        uv : array_like, shape (k, 2)
        exact : bool, default False
            Sum over every face instead of the truncated neighbourhood.

        Returns
        -------
        numpy.ndarray, shape (k, 3) float64

        Examples
        --------
        >>> import geoimg
        >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 1], [1, 1, 2], [0, 1, 1]], [[0, 1, 2], [0, 2, 3]])
        >>> p = geoimg.Parametrization(m.vertices[:, :2], (1, 1))
        >>> geoimg.fit_surface(m, p, geoimg.GaussianWeights()).evaluate([[0.5, 0.25]]).round(12).tolist()
        [[0.5, 0.25, 0.75]]
        """
        return self._points(uv, exact)[0]

    def derivatives(self, uv: ArrayLike, *, exact: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Analytic first derivatives ``(P_u, P_v)``, each of shape (k, 3)."""
        _, pu, pv, _ = self._points(uv, exact)
        return pu, pv

    def normals(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Unit normals ``orientation * (P_u x P_v) / |P_u x P_v|`` from the analytic derivatives, shape (k, 3)."""
        pu, pv = self.derivatives(uv, exact=exact)
        return unit(np.cross(pu, pv) * self.orientation)


class SphereAddressing:
    """``evaluate``, ``derivatives`` and ``normals`` at octahedral image coordinates of a surface over the
    sphere.
    """

    orientation: int

    def evaluate_directions(self, q: ArrayLike, *, exact: bool = False,
                            derivatives: bool = True) -> tuple:    # pragma: no cover - each surface has its own
        raise NotImplementedError

    def _uv(self, uv) -> np.ndarray:
        pts = np.asarray(uv, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise InputError(f"uv: expected parameter points of shape (k, 2), got {pts.shape}")
        if not np.isfinite(pts).all() or pts.min() < 0 or pts.max() > 1:
            raise InputError("uv: octahedral image coordinates must lie in [0, 1]")
        return pts

    def _glue(self, P: np.ndarray, nrm: np.ndarray | None):
        """Nothing to average: glued boundary pixels are evaluated at bit-identical directions, with the
        same faces summed in the same order, so they already hold identical values (tested).
        """
        return P, nrm, 0.0

    def evaluate(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Surface points at octahedral image coordinates ``uv`` (k, 2); shape (k, 3)."""
        return self.evaluate_directions(square_to_sphere(self._uv(uv)), exact=exact, derivatives=False)[0]

    def derivatives(self, uv: ArrayLike, *, exact: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """``(P_u, P_v)`` at image coordinates (one-sided on the octahedron's creases)."""
        pts = self._uv(uv)
        _, P1, P2, t1, t2, _ = self.evaluate_directions(square_to_sphere(pts), exact=exact)
        du, dv = square_jacobian(pts)
        pu = P1 * (du * t1).sum(1, keepdims=True) + P2 * (du * t2).sum(1, keepdims=True)
        pv = P1 * (dv * t1).sum(1, keepdims=True) + P2 * (dv * t2).sum(1, keepdims=True)
        return pu, pv

    def normals(self, uv: ArrayLike, *, exact: bool = False) -> np.ndarray:
        """Unit normals from the analytic derivatives (smooth across the creases), shape (k, 3)."""
        _, P1, P2, _, _, _ = self.evaluate_directions(square_to_sphere(self._uv(uv)), exact=exact)
        return unit(np.cross(P1, P2) * self.orientation)


def with_ghosts(mesh: Mesh, coords: np.ndarray, face_index: np.ndarray, ghosts: list):
    """The mesh with copies of faces (vertices copied too) at moved parameters appended; returns the mesh,
    its coordinates and, per face, the face of the input it copies.
    """
    verts, uvs, faces, source = [mesh.vertices], [coords], [mesh.faces], [np.arange(mesh.n_faces)]
    base = mesh.n_vertices
    for kept, R, b in ghosts:
        f = mesh.faces[face_index[kept]]
        used, inv = np.unique(f[f >= 0], return_inverse=True)
        local = np.full(f.shape, -1, np.int64)
        local[f >= 0] = inv + base
        verts.append(mesh.vertices[used])
        uvs.append(coords[used] @ R.T + b)
        faces.append(local)
        source.append(face_index[kept])
        base += len(used)
    return (Mesh(np.vstack(verts), np.vstack(faces)), np.vstack(uvs), np.concatenate(source))
