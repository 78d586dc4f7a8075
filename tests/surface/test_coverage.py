"""Coverage weights (``weights="coverage"``; linear precision is tested with the other weights in test_surface.py):
the mesh itself as the limit when s -> 0
(monotonically), truncated = exact, analytic derivatives = finite differences, on the plane and the sphere;
glued octahedral pixels; bad settings."""
import numpy as np
import pytest

import geoimg
from geoimg import fit_surface, parametrize
from geoimg.mesh import point_mesh_distance
from geoimg.surface import _coverage_kernels as ck
from geoimg.surface._coverage import _orientation, _quads_unfolded
from helpers import finite_differences, load_data, mixed_mesh
import meshes

AFFINE = np.array([[1.0, 0.5, -2.0], [0.3, -1.0, 0.7]])
OFFSET = np.array([0.2, -0.4, 1.5])


def affine_mesh():
    uv, faces = mixed_mesh(seed=3)
    return geoimg.Mesh(uv @ AFFINE + OFFSET, faces), geoimg.Parametrization(uv, (1.0, 1.0))


@pytest.fixture(scope="module")
def ball():
    mesh = meshes.icosphere(3, 0.3)
    return mesh, parametrize(mesh)


@pytest.mark.slow
def test_the_plane_surface_tends_to_the_mesh_itself_as_s_falls(mountain):
    """The terrain at random points: the largest distance to the mesh falls monotonically with s, about in
    proportion (only points within a few sigma of an edge move: the crease is rounded over sigma); at its
    vertices the surface is the mesh (the paper's weights plateau instead, at a few tenths of a face)."""
    param = parametrize(mountain, "heightfield", axis="y")
    rng = np.random.default_rng(5)
    pts = rng.uniform(0.05, 0.95, (2000, 2)) * param.extent
    far = []
    for s in (1.0, 0.5, 0.25, 0.1, 0.05, 0.02):
        surf = fit_surface(mountain, param, geoimg.CoverageWeights(s=s))
        far.append(point_mesh_distance(surf.evaluate(pts), mountain).max())
    assert all(a > b for a, b in zip(far, far[1:])), far
    assert far[-1] < 0.02 * far[0], far
    used = mountain.referenced_vertices()
    at_vertices = fit_surface(mountain, param, geoimg.CoverageWeights(s=0.02)).evaluate(param.coords[used])
    assert np.abs(at_vertices - mountain.vertices[used]).max() < 1e-9 * mountain.bounding_box_diagonal()


def test_the_sphere_surface_tends_to_the_mesh_itself_as_s_falls(ball):
    mesh, param = ball
    rng = np.random.default_rng(6)
    q = rng.normal(size=(3000, 3))
    far = []
    for s in (0.8, 0.4, 0.2, 0.1, 0.05, 0.02):
        surf = fit_surface(mesh, param, geoimg.CoverageWeights(s=s))
        far.append(point_mesh_distance(surf.evaluate_directions(q, derivatives=False)[0], mesh).max())
    assert all(a > b for a, b in zip(far, far[1:])), far
    assert far[-1] < 0.02 * far[0], far


@pytest.mark.parametrize("s", [0.1, 1.0])
def test_truncated_equals_exact(mountain, ball, s):
    param = parametrize(mountain, "heightfield", axis="y")
    surf = fit_surface(mountain, param, geoimg.CoverageWeights(s=s))
    pts = np.random.default_rng(3).uniform(0, 1, (300, 2)) * param.extent
    diag = mountain.bounding_box_diagonal()
    assert np.abs(surf.evaluate(pts) - surf.evaluate(pts, exact=True)).max() <= 1e-8 * diag
    assert np.abs(fit_surface(mountain, param, geoimg.CoverageWeights(s=s, tol=0)).evaluate(pts) -
                  surf.evaluate(pts, exact=True)).max() == 0.0
    mesh, sparam = ball
    sphere = fit_surface(mesh, sparam, geoimg.CoverageWeights(s=s))
    q = np.random.default_rng(4).normal(size=(300, 3))
    a = sphere.evaluate_directions(q)
    b = sphere.evaluate_directions(q, exact=True)
    assert (b[5] == ck.EXACT).all() and (a[5] == ck.TRUNCATED).all()
    for x, y in zip(a[:3], b[:3]):
        assert np.abs(x - y).max() <= 1e-8 * max(1.0, np.abs(y).max())


@pytest.mark.parametrize("s", [0.1, 1.0])
def test_analytic_derivatives_match_finite_differences(mountain, ball, s):
    param = parametrize(mountain, "heightfield", axis="y")
    surf = fit_surface(mountain, param, geoimg.CoverageWeights(s=s))
    pts = np.random.default_rng(4).uniform(0.1, 0.9, (80, 2))
    pu, pv = surf.derivatives(pts)
    fu, fv = finite_differences(surf, pts, h=1e-7)
    scale = np.abs(pu).max()
    assert np.abs(pu - fu).max() < 1e-4 * scale and np.abs(pv - fv).max() < 1e-4 * scale
    assert np.all(surf.normals(pts)[:, 1] > 0)             # y up
    mesh, sparam = ball
    sphere = fit_surface(mesh, sparam, geoimg.CoverageWeights(s=s))
    q = np.random.default_rng(7).normal(size=(60, 3))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    P, P1, P2, t1, t2, _ = sphere.evaluate_directions(q)
    h = 1e-7
    for t, D in ((t1, P1), (t2, P2)):
        fd = (sphere.evaluate_directions(q + h * t)[0] - sphere.evaluate_directions(q - h * t)[0]) / (2 * h)
        assert np.abs(fd - D).max() < 1e-4 * np.abs(D).max()


def test_an_octahedral_image_welds_watertight_and_keeps_its_input(ball):
    mesh, param = ball
    before = mesh.vertices.copy(), param.coords.copy()
    img = fit_surface(mesh, param, geoimg.CoverageWeights(s=0.2)).sample(33)
    quads = img.to_mesh()
    assert geoimg.mesh.topology(quads).closed and geoimg.mesh.topology(quads).genus == 0
    assert np.array_equal(mesh.vertices, before[0]) and np.array_equal(param.coords, before[1])
    normals = img.normals.reshape(-1, 3)
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)


def test_log_ndtr_is_finite_far_out():
    from scipy.special import log_ndtr
    for z in (-1e3, -200.0, -40.0, -37.0, -36.9, -5.0, 0.0, 3.0, 40.0):
        assert ck.log_ndtr(z) == pytest.approx(float(log_ndtr(z)), rel=1e-12, abs=1e-300)


def test_points_outside_a_planar_mesh_are_summed_exactly_over_its_border():
    mesh, param = affine_mesh()
    surf = fit_surface(mesh, param, geoimg.CoverageWeights(s=0.05))
    far = np.array([[3.0, 3.0], [-2.0, 0.5], [0.5, 1.5]])
    _, _, _, status = surf._points(far, False)
    assert (status == ck.EXACT).all()
    assert np.allclose(surf.evaluate(far), far @ AFFINE + OFFSET, atol=1e-9)      # linear precision still


@pytest.mark.parametrize("s, message", [(np.ones(3), "one number"), (0.0, "from 1e-06"), (1e4, "from 1e-06"),
                                        (np.nan, "from 1e-06"), ("1", "one number"), (True, "one number")])
def test_bad_smoothness_is_refused(s, message):
    mesh, param = affine_mesh()
    with pytest.raises(geoimg.InputError, match=message):
        fit_surface(mesh, param, geoimg.CoverageWeights(s=s))


def test_cuda_is_refused_for_coverage_weights():
    mesh, param = affine_mesh()
    with pytest.raises(geoimg.InputError, match="CPU only|no CUDA|not usable|cuda"):
        fit_surface(mesh, param, geoimg.CoverageWeights(s=0.5)).sample(9, backend="cuda")


def test_the_kernel_equals_its_numpy_twin(ball):
    from reference import coverage_numpy
    mesh, param = affine_mesh()
    bumpy = geoimg.Mesh(np.column_stack([mesh.vertices[:, :2], np.sin(7 * param.coords[:, 0])]), mesh.faces)
    for surf, pts in ((fit_surface(bumpy, param, geoimg.CoverageWeights(s=0.3)),
                       np.column_stack([np.random.default_rng(8).uniform(0, 1, (200, 2)), np.ones(200)])),
                      (fit_surface(*ball, geoimg.CoverageWeights(s=0.3)),
                       np.random.default_rng(9).normal(size=(200, 3)))):
        if pts[0, 2] != 1.0:
            pts /= np.linalg.norm(pts, axis=1, keepdims=True)
        _, K, w = surf.tables
        ref = coverage_numpy(pts, surf.edges(), K, w, 1.0)          # edges over each triangle's own width
        got = surf._evaluate(pts, pts * 0, pts * 0, derivatives=False)[0]
        assert np.abs(got - ref).max() < 1e-9 * np.abs(ref).max()


def test_triangles_thinner_than_rounding_are_left_out_and_nothing_overflows():
    # a sliver whose third corner lies 1e-13 off its base in (u, v), but far off it in space: its map is
    # huge, its inradius rounds to 0 (a width of nothing); beside it an ordinary triangle
    v = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0, 1.0], [0.5, -1, 0]])
    uv = np.array([[0, 0.5], [1, 0.5], [0.5, 0.5 + 1e-13], [0.5, 0.0]])
    mesh = geoimg.Mesh(v, [[0, 1, 2], [1, 0, 3]])
    param = geoimg.Parametrization(uv, (1.0, 1.0))
    with pytest.warns(UserWarning, match="1 triangles of zero area"):
        surf = fit_surface(mesh, param, geoimg.CoverageWeights(s=0.05))
    P = surf.evaluate(np.array([[0.5, 0.25], [0.5, 0.5], [0.2, 0.9]]))
    assert np.isfinite(P).all()
    assert np.allclose(P[0], [0.5, -0.5, 0.0], atol=1e-6)            # inside the ordinary triangle: its plane


def test_a_texture_is_read_from_the_part_its_coordinates_reach():
    import cv2
    from geoimg.surface._attributes import _texture_lookup
    rng = np.random.default_rng(0)
    tex = rng.integers(0, 256, (30, 50, 3), dtype=np.uint8)
    for lo, hi in [(0.2, 0.4), (0.0, 1.0), (-0.2, 0.3)]:              # cropped, whole, wrapped
        uv = rng.uniform(lo, hi, (3000, 2))
        x = (uv[:, 0] * 50 - 0.5).astype(np.float32)[None]
        y = ((1 - uv[:, 1]) * 30 - 0.5).astype(np.float32)[None]
        whole = cv2.remap(tex.astype(np.float32), x, y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)[0] / 255.0
        np.testing.assert_array_equal(_texture_lookup(tex, uv), whole.astype(np.float32))


def test_the_sphere_cells_list_every_triangle_where_it_counts_and_change_no_sample(ball):
    """The cells leave a triangle out of a cube only where one of its edge functions is below the cut-off
    throughout, or off the unit sphere: every triangle whose terms count at a unit point (its edge functions
    above the cut-off, the point in front of it) is in the point's cube, and the samples are the same bits as
    with the plain balls' cells."""
    from geoimg.surface._cells import build_cells_3d
    mesh, param = ball
    surf = fit_surface(mesh, param, geoimg.CoverageWeights(s=0.3))
    h, n, ptr, faces = surf.cells()
    E, zmin = surf.edges(), surf._zmin()
    q = np.random.default_rng(4).normal(size=(3000, 3))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    z = np.einsum("tec,kc->kte", E, q)                          # (points, triangles, edges)
    w = surf.tables[2]                                          # the kernel's other cut: w . p > WMIN
    counts = (z > zmin).all(axis=2) & (q @ w.T > ck.WMIN)
    idx = np.clip(np.floor((q + 1.0) / h).astype(int), 0, n - 1)
    cell = (idx[:, 2] * n + idx[:, 1]) * n + idx[:, 0]
    for k in range(len(q)):
        listed = set(faces[ptr[cell[k]]:ptr[cell[k] + 1]].tolist())
        assert set(np.flatnonzero(counts[k]).tolist()) <= listed
    plain = build_cells_3d(surf.centres, np.minimum(surf._reach(), 4.0))
    assert len(faces) < len(plain[3])                           # fewer candidates ...
    directions = surf.domain.directions(33).reshape(-1, 3)
    from geoimg.surface._cells import tangent_frames
    t1, t2 = tangent_frames(directions)
    tight = surf._evaluate(directions, t1, t2)
    object.__setattr__(surf, "_cells", plain)
    loose = surf._evaluate(directions, t1, t2)
    for a, b in zip(tight, loose):                              # ... the same sums
        np.testing.assert_array_equal(a, b)


def test_a_quad_its_shorter_split_would_fold_is_split_the_other_way():
    # a dart in (u, v), its reflex corner 2 raised: the shorter diagonal in space (1-3) runs outside the dart,
    # so that split turns a triangle over in the parameter domain and the surface's triangles would overlap
    v = np.array([[0.0, 0.0, -3.0], [2.0, 0.0, 0.0], [0.5, 0.5, 3.0], [0.0, 2.0, 0.0]])
    mesh = geoimg.Mesh(v, [[0, 1, 2, 3]])
    tris, owner = mesh.triangulate("shorter")
    assert sorted(map(sorted, tris.tolist())) == [[0, 1, 3], [1, 2, 3]]
    p = parametrize(mesh, "heightfield", axis="z")
    fixed = _quads_unfolded(mesh, tris, owner, p.coords)
    assert sorted(map(sorted, fixed.tolist())) == [[0, 1, 2], [0, 2, 3]]
    o = _orientation(p.coords, fixed)
    assert (o > 0).all() or (o < 0).all()
    img = geoimg.mesh_to_image(mesh, 33, parametrization=p, fidelity=False, weights=geoimg.CoverageWeights(s=1e-4))
    u, w = img.domain.pixel_uv(img.pixels.shape[:2])
    uv = np.stack(np.meshgrid(u, w), axis=-1)
    inside = np.zeros(uv.shape[:2], bool)                  # a pixel spacing within one of the two triangles
    for t in fixed:
        a, b, c = p.coords[t]
        lam = np.linalg.solve(np.array([b - a, c - a]).T, (uv - a).reshape(-1, 2).T).T.reshape(uv.shape)
        inside |= (lam.min(axis=-1) > 0.1) & (lam.sum(axis=-1) < 0.9)
    assert inside.sum() > 50
    assert point_mesh_distance(img.pixels[inside], geoimg.Mesh(v, fixed)).max() < 1e-6


def _brute_force(surf, q, t1, t2):
    """The truncated sum over every triangle (one cell holding them all), in ascending order."""
    E, K, w = (surf.edges(),) + tuple(surf.tables[1:])
    T = len(E)
    every = (4.0, 1, np.array([0, T], np.int64), np.arange(T, dtype=np.int64))
    return ck.evaluate_coverage(q, t1, t2, (E, K, w), every, np.arange(T), zmin=surf._zmin(),
                                floor=1e4 * surf.tol)


@pytest.fixture(scope="module")
def coarse_spheres(ball):
    """Sphere maps whose triangles are large on the sphere (the old cells' reach fell short on them): the
    scorpion's 496 triangles, the fish's 112-face cage, and the 8 faces of an octahedron turned off the axes."""
    out = [("ball", *ball)]
    for name in ("scorpion_low_resolution.obj", "fish_control_mesh.obj"):
        mesh = load_data(name)
        out.append((name, mesh, parametrize(mesh, "sphere")))
    v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    v = v @ np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])     # a rotation
    faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    octa = geoimg.Mesh(v * [1.0, 2.0, 0.5], faces)
    out.append(("octahedron", octa, geoimg.Parametrization(v, (1.0, 1.0), "octahedral", "sphere")))
    return out


@pytest.mark.parametrize("res, s", [(33, 0.3), (65, None), (129, None)])
def test_the_octahedral_image_sums_every_triangle_that_counts_in_order(coarse_spheres, res, s):
    """Images are swept triangle by triangle over each octant's share of their boxes: every pixel gets the
    terms of every triangle whose edge functions pass the cut-off there, in ascending order, so its point is
    the brute-force truncated sum's to the bit, and its normal (from derivatives along the image's axes) the
    brute force's (along tangent frames) within rounding."""
    from geoimg.surface._coverage import prefilter_s
    from geoimg.surface._grid import unit_normals
    from geoimg.surface._cells import tangent_frames
    for name, mesh, param in coarse_spheres:
        base = fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
        surf = base.with_s(prefilter_s(base, res) if s is None else s)
        image = surf.sample(res)
        q = surf.domain.directions(res).reshape(-1, 3)
        t1, t2 = tangent_frames(q)
        P, D1, D2, _ = _brute_force(surf, q, t1, t2)
        np.testing.assert_array_equal(image.pixels.reshape(-1, 3), P.astype(image.pixels.dtype), err_msg=name)
        normals = unit_normals(D1, D2, surf.orientation)
        np.testing.assert_allclose(image.normals.reshape(-1, 3), normals, atol=1e-6, err_msg=name)


def test_the_sphere_points_path_reaches_every_triangle_that_counts(coarse_spheres):
    """Points looked up in the 3-D cells get the same sums as the brute force on meshes with large triangles
    (the planar reach rule left out triangles whose weight was 0.007: points 0.0095 off on the scorpion)."""
    from geoimg.surface._coverage import prefilter_s
    from geoimg.surface._cells import tangent_frames
    q = np.random.default_rng(7).normal(size=(4000, 3))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    t1, t2 = tangent_frames(q)
    for name, mesh, param in coarse_spheres:
        base = fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
        surf = base.with_s(prefilter_s(base, 257))
        P = surf.evaluate_directions(q)[0]
        np.testing.assert_allclose(P, _brute_force(surf, q, t1, t2)[0], rtol=0, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("n", [3, 5, 9, 33])
def test_octant_rows_partition_the_image_as_its_owners_do(n):
    """Each pixel belongs to exactly one octant, the one its row ranges give (:func:`_octant_row`) and
    :func:`octant_owners` names, and that octant's affine unfolding gives its direction."""
    owners = ck.octant_owners(n)
    d = geoimg.OctahedralDomain().directions(n)
    seen = np.zeros((n, n), int)
    for oc in range(8):
        o0, oa, ob, _ = ck._octant(oc)
        for i in range(n):
            j0, j1 = ck._octant_row(oc, i, n - 1)
            seen[i, j0:j1] += 1
            assert (owners[i, j0:j1] == oc).all() and (owners[i, :j0] != oc).all() and (owners[i, j1:] != oc).all()
            for j in range(j0, j1):
                a, b = (2 * j - (n - 1)) / (n - 1), (2 * i - (n - 1)) / (n - 1)
                o = np.array(o0) + a * np.array(oa) + b * np.array(ob)
                np.testing.assert_allclose(o / np.linalg.norm(o), d[i, j], atol=1e-15)
    assert (seen == 1).all()


def test_octant_sides_bound_the_octants_triangles():
    """Each octant's three sides hold (>= 0) on its triangle and vanish at the two corners each passes through."""
    for oc in range(8):
        corners = np.array(ck._octant(oc)[3]).reshape(3, 2)
        g = ck._OCTANT_SIDES[oc][:, :1] + ck._OCTANT_SIDES[oc][:, 1:] @ corners.T       # (sides, corners)
        assert (g >= 0).all() and ((g == 0).sum(axis=1) == 2).all()
        centre = corners.mean(axis=0)
        assert (ck._OCTANT_SIDES[oc][:, 0] + ck._OCTANT_SIDES[oc][:, 1:] @ centre > 0).all()


def _polygon_box(pa, pb, m):
    return np.array([pa[:m].min(), pa[:m].max(), pb[:m].min(), pb[:m].max()]) if m else None


def test_the_reach_polygon_from_the_edges_triangle_is_the_octants_triangle_clipped(coarse_spheres):
    """Where a triangle's edges meet in a triangle, the reach polygon is found by clipping that triangle by the
    octant's sides (the shortcut); the same polygon as the octant's triangle clipped by the four half-planes,
    on meshes whose triangles cross octants (and the shortcut is taken on most of them)."""
    from geoimg.surface._coverage import prefilter_s
    buf = [np.empty(ck._VERTS) for _ in range(4)]
    taken = compared = 0
    for name, mesh, param in coarse_spheres:
        base = fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
        for res in (33, 257):
            surf = base.with_s(prefilter_s(base, res))
            E, w, zmin = surf.edges(), surf.tables[2], surf._zmin()
            near = ck._near_all(E, w, zmin)
            for t in range(0, len(E), max(1, len(E) // 300)):
                for oc in np.flatnonzero(np.unpackbits(near[t:t + 1], bitorder="little")):
                    corners = ck._octant(oc)[3]
                    for big in (1.0, 0.8):
                        H = np.empty((4, 3))
                        ck._half_planes(t, oc, E, w, zmin, big, H)
                        if not ck._edges_triangle(H, buf[0], buf[1]):
                            continue
                        taken += 1
                        m = ck._reach_in_octant(oc, H, corners, *buf)
                        shortcut = _polygon_box(buf[0], buf[1], m)
                        buf[0][:3], buf[1][:3] = corners[0::2], corners[1::2]
                        m = ck._clip_by(buf[0], buf[1], 3, H, 4, buf[2], buf[3])
                        clipped = _polygon_box(buf[0], buf[1], m)
                        assert (shortcut is None) == (clipped is None), (name, t, oc)
                        if clipped is not None:
                            compared += 1
                            np.testing.assert_allclose(shortcut, clipped, rtol=0, atol=1e-12, err_msg=name)
    assert compared > 500 and taken > compared


@pytest.mark.parametrize("res", [33, 129])
def test_the_planar_image_sums_every_triangle_that_counts_in_order(mountain, res):
    """Planar images, swept triangle by triangle over each one's box, give every pixel the brute-force truncated
    sum's point to the bit, on the terrain grid and on an irregular mixed mesh (rim pixels off the mesh's
    boundary at the boundary point they snap to)."""
    from geoimg.surface._coverage import prefilter_s
    from geoimg.surface._coverage_rim import snap_rim
    uv, faces = mixed_mesh(seed=3)
    irregular = geoimg.Mesh(np.column_stack([uv, np.sin(3 * uv[:, 0]) * uv[:, 1]]), faces)
    for mesh, param in ((mountain, parametrize(mountain, "heightfield")),
                        (irregular, geoimg.Parametrization(uv, (1.0, 1.0)))):
        base = fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
        surf = base.with_s(prefilter_s(base, res))
        image = surf.sample(res)
        u, v = surf.domain.pixel_uv(image.pixels.shape[:2])
        uu, vv = np.meshgrid(u, v)
        rows, cols, to = snap_rim(image.mask, u, v, surf.rim)
        uu[rows, cols], vv[rows, cols] = to[:, 0], to[:, 1]
        k = uu.size
        points = np.column_stack([uu.ravel(), vv.ravel(), np.ones(k)])
        E, K, w = (surf.edges(),) + tuple(surf.tables[1:])
        every = (4.0, 1, np.array([0, len(E)], np.int64), np.arange(len(E), dtype=np.int64))
        P = ck.evaluate_coverage(points, np.tile([1.0, 0.0, 0.0], (k, 1)), np.tile([0.0, 1.0, 0.0], (k, 1)),
                                 (E, K, w), every, surf.fallback, zmin=surf._zmin(), floor=1e4 * surf.tol)[0]
        np.testing.assert_array_equal(image.pixels.reshape(-1, 3), P.astype(image.pixels.dtype))


def test_the_edge_table_is_phi_and_its_slope_is_the_interpolants():
    """The table's cubic pieces lie within 1e-13 of Phi, and the slope it gives is the derivative of the value
    it gives (central differences), so the surface's derivatives are those of the surface evaluated."""
    import math
    z = np.linspace(-9.0, 9.0, 20011)
    cdf = np.array([ck._edge(x, 8.0, True, ck.TABLE)[0] for x in z])
    assert np.abs(cdf - np.array([0.5 * math.erfc(-x / math.sqrt(2.0)) for x in z])).max() < 1e-13
    h = 1e-6
    for x in np.linspace(-7.9, 7.9, 97):
        c, r = ck._edge(x, 8.0, True, ck.TABLE)
        fd = (ck._edge(x + h, 8.0, False, ck.TABLE)[0] - ck._edge(x - h, 8.0, False, ck.TABLE)[0]) / (2 * h)
        assert abs(c * r - fd) < 1e-9        # the differences err by about 1e-16 / h


@pytest.mark.slow
def test_the_exact_sum_leaves_out_only_terms_that_underflow():
    # far from the mesh (a charts image's gutters) the truncated sum cannot certify a point, which is summed over
    # every triangle in the log domain; a triangle whose bound lies 800 below the largest log weight is skipped
    from scipy.special import log_ndtr
    mesh = load_data("bob_tri.obj")
    param = parametrize(mesh)
    surf = fit_surface(mesh, param, geoimg.CoverageWeights(s=0.01))
    E, K, w = surf.edges(), surf.tables[1], surf.tables[2]
    rng = np.random.default_rng(3)
    uv = rng.uniform(-0.5, 1.5, (300, 2)) * np.asarray(surf.domain.extent)
    pts = np.column_stack([surf._uv(uv), np.ones(len(uv))])
    lf = log_ndtr(np.einsum("tkc,pc->ptk", E, pts)).sum(axis=2)          # (points, triangles)
    bound = np.array([[ck._log_weight_bound(t, p, E) for t in range(0, len(E), 7)] for p in pts[:40]])
    assert (bound >= lf[:40, ::7]).all()
    # the exact sum (over every triangle) against its plain twin in the log domain
    fb = np.arange(len(E))
    wp = pts @ w[fb].T
    L = np.where(wp > ck.WMIN, lf[:, fb], -np.inf)
    F = np.exp(L - L.max(axis=1, keepdims=True))
    P = np.einsum("tic,pc->pti", K[fb], pts) / np.where(wp > ck.WMIN, wp, 1.0)[..., None]
    ref = (F[..., None] * P).sum(axis=1) / F.sum(axis=1)[:, None]
    got = surf.evaluate(uv, exact=True)
    diag = np.linalg.norm(np.ptp(mesh.vertices, axis=0))
    assert np.isfinite(ref).all() and np.abs(got - ref).max() < 1e-9 * diag
    far = (uv < 0).any(axis=1) | (uv > np.asarray(surf.domain.extent)).any(axis=1)
    assert far.sum() > 100 and (L.max(axis=1) - L.min(axis=1))[far].max() > 800     # terms that were left out


def test_planar_cells_hold_the_layer_of_their_points_alone():
    # a planar surface is evaluated at homogeneous (u, v, 1) only: its cells fill the one layer of cubes that
    # holds z = 1, with the very lists the cells of every layer have there, and nothing elsewhere
    from geoimg.surface._cells import build_cells_3d
    from helpers import MOUNTAIN
    terrain = geoimg.load_mesh(MOUNTAIN)
    surf = fit_surface(terrain, parametrize(terrain, "heightfield"), geoimg.CoverageWeights(s=0.5))
    assert surf.POINTS_Z == 1.0
    h, n, ptr, faces = surf.cells()
    kw = {"planes": surf.edges(), "floor": surf._zmin()}
    h2, n2, ptr2, faces2 = build_cells_3d(surf.centres, np.minimum(surf._reach(), 4.0), **kw)
    assert (h, n) == (h2, n2) and len(faces) < len(faces2)
    layer = min(int(np.floor(2.0 / h)), n - 1)
    for cell in range(n ** 3):
        mine = faces[ptr[cell]:ptr[cell + 1]]
        if cell // (n * n) == layer:
            np.testing.assert_array_equal(mine, faces2[ptr2[cell]:ptr2[cell + 1]])
        else:
            assert len(mine) == 0


@pytest.mark.parametrize("planar", [True, False])
def test_the_slopes_closed_form_equals_the_largest_singular_value(planar):
    # each triangle's stretch, in closed form, against LAPACK's: pinv of the parameter edges, then the 2-norm;
    # random triangles, a tenth of them needles (one edge 1e-6 of the others), left unchanged
    from geoimg.surface._coverage import _slopes
    rng = np.random.default_rng(7)
    corners = rng.normal(size=(400, 3, 2 if planar else 3))
    corners[::10, 2] = corners[::10, 1] + 1e-6 * rng.normal(size=corners[::10, 2].shape)
    xyz = rng.normal(size=(400, 3, 3))
    before = corners.copy(), xyz.copy()
    got = _slopes(corners, xyz, planar)
    B = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=2)
    A = np.stack([xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0]], axis=2)
    want = np.linalg.norm(A @ np.linalg.pinv(B), ord=2, axis=(1, 2))
    assert np.allclose(got, want, rtol=1e-8, atol=0) and np.allclose(got[1::10], want[1::10], rtol=1e-12)
    assert np.array_equal(before[0], corners) and np.array_equal(before[1], xyz)
