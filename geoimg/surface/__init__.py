"""The weighted-mean surface of a parametrized mesh: fitting, evaluation, exact normals and curvature,
sampling into geometry images, and smoothness that varies over the surface.

>>> import geoimg
>>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
>>> surf = geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2], (1, 1)), GaussianWeights(s=2.0))
>>> isinstance(surf, Surface), surf.sample(5).shape
(True, (5, 5))
"""
from ._base import Surface
from ._gaussian_planar import PlanarSurface
from ._gaussian_sphere import SphereSurface
from ._fit import S_RANGE, WEIGHTS, fit_surface
from ._weights import CoverageWeights, GaussianWeights, make_weights
from ._coverage import PREFILTER, CoverageSurface, PlanarCoverageSurface, SphereCoverageSurface, prefilter_s
from ._gaussian_face_maps import SLIVER_RULES
from ._curvature import shape_operator_curvatures, surface_curvature
from ._gaussian_smoothness import SmoothnessMap, smoothness_field, uv_smoothness

__all__ = ["CoverageWeights", "GaussianWeights", "make_weights",
           "Surface", "PlanarSurface", "SphereSurface", "WEIGHTS", "S_RANGE", "fit_surface", "SLIVER_RULES",
           "shape_operator_curvatures", "surface_curvature", "SmoothnessMap", "smoothness_field", "uv_smoothness",
           "CoverageSurface", "PlanarCoverageSurface", "SphereCoverageSurface", "PREFILTER", "prefilter_s"]
