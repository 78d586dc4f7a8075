"""Collections of shapes by their harmonics: a coefficient table (a row per shape, aicsshparam's column names
per coordinate) and a shape space (the principal components of such rows: a mean shape and its modes).

Examples
--------
>>> c = np.zeros((3, 2, 3, 3)); c[0, 0, 1, 1] = c[1, 1, 1, 1] = c[2, 0, 1, 0] = 3 ** -0.5
>>> row = coefficient_row(Harmonics(c))
>>> len(row), row["x_shcoeffs_L1M1C"] == float(c[0, 0, 1, 1])
(27, True)
>>> bool(np.array_equal(harmonics_from_row(row).coeffs, c))
True
"""
from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, InputTypeError
from ._harmonics import COORDINATES, Harmonics

__all__ = ["coefficient_columns", "coefficient_row", "harmonics_from_row", "ShapeSpace", "shape_space"]

_NAME = re.compile(r"^([xyz])_shcoeffs_L(\d+)M(\d+)([CS])$")


def _terms(lmax: int):
    """(coordinate, cos/sin, l, m) of every stored term: m <= l, and no sine at m = 0 (it is 0)."""
    for k in range(3):
        for deg in range(lmax + 1):
            for m in range(deg + 1):
                yield k, 0, deg, m
                if m:
                    yield k, 1, deg, m


def coefficient_columns(lmax: int) -> list[str]:
    """The columns of a coefficient table to degree ``lmax``: ``{x|y|z}_shcoeffs_L{l}M{m}{C|S}`` (aicsshparam's
    names with the coordinate in front), for m <= l, each coordinate's cosine and sine terms by degree and order;
    the sine terms of order 0, always 0, left out: 3 (L + 1)^2 columns.

    Parameters
    ----------
    lmax : int
        The largest degree, L.

    Returns
    -------
    list of str
        The names, in the table's order.

    Examples
    --------
    >>> coefficient_columns(1)[:5]
    ['x_shcoeffs_L0M0C', 'x_shcoeffs_L1M0C', 'x_shcoeffs_L1M1C', 'x_shcoeffs_L1M1S', 'y_shcoeffs_L0M0C']
    """
    return [f"{COORDINATES[k]}_shcoeffs_L{deg}M{m}{'CS'[cs]}" for k, cs, deg, m in _terms(int(lmax))]


def coefficient_row(h: Harmonics) -> dict[str, float]:
    """The coefficients of ``h`` as one row of a coefficient table (:func:`coefficient_columns`).

    Parameters
    ----------
    h : Harmonics
        The shape's coefficients.

    Returns
    -------
    dict
        Column name -> value, in the columns' order.

    Examples
    --------
    >>> coefficient_row(Harmonics(np.ones((3, 2, 2, 2))))["z_shcoeffs_L1M1S"]
    1.0
    """
    if not isinstance(h, Harmonics):
        raise InputTypeError(f"h: expected Harmonics, got {type(h).__name__}")
    c = h.coeffs
    names = coefficient_columns(h.lmax)
    return {name: float(c[k, cs, deg, m]) for name, (k, cs, deg, m) in zip(names, _terms(h.lmax))}


def harmonics_from_row(row: Mapping) -> Harmonics:
    """The :class:`Harmonics` of one row of a coefficient table (other columns are ignored).

    Parameters
    ----------
    row : mapping
        Column name -> value (a dict, or a pandas row); every column of :func:`coefficient_columns` of one
        degree L must be there.

    Returns
    -------
    Harmonics
        The coefficients, to degree L.

    Raises
    ------
    InputError
        When no coefficient column is there, or some of degree L's are missing.

    Examples
    --------
    >>> harmonics_from_row({"input": "a.obj", **coefficient_row(Harmonics(np.ones((3, 2, 4, 4))))}).lmax
    3
    """
    found = {}
    for name in row.keys():
        match = _NAME.match(str(name))
        if match:
            found[name] = match
    if not found:
        raise InputError("row: no coefficient column (named like x_shcoeffs_L1M0C)")
    lmax = max(int(m.group(2)) for m in found.values())
    if lmax < 1:
        raise InputError("row: coefficients of degree 0 only; at least degree 1 is needed")
    names = coefficient_columns(lmax)
    missing = [n for n in names if n not in found]
    if missing:
        raise InputError(f"row: {len(missing)} of the degree-{lmax} table's columns are missing (first "
                         f"{missing[0]})")
    c = np.zeros((3, 2, lmax + 1, lmax + 1))
    for name, (k, cs, deg, m) in zip(names, _terms(lmax)):
        c[k, cs, deg, m] = float(row[name])
    return Harmonics(c)


@dataclass(frozen=True)
class ShapeSpace:
    """The principal components of a collection's coefficients: ``mean`` and ``modes`` (unit vectors of
    coefficients), ``sigma`` the standard deviation of the collection along each mode.

    Parameters
    ----------
    mean : Harmonics
        The mean shape's coefficients.
    modes : numpy.ndarray
        (K, 3, 2, L + 1, L + 1) the modes, orthonormal as vectors of coefficients.
    sigma : numpy.ndarray
        (K,) standard deviations along the modes (largest first).
    explained : numpy.ndarray
        (K,) the share of the collection's variance each mode explains.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> space = shape_space([Harmonics(rng.normal(size=(3, 2, 3, 3))) for _ in range(5)], 2)
    >>> space.modes.shape, bool(space.sigma[0] >= space.sigma[1])
    ((2, 3, 2, 3, 3), True)
    """

    mean: Harmonics
    modes: np.ndarray
    sigma: np.ndarray
    explained: np.ndarray

    def shape(self, weights: Sequence[float]) -> Harmonics:
        """The shape at ``weights`` standard deviations along the first ``len(weights)`` modes.

        Parameters
        ----------
        weights : sequence of float
            One number per mode (at most as many as there are modes).

        Returns
        -------
        Harmonics
            ``mean + sum_i weights[i] sigma[i] modes[i]``.

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> space = shape_space([Harmonics(rng.normal(size=(3, 2, 3, 3))) for _ in range(4)], 2)
        >>> bool(np.allclose(space.shape([0, 0]).coeffs, space.mean.coeffs))
        True
        """
        w = np.asarray(weights, np.float64).ravel()
        if len(w) > len(self.modes) or not np.isfinite(w).all():
            raise InputError(f"weights: expected at most {len(self.modes)} finite numbers, got {list(weights)!r}")
        c = self.mean.coeffs + np.tensordot(w * self.sigma[:len(w)], self.modes[:len(w)], axes=1)
        return Harmonics(c, {"shape_space_weights": w.tolist()})


def shape_space(shapes: Sequence[Harmonics], modes: int = 3) -> ShapeSpace:
    """The principal components of the coefficients of ``shapes`` (each truncated to the least degree among
    them): normalize them first (:meth:`Harmonics.normalized`) so that their terms correspond.

    Parameters
    ----------
    shapes : sequence of Harmonics
        At least two shapes.
    modes : int, default 3
        How many modes to keep (at most one fewer than the shapes).

    Returns
    -------
    ShapeSpace
        The mean shape, the modes and the spread along each.

    Examples
    --------
    >>> a, b = Harmonics(np.zeros((3, 2, 3, 3))), Harmonics(np.ones((3, 2, 3, 3)))
    >>> space = shape_space([a, b], 1)
    >>> float(space.mean.coeffs[0, 0, 0, 0]), round(float(space.sigma[0]), 6)   # sqrt(54) / 2
    (0.5, 3.674235)
    """
    shapes = list(shapes)
    if len(shapes) < 2 or not all(isinstance(h, Harmonics) for h in shapes):
        raise InputError(f"shapes: expected two or more Harmonics, got {len(shapes)} items")
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or not 1 <= modes < len(shapes):
        raise InputError(f"modes: expected an integer from 1 to {len(shapes) - 1}, got {modes!r}")
    lmax = min(h.lmax for h in shapes)
    x = np.stack([h.truncated(lmax).coeffs.ravel() for h in shapes])
    mean = x.mean(axis=0)
    _, s, vt = np.linalg.svd(x - mean, full_matrices=False)
    sigma = s / np.sqrt(len(shapes))
    total = float((sigma ** 2).sum())
    shape = (3, 2, lmax + 1, lmax + 1)
    explained = sigma ** 2 / total if total > 0 else np.zeros_like(sigma)
    return ShapeSpace(Harmonics(mean.reshape(shape), {"lmax": lmax, "shapes": len(shapes)}),
                      vt[:modes].reshape((modes,) + shape), sigma[:modes], explained[:modes])
