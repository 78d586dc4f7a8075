"""The weights of a weighted-mean surface, as one typed choice: :class:`CoverageWeights` (the faithful default:
each triangle weighted by its share of a Gaussian footprint) or :class:`GaussianWeights` (the paper's: the
rational Gaussians of the distance to each face's centre, or its locally supported weights). Each checks its
own fields; :func:`geoimg.fit_surface`, :func:`geoimg.mesh_to_image`, the batch and the command line take one.

The flat keywords of earlier releases (``s=``, ``weights="gaussian"``, ``n=``, ``tol=``, ``sliver_rule=``)
still work for one release, with a :class:`DeprecationWarning` (:func:`resolve_weights`).
"""
from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._choices import SLIVER_RULES, WEIGHTS
from ..errors import InputError, InputTypeError
from ._gaussian_smoothness import SmoothnessMap

__all__ = ["CoverageWeights", "GaussianWeights", "Weights", "make_weights", "resolve_weights",
           "COVERAGE_S_RANGE", "S_RANGE", "UNSET"]

COVERAGE_S_RANGE = (1e-6, 1e3)   # sigma = s dbar: no exponent to underflow, but a width of at least a millionth
S_RANGE = (1e-3, 1e3)            # sigma = s d: beyond these the Gaussians are a face's own plane, or the mean of all
UNSET: Any = type("Unset", (), {"__repr__": lambda self: "UNSET"})()     # a keyword not given


def _check_tol(tol) -> float:
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise InputTypeError(f"tol: expected a number, got {type(tol).__name__}")
    value = float(tol)
    if not (math.isfinite(value) and 0 <= value < 1):
        raise InputError(f"tol: expected a number from 0 (exact) to below 1, got {tol!r}")
    return value


def _number(value):
    """A NumPy scalar as the Python number it holds (so that weights compare and hash alike)."""
    return value.item() if isinstance(value, np.generic) and isinstance(value, numbers.Number) else value


def check_coverage_s(s) -> float:
    """One positive ``s`` for coverage weights (one width everywhere: no per-face values or maps)."""
    if isinstance(s, bool) or not isinstance(s, (int, float, np.number)):
        raise InputError(f"s: coverage weights take one number (one width everywhere), got {s!r:.80}")
    lo, hi = COVERAGE_S_RANGE
    if not (np.isfinite(s) and lo <= s <= hi):
        raise InputError(f"s: expected a number from {lo:g} to {hi:g} (sigma = s * dbar), got {s!r}")
    return float(s)


def check_s_range(values: np.ndarray) -> None:
    """Refuse Gaussian widths ``s`` outside :data:`S_RANGE`."""
    lo, hi = float(np.min(values)), float(np.max(values))
    if lo < S_RANGE[0] or hi > S_RANGE[1]:
        raise InputError(f"s: expected values from {S_RANGE[0]:g} to {S_RANGE[1]:g} (sigma = s d_i; outside that "
                         f"range the weights under- or overflow), got {lo:g}" + (f" to {hi:g}" if hi != lo else ""))


@dataclass(frozen=True)
class CoverageWeights:
    """Each triangle weighted by its share of a Gaussian footprint of width ``sigma = s * dbar`` around the
    point (``dbar``: the triangles' mean size in the parameter domain): infinitely smooth, and the mesh itself
    as ``s -> 0`` (see :mod:`geoimg.surface._coverage`). The default of every conversion.

    Parameters
    ----------
    s : float or None
        The width; None (default): the width that serves the resolution an image is sampled at (0.4 of a pixel
        spacing, :func:`geoimg.surface.prefilter_s`), a prefilter for the grid rather than a smoothing; points
        evaluated without a resolution see ``s = 1``. One number (1e-6 to 1000): no per-face values or maps.
    tol : float
        Weights below it are skipped; 0 sums every triangle.

    Raises
    ------
    InputError
        On an ``s`` or ``tol`` out of range.

    Examples
    --------
    >>> CoverageWeights(), CoverageWeights(s=2).s
    (CoverageWeights(s=None, tol=1e-10), 2.0)
    >>> CoverageWeights(s=[1, 2])
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: s: coverage weights take one number (one width everywhere), got [1, 2]
    """

    s: float | None = None
    tol: float = 1e-10

    kind: ClassVar[str] = "coverage"

    def __post_init__(self):
        if self.s is not None:
            object.__setattr__(self, "s", check_coverage_s(_number(self.s)))
        object.__setattr__(self, "tol", _check_tol(_number(self.tol)))


@dataclass(frozen=True)
class GaussianWeights:
    """The paper's weights: the rational Gaussians ``exp(-|x - c_i|^2 / 2 sigma_i^2)`` of the distance to each
    face's centre, ``sigma_i = s d_i`` (infinitely smooth; smooth the shape by about ``s`` faces), or with ``n``
    the paper's locally supported ``1 - 3R^2 + 2R^3`` (C1, faster, may leave holes, which are masked).

    Parameters
    ----------
    s : float, array_like of per-face values, or SmoothnessMap
        The smoothness (1e-3 to 1000): one number, one per face
        (:func:`geoimg.surface.smoothness_field`) or a map s(u, v) (:func:`geoimg.surface.uv_smoothness`,
        planar only); per-face values are checked against the mesh when fitted.
    n : int or None
        None: the rational Gaussians; a whole number of at least 2: the locally supported weights, each
        reaching ``n`` face centres.
    tol : float
        Truncation: skipped weights are below it; 0 for the exact sum.
    sliver_rule : {"robust", "paper"}
        How long thin faces are treated (see :mod:`geoimg.surface._gaussian_face_maps`).

    Raises
    ------
    InputError
        On a field out of range or not one of its choices.

    Examples
    --------
    >>> GaussianWeights(s=2).kind, GaussianWeights(n=10).kind
    ('gaussian', 'local')
    >>> GaussianWeights(n=1)
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: n: expected None or a whole number of at least 2, got 1
    """

    s: Any = 1.0
    n: int | None = None
    tol: float = 1e-10
    sliver_rule: str = "robust"

    def __post_init__(self):
        s = _number(self.s)
        object.__setattr__(self, "s", s)
        if isinstance(s, (bool, str, bytes)):
            raise InputError(f"s: expected a positive number, per-face values or a SmoothnessMap, got {s!r}")
        if isinstance(s, numbers.Real):
            if not (math.isfinite(s) and s > 0):
                raise InputError(f"s: expected a positive finite number, got {s!r}")
            check_s_range(np.array([s], np.float64))
            object.__setattr__(self, "s", float(s))
        elif not isinstance(s, SmoothnessMap):
            arr = np.asarray(s)
            if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or arr.ndim != 1:
                raise InputError(f"s: expected a positive number, per-face values or a SmoothnessMap, got {s!r:.80}")
        n = _number(self.n)
        if n is not None and (isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 2):
            raise InputError(f"n: expected None or a whole number of at least 2, got {n!r}")
        object.__setattr__(self, "n", None if n is None else int(n))
        object.__setattr__(self, "tol", _check_tol(_number(self.tol)))
        if not (isinstance(self.sliver_rule, str) and self.sliver_rule in SLIVER_RULES):
            raise InputError(f"sliver_rule: expected one of {', '.join(SLIVER_RULES)}, got {self.sliver_rule!r}")

    @property
    def kind(self) -> str:
        """``"gaussian"`` or, with ``n``, ``"local"``.

        Examples
        --------
        >>> GaussianWeights(n=6).kind
        'local'
        """
        return "gaussian" if self.n is None else "local"


Weights = CoverageWeights | GaussianWeights


def make_weights(kind: str = "coverage", *, s: Any = None, n: int | None = None, tol: float = 1e-10,
                 sliver_rule: str = "robust") -> Weights:
    """The weights a name and flat settings stand for (the command line's ``--weights``, ``--s``, ``--n``,
    ``--tol``, ``--sliver-rule``): coverage (``n`` and ``sliver_rule`` do not apply), gaussian (``s``
    default 1), or local (``n`` default 10).

    Parameters
    ----------
    kind : {"coverage", "gaussian", "local"}
    s, n, tol, sliver_rule
        As the weights take them; None for the default.

    Returns
    -------
    CoverageWeights or GaussianWeights

    Examples
    --------
    >>> make_weights("local", s=2.0)
    GaussianWeights(s=2.0, n=10, tol=1e-10, sliver_rule='robust')
    """
    if not (isinstance(kind, str) and kind in WEIGHTS):
        raise InputError(f"weights: expected one of {', '.join(WEIGHTS)}, got {kind!r}")
    if n is not None and kind != "local":
        GaussianWeights(n=n)                       # checked, though only the local weights use it
    if kind == "coverage":
        return CoverageWeights(s=s, tol=tol)
    return GaussianWeights(s=1.0 if s is None else s, n=(10 if n is None else n) if kind == "local" else None,
                           tol=tol, sliver_rule=sliver_rule)


def resolve_weights(weights: Any, *, s: Any = UNSET, n: Any = UNSET, tol: Any = UNSET, sliver_rule: Any = UNSET,
                    old_default: str, old_s: float | None = None, caller: str, stacklevel: int = 3) -> Weights:
    """The typed weights a call asks for: ``weights`` itself, or :class:`CoverageWeights` when nothing is
    given; the flat keywords of earlier releases (``s``, a name for ``weights``, ``n``, ``tol``,
    ``sliver_rule``, and a number where ``weights`` stands, once ``s``'s place) build them as they did then
    (``old_default`` the name and ``old_s`` the ``s`` they defaulted to), with a :class:`DeprecationWarning`.

    Raises
    ------
    InputError
        When typed weights come with flat keywords too.

    Examples
    --------
    >>> import warnings
    >>> resolve_weights(None, old_default="gaussian", caller="f")
    CoverageWeights(s=None, tol=1e-10)
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     resolve_weights(2.0, old_default="gaussian", caller="f"), w[0].category.__name__
    (GaussianWeights(s=2.0, n=None, tol=1e-10, sliver_rule='robust'), 'DeprecationWarning')
    """
    flat = {k: v for k, v in (("s", s), ("n", n), ("tol", tol), ("sliver_rule", sliver_rule)) if v is not UNSET}
    if isinstance(weights, (CoverageWeights, GaussianWeights)):
        if flat:
            raise InputError(f"{caller}: {', '.join(flat)} belong inside weights= ({type(weights).__name__}"
                             f"({', '.join(f'{k}=...' for k in flat)})), not beside it")
        return weights
    if weights is not None and not isinstance(weights, str):       # a number in s's old place
        if "s" in flat:
            raise InputTypeError(f"{caller}: weights: expected CoverageWeights or GaussianWeights, got "
                                 f"{type(weights).__name__}")
        flat["s"], weights = weights, None
    if weights is None and not flat:
        return CoverageWeights()
    kind = old_default if weights is None else weights
    said = [*flat] + ([f"weights={kind!r}"] if weights else [])
    settings = {k: v for k, v in flat.items() if v is not None}
    built = make_weights(kind, **{"s": old_s, **settings})
    warnings.warn(f"{caller}: the keywords {', '.join(said)} are deprecated and go in the next release; pass "
                  f"weights={built!r}", DeprecationWarning, stacklevel=stacklevel)
    return built
