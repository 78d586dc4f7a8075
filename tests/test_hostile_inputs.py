"""Hostile and odd inputs beyond the file readers (those are in tests/mesh/test_hostile_files.py): absurd
sizes refused with an estimate before any work, degenerate geometry and implausible images refused, bad
numbers refused, each in one line; metadata of numpy scalars written."""
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import filters
import geoimg
from geoimg._budget import ResourceError
from geoimg.cli import main

from helpers import MOUNTAIN


@pytest.fixture(scope="module")
def small_exr(tmp_path_factory):
    path = tmp_path_factory.mktemp("hostile") / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(path), "--res", "17", "-q"]) == 0
    return path


@pytest.mark.parametrize("argv, message", [
    (["image", str(MOUNTAIN), "--res", "100000"], "would need about .* GiB; the limit is"),
    (["image", str(MOUNTAIN), "--s", "1e-300", "--res", "9"], "s: expected a number from 1e-06 to 1000"),
    (["image", str(MOUNTAIN), "--s", "1e300", "--res", "9"], "s: expected a number from 1e-06 to 1000"),
    (["image", str(MOUNTAIN), "--s", "1e-300", "--res", "9", "--weights", "gaussian"],
     "s: expected values from 0.001 to 1000"),
])
def test_absurd_image_requests_are_one_line(tmp_path, capsys, argv, message):
    argv = argv[:2] + ["-o", str(tmp_path / "x.exr")] + argv[2:]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and __import__("re").search(message, err)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("ops, message", [
    (["--mean", "1000001"], "padding a 17 x 17 image by 500000 would need"),
    (["--gaussian", "1e6"], "would need about"),
])
def test_absurd_filters_are_one_line(tmp_path, capsys, small_exr, ops, message):
    assert main(["filter", str(small_exr), "-o", str(tmp_path / "f.exr")] + ops) == 2
    assert message in capsys.readouterr().err and not (tmp_path / "f.exr").exists()


def test_absurd_resizes_and_morph_pictures_are_refused(tmp_path, capsys, small_exr):
    with pytest.raises(filters.TooLarge, match="resizing to 1000000 x 1000000"):
        filters.resize(np.zeros((4, 4, 3)), (1_000_000, 1_000_000))
    assert main(["morph", str(small_exr), str(small_exr), "--frames", "100000000", "--gif",
                 str(tmp_path / "m.gif")]) == 2
    assert "100000000 pictures of 800 x 600 would need" in capsys.readouterr().err


def test_the_memory_limit_can_be_set(monkeypatch):
    monkeypatch.setenv("GEOIMG_MAX_MEMORY", "1M")
    surf = geoimg.fit_surface(*(lambda m: (m, geoimg.parametrize(m, "heightfield", axis="y")))(
        geoimg.load_mesh(MOUNTAIN)))
    with pytest.raises(ResourceError, match="the limit is 0.0 GiB"):
        surf.sample(257)
    monkeypatch.setenv("GEOIMG_MAX_MEMORY", "lots")
    with pytest.raises(ValueError, match="GEOIMG_MAX_MEMORY: expected a size"):
        filters.memory_limit()


@pytest.mark.parametrize("vertices, error, message", [
    ([[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]], geoimg.ParametrizationError, "zero area"),     # collinear
    (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]]) * 1e-300, geoimg.MeshError, "size 1e-300"),
    (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.5], [0, 1, 0]]) * 1e200, geoimg.MeshError, "size 1e\\+200"),
])
def test_degenerate_geometry_is_refused(vertices, error, message):
    faces = [[0, 1, 2], [1, 2, 3]] if message == "zero area" else [[0, 1, 2, 3]]
    with pytest.raises(error, match=message):
        geoimg.mesh_to_image(geoimg.Mesh(vertices, faces), 9)


def test_coordinates_near_the_float_limit_are_one_line(tmp_path, capsys):
    """A tetrahedron at 1e308: refused before the repairs square a size (they overflowed), and described by
    geoimg info without overflowing (its bounding box rounded by scaling read inf)."""
    path = tmp_path / "huge.obj"
    path.write_text("v 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\nv 1e308 1e308 1e308\n"
                    "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n")
    with pytest.raises(geoimg.MeshError, match="size 1e\\+308"):
        geoimg.mesh_to_images(path, 9)
    assert main(["image", str(path), "-o", str(tmp_path / "h.exr"), "--res", "9"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "scale the mesh first" in err
    assert not (tmp_path / "h.exr").exists()
    with __import__("warnings").catch_warnings():
        __import__("warnings").simplefilter("error")
        assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "[0, 0, 0] .. [1e+308, 1e+308, 1e+308], diagonal 1.73205e+308" in out


def test_a_preview_png_is_not_a_geometry_image(tmp_path, capsys, small_exr):
    img = geoimg.load_image(small_exr)
    img.preview(tmp_path / "p.png")
    with pytest.raises(geoimg.ImageFileError, match="a 16-bit preview, its coordinates rounded"):
        geoimg.load_image(tmp_path / "p.png")                 # read only when asked: approximate=True
    assert main(["mesh", str(tmp_path / "p.png"), "-o", str(tmp_path / "p.obj")]) == 2
    assert not (tmp_path / "p.obj").exists()


def test_bad_view_angles_and_rates_are_refused(tmp_path, capsys, small_exr):
    assert main(["render", str(small_exr), "-o", str(tmp_path / "r.png"), "--azimuth", "nan"]) == 2
    assert "azimuth: expected a finite number" in capsys.readouterr().err
    assert main(["morph", str(small_exr), str(small_exr), "-o", str(tmp_path / "m.glb"), "--fps", "inf",
                 "--frames", "2"]) == 2
    assert "fps" in capsys.readouterr().err and not (tmp_path / "m.glb").exists()


def test_numpy_scalars_in_metadata_are_written(tmp_path):
    img = geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32), metadata={"x": np.float32(2), "v": np.arange(2)})
    back = geoimg.load_image(img.save(tmp_path / "n.exr"))
    assert back.metadata == {"x": 2.0, "v": [0, 1]}
    with pytest.raises(geoimg.ImageError, match="metadata: cannot be written as JSON"):
        geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32), metadata={"f": object()}).save(tmp_path / "o.exr")


def test_an_all_masked_image_is_refused():
    with pytest.raises(geoimg.ImageError, match="selects no pixel"):
        geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32), np.zeros((3, 3), bool))


def test_a_file_name_that_is_not_utf8_is_one_line(tmp_path, capsys, small_exr):
    import os
    name = os.fsdecode(os.path.join(os.fsencode(str(tmp_path)), b"bad\xff.exr"))
    with open(name, "wb") as fh:
        fh.write(small_exr.read_bytes())
    assert main(["info", name]) == 2
    err = capsys.readouterr().err
    assert "not valid UTF-8" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("meta, message", [
    ('{"domain": "planar", "orientation": Infinity}', "orientation"),
    ('{"domain": "planar", "extent": [1.0]}', "extent"),
    ('{"domain": "planar", "extent": [1.0, 0.0]}', "extent"),
    ('[1, 2]', "not a JSON object"),
    ('{"domain": "cut", "segments": [[0, 3, 0]]}', "segments"),
])
def test_exr_metadata_that_lies_is_one_line(tmp_path, meta, message):
    import OpenImageIO as oiio
    path = tmp_path / "lie.exr"
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(5, 5, 3, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B")
    spec.attribute("geoimg:metadata", meta)
    spec.attribute("geoimg:domain", "cut" if '"cut"' in meta else "planar")
    out.open(str(path), spec)
    out.write_image(np.zeros((5, 5, 3), np.float32))
    out.close()
    with pytest.raises(geoimg.GeoimgError, match=message):
        geoimg.load_image(path)


@settings(max_examples=int(os.environ.get("GEOIMG_FUZZ_EXAMPLES", 30)), deadline=5000,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cut=st.floats(0.0, 1.0), at=st.integers(0, 4000), value=st.integers(0, 255))
def test_damaged_geometry_images_are_read_or_refused(tmp_path, small_exr, cut, at, value):
    data = bytearray(small_exr.read_bytes())
    data[min(at, len(data) - 1)] = value
    path = tmp_path / "damaged.exr"
    path.write_bytes(bytes(data[:max(1, int(len(data) * cut))]))
    try:
        geoimg.load_image(path)
    except geoimg.GeoimgError:
        pass


@pytest.mark.parametrize("faces", [[[0, 1, 2], [0, 2, 3], [0, 0, 1]],                 # a repeated vertex
                                   [[0, 4, 2], [4, 1, 2], [0, 2, 3], [0, 4, 1]]])     # corners on a line
def test_faces_of_zero_area_are_left_out_with_a_warning(faces):
    v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0, 0]]
    with pytest.warns(UserWarning, match="left out 1 faces of zero area"):
        images = geoimg.mesh_to_images(geoimg.Mesh(v, faces), 9)
    assert len(images) == 1 and images[0].domain.kind == "planar"


def test_an_impossible_path_is_one_line(tmp_path, capsys):
    # (a folder without write permission cannot be shown here: the tests run as root, who writes anywhere)
    assert main(["image", str(MOUNTAIN), "-o", str(tmp_path / ("n" * 300 + ".exr")), "--res", "9"]) == 2
    err = capsys.readouterr().err
    assert "File name too long" in err and len(err.strip().splitlines()) == 1


def test_raster_headers_are_checked_against_the_memory_limit_before_reading(tmp_path, monkeypatch):
    from helpers import textured_spot
    obj = textured_spot(tmp_path)
    monkeypatch.setenv("GEOIMG_MAX_MEMORY", "1M")              # the 1024 x 1024 texture needs 12 MiB as floats
    with pytest.raises(ResourceError, match="texture of 1024 x 1024 x 3"):
        geoimg.mesh._appearance.read_texture(tmp_path / "spot_texture.png")
    with pytest.warns(UserWarning, match="spot_texture.png cannot be read"):
        assert geoimg.load_mesh(obj).texture is None            # a texture too large is left out, said once


def test_wrong_types_are_geoimg_errors(tmp_path):
    """Each a GeoimgError naming the argument (they were ValueError from dict, TypeError from pathlib and
    AttributeError)."""
    px = np.zeros((5, 5, 3), np.float32)
    mesh = geoimg.load_mesh(MOUNTAIN)
    for call, message in [
        (lambda: geoimg.GeometryImage(px, metadata="abc"), "metadata: expected a dict"),
        (lambda: geoimg.load_mesh(123), "path: expected a file name"),
        (lambda: geoimg.load_image(123), "path: expected a file name"),
        (lambda: geoimg.save_mesh(mesh, 5), "path: expected a file name"),
        (lambda: geoimg.GeometryImage(px).save(5), "path: expected a file name"),
        (lambda: geoimg.mesh.surface_distance(mesh, "x"), "other: expected a geoimg.Mesh"),
        (lambda: geoimg.mesh.surface_distance(None, mesh), "reference: expected a geoimg.Mesh"),
        (lambda: geoimg.GeometryImage(px, normals=np.zeros((5, 5, 3), int)), "normals: expected a float"),
    ]:
        with pytest.raises(geoimg.GeoimgError, match=message):
            call()
    assert list(tmp_path.iterdir()) == []


def test_non_finite_results_are_refused_not_returned():
    px = np.zeros((5, 5, 3), np.float32)
    with pytest.raises(geoimg.ImageError, match="normals: contain NaN"):
        geoimg.GeometryImage(px, normals=np.full((5, 5, 3), np.nan, np.float32))
    with pytest.raises(geoimg.InputError, match="no direction"):
        geoimg.parametrization.sphere_to_square(np.zeros((2, 3)))
    with pytest.raises(geoimg.InputError, match="no direction"):
        geoimg.parametrization.area_ratio(np.zeros(3))
    mesh = geoimg.load_mesh(MOUNTAIN)
    planar = geoimg.fit_surface(mesh, geoimg.parametrize(mesh, "heightfield", axis="y"), geoimg.GaussianWeights(s=2.0))
    with pytest.raises(geoimg.InputError, match="so far outside the parameter domain"):
        planar.evaluate([[0.5, 0.5], [1e300, 1e300]])
    with pytest.raises(geoimg.InputError, match="so far outside the parameter domain"):
        planar.normals([[1e300, 1e300]])
    assert np.isfinite(planar.evaluate([[0.5, 0.5], [3.0, -2.0]])).all()       # extrapolation stays allowed
    from meshes import icosphere
    ball = icosphere(2)
    sphere = geoimg.fit_surface(ball, geoimg.parametrize(ball))
    with pytest.raises(geoimg.InputError, match="no direction"):
        sphere.evaluate_directions([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])


def test_numpy_scalars_are_numbers_in_the_conversion_options():
    from geoimg.batch import BatchOptions
    numpy_made = BatchOptions(resolution=np.int64(65), weights=geoimg.GaussianWeights(
        s=np.float32(0.5), n=np.int32(5), tol=np.float64(0.0)))
    assert numpy_made.digest() == BatchOptions(resolution=65, weights=geoimg.GaussianWeights(
        s=0.5, n=5, tol=0.0)).digest()
    assert type(numpy_made.resolution) is int and type(numpy_made.weights.s) is float
    assert type(numpy_made.weights.n) is int
    with pytest.raises(geoimg.InputError, match="resolution"):
        BatchOptions(resolution=np.float64(65.0))
