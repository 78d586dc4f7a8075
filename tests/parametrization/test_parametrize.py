
import numpy as np
import pytest

import geoimg
from geoimg import Mesh, ParametrizationError, parametrize
from geoimg.parametrization import signed_face_areas

import meshes
from helpers import load_data


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
    m = Mesh(np.eye(3), [[0, 1, 2]], uv=[[2, 2], [4, 2], [2, 3]])
    p = parametrize(m, "uv")
    assert p.coords.tolist() == [[0, 0], [1, 0], [0, 0.5]] and p.extent == (1.0, 0.5)


@pytest.mark.parametrize("make, words", [
    (meshes.three_pieces, "3 components.*split the 3 components .geoimg.mesh.repair; geoimg.mesh_to_images"),
    (lambda: geoimg.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]],
                         [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 5, 4], [0, 4, 6], [0, 6, 5], [4, 5, 6]]),
     "split the pinch vertices"),
])
def test_auto_refuses_what_no_parametrization_takes_and_says_why(make, words):
    with pytest.raises(ParametrizationError, match=words) as err:
        parametrize(make(), "auto")
    assert "heightfield: " in str(err.value)


@pytest.mark.slow
@pytest.mark.parametrize("make", [lambda: load_data("torus.obj"), lambda: load_data("bob_tri.obj"),
                                  meshes.holey_sphere])
def test_auto_cuts_open_what_is_neither_a_disk_nor_a_sphere(make):
    p = parametrize(make(), "auto")
    assert p.method == "cut" and p.domain == "cut" and p.flipped_faces == 0 and p.mesh is not None


def test_errors():
    m = Mesh(np.eye(3), [[0, 1, 2]])
    with pytest.raises(ParametrizationError, match="no per-vertex UVs"):
        parametrize(m, "uv")
    with pytest.raises(ParametrizationError, match="method: expected one of"):
        parametrize(m, "conformal")
    with pytest.raises(ParametrizationError, match="needs a closed genus-0 mesh.*1 boundary loop"):
        parametrize(m, "sphere")
    with pytest.raises(ParametrizationError, match="four are needed"):
        parametrize(m, "disk")
    with pytest.raises(ParametrizationError, match="coords: expected shape .N, 3. for the octahedral"):
        geoimg.Parametrization(np.zeros((3, 2)), (1, 1), "octahedral")
    with pytest.raises(ParametrizationError, match="unit vectors"):
        geoimg.Parametrization(np.ones((3, 3)), (1, 1), "octahedral")
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
