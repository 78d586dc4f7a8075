"""filters: image operations on float arrays (H, W, C), knowing nothing of meshes.

The smoothing, inverse-filtering, masking, FFT and blending operations land with the filters issue;
this package holds only the boundary padding they will share.
"""
from .padding import pad, PAD_MODES

__all__ = ["pad", "PAD_MODES"]
