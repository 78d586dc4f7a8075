import numpy as np
import pytest

import geoimg
from filters import (bandpass, bilateral_filter, blend, composite, denoise_nl_means, denoise_tv, feather,
                     fourier_filter, gaussian_filter, median_filter,
                     grid_curvature, guided_filter, highpass, inverse_filter, lowpass, mean_filter, pad, paste,
                     periodic_extension, resize, unsharp_mask)
from filters.inverse import blur_taps, blur_transfer
from geoimg.parametrization import grid_directions
from geoimg.parametrization._octahedral import weld_index
from geoimg.mesh import topology

from helpers import load_data

RNG = np.random.default_rng(7)
NOISE = RNG.normal(size=(17, 17, 3))

SMOOTHERS = {
    "mean": lambda a, mode, **k: mean_filter(a, 3, mode, **k),
    "mean5x2": lambda a, mode, **k: mean_filter(a, 5, mode, iterations=2, **k),
    "gaussian": lambda a, mode, **k: gaussian_filter(a, 1.5, mode, **k),
    "bilateral": lambda a, mode, **k: bilateral_filter(a, 2.0, 0.5, mode, **k),
    "guided": lambda a, mode, **k: guided_filter(a, 2, 0.01, mode, **k),
    "median": lambda a, mode, **k: median_filter(a, 3, mode, **k),
    "tv": lambda a, mode, **k: denoise_tv(a, 0.3, mode, **k),
    "nlmeans": lambda a, mode, **k: denoise_nl_means(a, 0.5, mode, **k),
}
PERIODIC_OPS = {
    "lowpass": lambda a, mode: lowpass(a, 0.1, mode),
    "inverse": lambda a, mode: inverse_filter(a, mode=mode),
    "inverse-clamp": lambda a, mode: inverse_filter(a, "gaussian", sigma=1.0, mode=mode, method="clamp"),
    "unsharp": lambda a, mode: unsharp_mask(a, 1.0, 1.5, mode),
}
ALL_OPS = {**SMOOTHERS, **PERIODIC_OPS}
MODES = ["reflect", "wrap", "octahedral"]


@pytest.fixture(scope="module")
def spot_octahedral():
    mesh = load_data("spot_low_resolution.obj")
    return geoimg.fit_surface(mesh, geoimg.parametrize(mesh, "sphere"), geoimg.GaussianWeights()).sample(65)


@pytest.fixture(scope="module")
def mountain_image(mountain_surface):
    return mountain_surface.sample(129)


# --- boundary rules ---------------------------------------------------------------------------------

@pytest.mark.parametrize("n", [5, 9, 33])
def test_octahedral_padding_continues_the_sphere_without_a_jump(n):
    q = grid_directions(n)

    def largest_step(a):
        return max(np.linalg.norm(np.diff(a, axis=0), axis=-1).max(), np.linalg.norm(np.diff(a, axis=1), axis=-1).max())

    for width in (1, 3, n - 1, 2 * n + 1):
        assert largest_step(pad(q, width, "octahedral")) == pytest.approx(largest_step(q), rel=1e-12)
    m = n - 1   # the 2M x 2M unfolding tiles the plane: padding is its periodic repetition
    assert np.array_equal(pad(q, 2 * m, "octahedral")[2 * m:4 * m, 2 * m:4 * m], periodic_extension(q, "octahedral"))
    assert np.array_equal(pad(q, 2 * m, "octahedral")[:2 * m, :2 * m], periodic_extension(q, "octahedral"))


def test_reflect_linear_and_wrap_rules():
    a = RNG.normal(size=(4, 5, 2))
    r = pad(a, 2, "reflect")
    assert np.array_equal(r[2:-2, 2:-2], a)
    assert np.array_equal(r[1, 2:-2], a[1]) and np.array_equal(r[2:-2, 0], a[:, 2])    # about the edge pixel
    assert np.array_equal(pad(a, 1, "wrap")[0, 1:-1], a[-1])
    u, v = np.meshgrid(np.arange(5.0), np.arange(4.0))
    bilinear = 1.5 * u - 2 * v + 0.25 * u * v + 3
    U, V = np.meshgrid(np.arange(-9.0, 14.0), np.arange(-9.0, 13.0))
    assert np.abs(pad(bilinear, 9, "linear") - (1.5 * U - 2 * V + 0.25 * U * V + 3)).max() < 1e-12
    ext = periodic_extension(a, "reflect")
    assert ext.shape == (6, 8, 2) and np.array_equal(ext[:4, :5], a)
    assert np.array_equal(pad(a, 6, "reflect")[6:12, 6:14], ext)


def test_padding_errors_and_input_unchanged():
    a = np.ones((3, 3))
    pad(a, 1, "octahedral")
    assert np.array_equal(a, np.ones((3, 3)))
    with pytest.raises(ValueError, match="mode"):
        pad(a, 1, "mirror")
    with pytest.raises(ValueError, match="'linear' is not periodic"):
        periodic_extension(a, "linear")
    with pytest.raises(ValueError, match="width"):
        pad(a, -1)
    with pytest.raises(ValueError, match="odd square"):
        pad(np.ones((4, 4)), 1, "octahedral")
    with pytest.raises(ValueError, match="odd square"):
        pad(np.ones((5, 7)), 1, "octahedral")
    with pytest.raises(ValueError, match="image"):
        pad(np.ones(3), 1)
    with pytest.raises(TypeError, match="image"):
        pad(np.array([["a", "b"]]), 1)
    with pytest.raises(ValueError, match="NaN"):
        mean_filter(np.full((3, 3), np.nan))


# --- smoothing and the other operations: invariants ---------------------------------------------------

@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("op", sorted(ALL_OPS))
def test_constant_images_stay_constant_and_inputs_are_not_mutated(op, mode):
    const = np.full((17, 17, 3), [1.5, -2.0, 0.25], np.float32)
    before = const.copy()
    out = ALL_OPS[op](const, mode)
    assert out.shape == const.shape and out.dtype == np.float32
    assert np.abs(out - const).max() < 1e-5
    assert np.array_equal(const, before)
    noisy = NOISE.copy()
    ALL_OPS[op](noisy, mode)
    assert np.array_equal(noisy, NOISE)


@pytest.mark.parametrize("op", ["mean", "mean5x2", "gaussian"])
@pytest.mark.parametrize("mode", ["wrap", "octahedral"])
def test_linear_smoothing_preserves_the_mean_of_the_periodic_image(op, mode):
    out = SMOOTHERS[op](NOISE, mode)
    before, after = periodic_extension(NOISE, mode).mean(axis=(0, 1)), periodic_extension(out, mode).mean(axis=(0, 1))
    assert np.abs(after - before).max() < 1e-12
    assert np.abs(out - NOISE).max() > 0.1     # it did smooth


def test_linear_mode_keeps_a_flat_sheet_in_place():
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 2, 7))
    sheet = np.stack([u, v, 0.3 * u - 0.2 * v], axis=-1)
    assert np.abs(mean_filter(sheet, 5, "linear", iterations=3) - sheet).max() < 1e-12
    assert np.abs(gaussian_filter(sheet, 2.0, "linear") - sheet).max() < 1e-12
    assert np.abs(mean_filter(sheet, 5, "reflect") - sheet).max() > 0.05   # the even rule pulls the border in


def test_spatial_and_fourier_filters_agree_exactly():
    # the same kernel applied by padding + OpenCV and by the transfer function on the periodic extension
    for mode in MODES:
        for blur, kw in (("mean", dict(size=3)), ("mean", dict(size=7)), ("gaussian", dict(sigma=1.3))):
            spatial = (
                mean_filter(NOISE, kw["size"], mode) if blur == "mean" else gaussian_filter(NOISE, kw["sigma"], mode)
            )
            fourier = fourier_filter(NOISE, blur_transfer(blur_taps(blur, **kw)), mode)
            assert np.abs(spatial - fourier).max() < 1e-12, (mode, blur, kw)


def test_edge_preserving_filters_keep_a_cliff_the_mean_filter_blurs():
    # a height channel with a 1-unit cliff and noise of 0.02: the edge-preserving filters remove the noise
    # and keep the cliff; the mean filter removes the noise and smears the cliff over its window
    u = np.linspace(0, 1, 33)
    height = np.where(u < 0.5, 0.0, 1.0)[None, :].repeat(33, axis=0).astype(np.float32)
    noisy = height + RNG.normal(scale=0.02, size=height.shape).astype(np.float32)
    cliff, flat = (slice(None), slice(15, 18)), (slice(None), slice(2, 12))

    def errors(out):
        return float(np.abs(out - height)[cliff].max()), float(np.sqrt(((out - height)[flat] ** 2).mean()))

    noise = errors(noisy)[1]
    mean_cliff, mean_noise = errors(mean_filter(noisy, 5, "linear"))
    assert mean_cliff > 0.3 and mean_noise < 0.5 * noise
    for out in (bilateral_filter(noisy, 2.0, 0.1, "linear"), guided_filter(noisy, 2, 0.01, "linear")):
        cliff_err, noise_err = errors(out)
        assert cliff_err < 0.1 and noise_err < 0.6 * noise


# --- octahedral seams -------------------------------------------------------------------------------

NOT_MIRROR_SYMMETRIC = {"tv", "nlmeans"}     # forward differences, patch sums: a mirrored input is not mirrored out


@pytest.mark.parametrize("op", sorted(set(ALL_OPS) - NOT_MIRROR_SYMMETRIC))
def test_filtered_octahedral_image_welds_without_a_seam(spot_octahedral, op):
    px = spot_octahedral.pixels
    out = ALL_OPS[op](px, "octahedral")
    flat = out.reshape(-1, 3)
    w = weld_index(px.shape[0]).ravel()
    scale = np.abs(px).max()
    assert np.abs(flat - flat[w]).max() <= 1e-5 * scale      # glued pixels agree to float precision
    mesh = geoimg.GeometryImage(out, domain="octahedral", metadata=spot_octahedral.metadata).to_mesh()
    topo = topology(mesh)
    assert topo.closed and topo.genus == 0 and topo.components == 1


def test_octahedral_smoothing_shows_no_seam_in_the_mesh(spot_octahedral):
    # the welded boundary is no rougher than the interior after smoothing: compare second differences
    out = mean_filter(spot_octahedral.pixels, 5, "octahedral", iterations=2)
    p = pad(out, 1, "octahedral").astype(np.float64)
    lap = np.linalg.norm(p[2:, 1:-1] + p[:-2, 1:-1] + p[1:-1, 2:] + p[1:-1, :-2] - 4 * p[1:-1, 1:-1], axis=-1)
    border = np.r_[lap[0], lap[-1], lap[:, 0], lap[:, -1]]
    interior = lap[1:-1, 1:-1]
    assert np.percentile(border, 99) < 2.0 * np.percentile(interior, 99)


# --- sharpening -------------------------------------------------------------------------------------

def test_inverse_filter_recovers_a_blurred_real_geometry_image(mountain_image):
    p = mountain_image.pixels                       # 129 x 129: the 3-box's zero is not on the grid
    blurred = mean_filter(p, 3)
    before = np.sqrt(((blurred - p) ** 2).mean())
    for kw in (dict(nsr=1e-6), dict(method="clamp", max_gain=1e3)):
        back = inverse_filter(blurred, **kw)
        assert back.dtype == np.float32
        assert np.sqrt(((back - p) ** 2).mean()) < 0.01 * before, kw
    g = gaussian_filter(p.astype(np.float64), 1.0)
    back = inverse_filter(g, "gaussian", sigma=1.0, nsr=1e-8)
    assert np.sqrt(((back - p) ** 2).mean()) < 0.01 * np.sqrt(((g - p) ** 2).mean())


def test_inverse_filter_gain_is_bounded():
    spike = np.zeros((33, 33))
    spike[16, 16] = 1.0
    out = inverse_filter(spike, method="clamp", max_gain=4.0)
    f_in, f_out = (np.abs(np.fft.fft2(periodic_extension(a, "reflect"))) for a in (spike, out))
    seen = f_in > 1e-9
    assert (f_out[seen] / f_in[seen]).max() == pytest.approx(4.0) and np.isfinite(out).all()


def test_unsharp_mask_sharpens():
    step = np.repeat([[0.0] * 8 + [1.0] * 8], 5, axis=0)
    soft = gaussian_filter(step, 1.0)
    sharp = unsharp_mask(soft, 1.0, 1.0)
    assert np.abs(sharp - step).mean() < np.abs(soft - step).mean()


# --- masks ------------------------------------------------------------------------------------------

def test_masked_smoothing_is_local_feathered_and_exact_outside():
    u, v = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 41))
    img = np.stack([u, v, 0.2 * np.sin(9 * u) * np.cos(7 * v)], axis=-1)
    mask = (u - 0.5) ** 2 + (v - 0.5) ** 2 < 0.15 ** 2
    out = gaussian_filter(img, 2.0, mask=mask, feather=5)
    w = feather(mask, 5)
    assert np.array_equal(out[w == 0], img[w == 0])                 # bit-identical far outside
    full = gaussian_filter(img, 2.0)
    assert np.array_equal(out[mask], full[mask])                     # fully smoothed inside
    ring = (w > 0) & (w < 1)
    assert ring.sum() > 50
    # feathered: the change ramps down; no pixel-to-pixel jump larger than the jump a hard mask makes
    hard = gaussian_filter(img, 2.0, mask=mask)
    def jump(a):
        return np.abs(np.diff(a[..., 2] - img[..., 2], axis=1)).max()
    assert jump(out) < 0.5 * jump(hard)


def test_feather_weights():
    m = np.zeros((1, 9), bool)
    m[0, 4] = True
    w = feather(m, 3)
    assert w[0, 4] == 1 and w[0, 0] == 0 and np.all(np.diff(w[0, 4:]) <= 0) and np.all(w[0, 5:7] > 0)
    soft = np.linspace(0, 0.4, 9)[None, :]
    assert np.array_equal(feather(soft, 0), soft)
    oct_mask = np.zeros((5, 5), bool)
    oct_mask[1, 1] = True                 # beside the top side, whose pixel (0, 3) is glued to (0, 1)
    assert feather(oct_mask, 1.5, "octahedral")[0, 3] > 0 and feather(oct_mask, 1.5, "reflect")[0, 3] == 0


@pytest.mark.parametrize("mask, error, message", [
    (np.ones((4, 4), bool), ValueError, r"mask: expected shape \(9, 9\)"),
    (np.ones((9, 9, 3)), ValueError, "mask: expected shape"),
    (np.full((9, 9), "x"), TypeError, "mask: expected a boolean or real array"),
    (np.full((9, 9), 2.0), ValueError, r"mask: values must lie in \[0, 1\]"),
    (np.full((9, 9), np.nan), ValueError, r"mask: values must lie in \[0, 1\]"),
])
def test_bad_masks_are_refused(mask, error, message):
    with pytest.raises(error, match=message):
        mean_filter(np.zeros((9, 9, 3)), 3, mask=mask)


@pytest.mark.parametrize("call, message", [
    (lambda: mean_filter(NOISE, 4), "odd size"),
    (lambda: mean_filter(NOISE, 0), "size"),
    (lambda: gaussian_filter(NOISE, -1), "sigma"),
    (lambda: bilateral_filter(np.zeros((5, 5, 4)), 1, 1), "1 or 3 channels"),
    (lambda: guided_filter(NOISE, 2, 0.1, guide=np.zeros((3, 3))), "guide"),
    (lambda: lowpass(NOISE, 0), "cutoff"),
    (lambda: lowpass(NOISE, 0.1, "linear"), "not periodic"),
    (lambda: bandpass(NOISE, 0.3, 0.1), "low < high"),
    (lambda: inverse_filter(NOISE, "box"), "blur"),
    (lambda: inverse_filter(NOISE, method="magic"), "method"),
    (lambda: inverse_filter(NOISE, nsr=0), "nsr"),
    (lambda: blend(NOISE, NOISE[:5]), "resample one with filters.resize"),
    (lambda: blend(NOISE, NOISE, np.inf), "finite"),
    (lambda: resize(NOISE, (8, 8), "octahedral"), "odd square"),
    (lambda: resize(NOISE, (1, 8)), "shape"),
])
def test_bad_arguments_are_refused(call, message):
    with pytest.raises((ValueError, TypeError), match=message):
        call()


def test_numpy_scalars_are_numbers_and_tiny_cutoffs_keep_only_the_mean():
    """``np.float32(0.1)`` is a number (bandpass refused it); a cutoff so small that its square underflows
    gives the limit (only frequency 0 passes), not NaN: the same bits as any cutoff far below 1/size."""
    np.testing.assert_array_equal(
        bandpass(NOISE, np.float32(0.1), np.float64(0.2)), bandpass(NOISE, float(np.float32(0.1)), 0.2)
    )
    np.testing.assert_array_equal(lowpass(NOISE, np.float32(0.1)), lowpass(NOISE, float(np.float32(0.1))))
    tiny = lowpass(NOISE, 1e-200)
    assert np.isfinite(tiny).all()
    np.testing.assert_array_equal(tiny, lowpass(NOISE, 1e-100))
    assert np.ptp(highpass(NOISE, 1e-200) + tiny - NOISE) < 1e-12


# --- Fourier ----------------------------------------------------------------------------------------

def test_fourier_bands_add_up_and_symmetric_extension_avoids_the_border_error(mountain_image):
    p = mountain_image.pixels.astype(np.float64)
    low, high = lowpass(p, 0.05), highpass(p, 0.05)
    assert np.abs(low + high - p).max() < 1e-9
    assert np.abs(bandpass(p, 0.02, 0.05) - (lowpass(p, 0.05) - lowpass(p, 0.02))).max() < 1e-9
    # the naive (periodic) FFT mixes opposite borders of a planar image; the symmetric extension does not
    reference = gaussian_filter(p, 3.0)
    gain = blur_transfer(blur_taps("gaussian", sigma=3.0))
    naive, symmetric = fourier_filter(p, gain, "wrap"), fourier_filter(p, gain, "reflect")
    rim = np.zeros(p.shape[:2], bool)
    rim[:3], rim[-3:], rim[:, :3], rim[:, -3:] = True, True, True, True
    err_naive = np.abs(naive - reference)[rim].max()
    assert np.abs(symmetric - reference).max() < 1e-9 and err_naive > 1e3 * 1e-9


# --- blending, compositing, resizing ----------------------------------------------------------------

def test_blend_is_affine_in_t_with_exact_ends():
    a, b = NOISE, RNG.normal(size=NOISE.shape)
    assert np.array_equal(blend(a, b, 0.0), a) and np.array_equal(blend(a, b, 1.0), b)
    t = [0.1, 0.35, 0.8]
    out = [blend(a, b, x) for x in t]
    assert np.abs((out[1] - out[0]) / 0.25 - (out[2] - out[1]) / 0.45).max() < 1e-12
    ramp = np.linspace(0, 1, 17)[None, :].repeat(17, axis=0)
    per_pixel = blend(a, b, ramp)
    assert np.array_equal(per_pixel[:, 0], a[:, 0]) and np.array_equal(per_pixel[:, -1], b[:, -1])


def test_composite_and_paste():
    base, over = np.zeros((21, 21, 3)), np.ones((21, 21, 3))
    mask = np.zeros((21, 21), bool)
    mask[8:13, 8:13] = True
    out = composite(base, over, mask, 3)
    assert np.array_equal(out[mask], over[mask]) and np.all(out[feather(mask, 3) == 0] == 0)
    target = np.zeros((21, 21, 3))
    source = np.full((21, 21, 3), 10.0)
    source[10, 10] += 1.0                                  # the detail to carry over
    pasted, offset = paste(target, source, mask, 3)
    assert np.allclose(offset, -10.0) and pasted[10, 10, 0] == pytest.approx(1.0) and np.abs(pasted).max() <= 1.0
    pasted, offset = paste(target, source, mask, 3, align=False)
    assert np.array_equal(offset, np.zeros(3)) and pasted[10, 10, 0] == pytest.approx(11.0)


def test_resize_keeps_linear_functions_and_octahedral_symmetry(spot_octahedral):
    u, v = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 6))
    plane = np.stack([u, v, 2 * u - v], axis=-1)
    up = resize(plane, (11, 17))
    U, V = np.meshgrid(np.linspace(0, 1, 17), np.linspace(0, 1, 11))
    assert np.abs(up - np.stack([U, V, 2 * U - V], axis=-1)).max() < 1e-9
    px = spot_octahedral.pixels
    for n in (33, 129):
        r = resize(px, (n, n), "octahedral").reshape(-1, 3)
        assert np.abs(r - r[weld_index(n).ravel()]).max() <= 1e-5 * np.abs(px).max()
    assert np.array_equal(resize(px, px.shape[:2], "octahedral"), px)


# --- curvature --------------------------------------------------------------------------------------

def test_grid_curvature_of_a_sphere():
    n = 129
    q = grid_directions(n) * 2.0                      # a sphere of radius 2, octahedral, outward normals
    K, H = grid_curvature(q, "octahedral")
    smooth = np.ones((n, n), bool)                    # away from the octahedron's creases
    c = (n - 1) // 2
    for k in (0, c, n - 1):
        smooth[max(k - 2, 0):k + 3] = smooth[:, max(k - 2, 0):k + 3] = False
    x, y = np.meshgrid(np.arange(n) - c, np.arange(n) - c)
    smooth &= np.abs(np.abs(x) + np.abs(y) - c) > 2
    assert np.abs(K[smooth] - 0.25).max() < 0.01 and np.abs(H[smooth] + 0.5).max() < 0.01
    with pytest.raises(ValueError, match="geometry image"):
        grid_curvature(np.zeros((5, 5)))


@pytest.mark.parametrize("op", ["median", "tv", "nlmeans"])
def test_denoisers_bring_a_noisy_sphere_image_back_towards_the_clean_one(spot_octahedral, op):
    clean = spot_octahedral.pixels.astype(np.float64)
    sigma = 0.01 * np.ptp(clean.reshape(-1, 3), axis=0).max()
    noisy = clean + np.random.default_rng(3).normal(0, sigma, clean.shape)
    strength = {"median": (3,), "tv": (sigma,), "nlmeans": (sigma,)}[op]
    fn = {"median": median_filter, "tv": denoise_tv, "nlmeans": denoise_nl_means}[op]
    out = fn(noisy, *strength, "octahedral")
    before, after = np.sqrt(((noisy - clean) ** 2).mean()), np.sqrt(((out - clean) ** 2).mean())
    assert after < 0.7 * before


@pytest.mark.parametrize("call, match", [
    (lambda: median_filter(np.zeros((5, 5)), 4), "odd"),
    (lambda: denoise_tv(np.zeros((5, 5)), -1.0), "weight"),
    (lambda: denoise_nl_means(np.zeros((5, 5)), 0.0), "h"),
    (lambda: denoise_nl_means(np.zeros((5, 5)), 1.0, patch_size=0), "patch_size"),
])
def test_denoisers_refuse_bad_settings(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize("op", sorted(NOT_MIRROR_SYMMETRIC))
def test_denoisers_that_are_not_mirror_symmetric_differ_little_across_a_seam_and_apply_welds_them(spot_octahedral,
                                                                                                   op):
    # a glued pixel's neighbourhood is its twin's turned over; TV and non-local means do not give a turned-over
    # input a turned-over output, so the two sides of a seam differ a little, and GeometryImage.apply averages them
    px = spot_octahedral.pixels
    out = ALL_OPS[op](px, "octahedral")
    flat = out.reshape(-1, 3)
    w = weld_index(px.shape[0]).ravel()
    change = np.abs(out - px).mean()
    assert np.abs(flat - flat[w]).max() < 0.2 * change
    img = spot_octahedral.apply({"tv": denoise_tv, "nlmeans": denoise_nl_means}[op], 0.3)
    glued = img.pixels.reshape(-1, 3)
    assert np.array_equal(glued, glued[w])
    topo = topology(img.to_mesh())
    assert topo.closed and topo.genus == 0
