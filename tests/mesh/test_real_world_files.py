"""Files as real exporters write them (the trimesh project's test models were the source of each case):
positions repeated along UV seams and hard edges, MeshLab's per-face texture coordinates, OBJ line
continuations, texture names with spaces, run-together OFF headers, glTF with its buffers beside it,
surfaces stored twice."""
import warnings

import numpy as np
import pytest

import geoimg
from geoimg import Mesh, MeshFileError, load_mesh, save_mesh
from geoimg.mesh import drop_duplicate_faces, repair, topology, weld_vertices
from geoimg.batch import find_inputs

import meshes


def _split_cube() -> Mesh:
    """A unit cube as glTF and PLY exporters store it: 24 vertices (each face its own four corners, with its
    own texture coordinates and normal), 12 triangles."""
    corners = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    quads = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
    v, uv, nrm, tris = [], [], [], []
    for k, q in enumerate(quads):
        base = len(v)
        v += corners[q].tolist()
        uv += [[k / 6, 0], [(k + 1) / 6, 0], [(k + 1) / 6, 1], [k / 6, 1]]
        n = np.cross(corners[q[1]] - corners[q[0]], corners[q[2]] - corners[q[0]])
        nrm += [(n / np.linalg.norm(n)).tolist()] * 4
        tris += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return Mesh(v, tris, uv=uv, normals=nrm)


def test_coincident_positions_are_welded_keeping_the_uv_seams(tmp_path):
    cube = _split_cube()
    assert topology(cube).components == 6                     # as stored: six loose squares
    path = save_mesh(cube, tmp_path / "cube.ply")
    with pytest.warns(UserWarning, match="joined 16 exactly coincident vertices") as caught:
        welded = load_mesh(path)
    assert "normals differ at 16 of them" in str(caught[0].message)     # PLY keeps the normals, not the UVs
    top = topology(welded)
    assert welded.n_vertices == 8 and top.closed and top.genus == 0 and top.components == 1
    assert welded.normals is None
    np.testing.assert_array_equal(welded.vertices[welded.faces], cube.vertices[cube.faces])
    # every corner keeps the texture coordinates it had: the seams survive per face corner
    w = weld_vertices(cube)
    assert "texture coordinates differ" in w.describe() and w.mesh.uv is None
    np.testing.assert_array_equal(w.mesh.face_uv.reshape(-1, 2), cube.uv[cube.faces.ravel()])
    assert cube.n_vertices == 24 and cube.uv is not None                   # the input is left as it was
    # asked not to, the file is read as stored
    raw = load_mesh(path, weld=False)
    assert raw.n_vertices == 24 and topology(raw).components == 6


def test_weld_leaves_what_it_need_not_touch():
    m = meshes.holey_sphere(unreferenced=3)          # three unused vertices at one place
    before = m.vertices.copy()
    w = weld_vertices(m)
    assert w.mesh is m and w.joined == 0 and w.describe().startswith("joined 0")
    np.testing.assert_array_equal(m.vertices, before)
    # -0.0 and 0.0 are the same position; 1e-300 apart are not
    t = Mesh([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [-0.0, 0, 0], [1, 1e-300, 0], [0, 1, 0]], [[0, 1, 2], [3, 5, 4]])
    w = weld_vertices(t)
    assert w.joined == 2 and w.mesh.n_vertices == 4 and w.vertex_map.tolist() == [0, 1, 2, 0, 3, 2]
    # colours that differ keep the first copy's, and say so
    c = Mesh(t.vertices, t.faces, colors=np.linspace(0, 1, 18).reshape(6, 3))
    w = weld_vertices(c)
    np.testing.assert_array_equal(w.mesh.colors, c.colors[[0, 1, 2, 4]])
    assert "colours differ at 2" in w.describe()


def test_a_welded_box_converts_as_one_closed_piece(tmp_path):
    path = save_mesh(_split_cube(), tmp_path / "cube.glb")
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        images = geoimg.mesh_to_images(path, 33)
    assert len(images) == 1 and images[0].domain.kind == "octahedral"
    assert images[0].metadata["psnr_db"] > 50


def test_gltf_with_its_buffers_is_read_and_found_in_folders(tmp_path):
    import trimesh
    cube = _split_cube()
    tm = trimesh.Trimesh(cube.vertices, cube.faces, process=False)
    files = tm.export(file_type="gltf")
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    with pytest.warns(UserWarning, match="joined 16"):
        m = load_mesh(tmp_path / "model.gltf")
    assert m.n_vertices == 8 and topology(m).closed
    assert find_inputs([tmp_path]) == [tmp_path / "model.gltf"]
    # its buffer missing: a bad file, named
    for name in files:
        if name != "model.gltf":
            (tmp_path / name).unlink()
    with pytest.raises(MeshFileError, match="model.gltf"):
        load_mesh(tmp_path / "model.gltf")
    (tmp_path / "junk.gltf").write_text("{ not json")
    with pytest.raises(MeshFileError, match=r"junk.gltf: not a valid glTF: its JSON cannot be read"):
        load_mesh(tmp_path / "junk.gltf")
    (tmp_path / "list.gltf").write_text("[1, 2]")
    with pytest.raises(MeshFileError, match="list.gltf: not a valid glTF: a JSON object with an 'asset'"):
        load_mesh(tmp_path / "list.gltf")
    (tmp_path / "bytes.gltf").write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(MeshFileError, match="bytes.gltf: not a valid glTF"):
        load_mesh(tmp_path / "bytes.gltf")
    with pytest.raises(MeshFileError, match="unknown mesh format"):
        save_mesh(cube, tmp_path / "out.gltf")


def test_obj_line_continuations_and_short_faces(tmp_path):
    p = tmp_path / "wall.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 \\\n 3 4\nf 2 \\\r\n5 3\n")
    assert load_mesh(p).faces.tolist() == [[0, 1, 2, 3], [1, 4, 2, -1]]
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1// 2//\nf 1// 2// 3//\n")
    with pytest.warns(UserWarning, match="left out 1 'f' lines of fewer than 3 corners"):
        assert load_mesh(p).faces.tolist() == [[0, 1, 2]]
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\nf 2 3\n")
    with pytest.raises(MeshFileError, match="all 2 'f' lines have fewer than 3 corners"):
        load_mesh(p)


def test_texture_names_with_spaces_and_map_options(tmp_path):
    from geoimg.mesh._appearance import write_texture
    tex = np.zeros((4, 8, 3), np.uint8)
    tex[:, 4:] = 255
    write_texture(tex, tmp_path / "my tex.png")
    (tmp_path / "m.mtl").write_text("newmtl a b\nmap_Kd -s 1 1 1 -clamp on my tex.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                    "usemtl a b\nf 1/1 2/2 3/3\n")
    m = load_mesh(tmp_path / "m.obj")
    np.testing.assert_array_equal(m.texture, tex)


def _meshlab_ply(path, texture_line="comment TextureFile my tex.png", extra=" 5 6 7 8 9 1", coords=6):
    """Two triangles with a (u, v) per corner and a colour per face; ``extra`` values after each face's
    colour (MeshLab writes such lines)."""
    uv = " ".join(["0.5"] * coords)
    path.write_text("ply\nformat ascii 1.0\n" + texture_line + "\nelement vertex 4\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                    "property list uchar float texcoord\nproperty uchar red\nproperty uchar green\n"
                    "property uchar blue\nproperty uchar alpha\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                    f"3 0 1 2 {coords} {uv} 1 1 1 1{extra}\n3 0 2 3 6 0 0 1 1 0 1 1 1 1 1{extra}\n")


def test_meshlab_ply_with_per_face_texture_coordinates(tmp_path):
    from geoimg.mesh._appearance import write_texture
    write_texture(np.full((2, 2, 3), 7, np.uint8), tmp_path / "my tex.png")
    p = tmp_path / "m.ply"
    _meshlab_ply(p)
    with pytest.warns(UserWarning, match="2 PLY lines hold more values than the header declares"):
        m = load_mesh(p)
    assert m.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert m.face_uv[1].tolist() == [[0, 0], [1, 1], [0, 1]] and m.texture[0, 0].tolist() == [7, 7, 7]
    _meshlab_ply(p, extra="")
    assert load_mesh(p).face_uv[0].tolist() == [[0.5, 0.5]] * 3
    # coordinates that do not fit the corners, or a texture that is not there: read without them, said
    _meshlab_ply(p, extra="", coords=4)
    with pytest.warns(UserWarning, match="texcoord lists do not hold"):
        assert load_mesh(p).face_uv is None
    _meshlab_ply(p, texture_line="comment TextureFile absent.png", extra="")
    with pytest.warns(UserWarning, match="absent.png not found"):
        m = load_mesh(p)
    assert m.texture is None and m.face_uv is not None


def test_binary_ply_with_per_face_texture_coordinates(tmp_path):
    import struct
    head = (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            b"property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            b"property list uchar float texcoord\nend_header\n")
    body = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3i", 3, 0, 1, 2) + \
        struct.pack("<B6f", 6, 0, 0, 1, 0, 0, 1)
    p = tmp_path / "b.ply"
    p.write_bytes(head + body)
    assert load_mesh(p).face_uv[0].tolist() == [[0, 0], [1, 0], [0, 1]]
    p.write_bytes(head + body[:-6])
    with pytest.raises(MeshFileError, match="corrupt or truncated|ends"):
        load_mesh(p)


def test_off_header_run_together(tmp_path):
    p = tmp_path / "w.off"
    p.write_text("\t   OFF4 1 0 # a comment\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    m = load_mesh(p)
    assert m.n_vertices == 4 and m.faces.tolist() == [[0, 1, 2, 3]]


def test_a_surface_stored_twice_is_one_piece():
    m = meshes.holey_sphere(unreferenced=0)
    flipped = m.faces[:, ::-1]
    twice = Mesh(m.vertices, np.vstack([m.faces, flipped]))      # two-sided: every face again, turned
    kept, dropped = drop_duplicate_faces(twice)
    assert dropped == m.n_faces and kept.faces.tolist() == m.faces.tolist()
    with pytest.warns(UserWarning, match=f"left out {m.n_faces} faces that repeat"):
        pieces = repair(twice)
    assert len(pieces) == 1 and pieces[0].mesh.n_faces == m.n_faces


def test_pieces_share_one_texture():
    quad = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    v = quad + [[x + 3, y, z] for x, y, z in quad]
    tex = np.zeros((512, 512, 3), np.uint8)
    m = Mesh(v, [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], face_uv=np.zeros((4, 3, 2)), texture=tex)
    tex[0, 0] = 9                                     # the mesh took a copy of what it was given
    assert m.texture[0, 0].tolist() == [0, 0, 0]
    with pytest.warns(UserWarning, match="2 separate pieces"):
        pieces = repair(m)
    assert all(p.mesh.texture is m.texture for p in pieces)
    # a read-only view of an array someone can still write is copied, not shared
    base = np.zeros((4, 4, 3), np.uint8)
    view = base.view()
    view.setflags(write=False)
    t = Mesh(v[:3], [[0, 1, 2]], face_uv=np.zeros((1, 3, 2)), texture=view)
    assert not np.shares_memory(t.texture, base)


def test_pieces_that_touch_at_a_point_stay_apart_but_a_soup_is_joined(tmp_path):
    # two tetrahedra whose tips meet, each tip stored on its own (as Suzanne's eyes touch her head)
    tet = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    v = np.vstack([tet, -tet])
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    m = Mesh(v, np.vstack([f, f[:, ::-1] + 4]))
    w = weld_vertices(m)
    assert w.joined == 0 and topology(w.mesh).components == 2          # joined, 0 would pinch
    # each tetrahedron stored face by face (seams everywhere, tips included): each closes up on its own,
    # and the two stay two
    corners = m.faces.ravel()
    split = Mesh(m.vertices[corners], np.arange(len(corners)).reshape(-1, 3))
    w = weld_vertices(split)
    top = topology(w.mesh)
    assert w.mesh.n_vertices == 8 and top.components == 2 and top.closed and top.nonmanifold_vertices == 0
    # the same two as an STL: every corner a copy; all of them joined, the pinch left to the repairs
    with pytest.warns(UserWarning, match="joined 17 exactly coincident"):       # 24 corners, 7 positions
        stl = load_mesh(save_mesh(m, tmp_path / "t.stl"))
    assert stl.n_vertices == 7
    with pytest.warns(UserWarning, match="split 1 pinch"):
        assert len(repair(stl)) == 2


def _areas(m: Mesh) -> np.ndarray:
    tris, _ = m.triangulate()
    p = m.vertices[tris]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2] / 2     # signed, polygons in z = 0


@pytest.mark.parametrize("start", range(8))
def test_polygons_that_a_fan_cannot_split_are_ear_clipped(start):
    # a notched octagon (a wall with a slot), each corner first in turn; and a rectangle with midpoints
    notch = [[0, 0, 0], [4, 0, 0], [4, 3, 0], [3, 3, 0], [3, 1, 0], [1, 1, 0], [1, 3, 0], [0, 3, 0]]
    order = np.roll(np.arange(8), -start)
    m = Mesh(notch, [order])
    a = _areas(m)
    assert (a > 0).all() and np.isclose(a.sum(), 4 * 3 - 2 * 2)        # inside it, covering it once
    mid = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [0, 1, 0], [0, 0.5, 0], [2, 0.5, 0]]
    rect = Mesh(mid, [np.roll([0, 1, 2, 7, 3, 4, 5, 6], -start)])
    a = _areas(rect)
    assert (a > 1e-9).all() and np.isclose(a.sum(), 2.0)               # no triangle of zero area


def test_convex_and_far_from_flat_polygons_keep_their_fan():
    hexagon = [[np.cos(t), np.sin(t), 0] for t in np.linspace(0, 2 * np.pi, 6, endpoint=False)]
    m = Mesh(hexagon, [[0, 1, 2, 3, 4, 5]])
    assert m.triangulate()[0].tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]
    # trimesh's polygonfaces.obj: a pentagon bent far out of any plane
    bent = Mesh([[-5, 0, 5], [5, 0, 5], [5, 0, -5], [-5, 0, -5], [0, 5, -5]], [[0, 1, 2, 3, 4]])
    assert bent.triangulate()[0].tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    tris, owner, corners = bent.triangle_corners()
    assert (bent.faces[owner[:, None], corners] == tris).all()


def test_a_house_of_planar_polygons_with_collinear_corners_converts(tmp_path):
    # wallhole.obj's kind of model: faces of 6 to 11 corners, several on one line (a fan gives flat
    # triangles and the sphere map's solve had no unique answer)
    box = [[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [0, 0, 2], [2, 0, 2], [2, 2, 2], [0, 2, 2]]
    mids = [[1, 0, 0], [1, 2, 0], [1, 0, 2], [1, 2, 2]]                      # 8 .. 11, on four edges
    v = box + mids
    faces = [[0, 3, 9, 2, 1, 8], [4, 10, 5, 6, 11, 7], [0, 8, 1, 5, 10, 4], [2, 9, 3, 7, 11, 6],
             [1, 2, 6, 5], [0, 4, 7, 3]]
    m = Mesh(v, faces)
    assert topology(m).closed and topology(m).genus == 0
    tris, _ = m.triangulate()
    p = np.asarray(v, float)[tris]
    assert (np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1) > 1e-9).all()
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        image = geoimg.mesh_to_image(m, 33)
    assert image.metadata["psnr_db"] > 45
