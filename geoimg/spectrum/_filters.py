"""Spectral filters of octahedral geometry images through the sphere's harmonics: isotropic by
construction (a gain per degree is the same in every direction of the sphere), seam-free (glued pixels
share their direction, so their rebuilt values), unlike filters of the image's 2 x 2 unfolding, which follow
the octahedron's orientation and its distortion.

Examples
--------
>>> import geoimg
>>> d = geoimg.OctahedralDomain()
>>> ball = geoimg.GeometryImage(d.directions(65).astype(np.float32), None, d)
>>> round(float(np.linalg.norm(heat_smooth(ball, 0.01, lmax=8).pixels[32, 32])), 3)    # degree 1 by e^-0.02
0.98
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import ImageError, InputError
from ..image import GeometryImage, OctahedralDomain
from ._harmonics import Harmonics, harmonics
from ._transform import check_lmax

__all__ = ["spectral_filter", "band_limit", "heat_smooth", "band_emphasis"]


def _rebuilt(image: GeometryImage, gain: np.ndarray, lmax: int) -> GeometryImage:
    h = harmonics(image, lmax)
    coeffs = h.coeffs * gain[None, None, :, None]
    out = Harmonics(coeffs, h.metadata).to_image(image.shape[0])
    meta = {**image.metadata, "spectral_lmax": lmax}
    return GeometryImage(out.pixels, None, image.domain, None, meta, colors=image.colors)


def _default_lmax(image: GeometryImage, lmax: int | None) -> int:
    return check_lmax(lmax if lmax is not None else max(1, (image.shape[0] - 1) // 2))


def spectral_filter(image: GeometryImage, gain: Callable[[np.ndarray], np.ndarray] | np.ndarray,
                    lmax: int | None = None) -> GeometryImage:
    """The octahedral ``image`` with each degree ``l`` of its harmonics (up to ``lmax``) scaled by ``gain``:
    an array of ``lmax + 1`` numbers, or a function of the degrees (0 to ``lmax``).

    Parameters
    ----------
    image : GeometryImage
        An octahedral image.
    gain : callable or array_like
        One gain per degree.
    lmax : int, optional
        The largest degree kept (default: half the image's side); degrees above it are dropped.

    Returns
    -------
    GeometryImage
        The filtered image, of the same side and domain (normals dropped: they no longer fit).

    Raises
    ------
    ImageError
        For an image that is not octahedral.
    InputError
        For a gain of the wrong length or not finite.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
    >>> round(float(spectral_filter(ball, np.array([1.0, 0.5, 1.0]), lmax=2).pixels[16, 16, 2]), 1)
    0.5
    """
    if not isinstance(image, GeometryImage) or not isinstance(image.domain, OctahedralDomain):
        raise ImageError("spectral filters work on octahedral images (closed genus-0 shapes on the sphere)")
    lmax = _default_lmax(image, lmax)
    degrees = np.arange(lmax + 1, dtype=np.float64)
    g = np.asarray(gain(degrees) if callable(gain) else gain, np.float64)
    if g.shape != (lmax + 1,) or not np.isfinite(g).all():
        raise InputError(f"gain: expected {lmax + 1} finite numbers (one per degree 0..{lmax}), got shape {g.shape}")
    return _rebuilt(image, g, lmax)


def band_limit(image: GeometryImage, lmax: int) -> GeometryImage:
    """The octahedral ``image`` rebuilt from its harmonics up to degree ``lmax`` alone: an isotropic
    low-pass.

    Parameters
    ----------
    image : GeometryImage
        An octahedral image.
    lmax : int
        The largest degree kept.

    Returns
    -------
    GeometryImage
        The band-limited image.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
    >>> band_limit(ball, 1).shape
    (33, 33)
    """
    return spectral_filter(image, np.ones(check_lmax(lmax) + 1), lmax)


def heat_smooth(image: GeometryImage, t: float, lmax: int | None = None) -> GeometryImage:
    """Heat-kernel smoothing on the sphere for time ``t``: degree ``l`` scaled by ``exp(-l (l + 1) t)``
    (the sphere's Laplacian's eigenvalues), the same in every direction.

    Parameters
    ----------
    image : GeometryImage
        An octahedral image.
    t : float
        The diffusion time (non-negative; 1 / (L (L + 1)) halves degree L by about e).
    lmax : int, optional
        The largest degree kept (default: half the image's side).

    Returns
    -------
    GeometryImage
        The smoothed image.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
    >>> heat_smooth(ball, 0.0, lmax=4).shape
    (33, 33)
    """
    if not np.isfinite(t) or t < 0:
        raise InputError(f"t: expected a non-negative number, got {t}")
    return spectral_filter(image, lambda deg: np.exp(-deg * (deg + 1) * float(t)), lmax)


def band_emphasis(image: GeometryImage, low: int, high: int, factor: float,
                  lmax: int | None = None) -> GeometryImage:
    """Degrees ``low`` to ``high`` scaled by ``factor`` (above 1 to emphasize that band's detail, below 1 to
    damp it), the others kept.

    Parameters
    ----------
    image : GeometryImage
        An octahedral image.
    low, high : int
        The band's degrees, inclusive.
    factor : float
        Their gain.
    lmax : int, optional
        The largest degree kept (default: half the image's side).

    Returns
    -------
    GeometryImage
        The filtered image.

    Examples
    --------
    >>> import geoimg
    >>> d = geoimg.OctahedralDomain()
    >>> ball = geoimg.GeometryImage(d.directions(33).astype(np.float32), None, d)
    >>> round(float(band_emphasis(ball, 1, 1, 2.0, lmax=2).pixels[16, 16, 2]), 1)
    2.0
    """
    if not (isinstance(low, (int, np.integer)) and isinstance(high, (int, np.integer)) and 0 <= low <= high):
        raise InputError(f"low, high: expected degrees with 0 <= low <= high, got {low!r}, {high!r}")
    if not np.isfinite(factor):
        raise InputError(f"factor: expected a finite number, got {factor}")
    return spectral_filter(image, lambda deg: np.where((deg >= low) & (deg <= high), float(factor), 1.0), lmax)
