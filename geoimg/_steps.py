"""Filter steps by name (``mean``, ``sharpen``, ...), applied to a geometry image in the order given: what
``geoimg filter`` and ``geoimg batch`` run.
"""
from __future__ import annotations

import filters

from . import spectrum
from ._choices import FILTER_STEPS
from .errors import InputError
from .image import GeometryImage

__all__ = ["FILTER_STEPS", "apply_steps", "check_steps"]

def check_steps(steps) -> tuple[tuple[str, tuple], ...]:
    """``steps`` as a tuple of ``(name, values)`` after checking the names and the number of values.

    Examples
    --------
    >>> check_steps([("mean", [5]), ("sharpen", (3,))])
    (('mean', (5,)), ('sharpen', (3,)))
    >>> check_steps([("blur", [5])])
    Traceback (most recent call last):
    ...
    geoimg.errors.InputError: unknown filter step 'blur': expected one of mean, gaussian, ...
    """
    checked = []
    for step in steps:
        try:
            name, values = step
        except (TypeError, ValueError):
            raise InputError(f"a filter step is (name, values), got {step!r}") from None
        if name not in FILTER_STEPS:
            raise InputError(f"unknown filter step {name!r}: expected one of {', '.join(FILTER_STEPS)}")
        kinds = FILTER_STEPS[name][1]
        values = tuple(values)
        if len(values) != len(kinds):
            raise InputError(f"filter step {name!r} takes {len(kinds)} value(s), got {len(values)}")
        try:
            values = tuple(k(v) for k, v in zip(kinds, values))
        except (TypeError, ValueError):
            raise InputError(f"filter step {name!r}: expected {' '.join(k.__name__ for k in kinds)}, "
                             f"got {values!r}") from None
        checked.append((name, values))
    return tuple(checked)


def apply_steps(image: GeometryImage, steps, *, mode: str | None = None, nsr: float = 1e-3, mask=None,
                feather: float = 4.0) -> GeometryImage:
    """Run the filter ``steps`` (``(name, values)`` pairs, see :data:`FILTER_STEPS`) on ``image`` in order.

    ``mode`` overrides the domain's boundary rule, ``nsr`` is the Wiener noise-to-signal ratio of
    ``sharpen``, and a ``mask`` (with ``feather``) restricts every step.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> img = geoimg.mesh_to_image(m, 9, method="heightfield", axis="z", weights=geoimg.CoverageWeights(s=2.0))
    >>> apply_steps(img, [("mean", [3]), ("sharpen", [3])]).metadata["filters"][-2:]
    ['mean_filter(3, mode=reflect)', "inverse_filter('mean', 3, nsr=0.001, mode=reflect)"]
    """
    out = image
    for name, values in check_steps(steps):
        where, _, function = FILTER_STEPS[name][0].rpartition(".")
        if where == "spectrum":                 # a filter of the image through its harmonics, not of its array
            if mask is not None:
                raise InputError(f"--{name} filters the whole sphere; it takes no region")
            done = list(out.metadata.get("filters", []))
            out = getattr(spectrum, function)(out, *values)
            out.metadata["filters"] = done + [f"{function}({', '.join(map(str, values))})"]
            continue
        op = getattr(filters, FILTER_STEPS[name][0])
        kwargs: dict = {}
        if mode:
            kwargs["mode"] = mode
        if name == "sharpen":
            kwargs["nsr"] = nsr
            values = ("mean",) + values
        if mask is not None:
            kwargs.update(mask=mask, feather=feather)
        out = out.apply(op, *values, **kwargs)
    return out
