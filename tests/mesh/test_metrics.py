"""Distances between surfaces: the numba point-to-triangle kernel against its numpy twin, and the metrics."""
import numpy as np
import pytest

import geoimg
from geoimg.mesh import point_mesh_distance, surface_distance
from geoimg.mesh._distance_kernels import nearest_triangle_distances
from reference import point_triangle_distance


def test_kernel_equals_the_numpy_twin_in_every_region_and_on_degenerate_triangles():
    rng = np.random.default_rng(1)
    V = rng.normal(size=(300, 3))
    V[11] = V[10]                                              # a repeated vertex
    V[20:23] = V[20] + np.outer([0, 1, 2], [1, 1, 1])          # corners on a line
    T = rng.integers(0, 300, size=(500, 3))
    T[0], T[1], T[2] = [10, 11, 12], [20, 21, 22], [5, 5, 5]
    P = rng.normal(size=(3000, 3)) * 2                        # inside, beside edges, past corners
    C = rng.integers(0, 500, size=(3000, 8))
    C[:, 0] = rng.integers(0, 3, 3000)                         # every point also sees a degenerate triangle
    with np.errstate(invalid="ignore"):
        ref = point_triangle_distance(P[:, None], V[T[C][..., 0]], V[T[C][..., 1]], V[T[C][..., 2]]).min(axis=1)
    got = nearest_triangle_distances(P, V, T.astype(np.int64), C.astype(np.int64))
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12)


def test_degenerate_triangles_measure_to_their_edges_without_dividing_by_zero():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 0]])
    tris = np.array([[0, 1, 2], [0, 0, 0], [0, 3, 1]])          # a segment, a point, a segment
    pts = np.array([[2.0, 0, 0], [0.5, 1, 0], [-1, 0, 0]])
    for t in range(3):
        got = nearest_triangle_distances(pts, v, tris, np.full((3, 1), t))
        want = [2.0, np.hypot(0.5, 1), 1.0] if t == 1 else [1.0, 1.0, 1.0]
        np.testing.assert_allclose(got, want, atol=1e-15)


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
