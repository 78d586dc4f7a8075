"""EXR layouts (the mask as A for compositing tools and OpenCV) and files without geoimg metadata (refused
unless their domain is named)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import geoimg
from geoimg._raster import FLOAT, write_raster
from geoimg.cli import main
from helpers import data_file, load_data


@pytest.fixture(scope="module")
def masked():
    rng = np.random.default_rng(3)
    mask = np.ones((6, 7), bool)
    mask[:2, :3] = False
    return geoimg.GeometryImage(rng.random((6, 7, 3)).astype(np.float32), mask,
                                normals=rng.random((6, 7, 3)).astype(np.float32), metadata={"source": "x"})


@pytest.mark.parametrize("which", ["masked", "octahedral"])
def test_the_rgba_layout_reads_back_exactly(masked, which, tmp_path):
    img = masked if which == "masked" else geoimg.mesh_to_image(load_data("sphere.obj"), 17)
    back = geoimg.load_image(img.save(tmp_path / "a.exr", layout="rgba"))
    np.testing.assert_array_equal(back.pixels, img.pixels)
    np.testing.assert_array_equal(back.normals, img.normals)
    assert (back.mask is None) == (img.mask is None) and np.array_equal(back.valid, img.valid)
    assert back.domain == img.domain and back.metadata == img.metadata


def test_opencv_reads_the_rgba_layout_with_the_mask_as_alpha(masked, tmp_path):
    path = masked.save(tmp_path / "a.exr", layout="rgba")
    code = ("import sys, numpy as np, cv2; a = cv2.imread(sys.argv[1], cv2.IMREAD_UNCHANGED); "
            "np.save(sys.argv[2], a)")
    subprocess.run([sys.executable, "-c", code, str(path), str(tmp_path / "cv.npy")], check=True,
                   env={**os.environ, "OPENCV_IO_ENABLE_OPENEXR": "1"})
    bgra = np.load(tmp_path / "cv.npy")
    assert bgra.shape == (6, 7, 4) and bgra.dtype == np.float32
    np.testing.assert_array_equal(bgra[..., 2::-1], masked.pixels)             # B, G, R = Z, Y, X
    np.testing.assert_array_equal(bgra[..., 3] > 0.5, masked.valid)


def test_a_bad_layout_is_refused(masked, tmp_path, capsys):
    with pytest.raises(geoimg.InputError, match="layout: expected one of geoimg, rgba"):
        masked.save(tmp_path / "a.exr", layout="rgb")
    with pytest.raises(SystemExit):
        main(["image", str(data_file("sphere.obj")), "-o", str(tmp_path / "b.exr"), "--layout", "argb"])
    assert "invalid choice: 'argb'" in capsys.readouterr().err and not (tmp_path / "b.exr").exists()


def test_an_exr_from_another_program_needs_its_domain_named(tmp_path, capsys):
    path = tmp_path / "foreign.exr"
    write_raster(path, np.random.default_rng(4).random((5, 6, 3)).astype(np.float32), ["R", "G", "B"], FLOAT)
    with pytest.raises(geoimg.ImageFileError, match="has no geoimg metadata"):
        geoimg.load_image(path)
    assert main(["mesh", str(path), "-o", str(tmp_path / "q.obj")]) == 2
    err = capsys.readouterr().err
    assert "--assume planar" in err and len(err.strip().splitlines()) == 1
    assert main(["mesh", str(path), "-o", str(tmp_path / "q.obj"), "--assume", "planar"]) == 0
    out = capsys.readouterr()
    assert "read as a geometry image of the planar domain" in out.err and "wrote" in out.out
    with pytest.warns(UserWarning, match="planar domain"):
        assert geoimg.load_image(path, assume="planar").shape == (5, 6)
