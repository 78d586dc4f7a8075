"""Meshes: the :class:`Mesh` type, mesh files, topology, terrains and distances between meshes.

>>> from geoimg.mesh import Mesh, topology
>>> topology(Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])).boundary_loops
1
"""
import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
