"""Shapes compressed into JPEG 2000 geometry images: the budget honoured, closed in closed out (the glued
seams welded after lossy coding moved them apart), files that any reader of geoimg takes, and every bad input
refused in one line with no file left behind."""
import dataclasses
import re

import numpy as np
import pytest

import geoimg
from geoimg._offset_fit import BENDINGS
from geoimg.cli import main
from geoimg.image._jp2 import HEADROOM, continue_masked, decode, encode
from geoimg.mesh import topology

from helpers import data_file, load_data

pytest.importorskip("imagecodecs")

SPOT_TEXTURED = data_file("spot.obj").parents[2] / "samples" / "data" / "spot" / "spot.obj"   # with its texture


@pytest.fixture(scope="module")
def spot():
    return load_data("spot_low_resolution.obj")


@pytest.fixture(scope="module")
def spot_image(spot):
    return geoimg.mesh_to_image(spot, 33, fidelity=False)


def test_lossless_coding_is_within_half_a_step_and_keeps_domain_mask_and_metadata(spot_image, mountain):
    terrain = geoimg.mesh_to_image(mountain, 17, method="heightfield", axis="y", fidelity=False)
    masked = geoimg.GeometryImage(terrain.pixels, np.arange(17)[:, None] + np.arange(17)[None] < 25,
                                  terrain.domain, metadata=dict(terrain.metadata, source="m.obj"))
    for image in (spot_image, masked):
        back = decode(encode(image, 0))
        p = image.pixels.astype(np.float64)
        step = np.ptp(p[image.valid], axis=0).max() / (65535 - 2 * HEADROOM)
        glued = image.domain.average_glued(p)                    # what the reader welds (lossless: the same)
        assert np.abs(back.pixels - glued)[image.valid].max() <= 0.5 * step + 1e-6 * np.abs(p).max()
        assert back.domain == image.domain and np.array_equal(back.valid, image.valid)
    assert back.metadata["source"] == "m.obj" and back.metadata["up"] == terrain.metadata["up"]


def test_a_file_spends_its_bytes_on_the_shape(spot_image):
    # no coder's comment (COM segment) in the codestream; the record (DEFLATE with a fixed dictionary) small
    import imagecodecs
    data = encode(spot_image, 70)
    start = data.index(b"jp2c") + 4
    assert b"\xff\x64" not in data[start:start + 200] and b"OpenJPEG" not in data
    assert data.index(b"jp2c") - data.index(b"uuid") < 90
    assert imagecodecs.jpeg2k_decode(data).shape == (33, 33, 3)          # still a standard file


def test_masked_pixels_are_continued_so_a_masked_image_costs_fewer_bytes(mountain):
    # a terrain with a hole and a ragged rim: the masked pixels continued (biharmonic) rather than a constant
    terrain = geoimg.mesh_to_image(mountain, 65, method="heightfield", axis="y", fidelity=False)
    yy, xx = np.mgrid[:65, :65]
    mask = ((yy - 30) ** 2 + (xx - 34) ** 2 > 90) & (xx + yy < 100)
    low = terrain.pixels[mask].min(axis=0)                 # the holes at the lowest corner (the first files' fill)
    holed = np.where(mask[..., None], terrain.pixels, low).astype(np.float32)
    raw = geoimg.GeometryImage(holed, mask, terrain.domain)
    before = raw.pixels.copy()
    continued = continue_masked(raw)
    assert np.array_equal(raw.pixels, before)                              # the input left as it was
    assert np.array_equal(continued.pixels[mask], raw.pixels[mask]) and np.array_equal(continued.mask, mask)
    low, high = raw.pixels[mask].min(axis=0), raw.pixels[mask].max(axis=0)
    span = high - low
    inside = continued.pixels[~mask]
    assert ((inside > low - 0.1 * span) & (inside < high + 0.1 * span)).all()     # a continuation, not a spike
    for level in (70, 60):
        a, b = encode(raw, level), encode(continued, level)
        err = [np.sqrt(((decode(d).pixels - terrain.pixels)[mask] ** 2).sum(axis=1).mean()) for d in (a, b)]
        assert len(b) < 0.85 * len(a) and err[1] < 1.2 * err[0]
    assert continue_masked(terrain) is terrain                             # nothing masked: as it is


@pytest.mark.slow
def test_a_candidate_is_the_closer_of_the_prefilter_and_the_mesh_resampled_as_it_is(tmp_path):
    # the angle block's cut-open image: resampled as it is, 3.7 dB closer than through the prefilter
    block = geoimg.mesh.repair(load_data("angle_block.STL"))[0].mesh
    got = geoimg.compress(block, tmp_path / "b.jp2", max_bytes=200_000, resolutions=(65,))
    against = geoimg.mesh.surface_distance
    prefiltered = geoimg.mesh_to_image(block, 65, fidelity=False)
    assert got.level == 0                                                  # lossless: the image itself
    assert (against(block, got.image.to_mesh(), n=20_000)["psnr_db"]
            > against(block, prefiltered.to_mesh(), n=20_000)["psnr_db"] + 2.0)


def test_files_with_the_first_record_format_are_read():
    # written by geoimg 2026-12-06 before the compact record (zlib'd JSON, the mask in base64): a curled,
    # notched petal at 17^2, coded at level 70
    import meshes
    image = geoimg.mesh_to_image(meshes.petal(300), 17, fidelity=False)
    back = geoimg.load_image(data_file("petal_v0_record.jp2"))
    assert back.domain == image.domain and np.array_equal(back.mask, image.mask)
    size = np.ptp(image.pixels[image.valid], axis=0).max()
    assert np.abs(back.pixels - image.pixels)[image.valid].max() < 0.01 * size


def test_the_budget_is_honoured_and_a_closed_shape_comes_back_closed(spot, tmp_path):
    path = tmp_path / "spot.jp2"
    made = geoimg.compress(spot, path, max_bytes=2500, resolutions=(33, 65))
    assert made.nbytes <= 2500 and path.read_bytes() == made.data
    assert {t["resolution"] for t in made.tried} == {33, 65} and made.psnr_db > 50
    assert max(t["psnr_db"] for t in made.tried) == round(made.psnr_db, 2)      # the best candidate kept
    read = geoimg.load_image(path)
    assert np.array_equal(read.pixels, made.image.pixels)
    quads = read.to_mesh()
    assert topology(quads).closed and topology(quads).genus == 0
    # lossy coding moved the glued seam pixels apart; the reader welded them again (each group one point)
    import imagecodecs
    raw = np.asarray(imagecodecs.jpeg2k_decode(made.data), np.float64)
    assert not np.array_equal(read.domain.average_glued(raw), raw)             # as decoded: apart
    assert np.array_equal(read.domain.average_glued(read.pixels.astype(np.float64)), read.pixels)   # as read
    bigger = geoimg.compress(spot, max_bytes=6000, resolutions=(33, 65))
    assert bigger.nbytes > made.nbytes and bigger.psnr_db > made.psnr_db


def test_a_psnr_target_gives_the_fewest_bytes_that_reach_it(spot):
    made = geoimg.compress(spot, psnr=55, resolutions=(33,))
    assert made.psnr_db >= 55
    lower = geoimg.compress(spot, max_bytes=made.nbytes - 200, resolutions=(33,))
    assert lower.psnr_db < 55 + 0.5


@pytest.mark.slow
def test_a_cut_open_shape_comes_back_closed():
    torus = load_data("torus.obj")
    made = geoimg.compress(torus, max_bytes=3000, resolutions=(33, 65))
    assert [t["resolution"] for t in made.tried] == [65]        # the cut layout rounds 33 up to 65: coded once
    quads = made.image.to_mesh()
    assert made.image.domain.kind == "cut" and topology(quads).closed and topology(quads).genus == 1


def test_an_image_is_coded_at_its_own_size_against_its_own_pixels(spot_image):
    made = geoimg.compress(spot_image, max_bytes=1500)
    assert made.resolution == 33 and made.nbytes <= 1500 and 40 < made.psnr_db < 200


@pytest.mark.parametrize("kwargs, message", [
    ({}, "one of the two"),
    ({"max_bytes": 1000, "psnr": 60}, "one of the two"),
    ({"max_bytes": 0}, "max_bytes"),
    ({"max_bytes": True}, "max_bytes"),
    ({"max_bytes": 1000.5}, "max_bytes"),
    ({"psnr": float("nan")}, "psnr"),
    ({"psnr": -3}, "psnr"),
    ({"max_bytes": 1000, "resolutions": (1,)}, "resolutions"),
    ({"max_bytes": 1000, "resolutions": ()}, "resolutions"),
    ({"max_bytes": 100, "resolutions": (33,)}, "the least that works is"),
    ({"psnr": 150, "resolutions": (17,)}, "reaches 150"),
])
def test_bad_targets_are_refused(spot, kwargs, message):
    with pytest.raises(geoimg.InputError, match=message):
        geoimg.compress(spot, **kwargs)


def test_bad_images_and_paths_are_refused_and_leave_nothing(spot_image, tmp_path):
    bad = spot_image.pixels.copy()
    bad[3, 3, 0] = np.nan
    with pytest.raises(geoimg.ImageError, match="NaN"):
        geoimg.compress(geoimg.GeometryImage(bad, None, spot_image.domain), max_bytes=2000)
    with pytest.raises(geoimg.InputError, match="own size"):
        geoimg.compress(spot_image, max_bytes=2000, resolutions=(65,))
    with pytest.raises(geoimg.InputError, match=".jp2"):
        geoimg.compress(spot_image, tmp_path / "x.exr", max_bytes=2000)
    (tmp_path / "taken.jp2").write_bytes(b"mine")
    with pytest.raises(FileExistsError):
        geoimg.compress(spot_image, tmp_path / "taken.jp2", max_bytes=2000)
    with pytest.raises(geoimg.InputTypeError):
        geoimg.compress([1, 2, 3], max_bytes=2000)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken.jp2"]


def test_files_that_are_not_geoimg_jpeg_2000_are_refused_in_one_line(spot_image, tmp_path):
    import imagecodecs
    picture = imagecodecs.jpeg2k_encode(np.zeros((16, 16, 3), np.uint8), codecformat="jp2")
    raw = imagecodecs.jpeg2k_encode(np.zeros((16, 16, 3), np.uint8), codecformat="j2k")
    good = encode(spot_image, 70)
    start = good.index(b"uuid") + 4 + 16
    cases = {"picture.jp2": (picture, "without geoimg's record"), "raw.jp2": (raw, "raw JPEG 2000 codestream"),
             "cut.jp2": (good[: start + 40], "inside geoimg's record; read more of the file"),
             "short.jp2": (good[:60], "before geoimg's record and the codestream"),
             "damaged.jp2": (good.replace(b"\xff\x51", b"\xff\x01", 1), "truncated or damaged"),
             "record.jp2": (good[:start] + b"\x00" * 8 + good[start + 8:], "record is damaged"),
             "record1.jp2": (good[:start] + b"\x01" + b"\xff" * 7 + good[start + 8:], "record is damaged"),
             "record2.jp2": (good[:start] + b"\x02" + good[start + 1:], "record is damaged"),
             "empty.jp2": (b"", "not a JP2 file")}
    for name, (data, message) in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(geoimg.ImageFileError, match=message):
            geoimg.load_image(tmp_path / name)


def test_the_command_compresses_and_the_other_commands_read_it(tmp_path, capsys):
    src, out = str(data_file("spot_low_resolution.obj")), tmp_path / "s.jp2"
    assert main(["compress", src, "-o", str(out), "--bytes", "2500", "--res", "33"]) == 0
    text = capsys.readouterr().out
    assert "bytes (budget 2500)" in text and "33 x 33" in text and out.stat().st_size <= 2500
    assert main(["info", str(out)]) == 0 and "octahedral" in capsys.readouterr().out
    assert main(["mesh", str(out), "-o", str(tmp_path / "q.obj")]) == 0
    assert main(["mesh", str(out), "-o", str(tmp_path / "coarse.obj"), "--bytes", "1500"]) == 0   # streamed
    assert re.search(r"from its first 1500 bytes: \d of \d wavelet levels", capsys.readouterr().out)
    assert main(["mesh", str(out), "-o", str(tmp_path / "none.obj"), "--bytes", "50"]) == 2
    assert "read more of the file" in capsys.readouterr().err and not (tmp_path / "none.obj").exists()
    for argv in (["--bytes", "10", "--res", "33"], ["--res", "33"], ["--bytes", "1000", "--psnr", "50"]):
        assert main(["compress", src, "-o", str(tmp_path / "no.jp2"), *argv]) == 2
        assert "error" in capsys.readouterr().err and not (tmp_path / "no.jp2").exists()
    assert main(["compress", src, "-o", str(tmp_path / "no.png"), "--bytes", "1000"]) == 2


def test_a_compressed_octahedral_image_has_harmonics(tmp_path):
    d = geoimg.OctahedralDomain()
    ball = geoimg.GeometryImage(d.directions(65).astype(np.float32), None, d)
    path = tmp_path / "ball.jp2"
    path.write_bytes(encode(ball, 0))
    h = geoimg.harmonics(path, 2)
    assert abs(h.invariants()[1] - 1) < 1e-3 and h.metadata["source"] == "ball.jp2"
    assert main(["harmonics", str(path), "--lmax", "2", "-o", str(tmp_path / "h.npz")]) == 0


def test_colours_are_coded_when_asked_and_cost_bytes(tmp_path, capsys):
    from geoimg.image._jp2 import COLOR_TOP
    textured = geoimg.load_mesh(SPOT_TEXTURED)
    image = geoimg.mesh_to_image(textured, 33, fidelity=False)
    assert image.colors is not None
    back = decode(encode(image, 0, colors=True))
    assert np.abs(back.colors - image.colors[..., :3]).max() <= 0.5 / COLOR_TOP + 1e-7
    assert decode(encode(image, 0)).colors is None                       # not asked: not coded
    assert len(encode(image, 60, colors=True)) > len(encode(image, 60))
    made = geoimg.compress(textured, max_bytes=6000, resolutions=(33, 65), colors=True)
    assert made.nbytes <= 6000 and made.image.colors is not None
    out = tmp_path / "t.jp2"
    src = str(SPOT_TEXTURED)
    assert main(["compress", src, "-o", str(out), "--bytes", "6000", "--res", "33", "--colors"]) == 0
    assert "with its colours" in capsys.readouterr().out and geoimg.load_image(out).colors is not None


def test_the_octahedral_encoding_of_normals_round_trips():
    # the coder's two normal channels are the octahedral map of the sphere's parametrization, in [0, 1]^2
    from geoimg.parametrization import sphere_to_square, square_to_sphere
    rng = np.random.default_rng(3)
    n = rng.normal(size=(2000, 3))
    n = np.concatenate([n, np.eye(3), -np.eye(3), [[1, 1, -1e-9]]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    p = sphere_to_square(n)
    assert np.abs(2 * p - 1).max() <= 1 + 1e-12 and np.allclose(square_to_sphere(p), n, atol=1e-12)


def test_normals_are_coded_when_asked_and_cost_bytes(spot_image, tmp_path, capsys):
    plain = decode(encode(spot_image, 70))
    coded = decode(encode(spot_image, 70, normals=True))
    assert plain.normals is None and coded.normals is not None
    assert len(encode(spot_image, 70, normals=True)) > len(encode(spot_image, 70))
    cos = np.clip((coded.normals * spot_image.normals).sum(axis=-1), -1, 1)
    assert np.degrees(np.arccos(cos)).mean() < 2.0                         # close to the surface's exact normals
    lossless = decode(encode(spot_image, 0, normals=True)).normals
    assert np.degrees(np.arccos(np.clip((lossless * spot_image.normals).sum(-1), -1, 1))).max() < 0.1
    glue = spot_image.domain.glue(spot_image.shape)
    if glue is not None:                                                   # glued pixels share one normal
        flat = coded.normals.reshape(-1, 3)
        reps, group = glue
        assert np.allclose(flat, flat[reps[group]], atol=1e-6)
    src, out = str(data_file("spot_low_resolution.obj")), tmp_path / "n.jp2"
    assert main(["compress", src, "-o", str(out), "--bytes", "3000", "--res", "33", "--normals"]) == 0
    assert "with its normals" in capsys.readouterr().out and geoimg.load_image(out).normals is not None


@pytest.fixture(scope="module")
def displaced_ball():
    """A unit sphere as a displaced file: a 17^2 ball (lossless), offsets at 65^2 coded at level 80."""
    from geoimg.image._displacement import base_frame
    d = geoimg.OctahedralDomain()
    base = geoimg.GeometryImage(d.directions(17).astype(np.float32), None, d)
    points, normals = base_frame(decode(encode(base, 0)).pixels, d, (65, 65))
    offsets = 1.0 - np.linalg.norm(points, axis=-1)           # to the sphere along the (radial) normals
    return base, offsets, encode(base, 0, offsets=offsets, offsets_level=80)


def test_a_displaced_file_is_the_base_moved_along_its_normals(displaced_ball):
    import imagecodecs
    base, offsets, data = displaced_ball
    back = decode(data)
    assert back.shape == (65, 65) and back.domain == base.domain
    radius = np.linalg.norm(back.pixels.astype(np.float64), axis=-1)
    assert np.abs(radius - 1).max() < 2e-3 < np.abs(offsets).max()       # the offsets did the work
    assert topology(back.to_mesh()).closed                                # glued pixels welded
    assert imagecodecs.jpeg2k_decode(data).shape == (17, 17, 3)          # a plain reader shows the base


def test_a_displaced_file_streams_base_first_then_the_offsets_levels(displaced_ball, tmp_path):
    base, _, data = displaced_ball
    second = data.rindex(b"jp2c") - 4                                     # the offsets' box
    only_base = decode(data, max_bytes=second)
    assert only_base.shape == (17, 17) and only_base.metadata["jpeg2000_offset_levels"] == "none"
    levels = [decode(data, max_bytes=k).metadata.get("jpeg2000_offset_levels")
              for k in range(second + 200, len(data), 300)]
    assert any(re.fullmatch(r"\d of \d", str(v)) for v in levels)
    assert decode(data, max_bytes=len(data)).metadata.get("jpeg2000_offset_levels") is None     # all of it
    (tmp_path / "cut.jp2").write_bytes(data[: len(data) - 40])
    with pytest.warns(UserWarning, match=r"truncated after \d+ bytes: decoded its offsets' first \d of \d"):
        assert geoimg.load_image(tmp_path / "cut.jp2").shape == (65, 65)


def test_damaged_displaced_files_and_bad_offsets_are_refused(displaced_ball, spot_image):
    base, offsets, data = displaced_ball
    second = data.rindex(b"jp2c") + 4
    damaged = data[:second] + data[second:].replace(b"\xff\x51", b"\xff\x01", 1)
    with pytest.raises(geoimg.ImageFileError, match="^data: the offsets' JPEG 2000 codestream cannot be decoded"):
        decode(damaged)
    other = encode(base, 0, offsets=offsets[:33, :33], offsets_level=80)   # the other file's offsets: 33^2
    swapped = data[:second - 8] + other[other.rindex(b"jp2c") - 4:]       # its whole box in place of ours
    with pytest.raises(geoimg.ImageFileError, match="its record asks for"):
        decode(swapped)
    for bad, message in ((np.full((65, 65), np.nan), "NaN"), (np.zeros(5), "an \\(H, W\\) array")):
        with pytest.raises(geoimg.ImageError, match=message):
            encode(base, 0, offsets=bad)
    with pytest.raises(geoimg.GeoimgError, match="odd side"):             # not an octahedral image's size
        encode(base, 0, offsets=np.zeros((64, 64)))
    masked = geoimg.GeometryImage(spot_image.pixels, np.ones((33, 33), bool), spot_image.domain)
    with pytest.raises(geoimg.ImageError, match="no mask"):
        encode(masked, 0, offsets=np.zeros((65, 65)))
    assert np.isfinite(offsets).all() and offsets.shape == (65, 65)       # the input left as it was


def test_weighted_offsets_come_back_divided_by_the_bases_area_weights(displaced_ball, monkeypatch):
    from geoimg.image import _jp2
    from geoimg.image._displacement import WEIGHT_RANGE, area_weights, base_frame
    base, offsets, plain = displaced_ball
    points, _ = base_frame(decode(encode(base, 0)).pixels, base.domain, offsets.shape)
    weights = area_weights(points, base.domain)
    assert 0.5 < np.percentile(weights, 1) < 0.9 < 1.1 < weights.max() < 2     # the octahedral sphere's cells
    assert weights.min() >= WEIGHT_RANGE ** -0.5 - 1e-12            # a pinched cell (edge midpoints) clipped
    kept = weights.copy()
    data = encode(base, 0, offsets=offsets, offsets_level=0, offsets_weights=weights)
    assert _jp2._record(data, "data")["offsets"]["weighted"] == "area"
    assert "weighted" not in _jp2._record(plain, "data")["offsets"]          # files before it: as they were
    radius = np.linalg.norm(decode(data).pixels.astype(np.float64), axis=-1)
    assert np.abs(radius - 1).max() < 1e-4                                   # lossless: the sphere itself
    wrong = encode(base, 0, offsets=offsets, offsets_level=0, offsets_weights=2 * weights)
    off = np.abs(np.linalg.norm(decode(wrong).pixels.astype(np.float64), axis=-1) - 1).max()
    assert off > 0.4 * np.abs(offsets).max()               # the reader divides by the base's own weights
    assert np.array_equal(weights, kept)
    for bad in (np.zeros_like(weights), np.full_like(weights, np.nan), weights[:5]):
        with pytest.raises(geoimg.ImageError, match="positive finite weights"):
            encode(base, 0, offsets=offsets, offsets_weights=bad)
    coded = _jp2.offsets_codestream
    monkeypatch.setattr(_jp2, "offsets_codestream",
                        lambda *a: (lambda cs, f: (cs, {**f, "weighted": "volume"}))(*coded(*a)))
    unknown = encode(base, 0, offsets=offsets, offsets_level=80, offsets_weights=weights)
    with pytest.raises(geoimg.ImageFileError, match="offsets weighted by 'volume', which this reader does not know"):
        decode(unknown)


@pytest.mark.slow
def test_a_low_budget_is_spent_on_a_displaced_image_that_beats_the_plain_ones(tmp_path):
    import imagecodecs
    spot = load_data("spot.obj")
    path = tmp_path / "spot.jp2"
    made = geoimg.compress(spot, path, max_bytes=3000, resolutions=(33, 65, 129))
    plain = [t for t in made.tried if "base" not in t and "psnr_db" in t]
    displaced = [t for t in made.tried if "base" in t]
    for base in (33, 65):                        # 40 % and 50 % of the budget, then on while it gains
        assert {0.4, 0.5} <= {t["share"] for t in displaced if t["base"] == base}
    assert made.base in (33, 65) and made.nbytes <= 3000
    assert made.psnr_db > max(t["psnr_db"] for t in plain) + 1.0
    fitted = [t for t in displaced if "fitted" in t]          # the best again, its offsets fitted: the closest kept
    best = max((t for t in displaced if "fitted" not in t), key=lambda t: t["psnr_db"])
    assert [t["fitted"] for t in fitted] == list(BENDINGS)
    assert all((t["base"], t["share"]) == (best["base"], best["share"]) for t in fitted)
    assert made.psnr_db == pytest.approx(max(t["psnr_db"] for t in fitted + [best]), abs=0.005)
    read = geoimg.load_image(path)
    assert np.array_equal(read.pixels, made.image.pixels) and read.shape == (129, 129)
    assert topology(read.to_mesh()).closed and topology(read.to_mesh()).genus == 0
    assert imagecodecs.jpeg2k_decode(made.data).shape == (made.base, made.base, 3)


def test_fitted_offsets_bring_quads_across_a_ridge_closer_than_where_each_line_meets_it():
    from geoimg._compress import _Surface
    from geoimg._offset_fit import fit_offsets
    roof = geoimg.Mesh([[-1, -1, -0.2], [0, -1, 0.3], [1, -1, -0.2], [-1, 1, -0.2], [0, 1, 0.3], [1, 1, -0.2]],
                       [[0, 1, 4, 3], [1, 2, 5, 4]])          # two planes meeting at a ridge x = 0, between columns
    u, v = np.meshgrid(np.linspace(-1, 1, 10), np.linspace(-1, 1, 10))
    points = np.dstack([u, v, 0 * u])
    normals = np.zeros_like(points)
    normals[..., 2] = 1.0
    surface = _Surface(roof)
    start = surface.offsets(points, normals)
    kept = start.copy()
    fitted = fit_offsets(start, points, normals, surface.closest, bending=0.03)
    assert np.array_equal(start, kept)                                       # the input left as it was
    assert np.allclose(start, 0.3 - 0.5 * np.abs(u), atol=1e-3)              # each line meets the roof
    assert np.array_equal(fit_offsets(start, points, 0 * normals, surface.closest), start)   # no normals: as is
    rms = [geoimg.mesh.surface_distance(roof, geoimg.GeometryImage((points + h[..., None] * normals).astype(
           np.float32)).to_mesh(), n=20_000)["rms"] for h in (start, fitted)]
    assert rms[1] < 0.8 * rms[0]


@pytest.mark.slow
def test_the_commands_say_a_file_is_displaced_and_what_a_prefix_of_it_holds(tmp_path, capsys):
    out = tmp_path / "s.jp2"
    assert main(["compress", str(data_file("spot.obj")), "-o", str(out), "--bytes", "3000", "--res", "65", "129"]) == 0
    text = capsys.readouterr().out
    base = int(re.search(r"129 x 129 octahedral image displaced on a (\d+) x \1 base", text).group(1))
    assert re.search(r"129 x 129 on 65 x 65 \(40% of the budget\): \d+ bytes", text)
    data = out.read_bytes()
    second = data.rindex(b"jp2c") - 4
    assert main(["mesh", str(out), "-o", str(tmp_path / "base.obj"), "--bytes", str(second)]) == 0
    assert "no offsets (the base alone)" in capsys.readouterr().out
    assert geoimg.load_mesh(tmp_path / "base.obj").n_vertices == (base - 1) ** 2 + 2
    assert main(["info", str(out)]) == 0 and f"jpeg2000_base: {base} x {base}" in capsys.readouterr().out
    assert main(["mesh", str(out), "-o", str(tmp_path / "all.obj")]) == 0
    assert "wavelet levels" not in capsys.readouterr().out
    assert geoimg.load_mesh(tmp_path / "all.obj").n_vertices == 128 ** 2 + 2


@pytest.mark.slow
@pytest.mark.parametrize("name, kind, loops, genus", [("demosthenes-low-res.obj", "planar", 1, 0),
                                                      ("torus.obj", "cut", 0, 1)])
def test_disk_and_cut_open_shapes_are_displaced_and_keep_their_rims_and_handles(name, kind, loops, genus):
    from geoimg._compress import _displaced_for_bytes, _Surface
    mesh = load_data(name)
    made = geoimg.compress(mesh, max_bytes=3000, resolutions=(65, 129))
    displaced = [t for t in made.tried if "base" in t]             # their all-true masks are no masks
    assert len(displaced) >= 2 and all(t["base"] == 65 and t["bytes"] <= 3000 for t in displaced)
    full, base = (geoimg.mesh_to_image(mesh, r, fidelity=False) for r in (129, 65))
    [(_, _, data)] = _displaced_for_bytes(full, dataclasses.replace(base, mask=None), _Surface(mesh), 3000, 0.5)
    back = decode(data)
    assert back.domain.kind == kind and back.shape == (129, 129) and len(data) <= 3000
    top = topology(back.to_mesh())
    assert (top.boundary_loops, top.genus) == (loops, genus)


def test_the_base_share_walks_towards_the_better_side_and_stops_where_it_loses():
    from geoimg._compress import _walk_shares
    for score, expected in ((lambda x: -abs(x - 0.23), [0.4, 0.5, 0.3, 0.2]),     # down to the bound
                            (lambda x: -abs(x - 0.53), [0.4, 0.5, 0.6]),           # up one, which loses
                            (lambda x: 1.0, [0.4, 0.5, 0.6])):                     # a tie: up, no gain
        seen: list = []
        _walk_shares(lambda share, score=score, seen=seen: seen.append(share) or score(share))
        assert seen == expected
    seen = []                                    # nothing fits from 0.5 on: down from 0.4
    _walk_shares(lambda share: seen.append(share) or (-np.inf if share >= 0.5 else share))
    assert seen == [0.4, 0.5, 0.3]


@pytest.mark.slow
def test_a_psnr_target_is_reached_in_fewer_bytes_by_a_displaced_file():
    spot = load_data("spot.obj")
    made = geoimg.compress(spot, psnr=64, resolutions=(65, 129))
    plain = [t["bytes"] for t in made.tried if "base" not in t and "bytes" in t]
    assert made.base is not None and made.psnr_db >= 64 and made.nbytes < min(plain)
    reaching = [t["bytes"] for t in made.tried if "base" in t and t["psnr_db"] >= 64.01]   # (rounded figures)
    assert made.nbytes <= min(reaching)                     # the fewest bytes of those that reach it
    assert decode(made.data).shape == (129, 129)
