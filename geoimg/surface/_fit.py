"""Fitting the weighted-mean surface of a parametrized mesh, over whatever domain the parametrization has."""
from __future__ import annotations

import numpy as np

from .._choices import WEIGHTS
from ..errors import InputError, InputTypeError
from ..image import Domain
from ..mesh import Mesh
from ..parametrization import Parametrization
from ._base import Surface
from ._coverage import check_s, fit_coverage_surface
from ._face_maps import SLIVER_RULES
from ._planar import fit_planar_surface
from ._smoothness import SmoothnessMap
from ._sphere import fit_sphere_surface
from .._threads import fixed_order

__all__ = ["fit_surface", "WEIGHTS", "check_s_range"]

_FITTERS = {2: fit_planar_surface, 3: fit_sphere_surface}     # by the dimension of the parameter coordinates


S_RANGE = (1e-3, 1e3)     # sigma = s d: beyond these the Gaussians are a face's own plane, or the mean of all


def check_s_range(values: np.ndarray) -> None:
    lo, hi = float(np.min(values)), float(np.max(values))
    if lo < S_RANGE[0] or hi > S_RANGE[1]:
        raise InputError(f"s: expected values from {S_RANGE[0]:g} to {S_RANGE[1]:g} (sigma = s d_i; outside that "
                         f"range the weights under- or overflow), got {lo:g}" + (f" to {hi:g}" if hi != lo else ""))


def _smoothness(s, n_faces: int) -> tuple[float, np.ndarray | None, object]:
    """``(s, None, None)`` for a number; ``(min s, per-face s, None)`` for an array; ``(min s, None, map)``
    for a :class:`~geoimg.surface.SmoothnessMap` (truncation and its certificate use the minimum, which
    is conservative).
    """
    if isinstance(s, SmoothnessMap):
        check_s_range(np.array([s.min, s.max]))
        return float(s.min), None, s
    if isinstance(s, (int, float, np.number)) and not isinstance(s, bool):
        if not (np.isfinite(s) and s > 0):
            raise InputError(f"s: expected a positive finite number, got {s!r}")
        check_s_range(np.array([s], np.float64))
        return float(s), None, None
    arr = np.asarray(s) if not isinstance(s, (str, bytes, bool)) else np.asarray([])
    if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or arr.shape != (n_faces,):
        raise InputError(f"s: expected a positive number or {n_faces} per-face values, got {s!r:.80}")
    arr = arr.astype(np.float64)
    if not (np.isfinite(arr).all() and (arr > 0).all()):
        raise InputError("s: per-face values must be positive and finite")
    check_s_range(arr)
    return float(arr.min()), arr, None


def _parametrized_mesh(mesh: Mesh, param: Parametrization) -> Mesh:
    """The mesh whose vertices ``param`` gives coordinates to: the input, or the one the parametrization
    made of it (cut open), its positions taken from the input (so a mesh with the same faces, another
    pose of the same shape, can share the parametrization).
    """
    if param.mesh is None:
        if param.coords.shape[0] != mesh.n_vertices:
            raise InputError(f"param: has {param.coords.shape[0]} points but the mesh has {mesh.n_vertices} vertices")
        return mesh
    src, w, made = param.source, param.source_weight, param.mesh
    if src is None or w is None or src.shape != (made.n_vertices, 2) or w.shape != (made.n_vertices,) or \
            src.min() < 0 or src.max() >= mesh.n_vertices:
        raise InputError(f"param: its cut-open mesh refers to vertices the mesh ({mesh.n_vertices} vertices) does "
                         "not have: it was made for another mesh")
    def blend(a):
        return None if a is None else (1 - w)[:, None] * a[src[:, 0]] + w[:, None] * a[src[:, 1]]

    return Mesh(blend(mesh.vertices), made.faces, colors=blend(mesh.colors))


@fixed_order
def fit_surface(mesh: Mesh, param: Parametrization, s: float = 1.0, *, weights: str = "gaussian", n: int = 10,
                tol: float = 1e-10, sliver_rule: str = "robust") -> Surface:
    """Fit the weighted-mean surface of a parametrized mesh.

    Parameters
    ----------
    mesh : Mesh
    param : Parametrization
        Per-vertex (u, v) of the mesh (see :func:`geoimg.parametrize`).
    s : float, array_like of shape (mesh.n_faces,), or SmoothnessMap; default 1.0
        Smoothness: sigma_i = s d_i (Gaussian weights). Per-face values
        (:func:`geoimg.surface.smoothness_field`) or a map s(u, v) that varies with the point evaluated
        (:func:`geoimg.surface.uv_smoothness`, planar only) give a surface smoothed more in some places
        than in others, its normals still exact (paper 4.5). Per-face values cannot keep a region sharp
        inside a smoothed surrounding (the wide Gaussians around reach in); a map can.
    weights : {"gaussian", "local", "coverage"}
        The paper's rational Gaussians of the distance to each face's centre (infinitely smooth), its
        locally supported ``1 - 3R^2 + 2R^3`` (C1, faster, may leave holes, which are reported and masked),
        or each triangle's share of a Gaussian footprint of width ``sigma = s * dbar`` (infinitely smooth,
        tends to the mesh itself as ``s -> 0``; one number ``s``; see :mod:`geoimg.surface._coverage`).
    n : int, default 10
        Face centres inside each local weight's support (``weights="local"``).
    tol : float, default 1e-10
        Truncation: skipped weights are below ``tol``; 0 for the exact, untruncated sum.
    sliver_rule : {"robust", "paper"}
        How long thin faces are treated (see :mod:`geoimg.surface._face_maps`).

    Returns
    -------
    Surface
        Over the parametrization's domain: a :class:`~geoimg.surface.PlanarSurface` for a planar one, a
        :class:`~geoimg.surface.SphereSurface` for a spherical (octahedral) one.

    Raises
    ------
    ValueError
        On a bad ``s``, ``weights``, ``n``, ``tol`` or ``sliver_rule``, or a parametrization that does not
        match the mesh.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> surf = geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2], (1, 1)), s=2.0)
    >>> surf.evaluate([[0.5, 0.5]]).shape
    (1, 3)
    """
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    if not isinstance(param, Parametrization):
        raise InputTypeError(f"param: expected a geoimg.Parametrization, got {type(param).__name__}")
    mesh = _parametrized_mesh(mesh, param)
    if weights not in WEIGHTS:
        raise InputError(f"weights: expected one of {WEIGHTS}, got {weights!r}")
    if not (isinstance(tol, (int, float, np.number)) and 0 <= tol < 1):
        raise InputError(f"tol: expected a number in [0, 1), got {tol!r}")
    domain = Domain.from_metadata(param.domain, {"extent": param.extent, **param.domain_fields,
                                                 "orientation": int(param.info.get("orientation", 1))})
    if domain.coverage_only and weights != "coverage":
        raise InputError(f"weights={weights!r}: a {domain.kind} image is sampled with weights='coverage' only (the "
                         "paper's weights reach from one chart across the gutter into the next)")
    if weights == "coverage":
        return fit_coverage_surface(mesh, param.coords, domain, check_s(s), tol=float(tol))
    s, s_face, s_map = _smoothness(s, mesh.n_faces)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise InputError(f"n: expected an integer >= 2, got {n!r}")
    if sliver_rule not in SLIVER_RULES:
        raise InputError(f"sliver_rule: expected one of {SLIVER_RULES}, got {sliver_rule!r}")
    fit = _FITTERS[domain.parameter_dim]
    return fit(mesh, param.coords, domain, s, s_face, s_map, weights=weights, n=int(n), tol=float(tol),
               sliver_rule=sliver_rule)
