"""The options of a batch conversion: checked once, before any work, and hashed to recognize finished outputs."""
from __future__ import annotations

import dataclasses
import hashlib
import json
import math

import filters

from .._choices import QUAD_FORMATS
from .._convert import POOR_HAUSDORFF, POOR_PSNR_DB
from .._options import ConversionOptions, check_choice, plain_number
from .. import __version__
from .._steps import check_steps
from ..spectrum._transform import check_lmax
from ..errors import InputError, InputTypeError

__all__ = ["BatchOptions", "QUAD_FORMATS"]


@dataclasses.dataclass(frozen=True)
class BatchOptions(ConversionOptions):
    """What :func:`geoimg.batch.convert` does to each input: the conversion's options
    (:class:`geoimg.ConversionOptions`, their fields first), then the filter ``steps`` (``(name, values)`` pairs of
    :data:`geoimg._steps.FILTER_STEPS`, with ``mode`` and ``nsr``), and what to write besides the image
    (``quads`` in ``quads_format``) and measure (``psnr``: the quad mesh against the input; below
    ``min_psnr`` dB or with a Hausdorff distance above ``max_hausdorff`` of the diagonal the input is marked
    ``poor``).

    Parameters
    ----------
    resolution, weights, method, axis, boundary, balance, component, normals, colors
        The conversion's options, as :class:`geoimg.ConversionOptions` takes them (the weights' ``s`` a
        number).
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
    harmonics : int or None
        Also expand each image in spherical harmonics to this degree (``NAME_sh.npz`` beside it; the batch's
        coefficient table gathers them): closed genus-0 inputs only, others refused; ``method`` auto or sphere.

    Raises
    ------
    InputError
        When an option is out of range or unknown.

    Examples
    --------
    >>> BatchOptions(resolution=65, steps=[("mean", [3])]).steps
    (('mean', (3,)),)
    >>> BatchOptions(nsr=0)
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: nsr: expected a positive number, got 0
    """

    steps: tuple = ()
    mode: str | None = None
    nsr: float = 1e-3
    quads: bool = False
    quads_format: str = "obj"
    psnr: bool = True
    min_psnr: float = POOR_PSNR_DB
    max_hausdorff: float = POOR_HAUSDORFF
    harmonics: int | None = None

    def __post_init__(self):
        super().__post_init__()
        for name in ("nsr", "min_psnr", "max_hausdorff"):   # NumPy scalars as Python's, so that options hash alike
            object.__setattr__(self, name, plain_number(getattr(self, name)))
        s = self.weights.s                                   # numbers, so that the options hash
        if s is not None and not isinstance(s, float):
            raise InputTypeError(f"s: a batch takes one number, got {type(s).__name__}")
        if isinstance(self.nsr, bool) or not isinstance(self.nsr, (int, float)):
            raise InputTypeError(f"nsr: expected a number, got {type(self.nsr).__name__}")
        for name in ("min_psnr", "max_hausdorff"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise InputError(f"{name}: expected a finite number, got {value!r}")
        if not self.max_hausdorff > 0:
            raise InputError(f"max_hausdorff: expected a fraction of the diagonal above 0, got {self.max_hausdorff!r}")
        if not (math.isfinite(self.nsr) and self.nsr > 0):
            raise InputError(f"nsr: expected a positive number, got {self.nsr!r}")
        check_choice("mode", self.mode, filters.PAD_MODES, optional=True)
        check_choice("quads_format", self.quads_format, QUAD_FORMATS)
        object.__setattr__(self, "steps", check_steps(self.steps))
        if self.harmonics is not None:
            object.__setattr__(self, "harmonics", check_lmax(self.harmonics))
            if self.method not in ("auto", "sphere"):
                raise InputError(f"harmonics: the spectrum is of the sphere map; method {self.method!r} makes none "
                                 "(use auto or sphere)")

    def digest(self, *extra: object) -> str:
        """A short hash of the options, this geoimg's version and ``extra`` (say, the output layout): equal
        hashes mean equal outputs.

        Parameters
        ----------
        *extra : object
            Anything else the outputs depend on (written as text).

        Returns
        -------
        str
            16 hexadecimal digits.

        Examples
        --------
        >>> BatchOptions(resolution=65).digest() == BatchOptions(resolution=65).digest()
        True
        >>> BatchOptions(resolution=65).digest() == BatchOptions(resolution=129).digest()
        False
        """
        record = dict(dataclasses.asdict(self), weights_kind=self.weights.kind, version=__version__,
                      extra=list(map(str, extra)))
        return hashlib.sha256(json.dumps(record, sort_keys=True, default=list).encode()).hexdigest()[:16]
