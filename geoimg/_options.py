"""The options of a conversion, mesh to geometry image: one object that :func:`geoimg.mesh_to_image`,
:func:`geoimg.mesh_to_images`, ``geoimg image``, the batch (:class:`geoimg.batch.BatchOptions` adds its
own) and a morph's mesh keys take, checked here, once, before any work.
"""
from __future__ import annotations

import dataclasses
import numbers

import numpy as np

from ._choices import COMPONENT_CHOICES, DEFAULT_DISK_BALANCE
from .errors import InputError, InputTypeError
from .parametrization import AXES, DISK_BALANCES, DISK_BOUNDARIES, PARAMETRIZATION_METHODS
from .parametrization._parametrize import check_axis
from .surface._weights import UNSET, CoverageWeights, GaussianWeights, resolve_weights

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


DEPRECATED = ("s", "n", "tol", "sliver_rule")      # flat weight settings of earlier releases


@dataclasses.dataclass(frozen=True)
class ConversionOptions:
    """How a mesh becomes a geometry image, checked on construction: the one object that
    :func:`geoimg.mesh_to_image`, :func:`geoimg.mesh_to_images`, ``geoimg image``, the batch
    (:class:`geoimg.batch.BatchOptions` adds its own) and a morph's mesh keys take. An option is added here,
    once (and as a flag of the same name on the command line).

    Parameters
    ----------
    resolution : int or None
        Pixels along the longer side; None: from the weights' width (see :func:`geoimg.mesh_to_image`).
    weights : CoverageWeights or GaussianWeights
        The surface's weights and their settings (default ``CoverageWeights()``, the faithful image).
    method : str
        The parametrization's method (see :func:`geoimg.parametrize`).
    axis : {"x", "y", "z"} or None
        A terrain's up axis (``heightfield`` and ``auto`` only).
    boundary : {"square", "keep"}
        A disk's boundary: on the unit square, or its own convex outline.
    balance : {"area", "slim", "none"}
        How a disk or cut-open map is relaxed.
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
    >>> ConversionOptions(weights="gaussian")
    Traceback (most recent call last):
    ...
    geoimg.errors.InputTypeError: weights: expected CoverageWeights or GaussianWeights, got str
    """

    resolution: int | None = None
    weights: CoverageWeights | GaussianWeights = CoverageWeights()
    method: str = "auto"
    axis: str | None = None
    boundary: str = "square"
    balance: str = DEFAULT_DISK_BALANCE
    component: str | int = "all"
    normals: bool = True
    colors: bool = True

    def __post_init__(self):
        for name in ("resolution", "component"):
            object.__setattr__(self, name, plain_number(getattr(self, name)))
        check_resolution(self.resolution)
        if not isinstance(self.weights, (CoverageWeights, GaussianWeights)):
            raise InputTypeError(f"weights: expected CoverageWeights or GaussianWeights, got "
                                 f"{type(self.weights).__name__}")
        check_choice("method", self.method, PARAMETRIZATION_METHODS)
        check_choice("axis", self.axis, AXES, optional=True)
        check_axis(self.method, self.axis)
        check_choice("boundary", self.boundary, DISK_BOUNDARIES)
        check_choice("balance", self.balance, DISK_BALANCES)
        if not (self.component in COMPONENT_CHOICES or (isinstance(self.component, int)
                                                        and not isinstance(self.component, bool)
                                                        and self.component >= 0)):
            raise InputError(f"component: expected 'all', 'largest' or a piece number, got {self.component!r}")
        for name in ("normals", "colors"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise InputTypeError(f"{name}: expected True or False, got {getattr(self, name)!r}")
            object.__setattr__(self, name, bool(getattr(self, name)))

    @classmethod
    def create(cls, options: ConversionOptions | None = None, *, caller: str, stacklevel: int = 3, **values):
        """These options built from ``options`` (or the defaults) with ``values`` replacing fields; the flat
        weight keywords of earlier releases (``s``, ``weights`` as a name, ``n``, ``tol``, ``sliver_rule``)
        build ``weights`` as they did then (see :func:`geoimg.surface._weights.resolve_weights`), with a
        :class:`DeprecationWarning` naming ``caller``.

        Parameters
        ----------
        options : ConversionOptions, optional
            The options to start from (the defaults when None).
        caller : str
            The function that was called, for messages.
        stacklevel : int
            Where a deprecation warning points (the caller's caller).
        **values
            Fields replacing those of ``options``, and the deprecated flat keywords.

        Returns
        -------
        ConversionOptions
            Of this class (a subclass adds its own fields).

        Raises
        ------
        InputTypeError
            On a keyword that is no option.

        Examples
        --------
        >>> ConversionOptions.create(caller="f", resolution=33, method="sphere").method
        'sphere'
        """
        if options is not None and not isinstance(options, cls):
            raise InputTypeError(f"{caller}: options: expected a {cls.__name__}, got {type(options).__name__}")
        flat = {k: values.pop(k) for k in DEPRECATED if k in values}
        weights = values.pop("weights", None)
        if flat or (weights is not None and not isinstance(weights, (CoverageWeights, GaussianWeights))):
            values["weights"] = resolve_weights(weights, **{k: flat.get(k, UNSET) for k in DEPRECATED},
                                                old_default="coverage", old_s=None, caller=caller,
                                                stacklevel=stacklevel + 1)
        elif weights is not None:
            values["weights"] = weights
        unknown = sorted(set(values) - {f.name for f in dataclasses.fields(cls)})
        if unknown:
            raise InputTypeError(f"{caller}: unknown option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}")
        return dataclasses.replace(options, **values) if options is not None else cls(**values)

    def conversion(self) -> ConversionOptions:
        """The conversion's own options (those of :class:`ConversionOptions`, whatever subclass this is).

        Returns
        -------
        ConversionOptions

        Examples
        --------
        >>> ConversionOptions(resolution=65).conversion().resolution
        65
        """
        return ConversionOptions(**{f.name: getattr(self, f.name) for f in dataclasses.fields(ConversionOptions)})
