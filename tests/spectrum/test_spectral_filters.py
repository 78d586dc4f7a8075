"""Spectral filters through the harmonics: a gain per degree (heat kernel, band limit, band emphasis),
the same in every direction of the sphere, where a Gaussian of the image's unfolding is not; seams closed;
bad input refused."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import filters
import geoimg
from geoimg.spectrum import band_emphasis, band_limit, heat_smooth, spectral_filter

N = 129


def _bump(axis):
    """The unit sphere with a round bump of 20 % about ``axis``, as an octahedral image."""
    d = geoimg.OctahedralDomain()
    dirs = d.directions(N)
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    r = 1.0 + 0.2 * np.exp(-np.arccos(np.clip(dirs @ a, -1, 1)) ** 2 / 0.15 ** 2)
    return geoimg.GeometryImage((dirs * r[..., None]).astype(np.float32), None, d), a


def _turn_gap(a, b, turn):
    """How far image ``b`` is from image ``a`` turned by ``turn``: at each pixel direction d of ``a``, b's
    point at the direction turn(d) (bilinear in b) against turn(a's point); the largest gap."""
    from scipy.ndimage import map_coordinates

    from geoimg.parametrization._octahedral import sphere_to_square
    d = a.domain.directions(N).reshape(-1, 3)
    uv = sphere_to_square(turn.apply(d)) * (N - 1)
    pb = np.stack([map_coordinates(b.pixels[..., k].astype(np.float64), [uv[:, 1], uv[:, 0]], order=1)
                   for k in range(3)], axis=1)
    return float(np.linalg.norm(pb - turn.apply(a.pixels.reshape(-1, 3).astype(np.float64)), axis=1).max())


def test_heat_smoothing_is_the_same_in_every_direction_where_the_unfolded_gaussian_is_not():
    """A bump on the octahedron's pole and the same bump turned towards a face: the spectral filter of the
    turned one is the turned filter of the first (up to the bilinear look-up), a Gaussian of the unfolding
    is not, by several times more."""
    turn = Rotation.from_euler("xy", [50, 35], degrees=True)
    (a, _), (b, _) = _bump([0, 0, 1]), _bump(turn.apply([0, 0, 1]))
    before = _turn_gap(a, b, turn)                       # the look-up's own error, on the images as they are
    ours = _turn_gap(heat_smooth(a, 2e-3, lmax=48), heat_smooth(b, 2e-3, lmax=48), turn)
    unfolded = _turn_gap(a.apply(filters.gaussian_filter, 2.0), b.apply(filters.gaussian_filter, 2.0), turn)
    top = np.linalg.norm(heat_smooth(a, 2e-3, lmax=48).pixels[N // 2, N // 2])
    assert top < 1.19                                   # it did smooth the bump's top (1.2 before)
    assert ours < 2 * before + 1e-3 and unfolded > 5 * ours, (before, ours, unfolded)


def test_gains_act_per_degree_and_keep_the_seams():
    ball, _ = _bump([0.3, -0.2, 0.9])
    same = spectral_filter(ball, np.ones(33), lmax=32)
    assert np.abs(same.pixels - ball.pixels).max() < 0.02           # degrees above 32 of a sharp bump dropped
    limited = band_limit(ball, 4)
    assert np.abs(np.linalg.norm(limited.pixels, axis=2) - 1).max() < 0.2
    glued, group = limited.domain.glue(limited.shape)
    flat = limited.pixels.reshape(-1, 3)
    for g in np.unique(group)[:50]:
        members = flat[group == g]
        assert (members == members[0]).all()                       # glued pixels, the same bytes
    doubled = band_emphasis(ball, 1, 1, 2.0, lmax=16)
    assert np.linalg.norm(doubled.pixels[N // 2, N // 2]) > 1.8
    assert geoimg.mesh.topology(limited.to_mesh()).closed


def test_bad_filters_are_refused():
    ball, _ = _bump([0, 0, 1])
    with pytest.raises(geoimg.ImageError, match="octahedral"):
        heat_smooth(geoimg.GeometryImage(np.zeros((9, 9, 3), np.float32)), 0.1)
    with pytest.raises(geoimg.InputError, match="t: expected"):
        heat_smooth(ball, -1.0)
    with pytest.raises(geoimg.InputError, match="gain: expected 5 finite numbers"):
        spectral_filter(ball, np.ones(3), lmax=4)
    with pytest.raises(geoimg.InputError, match="gain"):
        spectral_filter(ball, lambda d: d * np.nan, lmax=4)
    with pytest.raises(geoimg.InputError, match="low, high"):
        band_emphasis(ball, 5, 2, 2.0)
    with pytest.raises(geoimg.InputError, match="lmax"):
        band_limit(ball, 0)


def test_the_filter_command_takes_spectral_steps(tmp_path, capsys):
    from geoimg.cli import main
    ball, _ = _bump([0, 0, 1])
    geoimg.save_image(ball, tmp_path / "b.exr")
    assert main(["filter", str(tmp_path / "b.exr"), "-o", str(tmp_path / "h.exr"), "--heat", "0.002",
                 "--bandlimit", "24"]) == 0
    out = geoimg.load_image(tmp_path / "h.exr")
    assert out.metadata["filters"] == ["heat_smooth(0.002)", "band_limit(24)"]
    assert np.linalg.norm(out.pixels[N // 2, N // 2]) < 1.19
    capsys.readouterr()
    assert main(["filter", str(tmp_path / "b.exr"), "-o", str(tmp_path / "r.exr"), "--heat", "0.01",
                 "--uv-region", "0.5", "0.5", "0.2"]) == 2
    assert "takes no region" in capsys.readouterr().err and not (tmp_path / "r.exr").exists()
    flat = geoimg.GeometryImage(np.zeros((9, 9, 3), np.float32))
    geoimg.save_image(flat, tmp_path / "f.exr")
    assert main(["filter", str(tmp_path / "f.exr"), "-o", str(tmp_path / "g.exr"), "--heat", "0.01"]) == 2
    assert "octahedral" in capsys.readouterr().err and not (tmp_path / "g.exr").exists()
