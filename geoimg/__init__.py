"""geoimg: polygon meshes to geometry images and back, through Goshtasby's weighted-mean surface.

The pipeline, one subpackage per stage: :mod:`geoimg.mesh` (the Mesh type, files, topology) ->
:mod:`geoimg.parametrization` (planar, disk, sphere) -> :mod:`geoimg.surface` (the weighted-mean
surface) -> :mod:`geoimg.image` (geometry images, their domains, files, regions) ->
:mod:`geoimg.animation` (morphs, glTF, pictures). Image operations live in the separate package
:mod:`filters`.

>>> import geoimg
>>> mesh = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
>>> image = geoimg.mesh_to_image(mesh, 8, s=2.0, method="heightfield", axis="z")
>>> image.domain.kind, image.to_mesh().n_faces
('planar', 49)
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from filters._lazy import lazy_names

from .errors import (GeoimgError, ImageError, ImageFileError, InputError, InputTypeError, MeshError, MeshFileError,
                     MissingDependency, ParametrizationError, RenderError, ResourceError)

if TYPE_CHECKING:
    from .mesh import Mesh, grid_mesh, load_mesh, save_mesh
    from .parametrization import Parametrization, parametrize
    from .image import (CutDomain, Domain, GeometryImage, OctahedralDomain, PlanarDomain, grid_normals, load_image, save_image,
                        save_preview)
    from .surface import Surface, fit_surface
    from ._convert import mesh_to_image, mesh_to_images

__version__ = "0.1.0"

__all__ = [
    "GeoimgError", "ImageError", "ImageFileError", "InputError", "InputTypeError", "MeshError", "MeshFileError",
    "ParametrizationError", "ResourceError", "MissingDependency", "RenderError",
    "Mesh", "grid_mesh", "load_mesh", "save_mesh", "Parametrization", "parametrize",
    "CutDomain", "Domain", "GeometryImage", "OctahedralDomain", "PlanarDomain", "grid_normals", "load_image", "save_image",
    "save_preview", "Surface", "fit_surface", "mesh_to_image", "mesh_to_images",
]

_WHERE = {name: module for module, names in (
    ('.mesh', ('Mesh', 'grid_mesh', 'load_mesh', 'save_mesh',)),
    ('.parametrization', ('Parametrization', 'parametrize',)),
    ('.image', ('CutDomain', 'Domain', 'GeometryImage', 'OctahedralDomain', 'PlanarDomain', 'grid_normals', 'load_image',
     'save_image', 'save_preview',)),
    ('.surface', ('Surface', 'fit_surface',)),
    ('._convert', ('mesh_to_image', 'mesh_to_images',)),
) for name in names}


_SUBPACKAGES = ('mesh', 'parametrization', 'surface', 'image', 'animation', 'batch', 'errors', 'cli')


__getattr__, __dir__ = lazy_names(__name__, _WHERE, _SUBPACKAGES)
