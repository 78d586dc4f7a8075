"""The decimated copy of a large mesh: libigl's edge collapses, made in numba without the GIL."""
from pathlib import Path

import igl
import numpy as np
import pytest

import geoimg
from geoimg.mesh import Mesh, topology
from geoimg.parametrization._balance import sobolev_factor, sobolev_factor_later
from geoimg.parametrization._decimate import decimate

import meshes

DATA = Path(__file__).resolve().parents[1] / "data"


def _libigl(x, tris, triangles):
    U, G, _, _ = igl.decimate(np.asfortranarray(x, np.float64), np.asfortranarray(tris, np.int32), triangles)
    return np.asarray(U, np.float64), np.asarray(G, np.int64)


def _bumpy_ball():
    ball = meshes.icosphere(4)
    d = ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True)
    r = 1.0 + 0.05 * np.random.default_rng(3).normal(size=len(d))        # no two edges of one length
    return d * r[:, None], np.asarray(ball.faces, np.int64)


@pytest.mark.parametrize("case", ["bumpy ball", "spot"])
@pytest.mark.parametrize("triangles", [300, 2000])
def test_the_same_coarse_mesh_as_libigls_decimate_bit_for_bit(case, triangles):
    if case == "spot":
        mesh = geoimg.load_mesh(DATA / "spot.obj")
        x, tris = mesh.vertices, mesh.triangulate()[0]
    else:
        x, tris = _bumpy_ball()
    U, G = decimate(x, tris, triangles)
    want_U, want_G = _libigl(x, tris, triangles)
    assert U.shape == want_U.shape and np.array_equal(U, want_U)
    assert G.shape == want_G.shape and np.array_equal(G, want_G)
    t = topology(Mesh(U, G))
    assert len(G) <= triangles and t.closed and t.genus == 0 and t.components == 1


def test_inputs_are_left_as_they_are():
    x, tris = _bumpy_ball()
    x0, t0 = x.copy(), tris.copy()
    decimate(x, tris, 500)
    assert np.array_equal(x, x0) and np.array_equal(tris, t0)


def test_refused_edges_as_libigl_refuses_them():
    """An octahedron cannot go below a tetrahedron: the bipyramid's equator edges break the link condition,
    and a tetrahedron's edges would flatten it. Each refused edge is not tried without end."""
    v = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1.1, 0], [0, -1.2, 0], [0, 0, 1.3], [0, 0, -1.4]])
    f = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    for triangles in (6, 4, 2, 0):
        U, G = decimate(v, f, triangles)
        want_U, want_G = _libigl(v, f, triangles)
        assert np.array_equal(U, want_U) and np.array_equal(G, want_G)
        assert len(G) == max(triangles, 4)


def test_a_genus_one_mesh_keeps_its_genus():
    torus = geoimg.load_mesh(DATA / "torus.obj")
    U, G = decimate(torus.vertices, torus.triangulate()[0], 200)
    assert topology(Mesh(U, G)).genus == 1


def test_the_sobolev_factor_made_in_the_background_is_the_same():
    x, tris = _bumpy_ball()
    used = np.ones(len(x), bool)
    cache = sobolev_factor_later(x, tris, used)
    b = np.random.default_rng(0).normal(size=(len(x), 3))
    got = sobolev_factor(x, tris, used, cache=cache)
    assert cache["sobolev"] is got                           # waited for once, then kept
    assert np.array_equal(got.solve(b), sobolev_factor(x, tris, used).solve(b))


def test_a_factor_that_fails_in_the_background_fails_where_it_is_used():
    x, tris = _bumpy_ball()
    x[0] = np.nan                                           # SuperLU: "Factor is exactly singular"
    cache = sobolev_factor_later(x, tris, np.ones(len(x), bool))
    with pytest.raises(RuntimeError, match="singular"):
        sobolev_factor(x, tris, np.ones(len(x), bool), cache=cache).solve(np.ones(len(x)))


def test_poles_of_high_valence_and_edges_of_one_length():
    """A UV sphere: poles of valence 128 (wider than the rows' least width) and rings of edges that tie."""
    import trimesh
    ball = trimesh.creation.uv_sphere(count=[64, 64])
    x, tris = np.asarray(ball.vertices), np.asarray(ball.faces, np.int64)
    assert np.bincount(tris.ravel()).max() == 128
    U, G = decimate(x, tris, 2000)
    t = topology(Mesh(U, G))
    assert len(G) == 2000 and t.closed and t.genus == 0 and t.components == 1
    assert np.allclose(np.linalg.norm(U, axis=1), 1.0, atol=0.05)       # midpoints of short edges stay near it
