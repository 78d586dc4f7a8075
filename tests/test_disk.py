import warnings

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import geoimg
from geoimg import Mesh, ParametrizationError, parametrize
from geoimg.disk import disk_coords
from geoimg.parametrization import signed_face_areas
from geoimg.topology import boundary_loops

from helpers import shared_file

DISKS = ["meshes/open_disk/camelhead.off", "meshes/open_disk/hemisphere.off", "meshes/open_disk/cube_no_bottom.obj",
         "meshes/open_disk/mountain.obj", "meshes/open_disk/alligator.obj", "meshes/polygonal/L.off",
         "meshes/polygonal/inspired_mesh_quads_Conjugate.off"]


@pytest.mark.parametrize("rel", DISKS)
def test_disk_parametrization_folds_no_face(rel):
    mesh = geoimg.load_mesh(shared_file(rel))
    before = mesh.vertices.copy()
    p = parametrize(mesh, "disk")
    assert p.flipped_faces == 0 and p.degenerate_faces == 0 and np.allclose(p.extent, 1.0)
    tris, _ = mesh.triangulate()
    uv = p.coords
    area = np.cross(uv[tris[:, 1]] - uv[tris[:, 0]], uv[tris[:, 2]] - uv[tris[:, 0]])
    if rel.endswith("L.off"):          # one polygon: its fan is not a triangulation of the square
        assert signed_face_areas(mesh, uv)[0] > 0
    else:
        assert (area > 0).all()        # every triangle of the fans, not only each polygon
    loop = boundary_loops(mesh)[0]
    if p.info["side_bulge"]:   # bowed sides: every boundary vertex is a corner of the convex hull
        assert set(loop.tolist()) <= set(np.flatnonzero(mesh.referenced_vertices())[
            ConvexHull(uv[mesh.referenced_vertices()]).vertices].tolist())
    else:
        on_side = np.isclose(uv[loop], 0).any(axis=1) | np.isclose(uv[loop], 1).any(axis=1)
        assert on_side.all()
    assert np.array_equal(mesh.vertices, before)


def test_disk_corners_sit_on_the_sharp_corners_of_an_open_box():
    mesh = geoimg.load_mesh(shared_file("meshes/open_disk/cube_no_bottom.obj"))
    _, info = disk_coords(mesh)
    corners = mesh.vertices[info["corners"]]
    loop = boundary_loops(mesh)[0]
    ring = mesh.vertices[loop]
    # the bottom rim of the box is a square: its four corners are the vertices farthest from the rim's centre
    far = np.sort(np.linalg.norm(ring - ring.mean(0), axis=1))[-4:]
    assert np.allclose(np.sort(np.linalg.norm(corners - ring.mean(0), axis=1)), far)


def test_auto_picks_disk_for_a_curved_one_loop_mesh():
    mesh = geoimg.load_mesh(shared_file("meshes/open_disk/camelhead.off"))
    assert parametrize(mesh).method == "disk"
    assert parametrize(geoimg.load_mesh(shared_file("meshes/open_disk/mountain.obj"))).method == "heightfield"


def test_keep_boundary_keeps_a_convex_planar_outline_and_refuses_others():
    v = [[0, 0, 0], [2, 0, 0], [3, 1, 0], [2, 2, 0], [0, 2, 0], [1.2, 1, 0]]
    m = Mesh(v, [[0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 4, 5], [4, 0, 5]])
    p = parametrize(m, "disk", boundary="keep")
    assert p.flipped_faces == 0 and p.extent[0] != p.extent[1]   # the pentagon's proportions, not a square
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lshape = geoimg.load_mesh(shared_file("meshes/polygonal/L.off"))
    with pytest.raises(ParametrizationError, match="reflex"):
        parametrize(lshape, "disk", boundary="keep")
    with pytest.raises(ParametrizationError, match="boundary: expected"):
        parametrize(m, "disk", boundary="circle")


def test_disk_then_surface_reproduces_a_real_mesh():
    mesh = geoimg.load_mesh(shared_file("meshes/open_disk/camelhead.off"))
    surf = geoimg.fit_surface(mesh, parametrize(mesh, "disk"), s=1)
    img = surf.sample(129)
    quads = img.to_mesh()
    from geoimg.metrics import point_mesh_distance
    d = point_mesh_distance(quads.vertices, mesh)
    assert np.sqrt(np.mean(d ** 2)) < 0.01 * mesh.bounding_box_diagonal()
