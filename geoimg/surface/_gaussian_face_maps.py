"""Per-face quantities of the weighted-mean surface: parametric centre, size d_i and affine map P_i.

Each face's map is stored about its centre: ``P_i(u, v) = C_i + A_i (u - uc_i) + B_i (v - vc_i)``.

Sliver rule
-----------
The paper sets ``d_i`` to the radius of the smallest circle enclosing a triangle (mean vertex distance
for n > 3) and ``P_i`` to the plane through its vertices. A long thin face then has a huge Gaussian and
a steep plane, which bends the surface far from it. ``sliver_rule="robust"`` (the default) changes
only faces with ``d_i > 2 sqrt(area_i)`` (aspect beyond about 8:1; every well-shaped face, e.g.
equilateral 0.88, right isosceles 1.0, 30-30-120 1.32, is left as the paper has it): their ``d_i`` is
capped at ``2 sqrt(area_i)`` and their plane is the least-squares plane through the vertices of every
face sharing a vertex with it. Affine data stay exactly reproduced (linear precision holds).
``sliver_rule="paper"`` keeps the paper's definitions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from .._choices import SLIVER_RULES
from ..errors import InputError, ParametrizationError
from ..mesh import Mesh
from ..parametrization import signed_face_areas
from ._cells import enclosing_circle_radius

__all__ = [
    "FaceMaps",
    "SphereFaceMaps",
    "face_maps",
    "fit_planes",
    "robust_sliver_planes",
    "SLIVER_RULES",
    "SLIVER_RATIO",
]

SLIVER_RATIO = 2.0


@dataclass(frozen=True, eq=False)
class FaceMaps:
    """Per-face arrays (F faces that are kept)."""

    centres: np.ndarray   # (F, 2)
    d: np.ndarray         # (F,)
    C: np.ndarray         # (F, 3) value at the centre
    A: np.ndarray         # (F, 3) dP/du
    B: np.ndarray         # (F, 3) dP/dv
    face_index: np.ndarray  # (F,) index of the face in the mesh
    n_slivers: int        # faces the robust rule changed
    n_degenerate: int     # faces of zero parametric size, left out


@dataclass(frozen=True, eq=False)
class SphereFaceMaps(FaceMaps):
    """Per-face arrays of a mesh mapped onto the sphere: ``centres`` (F, 3) are unit directions, and each
    face's map is affine in the frame ``(e1, e2)`` of its chord plane through ``origin``.
    """

    origin: np.ndarray = None   # type: ignore[assignment]   # (F, 3) the chord polygon's centroid (required)
    e1: np.ndarray = None       # type: ignore[assignment]   # (F, 3) in-plane frame
    e2: np.ndarray = None       # type: ignore[assignment]


def fit_planes(uv: np.ndarray, xyz: np.ndarray, valid: np.ndarray, centres: np.ndarray):
    """Least-squares planes through point sets of shape (F, K, .), ``valid`` (F, K) marking real points.

    Exact when a set has three affinely independent points. Returns C, A, B of shape (F, 3).
    """
    w = valid.astype(np.float64)[..., None]
    du = (uv - centres[:, None, :]) * w
    m = np.concatenate([du, w], axis=2)                  # (F, K, 3): [u - uc, v - vc, 1]
    rhs = xyz * w
    mtm = np.einsum("fki,fkj->fij", m, m)
    mtb = np.einsum("fki,fkj->fij", m, rhs)
    coef = np.linalg.solve(mtm, mtb)                     # (F, 3, 3): rows A, B, C
    return coef[:, 2], coef[:, 0], coef[:, 1]


def _vertex_ring_points(mesh: Mesh, faces: np.ndarray):
    """For each face in ``faces``: the vertices of every face sharing a vertex with it (padded)."""
    f = mesh.faces
    rows = np.repeat(np.arange(len(f)), mesh.face_sizes)
    cols = f[f >= 0]
    fv = sparse.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(f), mesh.n_vertices))
    ring = (fv[faces] @ fv.T) @ fv  # faces -> neighbouring faces -> their vertices
    ring = ring.tocsr()
    counts = np.diff(ring.indptr)
    out = np.full((len(faces), counts.max()), -1, np.int64)
    for i in range(len(faces)):
        idx = ring.indices[ring.indptr[i]:ring.indptr[i + 1]]
        out[i, :len(idx)] = idx
    return out


def face_maps(mesh: Mesh, coords: np.ndarray, *, sliver_rule: str = "robust") -> FaceMaps:
    """Compute centres, sizes d_i and affine maps of the faces of a parametrized mesh.

    Faces of zero size in the parameter domain (all corners at one point, or on a line) have no
    affine map; they are left out and counted in ``n_degenerate``.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 2], [0, 1, 3]], [[0, 1, 2]])
    >>> fm = face_maps(m, np.array([[0., 0], [1, 0], [0, 1]]))
    >>> fm.A.round(12).tolist(), fm.B.round(12).tolist()
    ([[1.0, 0.0, 2.0]], [[0.0, 1.0, 3.0]])
    """
    if sliver_rule not in SLIVER_RULES:
        raise InputError(f"sliver_rule: expected one of {SLIVER_RULES}, got {sliver_rule!r}")
    f, k = mesh.faces, mesh.face_sizes
    valid = f >= 0
    idx = np.where(valid, f, f[:, :1])
    uv = coords[idx]                    # (F, K, 2)
    xyz = mesh.vertices[idx]            # (F, K, 3)
    centres = (uv * valid[..., None]).sum(axis=1) / k[:, None]
    area = np.abs(signed_face_areas(mesh, coords))
    d = np.empty(len(f))
    tri = k == 3
    if tri.any():
        d[tri] = enclosing_circle_radius(uv[tri, :3])
    if (~tri).any():
        dist = np.linalg.norm(uv[~tri] - centres[~tri, None, :], axis=2)
        d[~tri] = (dist * valid[~tri]).sum(axis=1) / k[~tri]
    scale = max(float(d.max()), 1e-300)
    keep = (d > 1e-12 * scale) & (area > 1e-14 * scale * scale)
    n_degenerate = int((~keep).sum())
    if not keep.any():
        raise ParametrizationError("every face has zero area in the parameter domain")
    face_index = np.flatnonzero(keep)
    uv, xyz, valid, centres, d, area = uv[keep], xyz[keep], valid[keep], centres[keep], d[keep], area[keep]
    C, A, B = fit_planes(uv, xyz, valid, centres)
    n_slivers = 0
    if sliver_rule == "robust":
        d, n_slivers = robust_sliver_planes(mesh, face_index, d, area, C, A, B,
                                            lambda ridx, sliver: (coords[ridx], True, centres[sliver]))
    return FaceMaps(centres, d, C, A, B, face_index, n_slivers, n_degenerate)


def robust_sliver_planes(mesh: Mesh, face_index, d, area, C, A, B, ring_coords):
    """The robust sliver rule: cap ``d_i`` at ``SLIVER_RATIO sqrt(area_i)`` and refit the plane of every
    capped face through the vertices of its 1-ring. ``C, A, B`` are updated in place.

    ``ring_coords(ridx, sliver)`` gives the parameter coordinates of the ring vertices ``ridx`` (S, K)
    in each sliver's own frame, a mask of those that can be used (or True), and the slivers' centres.
    Returns the new ``d`` and the number of slivers.
    """
    cap = SLIVER_RATIO * np.sqrt(area)
    sliver = d > cap
    n_slivers = int(sliver.sum())
    if n_slivers:
        d = np.where(sliver, cap, d)
        ring = _vertex_ring_points(mesh, face_index[sliver])
        rv = ring >= 0
        ridx = np.where(rv, ring, ring[:, :1])
        pts, usable, centres = ring_coords(ridx, sliver)
        C[sliver], A[sliver], B[sliver] = fit_planes(pts, mesh.vertices[ridx], rv & usable, centres)
    return d, n_slivers
