"""geoimg: polygon meshes to geometry images and back, through Goshtasby's weighted-mean surface.

The pipeline, one subpackage per stage: :mod:`geoimg.mesh` (the Mesh type, files, topology) ->
:mod:`geoimg.parametrization` (planar, disk, sphere) -> :mod:`geoimg.surface` (the weighted-mean
surface) -> :mod:`geoimg.image` (geometry images, their domains, files, regions) ->
:mod:`geoimg.animation` (morphs, glTF, pictures); :mod:`geoimg.spectrum` (spherical harmonics of closed genus-0
shapes). Image operations live in the separate package
:mod:`filters`.

>>> import geoimg
>>> mesh = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
>>> image = geoimg.mesh_to_image(mesh, 8, method="heightfield", axis="z", weights=geoimg.CoverageWeights(s=2.0))
>>> image.domain.kind, image.to_mesh().n_faces
('planar', 49)
"""
import lazy_loader

__version__ = "0.1.0"

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
