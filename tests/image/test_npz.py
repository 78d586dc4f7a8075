"""Geometry images as NumPy .npz archives: exact round trips of every domain, plain arrays that np.load reads,
and hostile archives refused with one line before anything large is read."""
import io
import json
import zipfile

import numpy as np
import pytest

import geoimg
from geoimg._budget import ResourceError
from geoimg.cli import main
from helpers import data_file, load_data


@pytest.fixture(scope="module")
def images():
    sphere = load_data("sphere.obj")
    torus = load_data("torus.obj")
    bumpy = geoimg.grid_mesh(np.random.default_rng(0).random((12, 9)))
    return {"planar": geoimg.mesh_to_image(bumpy, 17, method="heightfield", axis="z",
                                           weights=geoimg.CoverageWeights(s=2.0)),
            "octahedral": geoimg.mesh_to_image(sphere, 17),
            "cut": geoimg.mesh_to_image(torus, 65)}


def _same(a, b):
    np.testing.assert_array_equal(a.pixels, b.pixels)
    np.testing.assert_array_equal(a.valid, b.valid)
    assert (a.normals is None) == (b.normals is None)
    if a.normals is not None:
        np.testing.assert_array_equal(a.normals, b.normals)
    assert a.domain == b.domain and a.metadata == b.metadata


@pytest.mark.parametrize("kind", ["planar", "octahedral", "cut"])
def test_round_trip_is_exact_and_equals_the_exr(images, kind, tmp_path):
    img = images[kind]
    back = geoimg.load_image(geoimg.save_image(img, tmp_path / "a.npz"))
    _same(img, back)
    _same(back, geoimg.load_image(img.save(tmp_path / "a.exr")))
    with np.load(tmp_path / "a.npz", allow_pickle=False) as data:        # plain arrays, no pickles
        assert data["positions"].dtype == np.float32 and data["positions"].shape == img.pixels.shape
        assert json.loads(str(data["metadata"]))["domain"] == kind


def test_a_masked_planar_image_keeps_its_mask(tmp_path):
    mask = np.ones((5, 6), bool)
    mask[0, 0] = False
    img = geoimg.GeometryImage(np.random.default_rng(1).random((5, 6, 3)).astype(np.float32), mask)
    _same(img, geoimg.load_image(img.save(tmp_path / "m.npz")))


def test_an_existing_file_is_kept_unless_overwrite(images, tmp_path):
    path = tmp_path / "a.npz"
    path.write_bytes(b"precious")
    with pytest.raises(FileExistsError):
        images["planar"].save(path)
    assert path.read_bytes() == b"precious"


def _archive(path, **arrays):
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    path.write_bytes(buf.getvalue())
    return path


def _bytes(path, data):
    path.write_bytes(data)
    return path


def _huge_header_archive(path):
    """positions that declare (100000, 100000, 3) float32 in their header, with no data behind it."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f4", "fortran_order": False, "shape": (100000, 100000, 3)})
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("positions.npy", header.getvalue())
    return path


P = np.zeros((4, 4, 3), np.float32)
META = np.array('{"domain": "planar"}')


@pytest.mark.parametrize("make, error, match", [
    (lambda p: _bytes(p, b"not a zip at all"), geoimg.ImageFileError, "not a .npz archive"),
    (lambda p: _archive(p, xyz=P), geoimg.ImageFileError, "not a geoimg .npz"),
    (lambda p: _archive(p, positions=P, extra=P), geoimg.ImageFileError, "not a geoimg .npz"),
    (lambda p: _archive(p, positions=np.array([{"evil": 1}] * 3, dtype=object)), geoimg.ImageFileError,
     "expected 3-D of kind 'f'"),
    (lambda p: _archive(p, positions=P[..., 0]), geoimg.ImageFileError, "2-D float32"),
    (lambda p: _archive(p, positions=P.astype(np.int32)), geoimg.ImageFileError, "kind 'f'"),
    (lambda p: _archive(p, positions=P, metadata=np.array("{not json")), geoimg.ImageFileError, "not valid JSON"),
    (lambda p: _archive(p, positions=P, metadata=np.array("[1, 2]")), geoimg.ImageFileError, "not a JSON object"),
    (lambda p: _archive(p, positions=P, mask=np.ones((3, 3), bool), metadata=META), geoimg.ImageFileError,
     "mask: expected shape"),
    (lambda p: _archive(p, positions=np.full((4, 4, 3), np.nan, np.float32), metadata=META), geoimg.ImageFileError,
     "NaN"),
    (lambda p: _archive(p, positions=P), geoimg.ImageFileError, "has no geoimg metadata"),
    (lambda p: _archive(p, positions=P, metadata=np.array('{"domain": "klein bottle"}')), geoimg.ImageFileError,
     "klein bottle"),
    (_huge_header_archive, ResourceError, "positions would need about"),
])
def test_hostile_archives_are_refused_with_one_line(tmp_path, make, error, match):
    path = make(tmp_path / "bad.npz")
    with pytest.raises(error, match=match):
        geoimg.load_image(path)


def test_a_truncated_archive_is_refused(images, tmp_path):
    good = images["octahedral"].save(tmp_path / "good.npz")
    cut = tmp_path / "cut.npz"
    cut.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    with pytest.raises(geoimg.ImageFileError):
        geoimg.load_image(cut)


def test_the_command_line_reads_and_writes_npz(tmp_path, capsys):
    out = tmp_path / "spot.npz"
    assert main(["image", str(data_file("sphere.obj")), "-o", str(out), "--res", "17", "-q"]) == 0
    assert main(["info", str(out)]) == 0 and "domain octahedral" in capsys.readouterr().out
    assert main(["filter", str(out), "-o", str(tmp_path / "f.exr"), "--mean", "3", "-q"]) == 0
    assert main(["mesh", str(tmp_path / "f.exr"), "-o", str(tmp_path / "f.obj"), "-q"]) == 0
    assert main(["image", str(data_file("sphere.obj")), "-o", str(tmp_path / "x.jpg"), "--res", "17"]) == 2
    assert "x.jpg: the geometry image must be named *.exr or *.npz or *.tif or *.tiff or *.npy" in \
        capsys.readouterr().err


def test_arrays_without_metadata_are_read_only_when_their_domain_is_named(tmp_path):
    path = _archive(tmp_path / "mine.npz", positions=np.random.default_rng(2).random((5, 5, 3)).astype(np.float32))
    with pytest.warns(UserWarning, match="read as a geometry image of the octahedral domain"):
        img = geoimg.load_image(path, assume="octahedral")
    assert img.domain.kind == "octahedral"
    with pytest.raises(geoimg.InputError, match="assume: expected one of planar, octahedral"):
        geoimg.load_image(path, assume="cut")
