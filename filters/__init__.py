"""filters: image operations on float arrays (H, W) or (H, W, C), knowing nothing of meshes.

Every operation meets the image's edges through one mechanism, the boundary rule ``mode``
(:mod:`filters.padding`): ``reflect``, ``linear``, ``wrap`` or ``octahedral``. Spatial filters pad
by it; Fourier operations transform the periodic extension it defines.
"""
from ._checks import MEMORY_ENV, TooLarge, as_image, as_weights, check_memory, memory_limit, positive
from .padding import pad, periodic_extension, PAD_MODES, PERIODIC_MODES
from .masks import feather, apply_masked
from .smoothing import mean_filter, gaussian_filter, bilateral_filter, guided_filter
from .denoise import median_filter, denoise_tv, denoise_nl_means
from .fourier import fourier_filter, lowpass, highpass, bandpass
from .inverse import inverse_filter, unsharp_mask
from .blend import blend, composite, paste, resize
from .curvature import grid_curvature

__all__ = ["MEMORY_ENV", "TooLarge", "as_image", "as_weights", "check_memory", "memory_limit", "positive", "pad", "periodic_extension", "PAD_MODES", "PERIODIC_MODES", "feather", "apply_masked", "mean_filter",
           "gaussian_filter", "bilateral_filter", "guided_filter", "median_filter", "denoise_tv", "denoise_nl_means",
           "fourier_filter", "lowpass", "highpass",
           "bandpass", "inverse_filter", "unsharp_mask", "blend", "composite", "paste", "resize", "grid_curvature"]
