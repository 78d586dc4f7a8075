"""Multi-chart parametrization (after Sander, Wood, Gortler, Snyder & Hoppe 2003, "Multi-chart geometry
images"; charts laid out as squares whose sides match sample for sample, as in Carr, Hoberock, Crane & Hart
2006): a manifold mesh of any genus is split into topological discs, and each disc is mapped one to one onto
a square of its own. One chart for a surface of high genus starves most of it (a CAD part of genus 24 cut
open gives 83 % of its area less than a quarter of its fair share of the square); charts of about equal
area, each a disc, do not.

1. **Charts** grow from seeds over the faces' dual graph, each face joining the seed nearest to it. The
   seeds start farthest apart and move to their charts' centres (:data:`LLOYD_ROUNDS`). A chart that is
   not a disc (it goes round a handle or a hole) is cut open along the edges of libigl's cut graph inside
   it and the charts grow again; one with no such edge left gets a second seed at its face farthest from
   the first. (Growing on the surface alone, with no cut, split the ring gear ``fixed_top.ply`` into 112 to
   232 charts before all were discs; growing on the whole cut-open disc made every chart's border a comb of
   slits.)
2. **Borders and squares**: each chart's boundary loop is split into segments where the chart beyond it
   changes (or the mesh's own boundary begins or ends); a chart with more than :data:`MAX_SEGMENTS`
   (slits of the cut inside it) gets a second seed in step 1. Each chart's square gets a whole number of
   quanta a side, near its share of the surface (``sqrt(area)``, in a unit that packs the squares into
   about :data:`LAYOUT_QUANTA` quanta), and every segment a whole number of quanta of that square's
   perimeter, a border's two sides the same number, every square's segments summing to four sides: a
   small integer program (``scipy.optimize.milp``) kept near each segment's share of its chart's
   boundary. The squares are packed on shelves (:func:`pack_squares`). Within a segment vertices follow
   their arc length, so a border's two sides have the same positions in reverse, and on an image of ``m``
   pixels per quantum every pixel on one side has an exact twin on the other (see
   :class:`geoimg.image.ChartsDomain`). (Squares all of one size starved the large charts where small ones
   were many: trimesh's ``ADIS16480.STL``, genus 24, 42.1 dB at 393^2 against 49.8 dB at 257 x 253.)
3. **Each chart** is mapped onto its square as a cut-open disc is (:func:`._disk.planar_interior`, its
   boundary held): chords split, a vertex at each corner, the interior relaxed by area balancing.
"""
from __future__ import annotations

from collections.abc import Sequence

import igl
import numpy as np
from scipy.sparse import coo_matrix, hstack, identity
from scipy.sparse.csgraph import dijkstra

from .._choices import DEFAULT_DISK_BALANCE, DISK_BALANCES
from .._types import Progress
from ..errors import ParametrizationError
from ..mesh import Mesh, boundary_loops, topology
from ._cut import _closed_for_map, _split_at_corners, _split_chords, cut_along, edge_keys
from ._layout import MIN_SCALE, layout_span, perimeter_point, tile_points, weld_defects
from ._disk import planar_interior
from ._laplacian import planar_cross, starved_share, triangle_areas

__all__ = ["chart_coords", "pack_squares", "segment_charts", "CHART_GUTTER", "DEFAULT_CHARTS"]

LAYOUT_QUANTA = 64        # the layout's longer side, in quanta, that the squares' sizes aim at
CHART_GUTTER = 2          # quanta between neighbouring squares (filters read across a border half as far)
MIN_SIDE = 2              # quanta per side of the smallest square
DEFAULT_CHARTS = 8        # charts to start from; more where one is not a disc
MAX_CHARTS = 256
MIN_CHART_FACES = 8       # charts to start from at most one per this many faces (a chart of one triangle
                          # onto a square leaves part of it uncovered: trimesh's L.off as 4 charts, 14 % off)
MAX_SEGMENTS = 64         # a chart whose border has more segments (slits cut inside it) gets a second seed
LLOYD_ROUNDS = 3          # seeds moved to their charts' centres this many times
SIZE_WEIGHT = 8.0         # cost of a quantum of a square's side off its area's share (a segment's: 1)


def _shelves(order: list, sides: list, gutter: int, width: int) -> tuple[dict, int, int]:
    """Squares (largest first) on shelves no wider than ``width``: each shelf as tall as its first square,
    its squares in columns, a column as wide as its first and filled downwards while they fit.
    """
    place: dict = {}
    top = across = 0
    i = 0
    while i < len(order):
        height = sides[order[i]]
        left = 0
        while i < len(order) and (left == 0 or left + sides[order[i]] <= width):
            col_w, y = sides[order[i]], top
            while i < len(order) and y + sides[order[i]] <= top + height:
                place[order[i]] = (y, left)
                y += sides[order[i]] + gutter
                i += 1
            across = max(across, left + col_w)
            left += col_w + gutter
        top += height + gutter
    return place, across, top - gutter


def pack_squares(sides: Sequence, gutter: int, span: int | None = None) -> list:
    """Squares of ``sides`` (quanta) on shelves, ``gutter`` apart, the layout's longer side as short as the
    shelves allow: ``(row, column, side)`` per square. With ``span``, a layout whose longer side is shorter
    is moved that much from the first row (or column), so that an image of ``m span + 1`` pixels fits it.

    Examples
    --------
    >>> pack_squares([4, 2, 2], 1)                 # 5 x 7 quanta: the two small ones on a shelf of their own
    [(0, 0, 4), (5, 0, 2), (5, 3, 2)]
    >>> pack_squares([3, 1, 1], 1, span=10)        # 3 x 5 quanta, moved 5 down
    [(5, 0, 3), (9, 0, 1), (9, 2, 1)]
    """
    sides = [int(x) for x in sides]
    order = sorted(range(len(sides)), key=lambda k: (-sides[k], k))
    best = None
    total = sum(sides) + gutter * (len(sides) - 1)
    for width in sorted(set(np.linspace(max(sides), total, 200).astype(int).tolist()) | {total}):
        place, across, down = _shelves(order, sides, gutter, width)
        key = (max(across, down), across * down)
        if best is None or key < best[0]:
            best = (key, place)
    assert best is not None
    out = [(best[1][k][0], best[1][k][1], sides[k]) for k in range(len(sides))]
    return out if span is None else _to_span(out, span)


def _to_span(squares: list, span: int) -> list:
    """``squares`` moved from the first row (or column) so that the layout's longer side is ``span``, if
    shorter.
    """
    across, down = layout_span(squares)
    if max(across, down) >= span:
        return squares
    dr, dc = (span - down, 0) if down >= across else (0, span - across)
    return [(r + dr, c + dc, n) for r, c, n in squares]


def _dual_graph(vertices: np.ndarray, tris: np.ndarray):
    """The faces' adjacency (a symmetric sparse matrix of the distances between their centres), the pairs of
    faces across each interior edge and the edge's key (``min * n + max`` of its vertices).
    """
    F = len(tris)
    n = len(vertices)
    e = np.stack([tris, np.roll(tris, -1, axis=1)], axis=2).reshape(-1, 2)
    key = np.minimum(e[:, 0], e[:, 1]) * n + np.maximum(e[:, 0], e[:, 1])
    face = np.repeat(np.arange(F), 3)
    order = np.argsort(key, kind="stable")
    ks, fs = key[order], face[order]
    same = ks[1:] == ks[:-1]
    fa, fb = fs[:-1][same], fs[1:][same]
    centre = vertices[tris].mean(axis=1)
    w = np.linalg.norm(centre[fa] - centre[fb], axis=1)
    w = np.maximum(w, 1e-12 * max(float(w.max(initial=0.0)), 1e-300))      # dijkstra drops zero weights
    graph = coo_matrix((np.concatenate([w, w]), (np.concatenate([fa, fb]), np.concatenate([fb, fa]))),
                       shape=(F, F)).tocsr()
    return graph, fa, fb, ks[:-1][same]


def _without(graph, fa: np.ndarray, fb: np.ndarray, blocked: np.ndarray):
    """``graph`` with the dual edges ``blocked`` (booleans over ``fa, fb``) removed."""
    if not blocked.any():
        return graph
    g = graph.tolil(copy=True)
    g[fa[blocked], fb[blocked]] = 0
    g[fb[blocked], fa[blocked]] = 0
    out = g.tocsr()
    out.eliminate_zeros()
    return out


def _grow(graph, seeds: list) -> tuple[np.ndarray, np.ndarray]:
    """Each face's chart (the index of its nearest seed) and its distance to that seed."""
    dist, _, source = dijkstra(graph, indices=np.asarray(seeds), min_only=True, return_predecessors=True)
    if not np.isfinite(dist).all():
        raise ParametrizationError("method='charts': the mesh's faces are not all joined across edges (several "
                                   "pieces); geoimg.mesh.repair splits them")
    return np.searchsorted(np.sort(seeds), source), dist


def _centres(graph, label: np.ndarray, fa: np.ndarray, fb: np.ndarray, k: int) -> list:
    """Each chart's face farthest from its border (the next seeds)."""
    inside = label[fa] == label[fb]
    border = np.unique(np.concatenate([fa[~inside], fb[~inside]]))
    if not len(border):
        return []
    g = graph.tocoo()
    keep = label[g.row] == label[g.col]
    sub = coo_matrix((g.data[keep], (g.row[keep], g.col[keep])), shape=g.shape).tocsr()
    dist = dijkstra(sub, indices=border, min_only=True)
    dist = np.where(np.isfinite(dist), dist, -1.0)
    seeds = []
    for c in range(k):
        faces = np.flatnonzero(label == c)
        seeds.append(int(faces[np.argmax(dist[faces])]))
    return seeds


def _is_disc(tris: np.ndarray) -> bool:
    t = topology(Mesh(np.zeros((int(tris.max()) + 1, 3)), tris))
    return t.components == 1 and t.boundary_loops == 1 and t.genus == 0 and t.nonmanifold_vertices == 0 \
        and t.nonmanifold_edges == 0


def _cut_at(vertices: np.ndarray, tris: np.ndarray, keys: set):
    """The triangles cut open along the edges ``keys`` (vertices copied along them) and each vertex's source."""
    if not keys:
        return vertices, tris, np.arange(len(vertices))
    return cut_along(vertices, tris, keys)


def segment_charts(vertices: np.ndarray, tris: np.ndarray, charts: int = DEFAULT_CHARTS,
                   cut: set | None = None, max_segments: int | None = None) -> tuple[np.ndarray, int, set]:
    """Split the triangles into charts that are each a topological disc (see the module's step 1).

    ``cut``: keys (``min * n + max``) of edges that may be cut open where a chart is not a disc (a cut graph
    that makes the whole surface a disc, so that cutting always ends with discs). A chart that is not a
    disc is cut along those of its edges first; only one with none left gets a second seed.
    ``max_segments``: a disc whose boundary has more segments than this (borders with other charts and the
    sides of slits cut inside it) also gets a second seed, while charts may be added.

    Returns
    -------
    label : (F,) int64
        Each triangle's chart.
    splits : int
        Charts added because one was not a disc.
    opened : set
        The keys of the ``cut`` edges cut open.

    Examples
    --------
    >>> import geoimg
    >>> from geoimg.mesh import topology
    >>> t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> T, P = np.meshgrid(t, t)
    >>> v = np.stack([(2 + np.cos(P)) * np.cos(T), (2 + np.cos(P)) * np.sin(T), np.sin(P)], -1).reshape(-1, 3)
    >>> i = np.arange(144).reshape(12, 12)
    >>> a, b, c, d = i, np.roll(i, -1, 1), np.roll(np.roll(i, -1, 0), -1, 1), np.roll(i, -1, 0)
    >>> tris = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    >>> label, splits, opened = segment_charts(v, tris, 4)
    >>> tops = [topology(geoimg.Mesh(v, tris[label == k])) for k in range(label.max() + 1)]
    >>> all(t.boundary_loops == 1 and t.genus == 0 for t in tops), len(tops) >= 4, opened
    (True, True, set())
    """
    graph, fa, fb, keys = _dual_graph(vertices, tris)
    F = len(tris)
    k = max(1, min(int(charts), F // MIN_CHART_FACES))
    seeds = [0]
    dist = dijkstra(graph, indices=0)
    while len(seeds) < k:                      # farthest-point seeds
        seeds.append(int(np.argmax(np.where(np.isfinite(dist), dist, -1.0))))
        dist = np.minimum(dist, dijkstra(graph, indices=seeds[-1]))
    seeds = sorted(set(seeds))
    for _ in range(LLOYD_ROUNDS):
        label, _ = _grow(graph, seeds)
        moved = sorted(set(_centres(graph, label, fa, fb, len(seeds))))
        if not moved or moved == seeds:
            break
        seeds = moved
    cuttable = np.isin(keys, np.array(sorted(cut or ()), np.int64))
    splits = 0
    blocked = np.zeros(len(fa), bool)          # dual edges across the cut edges opened so far
    cut_tris = tris
    while True:
        label, dist = _grow(_without(graph, fa, fb, blocked), seeds)
        bad = [c for c in range(len(seeds)) if not _is_disc(cut_tris[label == c])]
        if not bad and max_segments is not None:
            bad = [c for c, n in enumerate(_segment_counts(vertices, tris, label, set(keys[blocked].tolist())))
                   if n > max_segments]
            if len(seeds) + len(bad) > min(MAX_CHARTS, F):
                bad = []
        if not bad:
            return label.astype(np.int64), splits, set(keys[blocked].tolist())
        inside = np.isin(label[fa], bad) & (label[fa] == label[fb]) & cuttable & ~blocked
        if inside.any():                       # open the cut inside the charts that are not discs
            blocked |= inside
            cut_tris = _cut_at(vertices, tris, set(keys[blocked].tolist()))[1]
            continue
        if len(seeds) + len(bad) > min(MAX_CHARTS, F):
            raise ParametrizationError(f"method='charts': {len(bad)} of {len(seeds)} charts are still not discs; "
                                       f"more than {MAX_CHARTS} charts would be needed")
        for c in bad:
            faces = np.flatnonzero(label == c)
            seeds.append(int(faces[np.argmax(dist[faces])]))
        seeds = sorted(set(seeds))
        splits += len(bad)


def _segment_counts(vertices: np.ndarray, tris: np.ndarray, label: np.ndarray, opened: set) -> list:
    """How many border segments each chart's boundary has (see :func:`_borders`)."""
    v, t, source = _cut_at(vertices, tris, opened)
    return [len(s) for s in _borders(_chart_loops(v, t, label), source)]


def _chart_loops(vertices: np.ndarray, tris: np.ndarray, label: np.ndarray) -> list:
    """Each chart's triangles in its own numbering, its vertices' input indices and its boundary loop."""
    out = []
    for c in range(int(label.max()) + 1):
        t = tris[label == c]
        used, local = np.unique(t, return_inverse=True)
        local = local.reshape(t.shape)
        loops = boundary_loops(Mesh(vertices[used], local))
        out.append((used, local, loops[0]))
    return out


def _borders(charts: list, source: np.ndarray) -> list:
    """Per chart: its boundary loop's segments as ``(first edge, edges, twin (chart, segment) or None)``; an
    edge's twin is the other chart edge on the same input edge (``source``: each vertex's input vertex).
    """
    edges = []                        # per chart, its loop's edges as input vertex pairs
    owner: dict = {}
    for c, (used, _, loop) in enumerate(charts):
        a, b = source[used[loop]], source[used[np.roll(loop, -1)]]
        edges.append(list(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist())))
        for i, key in enumerate(edges[c]):
            owner.setdefault(key, []).append((c, i))
    partner = []
    for c in range(len(charts)):
        mine = []
        for i, key in enumerate(edges[c]):
            other = [x for x in owner[key] if x != (c, i)]
            mine.append(other[0] if other else (-1, -1))
        partner.append(mine)
    starts: list = []
    for c, (_, _, loop) in enumerate(charts):
        n = len(loop)
        s = []
        for i in range(n):
            (ci, ji), (cj, jj) = partner[c][i], partner[c][i - 1]
            tip = (ci, ji) == (c, (i - 1) % n)        # the end of a slit: its two sides meet here
            if tip or ci != cj or (ci >= 0 and ji != (jj - 1) % len(charts[ci][2])):
                s.append(i)
        starts.append(s)
    for c, (used, _, loop) in enumerate(charts):        # a loop that is one run: start where its twin does
        if starts[c]:
            continue
        d = partner[c][0][0]
        if d >= 0 and d < c:
            first_vertex = source[charts[d][0][charts[d][2][starts[d][0]]]]
            starts[c] = [int(np.flatnonzero(source[used[loop]] == first_vertex)[0])]
        else:
            starts[c] = [0]
    segments = []
    where: dict = {}
    for c, (_, _, loop) in enumerate(charts):
        n = len(loop)
        s = starts[c]
        segs = []
        for k, a in enumerate(s):
            b = s[(k + 1) % len(s)] if len(s) > 1 else a + n
            length = (b - a) % n or n
            segs.append((a, length))
            for i in range(length):
                where[(c, (a + i) % n)] = (c, k)
        segments.append(segs)
    out = []
    for c, segs in enumerate(segments):
        out.append([(a, length, where[partner[c][a]] if partner[c][a][0] >= 0 else None) for a, length in segs])
    return out


def _solve_quanta(targets: np.ndarray, unit_of: list, fewest: np.ndarray, least: np.ndarray, wanted: np.ndarray):
    """Whole quanta per unit (at least ``fewest``) and per square's side (at least ``least``), each square's segments
    summing to four times its side, near ``targets`` and ``wanted`` (``scipy.optimize.milp``).
    """
    from scipy.optimize import Bounds, LinearConstraint, milp    # here: other maps start without scipy.optimize

    u, k = len(targets), len(unit_of)
    rows = [c for c, units in enumerate(unit_of) for _ in units]
    A = coo_matrix((np.ones(len(rows)), (rows, [x for units in unit_of for x in units])), shape=(k, u))
    eu, ek = identity(u), identity(k)
    zuk, zku = coo_matrix((u, k)), coo_matrix((k, u))
    constraints = [LinearConstraint(hstack([A, -4 * ek, zku, coo_matrix((k, k))]).tocsr(), 0, 0),
                   LinearConstraint(hstack([eu, zuk, -eu, zuk]).tocsr(), -np.inf, targets),
                   LinearConstraint(hstack([-eu, zuk, -eu, zuk]).tocsr(), -np.inf, -targets),
                   LinearConstraint(hstack([zku, ek, zku, -ek]).tocsr(), -np.inf, wanted),
                   LinearConstraint(hstack([zku, -ek, zku, -ek]).tocsr(), -np.inf, -wanted)]
    res = milp(np.concatenate([np.zeros(u + k), np.ones(u), np.full(k, SIZE_WEIGHT)]), constraints=constraints,
               integrality=np.concatenate([np.ones(u + k), np.zeros(u + k)]),
               bounds=Bounds(np.concatenate([fewest, least, np.zeros(u + k)]), np.full(2 * (u + k), np.inf)))
    if res.x is None:
        raise ParametrizationError("method='charts': the charts' borders cannot be laid out on their squares "
                                   f"(no whole numbers of quanta fit: {res.message})")
    return np.round(res.x[:u]).astype(int), np.round(res.x[u:u + k]).astype(int)


def _quantize(lengths: list, borders: list, areas: np.ndarray, closed: list) -> tuple[list, list, list]:
    """Whole numbers of quanta per side of each chart's square and per segment of its border (at least 1, or
    2 where its two ends are one vertex (``closed``): on one quantum of two pixels its two edges would be one;
    a border's two sides equal; a square's segments summing to four sides), near each chart's share of the
    surface (its side ``sqrt(area)`` in a unit chosen so that the packed layout's longer side is about
    :data:`LAYOUT_QUANTA` quanta) and each segment's share of its chart's boundary: a small integer program
    (``scipy.optimize.milp``).
    """
    unit: dict = {}                  # a border's two sides, or a rim segment -> its unknown
    unit_of: list = []               # per chart, each segment's unknown
    shares: list = []                # per unknown, its sides' (chart, share of the chart's boundary)
    loops: dict = {}
    for c, segs in enumerate(borders):
        unit_of.append([])
        perimeter = max(float(sum(lengths[c])), 1e-300)
        for s, (_, _, twin) in enumerate(segs):
            key = (c, s) if twin is None or twin > (c, s) else twin
            if key not in unit:
                unit[key] = len(shares)
                shares.append([])
            shares[unit[key]].append((c, lengths[c][s] / perimeter))
            loops[unit[key]] = loops.get(unit[key], False) or closed[c][s]
            unit_of[c].append(unit[key])
    least = np.array([max(MIN_SIDE, -(-len(segs) // 4)) for segs in borders], float)
    fewest = np.array([2.0 if loops[k] else 1.0 for k in range(len(shares))])
    root = np.sqrt(np.maximum(np.asarray(areas, np.float64), 0.0))
    per_quantum = max(float(np.sqrt(np.sum(root ** 2))), 1e-300) / (0.8 * LAYOUT_QUANTA)
    best: tuple | None = None
    for _ in range(6):               # the unit that packs to at most LAYOUT_QUANTA on the longer side, nearly
        wanted = root / per_quantum
        targets = np.array([np.mean([4 * wanted[c] * share for c, share in sides_of]) for sides_of in shares])
        x, sides = _solve_quanta(targets, unit_of, fewest, least, wanted)
        squares = pack_squares(sides, CHART_GUTTER)
        big = max(layout_span(squares))
        key = (big > LAYOUT_QUANTA, abs(big - LAYOUT_QUANTA))        # within the longer side first
        if best is None or key < best[0]:
            best = (key, x, sides, squares)
        if 0.9 * LAYOUT_QUANTA <= big <= LAYOUT_QUANTA:
            break
        per_quantum *= big / (0.95 * LAYOUT_QUANTA)
    assert best is not None
    _, x, sides, squares = best
    return [[int(x[k]) for k in units] for units in unit_of], sides.tolist(), _to_span(squares, LAYOUT_QUANTA)


def _first_segment(segs: list, quanta: list, c: int, q: int) -> int:
    """The segment of chart ``c`` to lay out from the square's corner (0, 0): the first that puts no slit's
    tip (where a segment meets its own twin) on a corner of the square (its quad would fold onto itself).
    """
    start = np.concatenate([[0], np.cumsum(quanta)[:-1]])
    tips = [s for s, (_, _, twin) in enumerate(segs) if twin == (c, (s - 1) % len(segs))]
    if not tips:
        return 0
    worst = [int(np.sum((start[tips] - start[r]) % q == 0)) for r in range(len(segs))]
    return int(np.argmin(worst))


def chart_coords(mesh: Mesh, *, charts: int = DEFAULT_CHARTS, balance: str = DEFAULT_DISK_BALANCE,
                 progress: Progress | None = None) -> tuple:
    """Split a manifold, oriented, connected mesh into disc charts and map each onto a square of its own.

    Parameters
    ----------
    mesh : Mesh
        A manifold, oriented, connected mesh.
    charts : int
        Charts to start from (more are added where one is not a disc).
    balance : {"area", "slim", "none"}
        How each chart's map is relaxed.
    progress : callable or None
        Called with each chart's progress.

    Returns
    -------
    charted : Mesh
        Triangles, chart by chart; vertices on a border appear once per chart (copies of one position),
        chords split at midpoints.
    coords : (N, 2) float64
        (u, v) of every vertex on the grid of squares (:func:`tile_points`).
    source : tuple of (N, 2) int64 and (N,) float64
        The input edge ``(a, b)`` each vertex lies on and its weight ``w`` along it (``a == b`` for copies of
        input vertices).
    layout : dict
        The :class:`~geoimg.image.ChartsDomain`'s fields: ``squares`` (``[row, column, side]`` per chart, in
        quanta), ``gutter`` and ``segments`` (``[tile, start, length, twin]``).
    info : dict
        ``charts``, ``chart_splits`` (charts added because one was not a disc), ``chart_errors`` (each
        chart's resampling error), ``cracks_zipped``, ``holes_filled``, ``starved_share``, ``stages``.

    Raises
    ------
    ParametrizationError
        When ``balance`` or ``charts`` is not valid, or the charts cannot be laid out.

    Examples
    --------
    >>> import geoimg
    >>> t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> T, P = np.meshgrid(t, t)
    >>> v = np.stack([(2 + np.cos(P)) * np.cos(T), (2 + np.cos(P)) * np.sin(T), np.sin(P)], -1).reshape(-1, 3)
    >>> i = np.arange(144).reshape(12, 12)
    >>> a, b, c, d = i, np.roll(i, -1, 1), np.roll(np.roll(i, -1, 0), -1, 1), np.roll(i, -1, 0)
    >>> torus = geoimg.Mesh(v, np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3))
    >>> charted, uv, source, layout, info = chart_coords(torus, charts=4)
    >>> info["charts"] >= 4, len(layout["squares"]) == info["charts"]
    (True, True)
    """
    if balance not in DISK_BALANCES:
        raise ParametrizationError(f"balance: expected one of {DISK_BALANCES}, got {balance!r}")
    if isinstance(charts, bool) or not isinstance(charts, (int, np.integer)) or not 1 <= charts <= MAX_CHARTS:
        raise ParametrizationError(f"charts: expected a whole number from 1 to {MAX_CHARTS}, got {charts!r}")
    vertices, tris, used, zipped, filled, _ = _closed_for_map(mesh)
    cut = edge_keys(igl.cut_to_disk(np.ascontiguousarray(tris, np.int64)), len(vertices))
    label, splits, opened = segment_charts(vertices, tris, charts, cut, max_segments=MAX_SEGMENTS)
    vertices, tris, disc_source = _cut_at(vertices, tris, opened)
    pieces = _chart_loops(vertices, tris, label)
    borders = _borders(pieces, disc_source)
    lengths, closed = [], []
    for (ids, _, loop), segs in zip(pieces, borders):
        edge = np.linalg.norm(vertices[ids[np.roll(loop, -1)]] - vertices[ids[loop]], axis=1)
        lengths.append([float(edge[(a + np.arange(n)) % len(loop)].sum()) for a, n, _ in segs])
        ends = disc_source[ids[loop]]
        closed.append([bool(ends[a] == ends[(a + n) % len(loop)]) for a, n, _ in segs])
    areas = [float(triangle_areas(vertices[ids], f).sum()) for ids, f, _ in pieces]
    quanta, sides, squares = _quantize(lengths, borders, np.array(areas), closed)
    k = len(pieces)
    offsets = np.cumsum([0] + [len(s) for s in borders])
    first = [_first_segment(segs, quanta[c], c, sides[c]) for c, segs in enumerate(borders)]

    def index(c: int, s: int) -> int:
        """The global index of chart ``c``'s segment ``s``, its segments numbered from ``first[c]``."""
        return int(offsets[c] + (s - first[c]) % len(borders[c]))

    segments, out_v, out_f, out_uv, out_src, out_w, errors, starved = [], [], [], [], [], [], [], []
    base = 0
    for c, ((ids, f, loop), segs) in enumerate(zip(pieces, borders)):
        v = vertices[ids]
        n = len(loop)
        on_boundary = np.zeros(len(v), bool)
        on_boundary[loop] = True
        v, f, src, _ = _split_chords(v, f, np.arange(len(v)), on_boundary)
        weight = np.where(src[:, 0] == src[:, 1], 0.0, 0.5)
        edge = np.linalg.norm(v[loop[(np.arange(n) + 1) % n]] - v[loop], axis=1)
        t = np.empty(n)
        start = 0
        for s in np.roll(np.arange(len(segs)), -first[c]).tolist():
            a, length, twin = segs[s]
            span = max(lengths[c][s], 1e-300)
            run = (a + np.arange(length)) % n
            arc = np.concatenate([[0.0], np.cumsum(edge[run])[:-1]])
            t[run] = start + quanta[c][s] * arc / span
            segments.append([c, start, quanta[c][s], -1 if twin is None else index(*twin)])
            start += quanta[c][s]
        v, f, src, weight, loop, t, _ = _split_at_corners(v, f, src, weight, loop, t, sides[c])
        heard = None if progress is None else (lambda msg, c=c: progress(f"chart {c + 1} of {k}: {msg}"))
        uv, relaxed = planar_interior(v, f, loop, perimeter_point(t, sides[c]), balance, progress=heard)
        errors.append(float(relaxed["start_errors"][relaxed["start"]]))
        placed = tile_points(np.full(len(v), c), uv, squares)
        # the share of the image each triangle gets is its area in the layout (the squares differ in size)
        starved.append((triangle_areas(v, f), np.abs(planar_cross(placed, f))))
        out_v.append(v)
        out_f.append(f + base)
        out_uv.append(placed)
        out_src.append(ids[src])
        out_w.append(weight)
        base += len(v)
    share = starved_share(np.concatenate([x[0] for x in starved]), np.concatenate([x[1] for x in starved]))
    defects = [weld_defects(segments, sides, scale) for scale in (MIN_SCALE, MIN_SCALE + 1)]
    if any(defects):
        raise ParametrizationError(f"method='charts': the {k} charts' borders would not weld into a manifold mesh "
                                   f"({max(defects)} perimeter edges glued wrongly); try other charts= or "
                                   "method='cut'")
    layout = {"squares": [list(x) for x in squares], "gutter": CHART_GUTTER, "segments": segments}
    across, down = layout_span(squares)
    stages = [f"{k} charts, each a disc ({splits} added where one was not), on squares of {min(sides)} to "
              f"{max(sides)} quanta ({across} x {down} in all)" if k > 1 else
              f"1 chart, a disc, on a square of {sides[0]} quanta ({across} x {down} in all)"]
    if zipped or filled:
        stages.insert(0, f"zipped {zipped} cracks and filled {filled} small holes (the image spans them)")
    info = {"charts": k, "chart_splits": int(splits), "cut_edges_opened": len(opened), "chart_errors": errors,
            "cracks_zipped": zipped, "holes_filled": filled, "starved_share": share, "stages": stages}
    source = used[disc_source[np.concatenate(out_src)]]
    return (Mesh(np.vstack(out_v), np.vstack(out_f)), np.vstack(out_uv), (source, np.concatenate(out_w)), layout,
            info)
