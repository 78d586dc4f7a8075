"""filters: image operations on float arrays (H, W) or (H, W, C), knowing nothing of meshes.

Every operation meets the image's edges through one mechanism, the boundary rule ``mode``
(:mod:`filters.padding`): ``reflect``, ``linear``, ``wrap`` or ``octahedral``. Spatial filters pad
by it; Fourier operations transform the periodic extension it defines.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_names

if TYPE_CHECKING:
    from ._checks import MEMORY_ENV, TooLarge, as_image, as_weights, check_memory, memory_limit, positive
    from .padding import pad, periodic_extension, PAD_MODES, PERIODIC_MODES
    from .masks import feather, apply_masked
    from .smoothing import mean_filter, gaussian_filter, bilateral_filter, guided_filter
    from .denoise import median_filter, denoise_tv, denoise_nl_means
    from .fourier import fourier_filter, lowpass, highpass, bandpass
    from .inverse import inverse_filter, unsharp_mask
    from .blending import blend, composite, paste, resize
    from .curvature import grid_curvature

__all__ = ["MEMORY_ENV", "TooLarge", "as_image", "as_weights", "check_memory", "memory_limit", "positive", "pad", "periodic_extension", "PAD_MODES", "PERIODIC_MODES", "feather", "apply_masked", "mean_filter",
           "gaussian_filter", "bilateral_filter", "guided_filter", "median_filter", "denoise_tv", "denoise_nl_means",
           "fourier_filter", "lowpass", "highpass",
           "bandpass", "inverse_filter", "unsharp_mask", "blend", "composite", "paste", "resize", "grid_curvature"]

_WHERE = {name: module for module, names in (
    ('._checks', ('MEMORY_ENV', 'TooLarge', 'as_image', 'as_weights', 'check_memory', 'memory_limit', 'positive',)),
    ('.padding', ('pad', 'periodic_extension', 'PAD_MODES', 'PERIODIC_MODES',)),
    ('.masks', ('feather', 'apply_masked',)),
    ('.smoothing', ('mean_filter', 'gaussian_filter', 'bilateral_filter', 'guided_filter',)),
    ('.denoise', ('median_filter', 'denoise_tv', 'denoise_nl_means',)),
    ('.fourier', ('fourier_filter', 'lowpass', 'highpass', 'bandpass',)),
    ('.inverse', ('inverse_filter', 'unsharp_mask',)),
    ('.blending', ('blend', 'composite', 'paste', 'resize',)),
    ('.curvature', ('grid_curvature',)),
) for name in names}


_SUBPACKAGES = ('padding', 'masks', 'smoothing', 'denoise', 'fourier', 'inverse', 'blending', 'curvature')


__getattr__, __dir__ = lazy_names(__name__, _WHERE, _SUBPACKAGES)
