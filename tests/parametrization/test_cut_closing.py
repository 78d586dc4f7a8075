"""What the cut map does before and after cutting: a crack is zipped, a pinhole filled (least area), a flat
fill refused, and a cut branch grown towards a squeezed point only when it helps."""
import numpy as np
import pytest

import geoimg
import geoimg.parametrization._cut as cut_module
from geoimg.mesh import boundary_loops, topology
from geoimg.parametrization import cut_coords
from geoimg.parametrization._cut import (_close_small_holes, _crack_pairs, _fill_quality, _least_area_fill,
                                         _path_to_worst, _welds_cleanly, _zip)
from geoimg.parametrization._laplacian import triangle_areas

import meshes


def _edge_keys(tris, n):
    a, b = tris, np.roll(tris, -1, 1)
    return set((np.minimum(a, b) * n + np.maximum(a, b)).ravel().tolist())


SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)


def test_the_least_area_fill_of_a_square_is_two_triangles_of_its_area():
    fill = _least_area_fill(SQUARE, np.arange(4), set())
    assert fill.shape == (2, 3) and triangle_areas(SQUARE, fill).sum() == pytest.approx(1.0)
    normal = np.cross(SQUARE[fill[:, 1]] - SQUARE[fill[:, 0]], SQUARE[fill[:, 2]] - SQUARE[fill[:, 0]])
    assert np.all(normal[:, 2] > 0)                       # wound as the rim runs


def test_a_diagonal_that_is_already_an_edge_is_not_drawn():
    blocked = {0 * 4 + 2}                                  # the diagonal 0-2
    fill = _least_area_fill(SQUARE, np.arange(4), blocked)
    assert sorted(map(sorted, fill.tolist())) == [[0, 1, 3], [1, 2, 3]]
    assert _least_area_fill(SQUARE, np.arange(4), {0 * 4 + 2, 1 * 4 + 3}) is None


def test_a_slit_fills_with_no_area():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 0, 0]], float)       # p, q, r, q' (q' on q)
    fill = _least_area_fill(v, np.arange(4), set())
    assert len(fill) == 2 and triangle_areas(v, fill).sum() == 0.0
    assert _fill_quality(v, fill) == 0.0 and _fill_quality(SQUARE, _least_area_fill(SQUARE, np.arange(4), set())) > 0.5


def test_a_crack_is_told_from_a_hole():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [2, 0, 0], [1, 0, 0]], float)
    loop = np.array([2, 3, 4, 5, 0, 1])                   # tips 0 and 3, whichever vertex the loop starts at
    assert sorted(_crack_pairs(v, loop, 1e-12)) == [(1, 5), (2, 4)] or \
        sorted(_crack_pairs(v, loop, 1e-12)) == [(4, 2), (5, 1)]
    v[4, 1] = 1e-3                                        # one side bent away: a hole, not a crack
    assert _crack_pairs(v, loop, 1e-6) is None and _crack_pairs(v, loop, 1e-2) is not None
    assert _crack_pairs(v[:5], np.arange(5), 1.0) is None     # odd: the sides cannot pair up
    assert _crack_pairs(SQUARE, np.arange(4), 1e-6) is None


def test_a_weld_that_would_crush_a_triangle_is_refused():
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    assert _welds_cleanly(np.arange(4), tris)
    assert not _welds_cleanly(np.array([0, 1, 1, 3]), tris)


def test_cracks_that_cannot_all_be_zipped_are_zipped_one_by_one():
    tris = np.array([[0, 1, 2], [3, 4, 5]])
    crushing, clean = np.array([[0, 1]]), np.array([[5, 6]])     # (kept, welded): 1 onto 0 crushes a triangle
    weld, zipped = _zip(7, tris, [crushing, clean])
    assert zipped == 1 and weld.tolist() == [0, 1, 2, 3, 4, 5, 5]
    weld, zipped = _zip(7, tris, [clean])
    assert zipped == 1 and weld.tolist() == [0, 1, 2, 3, 4, 5, 5]
    assert _zip(7, tris, [])[1] == 0


def cracked_torus(n_major=24, n_minor=12):
    """A torus grid cracked along two edges p-q-r of a meridian: q split in two, a 4-edge loop."""
    mesh = meshes.torus_grid(n_major, n_minor)
    i = np.arange(n_major * n_minor).reshape(n_major, n_minor)
    q, prev_row = i[0, 1], set(i[-1].tolist())
    f = mesh.faces.copy()
    side = np.array([bool(prev_row & set(t.tolist())) for t in f]) & (f == q).any(1)
    f[side] = np.where(f[side] == q, len(mesh.vertices), f[side])
    return geoimg.Mesh(np.vstack([mesh.vertices, mesh.vertices[q]]), f)


def test_a_cracked_torus_is_zipped_and_its_image_is_watertight():
    mesh = cracked_torus()
    before = (mesh.vertices.copy(), mesh.faces.copy())
    t = topology(mesh)
    assert (t.genus, t.boundary_loops) == (1, 1) and len(boundary_loops(mesh)[0]) == 4
    disk, uv, (source, weight), layout, info = cut_coords(mesh)
    assert (info["cracks_zipped"], info["holes_filled"], info["fill_faces"]) == (1, 0, 0)
    assert info["stages"][0] == "zipped 1 crack (at most 8 edges; the image spans them)"
    assert len(np.unique(source[weight == 0, 0])) == mesh.n_vertices - 1        # one side of the crack welded
    assert np.array_equal(before[0], mesh.vertices) and np.array_equal(before[1], mesh.faces)
    image = geoimg.mesh_to_image(mesh, 65)
    out = topology(image.to_mesh())
    assert image.valid.all() and out.closed and out.genus == 1 and out.boundary_edges == 0


def test_zipping_a_crack_saves_the_cut_its_path(monkeypatch):
    zipped = cut_coords(cracked_torus())[4]
    monkeypatch.setattr(cut_module, "SMALL_HOLE_EDGES", 0)
    kept_open = cut_coords(cracked_torus())[4]
    assert (zipped["cracks_zipped"], kept_open["cracks_zipped"]) == (1, 0)
    assert zipped["cut_paths"] < kept_open["cut_paths"]
    assert zipped["cut_length"] < kept_open["cut_length"]


def pierced_sphere(holes=5):
    """icosphere(3) with ``holes`` faces far apart removed: pinholes of 1/1280 of the surface each."""
    m = meshes.icosphere(3)
    centres = m.vertices[m.faces].mean(axis=1)
    chosen = [0]
    while len(chosen) < holes:
        d = np.min(np.linalg.norm(centres[:, None] - centres[chosen][None], axis=2), axis=1)
        chosen.append(int(np.argmax(d)))
    return geoimg.Mesh(m.vertices, np.delete(m.faces, chosen, axis=0))


def test_pinholes_are_filled_and_a_genus_0_surface_keeps_one_open():
    mesh = pierced_sphere(5)
    info = cut_coords(mesh)[4]
    assert (info["holes_filled"], info["cracks_zipped"], info["fill_faces"]) == (4, 0, 4)
    assert info["stages"][0] == "filled 4 small holes (at most 8 edges; the image spans them)"
    image = geoimg.mesh_to_image(mesh, 65, method="cut")
    out = topology(image.to_mesh())
    assert (out.genus, out.boundary_loops) == (0, 1)


def test_a_hole_of_a_bigger_share_stays_open():
    info = cut_coords(meshes.holey_sphere(5))[4]          # icosphere(2): each hole 1/320 of the surface
    assert info["holes_filled"] == 0 and info["cut_paths"] >= 4


def test_a_flat_fill_is_refused():
    n = 41                                                # a hole of 1/3200 of the plate
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
    v = np.stack([x, y, np.zeros_like(x)], -1).reshape(-1, 3)
    i = np.arange(n * n).reshape(n, n)
    a, b, c, d = i[:-1, :-1], i[1:, :-1], i[1:, 1:], i[:-1, 1:]
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    hole = int(np.flatnonzero((f == i[20, 20]).any(1) & (f == i[21, 21]).any(1) & (f == i[21, 20]).any(1))[0])
    f = np.delete(f, hole, axis=0)
    genus = 0
    weld, fill, zipped, filled = _close_small_holes(v, f, genus)
    assert (zipped, filled) == (0, 1) and len(fill) == 1             # the plate's rim stays, the hole closes
    flat = v.copy()
    flat[i[21, 20]] = 0.5 * (flat[i[20, 20]] + flat[i[21, 21]]) + [1e-6, -1e-6, 0]    # a corner on its far side
    weld, fill, zipped, filled = _close_small_holes(flat, f, genus)
    assert (zipped, filled) == (0, 0) and np.array_equal(weld, np.arange(len(v)))


def test_a_squeezed_finger_gets_a_cut_branch_that_helps():
    info = cut_coords(meshes.finger(segments=12, rows=16))[4]
    errors = info["cut_errors"]
    assert info["cut_branches"] >= 1 and len(errors) >= 2
    assert errors[info["cut_branches"]] <= cut_module.AUGMENT_GAIN ** info["cut_branches"] * errors[0]
    assert info["stages"][-1].startswith("cut towards the most squeezed point")


def test_no_branch_where_nothing_is_starved():
    info = cut_coords(meshes.torus_grid())[4]
    assert info["cut_branches"] == 0 and len(info["cut_errors"]) == 1
    assert not any(s.startswith("cut towards") for s in info["stages"])


def test_the_path_to_the_worst_point_runs_along_edges_from_the_cut(monkeypatch):
    mesh = meshes.torus_grid()
    tris = mesh.faces
    cuts = [np.asarray(c) for c in cut_module.igl.cut_to_disk(np.ascontiguousarray(tris, np.int64))]
    cut = cut_module._map_cut(mesh.vertices, tris, cuts, None, "area", None)
    assert _path_to_worst(mesh.vertices, tris, cut) is None                  # nothing starved
    monkeypatch.setattr(cut_module, "STARVED_SHARE", 10.0)                    # everything starved
    path = _path_to_worst(mesh.vertices, tris, cut)
    on_cut = set(np.concatenate(cuts).tolist())
    assert path[0] in on_cut and path[-1] not in on_cut and len(set(path.tolist())) == len(path)
    edges = _edge_keys(tris, mesh.n_vertices)
    n = mesh.n_vertices
    assert all(min(a, b) * n + max(a, b) in edges for a, b in zip(path[:-1], path[1:]))


def test_slim_balancing_grows_no_branch():
    info = cut_coords(meshes.finger(segments=12, rows=16), balance="slim")[4]
    assert info["cut_branches"] == 0 and len(info["cut_errors"]) == 1
