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
    param = geoimg.parametrize(mesh)
    for weights in (geoimg.GaussianWeights(s=2.0), geoimg.CoverageWeights(s=2.0)):
        by_hand = geoimg.fit_surface(mesh, param, weights).sample(33)
        image = geoimg.mesh_to_image(MOUNTAIN, 33, weights=weights)
        assert np.array_equal(image.pixels, by_hand.pixels) and np.array_equal(image.normals, by_hand.normals)
        assert image.domain == by_hand.domain
        assert image.metadata["source"] == "mountain.obj" and image.metadata["parametrization"] == "heightfield"


def test_by_default_the_width_serves_the_resolution_and_the_fidelity_is_recorded():
    """No s: coverage weights of width PREFILTER pixel spacings at that resolution (a prefilter, not a
    smoothing); the image's distance to the mesh is in its metadata, and closer than the paper's s = 1."""
    from geoimg.surface import PREFILTER, prefilter_s
    mesh = geoimg.load_mesh(MOUNTAIN)
    param = geoimg.parametrize(mesh)
    image = geoimg.mesh_to_image(mesh, 65, parametrization=param)
    surface = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1.0))
    assert image.metadata["weights"] == "coverage"
    assert image.metadata["s"] == prefilter_s(surface, 65)
    assert surface.with_s(image.metadata["s"]).sigma == pytest.approx(PREFILTER * surface.pixel_spacing(65))
    paper = geoimg.mesh_to_image(mesh, 65, parametrization=param, weights=geoimg.GaussianWeights())
    assert paper.metadata["s"] == 1.0
    assert image.metadata["psnr_db"] > paper.metadata["psnr_db"] > 30
    assert 0 < image.metadata["hausdorff"] < 0.01
    assert "psnr_db" not in geoimg.mesh_to_image(mesh, 9, parametrization=param, fidelity=False).metadata


def test_every_conversion_records_its_maps_stretch():
    from geoimg.parametrization import map_stretch
    mesh = load_data("spot_low_resolution.obj")
    param = geoimg.parametrize(mesh, "sphere")
    image = geoimg.mesh_to_image(mesh, 17, parametrization=param)
    want = map_stretch(mesh, param)
    assert image.metadata["map_stretch"] == round(want["l2"], 3) >= 1.0
    assert image.metadata["starved"] == round(want["starved"], 4)
    assert "map_stretch" not in geoimg.mesh_to_image(mesh, 17, parametrization=param, fidelity=False).metadata
    assert image.metadata["map_stages"] == "; ".join(param.info["stages"]) == "conformal"
    planar = geoimg.mesh_to_image(load_data("mountain.obj"), 9)
    assert "map_stages" not in planar.metadata and "map_stretch" in planar.metadata


def test_an_image_far_from_its_mesh_says_so(monkeypatch):
    import geoimg._convert as convert
    monkeypatch.setattr(convert, "POOR_PSNR_DB", 500.0)
    mesh = geoimg.load_mesh(MOUNTAIN)
    with pytest.warns(UserWarning, match=r"far from its mesh \(PSNR .* dB < 500"):
        convert.measure_fidelity(geoimg.mesh_to_image(mesh, 9, fidelity=False), mesh)
    with pytest.warns(UserWarning, match=r"its map squeezes or folds"):             # the map: nothing asked for
        convert.measure_fidelity(geoimg.mesh_to_image(mesh, 9, fidelity=False), mesh)
    with pytest.warns(UserWarning, match=r"the smoothing asked for \(s = 8.0\).*try a smaller --s"):
        geoimg.mesh_to_image(mesh, 9, weights=geoimg.CoverageWeights(s=8.0))        # s was asked for: it is named


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
        geoimg.mesh_to_image(MOUNTAIN, 9, weights=geoimg.CoverageWeights(s=-1))


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


def _long_strip() -> geoimg.Mesh:
    """A 10 x 1 rectangle whose boundary is its four corners alone, filled with triangles through a row of
    interior points (no boundary vertex near the quarter points of its outline)."""
    from scipy.spatial import Delaunay
    xy = np.array([[0, 0], [10, 0], [10, 1], [0, 1]] + [[x, 0.5] for x in np.linspace(1, 9, 9)], float)
    tri = Delaunay(xy).simplices
    area = np.cross(xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]])
    tri[area < 0] = tri[area < 0][:, ::-1]
    return geoimg.Mesh(np.column_stack([xy, 0.1 * xy[:, 0] ** 2]), tri)


def test_a_boundary_of_four_vertices_far_from_the_quarters_gets_its_corners():
    strip = _long_strip()
    param = geoimg.parametrize(strip, "disk")
    corners = {tuple(np.round(param.coords[i], 9)) for i in range(4)}
    assert corners == {(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)}
    assert param.flipped_faces == 0


def test_a_piece_whose_map_is_refused_is_left_out_of_the_others():
    strip = _long_strip()
    lone = geoimg.Mesh([[20, 0, 0], [21, 0, 0], [20, 1, 0]], [[0, 1, 2]])       # three corners: no square
    both = geoimg.Mesh(np.vstack([strip.vertices, lone.vertices]), np.vstack([strip.faces, lone.faces + 13]))
    with pytest.warns(UserWarning, match=r"1 of 2 pieces left out, their map refused \(piece 1, 1 faces"):
        images = geoimg.mesh_to_images(both, 17, method="disk")
    assert len(images) == 1 and images[0].metadata["component"] == 0
    with pytest.raises(geoimg.ParametrizationError, match="four are needed"):
        geoimg.mesh_to_images(both, 17, method="disk", component=1)


def test_every_error_users_catch_is_in_geoimg_errors():
    from geoimg import errors
    from geoimg._budget import ResourceError
    from geoimg.animation import RenderError
    for name in ("ResourceError", "MissingDependency", "RenderError"):
        cls = getattr(errors, name)
        assert issubclass(cls, geoimg.GeoimgError) and getattr(geoimg, name) is cls
    assert ResourceError is errors.ResourceError and RenderError is errors.RenderError
    assert MissingDependency is errors.MissingDependency
    assert issubclass(errors.ResourceError, MemoryError) and issubclass(errors.MissingDependency, ImportError)
