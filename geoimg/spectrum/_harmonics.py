"""Spherical harmonics of a closed genus-0 shape: the coefficients of x, y and z over its sphere map.

The shape is converted to an octahedral geometry image (the faithful default, at a resolution that does
not limit degree ``L``: the smallest ``2^k + 1`` of at least ``max(257, 8 L)`` pixels a side), or an
octahedral image is taken as it is: it already is a function on the sphere, made through geoimg's
area-balanced sphere map (an unbalanced, conformal map squeezes limbs into tiny caps, whose detail then
needs very high degrees). The image is sampled bilinearly on the transform's Gauss-Legendre grid
(:func:`geoimg.spectrum.grid_directions`) and each coordinate analysed (:func:`geoimg.spectrum.analyze`).

Examples
--------
>>> import geoimg
>>> d = geoimg.OctahedralDomain()
>>> ball = geoimg.GeometryImage(d.directions(129).astype(np.float32), None, d)     # the unit sphere
>>> h = harmonics(ball, 4)
>>> h.coeffs.shape, round(float(h.coeffs[2, 0, 1, 0]) * 3 ** 0.5, 3)            # z = P_10 / sqrt(3)
((3, 2, 5, 5), 1.0)
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.ndimage import map_coordinates

from .._atomic import atomic_path
from .._choices import COMPRESSED_FORMATS, IMAGE_FORMATS
from .._budget import check_memory
from .._convert import mesh_to_image
from .._threads import fixed_order
from .._types import Progress
from ..errors import ImageError, ImageFileError, InputTypeError, MeshError
from ..image import GeometryImage, OctahedralDomain, load_image
from ..image._npz import read_arrays
from ..mesh import Mesh, Topology, load_mesh, topology
from ..parametrization._octahedral import sphere_to_square
from ._transform import analyze, check_lmax, degree_power, grid_directions, grid_shape, synthesize

__all__ = ["Harmonics", "harmonics", "load_harmonics", "default_resolution", "require_sphere_topology",
           "IMAGE_SUFFIXES"]

IMAGE_SUFFIXES = IMAGE_FORMATS + COMPRESSED_FORMATS
COORDINATES = "xyz"


def default_resolution(lmax: int) -> int:
    """The octahedral image's side that does not limit degree ``lmax``: the smallest ``2^k + 1`` of at least
    ``max(257, 8 lmax)``.

    Parameters
    ----------
    lmax : int
        The largest degree, L.

    Returns
    -------
    int
        The side.

    Examples
    --------
    >>> default_resolution(16), default_resolution(64), default_resolution(256)
    (257, 513, 2049)
    """
    n = 257
    while n < 8 * check_lmax(lmax):
        n = 2 * n - 1
    return n


@dataclass(frozen=True)
class Harmonics:
    """The spherical-harmonic coefficients of a shape's x, y and z (real, 4pi-normalized, pyshtools'
    layout): ``coeffs[k, 0, l, m]`` the cosine and ``coeffs[k, 1, l, m]`` the sine coefficient of
    coordinate ``k`` at degree ``l`` and order ``m``.

    Parameters
    ----------
    coeffs : numpy.ndarray
        (3, 2, L + 1, L + 1) float64.
    metadata : dict
        Where they came from: ``source``, ``lmax``, ``resolution`` (of the image analysed), the conversion's
        ``psnr_db`` and map stages when a mesh was converted.

    Examples
    --------
    >>> h = Harmonics(np.zeros((3, 2, 3, 3)))
    >>> h.lmax
    2
    """

    coeffs: np.ndarray
    metadata: dict = field(default_factory=dict)

    def __post_init__(self):
        c = np.asarray(self.coeffs, np.float64)
        if c.ndim != 4 or c.shape[:2] != (3, 2) or c.shape[2] != c.shape[3] or c.shape[2] < 2:
            raise InputTypeError(f"coeffs: expected shape (3, 2, L + 1, L + 1) with L >= 1, got {c.shape}")
        if not np.isfinite(c).all():
            raise ImageError("coeffs: contains NaN or infinite values")
        object.__setattr__(self, "coeffs", c)

    @property
    def lmax(self) -> int:
        """The largest degree, L.

        Returns
        -------
        int
            L.

        Examples
        --------
        >>> Harmonics(np.zeros((3, 2, 5, 5))).lmax
        4
        """
        return self.coeffs.shape[2] - 1

    def truncated(self, lmax: int) -> Harmonics:
        """The coefficients up to degree ``lmax`` (at most :attr:`lmax`).

        Parameters
        ----------
        lmax : int
            The new largest degree.

        Returns
        -------
        Harmonics
            A copy, truncated.

        Examples
        --------
        >>> Harmonics(np.zeros((3, 2, 9, 9))).truncated(4).lmax
        4
        """
        lmax = check_lmax(lmax)
        if lmax > self.lmax:
            raise ImageError(f"lmax: {lmax} is above these coefficients' degree {self.lmax}")
        return Harmonics(self.coeffs[:, :, : lmax + 1, : lmax + 1].copy(), {**self.metadata, "lmax": lmax})

    def invariants(self) -> np.ndarray:
        """One number per degree, unchanged when the shape or its sphere is turned: the square root of the
        power of degree ``l`` summed over x, y and z (a turn of the shape mixes them orthogonally, a turn of
        the sphere keeps each one's power per degree).

        Returns
        -------
        numpy.ndarray
            (L + 1) non-negative numbers.

        Examples
        --------
        >>> c = np.zeros((3, 2, 2, 2)); c[0, 0, 1, 1] = c[1, 1, 1, 1] = c[2, 0, 1, 0] = 3 ** -0.5
        >>> Harmonics(c).invariants().round(12).tolist()
        [0.0, 1.0]
        """
        return np.sqrt(degree_power(self.coeffs).sum(axis=0))

    def normalized(self, *, scale: bool = False) -> Harmonics:
        """The coefficients in the first-order ellipsoid's frame, as SPHARM-PDM normalizes them: the shape
        moved to its centre (degree 0 set to 0), turned so that the degree-1 ellipsoid's axes lie along x,
        y and z (longest first), and its sphere turned so that the ellipsoid's axes are the sphere's; with
        ``scale``, shrunk so that the ellipsoid's longest semi-axis is 1. Shapes normalized alike can be
        compared coefficient by coefficient. The axes' signs, which the ellipsoid leaves open, are chosen so
        that the shape's third moment along the first two axes is not negative (the third axis follows, so
        that the turn is a rotation).

        Parameters
        ----------
        scale : bool, default False
            Also divide by the longest semi-axis.

        Returns
        -------
        Harmonics
            With ``metadata["normalization"]``: the object rotation, the sphere rotation and the scale.

        Examples
        --------
        >>> c = np.zeros((3, 2, 3, 3)); c[0, 0, 1, 0] = 2.0; c[1, 1, 1, 1] = 1.0; c[2, 0, 1, 1] = -0.5
        >>> n = Harmonics(c).normalized().coeffs
        >>> (np.sqrt(3) * np.array([n[0, 0, 1, 1], n[1, 1, 1, 1], n[2, 0, 1, 0]])).round(6).tolist()  # semi-axes
        [3.464102, 1.732051, 0.866025]
        """
        c = self.coeffs
        a = np.sqrt(3.0) * np.stack([c[:, 0, 1, 1], c[:, 1, 1, 1], c[:, 0, 1, 0]], axis=1)   # x(d) = A d + ...
        u, sigma, vt = np.linalg.svd(a)
        v = vt.T
        if np.linalg.det(u) < 0:                         # proper rotations: flip the third axis of both
            u[:, 2] *= -1
        if np.linalg.det(v) < 0:
            v[:, 2] *= -1
        lmax = self.lmax
        d = grid_directions(lmax).reshape(-1, 3)
        centred = c.copy()
        centred[:, :, 0, 0] = 0.0
        values = synthesize(centred, d @ v.T) @ u                  # x'(d) = U^T x(V d)
        moment = (values ** 3).mean(axis=0)
        flip = np.ones(3)
        for k in (0, 1):
            if moment[k] < 0:
                flip[k], flip[2] = -flip[k], -flip[2]
        if (flip < 0).any():                                       # turn the sphere too: synthesize again
            u, v = u * flip, v * flip
            values = synthesize(centred, d @ v.T) @ u
        size = float(sigma[0]) if scale and sigma[0] > 0 else 1.0
        coeffs = analyze((values / size).reshape(grid_shape(lmax) + (3,)), lmax)
        record = {"object_rotation": u.T.round(12).tolist(), "sphere_rotation": v.round(12).tolist(),
                  "scale": size}
        return Harmonics(coeffs, {**self.metadata, "normalization": record})

    def to_image(self, resolution: int | None = None, lmax: int | None = None) -> GeometryImage:
        """The octahedral geometry image of the shape up to degree ``lmax`` (default: all), ``resolution``
        pixels a side (default :func:`default_resolution`); glued pixels share their direction, and so their
        value.

        Parameters
        ----------
        resolution : int, optional
            The image's side (odd).
        lmax : int, optional
            Rebuild up to this degree only.

        Returns
        -------
        GeometryImage
            An octahedral image, its metadata naming the source and the degree.

        Examples
        --------
        >>> c = np.zeros((3, 2, 2, 2)); c[0, 0, 1, 1] = c[1, 1, 1, 1] = c[2, 0, 1, 0] = 3 ** -0.5
        >>> img = Harmonics(c).to_image(9)
        >>> img.shape, float(np.abs(np.linalg.norm(img.pixels, axis=2) - 1).max()) < 1e-6
        ((9, 9), True)
        """
        h = self if lmax is None else self.truncated(lmax)
        n = default_resolution(h.lmax) if resolution is None else int(resolution)
        domain = OctahedralDomain()
        n = domain.round_resolution(n)
        check_memory(8.0 * n * n * 6, f"a {n} x {n} reconstruction")
        pixels = synthesize(h.coeffs, domain.directions(n).reshape(-1, 3)).reshape(n, n, 3)
        meta = {k: v for k, v in h.metadata.items() if k in ("source", "parametrization")}
        meta.update(harmonics_lmax=h.lmax)
        return GeometryImage(pixels.astype(np.float32), None, domain, metadata=meta)

    def save(self, path: Any, *, overwrite: bool = False) -> Path:
        """Write ``coeffs`` (3, 2, L + 1, L + 1), ``invariants`` (L + 1) and the metadata (JSON text) to a
        ``.npz`` file, atomically.

        Parameters
        ----------
        path : path-like
            A ``.npz`` file.
        overwrite : bool, default False
            Replace an existing file.

        Returns
        -------
        pathlib.Path
            The file written.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> h = Harmonics(np.ones((3, 2, 3, 3)), {"source": "x.obj"})
        >>> p = h.save(pathlib.Path(tempfile.mkdtemp()) / "h.npz")
        >>> load_harmonics(p).metadata["source"]
        'x.obj'
        """
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise ImageFileError(f"{path}: coefficients are written to a .npz file")
        record = json.dumps({**self.metadata, "lmax": self.lmax, "convention": "real, 4pi-normalized, no "
                             "Condon-Shortley phase (pyshtools)"}, sort_keys=True, default=float)

        with atomic_path(path, overwrite) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, coeffs=self.coeffs, invariants=self.invariants(), metadata=np.array(record))
        return path


def load_harmonics(path: Any) -> Harmonics:
    """The :class:`Harmonics` of a ``.npz`` file written by :meth:`Harmonics.save`.

    Parameters
    ----------
    path : path-like
        The ``.npz`` file.

    Returns
    -------
    Harmonics
        Its coefficients and metadata.

    Raises
    ------
    ImageFileError
        When the file is not such an archive (a missing member, another shape, pickled objects).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = Harmonics(np.zeros((3, 2, 5, 5))).save(pathlib.Path(tempfile.mkdtemp()) / "h.npz")
    >>> load_harmonics(p).lmax
    4
    """
    path = Path(path)
    if not path.is_file():
        raise ImageFileError(f"{path}: no such file")
    arrays = read_arrays(path, {"coeffs": ("f", 4), "invariants": ("f", 1), "metadata": ("U", 0)}, "coeffs",
                         "geoimg harmonics file")
    coeffs = arrays["coeffs"]
    text = str(arrays["metadata"]) if "metadata" in arrays else "{}"
    try:
        meta = json.loads(text)
    except json.JSONDecodeError:
        meta = None
    if not isinstance(meta, dict):
        raise ImageFileError(f"{path}: its metadata is not a JSON object")
    if coeffs.dtype.kind != "f" or coeffs.ndim != 4 or coeffs.shape[:2] != (3, 2) \
            or coeffs.shape[2] != coeffs.shape[3] or coeffs.shape[2] < 2:
        raise ImageFileError(f"{path}: coeffs of shape {coeffs.shape} and type {coeffs.dtype}; expected float "
                             "(3, 2, L + 1, L + 1)")
    try:
        return Harmonics(coeffs, meta)
    except ImageError as e:
        raise ImageFileError(f"{path}: {e}") from None


def require_sphere_topology(topo: Topology) -> None:
    """Refuse, in one line that says what to do, a mesh of topology ``topo`` that is not one closed genus-0
    piece (no sphere map).
    """
    if not (topo.closed and topo.components == 1 and topo.genus == 0):
        advice = ("take one piece first (geoimg image --component)" if topo.components != 1 else
                  "close its holes first" if not topo.closed else
                  "a surface with handles has no map onto the sphere (its cut-open image has no spectrum)")
        raise MeshError(f"harmonics need a closed genus-0 surface (one piece, no boundary, no handle); this mesh "
                        f"is {topo.describe()}: {advice}")


def _sphere_image(source: Any, lmax: int, resolution: int | None,
                  progress: Progress | None) -> tuple[GeometryImage, Mesh | None]:
    """The octahedral image to analyse, and the mesh it was made of (None for an image)."""
    if isinstance(source, (str, Path)) and Path(source).suffix.lower() in IMAGE_SUFFIXES:
        source = load_image(source)
    if isinstance(source, GeometryImage):
        if not isinstance(source.domain, OctahedralDomain):
            raise ImageError(f"harmonics need a function on the sphere, an octahedral image; this one is "
                             f"{source.domain.kind} (cut-open, chart and planar images have no sphere: convert a "
                             "closed genus-0 mesh)")
        return source, None
    mesh = load_mesh(source) if isinstance(source, (str, Path)) else source
    if not isinstance(mesh, Mesh):
        raise InputTypeError(f"source: expected a closed genus-0 Mesh, an octahedral GeometryImage or a file, got "
                             f"{type(source).__name__}")
    require_sphere_topology(topology(mesh))
    n = default_resolution(lmax) if resolution is None else int(resolution)
    check_memory(4.0 * n * n * 12, f"a {n} x {n} octahedral image for the harmonics")
    return mesh_to_image(mesh, n, method="sphere", progress=progress), mesh


@fixed_order
def harmonics(source: Any, lmax: int, *, resolution: int | None = None,
              progress: Progress | None = None) -> Harmonics:
    """The spherical-harmonic coefficients of x, y and z up to degree ``lmax`` of a closed genus-0 mesh (or
    mesh file), over its area-balanced sphere map, or of an octahedral geometry image (or image file).

    Parameters
    ----------
    source : Mesh, GeometryImage or path-like
        The shape.
    lmax : int
        The largest degree, 1 to :data:`geoimg.spectrum.MAX_LMAX`.
    resolution : int, optional
        The octahedral image's side for a mesh (default :func:`default_resolution`).
    progress : callable, optional
        Called with a short message at each stage.

    Returns
    -------
    Harmonics
        With ``metadata``: ``source``, ``lmax``, ``resolution``, and for a mesh the conversion's ``psnr_db``.

    Raises
    ------
    MeshError
        For a mesh that is not closed, of genus 0 and in one piece.
    ImageError
        For an image that is not octahedral.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(2 * d.directions(65).astype(np.float32), None, d)
    >>> h = harmonics(ball, 2)
    >>> float(h.invariants()[1].round(2))     # a sphere of radius 2 (bilinear between pixels: 1.999)
    2.0
    """
    lmax = check_lmax(lmax)
    say = progress or (lambda message: None)
    check_memory(8.0 * np.prod(grid_shape(lmax)) * 3 * 2, f"the degree-{lmax} transform's grid")
    image, mesh = _sphere_image(source, lmax, resolution, progress)
    n = image.shape[0]
    say(f"sampling the {n} x {n} image on the degree-{lmax} grid; transforming")
    d = grid_directions(lmax)
    uv = sphere_to_square(d.reshape(-1, 3)) * (n - 1)
    pixels = np.asarray(image.pixels, np.float64)
    values = np.stack([map_coordinates(pixels[..., k], [uv[:, 1], uv[:, 0]], order=1, mode="nearest")
                       for k in range(3)], axis=1).reshape(d.shape[:2] + (3,))
    coeffs = analyze(values, lmax)
    meta: dict = {"lmax": lmax, "resolution": n, "source": image.metadata.get("source", "")}
    if isinstance(source, (str, Path)):
        meta["source"] = Path(source).name
    for key in ("psnr_db", "hausdorff", "map_stages", "parametrization"):
        if key in image.metadata:
            meta[key] = image.metadata[key]
    return Harmonics(coeffs, meta)
