"""filters: image operations on float arrays (H, W) or (H, W, C), knowing nothing of meshes.

Every operation meets the image's edges through one mechanism, the boundary rule ``mode``
(:mod:`filters.padding`): ``reflect``, ``linear``, ``wrap`` or ``octahedral``. Spatial filters pad
by it; Fourier operations transform the periodic extension it defines.

The exported names are listed once, in ``__init__.pyi``, and imported when first used (``lazy_loader``).

>>> import filters
>>> filters.mean_filter.__module__
'filters.smoothing'
"""
import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
