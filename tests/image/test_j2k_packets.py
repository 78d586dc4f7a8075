"""Progressive JPEG 2000 geometry images: the packet headers read exactly, a codestream cut after a resolution
level is a standard one that decodes to a coarser image, and the first k bytes of a file decode to a coarser
shape (closed in, closed out), or say in one line that they are too few."""
import struct
import warnings

import numpy as np
import pytest

import geoimg
from geoimg.errors import ImageFileError, InputError
from geoimg.image._j2k_packets import cut_after, read_layout, resolution_ends
from geoimg.image._jp2 import _boxes, decode, encode
from geoimg.mesh import topology
import meshes

imagecodecs = pytest.importorskip("imagecodecs")


@pytest.fixture(scope="module")
def images():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        spot = geoimg.load_mesh("samples/data/spot_low_resolution.obj")
        out = {res: geoimg.mesh_to_image(spot, res, fidelity=False) for res in (33, 129, 513)}
        out["terrain"] = geoimg.mesh_to_image("geoimg/data/mountain.obj", 65, fidelity=False)
        out["masked"] = geoimg.mesh_to_image(meshes.petal(), 33, method="heightfield", axis="z", fidelity=False)
    return out


def _codestream(data: bytes) -> bytes:
    (start, end), = [(s, e) for k, s, e in _boxes(data) if k == b"jp2c"]
    return data[start + 8:end]


@pytest.mark.parametrize("name", [33, 129, 513, "terrain", "masked"])
@pytest.mark.parametrize("level", [0, 50, 75])
def test_the_packets_are_read_to_the_last_byte_and_cuts_decode(images, name, level):
    img = images[name]
    cs = _codestream(encode(img, level))
    layout = read_layout(cs)
    ends = resolution_ends(cs)
    assert len(ends) == layout.levels + 1 and ends[-1] == layout.data_end      # every packet's length, exactly
    assert all(a <= b for a, b in zip(ends, ends[1:]))
    full = imagecodecs.jpeg2k_decode(cs).astype(np.float64)
    assert np.array_equal(imagecodecs.jpeg2k_decode(cut_after(cs, layout.levels)), full)
    errors = [np.abs(imagecodecs.jpeg2k_decode(cut_after(cs, r)) - full).mean() for r in range(layout.levels + 1)]
    assert all(a >= b for a, b in zip(errors, errors[1:])) and errors[-1] == 0


def test_colour_channels_are_packets_too(images):
    rng = np.random.default_rng(1)
    img = images[33]
    coloured = geoimg.GeometryImage(img.pixels, img.mask, img.domain, metadata=img.metadata,
                                    colors=rng.random(img.pixels.shape).astype(np.float32))
    cs = _codestream(encode(coloured, 60, colors=True))
    assert read_layout(cs).components == 6 and resolution_ends(cs)[-1] == read_layout(cs).data_end


def test_every_prefix_decodes_as_far_as_it_goes_or_says_so(images):
    data = encode(images[129], 70)
    levels, last = [], None
    for k in [*range(97, len(data), 97), len(data)]:
        try:
            out = decode(data, max_bytes=k)
        except ImageFileError as e:
            assert last is None and "read more of the file" in str(e)    # too few: refused, never after a success
            continue
        last = out.metadata.get("jpeg2000_levels", "whole")
        levels.append(last)
        assert topology(out.to_mesh()).describe().startswith("closed surface of genus 0")
    assert levels[0] == "1 of 5" and levels[-1] == "whole" and len(set(levels)) == 5     # 1 .. 4 of 5, whole


def test_a_truncated_file_is_decoded_with_a_warning(images, tmp_path):
    data = encode(images[129], 70)
    path = tmp_path / "cut.jp2"
    path.write_bytes(data[: len(data) // 2])
    with pytest.warns(UserWarning, match=r"truncated after \d+ bytes: decoded its first \d of 5"):
        out = geoimg.load_image(path)
    assert out.shape == (129, 129)
    first = geoimg.load_image(tmp_path / "cut.jp2", max_bytes=len(data) // 4)
    assert first.metadata["jpeg2000_bytes"] == len(data) // 4
    whole = geoimg.load_image(tmp_path / "cut.jp2", max_bytes=10 ** 30)      # more than the file: all of it
    assert whole.metadata["jpeg2000_levels"] == out.metadata["jpeg2000_levels"]
    with pytest.raises(ImageFileError, match="inside the JP2 signature; read more"):
        geoimg.load_image(tmp_path / "cut.jp2", max_bytes=10)
    with pytest.raises(InputError, match="only a compressed .jp2"):
        geoimg.load_image(tmp_path / "x.exr", max_bytes=100)
    with pytest.raises(InputError, match="max_bytes"):
        decode(data, max_bytes=-3)


def test_other_kinds_of_codestream_are_refused(images):
    cs = bytearray(_codestream(encode(images[33], 60)))
    tiled = bytearray(cs)
    tiled[24:28] = struct.pack(">I", 16)                             # SIZ: tiles of 16 pixels
    with pytest.raises(ImageFileError, match="more than one tile"):
        read_layout(bytes(tiled))
    at = cs.index(b"\xff\x52")
    layers = bytearray(cs)
    layers[at + 6:at + 8] = struct.pack(">H", 3)                     # three quality layers
    with pytest.raises(ImageFileError, match="several layers"):
        read_layout(bytes(layers))
    with pytest.raises(ImageFileError, match="not a JPEG 2000 codestream"):
        read_layout(b"\x00" * 40)
    with pytest.raises(ImageFileError, match="ends inside its headers"):
        read_layout(bytes(cs[:60]))
    with pytest.raises(ImageFileError, match="whole resolution levels"):
        cut_after(bytes(cs), 99)
