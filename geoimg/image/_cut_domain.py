"""The cut-open domain: the unit square whose boundary is glued to itself along a cut (any genus, any holes)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

import filters
from ..errors import ImageError
from ..parametrization._layout import perimeter_point, twin_positions

from ._domain import Domain
from ._perimeter import (copy_across, corners_within, ghost_copies, glue_groups, perimeter_pixels, perimeter_sides,
                         straight_pieces)

__all__ = ["CutDomain"]


@dataclass(frozen=True)
class CutDomain(Domain):
    """The unit square whose boundary is glued to itself along a cut (Gu, Gortler & Hoppe 2002): the
    image of a mesh of any genus and any number of boundary loops, cut open into one disk (see
    :mod:`geoimg.parametrization._cut`).

    The perimeter, counter-clockwise from pixel (0, 0) along row 0, is laid out in ``4 * quantum``
    quanta: ``segments`` are ``(start, length, twin)`` in quanta, ``twin`` the segment on the other side
    of the cut (-1: the mesh's own boundary, left open). Offset ``j`` along a segment is offset
    ``length - j`` along its twin, so on an ``N x N`` image with ``N - 1`` a multiple of ``quantum`` every
    boundary pixel on one side of a cut has an exact twin. Twins are glued (averaged after filters, welded
    in the quad mesh, which then has the mesh's genus and boundary loops), and filters see across a cut
    the twin's side of it.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    quantum : int
        Quanta per side of the square; an image's ``N - 1`` is a multiple of it.
    segments : tuple
        ``(start, length, twin)`` of each perimeter segment, in quanta.

    Examples
    --------
    >>> d = CutDomain(quantum=4, segments=((0, 4, 2), (4, 4, 3), (8, 4, 0), (12, 4, 1)))   # a torus
    >>> reps, group = d.glue((5, 5))
    >>> len(reps), int(group[0]) == int(group[4]) == int(group[20]) == int(group[24])    # 4 x 4 quads + 0
    (16, True)
    """

    quantum: int = 64
    segments: tuple = ()

    kind: ClassVar[str] = "cut"
    boundary: ClassVar[str | None] = None        # no filters rule: the domain pads itself (pad)

    def __post_init__(self):
        super().__post_init__()
        q = self.quantum
        if isinstance(q, bool) or not isinstance(q, (int, np.integer)) or q < 1:
            raise ImageError(f"quantum: expected a positive integer, got {q!r}")
        try:
            segs = tuple((int(a), int(n), int(t)) for a, n, t in self.segments)
        except (TypeError, ValueError):
            raise ImageError(f"segments: expected (start, length, twin) triples, got {self.segments!r:.80}") from None
        total = 4 * int(q)
        ok = len(segs) > 0 and segs[0][0] == 0 and all(n >= 1 for _, n, _ in segs) \
            and all(a + n == b for (a, n, _), (b, _, _) in zip(segs, segs[1:])) and segs[-1][0] + segs[-1][1] == total
        ok = ok and all(t == -1 or (0 <= t < len(segs) and segs[t][2] == i and segs[t][1] == n)
                        for i, (_, n, t) in enumerate(segs))
        if not ok:
            raise ImageError("segments: expected consecutive (start, length, twin) segments from 0 around the "
                             f"{total} quanta of the perimeter, twins of equal length naming each other")
        object.__setattr__(self, "quantum", int(q))
        object.__setattr__(self, "segments", segs)

    @classmethod
    def _from_fields(cls, metadata: dict) -> CutDomain:
        return cls(orientation=metadata.get("orientation", 1), quantum=metadata.get("quantum", 64),
                   segments=tuple(tuple(s) for s in metadata.get("segments", ())))

    def to_metadata(self) -> dict:
        return {**super().to_metadata(), "quantum": self.quantum, "segments": [list(s) for s in self.segments]}

    METADATA_KEYS: ClassVar[tuple] = Domain.METADATA_KEYS + ("quantum", "segments")

    def same_kind(self, other: Domain) -> bool:
        """Cut-open images pair up pixel for pixel only when their cuts are laid out alike (the same mesh's
        faces, or the same layout).

        Parameters
        ----------
        other : Domain
            Another image's domain.

        Returns
        -------
        bool
            Whether they blend pixel for pixel.

        Examples
        --------
        >>> d = CutDomain(segments=((0, 256, -1),))
        >>> d.same_kind(d), d.same_kind(CutDomain(segments=((0, 128, 1), (128, 128, 0))))
        (True, False)
        """
        return type(self) is type(other) and (self.quantum, self.segments) == (other.quantum, other.segments)

    def check_shape(self, shape: tuple[int, int]) -> None:
        h, w = shape
        if h != w or (h - 1) % self.quantum:
            raise ImageError(f"pixels: a cut-open image is N x N with N - 1 a multiple of {self.quantum} (so that "
                             f"the two sides of the cut pair up pixel for pixel, e.g. "
                             f"{self.round_resolution(max(h, w))}), got {h} x {w}")

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ImageError(f"resolution: expected an integer >= 2, got {resolution!r}")
        self.check_shape((resolution, resolution))
        return int(resolution), int(resolution)

    def round_resolution(self, resolution: int) -> int:
        q = self.quantum
        return int(-(-(max(int(resolution), 2) - 1) // q) * q + 1)

    def size_rule(self) -> str:
        return (f"a cut-open image is N x N with N - 1 a multiple of {self.quantum} (the two sides of the cut pair "
                "up pixel for pixel)")

    def _twin_pairs(self, n: int):
        """Perimeter positions ``(p, p')`` of twin pixels (both directions), in pixels."""
        _, p, _, q = twin_positions([(0, a, length, t) for a, length, t in self.segments], (n - 1) // self.quantum)
        return p, q

    def _make_glue(self, shape):
        self.check_shape(shape)
        n = shape[0]
        per = perimeter_pixels(n)
        p, q = self._twin_pairs(n)
        return glue_groups(n * n, per[p], per[q])

    def _pieces(self):
        """Straight pieces of the twinned segments: ``(a, b, a', b')`` perimeter positions (quanta) of a
        piece on one side of a cut and of its twin on the other (``a`` pairs with ``a'``).
        """
        out = []
        for start, length, t in self.segments:
            if t < 0:
                continue
            tstart = self.segments[t][0]
            for o1, o2 in straight_pieces(start, length, tstart, self.quantum):
                out.append((start + o1, start + o2, tstart + length - o1, tstart + length - o2))
        return out

    def ghosts(self, centres: np.ndarray, reach: np.ndarray, size: np.ndarray | None = None) -> list:
        """Across each cut, the faces near its other side, turned and moved rigidly onto this side's
        outside: the weighted mean at a cut then sees the surface continue, as inside. Each face goes
        with the straight piece of a cut nearest to it, if its weights reach that far.

        Parameters
        ----------
        centres : numpy.ndarray
            (F, 2) the faces' parametric centres.
        reach : numpy.ndarray
            (F,) how far each face's weights reach.
        size : numpy.ndarray or None
            (F,) each face's own size (its enclosing radius): a face within it of a twin piece's end is not
            copied (its copy would spill beside the next piece). None: no margin (the paper's weights, whose
            surface at s = 1 needs the copies up to the ends).

        Returns
        -------
        list
            ``(face indices, R, b)`` per copy.

        Examples
        --------
        >>> CutDomain(segments=((0, 256, -1),)).ghosts(np.full((1, 2), 0.5), np.full(1, 0.01))
        []
        """
        reach = np.minimum(np.asarray(reach, np.float64), 0.5)
        pieces = [(perimeter_point([a, b], self.quantum), perimeter_point([ta, tb], self.quantum))
                  for a, b, ta, tb in self._pieces()]
        rims = [perimeter_point([a, b], self.quantum) for a, b in self._rim_pieces()]
        return ghost_copies(centres, reach, pieces, rims, size)

    def _rim_pieces(self):
        """Straight pieces ``(a, b)`` (perimeter positions, quanta) of the mesh's own boundary."""
        out = []
        for start, length, t in self.segments:
            if t < 0:
                cuts = [start, *corners_within(start, length, self.quantum), start + length]
                out.extend(zip(cuts[:-1], cuts[1:]))
        return out

    def pad(self, array: np.ndarray, width: int) -> np.ndarray:
        """Reflected at the mesh's own boundary; across a cut, the pixels inward of the twin, so a filter
        sees the surface continue (exact along straight stretches of a side, approximate at the corners).

        Parameters
        ----------
        array : numpy.ndarray
            (N, N) or (N, N, C).
        width : int
            Pixels added on each side.

        Returns
        -------
        numpy.ndarray
            The padded array.

        Examples
        --------
        >>> CutDomain(segments=((0, 256, -1),)).pad(np.zeros((65, 65, 3)), 4).shape
        (73, 73, 3)
        """
        a = np.asarray(array)
        out = filters.pad(a, width, "reflect")
        if width == 0:
            return out
        n = a.shape[0]
        m = n - 1
        p, q = self._twin_pairs(n)
        keep = (p % m != 0) & (q % m != 0)          # corners have two sides: leave them reflected
        p, q = p[keep], q[keep]
        per = perimeter_pixels(n)
        copy_across(out, a, (per[p] // n, per[p] % n, perimeter_sides(p, n)),
                    (per[q] // n, per[q] % n, perimeter_sides(q, n)), np.full(len(p), width), width)
        return out
