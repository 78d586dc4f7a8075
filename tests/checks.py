"""Checks that the tests run on synthetic and (tests/test_real_meshes.py) real meshes alike."""
import warnings

import numpy as np
from scipy.spatial import ConvexHull

import geoimg
from geoimg import fit_surface, parametrize
from geoimg.animation import morph
from geoimg.mesh import boundary_loops, point_mesh_distance, surface_distance
from geoimg.parametrization import signed_face_areas, sphere_coords
from geoimg.parametrization._orientation import chord_orientation


def check_disk_map(mesh, single_polygon=False):
    """The disk map of a one-loop mesh folds nothing, puts the loop on the square's sides (or the hull of
    the map, when the sides bow) and leaves the mesh unchanged; returns the map."""
    before = mesh.vertices.copy()
    p = parametrize(mesh, "disk")
    assert p.flipped_faces == 0 and p.degenerate_faces == 0 and np.allclose(p.extent, 1.0)
    tris, _ = mesh.triangulate()
    uv = p.coords
    e1, e2 = uv[tris[:, 1]] - uv[tris[:, 0]], uv[tris[:, 2]] - uv[tris[:, 0]]
    area = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    if single_polygon:                 # one polygon: its fan is not a triangulation of the square
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
    return p


def check_disk_surface(mesh, param=None):
    """The surface over a disk map (``param``, made here when not given), sampled at 129^2, lies within 1 %
    of the diagonal of the mesh (RMS)."""
    surf = geoimg.fit_surface(mesh, parametrize(mesh, "disk") if param is None else param, geoimg.GaussianWeights())
    img = surf.sample(129)
    quads = img.to_mesh()
    d = point_mesh_distance(quads.vertices, mesh)
    assert np.sqrt(np.mean(d ** 2)) < 0.01 * mesh.bounding_box_diagonal()


def check_sphere_map(mesh):
    """The sphere map folds no triangle, lowers its energy, squeezes no triangle more than the conformal
    start did, and leaves the mesh unchanged."""
    before = mesh.vertices.copy()
    s, info = sphere_coords(mesh)
    tris, _ = mesh.triangulate(quads="shorter")         # the triangles the map is made on, and sampled by
    assert info["flipped_triangles"] == 0 and (chord_orientation(s, tris) > 0).all()
    assert np.allclose(np.linalg.norm(s, axis=1), 1)
    e_start, e_end = info["balance_energy"]
    assert e_end <= e_start and np.isfinite(e_end)                         # every accepted step lowers it
    if "conformal_area_ratio_min" in info:   # nor makes the worst-squeezed triangle worse than a direct start
        assert info["area_ratio_min"] >= info["conformal_area_ratio_min"]
    assert np.array_equal(mesh.vertices, before)


def check_shared_faces_morph(man, woman=None):
    """Two meshes with the same faces (``woman`` by default ``man`` bent and stretched) morph through one
    parametrization, and the mid frame is as close to the per-vertex mid mesh as the keys are to theirs."""
    if woman is None:
        x = man.vertices
        woman = geoimg.Mesh(x * [1.2, 0.9, 1.0] + 0.1 * np.sin(3 * x[:, [1, 2, 0]]), man.faces)
    with warnings.catch_warnings():
        warnings.simplefilter("error")           # the sphere map folds nothing: nothing to warn of
        m = morph(man, woman, frames=3, easing="linear", align="none", resolution=65)
    assert m.report[1]["parametrization"].startswith("shared with shape 0") and m.report[1]["rotation_deg"] == 0.0
    # the surface is linear in the vertices for a fixed parametrization, so a blend of the two images is
    # the image of the blended mesh: the mid frame is as close to the per-vertex mid mesh as the keys are
    truth = geoimg.Mesh(0.5 * (man.vertices + woman.vertices), man.faces)
    key_err = [surface_distance(man, m.frame(0.0).to_mesh(), n=5000)["rms"],
               surface_distance(woman, m.frame(1.0).to_mesh(), n=5000)["rms"]]
    mid_err = surface_distance(truth, m.frame(0.5).to_mesh(), n=5000)["rms"]
    assert mid_err < 1.1 * max(key_err)


# --- files ------------------------------------------------------------------------------------------


def surface_to_vertices_rms(mesh, smoothness, sliver_rule):
    """RMS distance of the mesh vertices to the surface over its height-field map, for each s. Below some
    s it plateaus (each point then follows the plane of the face with the smallest |x - c_i| / d_i, not
    always an incident one)."""
    param = parametrize(mesh, "heightfield")
    used = mesh.referenced_vertices()
    rms = []
    for s in smoothness:
        surf = fit_surface(mesh, param, geoimg.GaussianWeights(s=s, sliver_rule=sliver_rule))
        rms.append(np.sqrt(np.mean(np.sum((surf.evaluate(param.coords[used]) - mesh.vertices[used]) ** 2, 1))))
    return rms
