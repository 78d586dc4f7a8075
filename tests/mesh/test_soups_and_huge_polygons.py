"""Files that are not quite surfaces, answered in seconds: the faces of a volume mesh (its outer surface kept,
with a warning), a soup of faces (refused in one line that says what it is), thousands of pieces (refused
past a stated limit), polygons of thousands of corners (split in near-linear time, never fanned from one
corner); and libraries' logs and limits never reach the user in their own words."""
import itertools
import logging

import numpy as np
import pytest

import geoimg
from geoimg import MeshError
from geoimg.cli import main
from geoimg.mesh import Mesh, repair, topology
from geoimg.mesh._mesh import LARGE_POLYGON, _halving
from geoimg.mesh._repair import MAX_PIECES, drop_inner_walls, refuse_face_soup

import meshes

from helpers import DATA


def _lattice(n: int, *, cells: bool):
    """An n x n x n block of unit cubes: every cell's six faces (walls between cells stored twice, with
    opposite windings), or every face of the lattice once (edges inside shared by four faces)."""
    m = n + 1
    v = np.array(list(itertools.product(range(m), range(m), range(m))), float)

    def idx(i, j, k):
        return (i * m + j) * m + k

    faces = []
    if cells:
        for i, j, k in itertools.product(range(n), range(n), range(n)):
            c = [idx(i + a, j + b, k + d) for a, b, d in itertools.product((0, 1), (0, 1), (0, 1))]
            faces += [[c[x] for x in q] for q in ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6),
                                                   (0, 2, 6, 4), (1, 5, 7, 3))]
    else:
        for i, j, k in itertools.product(range(m), range(m), range(m)):
            if j < n and k < n:
                faces.append([idx(i, j, k), idx(i, j + 1, k), idx(i, j + 1, k + 1), idx(i, j, k + 1)])
            if i < n and k < n:
                faces.append([idx(i, j, k), idx(i, j, k + 1), idx(i + 1, j, k + 1), idx(i + 1, j, k)])
            if i < n and j < n:
                faces.append([idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k), idx(i, j + 1, k)])
    return Mesh(v, faces)


def test_the_faces_of_a_volume_mesh_become_its_outer_surface():
    block = _lattice(4, cells=True)                           # 384 faces, 288 of them walls between cells
    before = block.faces.copy()
    with pytest.warns(UserWarning, match="faces of a volume mesh: left out the 288 faces"):
        pieces = repair(block)
    assert np.array_equal(block.faces, before)                # the input is left as it is
    assert len(pieces) == 1
    outer = pieces[0].mesh
    topo = topology(outer)
    assert outer.n_faces == 6 * 16 and topo.closed and topo.genus == 0 and topo.nonmanifold_edges == 0


def test_a_two_sided_sheet_keeps_one_copy_of_its_faces():
    sheet = geoimg.grid_mesh(np.zeros((4, 4)))
    f = sheet.faces
    two_sided = Mesh(sheet.vertices, np.concatenate([f, f[:, ::-1]]))
    assert drop_inner_walls(two_sided)[1] == 0                 # everything doubled: not a volume
    with pytest.warns(UserWarning, match="repeat another face's corners"):
        assert repair(two_sided)[0].mesh.n_faces == len(f)


def test_the_faces_of_a_lattice_stored_once_are_refused_in_one_line(tmp_path, capsys):
    soup = _lattice(4, cells=False)
    with pytest.raises(MeshError, match=r"edges are shared by 3 to 4 faces: not a surface but the faces of a "
                                        "volume mesh or a soup of faces"):
        refuse_face_soup(soup)
    geoimg.save_mesh(soup, tmp_path / "lattice.obj")
    assert main(["image", str(tmp_path / "lattice.obj"), "-o", str(tmp_path / "l.exr"), "--res", "17"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "not a surface" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lattice.obj"]


def test_a_few_edges_of_three_faces_are_still_separated():
    """A fin on a box: one non-manifold edge is a repair, not a soup."""
    box = geoimg.mesh.load_mesh(DATA / "sphere.obj")
    a, b = box.faces[0, :2]
    fin = Mesh(np.vstack([box.vertices, [[5.0, 5.0, 5.0]]]),
               np.vstack([box.faces, [[a, b, box.n_vertices]]]))
    refuse_face_soup(fin)
    with pytest.warns(UserWarning, match="separated the faces at 1 edges"):
        assert len(repair(fin)) == 2


def test_thousands_of_pieces_are_refused_past_the_stated_limit():
    n = MAX_PIECES + 1
    v = (np.arange(n)[:, None, None] * 3.0 + np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]])[None]).reshape(-1, 3)
    soup = Mesh(v, np.arange(3 * n).reshape(n, 3))
    with pytest.raises(MeshError, match=f"{n} separate pieces .* more than the {MAX_PIECES}"):
        repair(soup)
    few = Mesh(v[:30], np.arange(30).reshape(10, 3))
    with pytest.warns(UserWarning, match="10 separate pieces"):
        assert [p.source_vertices.tolist() for p in repair(few)][:2] == [[0, 1, 2], [3, 4, 5]]


@pytest.mark.parametrize("k", [5, 6, 7, 65, 100, 1001, 20000])
def test_halving_splits_a_convex_polygon_into_its_area(k):
    t = _halving(k)
    assert t.shape == (k - 2, 3) and t.min() == 0 and t.max() == k - 1
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    xy = np.stack([np.cos(a), np.sin(a)], 1)[t]
    cross = (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1]) - \
        (xy[:, 1, 1] - xy[:, 0, 1]) * (xy[:, 2, 0] - xy[:, 0, 0])
    assert (cross > 0).all()                                             # every triangle turns the polygon's way
    assert np.isclose(0.5 * cross.sum(), 0.5 * k * np.sin(2 * np.pi / k), rtol=1e-12)
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts <= 2).all() and (counts == 1).sum() == k            # a manifold disk with the polygon's rim


def _polygon(k: int, radius=lambda a: 1.0, height=lambda a: 0.0):
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    r = radius(a)
    return Mesh(np.stack([r * np.cos(a), r * np.sin(a), height(a) + 0 * a], 1), [list(range(k))])


def test_a_large_convex_polygon_is_not_fanned_from_one_corner():
    poly = _polygon(5000)
    tris, owner = poly.triangulate()
    assert len(tris) == 4998 and (owner == 0).all()
    valence = np.bincount(tris.ravel(), minlength=5000)
    assert valence.max() < 40                     # a fan would put all 4998 triangles on corner 0


def test_a_large_polygon_with_reflex_corners_is_ear_clipped_inside_it():
    star = _polygon(3000, radius=lambda a: 1 + 0.3 * np.cos(25 * a))
    tris, _ = star.triangulate()
    xy = star.vertices[:, :2][tris]
    cross = (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1]) - \
        (xy[:, 1, 1] - xy[:, 0, 1]) * (xy[:, 2, 0] - xy[:, 0, 0])
    p = star.vertices[:, :2]
    area = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - p[:, 1] * np.roll(p[:, 0], -1))
    assert len(tris) == 2998 and (cross >= 0).all() and np.isclose(0.5 * cross.sum(), area, rtol=1e-9)


def test_small_polygons_split_as_before():
    """Up to LARGE_POLYGON corners: the fan, or the ear clipping of a polygon with a reflex corner."""
    poly = _polygon(LARGE_POLYGON)
    assert poly.triangulate()[0].tolist() == [[0, j, j + 1] for j in range(1, LARGE_POLYGON - 1)]


@pytest.mark.slow
def test_a_100000_corner_polygon_converts(tmp_path):
    k = 100_000
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    lines = [f"v {np.cos(t):.9f} {np.sin(t):.9f} 0" for t in a] + ["f " + " ".join(map(str, range(1, k + 1)))]
    (tmp_path / "circle.obj").write_text("\n".join(lines) + "\n")
    assert main(["image", str(tmp_path / "circle.obj"), "-o", str(tmp_path / "c.exr"), "--res", "33", "-q"]) == 0
    img = geoimg.load_image(tmp_path / "c.exr")
    assert img.metadata["parametrization"] == "heightfield" and img.metadata["psnr_db"] > 50


def test_a_polygon_without_inner_vertices_is_a_height_field_whatever_its_outline():
    """A disk map would pin each of its corners to the square's rim, every triangle flat."""
    star = _polygon(400, radius=lambda a: 1 + 0.6 * np.cos(9 * a))
    assert geoimg.parametrize(star).method == "heightfield"


def test_trimesh_logs_no_traceback_for_an_stl_whose_normals_are_junk(tmp_path):
    """trimesh logs a traceback when an ASCII STL's normals cannot be read (and reads the file well); no
    handler, the last-resort one that prints to stderr included, may see it."""
    text = (DATA / "multibody.stl").read_text().replace("facet normal -1", "facet normal zz", 1)
    (tmp_path / "junk.stl").write_text(text)
    seen = []

    class Catch(logging.Handler):
        def emit(self, record):
            seen.append(record)

    logger = logging.getLogger("trimesh")
    catch = Catch()
    logger.addHandler(catch)
    try:
        m = geoimg.load_mesh(tmp_path / "junk.stl")
    finally:
        logger.removeHandler(catch)
    assert m.n_faces == 32 and seen == []
    assert logger.handlers == [] or catch not in logger.handlers


def test_an_exr_whose_header_claims_66_gb_is_refused_in_geoimg_words(tmp_path, capsys):
    import struct
    small = geoimg.GeometryImage(np.zeros((8, 8, 3), np.float32), None, geoimg.PlanarDomain())
    path = geoimg.save_image(small, tmp_path / "s.exr")
    data = bytearray(path.read_bytes())
    for key in (b"dataWindow\0box2i\0", b"displayWindow\0box2i\0"):
        at = data.find(key) + len(key) + 4
        struct.pack_into("<4i", data, at, 0, 0, 77000, 77000)
    (tmp_path / "huge.exr").write_bytes(bytes(data))
    assert main(["info", str(tmp_path / "huge.exr")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert "header declares an image of 66.3 GiB in a file of" in err and "GEOIMG_MAX_MEMORY" in err
    assert "limits:" not in err and "OIIO" not in err


def test_a_mesh_that_needs_no_repair_comes_back_as_it_is():
    """One piece, one fan at every vertex, faces that agree: the repairs hand back the mesh itself (what was
    counted of it, its topology and edges, is then not counted again)."""
    from geoimg.mesh._repair import repair, split_components, split_fans
    ball = meshes.icosphere(2)
    assert split_fans(ball)[0] is ball and split_components(ball)[0][0] is ball
    (only,) = repair(ball)
    assert only.mesh is ball and np.array_equal(only.source_vertices, np.arange(ball.n_vertices))


def test_triangles_and_polygons_stored_twice_are_found_alike():
    """Triangles' corner sets are counted by one integer key, polygons' by rows: the same faces go."""
    from geoimg.mesh._repair import drop_duplicate_faces
    v = np.random.default_rng(0).normal(size=(6, 3))
    tris = [[0, 1, 2], [2, 1, 0], [1, 2, 3], [3, 4, 5], [5, 3, 4]]
    kept, dropped = drop_duplicate_faces(geoimg.Mesh(v, tris))
    assert kept.faces.tolist() == [[0, 1, 2], [1, 2, 3], [3, 4, 5]] and dropped == 2
    quads = [[0, 1, 2, 3], [3, 2, 1, 0], [1, 2, 3, 4], [0, 1, 2, -1], [2, 0, 1, -1]]
    kept, dropped = drop_duplicate_faces(geoimg.Mesh(v, [[c for c in q if c >= 0] for q in quads]))
    assert kept.n_faces == 3 and dropped == 2
