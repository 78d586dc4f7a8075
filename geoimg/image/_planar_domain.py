"""The planar domain: a parameter rectangle, nothing glued (terrains, disks, meshes with their own UVs)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import ImageError

from ._domain import Domain

__all__ = ["PlanarDomain"]


@dataclass(frozen=True)
class PlanarDomain(Domain):
    """A parameter rectangle ``[0, extent[0]] x [0, extent[1]]``, u along columns and v along rows.

    Nothing is glued; filters reflect at the edges (``mode="linear"`` keeps a border in place), and
    derivatives continue the surface linearly. Pixels outside the parametrized region are masked.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    extent : tuple of float
        The parameter rectangle's width and height (the longer side 1).

    Examples
    --------
    >>> d = PlanarDomain(extent=(1.0, 0.5))
    >>> d.grid_shape(5), d.glue((3, 5)) is None
    ((3, 5), True)
    """

    extent: tuple = (1.0, 1.0)

    kind: ClassVar[str] = "planar"

    def __post_init__(self):
        super().__post_init__()
        try:
            ext = tuple(float(e) for e in self.extent)
        except (TypeError, ValueError):
            raise ImageError(f"extent: expected two positive numbers, got {self.extent!r}") from None
        if len(ext) != 2 or not all(np.isfinite(e) and e > 0 for e in ext):
            raise ImageError(f"extent: expected two positive finite numbers, got {self.extent!r}")
        object.__setattr__(self, "extent", ext)

    @classmethod
    def _from_fields(cls, metadata: dict) -> PlanarDomain:
        return cls(orientation=metadata.get("orientation", 1), extent=tuple(metadata.get("extent", (1.0, 1.0))))

    def check_shape(self, shape: tuple[int, int]) -> None:
        pass

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        """The shorter side gets the count that keeps pixels nearly square; corners sit on the rectangle's
        corners (spacing ``extent / (count - 1)``, as the paper's increments of 1/255 for 256 samples).

        Parameters
        ----------
        resolution : int
            Pixels along the longer side.

        Returns
        -------
        tuple of int
            (H, W).

        Examples
        --------
        >>> PlanarDomain(extent=(0.5, 1.0)).grid_shape(9)
        (9, 5)
        """
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ImageError(f"resolution: expected an integer >= 2, got {resolution!r}")
        big = max(self.extent)
        w, h = (max(2, int(round((resolution - 1) * e / big)) + 1) for e in self.extent)
        return h, w
