"""The options of a batch conversion: checked once, before any work, and hashed to recognize finished outputs."""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import numbers

import numpy as np

import filters

from .._choices import DEFAULT_DISK_BALANCE, QUAD_FORMATS
from .._convert import POOR_HAUSDORFF, POOR_PSNR_DB, check_resolution
from .. import __version__
from .._steps import check_steps
from ..errors import InputError, InputTypeError
from ..parametrization import AXES, DISK_BALANCES, DISK_BOUNDARIES, PARAMETRIZATION_METHODS
from ..parametrization._parametrize import check_axis
from ..surface import S_RANGE, SLIVER_RULES, WEIGHTS
from ..surface._coverage import COVERAGE_S_RANGE

__all__ = ["ConvertOptions", "QUAD_FORMATS"]



def _choice(name, value, choices, optional=False):
    if (value is None and optional) or value in choices:
        return
    raise InputError(f"{name}: expected one of {', '.join(map(str, choices))}, got {value!r}")


@dataclasses.dataclass(frozen=True)
class ConvertOptions:
    """What :func:`geoimg.batch.convert` does to each input: the options of :func:`geoimg.mesh_to_images`,
    then the filter ``steps`` (``(name, values)`` pairs of :data:`geoimg._steps.FILTER_STEPS`, with
    ``mode`` and ``nsr``), and what to write besides the image (``quads`` in ``quads_format``) and
    measure (``psnr``: the quad mesh against the input; below ``min_psnr`` dB or with a Hausdorff distance
    above ``max_hausdorff`` of the diagonal the input is marked ``poor``).

    Parameters
    ----------
    resolution : int or None
        Pixels along the longer side; None: from ``s`` (see :func:`geoimg.mesh_to_image`).
    s : float or None
        The smoothness; None: the width that serves the resolution.
    method : str
        The parametrization's method (see :func:`geoimg.parametrize`).
    axis : {"x", "y", "z"} or None
        A terrain's up axis.
    boundary : {"square", "keep"}
        A disk's boundary: on the unit square, or its own convex outline.
    balance : {"area", "slim", "none"}
        How a disk or cut-open map is relaxed.
    weights : {"coverage", "gaussian", "local"}
        The surface's weights.
    n : int
        Faces per weight of ``local`` weights.
    tol : float
        The truncation tolerance of Gaussian weights (0: exact sums).
    sliver_rule : {"robust", "paper"}
        How long thin faces are treated.
    component : {"all", "largest"} or int
        Which pieces of a mesh of several.
    normals, colors : bool
        Keep the surface's normals and the mesh's colours in the images.
    steps : tuple
        Filter steps, ``(name, values)`` pairs, applied in order.
    mode : str or None
        The filters' boundary rule; None: the domain's.
    nsr : float
        The noise-to-signal ratio of a ``sharpen`` step.
    quads : bool
        Also write each image's quad mesh.
    quads_format : {"obj", "ply", "off"}
        The quad meshes' format.
    psnr : bool
        Measure each quad mesh against its input.
    min_psnr : float
        Below this PSNR (dB) an input is marked ``poor``.
    max_hausdorff : float
        Above this Hausdorff distance (a share of the diagonal) an input is marked ``poor``.

    Raises
    ------
    InputError
        When an option is out of range or unknown.

    Examples
    --------
    >>> ConvertOptions(resolution=65, steps=[("mean", [3])]).steps
    (('mean', (3,)),)
    >>> ConvertOptions(s=0).digest() # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: s: expected a number from 1e-06 to 1000, got 0
    """

    resolution: int | None = None
    s: float | None = None
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
    steps: tuple = ()
    mode: str | None = None
    nsr: float = 1e-3
    quads: bool = False
    quads_format: str = "obj"
    psnr: bool = True
    min_psnr: float = POOR_PSNR_DB
    max_hausdorff: float = POOR_HAUSDORFF

    def __post_init__(self):
        # numpy's scalars are numbers too: kept as Python's, so that equal options hash alike
        for name in ("resolution", "n", "component", "s", "tol", "nsr", "min_psnr", "max_hausdorff"):
            value = getattr(self, name)
            if isinstance(value, np.generic) and isinstance(value, numbers.Number):
                object.__setattr__(self, name, value.item())
        check_resolution(self.resolution)
        for name in ("s", "tol", "nsr"):
            value = getattr(self, name)
            if (name != "s" or value is not None) and (isinstance(value, bool) or not isinstance(value, (int, float))):
                raise InputTypeError(f"{name}: expected a number, got {type(value).__name__}")
        lo, hi = COVERAGE_S_RANGE if self.weights == "coverage" else S_RANGE
        if self.s is not None and not (math.isfinite(self.s) and lo <= self.s <= hi):
            raise InputError(f"s: expected a number from {lo:g} to {hi:g}, got {self.s!r}")
        if not (math.isfinite(self.tol) and 0 <= self.tol < 1):
            raise InputError(f"tol: expected a number from 0 (exact) to below 1, got {self.tol!r}")
        for name in ("min_psnr", "max_hausdorff"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise InputError(f"{name}: expected a finite number, got {value!r}")
        if not self.max_hausdorff > 0:
            raise InputError(f"max_hausdorff: expected a fraction of the diagonal above 0, got {self.max_hausdorff!r}")
        if not (math.isfinite(self.nsr) and self.nsr > 0):
            raise InputError(f"nsr: expected a positive number, got {self.nsr!r}")
        if isinstance(self.n, bool) or not isinstance(self.n, int) or self.n < 1:
            raise InputError(f"n: expected a positive whole number, got {self.n!r}")
        _choice("method", self.method, PARAMETRIZATION_METHODS)
        _choice("axis", self.axis, AXES, optional=True)
        check_axis(self.method, self.axis)
        _choice("boundary", self.boundary, DISK_BOUNDARIES)
        _choice("balance", self.balance, DISK_BALANCES)
        _choice("weights", self.weights, WEIGHTS)
        _choice("sliver_rule", self.sliver_rule, SLIVER_RULES)
        _choice("mode", self.mode, filters.PAD_MODES, optional=True)
        _choice("quads_format", self.quads_format, QUAD_FORMATS)
        if not (self.component in ("all", "largest") or (isinstance(self.component, int)
                                                          and not isinstance(self.component, bool)
                                                          and self.component >= 0)):
            raise InputError(f"component: expected 'all', 'largest' or a piece number, got {self.component!r}")
        object.__setattr__(self, "steps", check_steps(self.steps))

    def image_options(self) -> dict:
        """The keyword arguments of :func:`geoimg.mesh_to_images`."""
        return dict(
            resolution=self.resolution,
            s=None if self.s is None else float(self.s),
            method=self.method,
            component=self.component,
            axis=self.axis,
            boundary=self.boundary,
            balance=self.balance,
            weights=self.weights,
            n=self.n,
            tol=float(self.tol),
            sliver_rule=self.sliver_rule,
            normals=self.normals,
            colors=self.colors,
        )

    def digest(self, *extra: object) -> str:
        """A short hash of the options, this geoimg's version and ``extra`` (say, the output layout): equal
        hashes mean equal outputs.
        """
        record = dict(dataclasses.asdict(self), version=__version__, extra=list(map(str, extra)))
        return hashlib.sha256(json.dumps(record, sort_keys=True, default=list).encode()).hexdigest()[:16]
