"""Animation: morphs between shapes as blends of their geometry images, glTF morph-target files, frame
sequences and headless pictures (GIF, MP4). Writing GLB files and pictures needs the ``render`` extra
(``pip install 'geoimg[render]'``), MP4 the ``video`` extra; :func:`morph` itself needs neither.

>>> import numpy as np, geoimg
>>> a = geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32))
>>> m = morph(a, geoimg.GeometryImage(np.ones((3, 3, 3), np.float32)), frames=3, easing="linear", align="none")
>>> [float(f.pixels[0, 0, 0]) for f in m.frames()]
[0.0, 0.5, 1.0]
"""
from ._morph import ALIGNMENTS, EASINGS, Morph, morph
from ._gltf import FRAME_FORMATS, frame_jobs, save_frames, save_glb
from ._render import UP_AXES, Camera, RenderError, Renderer, render, save_animation, save_png, up_axis, label_points

__all__ = [
    "ALIGNMENTS",
    "EASINGS",
    "Morph",
    "morph",
    "FRAME_FORMATS",
    "frame_jobs",
    "save_frames",
    "save_glb",
    "UP_AXES",
    "Camera",
    "RenderError",
    "Renderer",
    "render",
    "save_animation",
    "save_png",
    "up_axis",
    "label_points",
]
