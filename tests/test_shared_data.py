"""The same checks on the larger third-party meshes of ../shared/data that are not bundled (their
licences do not allow it, or they are large). Skipped, with the reason shown, where ../shared/data is absent."""
import numpy as np
import pytest

from helpers import SHARED

if not SHARED.is_dir():
    pytest.skip(f"the third-party meshes of {SHARED} are not beside this checkout", allow_module_level=True)

from geoimg import parametrize
from geoimg.mesh import topology
from geoimg.parametrization import sphere_coords
from geoimg.parametrization._orientation import chord_orientation

from helpers import load_shared
from checks import (
    check_disk_map,
    check_disk_surface,
    check_shared_faces_morph,
    check_sphere_map,
    surface_to_vertices_rms,
)


@pytest.mark.parametrize("sliver_rule", ["robust", "paper"])
def test_surface_converges_to_the_hemisphere_as_s_shrinks(sliver_rule):
    rms = surface_to_vertices_rms(load_shared("meshes/open_disk/hemisphere.off"), (2.0, 1.0, 0.5, 0.25), sliver_rule)
    assert all(a > 1.5 * b for a, b in zip(rms, rms[1:])), rms
    assert rms[-1] < 0.1 * rms[0]


@pytest.mark.parametrize("rel", ["open_disk/camelhead.off", "open_disk/hemisphere.off", "open_disk/alligator.obj",
                                 "polygonal/L.off", "polygonal/inspired_mesh_quads_Conjugate.off"])
def test_disk_maps_of_real_meshes(rel):
    check_disk_map(load_shared(f"meshes/{rel}"), single_polygon=rel.endswith("L.off"))


def test_disk_surface_of_the_camel_head():
    mesh = load_shared("meshes/open_disk/camelhead.off")
    assert parametrize(mesh).method == "disk"
    check_disk_surface(mesh)


@pytest.mark.parametrize("rel", ["closed_genus0/bunny.obj", "closed_genus0/bumpy.off", "polygonal/chamfer-cube.off",
                                 "polygonal/horse_quad.obj", "polygonal/cylinder.obj",
                                 "polygonal/sword-quad-dominant.obj"])
def test_sphere_maps_of_real_meshes(rel):
    check_sphere_map(load_shared(f"meshes/{rel}"))


def test_area_balancing_lifts_the_bunny_ears():
    s, info = sphere_coords(load_shared("meshes/closed_genus0/bunny.obj"))
    assert info["conformal_area_ratio_min"] < 1e-3 and info["area_ratio_min"] > 0.05


def test_a_large_scan_is_mapped_through_a_coarse_copy():
    mesh = load_shared("meshes/closed_genus0/bunny.off")              # 69,666 triangles
    s, info = sphere_coords(mesh)
    tris, _ = mesh.triangulate()
    assert info["start"] == "multilevel" and info["flipped_triangles"] == 0 and (chord_orientation(s, tris) > 0).all()
    assert info["area_log_rms"] < 0.5       # measured 0.32; the direct map's 200 steps gave 1.35


def test_a_shape_whose_direct_maps_fold_is_mapped_coarse_to_fine():
    # the conformal map squeezes the fingers below float precision and the Tutte map folds too; the
    # progressive map (simplify to a tetrahedron, put the vertices back one by one, relax) folds nothing
    mesh = load_shared("meshes/closed_genus0/human_man.obj")
    s, info = sphere_coords(mesh)
    tris, _ = mesh.triangulate()
    assert info["direct_folds"] > 100 and info["start"] == "progressive" and info["misplaced"] == 0
    assert info["flipped_triangles"] == 0 and (chord_orientation(s, tris) > 0).all()
    assert info["area_ratio_min"] > 1e-3            # the conformal map gave 1e-19


def test_two_humans_with_the_same_faces_morph_through_one_parametrization():
    check_shared_faces_morph(load_shared("meshes/closed_genus0/human_man.obj"),
                             load_shared("meshes/closed_genus0/human_woman.obj"))


@pytest.mark.parametrize("rel, components, loops, genus, closed, words", [
    ("closed_genus0/bunny.obj", 1, 0, 0, True, "genus 0 (sphere-like)"),
    ("open_other/stanford-bunny.obj", 1, 5, 0, False, "5 boundary loops"),
    ("polygonal/suzanne.obj", 3, 4, 0, False, "3 components"),
    ("polygonal/chamfer-cube.off", 1, 0, 0, True, "sphere-like"),
    ("polygonal/L.off", 1, 1, 0, False, "(a disk)"),
    ("open_disk/camelhead.off", 1, 1, 0, False, "(a disk)"),
])
def test_topology_of_real_meshes_matches_the_catalog(rel, components, loops, genus, closed, words):
    t = topology(load_shared(f"meshes/{rel}"))
    assert (t.components, t.boundary_loops, t.genus, t.closed) == (components, loops, genus, closed)
    assert words in t.describe()


def test_the_original_bunny_scan_keeps_its_unreferenced_vertices():
    bunny = load_shared("meshes/open_other/stanford-bunny.obj")
    assert bunny.n_vertices == 35947 and int(bunny.referenced_vertices().sum()) == 34834
    assert np.unique(bunny.face_sizes).tolist() == [3]
