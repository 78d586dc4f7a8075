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
2. **Borders**: each chart's boundary loop is split into segments where the chart beyond it changes (or
   the mesh's own boundary begins or ends). Every segment gets a whole number of quanta of its tile's
   perimeter (``4 Q``), a border's two sides the same number, every tile's segments summing to ``4 Q``: a
   small integer program (``scipy.optimize.milp``) kept near each segment's share of its chart's
   boundary length. Within a segment vertices follow their arc length, so a border's two sides have the
   same positions in reverse, and on an image of ``m`` pixels per quantum every pixel on one side has an
   exact twin on the other (see :class:`geoimg.image.ChartsDomain`).
3. **Each chart** is mapped onto its square as a cut-open disc is (:func:`._disk.planar_interior`, its
   boundary held): chords split, a vertex at each corner, the interior relaxed by area balancing.
"""
from __future__ import annotations

import igl
import numpy as np
from scipy.optimize import Bounds, LinearConstraint, milp
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra

from .._choices import DEFAULT_DISK_BALANCE, DISK_BALANCES
from .._types import Progress
from ..errors import ParametrizationError
from ..mesh import Mesh, boundary_loops, topology
from ._cut import (_closed_for_map, _split_at_corners, _split_chords, cut_along, edge_keys, perimeter_point,
                   twin_positions)
from ._disk import planar_interior
from ._laplacian import planar_cross, starved_share, triangle_areas

__all__ = ["chart_coords", "tile_points", "layout_extent", "layout_span", "segment_charts", "weld_defects", "MIN_SCALE",
           "CHART_QUANTUM", "CHART_GUTTER", "DEFAULT_CHARTS"]

CHART_QUANTUM = 16        # quanta per side of a chart's square
CHART_GUTTER = 2          # quanta between neighbouring squares (filters read across a border half as far)
DEFAULT_CHARTS = 8        # charts to start from; more where one is not a disc
MAX_CHARTS = 256
MIN_SCALE = 2             # pixels per quantum at least: a border of one quantum then has a pixel inside it
LLOYD_ROUNDS = 3          # seeds moved to their charts' centres this many times


def layout_span(quantum: int, columns: int, rows: int, gutter: int) -> tuple[int, int]:
    """Quanta across and down a grid of ``columns x rows`` squares of ``quantum`` quanta, ``gutter`` apart.

    Examples
    --------
    >>> layout_span(4, 2, 1, 2)
    (10, 4)
    """
    pitch = quantum + gutter
    return columns * pitch - gutter, rows * pitch - gutter


def tile_points(tile: np.ndarray, uv: np.ndarray, quantum: int, columns: int, rows: int, gutter: int) -> np.ndarray:
    """Points ``uv`` (K, 2) of the unit square of each ``tile`` (K,) on a grid of ``columns x rows`` squares of
    ``quantum`` quanta a side, ``gutter`` quanta apart, scaled so that the grid's longer side is 1.

    Parameters
    ----------
    tile : numpy.ndarray
        (K,) tile indices (row by row).
    uv : numpy.ndarray
        (K, 2) points of the unit square.
    quantum, columns, rows, gutter : int
        The grid's layout.

    Returns
    -------
    numpy.ndarray
        (K, 2) parameter points.

    Examples
    --------
    >>> tile_points(np.array([0, 1]), np.array([[0.0, 0.0], [1.0, 1.0]]), 4, 2, 1, 2).tolist()
    [[0.0, 0.0], [1.0, 0.4]]
    """
    tile = np.asarray(tile, np.int64)
    pitch = quantum + gutter
    big = max(layout_span(quantum, columns, rows, gutter))
    corner = np.stack([(tile % columns) * pitch, (tile // columns) * pitch], axis=1)
    return (corner + np.asarray(uv, np.float64) * quantum) / big


def layout_extent(layout: dict) -> tuple[float, float]:
    """The parameter rectangle of a grid of squares (``layout``: a :class:`~geoimg.image.ChartsDomain`'s
    fields), its longer side 1.

    Parameters
    ----------
    layout : dict
        ``quantum``, ``columns``, ``rows`` and ``gutter``.

    Returns
    -------
    tuple of float
        (width, height).

    Examples
    --------
    >>> layout_extent({"quantum": 4, "columns": 2, "rows": 1, "gutter": 2})
    (1.0, 0.4)
    """
    across, down = layout_span(layout["quantum"], layout["columns"], layout["rows"], layout["gutter"])
    big = max(across, down)
    return across / big, down / big


def weld_defects(segments: list | tuple, quantum: int, tiles: int, scale: int) -> int:
    """How many perimeter edges of a layout of square charts (``segments``: ``(tile, start, length, twin)`` in
    quanta) would not weld into a manifold quad mesh on an image of ``scale`` pixels per quantum: an edge whose
    two ends are glued into one vertex, more than two edges glued into one (a border of one quantum beside
    its own twin's neighbour at ``scale = 1``), or a square's corner whose two sides are glued there (the tip
    of a slit at a corner folds the corner's quad onto itself).

    Examples
    --------
    >>> weld_defects([(0, 0, 16, 1), (1, 0, 16, 0)], 4, 2, 1)         # two squares glued round their rims
    0
    >>> weld_defects([(0, 0, 8, 1), (0, 8, 8, 0)], 4, 1, 2)           # one square folded: tips at two corners
    2
    """
    per = 4 * quantum * scale
    tp, p, tq, q = twin_positions(segments, scale)
    n = tiles * per
    _, group = connected_components(coo_matrix((np.ones(len(p)), (tp * per + p % per, tq * per + q % per)),
                                               shape=(n, n)), directed=False)
    used = np.unique([s[0] for s in segments])
    i = (used[:, None] * per + np.arange(per)).ravel()
    j = (used[:, None] * per + (np.arange(per) + 1) % per).ravel()
    x, y = group[i], group[j]
    collapsed = int(np.sum(x == y))
    _, counts = np.unique(np.minimum(x, y)[x != y] * n + np.maximum(x, y)[x != y], return_counts=True)
    base, corner = used[:, None] * per, np.arange(0, per, quantum * scale)     # a slit's tip at a corner folds
    folded = int(np.sum(group[base + (corner - 1) % per] == group[base + (corner + 1) % per]))   # its quad
    return collapsed + int(np.sum(counts[counts > 2])) + folded


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
                   cut: set | None = None) -> tuple[np.ndarray, int, set]:
    """Split the triangles into charts that are each a topological disc (see the module's step 1).

    ``cut``: keys (``min * n + max``) of edges that may be cut open where a chart is not a disc (a cut graph
    that makes the whole surface a disc, so that cutting always ends with discs). A chart that is not a
    disc is cut along those of its edges first; only one with none left gets a second seed.

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
    k = max(1, min(int(charts), F))
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


def _quantize(lengths: list, borders: list, quanta: int) -> list:
    """Whole numbers of quanta per segment, at least 1, a border's two sides equal, each chart's summing to
    ``quanta``, near each segment's share of its chart's boundary length (``scipy.optimize.milp``).
    """
    unit: dict = {}                  # a border's two sides, or a rim segment -> its unknown
    unit_of: list = []               # per chart, each segment's unknown
    targets: list = []
    for c, segs in enumerate(borders):
        perimeter = max(float(sum(lengths[c])), 1e-300)
        unit_of.append([])
        for s, (_, _, twin) in enumerate(segs):
            key = (c, s) if twin is None or twin > (c, s) else twin
            if key not in unit:
                unit[key] = len(targets)
                targets.append([])
            targets[unit[key]].append(lengths[c][s] / perimeter * quanta)
            unit_of[c].append(unit[key])
    u = len(targets)
    t = np.array([np.mean(x) for x in targets])
    rows = [c for c, units in enumerate(unit_of) for _ in units]
    A = coo_matrix((np.ones(len(rows)), (rows, [x for units in unit_of for x in units])),
                   shape=(len(borders), u)).toarray()
    eye = np.eye(u)
    constraints = [LinearConstraint(np.hstack([A, np.zeros((len(borders), u))]), quanta, quanta),
                   LinearConstraint(np.hstack([eye, -eye]), -np.inf, t),
                   LinearConstraint(np.hstack([-eye, -eye]), -np.inf, -t)]
    res = milp(np.concatenate([np.zeros(u), np.ones(u)]), constraints=constraints,
               integrality=np.concatenate([np.ones(u), np.zeros(u)]),
               bounds=Bounds(np.concatenate([np.ones(u), np.zeros(u)]), np.full(2 * u, np.inf)))
    if res.x is None:
        raise ParametrizationError("method='charts': the charts' borders cannot be laid out on their squares "
                                   f"(no whole numbers of quanta fit: {res.message})")
    x = np.round(res.x[:u]).astype(int)
    return [[int(x[k]) for k in units] for units in unit_of]


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
        The :class:`~geoimg.image.ChartsDomain`'s fields: ``quantum``, ``columns``, ``rows``, ``gutter`` and
        ``segments`` (``[tile, start, length, twin]``).
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
    >>> info["charts"] >= 4, layout["columns"] * layout["rows"] >= info["charts"]
    (True, True)
    """
    if balance not in DISK_BALANCES:
        raise ParametrizationError(f"balance: expected one of {DISK_BALANCES}, got {balance!r}")
    if isinstance(charts, bool) or not isinstance(charts, (int, np.integer)) or not 1 <= charts <= MAX_CHARTS:
        raise ParametrizationError(f"charts: expected a whole number from 1 to {MAX_CHARTS}, got {charts!r}")
    vertices, tris, used, zipped, filled, _ = _closed_for_map(mesh)
    cut = edge_keys(igl.cut_to_disk(np.ascontiguousarray(tris, np.int64)), len(vertices))
    label, splits, opened = segment_charts(vertices, tris, charts, cut)
    vertices, tris, disc_source = _cut_at(vertices, tris, opened)
    pieces = _chart_loops(vertices, tris, label)
    borders = _borders(pieces, disc_source)
    lengths = []
    for (ids, _, loop), segs in zip(pieces, borders):
        edge = np.linalg.norm(vertices[ids[np.roll(loop, -1)]] - vertices[ids[loop]], axis=1)
        lengths.append([float(edge[(a + np.arange(n)) % len(loop)].sum()) for a, n, _ in segs])
    q = CHART_QUANTUM
    while max(len(s) for s in borders) > 4 * q:
        q *= 2
    quanta = _quantize(lengths, borders, 4 * q)
    k = len(pieces)
    columns = int(np.ceil(np.sqrt(k)))
    rows = int(np.ceil(k / columns))
    offsets = np.cumsum([0] + [len(s) for s in borders])
    first = [_first_segment(segs, quanta[c], c, q) for c, segs in enumerate(borders)]

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
        v, f, src, weight, loop, t, _ = _split_at_corners(v, f, src, weight, loop, t, q)
        heard = None if progress is None else (lambda msg, c=c: progress(f"chart {c + 1} of {k}: {msg}"))
        uv, relaxed = planar_interior(v, f, loop, perimeter_point(t, q), balance, progress=heard)
        errors.append(float(relaxed["start_errors"][relaxed["start"]]))
        a3, a2 = triangle_areas(v, f), np.abs(planar_cross(uv, f))
        starved.append((a3, a2))
        out_v.append(v)
        out_f.append(f + base)
        out_uv.append(tile_points(np.full(len(v), c), uv, q, columns, rows, CHART_GUTTER))
        out_src.append(ids[src])
        out_w.append(weight)
        base += len(v)
    share = starved_share(np.concatenate([x[0] for x in starved]), np.concatenate([x[1] for x in starved]))
    defects = [weld_defects(segments, q, k, scale) for scale in (MIN_SCALE, MIN_SCALE + 1)]
    if any(defects):
        raise ParametrizationError(f"method='charts': the {k} charts' borders would not weld into a manifold mesh "
                                   f"({max(defects)} perimeter edges glued wrongly); try other charts= or "
                                   "method='cut'")
    layout = {"quantum": int(q), "columns": columns, "rows": rows, "gutter": CHART_GUTTER, "segments": segments}
    stages = [f"{k} charts, each a disc ({splits} added where one was not), on {columns} x {rows} squares"]
    if zipped or filled:
        stages.insert(0, f"zipped {zipped} cracks and filled {filled} small holes (the image spans them)")
    info = {"charts": k, "chart_splits": int(splits), "cut_edges_opened": len(opened), "chart_errors": errors,
            "cracks_zipped": zipped, "holes_filled": filled, "starved_share": share, "stages": stages}
    source = used[disc_source[np.concatenate(out_src)]]
    return (Mesh(np.vstack(out_v), np.vstack(out_f)), np.vstack(out_uv), (source, np.concatenate(out_w)), layout,
            info)
