"""Fitting the weighted-mean surface of a parametrized mesh, over whatever domain the parametrization has."""
from __future__ import annotations

from typing import Any

import numpy as np

from .._choices import WEIGHTS
from ..errors import InputError, InputTypeError
from ..image import Domain
from ..mesh import Mesh
from ..parametrization import Parametrization
from ._base import Surface
from ._coverage import fit_coverage_surface
from ._gaussian_planar import fit_planar_surface
from ._gaussian_smoothness import SmoothnessMap
from ._gaussian_sphere import fit_sphere_surface
from ._weights import S_RANGE, UNSET, CoverageWeights, GaussianWeights, check_s_range, resolve_weights
from .._threads import fixed_order

__all__ = ["fit_surface", "WEIGHTS", "S_RANGE", "check_s_range"]

_FITTERS = {2: fit_planar_surface, 3: fit_sphere_surface}     # by the dimension of the parameter coordinates


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
def fit_surface(mesh: Mesh, param: Parametrization, weights: CoverageWeights | GaussianWeights | None = None, *,
                s: Any = UNSET, n: Any = UNSET, tol: Any = UNSET, sliver_rule: Any = UNSET) -> Surface:
    """Fit the weighted-mean surface of a parametrized mesh.

    Parameters
    ----------
    mesh : Mesh
    param : Parametrization
        Per-vertex (u, v) of the mesh (see :func:`geoimg.parametrize`).
    weights : CoverageWeights or GaussianWeights, optional
        The weights and their settings (see :mod:`geoimg.surface._weights`). Default
        ``CoverageWeights()``: each triangle's share of a Gaussian footprint, the mesh itself as ``s -> 0``,
        sampled at the width that serves the image's resolution. ``GaussianWeights(s=...)``: the paper's
        rational Gaussians (``sigma_i = s d_i``), or with ``n`` its locally supported weights; per-face
        ``s`` or a map s(u, v) smooth some places more than others, the normals still exact (paper 4.5).
    s, n, tol, sliver_rule
        Deprecated (the flat keywords of earlier releases, where ``weights`` was a name and defaulted to
        ``"gaussian"``): they still build the weights they did, with a :class:`DeprecationWarning`.

    Returns
    -------
    Surface
        Over the parametrization's domain: a :class:`~geoimg.surface.PlanarSurface` or
        :class:`~geoimg.surface.SphereSurface` (the paper's weights), a
        :class:`~geoimg.surface.PlanarCoverageSurface` or :class:`~geoimg.surface.SphereCoverageSurface`
        (coverage weights).

    Raises
    ------
    InputError
        On bad weights, per-face ``s`` that do not match the faces, the paper's weights on a charts image,
        or a parametrization that does not match the mesh.

    Examples
    --------
    >>> import geoimg
    >>> from geoimg.surface import GaussianWeights
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> param = geoimg.Parametrization(m.vertices[:, :2], (1, 1))
    >>> geoimg.fit_surface(m, param).evaluate([[0.5, 0.5]]).shape
    (1, 3)
    >>> type(geoimg.fit_surface(m, param, GaussianWeights(s=2.0))).__name__
    'PlanarSurface'
    """
    weights = resolve_weights(weights, s=s, n=n, tol=tol, sliver_rule=sliver_rule, old_default="gaussian",
                              old_s=1.0, caller="fit_surface", stacklevel=4)
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"mesh: expected a geoimg.Mesh, got {type(mesh).__name__}")
    if not isinstance(param, Parametrization):
        raise InputTypeError(f"param: expected a geoimg.Parametrization, got {type(param).__name__}")
    mesh = _parametrized_mesh(mesh, param)
    domain = Domain.from_metadata(param.domain, {"extent": param.extent, **param.domain_fields,
                                                 "orientation": int(param.info.get("orientation", 1))})
    if isinstance(weights, CoverageWeights):
        return fit_coverage_surface(mesh, param.coords, domain, 1.0 if weights.s is None else weights.s,
                                    tol=weights.tol, serve=weights.s is None)
    if domain.coverage_only:
        raise InputError(f"weights={weights!r}: a {domain.kind} image is sampled with coverage weights only (the "
                         "paper's weights reach from one chart across the gutter into the next)")
    s_min, s_face, s_map = _smoothness(weights.s, mesh.n_faces)
    fit = _FITTERS[domain.parameter_dim]
    return fit(mesh, param.coords, domain, s_min, s_face, s_map, weights=weights.kind,
               n=10 if weights.n is None else weights.n, tol=weights.tol, sliver_rule=weights.sliver_rule)
