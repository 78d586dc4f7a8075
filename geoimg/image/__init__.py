"""Geometry images: the :class:`GeometryImage` type, its domains, files, regions and curvature.

>>> import numpy as np
>>> from geoimg.image import GeometryImage, OctahedralDomain
>>> img = GeometryImage(np.zeros((5, 5, 3), np.float32), domain=OctahedralDomain())
>>> img.to_mesh().n_vertices          # glued pixels welded: (5 - 1)^2 + 2
18
"""
from ._domain import DOMAIN_KINDS, Domain, grid_normals
from ._planar_domain import PlanarDomain
from ._octahedral_domain import OctahedralDomain
from ._cut_domain import CutDomain
from ._charts_domain import ChartsDomain
from ._perimeter import perimeter_pixels
from ._image import DEFAULT_PAD, EXR_LAYOUTS, GeometryImage
from ._io import (
    ASSUMABLE_DOMAINS,
    IMAGE_FORMATS,
    diverging_colors,
    load_image,
    save_colormap,
    save_image,
    save_normal_map,
    save_preview,
    save_scalar,
)
from .._ball import ball_weights
from ._regions import image_region, load_mask, uv_region
from ._curvature import image_curvature

__all__ = [
    "IMAGE_FORMATS",
    "EXR_LAYOUTS",
    "ASSUMABLE_DOMAINS",
    "DOMAIN_KINDS",
    "CutDomain",
    "ChartsDomain",
    "perimeter_pixels",
    "Domain",
    "OctahedralDomain",
    "PlanarDomain",
    "grid_normals",
    "DEFAULT_PAD",
    "GeometryImage",
    "diverging_colors",
    "load_image",
    "save_colormap",
    "save_image",
    "save_normal_map",
    "save_preview",
    "save_scalar",
    "ball_weights",
    "image_region",
    "load_mask",
    "uv_region",
    "image_curvature",
]
