"""The options of a conversion, mesh to geometry image: one object that :func:`geoimg.mesh_to_image`,
:func:`geoimg.mesh_to_images`, ``geoimg image``, the batch (:class:`geoimg.batch.ConvertOptions` adds its
own) and a morph's mesh keys take, checked here, once, before any work.
"""
from __future__ import annotations

import dataclasses
import math
import numbers
from typing import Any

import numpy as np

from ._choices import COMPONENT_CHOICES, DEFAULT_DISK_BALANCE
from .errors import InputError, InputTypeError
from .parametrization import AXES, DISK_BALANCES, DISK_BOUNDARIES, PARAMETRIZATION_METHODS
from .parametrization._parametrize import check_axis
from .surface import SLIVER_RULES, WEIGHTS
from .surface._coverage import check_s
from .surface._fit import check_s_range

__all__ = ["ConversionOptions", "check_resolution", "check_choice", "plain_number"]


def check_resolution(resolution) -> None:
    """Refuse a resolution that is not None or a whole number of pixels of at least 2."""
    if resolution is not None and (isinstance(resolution, bool) or not isinstance(resolution, numbers.Integral)
                                   or resolution < 2):
        raise InputError(f"resolution: expected a whole number of pixels of at least 2, got {resolution!r}")


def check_choice(name: str, value, choices, optional: bool = False) -> None:
    """Refuse ``value`` unless it is one of ``choices`` (or None, when ``optional``)."""
    if (value is None and optional) or (isinstance(value, str) and value in choices):
        return
    raise InputError(f"{name}: expected one of {', '.join(map(str, choices))}, got {value!r}")


def plain_number(value):
    """A NumPy scalar as the Python number it holds (so that options compare and hash alike)."""
    return value.item() if isinstance(value, np.generic) and isinstance(value, numbers.Number) else value


def _check_s(s, weights: str) -> None:
    """One number in the range of the weights; per-face values and maps (the paper's weights only) are
    checked by :func:`geoimg.fit_surface`, which knows the faces.
    """
    if s is None:
        return
    if isinstance(s, (bool, str, bytes)):
        raise InputTypeError(f"s: expected a number, got {type(s).__name__}")
    if not isinstance(s, numbers.Real):
        if weights == "coverage":
            raise InputError(f"s: coverage weights take one number (one width everywhere), got {s!r:.80}")
        return
    if weights == "coverage":
        check_s(s)
    elif not math.isfinite(s):
        raise InputError(f"s: expected a positive finite number, got {s!r}")
    else:
        check_s_range(np.array([s], np.float64))          # the messages fit_surface gives


@dataclasses.dataclass(frozen=True)
class ConversionOptions:
    """How a mesh becomes a geometry image, checked on construction.

    Parameters
    ----------
    resolution : int or None
        Pixels along the longer side; None: from ``s`` (see :func:`geoimg.mesh_to_image`).
    s : float, per-face values, SmoothnessMap or None
        The smoothness; None: the width that serves the resolution (coverage weights) or 1 (the paper's).
        Coverage weights take one number.
    method : str
        The parametrization's method (see :func:`geoimg.parametrize`).
    axis : {"x", "y", "z"} or None
        A terrain's up axis (``heightfield`` and ``auto`` only).
    boundary : {"square", "keep"}
        A disk's boundary: on the unit square, or its own convex outline.
    balance : {"area", "slim", "none"}
        How a disk or cut-open map is relaxed.
    weights : {"coverage", "gaussian", "local"}
        The surface's weights.
    n : int
        Faces per weight of ``local`` weights, at least 2.
    tol : float
        The truncation tolerance of Gaussian weights, in [0, 1) (0: exact sums).
    sliver_rule : {"robust", "paper"}
        How long thin faces are treated.
    component : {"all", "largest"} or int
        Which pieces of a mesh of several (:func:`geoimg.mesh_to_images`).
    normals, colors : bool
        Keep the surface's normals and the mesh's colours in the images.

    Raises
    ------
    InputError
        When an option is out of range or not one of its choices.
    InputTypeError
        When an option is of the wrong type.

    Examples
    --------
    >>> ConversionOptions(resolution=np.int64(65), method="sphere").resolution
    65
    >>> ConversionOptions(n=1)
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: n: expected a whole number of at least 2, got 1
    """

    resolution: int | None = None
    s: Any = None
    method: str = "auto"
    axis: str | None = None
    boundary: str = "square"
    balance: str = DEFAULT_DISK_BALANCE
    weights: str = "coverage"
    n: int = 10
    tol: float = 1e-10
    sliver_rule: str = "robust"
    component: str | int = "all"
    normals: bool = True
    colors: bool = True

    def __post_init__(self):
        for name in ("resolution", "n", "component", "s", "tol"):
            object.__setattr__(self, name, plain_number(getattr(self, name)))
        check_resolution(self.resolution)
        check_choice("weights", self.weights, WEIGHTS)
        _check_s(self.s, self.weights)
        if isinstance(self.tol, bool) or not isinstance(self.tol, numbers.Real):
            raise InputTypeError(f"tol: expected a number, got {type(self.tol).__name__}")
        if not (math.isfinite(self.tol) and 0 <= self.tol < 1):
            raise InputError(f"tol: expected a number from 0 (exact) to below 1, got {self.tol!r}")
        if isinstance(self.n, bool) or not isinstance(self.n, int) or self.n < 2:
            raise InputError(f"n: expected a whole number of at least 2, got {self.n!r}")
        check_choice("method", self.method, PARAMETRIZATION_METHODS)
        check_choice("axis", self.axis, AXES, optional=True)
        check_axis(self.method, self.axis)
        check_choice("boundary", self.boundary, DISK_BOUNDARIES)
        check_choice("balance", self.balance, DISK_BALANCES)
        check_choice("sliver_rule", self.sliver_rule, SLIVER_RULES)
        if not (self.component in COMPONENT_CHOICES or (isinstance(self.component, int)
                                                        and not isinstance(self.component, bool)
                                                        and self.component >= 0)):
            raise InputError(f"component: expected 'all', 'largest' or a piece number, got {self.component!r}")
        for name in ("normals", "colors"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise InputTypeError(f"{name}: expected True or False, got {getattr(self, name)!r}")
            object.__setattr__(self, name, bool(getattr(self, name)))

    def conversion(self) -> dict:
        """These options as keyword arguments of :func:`geoimg.mesh_to_images` (``component`` included).

        Returns
        -------
        dict
            ``resolution, s, method, ..., colors`` by name.

        Examples
        --------
        >>> ConversionOptions(resolution=65).conversion()["resolution"]
        65
        """
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(ConversionOptions)}
