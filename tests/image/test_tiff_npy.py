"""Geometry images as float TIFF (X, Y, Z and the mask as alpha, the record in ImageDescription) and as
.npy arrays with a JSON sidecar: exact round trips, other readers, files from elsewhere, hostile files."""
import json
import warnings

import cv2
import numpy as np
import pytest
import tifffile

import geoimg
from geoimg.cli import main
from geoimg.errors import ImageFileError
from helpers import load_data


@pytest.fixture(scope="module")
def images():
    bumpy = geoimg.grid_mesh(np.random.default_rng(0).random((12, 9)))
    disk = geoimg.mesh_to_image(load_data("cube_no_bottom.obj"), 17)            # a mask
    return {"planar": geoimg.mesh_to_image(bumpy, 17, method="heightfield", axis="z",
                                           weights=geoimg.CoverageWeights(s=2.0)), "disk": disk,
            "octahedral": geoimg.mesh_to_image(load_data("sphere.obj"), 17),
            "cut": geoimg.mesh_to_image(load_data("torus.obj"), 65)}


def _same(a, b, extras=True):
    np.testing.assert_array_equal(a.pixels, b.pixels)
    np.testing.assert_array_equal(a.valid, b.valid)
    assert a.domain == b.domain and a.metadata == b.metadata
    if extras:
        for name in ("normals", "colors"):
            x, y = getattr(a, name), getattr(b, name)
            assert (x is None) == (y is None) and (x is None or np.array_equal(x, y))


@pytest.mark.parametrize("kind", ["planar", "disk", "octahedral", "cut"])
def test_round_trips_are_exact(images, kind, tmp_path):
    img = images[kind]
    _same(img, geoimg.load_image(img.save(tmp_path / "a.npy")))
    with pytest.warns(UserWarning, match="the normals are not written"):
        back = geoimg.load_image(img.save(tmp_path / "a.tif"))
    _same(img, back, extras=False)
    assert back.normals is None


def test_other_readers_get_x_y_z_first(images, tmp_path):
    img = images["disk"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        img.save(tmp_path / "a.tif")
    img.save(tmp_path / "a.npy")
    t = tifffile.imread(tmp_path / "a.tif")  # scikit-image's TIFF reader
    assert (
        t.dtype == np.float32 and np.array_equal(t[..., :3], img.pixels) and np.array_equal(t[..., 3] > 0.5, img.valid)
    )
    bgra = cv2.imread(str(tmp_path / "a.tif"), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(bgra[..., 2::-1], img.pixels)
    a = np.load(tmp_path / "a.npy")
    assert np.array_equal(a[..., :3], img.pixels)
    record = json.loads((tmp_path / "a.npy.json").read_text())
    assert record["channels"][:4] == ["R", "G", "B", "mask"] and record["domain"] == "planar"


def test_files_from_elsewhere_need_their_domain_named(tmp_path):
    xyz = np.random.default_rng(1).random((6, 7, 3)).astype(np.float32)
    tifffile.imwrite(tmp_path / "x.tif", xyz, photometric="rgb")
    np.save(tmp_path / "x.npy", xyz)
    for name in ("x.tif", "x.npy"):
        with pytest.raises(ImageFileError, match="has no geoimg metadata"):
            geoimg.load_image(tmp_path / name)
        with pytest.warns(UserWarning, match="no geoimg metadata"):
            img = geoimg.load_image(tmp_path / name, assume="planar")
        assert np.array_equal(img.pixels, xyz) and img.domain.kind == "planar"


@pytest.mark.parametrize("write, match", [
    (lambda p: np.save(p, np.zeros((4, 4, 3), np.int32)), "float array"),
    (lambda p: np.save(p, np.zeros((4, 4), np.float32)), "float array"),
    (lambda p: np.save(p, np.zeros((4, 4, 2), np.float32)), "float array"),
    (lambda p: np.save(p, np.array([None, 1], dtype=object)), "float array"),
    (lambda p: p.write_bytes(b"not numpy at all"), "not a .npy array"),
    (lambda p: np.save(p, np.zeros((4, 4, 5), np.float32)), "5 channels and no x.npy.json"),
])
def test_hostile_npy_files_are_refused_in_one_line(tmp_path, write, match):
    p = tmp_path / "x.npy"
    write(p)
    with pytest.raises(ImageFileError, match=match):
        geoimg.load_image(p, assume="planar")


@pytest.mark.parametrize("sidecar, match", [
    ("{not json", "not a geoimg sidecar"),
    ('{"channels": ["R", "G"], "domain": "planar", "metadata": {}}', "must name the array's 3 channels"),
    ('{"channels": ["R", "G", "B"], "metadata": {}}', "KeyError"),
    ('{"channels": ["R", "G", "B"], "domain": "wobbly", "metadata": {}}', "wobbly"),
])
def test_a_damaged_sidecar_is_refused(tmp_path, sidecar, match):
    np.save(tmp_path / "x.npy", np.zeros((4, 4, 3), np.float32))
    (tmp_path / "x.npy.json").write_text(sidecar)
    with pytest.raises(ImageFileError, match=match):
        geoimg.load_image(tmp_path / "x.npy")


def test_integer_tiffs_and_damaged_records_are_refused(tmp_path):
    tifffile.imwrite(tmp_path / "i.tif", np.zeros((4, 4, 3), np.uint16), photometric="rgb")
    with pytest.raises(ImageFileError, match="integers, not coordinates"):
        geoimg.load_image(tmp_path / "i.tif", assume="planar")
    tifffile.imwrite(tmp_path / "d.tif", np.zeros((4, 4, 3), np.float32), photometric="rgb",
                     description='{"geoimg": [1, 2]}')
    with pytest.raises(ImageFileError, match="geoimg record is not a JSON object"):
        geoimg.load_image(tmp_path / "d.tif")


def test_a_sidecar_in_the_way_leaves_both_files_unwritten(images, tmp_path, capsys):
    (tmp_path / "a.npy.json").write_text("mine")
    with pytest.raises(FileExistsError):
        images["planar"].save(tmp_path / "a.npy")
    assert not (tmp_path / "a.npy").exists() and (tmp_path / "a.npy.json").read_text() == "mine"
    mesh = tmp_path / "m.obj"
    geoimg.save_mesh(geoimg.grid_mesh(np.random.default_rng(0).random((5, 5))), mesh)
    assert main(["image", str(mesh), "-o", str(tmp_path / "m.tif"), "--res", "9"]) == 0
    assert "geoimg image: warning:" in capsys.readouterr().err and (tmp_path / "m.tif").is_file()
    assert main(["image", str(mesh), "-o", str(tmp_path / "m.npy"), "--res", "9"]) == 0
    assert main(["mesh", str(tmp_path / "m.npy"), "-o", str(tmp_path / "q.obj")]) == 0
