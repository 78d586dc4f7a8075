"""Distances between surfaces: exact closest points (libigl's AABB tree) against brute force, quads split
along their shorter diagonal, and the metrics."""
import numpy as np
import pytest

import geoimg
from geoimg.mesh import point_mesh_distance, surface_distance
from reference import point_triangle_distance
import meshes


def test_distances_are_exact_closest_points_as_brute_force_finds_them():
    """libigl's AABB tree against the numpy point-triangle distance over every triangle: points inside,
    beside edges, past corners, near large triangles next to small ones (where the nearest centres misled the
    old candidate search), and degenerate triangles (a repeated vertex, corners on a line)."""
    rng = np.random.default_rng(1)
    V = rng.normal(size=(300, 3))
    V[11] = V[10]
    V[20:23] = V[20] + np.outer([0, 1, 2], [1, 1, 1])
    V[290:293] = [[-20, -20, 0], [20, -20, 0], [0, 20, 0]]       # a huge triangle among small ones
    T = rng.integers(0, 300, size=(500, 3))
    T[0], T[1], T[2] = [10, 11, 12], [20, 21, 22], [290, 291, 292]
    mesh = geoimg.Mesh(V, T)
    P = rng.normal(size=(3000, 3)) * 2
    with np.errstate(invalid="ignore", divide="ignore"):
        ref = point_triangle_distance(P[:, None], V[T][None, :, 0], V[T][None, :, 1], V[T][None, :, 2])
    ref = np.nanmin(ref, axis=1)
    np.testing.assert_allclose(point_mesh_distance(P, mesh), ref, rtol=1e-9, atol=1e-12)


def test_quads_are_measured_split_along_their_shorter_diagonal():
    """A non-planar quad whose 1-3 diagonal (3.16) is shorter than the fan's 0-2 (3.32): split along 1-3 its
    half (0, 1, 3) is flat, so a point on it is at distance 0; split as a fan it would not be."""
    quad = geoimg.Mesh([[0, 0, 0], [3, 0, 0], [3, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    tris, _ = quad.triangulate(quads="shorter")
    assert sorted(map(sorted, tris.tolist())) == [[0, 1, 3], [1, 2, 3]]
    point = np.array([[1.0, 0.3, 0.0]])
    assert point_mesh_distance(point, quad)[0] < 1e-12
    fan = geoimg.Mesh(quad.vertices, quad.triangulate()[0])
    assert point_mesh_distance(point, fan)[0] > 0.05


def test_bad_arguments_are_geoimg_errors():
    square = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    with pytest.raises(geoimg.InputTypeError, match="mesh: expected a geoimg.Mesh"):
        point_mesh_distance(np.zeros((1, 3)), "square")
    with pytest.raises(geoimg.InputError, match="NaN or infinite"):
        point_mesh_distance(np.array([[np.nan, 0, 0]]), square)
    assert point_mesh_distance(np.zeros((0, 3)), square).shape == (0,)


def test_point_mesh_distance_of_a_unit_square():
    square = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    p = np.array([[0.5, 0.5, 2.0], [2.0, 0.5, 0.0], [-3.0, -4.0, 0.0], [0.25, 0.75, 0.0]])
    np.testing.assert_allclose(point_mesh_distance(p, square), [2.0, 1.0, 5.0, 0.0], atol=1e-15)


def test_surface_distance_of_a_shifted_copy():
    rng = np.random.default_rng(0)
    a = geoimg.grid_mesh(rng.random((20, 20)) * 0.1)
    b = geoimg.Mesh(a.vertices + [0, 0, 0.01], a.faces)
    d = surface_distance(a, b, n=5000)
    assert d["hausdorff"] == pytest.approx(0.01, rel=1e-6)
    assert d["psnr_db"] == pytest.approx(20 * np.log10(d["diagonal"] / 0.01), abs=0.05)
    assert surface_distance(a, a, n=2000)["psnr_db"] > 250          # rounding only


def test_the_triangle_tree_finds_libigls_distances():
    # point_mesh_distance descends geoimg's own bounding-volume hierarchy (about 0.4 of libigl's
    # time on an image's quad mesh): the same distances as libigl's AABB tree, to rounding, on a quad mesh of an
    # image, a random soup with slivers, triangles of no area (collinear corners, a repeated corner, one point),
    # and points on, near and far from the surfaces
    import igl
    import geoimg
    from geoimg.mesh._bvh import TriangleTree
    rng = np.random.default_rng(7)
    quads = geoimg.mesh_to_image(meshes.icosphere(2, bumps=0.1), 33, fidelity=False).to_mesh()
    soup_v = rng.normal(size=(300, 3))
    soup_t = rng.integers(0, 300, (400, 3))
    flat_v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [5, 5, 5]], float)
    flat_t = np.array([[0, 1, 2], [0, 0, 3], [4, 4, 4], [0, 1, 3]])
    cases = [(quads.vertices, quads.triangulate(quads="shorter")[0]), (soup_v, soup_t), (flat_v, flat_t),
             (soup_v, soup_t[:1])]
    for v, t in cases:
        scale = np.ptp(v, axis=0).max()
        on = v[t[:, 0]] * 0.3 + v[t[:, 1]] * 0.3 + v[t[:, 2]] * 0.4
        points = np.vstack([on, on + rng.normal(scale=1e-3 * scale, size=on.shape), rng.normal(size=(200, 3)) * 3
                            * scale, v])
        ours = TriangleTree(v, t).squared_distances(points)
        theirs, _, _ = igl.point_mesh_squared_distance(points, v, np.ascontiguousarray(t, np.int64))
        assert np.allclose(np.sqrt(ours), np.sqrt(np.maximum(theirs, 0)), rtol=1e-12, atol=1e-12 * scale)


def test_a_refitted_tree_finds_the_distances_of_a_tree_of_its_own():
    # a second image of the same grid gets the first one's hierarchy with its boxes made anew: the same
    # distances to the bit as a tree built for it, and exact even for triangles that lie nowhere near the
    # first ones (a shuffled soup: only slower); the first tree is left as it was
    from geoimg.mesh._bvh import TriangleTree
    rng = np.random.default_rng(3)
    first = geoimg.mesh_to_image(meshes.icosphere(2, bumps=0.1), 33, fidelity=False)
    second = geoimg.GeometryImage(first.pixels * 1.01 + 0.002, first.mask, first.domain)
    a, b = first.to_mesh(), second.to_mesh()
    ta, tb = a.triangulate(quads="shorter")[0], b.triangulate(quads="shorter")[0]
    tree = TriangleTree(a.vertices, ta)
    before = tree.squared_distances(b.vertices)
    points = np.vstack([b.vertices, rng.normal(size=(500, 3))])
    refitted = tree.refit(b.vertices, tb)
    assert np.array_equal(refitted.squared_distances(points), TriangleTree(b.vertices, tb).squared_distances(points))
    soup = rng.normal(size=(len(b.vertices), 3))
    shuffled = rng.permutation(len(tb))
    assert np.array_equal(tree.refit(soup, tb[shuffled]).squared_distances(points),
                          TriangleTree(soup, tb).squared_distances(points))
    assert np.array_equal(tree.squared_distances(b.vertices), before)
    with pytest.raises(ValueError, match="refit: 3 triangles for a tree of"):
        tree.refit(b.vertices, tb[:3])


def test_measuring_two_images_of_one_grid_in_turn_is_measuring_each_alone():
    # ReferenceDistances refits the first image's tree for the second (same faces), queries its samples in a
    # Morton order: every figure equals a fresh measurement's to the bit; without the other's vertices the RMS
    # and PSNR are the same and the Hausdorff distance is over fewer points (never larger)
    from geoimg.mesh._metrics import ReferenceDistances
    mesh = meshes.icosphere(2, bumps=0.1)
    first = geoimg.mesh_to_image(mesh, 33, fidelity=False)
    second = geoimg.GeometryImage(first.pixels * 1.01, first.mask, first.domain)
    against = ReferenceDistances(mesh, 3000)
    against.to(first.to_mesh())
    again = against.to(second.to_mesh())
    alone = ReferenceDistances(mesh, 3000).to(second.to_mesh())
    assert again == alone
    quick = ReferenceDistances(mesh, 3000).to(second.to_mesh(), vertices=False)
    assert (quick["rms"], quick["psnr_db"]) == (alone["rms"], alone["psnr_db"])
    assert quick["hausdorff"] <= alone["hausdorff"]


def test_the_closest_of_several_surfaces_is_measured_as_alone_and_the_first_wins_a_tie():
    # closest() measures each candidate by its samples and the winner's vertices last: its figures are a
    # fresh measurement's to the bit; the farther candidate loses whichever comes first; equals: the first
    from geoimg.mesh._metrics import ReferenceDistances
    mesh = meshes.icosphere(2, bumps=0.1)
    image = geoimg.mesh_to_image(mesh, 33, fidelity=False)
    near = image.to_mesh()
    far = geoimg.GeometryImage(image.pixels * 1.02, image.mask, image.domain).to_mesh()
    alone = ReferenceDistances(mesh, 3000).to(near)
    assert ReferenceDistances(mesh, 3000).closest([far, near]) == (1, alone)
    assert ReferenceDistances(mesh, 3000).closest([near, far]) == (0, alone)
    assert ReferenceDistances(mesh, 3000).closest([near, near])[0] == 0
    with pytest.raises(geoimg.errors.InputTypeError):
        ReferenceDistances(mesh, 3000).closest([near, "not a mesh"])


def test_surface_samples_are_numpys_uniform_triangle_samples():
    # the numba area and point kernels keep numpy's formulas to the bit: the areas behind the triangle
    # choice, then a + r1 (b - a) + r2 (c - a) with both folded where they sum over 1
    from geoimg.mesh import sample_surface
    rng = np.random.default_rng(5)
    v = rng.normal(size=(200, 3)) * 10.0 ** rng.uniform(-3, 3, (200, 1))
    t = rng.integers(0, 200, (400, 3))
    mesh = geoimg.Mesh(v, t)
    p = v[t]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    r = np.random.default_rng(0)
    k = r.choice(len(t), size=1000, p=area / area.sum())
    r1, r2 = r.random(1000), r.random(1000)
    flip = r1 + r2 > 1
    r1, r2 = np.where(flip, 1 - r1, r1), np.where(flip, 1 - r2, r2)
    expected = p[k, 0] + r1[:, None] * (p[k, 1] - p[k, 0]) + r2[:, None] * (p[k, 2] - p[k, 0])
    assert np.array_equal(sample_surface(mesh, 1000)[:1000], expected)


def test_a_surface_of_no_area_is_sampled_at_its_points():
    # every triangle flat (an image whose pixels all coincide): the samples are its points, picked alike,
    # not a division by zero or an index past the end
    from geoimg.mesh import sample_surface
    flat = geoimg.Mesh(np.array([[1.0, 2.0, 3.0]] * 4), [[0, 1, 2], [0, 2, 3]])
    points = sample_surface(flat, 50)
    assert points.shape == (54, 3) and (points == [1.0, 2.0, 3.0]).all()
    line = geoimg.Mesh(np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]), [[0, 1, 2]])
    d = surface_distance(line, line, n=100)
    assert d["hausdorff"] == 0.0 and np.isfinite(sample_surface(line, 10)).all()
