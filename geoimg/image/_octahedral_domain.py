"""The octahedral domain: the unit sphere unfolded onto an odd square whose sides are glued to themselves."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ImageError
from ..parametrization import grid_directions
from ..parametrization._octahedral import check_size, glued_groups

from ._domain import Domain

__all__ = ["OctahedralDomain"]


@dataclass(frozen=True)
class OctahedralDomain(Domain):
    """The unit sphere unfolded onto an odd ``N x N`` square by the octahedral map (Praun & Hoppe 2003).

    Each side of the square is glued to itself, mirrored about its midpoint, and the four corners are
    one point (see :mod:`geoimg.parametrization._octahedral`): filters continue across the sides by a
    half-turn, glued pixels are averaged after a filter, and the quad mesh welds them by index into a
    closed genus-0 surface. The image covers the whole sphere, so it takes no mask.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).

    Examples
    --------
    >>> d = OctahedralDomain()
    >>> reps, group = d.glue((5, 5))
    >>> len(reps), int(group[4]), int(group[24])     # the corners are one point
    (18, 0, 0)
    """

    kind: ClassVar[str] = "octahedral"
    boundary: ClassVar[str] = "octahedral"
    extension: ClassVar[str] = "octahedral"
    parameter_dim: ClassVar[int] = 3
    rotations: ClassVar[bool] = True

    def check_shape(self, shape: tuple[int, int]) -> None:
        if shape[0] != shape[1]:
            raise ImageError(f"pixels: an octahedral image must be square, got {tuple(shape)}")
        check_size(shape[0])

    def check_mask(self, mask: ArrayLike | None) -> None:
        if mask is not None and not np.all(mask):
            raise ImageError("mask: an octahedral image covers the whole sphere; it takes no mask")

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        n = check_size(resolution)
        return n, n

    def round_resolution(self, resolution: int) -> int:
        return int(resolution) + 1 - int(resolution) % 2

    def size_rule(self) -> str:
        return "an octahedral image has an odd side (its glued sides pair up pixel for pixel)"

    def directions(self, n: int) -> np.ndarray:
        """Unit directions (n, n, 3) of the pixels, computed so that glued pixels get identical ones.

        Parameters
        ----------
        n : int
            The image's side, odd.

        Returns
        -------
        numpy.ndarray
            (n, n, 3) unit directions.

        Examples
        --------
        >>> OctahedralDomain().directions(5)[2, 2].tolist()
        [0.0, 0.0, 1.0]
        """
        return grid_directions(n)

    def parameter_points(self, shape: tuple[int, int]) -> np.ndarray:
        """The pixels' unit directions on the sphere, (H * W, 3).

        Parameters
        ----------
        shape : tuple of int
            The image's (H, W).

        Returns
        -------
        numpy.ndarray
            (H * W, 3) unit directions.

        Examples
        --------
        >>> OctahedralDomain().parameter_points((5, 5)).shape
        (25, 3)
        """
        self.check_shape(shape)
        return self.directions(shape[0]).reshape(-1, 3)

    def _make_glue(self, shape):
        self.check_shape(shape)
        return glued_groups(shape[0])

    def estimate_normals(self, pixels: ArrayLike) -> np.ndarray | None:
        return None
