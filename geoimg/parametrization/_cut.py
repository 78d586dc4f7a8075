"""Cut-open parametrization (after Gu, Gortler & Hoppe 2002, "Geometry images"): a manifold mesh of any
genus and any number of boundary loops is cut into one topological disk, and the disk is mapped one to
one onto the unit square.

0. Small holes (at most :data:`SMALL_HOLE_EDGES` edges) are closed first, since each would cost the cut a
   path: a crack (its two sides one line of points, as the repairs leave where sheets met) is zipped, a
   pinhole filled with the triangles of least area (Liepa 2003); the image then spans them.
1. The cut graph is libigl's ``cut_to_disk`` (Gu et al.'s triangle deletion: 2g loops for genus g, paths
   joining the boundary loops); libigl's ``cut_mesh`` copies the vertices along it. When the map (step 4)
   squeezes a point off the cut, a branch is cut to it along the shortest edge path and the map made
   again (Gu et al.'s cut augmentation), kept only when it lowers the resampling error by a tenth or more,
   starves less of the surface and folds nothing more (:data:`AUGMENT_ROUNDS` times at most).
2. The disk's boundary runs along the cut, each cut path twice (its two sides, in opposite directions),
   and along the mesh's own boundary loops once. It is split into segments at the nodes (the cut
   graph's vertices of degree other than 2). Every segment gets a whole number of "quanta" of the
   square's perimeter (4 Q quanta), in proportion to its length, a cut path's two sides the same number;
   within a segment the vertices follow their arc length. So the two sides of a cut have the same
   positions in reverse, and on an image whose side N has N - 1 a multiple of Q, every boundary pixel on
   one side of a cut has an exact twin pixel on the other (see :class:`geoimg.image.CutDomain`).
3. Edges that join two boundary vertices across the disk's interior would lie along a side of the
   square and flatten their faces: they are split at their midpoints (the new vertices are interior).
4. The interior follows from positive weights and a convex boundary, so no triangle folds over (Floater's
   mean-value weights and Tutte's uniform ones, each relaxed, the better kept: see
   :func:`._disk.planar_interior`), relaxed by the area balancing of the disk and sphere maps (or libigl's
   SLIM, ``balance="slim"``), which keeps every triangle the right way round, the boundary held in place.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import igl
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from .._choices import DEFAULT_DISK_BALANCE, DISK_BALANCES
from .._types import Progress
from ..errors import ParametrizationError
from ..mesh import Mesh, boundary_loops, topology
from ._disk import GaussNewtonStalled, _folds, planar_interior
from ._laplacian import STARVED_SHARE, planar_cross, starved_share, triangle_areas
from ._layout import perimeter_point

__all__ = ["cut_coords", "layout_quanta", "QUANTA_PER_SIDE"]

QUANTA_PER_SIDE = 64
SMALL_HOLE_EDGES = 8      # a hole of at most this many edges is closed for the map (it would cost a cut path):
CRACK_GAP = 1e-9          # zipped when its two sides lie this close (share of the bounding diagonal), else
SMALL_HOLE_AREA = 1e-3    # filled when the fill covers at most this share of the surface
FILL_QUALITY = 1e-3       # and no fill triangle is flatter than this (4 sqrt(3) area / squared edges)
AUGMENT_ROUNDS = 4        # at most this many cut branches towards a starved point, each kept when it helps:
AUGMENT_GAIN = 0.9        # when it lowers the resampling error to this share or less and starves less of the
                          # surface (smaller gains, or none in starvation, cost fidelity: a CAD plate -1.7 dB)


def _closed_for_map(mesh: Mesh) -> tuple:
    """The mesh's triangles with its small holes closed (:func:`_close_small_holes`), every vertex on one:
    ``vertices, tris, used`` (each vertex's index in the mesh), and how many cracks were zipped, holes filled
    and fill triangles added.
    """
    tris, _ = mesh.triangulate()
    weld, fill, zipped, filled = _close_small_holes(mesh.vertices, tris, topology(mesh).genus or 0)
    tris = np.concatenate([weld[tris], fill])
    used = np.unique(tris)          # a crack's welded side, and any vertex on no triangle, leave
    remap = np.full(mesh.n_vertices, -1, np.int64)
    remap[used] = np.arange(len(used))
    return mesh.vertices[used], remap[tris], used, zipped, filled, int(len(fill))


def edge_keys(paths: list, n: int) -> set:
    """The keys ``min * n + max`` of the edges along ``paths`` (sequences of vertex indices)."""
    keys: set = set()
    for c in paths:
        c = np.asarray(c, np.int64)
        keys.update((np.minimum(c[:-1], c[1:]) * n + np.maximum(c[:-1], c[1:])).tolist())
    return keys


def _cut_open(vertices: np.ndarray, tris: np.ndarray, cuts: list):
    """The disk mesh (vertices copied along the ``cuts``, paths of vertices) and each disk vertex's source
    vertex.
    """
    return cut_along(vertices, tris, edge_keys(cuts, len(vertices)))


def cut_along(vertices: np.ndarray, tris: np.ndarray, keys: set):
    """The triangles cut open along the edges ``keys`` (``min * n + max``; libigl's ``cut_mesh`` copies the
    vertices along them) and each vertex's source vertex.
    """
    tris = np.ascontiguousarray(tris, np.int64)
    n = len(vertices)
    cut = np.zeros(tris.shape, bool)
    for k in range(3):
        a, b = tris[:, k], tris[:, (k + 1) % 3]
        cut[:, k] = np.isin(np.minimum(a, b) * n + np.maximum(a, b), list(keys)) if keys else False
    v, f, source = igl.cut_mesh(np.ascontiguousarray(vertices, np.float64), tris, cut)
    return np.asarray(v), np.asarray(f, np.int64), np.asarray(source, np.int64)


def _split_chords(v: np.ndarray, f: np.ndarray, source: np.ndarray, on_boundary: np.ndarray):
    """Split every interior edge whose two ends are on the boundary at its midpoint (repeated until none
    is left). Returns vertices, faces, source vertex pairs (a, b) per vertex (a == b for originals) and the
    number of edges split.
    """
    src = np.stack([source, source], axis=1) if source.ndim == 1 else source
    split = 0
    for _ in range(8):
        a, b = f, np.roll(f, -1, axis=1)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        key = lo * len(v) + hi
        _, inv, counts = np.unique(key.ravel(), return_inverse=True, return_counts=True)
        interior = counts[inv].reshape(f.shape) == 2
        chord = interior & on_boundary[a] & on_boundary[b]
        if not chord.any():
            break
        chord_keys = np.unique(key[chord])
        mid = len(v) + np.arange(len(chord_keys))
        ca, cb = chord_keys // len(v), chord_keys % len(v)
        v = np.vstack([v, 0.5 * (v[ca] + v[cb])])
        src = np.vstack([src, np.stack([src[ca, 0], src[cb, 0]], axis=1)])
        on_boundary = np.concatenate([on_boundary, np.zeros(len(mid), bool)])
        # every face with chords is split at all of them at once, so neighbours agree
        pos = np.searchsorted(chord_keys, key)
        hit = np.where(chord, mid[np.minimum(pos, len(mid) - 1)], -1)
        done = chord.any(axis=1)
        new_faces = [_split_triangle(f[i], hit[i]) for i in np.flatnonzero(done)]
        new_faces = [t for group in new_faces for t in group]
        f = np.vstack([f[~done], np.array(new_faces, np.int64)])
        split += len(chord_keys)
    return v, f, src, split


def _split_triangle(tri, mids) -> list:
    """Triangle ``tri`` (3,) split at the midpoints ``mids`` (3,) of its edges (edge k runs from corner k to
    corner k + 1; -1 where an edge is not split), the pieces wound like the triangle.
    """
    v, m = [int(x) for x in tri], [int(x) for x in mids]
    split = [k for k in range(3) if m[k] >= 0]
    if len(split) == 3:
        return [[v[0], m[0], m[2]], [m[0], v[1], m[1]], [m[2], m[1], v[2]], [m[0], m[1], m[2]]]
    if len(split) == 1:
        k = split[0]
        return [[v[k], m[k], v[(k + 2) % 3]], [m[k], v[(k + 1) % 3], v[(k + 2) % 3]]]
    j = ({0, 1, 2} - set(split)).pop()            # the edge left whole
    a, b, c = v[j], v[(j + 1) % 3], v[(j + 2) % 3]
    mbc, mca = m[(j + 1) % 3], m[(j + 2) % 3]
    return [[c, mca, mbc], [a, b, mbc], [a, mbc, mca]]


def _split_at_corners(v, f, src, weight, loop, t, quanta_per_side):
    """Put a vertex at each corner of the square: a boundary edge running round a corner is split there
    (and its twin on the other side of the cut at the same point), its face in two. Returns the updated
    arrays and the number of corners split.
    """
    total = 4 * quanta_per_side
    split = 0
    for c in (quanta_per_side, 2 * quanta_per_side, 3 * quanta_per_side):
        n = len(loop)
        ends = np.roll(t, -1)
        ends = np.where(ends <= t, ends + total, ends)
        hit = np.flatnonzero((t < c) & (c < ends))
        if not len(hit):
            continue
        i = int(hit[0])
        alpha = (c - t[i]) / (ends[i] - t[i])
        a, b = loop[i], loop[(i + 1) % n]
        jobs = [(i, alpha, c)]
        for j in range(n):                                  # the other side of the cut, if any
            if j != i and _same_point(src, weight, loop[j], b) and _same_point(src, weight, loop[(j + 1) % n], a):
                jobs.append((j, 1.0 - alpha, t[j] + (1.0 - alpha) * (ends[j] - t[j])))
                break
        for j, frac, pos in sorted(jobs, reverse=True):      # from the back, so indices stay valid
            p, q = loop[j], loop[(j + 1) % len(loop)]
            x = len(v)
            v = np.vstack([v, (1 - frac) * v[p] + frac * v[q]])
            pa, pw = _on_edge(src, weight, p, q)
            src = np.vstack([src, pa])
            weight = np.append(weight, pw[0] + frac * (pw[1] - pw[0]))
            row = np.flatnonzero(((f == p) & (np.roll(f, -1, axis=1) == q)).any(axis=1))[0]
            k = int(np.flatnonzero((f[row] == p) & (np.roll(f[row], -1) == q))[0])
            r = f[row, (k + 2) % 3]
            f = np.vstack([np.delete(f, row, axis=0), [[p, x, r], [x, q, r]]])
            loop = np.insert(loop, j + 1, x)
            t = np.insert(t, j + 1, pos % total)
            split += 1
    return v, f, src, weight, loop, t, split


def _same_point(src, weight, p, q) -> bool:
    """Whether disk vertices p and q are copies of one point of the input (by source indices)."""
    if src[p, 0] == src[p, 1] and src[q, 0] == src[q, 1]:
        return src[p, 0] == src[q, 0]
    return {int(src[p, 0]), int(src[p, 1])} == {int(src[q, 0]), int(src[q, 1])} and \
        np.isclose(weight[p] if src[p, 0] == src[q, 0] else 1 - weight[p], weight[q])


def _on_edge(src, weight, p, q):
    """The input edge (A, B) that boundary vertices p and q lie on, and their weights along it."""
    ids = []
    for x in (p, q):
        for y in src[x]:
            if int(y) not in ids:
                ids.append(int(y))
    A, B = ids[0], ids[-1]

    def w(x):
        a, b = int(src[x, 0]), int(src[x, 1])
        if a == b:
            return 0.0 if a == A else 1.0
        return float(weight[x]) if a == A else 1.0 - float(weight[x])

    return np.array([A, B]), (w(p), w(q))


def _segments(loop: np.ndarray, source: np.ndarray, lengths: np.ndarray):
    """Split the disk's boundary loop into segments between nodes. Returns the node positions (loop
    indices where segments start) and each segment's twin (or -1 for the mesh's own boundary).
    """
    n = len(loop)
    s_from, s_to = source[loop], source[np.roll(loop, -1)]
    edge_key: dict[tuple[int, int], list[int]] = {}
    for i, (a, b) in enumerate(zip(s_from.tolist(), s_to.tolist())):
        edge_key.setdefault((min(a, b), max(a, b)), []).append(i)
    twin_edge = np.full(n, -1, np.int64)
    for ids in edge_key.values():
        if len(ids) == 2:
            twin_edge[ids[0]], twin_edge[ids[1]] = ids[1], ids[0]
    # node: where the boundary does not continue as the mirror of its twin (or changes between cut and rim)
    starts: Any = []                         # positions, then their array
    for i in range(n):
        j = (i - 1) % n                      # the edge before position i
        ti, tj = twin_edge[i], twin_edge[j]
        continuous = (ti < 0 and tj < 0) or (ti >= 0 and tj >= 0 and ti == (tj - 1) % n)
        if not continuous:
            starts.append(i)
    if not starts:                           # one closed run (never both sides of a cut): start anywhere
        starts = [0]
    starts = np.array(starts)
    seg_of_edge = np.searchsorted(starts, np.arange(n), side="right") - 1
    seg_of_edge[seg_of_edge < 0] = len(starts) - 1
    twin = np.full(len(starts), -1, np.int64)
    for s in range(len(starts)):
        e = starts[s]
        if twin_edge[e] >= 0:
            twin[s] = seg_of_edge[twin_edge[e]]
    seg_len = np.bincount(seg_of_edge, lengths, minlength=len(starts))
    return starts, twin, seg_len, seg_of_edge


def _quantize(seg_len: np.ndarray, twin: np.ndarray, quanta: int) -> np.ndarray:
    """Whole numbers of quanta per segment, at least 1, twins equal, summing to ``quanta``, near the
    segments' shares of the total length (largest remainders).
    """
    n = len(seg_len)
    if n > quanta:
        raise ParametrizationError(f"method='cut': the boundary has {n} segments, more than the {quanta} the layout "
                                   "holds")
    # pair twins into units (a pair counts twice)
    unit_of = np.full(n, -1)
    units: list = []
    for s in range(n):
        if unit_of[s] < 0:
            members = [s] if twin[s] < 0 or twin[s] == s else [s, int(twin[s])]
            for m in members:
                unit_of[m] = len(units)
            units.append(members)
    size = np.array([len(u) for u in units])
    length = np.array([seg_len[u[0]] for u in units])
    total = float((length * size).sum())
    share = length / max(total, 1e-300) * quanta
    q = np.maximum(1, np.floor(share)).astype(int)
    while (q * size).sum() > quanta:                 # too many: take from the largest
        i = int(np.argmax(np.where(q > 1, q - share, -np.inf)))
        q[i] -= 1
    left = quanta - int((q * size).sum())
    while left > 0:                                 # hand out the rest, pairs only where two fit
        fits = size <= left
        if not fits.any():
            break
        i = int(np.argmax(np.where(fits, share - q, -np.inf)))
        q[i] += 1
        left -= size[i]
    if left:                                        # an odd quantum left and only pairs: give it to a rim
        raise ParametrizationError("method='cut': could not lay the boundary out on the square evenly")
    return q[unit_of]


def layout_quanta(segments: int, quanta_per_side: int | None = None) -> int:
    """Quanta per side of the square for a boundary of ``segments`` segments: ``quanta_per_side`` when given,
    else :data:`QUANTA_PER_SIDE` doubled until the perimeter's four sides hold a quantum per segment (a mesh
    of high genus or many holes has hundreds of segments; its image then needs N - 1 a multiple of the
    larger quantum).

    Parameters
    ----------
    segments : int
        The boundary's segment count.
    quanta_per_side : int or None
        A quantum asked for (checked).

    Returns
    -------
    int
        Quanta per side.

    Examples
    --------
    >>> layout_quanta(200), layout_quanta(288), layout_quanta(600)
    (64, 128, 256)
    """
    if quanta_per_side is not None:
        return int(quanta_per_side)
    q = QUANTA_PER_SIDE
    while 4 * q < segments:
        q *= 2
    return q


class _CutMap(NamedTuple):
    """One cut's map: what :func:`cut_coords` returns (``result``, sources in the triangles' own numbering),
    the cut's paths, the map's folded triangles, its :func:`._disk.resampling_error`, the share of the
    surface it starves (triangles given less than :data:`STARVED_SHARE` of their fair share of the square).
    """

    result: tuple
    cuts: list
    folds: int
    error: float
    starved: float


def _map_cut(vertices: np.ndarray, tris: np.ndarray, cuts: list, quanta_per_side: int | None, balance: str,
             progress: Progress | None, *, newton_only: bool = False) -> _CutMap:
    """Cut the triangles ``vertices, tris`` (every vertex on one) open along ``cuts`` and map the disk onto
    the square; ``newton_only`` as for :func:`planar_interior` (which raises where it gives up).
    """
    v, f, src = _cut_open(vertices, tris, cuts)
    disk = Mesh(v, f)
    loops = boundary_loops(disk)
    if len(loops) != 1:
        raise ParametrizationError(f"method='cut': cutting gave {topology(disk).describe()}, not one disk")
    loop = loops[0]
    on_boundary = np.zeros(len(v), bool)
    on_boundary[loop] = True
    v, f, source, n_chords = _split_chords(v, f, src, on_boundary)
    weight = np.where(source[:, 0] == source[:, 1], 0.0, 0.5)
    lengths = np.linalg.norm(v[np.roll(loop, -1)] - v[loop], axis=1)
    starts, twin, seg_len, seg_of_edge = _segments(loop, source[:, 0], lengths)
    quanta_per_side = layout_quanta(len(starts), quanta_per_side)
    quanta = _quantize(seg_len, twin, 4 * quanta_per_side)
    seg_start = np.concatenate([[0], np.cumsum(quanta)[:-1]])
    # positions along each segment by arc length; a segment and its twin share them, reversed
    arc = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    t = np.empty(len(loop))
    for s in range(len(starts)):
        edges = np.flatnonzero(seg_of_edge == s)
        first = starts[s]
        rel = (arc[edges] - arc[first]) % max(float(lengths.sum()), 1e-300)
        span = seg_len[s] if seg_len[s] > 0 else 1.0
        t[edges] = seg_start[s] + quanta[s] * rel / span
    v, f, source, weight, loop, t, n_corners = _split_at_corners(v, f, source, weight, loop, t, quanta_per_side)
    disk = Mesh(v, f)
    # the boundary held: twins stay twins
    coords, relaxed = planar_interior(v, f, loop, perimeter_point(t, quanta_per_side), balance, progress=progress,
                                      newton_only=newton_only)
    layout = {"quantum": int(quanta_per_side),
              "segments": [[int(a), int(b), int(c)] for a, b, c in zip(seg_start, quanta, twin)]}
    info = {"cut_length": float(sum(lengths[twin[seg_of_edge] >= 0]) / 2),
            "chords_split": int(n_chords), "corners_split": int(n_corners), "segments": len(starts),
            **relaxed}
    error = relaxed["start_errors"][relaxed["start"]]
    starved = starved_share(triangle_areas(v, f), np.abs(planar_cross(coords, f)))
    return _CutMap((disk, coords, (source, weight), layout, info), cuts, _folds(coords, f), error, starved)


def _least_area_fill(vertices: np.ndarray, rim: np.ndarray, edges: set) -> np.ndarray | None:
    """The triangles of least total area that close the polygon ``rim`` (dynamic programming over its
    diagonals, Liepa 2003), wound as ``rim`` runs: a slit (its two sides one line) closes with triangles of
    no area, not with two that cover each other. A diagonal that is already an edge (key ``a * n + b``,
    a < b, in ``edges``) is not drawn; None when no triangulation avoids one.
    """
    m, n = len(rim), len(vertices)
    cost = np.full((m, m), np.inf)
    split = np.zeros((m, m), np.int64)
    for i in range(m - 1):
        cost[i, i + 1] = 0.0
    for span in range(2, m):
        for i in range(m - span):
            j = i + span
            a, b = sorted((int(rim[i]), int(rim[j])))
            if span < m - 1 and a * n + b in edges:
                continue
            for k in range(i + 1, j):
                area = 0.5 * float(np.linalg.norm(np.cross(vertices[rim[k]] - vertices[rim[i]],
                                                           vertices[rim[j]] - vertices[rim[i]])))
                if cost[i, k] + cost[k, j] + area < cost[i, j]:
                    cost[i, j], split[i, j] = cost[i, k] + cost[k, j] + area, k
    if not np.isfinite(cost[0, m - 1]):
        return None
    out, todo = [], [(0, m - 1)]
    while todo:
        i, j = todo.pop()
        if j - i < 2:
            continue
        k = int(split[i, j])
        out.append([rim[i], rim[k], rim[j]])
        todo += [(i, k), (k, j)]
    return np.array(out, np.int64)


def _crack_pairs(vertices: np.ndarray, loop: np.ndarray, gap: float) -> list | None:
    """When the hole ``loop`` is a crack, its two sides the same line of points (the i-th vertex after one tip
    within ``gap`` of the i-th before it, up to the other tip), the pairs (kept, welded) that zip it; else
    None.
    """
    m = len(loop)
    if m % 2 or m < 4:
        return None
    i = np.arange(1, m // 2)
    for tip in range(m // 2):
        q = np.roll(loop, -tip)
        if np.all(np.linalg.norm(vertices[q[i]] - vertices[q[m - i]], axis=1) <= gap):
            return list(zip(q[i].tolist(), q[m - i].tolist()))
    return None


def _fill_quality(vertices: np.ndarray, fill: np.ndarray) -> float:
    """The worst of the triangles' shape measures, 4 sqrt(3) area over their squared edges (1: equilateral,
    0: flat).
    """
    c = vertices[fill]
    squares = (np.linalg.norm(c - np.roll(c, 1, axis=1), axis=2) ** 2).sum(1)
    return float(np.min(4 * np.sqrt(3) * triangle_areas(vertices, fill) / np.maximum(squares, 1e-300)))


def _close_small_holes(vertices: np.ndarray, tris: np.ndarray, genus: int) -> tuple:
    """Close the mesh's small holes (at most :data:`SMALL_HOLE_EDGES` edges) for the map: each would cost the
    cut a path and the square's perimeter a few quanta, and a scan's cracks (the slits its repairs leave
    where sheets met) can take half of it. A crack (its sides one line, :data:`CRACK_GAP`) is zipped, its
    sides' vertices welded; another hole is filled by :func:`_least_area_fill` when the fill covers at
    most :data:`SMALL_HOLE_AREA` of the surface and no fill triangle is flatter than :data:`FILL_QUALITY`
    (a flat one would spoil the weights of the map inside). A hole that would repeat an edge or a vertex,
    or the largest loop of a genus-0 surface (its cut needs one), stays open.

    Returns
    -------
    weld : (N,) int64
        The vertex each vertex becomes (itself, or its twin across a crack).
    fill : (K, 3) int64
        Triangles filling holes, oriented as their neighbours (in welded numbering).
    zipped, filled : int
        How many cracks were zipped and holes filled.
    """
    n = len(vertices)
    loops = boundary_loops(Mesh(vertices, tris))
    if not loops:
        return np.arange(n), np.zeros((0, 3), np.int64), 0, 0
    edges = set((np.minimum(tris, np.roll(tris, -1, 1)) * n + np.maximum(tris, np.roll(tris, -1, 1))).ravel().tolist())
    total = float(triangle_areas(vertices, tris).sum())
    gap = CRACK_GAP * float(np.linalg.norm(np.ptp(vertices, axis=0)))
    perimeter = [float(np.linalg.norm(vertices[np.roll(L, -1)] - vertices[L], axis=1).sum()) for L in loops]
    keep_open = int(np.argmax(perimeter)) if genus == 0 else -1
    fills, cracks = [], []
    for k, loop in enumerate(loops):
        if k == keep_open or len(loop) > SMALL_HOLE_EDGES or len(np.unique(loop)) < len(loop):
            continue
        pairs = _crack_pairs(vertices, loop, gap)
        if pairs is not None:
            cracks.append(np.array(pairs, np.int64))
            continue
        fill = _least_area_fill(vertices, loop[::-1], edges)     # against the loop: the way the neighbours run
        if fill is None or triangle_areas(vertices, fill).sum() > SMALL_HOLE_AREA * total or \
                _fill_quality(vertices, fill) < FILL_QUALITY:
            continue
        fills.append(fill)
    weld, zipped = _zip(n, tris, cracks)
    fill = weld[np.concatenate(fills)] if fills else np.zeros((0, 3), np.int64)
    return weld, fill[~_crushed(fill)], zipped, len(fills)


def _zip(n: int, tris: np.ndarray, cracks: list) -> tuple[np.ndarray, int]:
    """The weld (each of the ``n`` vertices' new number) that zips the ``cracks`` ((k, 2) pairs (kept,
    welded) each) and how many it zips: all at once when that keeps the mesh clean (one check), else one by
    one, each kept when it does.
    """
    weld = np.arange(n)
    if not cracks:
        return weld, 0
    every = weld.copy()
    for pairs in cracks:
        every[pairs[:, 1]] = pairs[:, 0]
    if _welds_cleanly(every, tris):
        return every, len(cracks)
    zipped = 0
    for pairs in cracks:
        trial = weld.copy()
        trial[pairs[:, 1]] = pairs[:, 0]
        if _welds_cleanly(trial, tris):
            weld, zipped = trial, zipped + 1
    return weld, zipped


def _crushed(tris: np.ndarray) -> np.ndarray:
    """Which triangles repeat a vertex."""
    return (tris[:, 0] == tris[:, 1]) | (tris[:, 1] == tris[:, 2]) | (tris[:, 2] == tris[:, 0])


def _welds_cleanly(weld: np.ndarray, tris: np.ndarray) -> bool:
    """Whether welding (``weld``: each vertex's new number) keeps every triangle whole and the mesh manifold."""
    w = weld[tris]
    if np.any(_crushed(w)):
        return False
    t = topology(Mesh(np.zeros((len(weld), 3)), w))
    return t.nonmanifold_edges == 0 and t.nonmanifold_vertices == 0


def _led(progress: Progress, lead: str) -> Progress:
    """``progress`` with every message led by ``lead``."""
    return lambda msg: progress(lead + msg)


def _shares(x: np.ndarray) -> np.ndarray:
    """``x`` over its sum."""
    return np.asarray(x, np.float64) / max(float(x.sum()), 1e-300)


def _path_to_worst(vertices: np.ndarray, tris: np.ndarray, cut: _CutMap) -> np.ndarray | None:
    """The shortest path along the mesh's edges from the cut (or the mesh's boundary) to the vertex the map
    squeezes most (its triangles' share of the square against their share of the surface), when that is a
    starved vertex (below :data:`._stretch.STARVED_SHARE`) off the cut; else None (Gu et al. 2002, 3.2).
    """
    disk, coords, (source, weight), _, _ = cut.result
    f = disk.faces
    a3 = triangle_areas(disk.vertices, f)
    a2 = np.abs(planar_cross(coords, f))
    own = source[:, 0] == source[:, 1]               # copies of the input's vertices (not midpoints)
    n = len(vertices)
    corner = np.where(own[f], source[f, 0], n)       # midpoints count to a dummy vertex n
    share3, share2 = (_shares(np.bincount(corner.ravel(), np.repeat(a, 3), minlength=n + 1)[:n]) for a in (a3, a2))
    on_cut = np.zeros(n, bool)
    on_cut[source[boundary_loops(disk)[0], 0]] = True
    fair = np.where(on_cut | (share3 <= 0), np.inf, share2 / np.maximum(share3, 1e-300))
    worst = int(np.argmin(fair))
    if not fair[worst] < STARVED_SHARE:
        return None
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    length = np.linalg.norm(vertices[e[:, 0]] - vertices[e[:, 1]], axis=1)
    keep = length > 1e-9 * max(float(length.max()), 1e-300)     # no edge of no length (a boundary edge of none)
    graph = coo_matrix((length[keep], (e[keep, 0], e[keep, 1])), shape=(n, n)).tocsr()
    _, pred, origin = dijkstra(graph, directed=False, indices=np.flatnonzero(on_cut), min_only=True,
                               return_predecessors=True)
    if origin[worst] < 0:
        return None
    path = [worst]
    while not on_cut[path[-1]]:
        path.append(int(pred[path[-1]]))
    return np.array(path[::-1], np.int64)


def cut_coords(mesh: Mesh, *, quanta_per_side: int | None = None, balance: str = DEFAULT_DISK_BALANCE,
               progress: Progress | None = None) -> tuple:
    """Cut a manifold, oriented, connected mesh into a disk and map it onto the unit square.

    ``quanta_per_side`` is the boundary layout's unit (see :func:`layout_quanta`; default: the smallest of
    64, 128, 256, ... that holds the boundary's segments).

    Parameters
    ----------
    mesh : Mesh
        A manifold, oriented, connected mesh (not a disk or a closed genus-0 surface: those have maps of
        their own, though they may be cut too).
    quanta_per_side : int or None
        The boundary layout's unit.
    balance : {"area", "slim", "none"}
        How the map inside is relaxed.
    progress : callable or None
        Called with the area balancing's progress.

    Returns
    -------
    disk : Mesh
        Triangles; vertices along the cut appear once per side (copies of the same position), chords
        split at midpoints.
    coords : (N, 2) float64
        (u, v) of the disk's vertices in the unit square.
    source : tuple of (N, 2) int64 and (N,) float64
        The input edge ``(a, b)`` each disk vertex lies on and its weight ``w`` along it: the vertex is
        ``(1 - w) p_a + w p_b`` (``a == b`` for copies of input vertices).
    layout : dict
        ``quantum`` (quanta per side) and ``segments``: ``[start, length, twin]`` in quanta along the
        perimeter, counter-clockwise from (0, 0); ``twin`` is the segment on the other side of the cut, -1
        for the mesh's own boundary.
    info : dict
        ``cut_paths`` (libigl's), ``cut_branches`` (grown towards squeezed points), ``cut_errors`` (the
        resampling error of each cut tried, the first libigl's), ``cracks_zipped``, ``holes_filled`` and
        ``fill_faces`` (the triangles added), ``starved_share`` (of the surface, given less than
        :data:`STARVED_SHARE` of its fair share of the square), ``cut_length`` (3-D), ``chords_split``, ``segments``,
        ``balance`` and ``balance_steps``: the mean-value map inside is relaxed with the boundary held, by
        area balancing (``balance="area"``, the default), SLIM (``"slim"``) or not (``"none"``); ``progress``
        hears from the area balancing every ten steps.

    Raises
    ------
    ParametrizationError
        When ``balance`` is unknown, or cutting does not give one disk.

    Examples
    --------
    >>> import geoimg
    >>> t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> T, P = np.meshgrid(t, t)
    >>> v = np.stack([(2 + np.cos(P)) * np.cos(T), (2 + np.cos(P)) * np.sin(T), np.sin(P)], -1).reshape(-1, 3)
    >>> i = np.arange(64).reshape(8, 8)
    >>> a, b, c, d = i, np.roll(i, -1, 1), np.roll(np.roll(i, -1, 0), -1, 1), np.roll(i, -1, 0)
    >>> torus = geoimg.Mesh(v, np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3))
    >>> disk, uv, source, layout, info = cut_coords(torus)
    >>> info["cut_paths"], all(tw >= 0 for _, _, tw in layout["segments"]), float(uv.min()), float(uv.max())
    (2, True, 0.0, 1.0)
    """
    if balance not in DISK_BALANCES:
        raise ParametrizationError(f"balance: expected one of {DISK_BALANCES}, got {balance!r}")
    vertices, tris, used, zipped, filled, fill_faces = _closed_for_map(mesh)
    cuts = [np.asarray(c, np.int64) for c in igl.cut_to_disk(np.ascontiguousarray(tris, np.int64))]
    best = _map_cut(vertices, tris, cuts, quanta_per_side, balance, progress)
    errors = [best.error]
    gave_up = False
    for _ in range(AUGMENT_ROUNDS if balance == "area" else 0):
        path = _path_to_worst(vertices, tris, best)
        if path is None:
            break
        heard = None if progress is None else _led(progress, f"cut {len(errors) + 1}: ")
        # a map made by Gauss-Newton steps is not traded for one they cannot make: where they stall on the
        # trial's two starts it is given up before its Sobolev steps (the Stanford bunny with its 5 holes:
        # such a trial took 11 of 15.5 s and ended worse, 1.77 -> 1.93)
        try:
            trial = _map_cut(vertices, tris, best.cuts + [path], quanta_per_side, balance, heard,
                             newton_only=bool(best.result[4].get("gauss_newton")))
        except GaussNewtonStalled:
            gave_up = True
            break
        errors.append(trial.error)
        if trial.folds > best.folds or not trial.error <= AUGMENT_GAIN * best.error or \
                not trial.starved < best.starved:
            break
        best = trial
    disk, coords, (source, weight), layout, info = best.result
    source = used[source]
    info.update(cut_paths=len(cuts), cut_branches=len(best.cuts) - len(cuts), cut_errors=errors,
                cracks_zipped=zipped, holes_filled=filled, fill_faces=fill_faces, starved_share=best.starved)
    closed = [f"zipped {zipped} crack{'s' * (zipped > 1)}"] * bool(zipped) + \
        [f"filled {filled} small hole{'s' * (filled > 1)}"] * bool(filled)
    if closed:
        info["stages"] = [" and ".join(closed) + f" (at most {SMALL_HOLE_EDGES} edges; the image spans them)"] + \
            info["stages"]
    if len(errors) > 1:
        info["stages"] = info["stages"] + [f"cut towards the most squeezed point {len(best.cuts) - len(cuts)} of "
                                           f"{len(errors) - 1} times (resampling error "
                                           + " -> ".join(f"{e:.3g}" for e in errors) + ")"]
    if gave_up:
        info["stages"] = info["stages"] + ["a further cut given up: its Gauss-Newton steps stalled"]
    return disk, coords, (source, weight), layout, info
