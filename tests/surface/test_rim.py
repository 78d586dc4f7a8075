"""Rims that follow the mesh (geoimg.surface._coverage_rim): a planar image's rim within half a pixel spacing of the
mesh's boundary, where the mask's staircase strays farther; rectangles left to the bit; the exact nearest
points and the boundary distance it is measured with."""
import warnings

import numpy as np
import pytest

import geoimg
from geoimg.errors import InputError, InputTypeError
from geoimg.mesh import boundary_distance, grid_mesh
from geoimg.mesh._metrics import nearest_on_segments
from geoimg.surface import prefilter_s
from geoimg.surface._coverage_rim import rim_pixels
import meshes


def _image(mesh, param, res, snap=True):
    surf = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
    surf = surf.with_s(prefilter_s(surf, res))
    if not snap:                                            # the mask's staircase, as before
        surf = type(surf)(**{**surf.__dict__, "rim": None})
    return surf.sample(res, normals=False)


def _spacing(mesh, param, res):
    """A pixel spacing in space: the parameter spacing times the mesh's size over its parameter size."""
    scale = np.linalg.norm(np.ptp(mesh.vertices, axis=0)) / np.linalg.norm(np.ptp(param.coords, axis=0))
    return scale * max(param.extent) / (res - 1)


@pytest.mark.parametrize("shape, res", [("flat_disk", 33), ("flat_disk", 65), ("petal", 65)])
def test_rim_within_half_a_pixel_of_the_boundary(shape, res):
    mesh = getattr(meshes, shape)()
    param = geoimg.parametrize(mesh, "heightfield", axis="z")
    h = _spacing(mesh, param, res)
    snapped = boundary_distance(mesh, _image(mesh, param, res).to_mesh(), step=h / 8)
    stairs = boundary_distance(mesh, _image(mesh, param, res, snap=False).to_mesh(), step=h / 8)
    assert stairs["other_max"] > 0.6 * h                   # the staircase the snapping removes
    assert snapped["other_max"] < 0.5 * h and snapped["reference_max"] < 0.5 * h


def test_the_default_conversion_snaps_too():
    mesh = meshes.petal()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        img = geoimg.mesh_to_image(mesh, 65, method="heightfield", axis="z")
    h = _spacing(mesh, geoimg.parametrize(mesh, "heightfield", axis="z"), 65)
    assert boundary_distance(mesh, img.to_mesh(), step=h / 8)["other_max"] < 0.5 * h


def test_a_rectangle_is_left_to_the_bit():
    z = np.random.default_rng(0).random((9, 12))
    mesh = grid_mesh(z, (1.1, 0.8))
    param = geoimg.parametrize(mesh, "heightfield", axis="z")
    a, b = _image(mesh, param, 33), _image(mesh, param, 33, snap=False)
    assert np.array_equal(a.pixels, b.pixels) and np.array_equal(a.mask, b.mask)


def test_rim_pixels_are_the_quad_mesh_rim():
    rng = np.random.default_rng(1)
    for _ in range(20):
        valid = rng.random((7, 9)) < 0.75
        if not (valid[:-1, :-1] & valid[:-1, 1:] & valid[1:, :-1] & valid[1:, 1:]).any():
            continue
        rows, cols = np.mgrid[:7, :9]
        pixels = np.stack([cols, rows, np.zeros_like(rows)], axis=-1).astype(np.float32)   # a vertex: its pixel
        quad = geoimg.GeometryImage(pixels, valid).to_mesh()
        f = quad.faces
        a, b = f.ravel(), np.roll(f, -1, axis=1).ravel()
        key = np.minimum(a, b) * quad.n_vertices + np.maximum(a, b)
        _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
        on_rim = np.unique(np.concatenate([a[counts[inv] == 1], b[counts[inv] == 1]]))
        expected = np.zeros_like(valid)
        at = quad.vertices[on_rim].astype(int)
        expected[at[:, 1], at[:, 0]] = True
        assert np.array_equal(rim_pixels(valid), expected)


def test_nearest_on_segments_is_exact():
    rng = np.random.default_rng(2)
    for dim in (2, 3):
        seg = rng.random((40, 2, dim))
        pts = rng.random((200, dim)) * 1.4 - 0.2
        t, d, k = nearest_on_segments(pts, seg, 0.05)
        ab = seg[:, 1] - seg[:, 0]
        tt = np.clip(np.einsum("psd,sd->ps", pts[:, None] - seg[None, :, 0], ab) / (ab ** 2).sum(1), 0, 1)
        dd = np.linalg.norm(seg[None, :, 0] + tt[..., None] * ab - pts[:, None], axis=2)
        assert np.allclose(d, dd.min(axis=1), atol=1e-12)
        assert np.allclose(np.linalg.norm(seg[k, 0] + t[:, None] * ab[k] - pts, axis=1), d)


def test_boundary_distance_refuses_what_has_no_boundary():
    closed = meshes.icosphere(1)
    with pytest.raises(InputError, match="no boundary"):
        boundary_distance(closed, meshes.flat_disk())
    with pytest.raises(InputTypeError, match="expected a geoimg.Mesh"):
        boundary_distance(meshes.flat_disk(), np.zeros((3, 3)))
