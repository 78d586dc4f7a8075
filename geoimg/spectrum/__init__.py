"""The sphere's own spectrum: spherical harmonics of closed genus-0 shapes and octahedral images."""
from ._harmonics import Harmonics, default_resolution, harmonics, load_harmonics
from ._transform import MAX_LMAX, analyze, degree_power, grid_directions, grid_shape, synthesize

__all__ = ["Harmonics", "harmonics", "load_harmonics", "default_resolution", "analyze", "synthesize",
           "grid_directions", "grid_shape", "degree_power", "MAX_LMAX"]
