import numpy as np
import pytest

import geoimg
from geoimg import Mesh, ParametrizationError, parametrize
from geoimg.parametrization import signed_face_areas

from helpers import shared_file


def test_heightfield_of_a_y_up_terrain_fills_the_unit_square(mountain):
    p = parametrize(mountain, "heightfield")
    assert p.info["snapped_to_axis"] == "y"
    assert max(p.extent) == 1.0 and min(p.extent) > 0.99
    assert p.flipped_faces == 0 and p.degenerate_faces == 0
    assert p.coords.min() >= 0 and np.all(p.coords.max(axis=0) <= np.array(p.extent) + 1e-12)


def test_heightfield_keeps_aspect_ratio():
    m = Mesh([[0, 0, 0], [4, 0, 0.1], [4, 1, 0.2], [0, 1, 0]], [[0, 1, 2, 3]])
    p = parametrize(m, "heightfield", axis="z")
    assert sorted(p.extent) == [0.25, 1.0]


def test_heightfield_orientation_follows_face_normals():
    # faces whose normals point down (-z): with axis z they are clockwise, and the report says so
    m = Mesh([[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]], [[0, 1, 2, 3]])
    assert parametrize(m, "heightfield", axis="z").info["orientation"] == -1
    assert parametrize(m, "heightfield").info["orientation"] == 1   # best-fit normal follows the faces


def test_folded_faces_are_reported():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.2, 0.2, 1]], float)
    m = Mesh(v, [[0, 1, 2], [1, 3, 2], [0, 1, 4], [0, 4, 1]])  # the last two overlap, one is folded
    with pytest.warns(UserWarning, match="folded over"):
        p = parametrize(m, "heightfield", axis="z")
    assert p.flipped_faces == 1


def test_uv_method_uses_mesh_uv_and_normalizes():
    m = Mesh(np.zeros((3, 3)) + np.arange(3)[:, None], [[0, 1, 2]], uv=[[2, 2], [4, 2], [2, 3]])
    p = parametrize(m, "uv")
    assert p.coords.tolist() == [[0, 0], [1, 0], [0, 0.5]] and p.extent == (1.0, 0.5)


def test_auto_refuses_a_closed_mesh_and_says_why():
    bunny = geoimg.load_mesh(shared_file("meshes/closed_genus0/bunny.obj"))
    with pytest.raises(ParametrizationError, match="closed surface of genus 0.*heightfield: .* faces fold over"
                                                  ".*not a height field.*spherical parametrization"):
        parametrize(bunny, "auto")
    torus = geoimg.load_mesh(shared_file("meshes/closed_higher_genus/torus.obj"))
    with pytest.raises(ParametrizationError, match="genus 1 .torus-like.*1 handle would have to be cut"):
        parametrize(torus, "auto")


def test_errors():
    m = Mesh(np.eye(3), [[0, 1, 2]])
    with pytest.raises(ParametrizationError, match="no per-vertex UVs"):
        parametrize(m, "uv")
    with pytest.raises(ParametrizationError, match="method: expected one of"):
        parametrize(m, "sphere")
    with pytest.raises(ParametrizationError, match="axis: expected one of"):
        parametrize(m, "heightfield", axis="w")
    with pytest.raises(ParametrizationError, match="lie on a line"):
        parametrize(Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 1]], [[0, 1, 2]]), "heightfield", axis="z")
    with pytest.raises(TypeError, match="geoimg.Mesh"):
        parametrize(np.eye(3))
    with pytest.raises(ParametrizationError, match="NaN"):
        geoimg.Parametrization(np.full((2, 2), np.nan), (1, 1))


def test_signed_areas_of_mixed_faces():
    uv = np.array([[0, 0], [2, 0], [2, 1], [0, 1], [1, 2]], float)
    m = Mesh(np.zeros((5, 3)), [[0, 1, 2, 3], [3, 2, 4], [0, 3, 2, 1]])
    assert signed_face_areas(m, uv).tolist() == [2.0, 1.0, -2.0]
