
import numpy as np
import geoimg
import pytest

from geoimg import Mesh, Parametrization, fit_surface, parametrize
from geoimg.surface import make_weights
from reference import evaluate_exact_numpy, sample_grid_numpy

from checks import surface_to_vertices_rms
import meshes
from helpers import data_file, finite_differences, mixed_mesh

AFFINE = np.array([[2.0, -1.0, 0.5], [0.3, 4.0, -2.0]])   # rows: dP/du, dP/dv
OFFSET = np.array([10.0, -3.0, 7.0])


def affine_mesh(seed=0, n=7):
    uv, faces = mixed_mesh(seed, n)
    return Mesh(uv @ AFFINE + OFFSET, faces), Parametrization(uv, (1.0, 1.0))


def test_mixed_mesh_has_triangles_quads_and_hexagons():
    mesh, _ = affine_mesh()
    assert set(mesh.face_sizes.tolist()) == {3, 4, 6}


@pytest.mark.parametrize("weights, s", [("gaussian", 0.5), ("gaussian", 1.0), ("gaussian", 3.0), ("local", 1.0),
                                       ("coverage", 0.05), ("coverage", 0.5), ("coverage", 3.0)])
@pytest.mark.parametrize("sliver_rule", ["robust", "paper"])
def test_linear_precision_on_irregular_polygon_mesh(weights, s, sliver_rule):
    mesh, param = affine_mesh()
    surf = fit_surface(mesh, param, make_weights(weights, s=s, n=6, sliver_rule=sliver_rule))
    rng = np.random.default_rng(2)
    pts = np.concatenate([rng.uniform(0, 1, (300, 2)), [[0, 0], [1, 1], [0.5, -0.1]]])
    assert np.allclose(surf.evaluate(pts), pts @ AFFINE + OFFSET, rtol=0, atol=1e-10)
    pu, pv = surf.derivatives(pts)
    assert np.allclose(pu, AFFINE[0], atol=1e-9) and np.allclose(pv, AFFINE[1], atol=1e-9)
    img = surf.sample(33)
    u, v = surf.grid(33)
    uu, vv = np.meshgrid(u, v)
    expected = np.stack([uu, vv], axis=-1) @ AFFINE + OFFSET
    assert np.allclose(img.pixels, expected, atol=1e-4)   # float32 pixels
    assert img.mask.all()


@pytest.mark.parametrize("s", [1.0, 4.0])
def test_truncated_equals_exact_on_a_real_terrain(mountain, s):
    param = parametrize(mountain, "heightfield", axis="y")
    surf = fit_surface(mountain, param, geoimg.GaussianWeights(s=s))
    rng = np.random.default_rng(3)
    pts = rng.uniform(0, 1, (400, 2)) * param.extent
    diag = mountain.bounding_box_diagonal()
    truncated = surf.evaluate(pts)
    exact = surf.evaluate(pts, exact=True)
    assert np.abs(truncated - exact).max() <= 1e-9 * diag
    # the exact numba sum agrees with a plain numpy log-domain sum
    fm = surf.faces
    ref = evaluate_exact_numpy(pts[:20], fm.centres, surf.sigma, fm.C, fm.A, fm.B)
    assert np.abs(exact[:20] - ref).max() <= 1e-12 * diag
    # and with tol=0 the grid sampler is exact too
    exact_surf = fit_surface(mountain, param, geoimg.GaussianWeights(s=s, tol=0))
    u, v = surf.grid(17)
    uu, vv = np.meshgrid(u, v)
    grid_pts = np.stack([uu.ravel(), vv.ravel()], axis=1)
    assert np.abs(exact_surf.sample(17).pixels.reshape(-1, 3) - exact_surf.evaluate(grid_pts)).max() <= 1e-5 * diag


@pytest.mark.parametrize("sliver_rule", ["robust", "paper"])
def test_surface_converges_to_the_mesh_as_s_shrinks(sliver_rule):
    # an octahedral hemisphere: its projection squeezes the rim's triangles, so it plateaus from s ~ 0.5
    # on (tests/test_real_meshes.py holds the terrain and pmp's hemisphere.off to the finer steps down to s = 0.25)
    rms = surface_to_vertices_rms(meshes.octa_hemisphere(20), (2.0, 1.0, 0.5), sliver_rule)
    assert all(a > 1.5 * b for a, b in zip(rms, rms[1:])), rms
    assert rms[-1] < 0.3 * rms[0]


@pytest.mark.parametrize("weights", ["gaussian", "local"])
def test_analytic_derivatives_match_finite_differences(mountain, weights):
    param = parametrize(mountain, "heightfield", axis="y")
    surf = fit_surface(mountain, param, make_weights(weights, s=1.5, n=12))
    rng = np.random.default_rng(4)
    pts = rng.uniform(0.1, 0.9, (50, 2))
    pu, pv = surf.derivatives(pts)
    fu, fv = finite_differences(surf, pts)
    scale = np.abs(pu).max()
    assert np.abs(pu - fu).max() < 1e-5 * scale and np.abs(pv - fv).max() < 1e-5 * scale
    n = surf.normals(pts)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert np.all(n[:, 1] > 0)  # y-up terrain: normals point up


def test_numba_grid_kernel_equals_numpy_baseline(mountain_surface):
    surf = mountain_surface
    u, v = surf.grid(48)
    fm = surf.faces
    P_np, S_np = sample_grid_numpy(u, v, fm.centres, surf.sigma, surf._radius, fm.C, fm.A, fm.B)
    img = surf.sample(48)
    assert np.abs(img.pixels - P_np).max() <= 1e-5 * np.abs(P_np).max()  # float32 rounding only
    assert (S_np >= surf.g_ref).all()


def test_grid_sampler_agrees_with_point_evaluation(mountain_surface):
    img = mountain_surface.sample(40)
    u, v = mountain_surface.grid(40)
    uu, vv = np.meshgrid(u, v)
    pts = np.stack([uu.ravel(), vv.ravel()], axis=1)
    assert np.allclose(img.pixels.reshape(-1, 3), mountain_surface.evaluate(pts), atol=1e-4)
    assert np.allclose(img.normals.reshape(-1, 3), mountain_surface.normals(pts), atol=1e-5)


def test_far_points_and_tiny_s_give_finite_values():
    mesh, param = affine_mesh()
    for s in (1.0, 0.02):
        surf = fit_surface(mesh, param, geoimg.GaussianWeights(s=s))
        far = np.array([[1e3, -1e3], [50.0, 0.5], [-7.0, 2.0]])
        p = surf.evaluate(far)
        assert np.isfinite(p).all()
        assert np.allclose(p, far @ AFFINE + OFFSET, atol=1e-6 * np.abs(p).max())
        assert np.isfinite(surf.sample(9).pixels).all()


def test_local_weights_report_holes_not_nan():
    # small faces on the left, one huge face on the right: n=2 cannot cover it
    v = np.array([[0, 0], [0.1, 0], [0.1, 0.1], [0, 0.1], [0.2, 0], [0.2, 0.1], [1, 0], [1, 1], [0, 1]], float)
    faces = [[0, 1, 2, 3], [1, 4, 5, 2], [4, 6, 7, 5], [3, 2, 5, 7, 8]]
    mesh = Mesh(np.c_[v, v[:, 0] * v[:, 1]], faces)
    surf = fit_surface(mesh, Parametrization(v, (1, 1)), geoimg.GaussianWeights(n=2))
    with pytest.warns(UserWarning, match="holes"):
        img = surf.sample(32)
    assert img.metadata["hole_pixels"] > 0
    assert np.isfinite(img.pixels).all()
    assert (~img.mask).sum() == img.metadata["hole_pixels"]


def test_auto_resolution_follows_s():
    mesh, param = affine_mesh(n=9)
    r1 = fit_surface(mesh, param, geoimg.GaussianWeights()).auto_resolution()
    r4 = fit_surface(mesh, param, geoimg.GaussianWeights(s=4.0)).auto_resolution()
    assert r1 > r4 >= 2
    assert abs(r1 / r4 - 4) < 1.5


def test_rectangular_domain_gives_rectangular_image():
    v = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 1], [0, 1, 1]], float)
    mesh = Mesh(v, [[0, 1, 2, 3]])
    param = parametrize(mesh, "heightfield", axis="z")
    img = fit_surface(mesh, param, geoimg.GaussianWeights()).sample(65)
    assert sorted(img.shape) == [33, 65]


def test_inputs_left_unchanged(mountain):
    param = parametrize(mountain, "heightfield", axis="y")
    v0, f0, c0 = mountain.vertices.copy(), mountain.faces.copy(), param.coords.copy()
    surf = fit_surface(mountain, param, geoimg.GaussianWeights(s=2.0))
    pts = np.array([[0.3, 0.4], [0.5, 0.5]])
    p0 = pts.copy()
    surf.evaluate(pts)
    assert np.array_equal(pts, p0)
    assert np.array_equal(mountain.vertices, v0) and np.array_equal(mountain.faces, f0)
    assert np.array_equal(param.coords, c0)


def test_degenerate_parametric_faces_are_left_out_with_a_warning():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    mesh = Mesh(v, [[0, 1, 2], [0, 2, 3], [0, 1, 4]])  # the last one is a segment in (u, v)
    with pytest.warns(UserWarning, match="1 faces of zero area"):
        surf = fit_surface(mesh, Parametrization(v[:, :2] / 2, (1, 0.5)), geoimg.GaussianWeights())
    assert surf.faces.n_degenerate == 1


@pytest.mark.parametrize("kwargs, message", [
    (dict(s=0), "s: expected a positive"), (dict(s=-1.0), "s: expected"), (dict(s=np.nan), "s: expected"),
    (dict(s=True), "s: expected"), (dict(weights="cubic"), "weights: expected"), (dict(n=1), "n: expected"),
    (dict(tol=1.0), "tol: expected"), (dict(tol=-1e-3), "tol: expected"), (dict(sliver_rule="x"), "sliver_rule"),
])
def test_bad_settings_are_refused(kwargs, message):
    mesh, param = affine_mesh()
    with pytest.raises(ValueError, match=message):
        fit_surface(mesh, param, **kwargs)


def test_bad_arguments_are_refused():
    mesh, param = affine_mesh()
    with pytest.raises(TypeError, match="geoimg.Mesh"):
        fit_surface(mesh.vertices, param)
    with pytest.raises(TypeError, match="Parametrization"):
        fit_surface(mesh, param.coords)
    with pytest.raises(ValueError, match="has 4 points but the mesh has"):
        fit_surface(mesh, Parametrization(np.zeros((4, 2)), (1, 1)))
    surf = fit_surface(mesh, param)
    with pytest.raises(ValueError, match=r"uv: expected parameter points of shape \(k, 2\)"):
        surf.evaluate(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="NaN"):
        surf.evaluate([[np.nan, 0.0]])
    with pytest.raises(ValueError, match="resolution: expected an integer >= 2"):
        surf.sample(1)
    with pytest.raises(ValueError, match="resolution"):
        surf.sample(2.5)


def sliver_tin(n_points=1500, seed=0):
    """A Delaunay TIN of scattered points of a real DEM: slivers line its convex hull."""
    import OpenImageIO as oiio
    from scipy.spatial import Delaunay

    z = oiio.ImageBuf(str(data_file("msh_nad83_27_2007-07-05.tif"))).get_pixels(oiio.FLOAT)[..., 0]
    rng = np.random.default_rng(seed)
    rc = np.unique(np.stack([rng.integers(0, z.shape[0], n_points), rng.integers(0, z.shape[1], n_points)], 1), axis=0)
    xy = np.stack([rc[:, 1] * 10.0, -rc[:, 0] * 10.0], axis=1)
    tri = Delaunay(xy)
    return Mesh(np.c_[xy, z[rc[:, 0], rc[:, 1]]], tri.simplices), tri


def test_robust_sliver_rule_follows_a_real_tin_closer_than_the_paper_rule():
    from scipy.interpolate import LinearNDInterpolator

    mesh, tri = sliver_tin()
    param = parametrize(mesh, "heightfield", axis="z")
    tin = LinearNDInterpolator(tri, mesh.vertices[:, 2])
    rms = {}
    for rule in ("paper", "robust"):
        surf = fit_surface(mesh, param, geoimg.GaussianWeights(sliver_rule=rule))
        img = surf.sample(96, normals=False)
        P = img.pixels.astype(float)
        ref = tin(P[..., 0], P[..., 1])
        inside = img.mask & np.isfinite(ref)
        rms[rule] = np.sqrt(np.mean((P[..., 2] - ref)[inside] ** 2))
        if rule == "robust":
            assert surf.faces.n_slivers > 0
    assert rms["robust"] < 0.25 * rms["paper"], rms


def test_robust_rule_changes_nothing_on_well_shaped_faces(mountain):
    param = parametrize(mountain, "heightfield", axis="y")
    robust = fit_surface(mountain, param, geoimg.GaussianWeights(s=2.0))
    paper = fit_surface(mountain, param, geoimg.GaussianWeights(s=2.0, sliver_rule="paper"))
    assert robust.faces.n_slivers == 0
    assert np.array_equal(robust.sample(32).pixels, paper.sample(32).pixels)


def test_unreferenced_vertices_and_repeated_indices_are_cleaned_up_and_reported():
    mesh, param = affine_mesh()
    v = np.vstack([mesh.vertices, [[1e6, 1e6, 1e6]]])          # an unreferenced far-away vertex
    faces = [f.tolist() for f in mesh.face_list()] + [[0, 0, 1]]  # a face with a repeated index
    dirty = Mesh(v, faces)
    p = parametrize(dirty, "heightfield", axis="z")
    with pytest.warns(UserWarning, match="1 faces of zero area"):
        surf = fit_surface(dirty, p, geoimg.GaussianWeights())
    pts = np.random.default_rng(5).uniform(0, 1, (50, 2)) * p.extent
    clean = fit_surface(Mesh(mesh.vertices, mesh.face_list()), parametrize(mesh, "heightfield", axis="z"),
                        geoimg.GaussianWeights())
    assert np.allclose(surf.evaluate(pts), clean.evaluate(pts), atol=1e-9)


def test_box_ranges_are_searchsorted_on_any_increasing_grid():
    from geoimg.surface._gaussian_kernels import _ranges
    rng = np.random.default_rng(0)
    for coord in (np.linspace(0, 1, 256), np.sort(rng.random(100)), np.array([0.5]), np.array([0., 0., 1., 1., 2.])):
        c = np.concatenate([rng.uniform(-0.5, 2.5, 3000), coord, coord + 1e-17])     # ends exactly on grid points
        r = np.concatenate([rng.uniform(0, 0.3, 3000), np.zeros(2 * len(coord))])
        lo, hi = _ranges(coord, c, r)
        np.testing.assert_array_equal(lo, np.searchsorted(coord, c - r, "left"))
        np.testing.assert_array_equal(hi, np.searchsorted(coord, c + r, "right"))
