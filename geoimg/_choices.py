"""The vocabularies of options: the names each choice of the API and the command line accepts, kept apart
from the code that acts on them so that the command line's parser (``geoimg --help``) needs none of it.
Each is re-exported by the module that acts on it (``geoimg.mesh.MESH_FORMATS``, ...).
"""
from __future__ import annotations

import numpy as np

__all__ = [
    "MESH_FORMATS",
    "MESH_READ_FORMATS",
    "COMPONENT_CHOICES",
    "ASSUMABLE_DOMAINS",
    "IMAGE_FORMATS",
    "COMPRESSED_FORMATS",
    "DEFAULT_CURVATURE_SCALE",
    "READ_IMAGE_FORMATS",
    "EXR_LAYOUTS",
    "PARAMETRIZATION_METHODS",
    "AXES",
    "DISK_BOUNDARIES",
    "DISK_BALANCES",
    "DEFAULT_DISK_BALANCE",
    "EASINGS",
    "ALIGNMENTS",
    "FRAME_FORMATS",
    "UP_AXES",
    "QUAD_FORMATS",
    "WEIGHTS",
    "SLIVER_RULES",
    "FILTER_STEPS",
    "BACKENDS",
    "POOR_PSNR_DB",
    "POOR_HAUSDORFF",
]

MESH_FORMATS = (".obj", ".off", ".ply", ".stl", ".glb")                 # read and written
MESH_READ_FORMATS = MESH_FORMATS + (".gltf",)                          # read only (its buffers beside it)
QUAD_FORMATS = tuple(f.lstrip(".") for f in MESH_FORMATS if f in (".obj", ".ply", ".off"))    # formats that keep quads
COMPONENT_CHOICES = ("all", "largest")
IMAGE_FORMATS = (".exr", ".npz", ".tif", ".tiff", ".npy")
DEFAULT_CURVATURE_SCALE = 0.01   # of the diagonal: a terrain's ridges and valleys, not its facets
COMPRESSED_FORMATS = (".jp2",)                  # written by geoimg compress, read as any geometry image
READ_IMAGE_FORMATS = IMAGE_FORMATS + (".png",) + COMPRESSED_FORMATS     # .png: a preview, with --approximate
EXR_LAYOUTS = ("geoimg", "rgba")      # the mask as channel "mask", or as "A" (alpha) for compositing tools
ASSUMABLE_DOMAINS = ("planar", "octahedral")     # a cut-open image cannot be read without its recorded layout
PARAMETRIZATION_METHODS = ("auto", "uv", "heightfield", "disk", "sphere", "cut", "charts")
AXES = ("x", "y", "z")
DISK_BOUNDARIES = ("square", "keep")
DISK_BALANCES = ("area", "slim", "none")
DEFAULT_DISK_BALANCE = "area"
WEIGHTS = ("coverage", "gaussian", "local")
SLIVER_RULES = ("robust", "paper")
BACKENDS = ("cpu", "cuda")            # where a planar surface's Gaussian sums are sampled
EASINGS = {
    "linear": lambda t: t,
    "smoothstep": lambda t: t * t * (3.0 - 2.0 * t),
    "ease-in-out": lambda t: 0.5 - 0.5 * np.cos(np.pi * t),
    "ease-in": lambda t: t * t,
    "ease-out": lambda t: 1.0 - (1.0 - t) ** 2,
}
ALIGNMENTS = ("similarity", "centre", "none")
FRAME_FORMATS = ("obj", "ply", "off", "exr")
UP_AXES = ("x", "y", "z")

# step name -> (filters function, argument types, metavar, help)
FILTER_STEPS: dict[str, tuple[str, tuple[type, ...], str | tuple[str, ...], str]] = {
    "mean": ("mean_filter", (int,), "SIZE", "mean (box) filter of SIZE x SIZE pixels (odd), as in the paper"),
    "gaussian": ("gaussian_filter", (float,), "SIGMA", "Gaussian smoothing, SIGMA pixels"),
    "bilateral": ("bilateral_filter", (float, float), ("SIGMA", "RANGE"),
                  "edge-preserving bilateral filter: SIGMA pixels, RANGE in coordinate units"),
    "guided": ("guided_filter", (int, float), ("RADIUS", "EPS"), "edge-preserving guided filter"),
    "median": ("median_filter", (int,), "SIZE", "median of SIZE x SIZE pixels per channel: removes spikes"),
    "tv": ("denoise_tv", (float,), "WEIGHT", "total-variation denoising (scikit-image), WEIGHT in coordinate units"),
    "nlmeans": ("denoise_nl_means", (float,), "H",
                "non-local means denoising (scikit-image), H in coordinate units (about the noise's sigma)"),
    "sharpen": ("inverse_filter", (int,), "SIZE", "inverse filter undoing a SIZE x SIZE mean filter (Wiener, --nsr)"),
    "unsharp": ("unsharp_mask", (float, float), ("SIGMA", "AMOUNT"), "unsharp masking"),
    "lowpass": ("lowpass", (float,), "CUTOFF", "Fourier low-pass, CUTOFF cycles per pixel (0.5 = Nyquist)"),
    "bandpass": ("bandpass", (float, float), ("LOW", "HIGH"), "Fourier band-pass (the detail between two cutoffs)"),
    # through the sphere's harmonics (geoimg.spectrum): octahedral images only, the same in every direction
    "heat": ("spectrum.heat_smooth", (float,), "T",
             "heat-kernel smoothing on the sphere for time T, through the spherical harmonics (octahedral images)"),
    "bandlimit": ("spectrum.band_limit", (int,), "L",
                  "keep the sphere's harmonics up to degree L: an isotropic low-pass (octahedral images)"),
}

POOR_PSNR_DB = 30.0          # an image below this PSNR, or with a Hausdorff distance above POOR_HAUSDORFF of
POOR_HAUSDORFF = 0.10        # the diagonal, is far from its mesh: a warning, and 'poor' in a batch
