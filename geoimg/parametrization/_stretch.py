"""How much a map stretches the surface: the L2 geometric stretch of Sander, Snyder, Gortler & Hoppe (2001),
which Praun & Hoppe (2003) and Sander et al. (2003) report for geometry images, and the share of the surface
that the map starves of parameter area (parts an image then draws with too few pixels).
"""
from __future__ import annotations

import numpy as np

from ..errors import InputTypeError
from ..mesh import Mesh
from ._laplacian import STARVED_SHARE
from ._parametrize import Parametrization

__all__ = ["map_stretch", "STARVED_SHARE"]



def _frame_coords(p: np.ndarray) -> np.ndarray:
    """(T, 3, 2) coordinates of each triangle's corners in a frame of its own plane (for corners in 3-D)."""
    e1 = p[:, 1] - p[:, 0]
    n = np.cross(e1, p[:, 2] - p[:, 0])
    e1 = e1 / np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-300)
    e2 = np.cross(n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300), e1)
    d = p - p[:, :1]
    return np.stack([np.einsum("tkc,tc->tk", d, e1), np.einsum("tkc,tc->tk", d, e2)], axis=-1)


def map_stretch(mesh: Mesh, param: Parametrization) -> dict:
    """The L2 stretch of a map from the surface to its parameter domain, normalized so that 1 is a map
    that keeps every triangle's shape and share of the area (an isometry up to one scale).

    Each triangle's stretch is ``sqrt((G^2 + g^2) / 2)``, ``G`` and ``g`` the singular values of the map
    from parameters to the surface; the map's is their root mean square over the surface's area (Sander et al.
    2001: a triangle squeezed to no parameter area has infinite stretch), times
    ``sqrt(parameter area / surface area)``. Planar, disk and cut-open maps are measured in their (u, v);
    sphere maps on the sphere (each triangle through its chord), before the octahedral image's own,
    fixed, distortion. Polygons are split into triangles (quads along their shorter diagonal).

    Parameters
    ----------
    mesh : Mesh
        The mesh the map was made of.
    param : Parametrization
        Its map (a cut-open map's ``param.mesh`` is the mesh cut open).

    Returns
    -------
    dict
        ``l2`` (at least 1), ``efficiency`` (``1 / l2``), ``worst`` (the largest triangle's stretch, on the
        same scale), ``starved`` (the share of the surface's area whose triangles get less than
        :data:`STARVED_SHARE` of their fair share of the parameter area, or none), and ``degenerate`` (triangles of
        no parameter area, left out of the others).

    Raises
    ------
    InputTypeError
        When ``mesh`` is not a Mesh or ``param`` not a Parametrization.

    Examples
    --------
    >>> from geoimg import Mesh, Parametrization
    >>> square = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> round(map_stretch(square, Parametrization(square.vertices[:, :2] * 3, (1, 1)))["l2"], 12)   # a scale
    1.0
    >>> map_stretch(square, Parametrization(square.vertices[:, :2] * [2, 0.5], (1, 1)))["l2"] > 1   # a shear
    True
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    if not isinstance(param, Parametrization):
        raise InputTypeError(f"param: expected a geoimg.Parametrization, got {type(param).__name__}")
    m = param.mesh if param.mesh is not None else mesh
    tris, _ = m.triangulate(quads="shorter")
    q = m.vertices[tris]                                          # (T, 3, 3) on the surface
    p = np.asarray(param.coords, np.float64)[tris]                # (T, 3, 2) or (T, 3, 3)
    st = p if p.shape[-1] == 2 else _frame_coords(p)
    s, t = st[..., 0], st[..., 1]
    area_p = 0.5 * ((s[:, 1] - s[:, 0]) * (t[:, 2] - t[:, 0]) - (s[:, 2] - s[:, 0]) * (t[:, 1] - t[:, 0]))
    area_q = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    scale = max(float(np.abs(area_p).max(initial=0.0)), 1e-300)
    ok = np.abs(area_p) > 1e-14 * scale
    two = 2.0 * area_p[ok, None]
    qs, ss, ts = q[ok], s[ok], t[ok]
    d_s = (qs[:, 0] * (ts[:, 1] - ts[:, 2])[:, None] + qs[:, 1] * (ts[:, 2] - ts[:, 0])[:, None]
           + qs[:, 2] * (ts[:, 0] - ts[:, 1])[:, None]) / two
    d_t = (qs[:, 0] * (ss[:, 2] - ss[:, 1])[:, None] + qs[:, 1] * (ss[:, 0] - ss[:, 2])[:, None]
           + qs[:, 2] * (ss[:, 1] - ss[:, 0])[:, None]) / two
    stretch2 = 0.5 * (np.einsum("tc,tc->t", d_s, d_s) + np.einsum("tc,tc->t", d_t, d_t))
    a_p, a_q = np.abs(area_p[ok]), area_q[ok]
    norm = np.sqrt(a_p.sum() / max(a_q.sum(), 1e-300))
    l2 = float(np.sqrt((stretch2 * a_q).sum() / max(a_q.sum(), 1e-300)) * norm)
    share = (a_p / a_p.sum()) / np.maximum(a_q / max(a_q.sum(), 1e-300), 1e-300)
    starved = float((a_q[share < STARVED_SHARE].sum() + area_q[~ok].sum()) / max(area_q.sum(), 1e-300))
    return {"l2": l2, "efficiency": 1.0 / l2 if l2 > 0 else 0.0, "worst": float(np.sqrt(stretch2.max()) * norm),
            "starved": starved, "degenerate": int((~ok).sum())}
