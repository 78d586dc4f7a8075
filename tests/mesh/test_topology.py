import pytest

import geoimg
from geoimg.mesh import topology

import meshes
from helpers import MOUNTAIN, data_file, load_data


@pytest.mark.parametrize("make, components, loops, genus, closed, words", [
    (lambda: load_data("bob_tri.obj"), 1, 0, 1, True, "closed surface of genus 1 (torus-like)"),
    (lambda: load_data("torus.obj"), 1, 0, 1, True, "genus 1"),
    (lambda: load_data("spot.obj"), 1, 0, 0, True, "genus 0 (sphere-like)"),
    (meshes.holey_sphere, 1, 5, 0, False, "5 boundary loops"),
    (meshes.three_pieces, 3, 2, 0, False, "3 components"),
    (meshes.rhombicuboctahedron, 1, 0, 0, True, "sphere-like"),
    (meshes.l_hexagon, 1, 1, 0, False, "(a disk)"),
    (lambda: load_data("cube_no_bottom.obj"), 1, 1, 0, False, "(a disk)"),
])
def test_topology_of_bundled_and_synthetic_meshes(make, components, loops, genus, closed, words):
    t = topology(make())
    assert (t.components, t.boundary_loops, t.genus, t.closed) == (components, loops, genus, closed)
    assert words in t.describe()


def test_uv_seams_do_not_split_the_topology():
    spot = geoimg.load_mesh(data_file("spot.obj"))
    assert spot.uv is None and spot.face_uv is not None         # seams: texture coordinates per corner only
    t = topology(spot)
    assert t.closed and t.genus == 0 and t.vertices == 2930 and t.faces == 5856


def test_mountain_is_a_disk():
    t = topology(geoimg.load_mesh(MOUNTAIN))
    assert (t.boundary_loops, t.genus, t.euler) == (1, 0, 1)


def test_a_pinch_vertex_is_counted_and_refused():
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]]
    tets = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 5, 4], [0, 4, 6], [0, 6, 5], [4, 5, 6]]
    mesh = geoimg.Mesh(v, tets)              # two tetrahedra touching at vertex 0: every edge is manifold
    t = topology(mesh)
    assert t.nonmanifold_edges == 0 and t.nonmanifold_vertices == 1 and not t.closed and t.genus is None
    assert "1 vertices where separate fans of faces meet" in t.describe()
    with pytest.raises(geoimg.ParametrizationError, match="split the pinch vertices"):
        geoimg.parametrize(mesh)
    assert topology(geoimg.Mesh(v[:4], tets[:4])).nonmanifold_vertices == 0
