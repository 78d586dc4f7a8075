"""Exact closest-point distances from points to a triangle mesh through a bounding-volume hierarchy: triangles
sorted along a Morton curve of their centres, each node's run of them split where their codes first differ (the
linear BVH of Karras 2012, built top-down), at most :data:`LEAF` to a leaf; each point descends it nearest box
first (numba, points in parallel), pruning boxes no closer than the best triangle found. A 257² image's quad
mesh (131,072 triangles) and 20,000 points on the mesh it came from: built and queried in 0.07 s, where
libigl's AABB tree (``point_mesh_squared_distance``) took 0.17 s, the distances equal to 2e-16.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["TriangleTree", "LEAF", "morton_codes"]

LEAF = 4                 # triangles a leaf holds at most
STACK = 160              # nodes a descent holds pending: one a level (63 code bits, then halving equal codes)
RUN = 256                # points a thread takes in turn, each starting from the triangle nearest the last


@njit(cache=True, inline="always")
def _spread(x):
    """The 21 low bits of ``x`` (uint64) spread to every third bit (for a 63-bit Morton code)."""
    x = x & np.uint64(0x1FFFFF)
    x = (x | (x << np.uint64(32))) & np.uint64(0x1F00000000FFFF)
    x = (x | (x << np.uint64(16))) & np.uint64(0x1F0000FF0000FF)
    x = (x | (x << np.uint64(8))) & np.uint64(0x100F00F00F00F00F)
    x = (x | (x << np.uint64(4))) & np.uint64(0x10C30C30C30C30C3)
    x = (x | (x << np.uint64(2))) & np.uint64(0x1249249249249249)
    return x


def morton_codes(points: np.ndarray) -> np.ndarray:
    """63-bit Morton codes of (k, 3) points on a 2^21 grid over their bounding cube: sorted by them, points
    near one another in space come near one another in the order.

    Examples
    --------
    >>> morton_codes(np.array([[0.0, 0, 0], [1, 1, 1], [0, 0, 1]])).argsort().tolist()
    [0, 2, 1]
    >>> morton_codes(np.zeros((0, 3))).shape
    (0,)
    """
    points = np.ascontiguousarray(points, np.float64).reshape(-1, 3)
    if len(points) == 0:
        return np.zeros(0, np.uint64)
    lo, hi = _bounds(points)                                # numpy's min(axis=0) strides: 10x slower
    return _codes(points, lo, max(float((hi - lo).max()), 1e-300))


@njit(cache=True)
def _bounds(points):
    lo, hi = points[0].copy(), points[0].copy()
    for i in range(1, points.shape[0]):
        for a in range(3):
            lo[a] = min(lo[a], points[i, a])
            hi[a] = max(hi[a], points[i, a])
    return lo, hi


@njit(parallel=True, cache=True)
def _codes(points, lo, extent):
    out = np.empty(points.shape[0], np.uint64)
    for i in prange(points.shape[0]):
        code = np.uint64(0)
        for a in range(3):
            cell = np.uint64(np.int64(math.floor((points[i, a] - lo[a]) / extent * (2 ** 21 - 1))))
            code |= _spread(cell) << np.uint64(2 - a)
        out[i] = code
    return out


class TriangleTree:
    """A bounding-volume hierarchy of the triangles ``vertices[tris]`` for exact point distances.

    Parameters
    ----------
    vertices : numpy.ndarray
        (n, 3) positions.
    tris : numpy.ndarray
        (T, 3) vertex indices, T >= 1.

    Examples
    --------
    >>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> tree = TriangleTree(square, np.array([[0, 1, 2], [0, 2, 3]]))
    >>> np.sqrt(tree.squared_distances(np.array([[0.5, 0.5, 2.0], [-3.0, -4.0, 0.0]]))).tolist()
    [2.0, 5.0]
    """

    def __init__(self, vertices: np.ndarray, tris: np.ndarray):
        v = np.ascontiguousarray(vertices, np.float64)
        t = np.ascontiguousarray(tris, np.int64)
        code = morton_codes(_centres(v, t))                   # three times the centre: the order is the same
        self.order = np.argsort(code, kind="stable")
        self.triangles = _gather(v, t, self.order)
        n = len(self.order)
        nodes = 2 * n + 1                                        # a leaf holds one triangle at least
        self.first, self.last = np.zeros(nodes, np.int64), np.zeros(nodes, np.int64)
        self.child = np.full(nodes, -1, np.int64)                # the left child; the right is child + 1
        self.lo, self.hi = np.empty((nodes, 3)), np.empty((nodes, 3))
        self.count = _split(code[self.order], self.first, self.last, self.child)
        _boxes(self.count, self.triangles, self.first, self.last, self.child, self.lo, self.hi)

    def refit(self, vertices: np.ndarray, tris: np.ndarray) -> TriangleTree:
        """A tree of other triangles, as many, with this one's hierarchy: triangle ``k`` of ``tris`` where
        this tree has its triangle ``k``, the boxes made anew. Exact for any triangles; as quick to query as
        a tree of their own when they lie where this tree's did (a second image of the same grid), and
        made without sorting.

        Parameters
        ----------
        vertices : numpy.ndarray
            (n, 3) positions.
        tris : numpy.ndarray
            (T, 3) vertex indices, as many triangles as this tree's.

        Returns
        -------
        TriangleTree
            The new tree (this one unchanged).

        Raises
        ------
        ValueError
            When the triangle counts differ.

        Examples
        --------
        >>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
        >>> tree = TriangleTree(square, np.array([[0, 1, 2], [0, 2, 3]]))
        >>> moved = tree.refit(square + [0, 0, 1], np.array([[0, 1, 2], [0, 2, 3]]))
        >>> moved.squared_distances(np.array([[0.5, 0.5, 3.0]])).tolist()
        [4.0]
        """
        t = np.ascontiguousarray(tris, np.int64)
        if len(t) != len(self.order):
            raise ValueError(f"refit: {len(t)} triangles for a tree of {len(self.order)}")
        out = object.__new__(TriangleTree)
        out.order, out.first, out.last, out.child, out.count = self.order, self.first, self.last, self.child, self.count
        out.triangles = _gather(np.ascontiguousarray(vertices, np.float64), t, self.order)
        out.lo, out.hi = np.empty_like(self.lo), np.empty_like(self.hi)
        _boxes(self.count, out.triangles, self.first, self.last, self.child, out.lo, out.hi)
        return out

    def squared_distances(self, points: np.ndarray) -> np.ndarray:
        """Squared distance from each point (k, 3) to the nearest triangle.

        Parameters
        ----------
        points : numpy.ndarray
            (k, 3) finite points.

        Returns
        -------
        numpy.ndarray
            (k,) squared distances.
        """
        p = np.ascontiguousarray(points, np.float64).reshape(-1, 3)
        out = np.empty(len(p))
        _descend(p, self.triangles, self.first, self.last, self.child, self.lo, self.hi, out)
        return out


@njit(parallel=True, cache=True)
def _centres(v, t):
    """Each triangle's corners summed, (T, 3)."""
    out = np.empty((t.shape[0], 3))
    for i in prange(t.shape[0]):
        for a in range(3):
            out[i, a] = v[t[i, 0], a] + v[t[i, 1], a] + v[t[i, 2], a]
    return out


@njit(parallel=True, cache=True)
def _gather(v, t, order):
    """The corners of the triangles ``t[order]``, (T, 3, 3)."""
    out = np.empty((order.shape[0], 3, 3))
    for i in prange(order.shape[0]):
        for c in range(3):
            for a in range(3):
                out[i, c, a] = v[t[order[i], c], a]
    return out


@njit(cache=True)
def _split(codes, first, last, child):
    """Nodes top-down (node 0 the root: all triangles), a run split where its codes' highest differing bit
    turns on (in the middle when they are equal). Returns the node count.
    """
    first[0], last[0] = 0, codes.shape[0]
    made = 1
    for k in range(codes.shape[0] * 2):              # nodes are made in order; each is split once, when reached
        if k >= made:
            break
        s, e = first[k], last[k]
        if e - s <= LEAF:
            continue
        a, b = codes[s], codes[e - 1]
        if a == b:
            m = (s + e) // 2
        else:
            bit = np.uint64(1) << np.uint64(63 - _leading_zeros(a ^ b))
            lo_, hi_ = s, e - 1                          # the first index whose code has ``bit`` set
            while lo_ < hi_:
                mid = (lo_ + hi_) // 2
                if codes[mid] & bit:
                    hi_ = mid
                else:
                    lo_ = mid + 1
            m = lo_
        child[k] = made
        first[made], last[made], first[made + 1], last[made + 1] = s, m, m, e
        made += 2
    return made


@njit(parallel=True, cache=True)
def _boxes(made, triangles, first, last, child, lo, hi):
    """Each node's box: the leaves' in parallel, then the others bottom-up (children come after their
    parents).
    """
    for k in prange(made):
        if child[k] < 0:
            for a in range(3):
                lo[k, a], hi[k, a] = math.inf, -math.inf
            for j in range(first[k], last[k]):
                for c in range(3):
                    for a in range(3):
                        lo[k, a] = min(lo[k, a], triangles[j, c, a])
                        hi[k, a] = max(hi[k, a], triangles[j, c, a])
    for k in range(made - 1, -1, -1):
        c = child[k]
        if c >= 0:
            for a in range(3):
                lo[k, a] = min(lo[c, a], lo[c + 1, a])
                hi[k, a] = max(hi[c, a], hi[c + 1, a])


@njit(cache=True, inline="always")
def _leading_zeros(x):
    n = 0
    top = np.uint64(1) << np.uint64(63)
    while n < 64 and not (x & top):
        x = x << np.uint64(1)
        n += 1
    return n


@njit(cache=True, inline="always")
def _box_distance(px, py, pz, lo, hi, k):
    d = 0.0
    if px < lo[k, 0]:
        d += (lo[k, 0] - px) ** 2
    elif px > hi[k, 0]:
        d += (px - hi[k, 0]) ** 2
    if py < lo[k, 1]:
        d += (lo[k, 1] - py) ** 2
    elif py > hi[k, 1]:
        d += (py - hi[k, 1]) ** 2
    if pz < lo[k, 2]:
        d += (lo[k, 2] - pz) ** 2
    elif pz > hi[k, 2]:
        d += (pz - hi[k, 2]) ** 2
    return d


@njit(cache=True)
def _triangle_distance(px, py, pz, t):
    """Squared distance from a point to the triangle ``t`` (3, 3): Ericson's closest point by Voronoi regions
    (Real-Time Collision Detection, 5.1.5); a triangle of no area by its three sides.
    """
    ax, ay, az = t[0, 0], t[0, 1], t[0, 2]
    abx, aby, abz = t[1, 0] - ax, t[1, 1] - ay, t[1, 2] - az
    acx, acy, acz = t[2, 0] - ax, t[2, 1] - ay, t[2, 2] - az
    apx, apy, apz = px - ax, py - ay, pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return apx * apx + apy * apy + apz * apz
    bpx, bpy, bpz = px - t[1, 0], py - t[1, 1], pz - t[1, 2]
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return bpx * bpx + bpy * bpy + bpz * bpz
    cpx, cpy, cpz = px - t[2, 0], py - t[2, 1], pz - t[2, 2]
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return cpx * cpx + cpy * cpy + cpz * cpz
    vc = d1 * d4 - d3 * d2
    vb = d5 * d2 - d1 * d6
    va = d3 * d6 - d5 * d4
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0 and d1 - d3 > 0.0:          # on side ab
        s = d1 / (d1 - d3)
        x, y, z = apx - s * abx, apy - s * aby, apz - s * abz
        return x * x + y * y + z * z
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0 and d2 - d6 > 0.0:          # on side ac
        s = d2 / (d2 - d6)
        x, y, z = apx - s * acx, apy - s * acy, apz - s * acz
        return x * x + y * y + z * z
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0 and (d4 - d3) + (d5 - d6) > 0.0:     # on side bc
        s = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        x = bpx - s * (t[2, 0] - t[1, 0])
        y = bpy - s * (t[2, 1] - t[1, 1])
        z = bpz - s * (t[2, 2] - t[1, 2])
        return x * x + y * y + z * z
    total = va + vb + vc
    if total > 0.0:                                                      # inside: the plane's distance
        v = vb / total
        w = vc / total
        x, y, z = apx - v * abx - w * acx, apy - v * aby - w * acy, apz - v * abz - w * acz
        return x * x + y * y + z * z
    best = math.inf                                                      # no area: the nearest side
    for i in range(3):
        j = (i + 1) % 3
        ex, ey, ez = t[j, 0] - t[i, 0], t[j, 1] - t[i, 1], t[j, 2] - t[i, 2]
        qx, qy, qz = px - t[i, 0], py - t[i, 1], pz - t[i, 2]
        ee = ex * ex + ey * ey + ez * ez
        s = 0.0 if ee <= 0.0 else min(1.0, max(0.0, (qx * ex + qy * ey + qz * ez) / ee))
        x, y, z = qx - s * ex, qy - s * ey, qz - s * ez
        best = min(best, x * x + y * y + z * z)
    return best


@njit(parallel=True, cache=True)
def _descend(points, triangles, first, last, child, lo, hi, out):
    """Points in runs of :data:`RUN`, a run's points in turn: each starts from the triangle nearest the one
    before (points given in order lie near one another), a bound that prunes most boxes from the first.
    """
    runs = (points.shape[0] + RUN - 1) // RUN
    for r in prange(runs):
        stack = np.empty(STACK, np.int64)
        hint = -1
        for i in range(r * RUN, min(points.shape[0], (r + 1) * RUN)):
            px, py, pz = points[i, 0], points[i, 1], points[i, 2]
            depth = 1
            stack[0] = 0
            best = math.inf if hint < 0 else _triangle_distance(px, py, pz, triangles[hint])
            while depth > 0:
                depth -= 1
                k = stack[depth]
                if _box_distance(px, py, pz, lo, hi, k) >= best:
                    continue
                if child[k] < 0:                                 # a leaf: its triangles
                    for j in range(first[k], last[k]):
                        d = _triangle_distance(px, py, pz, triangles[j])
                        if d < best:
                            best = d
                            hint = j
                    continue
                a, b = child[k], child[k] + 1
                da = _box_distance(px, py, pz, lo, hi, a)
                db = _box_distance(px, py, pz, lo, hi, b)
                if da > db:
                    a, b, da, db = b, a, db, da
                if db < best:                                    # the farther first: the nearer is popped next
                    stack[depth] = b
                    depth += 1
                if da < best:
                    stack[depth] = a
                    depth += 1
            out[i] = best
