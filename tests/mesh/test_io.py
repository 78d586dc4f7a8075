import struct

import numpy as np
import pytest

from geoimg import Mesh, MeshFileError, load_mesh, save_mesh

import meshes
from meshes import write


@pytest.fixture
def mixed():
    rng = np.random.default_rng(1)
    v = rng.normal(size=(9, 3))
    return Mesh(v, [[0, 1, 2], [2, 3, 4, 5], [5, 6, 7, 8, 0]])


@pytest.mark.parametrize("ext", [".obj", ".off", ".ply"])
def test_polygon_formats_round_trip_exactly(tmp_path, mixed, ext):
    back = load_mesh(save_mesh(mixed, tmp_path / f"m{ext}"))
    assert np.array_equal(back.faces, mixed.faces)
    assert np.array_equal(back.vertices, mixed.vertices)  # %.17g text and binary doubles are exact


def _obj_text_row_by_row(mesh):
    """The OBJ text as numpy.savetxt and a loop over the faces write it: the writer, formatting blocks at a
    time, must write exactly these bytes."""
    import io
    fh = io.StringIO()
    fh.write("# written by geoimg\n")
    np.savetxt(fh, mesh.vertices, fmt="v %.17g %.17g %.17g")
    np.savetxt(fh, mesh.uv, fmt="vt %.17g %.17g")
    np.savetxt(fh, mesh.normals, fmt="vn %.9g %.9g %.9g")
    for row, k in zip((mesh.faces + 1).tolist(), mesh.face_sizes.tolist()):
        fh.write("f " + " ".join(f"{i}/{i}/{i}" for i in row[:k]) + "\n")
    return fh.getvalue()


def test_obj_text_is_the_row_by_row_text(tmp_path, mixed, monkeypatch):
    import geoimg.mesh._obj as obj
    rng = np.random.default_rng(2)
    m = Mesh(mixed.vertices, mixed.faces, uv=rng.random((9, 2)), normals=rng.normal(size=(9, 3)))
    monkeypatch.setattr(obj, "ROWS_AT_ONCE", 2)                 # blocks that end inside the arrays
    path = save_mesh(m, tmp_path / "m.obj")
    assert path.read_text() == _obj_text_row_by_row(m)


def test_obj_round_trips_uv_and_normals(tmp_path):
    m = Mesh(np.eye(3), [[0, 1, 2]], uv=[[0, 0], [1, 0], [0, 1]], normals=[[0, 0, 1]] * 3)
    back = load_mesh(save_mesh(m, tmp_path / "m.obj"))
    assert np.array_equal(back.uv, m.uv)


def test_ply_round_trips_normals(tmp_path):
    m = Mesh(np.eye(3), [[0, 1, 2]], normals=[[0, 0, 1]] * 3)
    back = load_mesh(save_mesh(m, tmp_path / "m.ply"))
    assert np.allclose(back.normals, m.normals)


@pytest.mark.parametrize("ext", [".stl", ".glb"])
def test_triangle_formats_are_triangulated(tmp_path, mixed, ext):
    back = load_mesh(save_mesh(mixed, tmp_path / f"m{ext}"))
    assert back.is_triangle_mesh and back.n_faces == 1 + 2 + 3
    assert np.allclose(np.sort(back.vertices, axis=0), np.sort(mixed.vertices, axis=0), atol=1e-6)


def test_obj_one_to_one_vt_become_uv_and_seams_stay_per_corner(tmp_path):
    p = tmp_path / "uv.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt .5 0\nvt .5 .5\nvt 0 .5\nf 1/1 2/2 3/3 4/4\n")
    assert load_mesh(p).uv.tolist() == [[0, 0], [0.5, 0], [0.5, 0.5], [0, 0.5]]
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 9 9\n"
                 "f 1/1 2/2 3/3\nf 1/4 3/3 4/1\n")
    m = load_mesh(p)           # a UV seam: per-corner texture coordinates only, topology from the positions
    assert m.uv is None and m.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert m.face_uv.tolist() == [[[0, 0], [1, 0], [1, 1]], [[9, 9], [1, 1], [0, 0]]]


def test_obj_negative_indices(tmp_path):
    p = tmp_path / "neg.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    assert load_mesh(p).faces.tolist() == [[0, 1, 2]]


def test_binary_off(tmp_path):
    p = tmp_path / "b.off"
    body = struct.pack(">iii", 4, 1, 0) + struct.pack(">12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    body += struct.pack(">i4ii", 4, 0, 1, 2, 3, 0)
    p.write_bytes(b"OFF BINARY\n" + body)
    m = load_mesh(p)
    assert m.faces.tolist() == [[0, 1, 2, 3]] and m.vertices[2].tolist() == [1, 1, 0]


def test_ascii_ply_with_tristrips(tmp_path):
    p = tmp_path / "s.ply"
    p.write_text("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                 "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 1 0\n5 0 1 2 3 4\n")
    m = load_mesh(p)
    assert m.faces.tolist() == [[0, 1, 2], [2, 1, 3], [2, 3, 4]]  # alternate strip triangles flipped


def test_polygonal_files_keep_their_faces_and_unused_vertices(tmp_path):
    L = load_mesh(write(meshes.l_hexagon(), tmp_path / "L.off"))
    assert L.face_sizes.tolist() == [6]
    cyl = load_mesh(write(meshes.capped_cylinder(), tmp_path / "cylinder.obj"))
    assert sorted(np.unique(cyl.face_sizes).tolist()) == [4, 20]
    holes = load_mesh(write(meshes.holey_sphere(unreferenced=3), tmp_path / "holes.ply"))
    assert holes.n_vertices == 165 and int(holes.referenced_vertices().sum()) == 162


def test_missing_unknown_empty_and_corrupt_files(tmp_path):
    with pytest.raises(FileNotFoundError):
        load_mesh(tmp_path / "nope.obj")
    (tmp_path / "a.xyz").write_text("1 2 3")
    with pytest.raises(MeshFileError, match="unknown mesh format"):
        load_mesh(tmp_path / "a.xyz")
    (tmp_path / "e.obj").write_text("")
    with pytest.raises(MeshFileError, match="empty"):
        load_mesh(tmp_path / "e.obj")
    (tmp_path / "nof.obj").write_text("v 0 0 0\n")
    with pytest.raises(MeshFileError, match="no faces"):
        load_mesh(tmp_path / "nof.obj")
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(MeshFileError, match="bad.obj.*refers to vertex 6"):
        load_mesh(tmp_path / "bad.obj")
    (tmp_path / "junk.obj").write_text("v 0 zero 0\nf 1 2 3\n")
    with pytest.raises(MeshFileError, match="corrupt"):
        load_mesh(tmp_path / "junk.obj")
    (tmp_path / "t.off").write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(MeshFileError, match="ends early"):
        load_mesh(tmp_path / "t.off")
    (tmp_path / "t.ply").write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                     b"property float y\nproperty float z\nend_header\n" + b"\0" * 10)
    with pytest.raises(MeshFileError, match="declares 3 items, more than the file.s 10 bytes of data can hold"):
        load_mesh(tmp_path / "t.ply")


def test_save_refuses_to_overwrite_and_writes_atomically(tmp_path, mixed):
    p = save_mesh(mixed, tmp_path / "m.obj")
    before = p.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite=True"):
        save_mesh(mixed, p)
    save_mesh(Mesh(np.eye(3), [[0, 1, 2]]), p, overwrite=True)
    assert p.read_bytes() != before
    with pytest.raises(MeshFileError, match="unknown mesh format"):
        save_mesh(mixed, tmp_path / "m.abc")
    with pytest.raises(TypeError, match="geoimg.Mesh"):
        save_mesh("not a mesh", tmp_path / "x.obj")
    assert sorted(f.name for f in tmp_path.iterdir()) == ["m.obj"]  # no temporary files left behind


def test_failed_write_leaves_nothing(tmp_path, monkeypatch, mixed):
    import geoimg.mesh._io as mio

    def boom(*a):
        raise OSError("disk full")
    monkeypatch.setattr(mio, "write_obj", boom)
    with pytest.raises(OSError, match="disk full"):
        save_mesh(mixed, tmp_path / "m.obj")
    assert list(tmp_path.iterdir()) == []


def test_written_files_get_a_normal_mode(tmp_path, mixed):
    import os
    mask = os.umask(0o022)
    try:
        p = save_mesh(mixed, tmp_path / "m.obj")
        assert p.stat().st_mode & 0o777 == 0o644
        os.chmod(p, 0o600)
        save_mesh(mixed, p, overwrite=True)                    # a replaced file keeps its mode
        assert p.stat().st_mode & 0o777 == 0o600
    finally:
        os.umask(mask)


@pytest.mark.parametrize("faces, expect", [
    ("3 0 1 2\n3 0 2 3\n", [[0, 1, 2], [0, 2, 3]]),                       # all one size: read in one go
    ("3 0 1 2 255 0 0\n3 0 2 3 0 255 0\n", [[0, 1, 2], [0, 2, 3]]),       # colours after the indices
    ("4 0 1 2 3\n3 0 2 3\n", [[0, 1, 2, 3], [0, 2, 3, -1]]),              # mixed sizes
    ("3 0 1\n2\n3 0 2 3\n", [[0, 1, 2], [0, 2, 3]]),                       # a face running on over two lines
    ("3 0 1 2\n4 0 2 3 1\n", [[0, 1, 2, -1], [0, 2, 3, 1]]),
])
def test_ascii_off_faces_whatever_their_layout(tmp_path, faces, expect):
    (tmp_path / "f.off").write_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + faces)
    assert load_mesh(tmp_path / "f.off").faces.tolist() == expect


def test_ascii_off_with_bad_indices_is_refused_either_way(tmp_path):
    for faces in ("3 0 1 x\n3 0 2 3\n", "3 0 1 2.5\n3 0 2 3\n", "3 0 1 99999999999999999999\n3 0 2 3\n"):
        (tmp_path / "f.off").write_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + faces)
        with pytest.raises(MeshFileError):
            load_mesh(tmp_path / "f.off")


@pytest.mark.parametrize("vertices, faces", [
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 1 2\n3 0 2 3\n"),
    ("0 0 0\n1e400 0 0\n1 nan 0\n-0.0 1 0.1e-3\n", "4 0 1 2 3\n4 3 2 1 0\n"),        # quads, odd numbers
    ("0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n", "3 0 1 2\n3 0 2 3\n"),  # normals after x, y, z
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 1 4\n3 0 2 3\n"),                          # an index past the end
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 -1 2\n3 0 2 3\n"),
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 1 2 7\n3 0 2\n"),                           # counts that add up
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "3 0 1 99999999999999999999\n3 0 2 3\n"),         # past 64 bits
    ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "2 0 1\n2 1 2\n"),                                   # two corners a face
    ("0 0 0\n1 0 x\n1 1 0\n0 1 0\n", "3 0 1 2\n3 0 2 3\n"),
])
def test_ascii_off_read_in_one_parse_as_line_by_line(tmp_path, monkeypatch, vertices, faces):
    # the one-parse path (every vertex line, then every face line, as one string of numbers) reads what the
    # line-by-line reader reads, or hands the file to it: the same mesh or the same error either way
    import geoimg.mesh._off as off
    p = tmp_path / "f.off"
    p.write_text("OFF\n4 2 0\n" + vertices + faces)

    def read():
        try:
            m = load_mesh(p)
        except MeshFileError as e:
            return str(e)
        return m.vertices.tobytes(), m.faces.tobytes()

    fast = read()
    monkeypatch.setattr(off, "_numbers", lambda *args: None)
    assert fast == read()


def test_face_lines_are_the_text_of_d_formatting(tmp_path):
    # the f lines are gathered from each vertex's token as one character array: the same text as formatting
    # each face with %d, for every kind of corner and for polygons of several sizes (-1 padding left out)
    rng = np.random.default_rng(3)
    n = 12_345
    faces = [rng.choice(n, k, replace=False).tolist() for k in rng.choice([3, 4, 5, 7], 300)]
    faces += [[0, 9, 10, 99], [100, 999, 1000, 9999], [10_000, 12_344, 5]]
    v = rng.normal(size=(n, 3))
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    kinds = {"%d": {}, "%d/%d": {"uv": rng.random((n, 2))}, "%d//%d": {"normals": normals},
             "%d/%d/%d": {"uv": rng.random((n, 2)), "normals": normals}}
    for corner, extra in kinds.items():
        path = tmp_path / f"{corner.count('%')}{corner.count('/')}.obj"
        save_mesh(Mesh(v, faces, **extra), path)
        lines = [ln for ln in path.read_text().splitlines() if ln.startswith("f ")]
        expected = ["f " + " ".join(corner % ((i + 1,) * corner.count("%")) for i in face) for face in faces]
        assert lines == expected, corner


def test_stl_is_written_as_trimesh_writes_it(tmp_path, mixed):
    # geoimg writes binary STL itself (trimesh's import alone took longer than writing a 513^2 quad mesh):
    # the same triangles (quads split along the shorter diagonal), corners and unit normals as trimesh's
    import trimesh
    from geoimg.mesh._stl import STL_RECORD
    flat = Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], [[0, 1, 2], [0, 1, 3]])     # one degenerate
    for mesh in (mixed, flat, meshes.quad_disk(6)):
        ours = np.frombuffer(save_mesh(mesh, tmp_path / "m.stl", overwrite=True).read_bytes()[84:], STL_RECORD)
        tris, _ = mesh.triangulate(quads="shorter")
        theirs = np.frombuffer(trimesh.Trimesh(mesh.vertices, tris, process=False).export(file_type="stl")[84:],
                               STL_RECORD)
        assert np.array_equal(ours["corners"], theirs["corners"])
        assert np.allclose(ours["normal"], theirs["normal"], atol=1e-6)


def test_glb_holds_what_trimesh_would_write(tmp_path, mixed):
    # geoimg writes GLB itself too: read back by trimesh, the same float32 positions and triangles (quads split
    # along the shorter diagonal) as trimesh's own export of that triangulation
    import trimesh
    for mesh in (mixed, meshes.quad_disk(6)):
        ours = trimesh.load(save_mesh(mesh, tmp_path / "m.glb", overwrite=True), force="mesh", process=False)
        tris, _ = mesh.triangulate(quads="shorter")
        theirs = trimesh.load(trimesh.util.wrap_as_stream(trimesh.Trimesh(mesh.vertices, tris, process=False)
                                                           .export(file_type="glb")), file_type="glb",
                              force="mesh", process=False)
        assert np.array_equal(ours.vertices, theirs.vertices) and np.array_equal(ours.faces, theirs.faces)
