"""Disk parametrizations: fold-free maps of one-loop meshes onto the square."""
import numpy as np
import pytest

from geoimg import Mesh, ParametrizationError, parametrize
from geoimg.parametrization import disk_coords
import geoimg
from geoimg.mesh import boundary_loops, surface_distance, topology

from checks import check_disk_map, check_disk_surface
import meshes
from helpers import load_data

DISKS = {
    "cup": lambda: meshes.cap(135.0),
    "hemisphere": meshes.cap,
    "open box": lambda: load_data("cube_no_bottom.obj"),
    "mountain (a corner)": lambda: _corner(load_data("mountain.obj")),
    "L": meshes.l_hexagon,
    "quads": meshes.quad_disk,
}


def _corner(mesh, share=0.4):
    """The faces of a terrain TIN over the first ``share`` of its x and z ranges: a real disk of 7,938
    faces (the whole mountain's disk map takes 20 s; bench_disk.py times it)."""
    v = mesh.vertices
    inside = (v[:, 0] <= np.quantile(v[:, 0], share)) & (v[:, 2] <= np.quantile(v[:, 2], share))
    faces = mesh.faces[inside[mesh.faces].all(axis=1)]
    used = np.unique(faces)
    index = np.full(len(v), -1)
    index[used] = np.arange(len(used))
    return geoimg.Mesh(v[used], index[faces])


@pytest.mark.parametrize("name", DISKS)
def test_disk_parametrization_folds_no_face(name):
    check_disk_map(DISKS[name](), single_polygon=name == "L")


def test_disk_corners_sit_on_the_sharp_corners_of_an_open_box():
    mesh = load_data("cube_no_bottom.obj")
    _, info = disk_coords(mesh)
    corners = mesh.vertices[info["corners"]]
    loop = boundary_loops(mesh)[0]
    ring = mesh.vertices[loop]
    # the bottom rim of the box is a square: its four corners are the vertices farthest from the rim's centre
    far = np.sort(np.linalg.norm(ring - ring.mean(0), axis=1))[-4:]
    assert np.allclose(np.sort(np.linalg.norm(corners - ring.mean(0), axis=1)), far)


def test_auto_picks_disk_for_a_curved_one_loop_mesh():
    assert parametrize(meshes.cap(135.0)).method == "disk"          # a cup: its projection folds
    assert parametrize(load_data("mountain.obj")).method == "heightfield"


def test_auto_weighs_a_disk_map_against_a_steep_height_field():
    # a hemisphere seen from above is a fold-free height field, but its walls get few pixels: the disk map's
    # image is far closer (hemisphere.off's twin, 1,861 vertices; 77.0 -> 93.7 dB at 129^2)
    mesh = meshes.octa_hemisphere(30)
    auto = parametrize(mesh)
    assert auto.method == "disk" and "height field steep" in auto.info["stages"][0]
    heights = parametrize(mesh, "heightfield")
    assert heights.flipped_faces == 0
    db = {p.method: surface_distance(mesh, geoimg.mesh_to_image(mesh, 33, parametrization=p, fidelity=False)
                                     .to_mesh(), n=20_000)["psnr_db"] for p in (auto, heights)}
    assert db["disk"] > db["heightfield"] + 10
    assert parametrize(mesh, axis="z").method == "heightfield"                   # an up axis asks for heights
    assert parametrize(meshes.cap(40.0)).method == "heightfield"                 # a gentle cap keeps them


def test_no_triangle_of_a_bent_polygon_is_flattened_onto_one_side_of_the_square():
    # one bent hexagon, all its corners on the boundary: with corners 2, 3, 4, 5 its fan triangle (0, 1, 2)
    # had all three on one side of the square (zero area in the image) while the hexagon spanned four
    v = [[0.7, 0.5, 0.0], [0.2, 1.0, -0.1], [-0.3, 1.0, 0.1], [-1.2, -0.5, 0.6], [-0.4, -0.9, 0.5], [1.4, -0.4, 0.0]]
    m = Mesh(v, [[0, 1, 2, 3, 4, 5]])
    p = parametrize(m, "disk")
    assert p.degenerate_faces == 0 and p.flipped_faces == 0
    tris = np.concatenate([m.triangulate()[0], m.triangulate(quads="shorter")[0]])
    e1, e2 = p.coords[tris[:, 1]] - p.coords[tris[:, 0]], p.coords[tris[:, 2]] - p.coords[tris[:, 0]]
    assert np.all(np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) > 1e-3)


def test_a_bent_pentagon_seen_from_above_folds_so_auto_maps_it_as_a_disk_and_the_image_keeps_its_slope():
    # trimesh's polygonfaces.obj: a square with a fifth corner raised above one side; projected from above the
    # raised triangle lies over the square, folded, though the pentagon's outline turns the right way
    v = [[-5, 0, 5], [5, 0, 5], [5, 0, -5], [-5, 0, -5], [0, 5, -5]]
    m = Mesh(v, [[0, 1, 2, 3, 4]])
    with pytest.warns(UserWarning, match="folded"):
        assert parametrize(m, "heightfield", axis="y").flipped_faces == 1
    p = parametrize(m)
    assert p.method == "disk" and p.flipped_faces == 0 and p.degenerate_faces == 0
    img = geoimg.mesh_to_image(m, resolution=65)
    assert surface_distance(m, img.to_mesh(), n=20000)["hausdorff_rel"] < 0.01


def test_keep_boundary_keeps_a_convex_planar_outline_and_refuses_others():
    v = [[0, 0, 0], [2, 0, 0], [3, 1, 0], [2, 2, 0], [0, 2, 0], [1.2, 1, 0]]
    m = Mesh(v, [[0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 4, 5], [4, 0, 5]])
    p = parametrize(m, "disk", boundary="keep")
    assert p.flipped_faces == 0 and p.extent[0] != p.extent[1]   # the pentagon's proportions, not a square
    lshape = meshes.l_hexagon()
    with pytest.raises(ParametrizationError, match="reflex"):
        parametrize(lshape, "disk", boundary="keep")
    with pytest.raises(ParametrizationError, match="boundary: expected"):
        parametrize(m, "disk", boundary="circle")


def test_disk_then_surface_reproduces_a_curved_mesh():
    check_disk_surface(meshes.cap(135.0, rings=16, segments=40))




def test_auto_maps_a_winding_flat_outline_onto_the_square_so_the_image_keeps_it_in_one_piece():
    # a flat U: a height field would mask the gap between the arms, and thin arms come apart in the mask
    t = np.linspace(0.0, 1.0, 21)
    x, y = np.meshgrid(t, t)
    idx = np.arange(441).reshape(21, 21)
    quads = [[idx[i, j], idx[i, j + 1], idx[i + 1, j + 1], idx[i + 1, j]] for i in range(20) for j in range(20)
             if not (i >= 4 and 2 <= j < 18)]                       # the arms are 2 cells wide
    used = np.unique(quads)
    remap = np.full(441, -1)
    remap[used] = np.arange(len(used))
    u_shape = Mesh(np.stack([x, y, 0 * x], -1).reshape(-1, 3)[used], remap[np.array(quads)])
    p = parametrize(u_shape)
    assert p.method == "disk"
    image = geoimg.fit_surface(u_shape, p, geoimg.GaussianWeights()).sample(65)
    assert topology(image.to_mesh()).boundary_loops == 1 and topology(image.to_mesh()).components == 1


def test_slim_opens_up_a_squeezed_finger_without_folding_and_holds_the_boundary():
    m = meshes.finger()
    plain = parametrize(m, "disk", balance="none")
    balanced = parametrize(m, "disk", balance="slim")
    assert plain.info["slim_steps"] == 0 and plain.info["area_log_rms"] == plain.info["mean_value_area_log_rms"]
    assert plain.info["area_log_rms"] > 8                            # the tip squeezed to e^-8 of its share
    assert balanced.info["balance"] == "slim" and balanced.info["slim_steps"] > 0
    assert balanced.flipped_faces == 0 and balanced.info["area_log_rms"] < 1.5
    assert balanced.info["mean_value_area_log_rms"] == plain.info["area_log_rms"]
    loop = boundary_loops(m)[0]
    np.testing.assert_array_equal(balanced.coords[loop], plain.coords[loop])       # boundary held exactly
    # and the geometry image samples the tip: the quad mesh lies far closer to the finger
    d = {name: surface_distance(m, geoimg.mesh_to_image(m, 65, parametrization=p).to_mesh(), n=20000)
         for name, p in (("plain", plain), ("balanced", balanced))}
    assert d["balanced"]["psnr_db"] > d["plain"]["psnr_db"] + 15
    assert d["balanced"]["hausdorff"] < d["plain"]["hausdorff"] / 2


def test_a_bad_balance_is_refused():
    with pytest.raises(geoimg.ParametrizationError, match="balance: expected one of"):
        parametrize(meshes.finger(rows=4), "disk", balance="stretch")
