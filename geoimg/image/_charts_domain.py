"""The multi-chart domain: square charts packed in one image, their sides glued to each other's by index."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

import filters
from ..errors import ImageError
from ..parametrization import perimeter_point, twin_positions
from ..parametrization._charts import MIN_SCALE, layout_extent, layout_span, tile_points, weld_defects

from ._domain import Domain, grid_normals
from ._perimeter import (copy_across, corners_within, ghost_copies, glue_groups, perimeter_pixels, perimeter_sides,
                         straight_pieces)

__all__ = ["ChartsDomain"]


@dataclass(frozen=True)
class ChartsDomain(Domain):
    """Square charts on a grid of ``columns x rows`` tiles, ``gutter`` quanta apart, each chart's perimeter
    glued to its neighbours' (Sander et al. 2003, "Multi-chart geometry images", with charts as squares
    whose sides match sample for sample, as Carr et al. 2006 lay them out): the image of a surface of any
    genus cut into discs (see :mod:`geoimg.parametrization._charts`).

    Each tile's perimeter is ``4 * quantum`` quanta, counter-clockwise from its pixel (0, 0) along its first
    row, split into ``segments``: ``(tile, start, length, twin)``, ``twin`` the index of the segment glued to
    it in reverse (on another tile, or -1: the mesh's own boundary). On an image whose ``N - 1`` is a multiple
    ``m`` of the layout's span (``columns * (quantum + gutter) - gutter`` quanta across, the same with
    ``rows`` down), a tile is ``m * quantum + 1`` pixels a side and every pixel on a glued side has an exact
    twin: twins are welded in the quad mesh (watertight across charts), averaged after filters, and
    filters read across a side the pixels inward of its twin, as far as half the gutter. Pixels of the
    gutter belong to no chart and are never valid.

    Parameters
    ----------
    orientation : int
        +1 or -1: the winding of the quad mesh's faces (see :class:`Domain`).
    quantum : int
        Quanta per side of a tile.
    columns, rows : int
        The grid of tiles; tile ``k`` is in row ``k // columns``, column ``k % columns``.
    gutter : int
        Quanta between neighbouring tiles.
    segments : tuple
        ``(tile, start, length, twin)`` per perimeter segment, in quanta.

    Examples
    --------
    >>> d = ChartsDomain(quantum=4, columns=2, rows=1, gutter=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
    >>> d.grid_shape(21), d.extent           # 2 tiles of 4 quanta, 2 between: 10 quanta across, 2 pixels each
    ((9, 21), (1.0, 0.4))
    >>> reps, group = d.glue((9, 21))
    >>> int(group[0]) == int(group[12]), int(group[1]) == int(group[33])   # tile 0's (0, 0), (0, 1): 1's (0, 0), (1, 0)
    (True, True)
    """

    quantum: int = 16
    columns: int = 1
    rows: int = 1
    gutter: int = 2
    segments: tuple = ()

    kind: ClassVar[str] = "charts"
    boundary: ClassVar[str | None] = None        # the domain pads itself, tile by tile (pad)
    coverage_only: ClassVar[bool] = True

    def __post_init__(self):
        super().__post_init__()
        for name in ("quantum", "columns", "rows"):
            x = getattr(self, name)
            if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or x < 1:
                raise ImageError(f"{name}: expected a positive integer, got {x!r}")
            object.__setattr__(self, name, int(x))
        g = self.gutter
        if isinstance(g, bool) or not isinstance(g, (int, np.integer)) or g < 1:
            raise ImageError(f"gutter: expected a positive integer (quanta between tiles), got {g!r}")
        object.__setattr__(self, "gutter", int(g))
        try:
            segs = tuple((int(k), int(a), int(n), int(t)) for k, a, n, t in self.segments)
        except (TypeError, ValueError):
            raise ImageError(f"segments: expected (tile, start, length, twin) quadruples, got "
                             f"{self.segments!r:.80}") from None
        tiles = self.columns * self.rows
        total = 4 * self.quantum
        ok = len(segs) > 0 and all(0 <= k < tiles and n >= 1 for k, _, n, _ in segs)
        ok = ok and all(t == -1 or (0 <= t < len(segs) and t != i and segs[t][3] == i and segs[t][2] == n)
                        for i, (_, _, n, t) in enumerate(segs))
        if ok:
            for k in range(tiles):
                mine = [(a, n) for kk, a, n, _ in segs if kk == k]
                ok = ok and (not mine or (mine[0][0] == 0 and sum(n for _, n in mine) == total and
                                          all(a + n == b for (a, n), (b, _) in zip(mine, mine[1:]))))
            used = sorted({k for k, _, _, _ in segs})
            ok = ok and used == list(range(len(used))) and \
                all(segs[i][0] <= segs[i + 1][0] for i in range(len(segs) - 1))
        if not ok:
            raise ImageError(f"segments: expected, tile by tile from tile 0 (of {tiles}), consecutive "
                             f"(tile, start, length, twin) segments from 0 around the {total} quanta of its "
                             "perimeter, twins of equal length on other tiles naming each other")
        object.__setattr__(self, "segments", segs)

    # ------------------------------------------------------------------ files
    @classmethod
    def _from_fields(cls, metadata: dict) -> ChartsDomain:
        return cls(orientation=metadata.get("orientation", 1), quantum=metadata.get("quantum", 16),
                   columns=metadata.get("columns", 1), rows=metadata.get("rows", 1),
                   gutter=metadata.get("gutter", 2), segments=tuple(tuple(s) for s in metadata.get("segments", ())))

    def to_metadata(self) -> dict:
        return {**super().to_metadata(), "quantum": self.quantum, "columns": self.columns, "rows": self.rows,
                "gutter": self.gutter, "segments": [list(s) for s in self.segments]}

    METADATA_KEYS: ClassVar[tuple] = Domain.METADATA_KEYS + ("quantum", "columns", "rows", "gutter", "segments")

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
        >>> d = ChartsDomain(quantum=4, columns=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> d.same_kind(d), d.same_kind(ChartsDomain(quantum=4, segments=((0, 0, 16, -1),)))
        (True, False)
        """
        return type(self) is type(other) and self.to_metadata() | {"orientation": 0} == \
            other.to_metadata() | {"orientation": 0}

    # ------------------------------------------------------------------ grid
    @property
    def tiles(self) -> int:
        """How many tiles the grid has (the charts use the first ones).

        Examples
        --------
        >>> ChartsDomain(quantum=4, columns=2, rows=2, segments=((0, 0, 16, -1),)).tiles
        4
        """
        return self.columns * self.rows

    def _span(self) -> tuple[int, int]:
        """Quanta across and down the layout."""
        return layout_span(self.quantum, self.columns, self.rows, self.gutter)

    @property
    def extent(self) -> tuple:
        return layout_extent({"quantum": self.quantum, "columns": self.columns, "rows": self.rows,
                              "gutter": self.gutter})

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
        return (f"a multi-chart image of {self.columns} x {self.rows} tiles is (m {down} + 1) x (m {across} + 1) "
                f"pixels for a whole m >= {MIN_SCALE} (the charts' sides pair up pixel for pixel)")

    def _origins(self, shape) -> tuple[np.ndarray, np.ndarray, int]:
        """Each tile's first pixel (row, column) and the tiles' side in pixels."""
        m = self._scale(shape)
        k = np.arange(self.tiles)
        pitch = m * (self.quantum + self.gutter)
        return (k // self.columns) * pitch, (k % self.columns) * pitch, m * self.quantum + 1

    def tile_points(self, tile: np.ndarray, uv: np.ndarray) -> np.ndarray:
        """Points ``uv`` (K, 2) of the unit square of each ``tile`` (K,) in the image's parameter space.

        Parameters
        ----------
        tile : numpy.ndarray
            (K,) tile indices.
        uv : numpy.ndarray
            (K, 2) points of the unit square.

        Returns
        -------
        numpy.ndarray
            (K, 2) parameter points.

        Examples
        --------
        >>> d = ChartsDomain(quantum=4, columns=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> d.tile_points(np.array([1]), np.array([[0.0, 1.0]])).tolist()
        [[0.6, 0.4]]
        """
        return tile_points(tile, uv, self.quantum, self.columns, self.rows, self.gutter)

    # ------------------------------------------------------------------ glue
    def _twin_pairs(self, n: int):
        """``(tile, position)`` of every glued perimeter pixel and of its twin (both directions), positions in
        pixels along the tile's perimeter.
        """
        return twin_positions(self.segments, (n - 1) // self.quantum)

    def _pixel_of(self, shape, tile: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Image (row, column) of perimeter positions (pixels) of tiles."""
        r0, c0, n = self._origins(shape)
        per = perimeter_pixels(n)[position]
        return r0[tile] + per // n, c0[tile] + per % n

    def _make_glue(self, shape):
        self.check_shape(shape)
        defects = weld_defects(self.segments, self.quantum, self.tiles, self._scale(shape))
        if defects:
            raise ImageError(f"segments: at {shape[0]} x {shape[1]} pixels {defects} perimeter edges of the charts "
                             "would be glued wrongly (not a manifold quad mesh); take a larger image")
        H, W = shape
        tp, p, tq, q = self._twin_pairs(self._origins(shape)[2])
        rp, cp = self._pixel_of(shape, tp, p)
        rq, cq = self._pixel_of(shape, tq, q)
        return glue_groups(H * W, rp * W + cp, rq * W + cq)

    # ------------------------------------------------------------------ the surface beyond a side
    def _tile_point(self, tile: int, t: list) -> np.ndarray:
        return self.tile_points(np.full(len(t), tile), perimeter_point(t, self.quantum))

    def _pieces(self) -> list:
        """Straight pieces of the glued segments: ``(tile, ((p0, p1), (q0, q1)))``, the parameter points of a
        piece of the tile's perimeter and of its twin (``p0`` glued to ``q0``).
        """
        out = []
        for tile, start, length, t in self.segments:
            if t < 0:
                continue
            ttile, tstart = self.segments[t][0], self.segments[t][1]
            for o1, o2 in straight_pieces(start, length, tstart, self.quantum):
                out.append((tile, (self._tile_point(tile, [start + o1, start + o2]),
                                   self._tile_point(ttile, [tstart + length - o1, tstart + length - o2]))))
        return out

    def _rims(self) -> list:
        out: list = []
        for tile, start, length, t in self.segments:
            if t < 0:
                cuts = [start, *corners_within(start, length, self.quantum), start + length]
                out.extend(self._tile_point(tile, [a, b]) for a, b in zip(cuts[:-1], cuts[1:]))
        return out

    def ghosts(self, centres: np.ndarray, reach: np.ndarray) -> list:
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

        Returns
        -------
        list
            ``(face indices, R, b)`` per copy.

        Examples
        --------
        >>> d = ChartsDomain(quantum=4, columns=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
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
                                          self._rims()):
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
        >>> d = ChartsDomain(quantum=4, columns=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
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
        tp, p, tq, q = self._twin_pairs(n)
        m = n - 1
        keep = (p % m != 0) & (q % m != 0)          # corners have two sides: left as they are
        tp, p, tq, q = tp[keep], p[keep], tq[keep], q[keep]
        rp, cp = self._pixel_of(a.shape[:2], tp, p)
        rq, cq = self._pixel_of(a.shape[:2], tq, q)
        side_p, side_q = perimeter_sides(p, n), perimeter_sides(q, n)
        gutter_px = self._scale(a.shape[:2]) * self.gutter - 1
        edge = np.choose(side_p, [rp == 0, cp == W - 1, rp == H - 1, cp == 0])
        steps = np.where(edge, width, min(width, gutter_px // 2))
        copy_across(out, a, (rp, cp, side_p), (rq, cq, side_q), steps, width)
        return out

    def estimate_normals(self, pixels: np.ndarray) -> np.ndarray | None:
        """Normals from each tile's own grid (never across the gutter; zero there).

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
        >>> d = ChartsDomain(quantum=4, columns=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
        >>> u, v = np.meshgrid(np.arange(21.0), np.arange(9.0))
        >>> d.estimate_normals(np.dstack([u, v, 0 * u]))[4, 4].tolist()
        [0.0, 0.0, 1.0]
        """
        p = np.asarray(pixels, np.float64)
        out = np.zeros(p.shape[:2] + (3,))
        r0, c0, n = self._origins(p.shape[:2])
        for r, c in zip(r0.tolist(), c0.tolist()):
            out[r:r + n, c:c + n] = grid_normals(p[r:r + n, c:c + n], self.orientation)
        return out
