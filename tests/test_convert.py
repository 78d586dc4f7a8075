"""mesh_to_image: one call from a mesh (or file) to its geometry image, the same as the steps it runs;
optional dependencies refused in one line."""
import sys

import numpy as np
import pytest

import geoimg
from geoimg._optional import MissingDependency, require

from helpers import MOUNTAIN, load_data


def test_mesh_to_image_is_the_pipeline_in_one_call():
    mesh = geoimg.load_mesh(MOUNTAIN)
    by_hand = geoimg.fit_surface(mesh, geoimg.parametrize(mesh), 2.0).sample(33)
    image = geoimg.mesh_to_image(MOUNTAIN, 33, 2.0)
    assert np.array_equal(image.pixels, by_hand.pixels) and np.array_equal(image.normals, by_hand.normals)
    assert image.domain == by_hand.domain
    assert image.metadata["source"] == "mountain.obj" and image.metadata["parametrization"] == "heightfield"


def test_a_given_parametrization_is_used_and_progress_is_reported():
    mesh = load_data("spot_low_resolution.obj")
    param = geoimg.parametrize(mesh, "sphere")
    said = []
    image = geoimg.mesh_to_image(mesh, 17, parametrization=param, normals=False, progress=said.append)
    assert image.domain.kind == "octahedral" and image.normals is None and image.metadata["source"] == ""
    assert not any("parametrizing" in s for s in said) and any("sampling 17" in s for s in said)


def test_bad_inputs_are_refused(tmp_path):
    with pytest.raises(TypeError, match="mesh_or_path"):
        geoimg.mesh_to_image(42)
    with pytest.raises(FileNotFoundError):
        geoimg.mesh_to_image(tmp_path / "none.obj")
    with pytest.raises(ValueError, match="s: expected"):
        geoimg.mesh_to_image(MOUNTAIN, 9, s=-1)


def test_a_missing_optional_dependency_names_the_install_command(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pygltflib", None)          # as if it were not installed
    with pytest.raises(MissingDependency, match=r"writing a glTF morph needs the pygltflib package: "
                                                r"pip install 'geoimg\[render\]'"):
        require("pygltflib", "writing a glTF morph")
    from geoimg.animation import morph, save_glb
    a = geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32))
    m = morph(a, a, frames=2, align="none")                      # morphs need no extra
    with pytest.raises(MissingDependency, match="pygltflib"):
        save_glb(m, tmp_path / "m.glb")
    assert not (tmp_path / "m.glb").exists()
