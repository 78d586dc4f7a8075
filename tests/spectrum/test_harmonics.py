"""Spherical harmonics of closed genus-0 shapes: the transform's convention (pyshtools' real 4pi-normalized
functions, no Condon-Shortley phase) against scipy's complex harmonics, exact round trips of band-limited
functions, reconstructions that converge with the degree, invariants that a turn leaves alone, and every
bad input refused in one line with nothing written."""
import io
import warnings
import zipfile

import numpy as np
import pytest
import scipy.special as sp
from scipy.spatial.transform import Rotation

import geoimg
from geoimg.cli import main
from geoimg.spectrum import (analyze, grid_directions, grid_shape, harmonics, load_harmonics,
                             synthesize)
from geoimg._convert import measure_fidelity

from helpers import DATA


def _random_coeffs(k, lmax, seed=0):
    c = np.random.default_rng(seed).normal(size=(k, 2, lmax + 1, lmax + 1))
    c *= np.tril(np.ones((lmax + 1, lmax + 1)))[None, None]        # m <= l
    c[:, 1, :, 0] = 0.0
    return c


@pytest.mark.parametrize("deg, m", [(0, 0), (1, 0), (1, 1), (3, 2), (6, 6), (9, 4)])
def test_the_functions_are_pyshtools_real_4pi_normalized_ones(deg, m):
    rng = np.random.default_rng(deg * 10 + m)
    theta, phi = rng.uniform(0.05, 3.1, 50), rng.uniform(-np.pi, np.pi, 50)
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1)
    y = sp.sph_harm_y(deg, m, theta, phi)            # orthonormal complex, with the Condon-Shortley phase
    scale = np.sqrt(4 * np.pi) * (np.sqrt(2) if m else 1.0) * (-1) ** m
    for part, ref in ((0, scale * y.real), (1, scale * y.imag)):
        if part == 1 and m == 0:
            continue
        c = np.zeros((1, 2, 10, 10))
        c[0, part, deg, m] = 1.0
        assert np.allclose(synthesize(c, d)[:, 0], ref, atol=1e-12)


@pytest.mark.parametrize("lmax", [1, 5, 24])
def test_analysis_inverts_synthesis_for_band_limited_functions(lmax):
    c = _random_coeffs(3, lmax)
    d = grid_directions(lmax)
    values = synthesize(c, d.reshape(-1, 3)).reshape(grid_shape(lmax) + (3,))
    assert np.abs(analyze(values, lmax) - c).max() < 1e-12
    assert np.allclose(np.linalg.norm(d, axis=2), 1.0)


@pytest.mark.parametrize("lmax", [3, 24])
def test_rows_are_synthesized_exactly(lmax):
    from geoimg.spectrum import synthesize_rows
    c = _random_coeffs(2, lmax, seed=3)
    x = np.array([1.0, 0.7, 0.0, -0.3, -1.0])
    cols = 2 * lmax + 3
    phi = 2 * np.pi * np.arange(cols) / cols
    s = np.sqrt(1 - x * x)
    d = np.stack([s[:, None] * np.cos(phi), s[:, None] * np.sin(phi), np.broadcast_to(x[:, None], (5, cols))], -1)
    assert np.abs(synthesize_rows(c, x, cols) - synthesize(c, d.reshape(-1, 3)).reshape(5, cols, 2)).max() < 1e-11
    with pytest.raises(ValueError, match="cannot hold"):
        synthesize_rows(c, x, 2 * lmax)


@pytest.mark.parametrize("lmax, decay, tolerance", [(8, 2, 1e-6), (40, 2, 2e-6), (40, 0, 3e-5)])
def test_many_points_are_interpolated_within_the_stated_error(lmax, decay, tolerance, monkeypatch):
    import geoimg.spectrum._transform as transform
    c = _random_coeffs(3, lmax, seed=5) / (1.0 + np.arange(lmax + 1))[None, None, :, None] ** decay
    d = np.random.default_rng(2).normal(size=(4000, 3))
    d = np.vstack([d, [[0, 0, 1], [0, 0, -1], [1e-7, 0, 1], [0.01, -0.02, -1], [1, 0, 0], [0, -1, 1e-9]]])
    exact = synthesize(c, d)
    monkeypatch.setattr(transform, "EXACT_TERMS", 0)                   # every call takes the grid's path
    fast = synthesize(c, d)
    error = np.abs(fast - exact).max() / np.abs(exact).max()
    assert 0 < error < tolerance


def test_the_unit_sphere_is_degree_one_alone():
    domain = geoimg.OctahedralDomain()
    ball = geoimg.GeometryImage(domain.directions(257).astype(np.float32), None, domain)
    h = harmonics(ball, 6)
    c = h.coeffs
    third = 3 ** -0.5
    assert c[0, 0, 1, 1] == pytest.approx(third, abs=1e-4) and c[1, 1, 1, 1] == pytest.approx(third, abs=1e-4)
    assert c[2, 0, 1, 0] == pytest.approx(third, abs=1e-4)
    rest = c.copy()
    rest[0, 0, 1, 1] = rest[1, 1, 1, 1] = rest[2, 0, 1, 0] = 0.0
    assert np.abs(rest).max() < 1e-4


@pytest.fixture(scope="module")
def spot():
    return geoimg.load_mesh(DATA / "spot.obj"), harmonics(DATA / "spot.obj", 16)


def test_reconstructions_converge_with_the_degree(spot):
    mesh, h = spot
    assert h.coeffs.shape == (3, 2, 17, 17) and h.metadata["resolution"] == 257 and h.metadata["psnr_db"] > 80
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                       # degree 2 is far from the mesh, and says so
        psnr = [measure_fidelity(h.to_image(129, lmax=L), mesh)["psnr_db"] for L in (2, 4, 8, 16)]
    assert psnr == sorted(psnr) and psnr[-1] > 48 and psnr[-1] - psnr[1] > 12
    img = h.to_image(65)
    glued, group = img.domain.glue(img.shape)
    flat = img.pixels.reshape(-1, 3)
    assert all(np.array_equal(flat[group == g][0], p) for g, p in zip(range(5), flat[glued][:5]))
    m = img.to_mesh()
    assert geoimg.mesh.topology(m).closed and geoimg.mesh.topology(m).genus == 0


@pytest.fixture(scope="module")
def turned(spot):
    """The harmonics of Spot turned and moved (its own sphere map: not exactly the turned map)."""
    mesh, _ = spot
    turn = Rotation.from_euler("xyz", [40, -25, 70], degrees=True).as_matrix()
    return harmonics(geoimg.Mesh(mesh.vertices @ turn.T + [1.0, 2.0, -0.5], mesh.faces), 16)


def test_invariants_of_a_turned_copy_agree_within_two_percent(spot, turned):
    mesh, h = spot
    other = turned
    a, b = h.invariants()[1:], other.invariants()[1:]
    big = a > 1e-3 * a.max()                      # degrees that carry the shape (not rounding)
    assert np.abs(b[big] - a[big]).max() / a.max() < 0.02
    assert np.abs(b[big] / a[big] - 1).max() < 0.02


def test_coefficients_are_saved_and_read_back_bit_for_bit(tmp_path, spot):
    _, h = spot
    path = h.save(tmp_path / "h.npz")
    back = load_harmonics(path)
    assert back.coeffs.tobytes() == h.coeffs.tobytes() and back.metadata["source"] == "spot.obj"
    with np.load(path) as data:
        assert data["invariants"].shape == (17,) and "4pi" in str(data["metadata"])
    with pytest.raises(FileExistsError):
        h.save(path)                                          # exists


def test_bad_inputs_are_refused(tmp_path):
    domain = geoimg.OctahedralDomain()
    ball = geoimg.GeometryImage(domain.directions(33).astype(np.float32), None, domain)
    for lmax in (0, -3, 1025, 2.5, True, "8"):
        with pytest.raises(geoimg.InputError, match="lmax: expected a whole number from 1 to 1024"):
            harmonics(ball, lmax)
    with pytest.raises(geoimg.MeshError, match="genus 1.*handles"):
        harmonics(DATA / "torus.obj", 4)
    with pytest.raises(geoimg.MeshError, match="open surface.*close its holes"):
        harmonics(geoimg.mesh.load_mesh(DATA / "cube_no_bottom.obj"), 4)
    planar = geoimg.GeometryImage(np.zeros((9, 9, 3), np.float32))
    with pytest.raises(geoimg.ImageError, match="octahedral image; this one is planar"):
        harmonics(planar, 4)
    with pytest.raises(geoimg.InputTypeError):
        harmonics(42, 4)
    (tmp_path / "junk.npz").write_bytes(b"junk")
    with zipfile.ZipFile(tmp_path / "other.npz", "w") as z:
        z.writestr("a.npy", b"x")
    np.savez(tmp_path / "shape.npz", coeffs=np.zeros((3, 2, 4, 5)))
    np.savez(tmp_path / "nan.npz", coeffs=np.full((3, 2, 4, 4), np.nan))
    np.savez(tmp_path / "objects.npz", coeffs=np.array([None, 1], dtype=object))
    for name, message in (("junk", "not a .npz archive"), ("other", "not a geoimg harmonics file"),
                          ("shape", "expected float"), ("nan", "NaN"), ("objects", "expected 4-D of kind 'f'"),
                          ("missing", "no such file")):
        with pytest.raises(geoimg.ImageFileError, match=message):
            load_harmonics(tmp_path / f"{name}.npz")
    header = io.BytesIO()                             # a header claiming 480 GB over 16 bytes of data
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False,
                                                  "shape": (3, 2, 100000, 100000)})
    with zipfile.ZipFile(tmp_path / "huge.npz", "w") as z:
        z.writestr("coeffs.npy", header.getvalue() + bytes(16))
    with pytest.raises(geoimg.GeoimgError, match="coeffs would need about"):
        load_harmonics(tmp_path / "huge.npz")


def test_the_command_writes_coefficients_and_a_rebuilt_shape(tmp_path, capsys):
    args = ["harmonics", str(DATA / "sphere.obj"), "--lmax", "6", "-o", str(tmp_path / "s.npz"), "--mesh",
            str(tmp_path / "s.obj"), "--image", str(tmp_path / "s.exr"), "--res", "65"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "coefficients of x, y, z to degree 6" in out and "rebuilt at degree 6" in out
    assert load_harmonics(tmp_path / "s.npz").lmax == 6
    assert geoimg.load_image(tmp_path / "s.exr").domain.kind == "octahedral"
    assert geoimg.load_mesh(tmp_path / "s.obj").n_faces == 64 * 64
    assert main(args) == 2 and "exists" in capsys.readouterr().err          # nothing replaced without --force


@pytest.mark.parametrize("argv, message", [
    (["--lmax", "0"], "lmax: expected"),
    (["--lmax", "4", "--mesh", "x.txt"], "must be named"),
    (["--lmax", "4", "--image", "x.txt"], "must be named"),
])
def test_bad_command_lines_are_one_line_and_leave_nothing(tmp_path, capsys, argv, message):
    args = ["harmonics", str(DATA / "torus.obj"), "-o", str(tmp_path / "t.npz")] + argv
    args = [a if a != "x.txt" else str(tmp_path / "x.txt") for a in args]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert list(tmp_path.iterdir()) == []


def test_a_torus_is_refused_by_the_command(tmp_path, capsys):
    assert main(["harmonics", str(DATA / "torus.obj"), "--lmax", "4", "-o", str(tmp_path / "t.npz")]) == 2
    assert "genus 1" in capsys.readouterr().err and list(tmp_path.iterdir()) == []


def test_normalized_coefficients_of_a_turned_copy_agree(spot, turned):
    """SPHARM's first-order-ellipsoid frame: Spot and a turned, moved copy give the same coefficients
    (measured 0.34 % of their norm apart to degree 16; the two sphere maps differ a little)."""
    mesh, h = spot
    other = turned
    a, b = h.normalized().coeffs, other.normalized().coeffs
    assert np.linalg.norm(a - b) / np.linalg.norm(a) < 0.01
    assert np.abs(a[:, :, 0, 0]).max() < 1e-9                       # centred
    raw = np.linalg.norm(h.coeffs - other.coeffs) / np.linalg.norm(h.coeffs)
    assert raw > 0.3                                                # they were not alike before
    scaled = h.normalized(scale=True)
    semi = np.sqrt(3) * np.array([scaled.coeffs[0, 0, 1, 1], scaled.coeffs[1, 1, 1, 1], scaled.coeffs[2, 0, 1, 0]])
    assert semi[0] == pytest.approx(1.0) and semi[0] >= semi[1] >= semi[2] > 0
    record = scaled.metadata["normalization"]
    assert np.allclose(np.array(record["object_rotation"]) @ np.array(record["object_rotation"]).T, np.eye(3))
