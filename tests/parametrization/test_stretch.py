"""The L2 stretch of a map (Sander et al. 2001): 1 for maps that keep shapes and shares of area, the closed
form for a shear, the same on the sphere, and the starved share of a map that squeezes a part."""
import numpy as np
import pytest

import geoimg
from geoimg.parametrization import map_stretch
import meshes


def _grid(n=6):
    return geoimg.grid_mesh(np.zeros((n, n)), (1.0, 1.0))


def test_a_map_that_only_scales_has_stretch_one():
    m = _grid()
    for k in (0.01, 1.0, 30.0):
        out = map_stretch(m, geoimg.Parametrization(m.vertices[:, :2] * k, (1, 1)))
        assert out["l2"] == pytest.approx(1.0, abs=1e-12) and out["worst"] == pytest.approx(1.0, abs=1e-12)
        assert out["starved"] == 0.0 and out["degenerate"] == 0


def test_a_conformal_map_that_squeezes_one_end_has_the_closed_form_stretch():
    """exp(x + iy) on [0, 3] x [0, 1] keeps angles but gives x = 0 a 400th of the area scale of x = 3: the
    stretch, a root mean square over the surface's area, is sqrt((1 - e^-6)(e^6 - 1) / 36) (about 3.3). A mean
    over the parameter area would call every conformal map 1."""
    g = geoimg.grid_mesh(np.zeros((41, 121)), (1.0, 1.0))
    lo, hi = g.vertices.min(axis=0), g.vertices.max(axis=0)
    px, py = 3.0 * (g.vertices[:, 0] - lo[0]) / (hi[0] - lo[0]), (g.vertices[:, 1] - lo[1]) / (hi[1] - lo[1])
    m = geoimg.Mesh(np.column_stack([px, py, np.zeros_like(px)]), g.faces)
    out = map_stretch(m, geoimg.Parametrization(np.column_stack([np.exp(px) * np.cos(py), np.exp(px) * np.sin(py)]),
                                                (1, 1)))
    assert out["l2"] == pytest.approx(np.sqrt((1 - np.exp(-6)) * (np.exp(6) - 1) / 36), rel=0.01)


def test_a_shear_has_its_closed_form_stretch():
    """u = 2x, v = y/2 keeps areas; the parameters-to-surface map has singular values 1/2 and 2, so every
    triangle's stretch is sqrt((1/4 + 4) / 2)."""
    m = _grid()
    out = map_stretch(m, geoimg.Parametrization(m.vertices[:, :2] * [2.0, 0.5], (1, 1)))
    assert out["l2"] == pytest.approx(np.sqrt(2.125), rel=1e-12)
    assert out["efficiency"] == pytest.approx(1 / np.sqrt(2.125), rel=1e-12)


def test_on_the_sphere_the_identity_map_of_a_sphere_mesh_has_stretch_one():
    s = meshes.icosphere(2)
    param = geoimg.Parametrization(s.vertices / np.linalg.norm(s.vertices, axis=1, keepdims=True), (1, 1),
                                   domain="octahedral")
    assert map_stretch(s, param)["l2"] == pytest.approx(1.0, abs=1e-9)


def test_a_squeezed_part_is_starved_and_raises_the_stretch():
    m = _grid(9)
    uv = m.vertices[:, :2].copy()
    near = uv[:, 0] < 3.0                          # the left three columns of cells squeezed into a sliver
    uv[near, 0] *= 0.01
    uv[~near, 0] = 0.03 + (uv[~near, 0] - 3.0) * (8.0 - 0.03) / 5.0
    before = m.vertices.copy()
    out = map_stretch(m, geoimg.Parametrization(uv, (1, 1)))
    assert out["l2"] > 2 and out["worst"] > out["l2"]
    assert out["starved"] == pytest.approx(3 / 8)            # the squeezed columns' share of the area
    assert np.array_equal(m.vertices, before)                 # inputs unchanged


def test_real_maps_of_each_domain_are_measured():
    for mesh in (meshes.torus_grid(), meshes.cap(), meshes.icosphere(2, bumps=0.1)):   # cut, disk, sphere
        param = geoimg.parametrize(mesh)
        out = map_stretch(mesh, param)
        assert 1.0 <= out["l2"] < 10 and 0.0 <= out["starved"] < 0.5, (param.method, out)


def test_collapsed_triangles_count_as_starved_and_degenerate():
    m = _grid(3)
    uv = m.vertices[:, :2].copy()
    uv[4] = uv[0]                                  # the middle vertex onto a corner: some triangles collapse
    out = map_stretch(m, geoimg.Parametrization(uv, (1, 1)))
    assert out["degenerate"] > 0 and out["starved"] > 0


def test_bad_input_is_refused():
    m = _grid(3)
    with pytest.raises(geoimg.InputTypeError, match="mesh"):
        map_stretch("mesh", geoimg.Parametrization(m.vertices[:, :2], (1, 1)))
    with pytest.raises(geoimg.InputTypeError, match="param"):
        map_stretch(m, m.vertices[:, :2])
