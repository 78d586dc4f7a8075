"""Shares of the image by bending: the curvature estimate, the shares it asks for, the balancing towards them,
and what it buys: a sphere map that spends its samples where the surface bends resamples it closer."""
import numpy as np
import pytest

import geoimg
import geoimg.parametrization._sphere as sphere_module
from geoimg.errors import InputError
from geoimg.mesh import surface_distance
from geoimg.parametrization._balance import balance, target_shares
from geoimg.parametrization._laplacian import triangle_areas
from geoimg.parametrization._octahedral import sampling_rotation
from geoimg.parametrization._sampling_shares import FLOOR, bending, bending_weight, sampling_shares

import meshes


def _tris(mesh):
    return np.asarray(mesh.triangulate(quads="shorter")[0], np.int64)


@pytest.mark.parametrize("radius", [0.5, 2.0])
def test_bending_of_a_sphere_tends_to_two_over_r_squared(radius):
    # kappa_1^2 + kappa_2^2 = 2 / R^2 on a sphere; the estimate converges as the mesh is refined
    errors, worst = [], []
    for sub in (2, 3, 4):
        m = meshes.icosphere(sub)
        x, tris = m.vertices * radius, _tris(m)
        k2 = bending(x, tris)
        area = triangle_areas(x, tris)
        errors.append(abs((area @ k2) / area.sum() * radius ** 2 / 2.0 - 1.0))
        worst.append(np.abs(k2 * radius ** 2 / 2.0 - 1.0).max())     # the icosphere's uneven triangles
    assert errors[-1] < 0.003 and errors[0] > errors[1] > errors[2], errors
    assert max(worst) < 0.05, worst


def test_bending_of_a_cylinder_is_one_over_r_squared_away_from_its_rim():
    m = meshes.capped_cylinder(96, 48)                  # radius 1, height 2; caps are flat n-gons
    x = m.vertices * [0.5, 0.5, 1.0]                    # radius 0.5
    tris = _tris(m)
    k2 = bending(x, tris)
    mid = np.abs(x[tris].mean(axis=1)[:, 2]) < 0.5
    side = np.abs(np.linalg.norm(x[tris].mean(axis=1)[:, :2], axis=1) - 0.5) < 0.01
    assert np.allclose(k2[mid & side], 4.0, rtol=0.01)


def test_shares_sum_to_one_and_do_not_depend_on_scale_turn_or_place():
    m = meshes.icosphere(3, bumps=0.3)
    x, tris = m.vertices.copy(), _tris(m)
    before = x.copy()
    shares = sampling_shares(x, tris)
    assert np.all(shares > 0) and shares.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.array_equal(x, before)                                    # the input is left as it is
    q, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))
    moved = 7.5 * x @ q.T + [3.0, -2.0, 11.0]
    assert np.allclose(sampling_shares(moved, tris), shares, rtol=1e-9, atol=0)
    # bumps bend unevenly: the shares are not the areas'
    area = triangle_areas(x, tris) / triangle_areas(x, tris).sum()
    assert np.ptp(shares / area) > 0.2


def test_shares_grow_as_the_cube_root_of_the_bending():
    # two spheres in one mesh, radii 1 and 3: bending 2 and 2/9 over the mean, plus FLOOR, per unit area
    small, big = meshes.icosphere(4), meshes.icosphere(4)
    x = np.concatenate([small.vertices, 3.0 * big.vertices])
    tris = np.concatenate([_tris(small), _tris(big) + small.n_vertices])
    weight = bending_weight(x, tris)
    area = triangle_areas(x, tris)
    k2 = bending(x, tris)
    mean = (area @ k2) / area.sum()
    assert np.allclose(weight, k2 / mean + FLOOR)
    density = sampling_shares(x, tris) / area
    half = len(_tris(small))
    expected = ((2.0 / mean + FLOOR) / (2.0 / 9.0 / mean + FLOOR)) ** (1.0 / 3.0)
    assert np.median(density[:half]) / np.median(density[half:]) == pytest.approx(expected, rel=0.03)


def test_a_flat_mesh_and_triangles_of_no_area():
    x = np.array([[0.0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [1, 0, 0]])
    tris = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 1]])          # the last one has no area
    assert bending_weight(x, tris).tolist() == [1.0, 1.0, 1.0]
    assert sampling_shares(x, tris).tolist() == [0.5, 0.5, 0.0]


@pytest.mark.parametrize("shares", [[1.0, 2.0], [1.0, -1.0, 1.0], [1.0, np.nan, 1.0], [0.0, 0.0, 0.0],
                                    [[1.0, 1.0, 1.0]]])
def test_target_shares_refuse_what_is_not_one_share_per_triangle(shares):
    x = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
    tris = np.array([[0, 1, 2], [0, 2, 3], [1, 2, 3]])
    with pytest.raises(InputError, match="shares"):
        target_shares(x, tris, shares)


def test_balancing_goes_towards_the_shares_asked():
    m = meshes.icosphere(3)
    x, tris = m.vertices, _tris(m)
    c = x[tris].mean(axis=1)
    asked = triangle_areas(x, tris) * np.exp(1.2 * c[:, 2])           # more towards +z
    asked /= asked.sum()
    before = x.copy()
    out, steps, (e0, e1) = balance(x, x, tris, shares=asked)
    assert np.array_equal(x, before) and steps > 0 and e1 < e0

    def misfit(s):
        got = triangle_areas(s, tris) / triangle_areas(s, tris).sum()
        return np.sqrt(np.mean(np.log(got / asked) ** 2))
    assert misfit(out) < 0.25 * misfit(x)
    assert np.allclose(np.linalg.norm(out, axis=1), 1.0)


def test_the_rotation_weighs_the_triangles_by_their_bending():
    # a cap of the sphere that bends 50 times as much as the rest, centred where the octahedral image is
    # sparsest (the centre of an octant): with the bending, a turn that takes it near a vertex of the
    # octahedron (where the image is densest) wins; the sphere itself is alike under every turn
    m = meshes.icosphere(3)
    s = m.vertices
    tris = _tris(m)
    d = np.ones(3) / np.sqrt(3.0)
    bend = np.where(s[tris].mean(axis=1) @ d > 0.8, 50.0, 1.0)
    turn, gain = sampling_rotation(s, s, tris, bend)
    cap = turn @ d
    assert gain > 1.0 and np.abs(cap).max() > 0.9, (gain, cap)
    _, plain_gain = sampling_rotation(s, s, tris)
    assert plain_gain < gain


@pytest.fixture(scope="module")
def lens():
    """A flattened icosphere: flat faces that bend sharply at the rim."""
    m = meshes.icosphere(3)
    return geoimg.Mesh(m.vertices * [1.0, 1.0, 0.15], m.faces)


def test_a_map_with_shares_by_bending_resamples_a_lens_closer(lens, monkeypatch):
    # the lens's flat faces need few samples, its rim many; with the shares by area alone, 7 dB are lost
    tm = geoimg.Mesh(lens.vertices, _tris(lens))
    by_bend = geoimg.parametrize(lens, "sphere")
    monkeypatch.setattr(sphere_module, "sampling_shares", lambda x, tris, weight=None: triangle_areas(x, tris))
    monkeypatch.setattr(sphere_module, "bending_weight", lambda x, tris: None)
    by_area = geoimg.parametrize(lens, "sphere")
    assert by_bend.flipped_faces == by_area.flipped_faces == 0

    def psnr(param):
        image = geoimg.mesh_to_image(lens, 65, parametrization=param, fidelity=False,
                                     weights=geoimg.CoverageWeights(s=1e-4))
        return surface_distance(tm, image.to_mesh(), 20000)["psnr_db"]
    bend_db, area_db = psnr(by_bend), psnr(by_area)
    assert bend_db > area_db + 3.0, (bend_db, area_db)


def test_the_turns_proxy_kernel_equals_numpys_sum_and_the_turn_returned_is_a_copy():
    from geoimg.parametrization._octahedral import _sampling_turns
    from geoimg.parametrization._octahedral_kernels import turned_errors
    rng = np.random.default_rng(3)
    c = rng.normal(size=(500, 3))
    c /= np.linalg.norm(c, axis=1, keepdims=True)
    weight = rng.random(500)
    turns = _sampling_turns()
    got = np.empty(len(turns))
    turned_errors(c, weight, turns, got)
    want = np.array([weight @ (np.abs(c @ R.T).sum(axis=1) ** 6) for R in turns])
    assert np.allclose(got, want, rtol=1e-12, atol=0) and np.argmin(got) == np.argmin(want)
    m = meshes.icosphere(2)
    turn, _ = sampling_rotation(m.vertices, m.vertices, _tris(m))
    turn[:] = 0.0                                   # the caller's to change: the fixed set stays as it was
    assert np.allclose(np.einsum("rij,rkj->rik", turns, turns), np.eye(3))


def test_the_fixed_rotations_are_scipys_bit_for_bit():
    """Made with numpy alone (scipy.spatial costs 0.2 s of a first conversion), the same bits as
    ``Rotation.random(R, random_state=0).as_matrix()``, the identity first."""
    from scipy.spatial.transform import Rotation
    from geoimg.parametrization._octahedral import SAMPLING_ROTATIONS, _sampling_turns
    turns = _sampling_turns()
    assert np.array_equal(turns[0], np.eye(3))
    assert np.array_equal(turns[1:], Rotation.random(SAMPLING_ROTATIONS, random_state=0).as_matrix())
