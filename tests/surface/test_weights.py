"""The weights as one typed choice: one default everywhere, each kind checks its own fields, and the flat keywords
of earlier releases still build the same surfaces, with a DeprecationWarning."""
import warnings

import numpy as np
import pytest

import geoimg
from geoimg import ConversionOptions, CoverageWeights, GaussianWeights
from geoimg.batch import BatchOptions
from geoimg.cli import build_parser
from geoimg.errors import InputError, InputTypeError
from geoimg.surface import make_weights, prefilter_s
from helpers import load_data


@pytest.fixture(scope="module")
def terrain():
    mesh = geoimg.grid_mesh(np.random.default_rng(0).random((12, 15)), (1.4, 1.1))
    return mesh, geoimg.parametrize(mesh, "heightfield", axis="z")


def test_one_default_everywhere(terrain):
    mesh, param = terrain
    assert ConversionOptions().weights == BatchOptions().weights == CoverageWeights()
    args = build_parser().parse_args(["image", "m.obj", "-o", "m.exr"])
    assert make_weights(args.weights, s=args.s, n=args.n, tol=args.tol, sliver_rule=args.sliver_rule) \
        == CoverageWeights()
    surf = geoimg.fit_surface(mesh, param)
    assert surf.weights == "coverage"
    by_hand = geoimg.fit_surface(mesh, param, CoverageWeights(s=1.0))
    served = by_hand.with_s(prefilter_s(by_hand, 33)).sample(33)        # the width that serves the resolution
    image = surf.sample(33)
    assert image.metadata["s"] == served.metadata["s"]
    assert np.array_equal(image.pixels, served.pixels) and np.array_equal(image.normals, served.normals)
    assert np.array_equal(geoimg.mesh_to_image(mesh, 33, parametrization=param, fidelity=False).pixels,
                          image.pixels)


@pytest.mark.parametrize("make, message", [
    (lambda: CoverageWeights(s=0), "s: expected a number from"), (lambda: CoverageWeights(s=[1, 2]), "one number"),
    (lambda: CoverageWeights(s=np.nan), "s: expected"), (lambda: CoverageWeights(tol=1.0), "tol: expected"),
    (lambda: GaussianWeights(s=0), "s: expected a positive"), (lambda: GaussianWeights(s=True), "s: expected"),
    (lambda: GaussianWeights(s="1"), "per-face values"), (lambda: GaussianWeights(s=1e9), "s: expected values"),
    (lambda: GaussianWeights(n=1), "n: expected"), (lambda: GaussianWeights(n=2.5), "n: expected"),
    (lambda: GaussianWeights(tol=-1e-3), "tol: expected"), (lambda: GaussianWeights(sliver_rule="x"), "sliver_rule"),
    (lambda: make_weights("cubic"), "weights: expected one of"),
    (lambda: ConversionOptions(weights="gaussian"), "expected CoverageWeights or GaussianWeights"),
    (lambda: ConversionOptions.create(caller="f", colour=True), "unknown option colour"),
])
def test_each_kind_checks_its_own_fields(make, message):
    with pytest.raises((InputError, InputTypeError), match=message):
        make()


def test_numpy_numbers_become_python_numbers():
    w = GaussianWeights(s=np.float32(0.5), n=np.int64(6), tol=np.float64(0))
    assert (type(w.s), type(w.n), type(w.tol)) == (float, int, float) and w.kind == "local"
    assert CoverageWeights(s=np.float32(2.0)) == CoverageWeights(s=2.0)


def test_the_flat_keywords_still_build_the_same_surfaces_with_a_warning(terrain):
    mesh, param = terrain
    cases = [(dict(s=2.0), GaussianWeights(s=2.0)),                      # fit_surface defaulted to "gaussian"
             (dict(weights="coverage"), CoverageWeights(s=1.0)),          # ... and to s = 1
             (dict(weights="local", n=6, s=1.5), GaussianWeights(s=1.5, n=6)),
             (dict(tol=0.0), GaussianWeights(tol=0.0)),
             (dict(sliver_rule="paper"), GaussianWeights(sliver_rule="paper"))]
    for old, new in cases:
        with pytest.warns(DeprecationWarning, match=r"deprecated .* pass weights=") as caught:
            a = geoimg.fit_surface(mesh, param, **old).sample(17)
        assert caught[0].filename == __file__                          # the warning points at the caller
        b = geoimg.fit_surface(mesh, param, new).sample(17)
        assert np.array_equal(a.pixels, b.pixels), old
    with pytest.warns(DeprecationWarning):
        old = geoimg.fit_surface(mesh, param, 2.0).sample(17)             # a number in s's old place
    assert np.array_equal(old.pixels, geoimg.fit_surface(mesh, param, GaussianWeights(s=2.0)).sample(17).pixels)
    with pytest.warns(DeprecationWarning, match="mesh_to_image"):
        a = geoimg.mesh_to_image(mesh, 17, s=2.0, parametrization=param, fidelity=False)   # coverage was its default
    b = geoimg.mesh_to_image(mesh, 17, weights=CoverageWeights(s=2.0), parametrization=param, fidelity=False)
    assert np.array_equal(a.pixels, b.pixels)
    with pytest.warns(DeprecationWarning):
        assert BatchOptions.create(caller="convert", s=2.0, weights="gaussian").weights == GaussianWeights(s=2.0)
    with pytest.warns(DeprecationWarning, match="BatchOptions"):
        from geoimg.batch import ConvertOptions
    assert ConvertOptions is BatchOptions


def test_typed_weights_and_flat_keywords_do_not_mix(terrain):
    mesh, param = terrain
    with pytest.raises(InputError, match="belong inside weights="):
        geoimg.fit_surface(mesh, param, GaussianWeights(), s=2.0)
    with pytest.raises(InputError, match="belong inside weights="):
        ConversionOptions.create(caller="mesh_to_image", weights=CoverageWeights(), tol=0.0)
    with pytest.raises(InputTypeError, match="expected a ConversionOptions"):
        geoimg.mesh_to_image(mesh, 9, options={"method": "sphere"})
    with warnings.catch_warnings():
        warnings.simplefilter("error")                                  # the new forms warn about nothing
        geoimg.fit_surface(mesh, param, GaussianWeights(s=2.0))
        geoimg.mesh_to_image(mesh, 9, parametrization=param, fidelity=False,
                             options=ConversionOptions(weights=GaussianWeights(n=6)))


def test_options_and_keywords_meet_in_one_object(terrain):
    mesh, param = terrain
    options = ConversionOptions(resolution=17, weights=CoverageWeights(s=0.5))
    a = geoimg.mesh_to_image(mesh, options=options, parametrization=param, fidelity=False)
    b = geoimg.mesh_to_image(mesh, 17, weights=CoverageWeights(s=0.5), parametrization=param, fidelity=False)
    c = geoimg.mesh_to_image(mesh, 9, options=options, parametrization=param, fidelity=False)  # resolution replaced
    assert np.array_equal(a.pixels, b.pixels) and c.shape[1] == 9 and a.metadata["s"] == 0.5


def test_charts_refuse_the_papers_weights():
    mesh = load_data("torus.obj")
    param = geoimg.parametrize(mesh, "charts")
    with pytest.raises(InputError, match="coverage weights only"):
        geoimg.fit_surface(mesh, param, GaussianWeights())
