"""16-bit previews record their offset and step: read back as approximate geometry only when asked."""
import json

import numpy as np
import pytest

import geoimg
from geoimg._raster import UINT16, UINT8, write_raster
from geoimg.cli import main
from helpers import load_data


@pytest.fixture(scope="module")
def images():
    rng = np.random.default_rng(5)
    mask = np.ones((9, 11), bool)
    mask[3:5, 4:7] = False
    masked = geoimg.GeometryImage((rng.random((9, 11, 3)) * [10, 200, 0.01] - 50).astype(np.float32), mask,
                                  metadata={"source": "m"})
    return {"masked planar": masked, "octahedral": geoimg.mesh_to_image(load_data("sphere.obj"), 17)}


@pytest.mark.parametrize("which", ["masked planar", "octahedral"])
def test_a_preview_comes_back_within_half_a_step_when_asked(images, which, tmp_path):
    img = images[which]
    path = img.preview(tmp_path / "p.png")
    with pytest.raises(geoimg.ImageFileError, match="approximate=True"):
        geoimg.load_image(path)
    back = geoimg.load_image(path, approximate=True)
    np.testing.assert_array_equal(back.valid, img.valid)
    assert back.domain == img.domain and back.normals is None
    assert {k: v for k, v in back.metadata.items() if k != "approximate"} == img.metadata
    p = img.pixels[img.valid].astype(np.float64)
    step = np.ptp(p, axis=0) / 65534
    err = np.abs(back.pixels[img.valid] - p).max(axis=0)
    assert np.all(err <= 0.5 * step + 2 * np.finfo(np.float32).eps * np.abs(p).max(axis=0))


def _png(path, data, fmt, attrs=()):
    write_raster(path, data, ["R", "G", "B"], fmt, attrs)
    return path


GOOD = {"domain": "planar", "preview_offset": [0, 0, 0], "preview_step": [1, 1, 1]}


@pytest.mark.parametrize("attrs, match", [
    ((), "not a geoimg preview"),
    ([("geoimg:preview", "{oops")], "damaged"),
    ([("geoimg:preview", json.dumps({"domain": "planar"}))], "damaged"),
    ([("geoimg:preview", json.dumps({**GOOD, "preview_step": [1, 1]}))], "damaged"),
    ([("geoimg:preview", json.dumps({**GOOD, "preview_offset": [0, 0, None]}))], "damaged"),
    ([("geoimg:preview", json.dumps({**GOOD, "domain": "torus"}))], "torus"),
])
def test_other_pngs_and_damaged_previews_are_refused(tmp_path, attrs, match):
    path = _png(tmp_path / "x.png", np.full((4, 4, 3), 7, np.uint16), UINT16, attrs)
    with pytest.raises(geoimg.ImageFileError, match=match):
        geoimg.load_image(path, approximate=True)


def test_an_8_bit_picture_is_refused(tmp_path):
    path = _png(tmp_path / "photo.png", np.full((4, 4, 3), 200, np.uint8), UINT8)
    with pytest.raises(geoimg.ImageFileError, match="a picture cannot become geometry"):
        geoimg.load_image(path, approximate=True)


def test_the_command_line_reads_a_preview_only_with_approximate(images, tmp_path, capsys):
    path = images["octahedral"].preview(tmp_path / "p.png")
    assert main(["mesh", str(path), "-o", str(tmp_path / "q.obj")]) == 2
    assert "--approximate" in capsys.readouterr().err
    assert main(["mesh", str(path), "-o", str(tmp_path / "q.obj"), "--approximate", "-q"]) == 0
    assert geoimg.load_mesh(tmp_path / "q.obj").n_faces == images["octahedral"].to_mesh().n_faces


@pytest.mark.parametrize("shape, side", [((9, 11), 264), ((600, 300), 512)])
def test_a_notebook_shows_the_image_as_a_picture(shape, side):
    import cv2
    rng = np.random.default_rng(6)
    mask = np.ones(shape, bool)
    mask[0, 0] = False
    img = geoimg.GeometryImage(rng.random(shape + (3,)).astype(np.float32), mask)
    rgb = cv2.imdecode(np.frombuffer(img._repr_png_(), np.uint8), cv2.IMREAD_COLOR)
    assert max(rgb.shape[:2]) == side and rgb.shape[2] == 3
    assert not rgb[0, 0].any() and rgb[-1, -1].all()               # masked pixels black, valid ones lit


def test_a_notebook_shows_a_mesh_as_a_table():
    m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5]], [[0, 1, 2, 3], [0, 1, 2, -1]])
    html = m._repr_html_()
    assert html.startswith("<table>") and "5 (1 unreferenced)" in html and "1 triangles, 1 quads" in html
    assert "[0.0, 0.0, 0.0] .. [1.0, 1.0, 0.0]" in html
