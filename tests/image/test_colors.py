"""Colours on geometry images: resampled from vertex colours or a texture, kept by filters and files,
carried to the quad mesh, drawn in pictures."""

import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay

import filters
import geoimg
from geoimg.errors import ImageError
from geoimg.surface._attributes import locate

import meshes
from helpers import textured_spot


def affine_colours(v):
    return np.stack([0.1 + 0.2 * v[:, 0], 0.2 + 0.3 * v[:, 1], 0.5 + 0.1 * v[:, 0] - 0.1 * v[:, 1]], axis=1)


@pytest.fixture(scope="module")
def coloured_terrain():
    rng = np.random.default_rng(3)
    m = geoimg.mesh.grid_mesh(rng.random((9, 11)) * 0.5)
    v = m.vertices.copy()
    v[:, :2] = (v[:, :2] - v[:, :2].min(0)) / np.ptp(v[:, :2], axis=0)
    return geoimg.Mesh(v, m.faces, colors=affine_colours(v))


@pytest.fixture(scope="module")
def spot_image(tmp_path_factory):
    return geoimg.mesh_to_image(textured_spot(tmp_path_factory.mktemp("spot")), 65)


def test_locate_finds_the_triangle_and_barycentrics_in_the_plane_and_on_the_sphere():
    rng = np.random.default_rng(0)
    pts = rng.random((300, 2))
    tri = Delaunay(pts)
    q = rng.random((2000, 2)) * 0.8 + 0.1
    inside = tri.find_simplex(q) >= 0
    t, b = locate(q[inside], pts[tri.simplices])
    assert np.array_equal(t, tri.find_simplex(q[inside]))
    assert np.allclose(np.einsum("pk,pkc->pc", b, pts[tri.simplices][t]), q[inside], atol=1e-12)
    d = rng.normal(size=(400, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    hull = ConvexHull(d)
    q = rng.normal(size=(3000, 3))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    t, b = locate(q, d[hull.simplices])
    hit = np.einsum("pk,pkc->pc", b, d[hull.simplices][t])           # on the chord, along q
    assert np.all(b >= 0) and np.allclose(np.cross(hit, q), 0, atol=1e-12) and np.all((hit * q).sum(1) > 0)


def test_vertex_colours_affine_in_position_are_reproduced(coloured_terrain):
    img = geoimg.mesh_to_image(coloured_terrain, 33, method="heightfield", axis="z",
                               weights=geoimg.CoverageWeights(s=1.0))
    assert img.colors.shape == (33, 33, 3) and img.colors.dtype == np.float32
    # x and y are linear in (u, v) on a height field, and so are the colours: interpolation is exact
    want = affine_colours(img.pixels.reshape(-1, 3).astype(np.float64)).reshape(33, 33, 3)
    assert np.abs(img.colors - want)[img.valid].max() < 1e-5
    assert geoimg.mesh_to_image(coloured_terrain, 33, method="heightfield", axis="z", colors=False).colors is None


def test_texture_is_read_through_the_corner_uvs():
    # a 4 x 4 grid whose texture coordinates are its (x, y); a texture whose red is the column
    v = np.array([[x, y, 0.0] for y in np.linspace(0, 1, 5) for x in np.linspace(0, 1, 5)])
    m = geoimg.mesh.grid_mesh(np.zeros((5, 5)))
    m = geoimg.Mesh(np.column_stack([m.vertices[:, 0] / 4, 1 + m.vertices[:, 1] / 4, m.vertices[:, 2]]), m.faces)
    tex = np.zeros((64, 256, 3), np.uint8)
    tex[..., 0] = np.arange(256)[None, :]
    tex[..., 1] = 200
    m = geoimg.Mesh(m.vertices, m.faces, face_uv=m.vertices[m.faces][..., :2], texture=tex)
    img = geoimg.mesh_to_image(m, 41, method="heightfield", axis="z")
    x = img.pixels[..., 0]
    expected = np.clip(x * 256 - 0.5, 0, 255) / 255          # bilinear between texel centres
    inner = (x > 1 / 256) & (x < 1 - 1 / 256)
    assert np.abs(img.colors[..., 0] - expected)[inner].max() < 1e-3
    assert np.allclose(img.colors[..., 1], 200 / 255, atol=1e-6)
    assert v.shape == (25, 3)


def test_glued_pixels_get_one_colour_and_the_quad_mesh_welds_them(spot_image):
    img = spot_image
    assert img.domain.kind == "octahedral" and img.colors.shape == (65, 65, 3)
    reps, group = img.domain.glue(img.shape)
    flat = img.colors.reshape(-1, 3)
    assert np.array_equal(flat, flat[reps[group]])
    q = img.to_mesh()
    assert q.colors.shape == (q.n_vertices, 3) and q.texture.shape == (65, 65, 3)
    assert geoimg.mesh.topology(q).genus == 0 and geoimg.mesh.topology(q).boundary_loops == 0
    # every corner reads its own pixel's colour from the texture
    rows = np.round((1 - q.face_uv[..., 1]) * 65 - 0.5).astype(int)
    cols = np.round(q.face_uv[..., 0] * 65 - 0.5).astype(int)
    assert np.array_equal(q.texture[rows, cols], np.round(img.colors[rows, cols] * 255).astype(np.uint8))
    # the texture is the spot's: mostly white-ish hide with dark patches and the pink muzzle
    assert 0.05 < (img.colors.mean(axis=2) < 0.3).mean() < 0.5


@pytest.mark.parametrize("ext", [".exr", ".npz"])
def test_colours_round_trip_through_files(tmp_path, spot_image, ext):
    back = geoimg.load_image(spot_image.save(tmp_path / f"s{ext}"))
    assert np.array_equal(back.colors, spot_image.colors)


def test_filters_keep_the_colours_and_bad_colours_are_refused(spot_image):
    out = spot_image.apply(filters.mean_filter, 3)
    assert np.array_equal(out.colors, spot_image.colors) and not np.array_equal(out.pixels, spot_image.pixels)
    for bad, match in ((np.full((65, 65, 3), 1.5), "values in"), (np.zeros((65, 64, 3)), "expected shape"),
                       (np.zeros((65, 65, 2)), "expected shape")):
        with pytest.raises(ImageError, match=match):
            geoimg.GeometryImage(spot_image.pixels, domain="octahedral", colors=bad)


def test_cut_open_meshes_keep_vertex_colours_and_say_the_texture_is_not_carried():
    torus = meshes.torus_grid()
    coloured = geoimg.Mesh(torus.vertices, torus.faces, colors=(torus.vertices - torus.vertices.min(0)) /
                           np.ptp(torus.vertices, axis=0))
    img = geoimg.mesh_to_image(coloured, 65)
    assert img.domain.kind == "cut" and img.colors.shape == (65, 65, 3)
    # a pixel's colour is its position's (colours are affine in position; the surface is near the mesh)
    want = (img.pixels - torus.vertices.min(0)) / np.ptp(torus.vertices, axis=0)
    assert np.median(np.abs(img.colors - want)) < 0.05
    textured = geoimg.Mesh(torus.vertices, torus.faces, face_uv=np.zeros(torus.faces.shape + (2,)),
                           texture=np.zeros((2, 2, 3), np.uint8))
    with pytest.warns(UserWarning, match="texture is not carried onto a cut-open image"):
        assert geoimg.mesh_to_image(textured, 65).colors is None


def test_a_point_near_only_faces_of_zero_area_gets_the_nearest_one():
    flat = np.array([[[0.0, 0], [1, 0], [2, 0]], [[0.0, 1], [1, 1], [2, 1]]])      # two collinear "triangles"
    t, b = locate(np.array([[0.9, 0.2], [1.0, 0.9]]), flat)
    assert t.tolist() == [0, 1] and np.allclose(b, 1 / 3)
