"""The multi-chart domain: square charts packed in one image, their sides glued to each other's by index."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

import filters
from ..errors import ImageError
from ..parametrization._layout import (MIN_SCALE, layout_extent, layout_span, perimeter_point, tile_points,
                                      twin_positions, weld_defects)

from ._domain import Domain, grid_normals
from ._perimeter import (copy_across, corners_within, ghost_copies, glue_groups, perimeter_cells, perimeter_sides,
                         straight_pieces)

__all__ = ["ChartsDomain"]


def _overlapping(squares: tuple, gutter: int) -> bool:
    """Whether two of ``squares`` ``(row, column, side)`` come closer than ``gutter``."""
    sq = np.array(squares, np.int64)
    r, c, n = sq[:, 0], sq[:, 1], sq[:, 2]
    apart = (r[:, None] + n[:, None] + gutter <= r[None]) | (r[None] + n[None] + gutter <= r[:, None]) | \
        (c[:, None] + n[:, None] + gutter <= c[None]) | (c[None] + n[None] + gutter <= c[:, None])
    np.fill_diagonal(apart, True)
    return not bool(apart.all())


@dataclass(frozen=True)
class ChartsDomain(Domain):
    """Square charts of their own sizes packed in one image, ``gutter`` quanta apart, each chart's perimeter
    glued to its neighbours' (Sander et al. 2003, "Multi-chart geometry images", with charts as squares
    whose sides match sample for sample, as Carr et al. 2006 lay them out): the image of a surface of any
    genus cut into discs (see :mod:`geoimg.parametrization._charts`).

    Square ``k`` is ``squares[k] = (row, column, side)`` in quanta; its perimeter is ``4 * side`` quanta,
    counter-clockwise from its pixel (0, 0) along its first row, split into ``segments``: ``(tile, start,
    length, twin)``, ``twin`` the index of the segment glued to it in reverse (on another square or the
    same one, or -1: the mesh's own boundary). On an image whose ``N - 1`` is a multiple ``m`` of the
    layout's span in quanta, a square is ``m * side + 1`` pixels a side and every pixel on a glued side has
    an exact twin: twins are welded in the quad mesh (watertight across charts), averaged after filters, and
    filters read across a side the pixels inward of its twin, as far as half the gutter. Pixels of the
    gutter belong to no chart and are never valid.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    squares : tuple
        ``(row, column, side)`` per square, in quanta; squares at least ``gutter`` apart.
    gutter : int
        Quanta between neighbouring squares at least.
    segments : tuple
        ``(tile, start, length, twin)`` per perimeter segment, in quanta, square by square.

    Examples
    --------
    >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), gutter=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
    >>> d.grid_shape(21), d.extent           # 2 squares of 4 quanta, 2 between: 10 quanta across, 2 pixels each
    ((9, 21), (1.0, 0.4))
    >>> reps, group = d.glue((9, 21))
    >>> int(group[0]) == int(group[12]), int(group[1]) == int(group[33])   # (0, 0), (0, 1) of 0: (0, 0), (1, 0) of 1
    (True, True)
    """

    squares: tuple = ((0, 0, 16),)
    gutter: int = 2
    segments: tuple = ()

    kind: ClassVar[str] = "charts"
    boundary: ClassVar[str | None] = None        # the domain pads itself, square by square (pad)
    coverage_only: ClassVar[bool] = True

    def __post_init__(self):
        super().__post_init__()
        g = self.gutter
        if isinstance(g, bool) or not isinstance(g, (int, np.integer)) or g < 1:
            raise ImageError(f"gutter: expected a positive integer (quanta between squares), got {g!r}")
        object.__setattr__(self, "gutter", int(g))
        try:
            sq = tuple((int(r), int(c), int(n)) for r, c, n in self.squares)
            segs = tuple((int(k), int(a), int(n), int(t)) for k, a, n, t in self.segments)
        except (TypeError, ValueError):
            raise ImageError(f"squares, segments: expected (row, column, side) triples and (tile, start, length, "
                             f"twin) quadruples, got {self.squares!r:.60} and {self.segments!r:.60}") from None
        if not sq or any(r < 0 or c < 0 or n < 1 for r, c, n in sq) or _overlapping(sq, int(g)):
            raise ImageError(f"squares: expected (row, column, side) in quanta, sides positive, squares {g} quanta "
                             f"apart at least, got {self.squares!r:.80}")
        ok = len(segs) > 0 and all(0 <= k < len(sq) and n >= 1 for k, _, n, _ in segs)
        ok = ok and all(t == -1 or (0 <= t < len(segs) and t != i and segs[t][3] == i and segs[t][2] == n)
                        for i, (_, _, n, t) in enumerate(segs))
        if ok:
            for k, (_, _, side) in enumerate(sq):
                mine = [(a, n) for kk, a, n, _ in segs if kk == k]
                ok = ok and bool(mine) and mine[0][0] == 0 and sum(n for _, n in mine) == 4 * side and \
                    all(a + n == b for (a, n), (b, _) in zip(mine, mine[1:]))
            ok = ok and all(segs[i][0] <= segs[i + 1][0] for i in range(len(segs) - 1))
        if not ok:
            raise ImageError(f"segments: expected, square by square from square 0 (of {len(sq)}), consecutive "
                             "(tile, start, length, twin) segments from 0 around the 4 x side quanta of its "
                             "perimeter, twins of equal length naming each other")
        object.__setattr__(self, "squares", sq)
        object.__setattr__(self, "segments", segs)

    # ------------------------------------------------------------------ files
    @classmethod
    def _from_fields(cls, metadata: dict) -> ChartsDomain:
        return cls(orientation=metadata.get("orientation", 1),
                   squares=tuple(tuple(s) for s in metadata.get("squares", ((0, 0, 16),))),
                   gutter=metadata.get("gutter", 2), segments=tuple(tuple(s) for s in metadata.get("segments", ())))

    def to_metadata(self) -> dict:
        return {**super().to_metadata(), "squares": [list(s) for s in self.squares], "gutter": self.gutter,
                "segments": [list(s) for s in self.segments]}

    METADATA_KEYS: ClassVar[tuple] = Domain.METADATA_KEYS + ("squares", "gutter", "segments")

    def same_kind(self, other: Domain) -> bool:
        """Multi-chart images pair up pixel for pixel only when laid out alike.

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
        >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> d.same_kind(d), d.same_kind(ChartsDomain(squares=((0, 0, 4),), segments=((0, 0, 16, -1),)))
        (True, False)
        """
        return type(self) is type(other) and self.to_metadata() | {"orientation": 0} == \
            other.to_metadata() | {"orientation": 0}

    # ------------------------------------------------------------------ grid
    @property
    def sides(self) -> np.ndarray:
        """Each square's side in quanta.

        Examples
        --------
        >>> ChartsDomain(squares=((0, 0, 4), (0, 6, 2)), segments=((0, 0, 16, -1), (1, 0, 8, -1))).sides.tolist()
        [4, 2]
        """
        return np.array([n for _, _, n in self.squares], np.int64)

    def _span(self) -> tuple[int, int]:
        """Quanta across and down the layout."""
        return layout_span(self.squares)

    @property
    def extent(self) -> tuple:
        return layout_extent({"squares": self.squares})

    def _scale(self, shape) -> int:
        """Pixels per quantum of an image of ``shape``."""
        across, down = self._span()
        return (int(shape[1]) - 1) // across

    def check_shape(self, shape: tuple[int, int]) -> None:
        h, w = (int(x) for x in shape)
        across, down = self._span()
        m = (w - 1) // across
        if m < MIN_SCALE or (w - 1) % across or (h - 1) != m * down:
            eh, ew = self.grid_shape(self.round_resolution(max(h, w)))
            raise ImageError(f"pixels: {self.size_rule()} (e.g. {eh} x {ew}), got {h} x {w}")

    def grid_shape(self, resolution: int) -> tuple[int, int]:
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 2:
            raise ImageError(f"resolution: expected an integer >= 2, got {resolution!r}")
        across, down = self._span()
        big = max(across, down)
        if (int(resolution) - 1) % big or int(resolution) - 1 < MIN_SCALE * big:
            raise ImageError(f"resolution: {self.size_rule()}, got {resolution} (e.g. "
                             f"{self.round_resolution(int(resolution))})")
        m = (int(resolution) - 1) // big
        return m * down + 1, m * across + 1

    def round_resolution(self, resolution: int) -> int:
        big = max(self._span())
        return int(max(-(-(max(int(resolution), 2) - 1) // big), MIN_SCALE) * big + 1)

    def size_rule(self) -> str:
        across, down = self._span()
        return (f"a multi-chart image of {len(self.squares)} squares is (m {down} + 1) x (m {across} + 1) pixels "
                f"for a whole m >= {MIN_SCALE} (the charts' sides pair up pixel for pixel)")

    def _origins(self, shape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each square's first pixel (row, column) and its side in pixels."""
        m = self._scale(shape)
        sq = np.array(self.squares, np.int64)
        return m * sq[:, 0], m * sq[:, 1], m * sq[:, 2] + 1

    def tile_points(self, tile: np.ndarray, uv: np.ndarray) -> np.ndarray:
        """Points ``uv`` (K, 2) of the unit square of each ``tile`` (K,) in the image's parameter space.

        Parameters
        ----------
        tile : numpy.ndarray
            (K,) square indices.
        uv : numpy.ndarray
            (K, 2) points of the unit square.

        Returns
        -------
        numpy.ndarray
            (K, 2) parameter points.

        Examples
        --------
        >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> d.tile_points(np.array([1]), np.array([[0.0, 1.0]])).tolist()
        [[0.6, 0.4]]
        """
        return tile_points(tile, uv, self.squares)

    # ------------------------------------------------------------------ glue
    def _twin_pairs(self, scale: int):
        """``(tile, position)`` of every glued perimeter pixel and of its twin (both directions), positions in
        pixels along the square's perimeter, on an image of ``scale`` pixels per quantum.
        """
        return twin_positions(self.segments, scale)

    def _pixel_of(self, shape, tile: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Image (row, column) of perimeter positions (pixels) of squares."""
        r0, c0, n = self._origins(shape)
        row, col = perimeter_cells(position, n[tile])
        return r0[tile] + row, c0[tile] + col

    def _make_glue(self, shape):
        self.check_shape(shape)
        defects = weld_defects(self.segments, self.sides, self._scale(shape))
        if defects:
            raise ImageError(f"segments: at {shape[0]} x {shape[1]} pixels {defects} perimeter edges of the charts "
                             "would be glued wrongly (not a manifold quad mesh); take a larger image")
        H, W = shape
        tp, p, tq, q = self._twin_pairs(self._scale(shape))
        rp, cp = self._pixel_of(shape, tp, p)
        rq, cq = self._pixel_of(shape, tq, q)
        return glue_groups(H * W, rp * W + cp, rq * W + cq)

    # ------------------------------------------------------------------ the surface beyond a side
    def _tile_point(self, tile: int, t: list) -> np.ndarray:
        return self.tile_points(np.full(len(t), tile), perimeter_point(t, self.squares[tile][2]))

    def _pieces(self) -> list:
        """Straight pieces of the glued segments: ``(tile, ((p0, p1), (q0, q1)))``, the parameter points of a
        piece of the tile's perimeter and of its twin (``p0`` glued to ``q0``).
        """
        out = []
        for tile, start, length, t in self.segments:
            if t < 0:
                continue
            ttile, tstart = self.segments[t][0], self.segments[t][1]
            for o1, o2 in straight_pieces(start, length, tstart, self.squares[tile][2], self.squares[ttile][2]):
                out.append((tile, (self._tile_point(tile, [start + o1, start + o2]),
                                   self._tile_point(ttile, [tstart + length - o1, tstart + length - o2]))))
        return out

    def _rims(self) -> list:
        out: list = []
        for tile, start, length, t in self.segments:
            if t < 0:
                cuts = [start, *corners_within(start, length, self.squares[tile][2]), start + length]
                out.extend(self._tile_point(tile, [a, b]) for a, b in zip(cuts[:-1], cuts[1:]))
        return out

    def ghosts(self, centres: np.ndarray, reach: np.ndarray, size: np.ndarray | None = None) -> list:
        """Across each glued side, the faces near its twin (on another chart), turned and moved rigidly onto
        this side's outside, so the weighted mean at a chart's border sees the surface continue. A copy
        stays within half the gutter of its tile (its centre's distance plus a quarter of its reach, the
        face's own size for the weights that ask), so that nothing of one chart reaches the next tile.

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
        >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> [len(k) for k, R, b in d.ghosts(d.tile_points(np.array([1]), np.array([[0.5, 0.02]])), np.full(1, 0.05))]
        [1]
        """
        c = np.asarray(centres, np.float64)
        reach = np.asarray(reach, np.float64)
        half = 0.5 * self.gutter / max(self._span())
        pieces = self._pieces()
        out: list = []
        for tile in sorted({k for k, _ in pieces}):
            lo, hi = self.tile_points(np.array([tile, tile]), np.array([[0.0, 0.0], [1.0, 1.0]]))
            for idx, R, b in ghost_copies(c, np.minimum(reach, half), [x for k, x in pieces if k == tile],
                                          self._rims(), size):
                moved = c[idx] @ R.T + b
                beyond = np.maximum(np.maximum(lo - moved, moved - hi), 0.0).max(axis=1)
                keep = beyond + 0.25 * reach[idx] <= half
                if keep.any():
                    out.append((idx[keep], R, b))
        return out

    # ------------------------------------------------------------------ filters and normals
    def pad(self, array: np.ndarray, width: int) -> np.ndarray:
        """Reflected at the image's edges; beyond each glued side, the pixels inward of its twin, as far as
        half the gutter (or ``width`` at the image's edge), so that a filter sees the surface continue
        across charts.

        Parameters
        ----------
        array : numpy.ndarray
            (H, W) or (H, W, C).
        width : int
            Pixels added on each side.

        Returns
        -------
        numpy.ndarray
            The padded array.

        Examples
        --------
        >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> d.pad(np.zeros((9, 21, 3)), 2).shape
        (13, 25, 3)
        """
        a = np.asarray(array)
        self.check_shape(a.shape[:2])
        out = filters.pad(a, width, "reflect")
        if width == 0:
            return out
        H, W = a.shape[:2]
        n = self._origins(a.shape[:2])[2]
        tp, p, tq, q = self._twin_pairs(self._scale(a.shape[:2]))
        keep = (p % (n[tp] - 1) != 0) & (q % (n[tq] - 1) != 0)       # corners have two sides: left as they are
        tp, p, tq, q = tp[keep], p[keep], tq[keep], q[keep]
        rp, cp = self._pixel_of(a.shape[:2], tp, p)
        rq, cq = self._pixel_of(a.shape[:2], tq, q)
        side_p, side_q = perimeter_sides(p, n[tp]), perimeter_sides(q, n[tq])
        gutter_px = self._scale(a.shape[:2]) * self.gutter - 1
        edge = np.choose(side_p, [rp == 0, cp == W - 1, rp == H - 1, cp == 0])
        steps = np.where(edge, width, min(width, gutter_px // 2))
        copy_across(out, a, (rp, cp, side_p), (rq, cq, side_q), steps, width)
        return out

    def estimate_normals(self, pixels: np.ndarray) -> np.ndarray | None:
        """Normals from each square's own grid (never across the gutter; zero there).

        Parameters
        ----------
        pixels : numpy.ndarray
            (H, W, 3) positions.

        Returns
        -------
        numpy.ndarray
            (H, W, 3) unit normals.

        Examples
        --------
        >>> d = ChartsDomain(squares=((0, 0, 4), (0, 6, 4)), segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> u, v = np.meshgrid(np.arange(21.0), np.arange(9.0))
        >>> d.estimate_normals(np.dstack([u, v, 0 * u]))[4, 4].tolist()
        [0.0, 0.0, 1.0]
        """
        p = np.asarray(pixels, np.float64)
        out = np.zeros(p.shape[:2] + (3,))
        r0, c0, n = self._origins(p.shape[:2])
        for r, c, k in zip(r0.tolist(), c0.tolist(), n.tolist()):
            out[r:r + k, c:c + k] = grid_normals(p[r:r + k, c:c + k], self.orientation)
        return out
