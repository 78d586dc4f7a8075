import numpy as np
import pytest

from geoimg import Mesh, MeshError
from geoimg.mesh import pad_faces


def test_faces_kept_as_given_and_padded():
    m = Mesh(np.zeros((6, 3)), [[0, 1, 2], [2, 3, 4, 5], [0, 2, 4, 5, 1]])
    assert m.face_sizes.tolist() == [3, 4, 5]
    assert m.faces.tolist()[0] == [0, 1, 2, -1, -1]
    assert [f.tolist() for f in m.face_list()] == [[0, 1, 2], [2, 3, 4, 5], [0, 2, 4, 5, 1]]


def test_inputs_are_copied_not_mutated():
    v = np.arange(12, dtype=np.float32).reshape(4, 3)
    f = np.array([[0, 1, 2, 3]])
    v0, f0 = v.copy(), f.copy()
    m = Mesh(v, f)
    assert m.vertices.dtype == np.float64
    v[0, 0] = 99
    f[0, 0] = 3
    assert np.array_equal(m.vertices, v0) and np.array_equal(m.faces, f0)
    with pytest.raises(ValueError):
        m.vertices[0, 0] = 1.0  # read-only


def test_triangulate_fans_each_face_in_order():
    m = Mesh(np.zeros((6, 3)), [[0, 1, 2, 3], [3, 2, 4, 5, 1]])
    tris, owner = m.triangulate()
    assert tris.tolist() == [[0, 1, 2], [0, 2, 3], [3, 2, 4], [3, 4, 5], [3, 5, 1]]
    assert owner.tolist() == [0, 0, 1, 1, 1]


@pytest.mark.parametrize("vertices, faces, message", [
    (np.zeros((3, 2)), [[0, 1, 2]], "vertices: expected shape"),
    (np.zeros((0, 3)), [[0, 1, 2]], "no vertices"),
    ([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], [[0, 1, 2]], "NaN or infinite"),
    ([[0, 0, 0], [1, np.inf, 0], [0, 1, 0]], [[0, 1, 2]], "NaN or infinite"),
    (np.zeros((3, 3)), [[0, 1, 3]], "refers to vertex 3 but there are only 3"),
    (np.zeros((3, 3)), [[0, 1, -2]], "negative vertex index"),
    (np.zeros((3, 3)), [[0, 1]], "at least 3 vertices"),
    (np.zeros((3, 3)), np.zeros((0, 3), int), "no faces"),
    (np.zeros((3, 3)), [[0, -1, 1, 2]], "padding must come after"),
    (np.zeros((3, 3)), np.array([[0.0, 1.5, 2.0]]), "integer vertex indices"),
    (np.zeros((3, 3)), np.zeros((3,), int), "2-D"),
])
def test_bad_meshes_are_refused_with_a_clear_message(vertices, faces, message):
    with pytest.raises(MeshError, match=message):
        Mesh(vertices, faces)


def test_bad_uv_and_normals_are_refused():
    with pytest.raises(MeshError, match=r"uv: expected shape \(3, 2\)"):
        Mesh(np.zeros((3, 3)), [[0, 1, 2]], uv=np.zeros((2, 2)))
    with pytest.raises(MeshError, match="normals: contains NaN"):
        Mesh(np.zeros((3, 3)), [[0, 1, 2]], normals=np.full((3, 3), np.nan))


def test_pad_faces_accepts_lists_of_mixed_length():
    assert pad_faces([[1, 2, 3], [4, 5, 6, 7]]).tolist() == [[1, 2, 3, -1], [4, 5, 6, 7]]


@pytest.mark.parametrize("faces", [[[0, 1, 10 ** 20]], [[0, 1, 10 ** 20], [0, 1, 2, 3]], [["0", "1", "2"]],
                                   np.array([[0, 1, None]], dtype=object)])
def test_pad_faces_refuses_indices_that_are_not_64_bit_integers(faces):
    with pytest.raises(MeshError, match="faces: .*(beyond 64-bit|expected integer)"):
        pad_faces(faces)


def test_referenced_vertices_and_bbox():
    m = Mesh([[0, 0, 0], [3, 0, 0], [0, 4, 0], [100, 100, 100]], [[0, 1, 2]])
    assert m.referenced_vertices().tolist() == [True, True, True, False]
    assert m.bounding_box_diagonal() == pytest.approx(5.0)


def _cube_with_a_doublet():
    """A cube whose top is two quads sharing both edges at a raised vertex 8 of valence 2 (a doublet)."""
    v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1], [0.5, 0.5, 2.5]]
    f = [[0, 3, 2, 1], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 8], [6, 7, 4, 8]]
    return Mesh(v, f)


@pytest.mark.parametrize("quads", ["fan", "shorter"])
def test_quads_around_a_valence_2_vertex_are_split_through_it(quads):
    # split along the diagonal that misses vertex 8, both quads give the triangle (4, 6, 8): its edges would
    # lie on four triangles, which no map of a closed surface can unfold
    tris, owner = _cube_with_a_doublet().triangulate(quads)
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()
    assert len(np.unique(np.sort(tris, axis=1), axis=0)) == len(tris) == 14
    assert all(8 in t for t in tris[owner >= 5].tolist())
    assert np.array_equal(owner, np.repeat(np.arange(7), 2))


def test_triangles_given_twice_are_found_with_any_vertex_count():
    """The same repeated triangles are found whether the indices fit one int64 key a row (below 2^21) or
    not (rows compared whole)."""
    from geoimg.mesh._mesh import _quads_split_twice
    tris = np.array([[0, 1, 2], [2, 0, 1], [3, 4, 5], [5, 4, 6], [6, 5, 4], [1, 2, 3], [0, 2, 4], [1, 1 << 20, 9]])
    owner, quad = np.arange(8), np.array([True, True, True, True, False, True, True, True])
    small = _quads_split_twice(tris, owner, quad)
    assert small.tolist() == [True, True, False, True, False, False, False, False]
    assert np.array_equal(_quads_split_twice(tris + (1 << 22), owner, quad), small)


@pytest.mark.parametrize("quads", ["fan", "shorter"])
def test_a_mesh_of_quads_only_splits_as_the_general_rule_does(quads):
    # quads only (an image's quad mesh) take a shortcut: the same triangles, faces and corners as the rule for
    # any polygons gives them when one triangle more sends the mesh that way
    import geoimg
    import meshes
    image = geoimg.mesh_to_image(meshes.icosphere(2, bumps=0.1), 33, fidelity=False).to_mesh()
    for q in (image, _cube_with_a_doublet()):               # the cube: a doublet, split through its vertex
        n = q.n_vertices                                   # one triangle more, on a vertex of its own
        mixed = Mesh(np.vstack([q.vertices, [[9.0, 9.0, 9.0]]]), np.vstack([q.faces, [[0, 1, n, -1]]]))
        for mine, general in zip(q.triangle_corners(quads), mixed.triangle_corners(quads)):
            assert np.array_equal(mine, general[:len(mine)])



def test_what_is_made_of_a_mesh_is_made_once_and_read_only():
    from geoimg.mesh import topology
    from geoimg.mesh._topology import edge_uses
    m = Mesh([[0, 0, 0], [2, 0, 0], [3, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    fan, shorter = m.triangulate(), m.triangulate("shorter")
    assert m.triangulate()[0] is fan[0] and m.triangulate("shorter")[0] is shorter[0]
    assert fan[0].tolist() == [[0, 1, 2], [0, 2, 3]] and shorter[0].tolist() == [[1, 2, 3], [1, 3, 0]]
    assert topology(m) is topology(m) and edge_uses(m)[4] is edge_uses(m)[4]
    with pytest.raises(ValueError):
        fan[0][0, 0] = 3                       # shared with every later caller: nobody may change it
    other = Mesh(m.vertices, [[0, 1, 3]])      # another mesh of the same vertices counts its own
    assert other.triangulate()[0].tolist() == [[0, 1, 3]] and topology(other).faces == 1
