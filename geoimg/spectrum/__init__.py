"""The sphere's own spectrum: spherical harmonics of closed genus-0 shapes and octahedral images, and the
isotropic filters they give.
"""
from ._collection import ShapeSpace, coefficient_columns, coefficient_row, harmonics_from_row, shape_space
from ._filters import band_emphasis, band_limit, heat_smooth, spectral_filter
from ._harmonics import Harmonics, default_resolution, harmonics, load_harmonics
from ._transform import MAX_LMAX, analyze, degree_power, grid_directions, grid_shape, synthesize, synthesize_rows

__all__ = ["Harmonics", "harmonics", "load_harmonics", "default_resolution", "spectral_filter", "band_limit",
           "heat_smooth", "band_emphasis", "analyze", "synthesize", "synthesize_rows", "grid_directions",
           "grid_shape", "degree_power", "MAX_LMAX", "coefficient_columns", "coefficient_row", "harmonics_from_row",
           "ShapeSpace", "shape_space"]
