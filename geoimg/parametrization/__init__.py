"""Parametrizations: per-vertex coordinates of a mesh in a planar rectangle or on the unit sphere, and
the octahedral map that unfolds the sphere onto a square.

>>> from geoimg.parametrization import square_to_sphere
>>> square_to_sphere([[0.5, 0.5]]).tolist()
[[0.0, 0.0, 1.0]]
"""
import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
