"""GeometryImage.apply runs any operation seam-free: filters functions through their ``mode``, and any other
callable on arrays (OpenCV, scipy, scikit-image) through pad-by-the-domain's-rule -> call -> crop."""
import cv2
import numpy as np
import pytest
from scipy import ndimage
from skimage.restoration import denoise_tv_chambolle

import filters
import geoimg
from geoimg import GeometryImage, ImageError, OctahedralDomain, PlanarDomain

from helpers import glue_spread, load_data


@pytest.fixture(scope="module")
def spot_octahedral():
    mesh = load_data("spot_low_resolution.obj")
    return geoimg.fit_surface(mesh, geoimg.parametrize(mesh, "sphere"), geoimg.GaussianWeights()).sample(65)


@pytest.fixture(scope="module")
def bumpy_planar():
    rng = np.random.default_rng(3)
    x, y = np.meshgrid(np.linspace(0, 1, 24), np.linspace(0, 0.75, 18))
    z = 0.1 * np.sin(6 * x) * np.cos(5 * y) + 0.01 * rng.normal(size=x.shape)
    return GeometryImage(np.stack([x, y, z], axis=-1).astype(np.float32), domain=PlanarDomain(extent=(1.0, 0.75)))


def raw_result(image, op, width, *args, **kwargs):
    """What apply computes before glued pixels are averaged."""
    h, w = image.shape
    return np.asarray(op(image.domain.pad(image.pixels, width), *args, **kwargs))[width:width + h, width:width + w]


@pytest.mark.parametrize("op, args, kwargs, width", [
    (cv2.GaussianBlur, ((7, 7), 1.5), {}, 4),
    (cv2.blur, ((5, 5),), {}, 3),
    (cv2.medianBlur, (5,), {}, 3),
    (ndimage.median_filter, (), {"size": (3, 3, 1)}, 2),
    (ndimage.gaussian_filter, (), {"sigma": (1.0, 1.0, 0)}, 5),
])
def test_local_operations_cross_the_octahedral_seams(spot_octahedral, op, args, kwargs, width):
    img = spot_octahedral
    # padded by the octahedral rule, each glued pair sees the same neighbourhood: the raw results agree
    # to rounding; padded by reflection (what the operation would do on its own) they do not
    good = raw_result(img, op, width, *args, **kwargs)
    h = img.shape[0]
    reflected = np.asarray(op(filters.pad(img.pixels, width, "reflect"), *args, **kwargs))[
        width : width + h, width : width + h
    ]
    scale = np.ptp(img.pixels)
    assert glue_spread(img, good) < 1e-5 * scale < 1e-3 * scale < glue_spread(img, reflected)
    out = img.apply(op, *args, pad=width, **kwargs)
    assert out.domain == img.domain and out.normals is None and out.pixels.dtype == np.float32
    assert glue_spread(out, out.pixels) == 0.0                     # glued pixels identical after averaging
    assert np.allclose(out.pixels, img.domain.average_glued(good), atol=1e-6 * scale)
    assert out.metadata["filters"][-1].startswith(getattr(op, "__name__", "op")) and f"pad={width}" in \
        out.metadata["filters"][-1]


def test_a_box_filter_from_scipy_equals_the_filters_mean_filter(spot_octahedral, bumpy_planar):
    for img in (spot_octahedral, bumpy_planar):
        ours = img.apply(filters.mean_filter, 3)
        theirs = img.apply(ndimage.uniform_filter, size=(3, 3, 1), pad=1)
        assert np.allclose(ours.pixels, theirs.pixels, atol=1e-6 * np.ptp(img.pixels))


def test_planar_borders_follow_the_rule(bumpy_planar):
    img = bumpy_planar
    out = img.apply(ndimage.uniform_filter, size=(3, 3, 1), pad=1)
    p = img.pixels.astype(np.float64)
    # reflect: the pixel beyond the left edge is the one right of it, so the first column's 3 x 3 mean is
    rows = np.clip(np.arange(-1, 2) + 5, 0, None)
    expect = (p[rows][:, [1, 0, 1]]).mean(axis=(0, 1))
    assert np.allclose(out.pixels[5, 0], expect, atol=1e-6)


def test_a_global_denoiser_runs_on_octahedral_images(spot_octahedral):
    rng = np.random.default_rng(0)
    img = spot_octahedral
    noisy = img.with_pixels(OctahedralDomain().average_glued(
        img.pixels + rng.normal(scale=0.01, size=img.pixels.shape).astype(np.float32)))
    out = noisy.apply(denoise_tv_chambolle, weight=0.01, channel_axis=-1, pad=8)
    assert out.pixels.dtype == np.float32 and glue_spread(out, out.pixels) == 0.0
    assert np.sqrt(np.mean((out.pixels - img.pixels) ** 2)) < np.sqrt(np.mean((noisy.pixels - img.pixels) ** 2))
    # the seams see across themselves: before averaging, glued pixels agree far better padded than not
    padded = glue_spread(noisy, raw_result(noisy, denoise_tv_chambolle, 8, weight=0.01, channel_axis=-1))
    unpadded = glue_spread(noisy, raw_result(noisy, denoise_tv_chambolle, 0, weight=0.01, channel_axis=-1))
    assert padded < 0.5 * unpadded


def test_any_callable_can_be_masked(bumpy_planar):
    img = bumpy_planar
    mask = np.zeros(img.shape)
    mask[5:12, 5:15] = 1
    out = img.apply(cv2.GaussianBlur, (5, 5), 1.0, mask=mask, feather=0, pad=3)
    assert np.array_equal(out.pixels[mask == 0], img.pixels[mask == 0])
    assert not np.array_equal(out.pixels[mask == 1], img.pixels[mask == 1])


def test_inputs_are_left_unchanged(spot_octahedral):
    before = spot_octahedral.pixels.copy()
    spot_octahedral.apply(cv2.GaussianBlur, (3, 3), 1.0)
    assert np.array_equal(spot_octahedral.pixels, before)


@pytest.mark.parametrize("call, error, message", [
    (lambda img: img.apply(lambda a: a[1:]), ImageError, "returned shape"),
    (lambda img: img.apply(lambda a: a * np.nan), ImageError, "NaN"),
    (lambda img: img.apply(cv2.blur, (3, 3), pad=-1), ValueError, "pad"),
    (lambda img: img.apply(cv2.blur, (3, 3), pad=1.5), ValueError, "pad"),
    (lambda img: img.apply(filters.mean_filter, 3, pad=2), ImageError, "pad is for other callables"),
    (lambda img: img.apply(cv2.blur, (3, 3), mask=np.ones((2, 2))), ValueError, "mask"),
    (lambda img: img.apply(filters.blend, GeometryImage(np.zeros((5, 5, 3), np.float32))), ImageError,
     "expected a planar .18, 24. geometry image"),
])
def test_bad_operations_are_refused(bumpy_planar, call, error, message):
    with pytest.raises(error, match=message):
        call(bumpy_planar)
