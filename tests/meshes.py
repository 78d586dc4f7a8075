"""Synthetic meshes for the tests, each standing in for a kind of real mesh whose file may not be bundled:
one polygon, disks (curved, quads), closed polygonal solids, holes, several pieces, a bumpy sphere.
Made here from formulas, so they carry no third-party licence."""
import numpy as np
from scipy.spatial import ConvexHull

import geoimg


def l_hexagon() -> geoimg.Mesh:
    """One non-convex hexagon (an L): 1 face, 1 boundary loop, a reflex corner at vertex 3."""
    v = [[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]]
    return geoimg.Mesh(v, [[0, 1, 2, 3, 4, 5]])


def cap(max_latitude_deg: float = 90.0, rings: int = 10, segments: int = 24) -> geoimg.Mesh:
    """Triangles of a unit sphere's cap around +z, from the pole down to ``max_latitude_deg`` from it:
    90 is a hemisphere (a height field); beyond 90 it is a cup whose projection folds."""
    theta = np.radians(np.linspace(0, max_latitude_deg, rings + 1)[1:])
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], axis=-1).reshape(-1, 3)
    v = np.vstack([[0.0, 0.0, 1.0], ring])
    faces = [[0, 1 + j, 1 + (j + 1) % segments] for j in range(segments)]
    for i in range(rings - 1):
        a, b = 1 + i * segments, 1 + (i + 1) * segments
        for j in range(segments):
            k = (j + 1) % segments
            faces += [[a + j, b + j, b + k], [a + j, b + k, a + k]]
    return geoimg.Mesh(v, faces)


def octa_hemisphere(n: int = 30) -> geoimg.Mesh:
    """The upper half of an octahedron, each of its 4 faces split into n^2 triangles, pushed onto the unit
    sphere: a hemisphere whose rim is the equator (4 n^2 faces; n = 30 gives 1,861 vertices)."""
    corners = np.array([[1.0, 0, 0], [0, 1.0, 0], [-1.0, 0, 0], [0, -1.0, 0]])
    top = np.array([0.0, 0, 1])
    index, v, faces = {}, [], []

    def vid(p):
        key = tuple(np.round(p, 12))
        if key not in index:
            index[key] = len(v)
            v.append(p / np.linalg.norm(p))
        return index[key]

    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        grid = {(i, j): vid((a * (n - i - j) + b * i + top * j) / n) for i in range(n + 1) for j in range(n + 1 - i)}
        for i in range(n):
            for j in range(n - i):
                faces.append([grid[i, j], grid[i + 1, j], grid[i, j + 1]])
                if i + j < n - 1:
                    faces.append([grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]])
    return geoimg.Mesh(np.array(v), faces)


def quad_disk(n: int = 12) -> geoimg.Mesh:
    """A wavy sheet of (n - 1)^2 quads: a disk made of quads only."""
    t = np.linspace(0.0, 1.0, n)
    x, y = np.meshgrid(t, t)
    z = 0.15 * np.sin(3 * x) * np.cos(2 * y)
    idx = np.arange(n * n).reshape(n, n)
    quads = np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], axis=-1).reshape(-1, 4)
    return geoimg.Mesh(np.stack([x, y, z], axis=-1).reshape(-1, 3), quads)


def capped_cylinder(segments: int = 20, rows: int = 10) -> geoimg.Mesh:
    """A closed cylinder of ``segments * rows`` quads and two ``segments``-gon caps (genus 0)."""
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    z = np.linspace(-1.0, 1.0, rows + 1)
    v = np.stack([np.repeat(np.cos(phi)[None], rows + 1, 0), np.repeat(np.sin(phi)[None], rows + 1, 0),
                  np.repeat(z[:, None], segments, 1)], axis=-1).reshape(-1, 3)
    faces = []
    for i in range(rows):
        for j in range(segments):
            k = (j + 1) % segments
            faces.append([i * segments + j, i * segments + k, (i + 1) * segments + k, (i + 1) * segments + j])
    faces.append(list(range(segments))[::-1])                                   # bottom, facing -z
    faces.append([rows * segments + j for j in range(segments)])               # top, facing +z
    return geoimg.Mesh(v, faces)


def rhombicuboctahedron() -> geoimg.Mesh:
    """8 triangles and 18 squares, closed genus 0 (a coarse chamfered cube, 24 vertices)."""
    a = 1 + np.sqrt(2)
    pts = []
    for perm in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-a, a):
                    p = np.empty(3)
                    p[list(perm)] = [sx, sy, sz]
                    pts.append(p)
    v = np.array(pts)
    hull = ConvexHull(v)
    faces = []
    for plane in np.unique(np.round(hull.equations, 9), axis=0):
        on = np.flatnonzero(np.abs(v @ plane[:3] + plane[3]) < 1e-9)
        c = v[on].mean(axis=0)
        e1 = v[on[0]] - c
        e2 = np.cross(plane[:3], e1)
        order = np.argsort(np.arctan2((v[on] - c) @ e2, (v[on] - c) @ e1))   # counter-clockwise from outside
        faces.append(on[order].tolist())
    return geoimg.Mesh(v, [f + [-1] * (4 - len(f)) for f in faces])


def icosphere(subdivisions: int = 2, bumps: float = 0.0) -> geoimg.Mesh:
    """A subdivided icosahedron on the unit sphere, outward-facing; ``bumps`` > 0 moves the vertices
    radially by ``bumps * sin(5x) sin(4y) sin(3z)`` (a bumpy blob)."""
    t = (1 + 5 ** 0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid, out = {}, []

        def middle(a, b, mid=mid):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[key] = len(v) - 1
            return mid[key]

        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            out += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = out
    v = np.array(v)
    if bumps:
        v = v * (1 + bumps * np.sin(5 * v[:, :1]) * np.sin(4 * v[:, 1:2]) * np.sin(3 * v[:, 2:]))
    return geoimg.Mesh(v, f)


def holey_sphere(holes: int = 5, unreferenced: int = 3) -> geoimg.Mesh:
    """An icosphere with ``holes`` faces far apart removed (that many boundary loops) and
    ``unreferenced`` extra vertices that no face uses (as scans often have)."""
    m = icosphere(2)
    centres = m.vertices[m.faces].mean(axis=1)
    chosen = [0]
    while len(chosen) < holes:       # farthest-point picks: holes that share no edge
        d = np.min(np.linalg.norm(centres[:, None] - centres[chosen][None], axis=2), axis=1)
        chosen.append(int(np.argmax(d)))
    keep = np.setdiff1d(np.arange(m.n_faces), chosen)
    v = np.vstack([m.vertices, np.full((unreferenced, 3), 2.0)])
    return geoimg.Mesh(v, m.faces[keep])


def three_pieces() -> geoimg.Mesh:
    """Three separate pieces: a hemisphere (1 loop), a sheet of quads (1 loop) and a closed
    tetrahedron, so 3 components and 2 boundary loops."""
    parts = [cap(90.0, 4, 12), quad_disk(4)]
    tet = geoimg.Mesh([[0, 0, 3], [1, 0, 3], [0, 1, 3], [0, 0, 4]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    parts.append(tet)
    vs, fs, base = [], [], 0
    for p in parts:
        f = np.where(p.faces >= 0, p.faces + base, -1)
        fs.append(np.pad(f, ((0, 0), (0, 4 - f.shape[1])), constant_values=-1))
        vs.append(p.vertices + [3.0 * len(vs), 0, 0])
        base += p.n_vertices
    return geoimg.Mesh(np.vstack(vs), np.vstack(fs))


def write(mesh: geoimg.Mesh, path) -> str:
    """Save a mesh to ``path`` (any writable format) and return the path as a string."""
    geoimg.save_mesh(mesh, path, overwrite=True)
    return str(path)


def mobius(segments: int = 12) -> geoimg.Mesh:
    """A Moebius strip: one side only, so no consistent orientation exists."""
    t = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    v = []
    for a in t:
        for s in (-1, 1):
            r = 1 + 0.3 * s * np.cos(a / 2)
            v.append([r * np.cos(a), r * np.sin(a), 0.3 * s * np.sin(a / 2)])
    f = []
    for i in range(segments):
        j = (i + 1) % segments
        b0, b1 = (2 * j, 2 * j + 1) if j else (1, 0)        # the strip's half-turn: the sides swap
        f += [[2 * i, b0, b1], [2 * i, b1, 2 * i + 1]]
    return geoimg.Mesh(np.array(v), f)


def torus_grid(n_major: int = 24, n_minor: int = 12, R: float = 1.0, r: float = 0.4) -> geoimg.Mesh:
    """A torus of n_major x n_minor quads split into triangles, outward-facing (genus 1)."""
    T, P = np.meshgrid(np.linspace(0, 2 * np.pi, n_major, endpoint=False),
                       np.linspace(0, 2 * np.pi, n_minor, endpoint=False), indexing="ij")
    v = np.stack([(R + r * np.cos(P)) * np.cos(T), (R + r * np.cos(P)) * np.sin(T), r * np.sin(P)], -1).reshape(-1, 3)
    i = np.arange(n_major * n_minor).reshape(n_major, n_minor)
    a, b, c, d = i, np.roll(i, -1, 0), np.roll(np.roll(i, -1, 0), -1, 1), np.roll(i, -1, 1)
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return geoimg.Mesh(v, faces)


def finger(segments: int = 24, rows: int = 30, length: float = 3.0, radius: float = 0.25,
           cap_rings: int = 6) -> geoimg.Mesh:
    """A tube open at one end with a rounded tip (a disk): what sticks out, which a mean-value map onto the
    square squeezes about geometrically along its length."""
    t = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    v = []
    for z in np.linspace(0, length, rows):
        v += [[radius * np.cos(a), radius * np.sin(a), z] for a in t]
    for k in range(1, cap_rings):
        phi = k / cap_rings * np.pi / 2
        v += [[radius * np.cos(phi) * np.cos(a), radius * np.cos(phi) * np.sin(a), length + radius * np.sin(phi)]
              for a in t]
    v.append([0.0, 0.0, length + radius])
    f = []
    rings = rows + cap_rings - 1
    for r in range(rings - 1):
        for i in range(segments):
            j = (i + 1) % segments
            a, b, c, d = r * segments + i, r * segments + j, (r + 1) * segments + j, (r + 1) * segments + i
            f += [[a, b, c], [a, c, d]]
    tip = len(v) - 1
    f += [[(rings - 1) * segments + i, (rings - 1) * segments + (i + 1) % segments, tip] for i in range(segments)]
    return geoimg.Mesh(np.array(v), f)


def outline_sheet(outline, n: int = 600, height=None, seed: int = 0) -> geoimg.Mesh:
    """A sheet over a closed 2-D ``outline`` ((K, 2) vertices, in order): the outline and ``n`` random points
    inside it, Delaunay-triangulated (faces of the convex hull outside the outline dropped), lifted by
    ``height(x, y)`` (flat by default): an irregular TIN whose outline is not a rectangle.
    """
    from scipy.spatial import Delaunay
    from skimage.measure import points_in_poly

    from geoimg.mesh._metrics import nearest_on_segments

    outline = np.asarray(outline, np.float64)
    rng = np.random.default_rng(seed)
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    pts = lo + rng.random((8 * n, 2)) * (hi - lo)
    segments = np.stack([outline, np.roll(outline, -1, axis=0)], axis=1)
    edge = np.min(np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1))
    _, gap, _ = nearest_on_segments(pts, segments, edge)
    pts = pts[points_in_poly(pts, outline) & (gap > 0.7 * edge)]       # inside, off the outline
    pts = np.vstack([outline, pts[:n]])
    tri = Delaunay(pts).simplices
    tri = tri[points_in_poly(pts[tri].mean(axis=1), outline)]
    used = np.unique(tri)
    remap = np.full(len(pts), -1)
    remap[used] = np.arange(len(used))
    xy = pts[used]
    z = np.zeros(len(xy)) if height is None else height(xy[:, 0], xy[:, 1])
    faces = remap[tri]
    a, b, c = (xy[faces[:, k]] for k in range(3))
    ccw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) > 0
    faces[~ccw] = faces[~ccw][:, ::-1]
    return geoimg.Mesh(np.column_stack([xy, z]), faces)


def petal(n: int = 600, seed: int = 0) -> geoimg.Mesh:
    """A petal: a pointed oval outline (narrow at its base, a notch at its tip), curled up across and along."""
    t = np.linspace(0.0, 2 * np.pi, 160, endpoint=False)
    r = 1.0 - 0.12 * np.exp(-((t - np.pi / 2) / 0.12) ** 2)             # the notch at the tip
    x = 0.45 * np.cos(t) * (1.0 - 0.5 * np.sin(t) ** 2) * r
    y = 0.5 + 0.5 * np.sin(t) * r
    return outline_sheet(np.column_stack([x, y]), n, lambda x, y: 0.6 * x ** 2 + 0.15 * y ** 2, seed)


def flat_disk(n: int = 600, seed: int = 0) -> geoimg.Mesh:
    """A flat unit disk, an irregular TIN."""
    t = np.linspace(0.0, 2 * np.pi, 96, endpoint=False)
    return outline_sheet(np.column_stack([np.cos(t), np.sin(t)]), n, None, seed)
