"""geoimg: polygon meshes to geometry images and back, through Goshtasby's weighted-mean surface.

>>> import geoimg
>>> mesh = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
>>> param = geoimg.parametrize(mesh, "heightfield", axis="z")
>>> image = geoimg.fit_surface(mesh, param, s=2.0).sample(8)
>>> image.to_mesh().n_faces
49
"""
from .errors import GeoimgError, ImageFileError, MeshError, MeshFileError, ParametrizationError
from .image import GeometryImage, grid_normals
from .image_io import load_image, save_image, save_preview
from .mesh import Mesh
from .mesh_io import load_mesh, save_mesh
from .parametrization import Parametrization, parametrize
from .surface import Surface, fit_surface
from .terrain import grid_mesh

__version__ = "0.1.0"

__all__ = [
    "GeoimgError", "ImageFileError", "MeshError", "MeshFileError", "ParametrizationError",
    "GeometryImage", "grid_normals", "load_image", "save_image", "save_preview",
    "Mesh", "load_mesh", "save_mesh", "Parametrization", "parametrize", "Surface", "fit_surface", "grid_mesh",
]
