"""Geometry images through the filters: domain rules, masks and regions, curvature, varying s, CLI."""

import numpy as np
import pytest

import filters
import geoimg
from geoimg.cli import main
from geoimg.image import image_curvature
from geoimg.surface import surface_curvature
from geoimg.parametrization._octahedral import weld_index
from geoimg.image import image_region, load_mask, uv_region
from geoimg.surface import smoothness_field
from geoimg.mesh import topology

from helpers import finite_differences, load_data




@pytest.fixture(scope="module")
def spot():
    mesh = load_data("spot_low_resolution.obj")
    param = geoimg.parametrize(mesh, "sphere")
    surf = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights())
    return mesh, param, surf, surf.sample(65)


def test_apply_uses_the_domain_rule_and_keeps_glued_pixels_identical(spot):
    *_, img = spot
    out = img.apply(filters.gaussian_filter, 2.0)
    flat = out.pixels.reshape(-1, 3)
    assert np.array_equal(flat, flat[weld_index(65).ravel()])
    assert out.normals is None and out.domain == img.domain and img.normals is not None
    assert out.metadata["filters"] == ["gaussian_filter(2.0, mode=octahedral)"]
    assert np.array_equal(
        out.pixels, geoimg.OctahedralDomain().average_glued(filters.gaussian_filter(img.pixels, 2.0, "octahedral"))
    )
    topo = topology(out.to_mesh())
    assert topo.closed and topo.genus == 0


def test_apply_masks_any_operation_and_leaves_far_pixels_bit_identical(spot, mountain_surface):
    *_, img = spot
    centre = img.pixels[20, 30]
    region = image_region(img, centre, 0.15)
    assert region.sum() > 10
    for op, args in ((filters.lowpass, (0.05,)), (filters.mean_filter, (5,))):   # without / with a mask argument
        out = img.apply(op, *args, mask=region, feather=3)
        far = filters.feather(region, 3, "octahedral") == 0
        assert np.array_equal(out.pixels[far], img.pixels[far])
        assert np.abs(out.pixels[region == 1] - img.pixels[region == 1]).max() > 1e-4
    planar = mountain_surface.sample(33)
    with pytest.raises(ValueError, match="octahedral"):
        img.apply(filters.blend, planar, 0.5)
    blended = planar.apply(filters.blend, planar.apply(filters.mean_filter, 3), 0.5)
    assert blended.mask is not None and np.array_equal(blended.mask, planar.mask)


def test_octahedral_masks_are_made_symmetric(spot):
    *_, img = spot
    one_side = np.zeros((65, 65))
    one_side[0, 10] = 1.0                 # glued to (0, 54)
    out = img.apply(filters.mean_filter, 3, mask=one_side, feather=0)
    assert not np.array_equal(out.pixels[0, 54], img.pixels[0, 54])


def test_uv_region_and_mask_files(tmp_path):
    import OpenImageIO as oiio

    w = uv_region((21, 31), (0.5, 0.5), 0.2, 0.1)
    assert w[10, 15] == 1 and w[0, 0] == 0 and 0 < w[10, 22] < 1
    png = tmp_path / "m.png"
    data = (np.arange(31)[None, :].repeat(21, 0) >= 15).astype(np.uint8) * 255
    out = oiio.ImageOutput.create(str(png))
    out.open(str(png), oiio.ImageSpec(31, 21, 1, oiio.UINT8))
    out.write_image(data[..., None])
    out.close()
    m = load_mask(png, (21, 31))
    assert m.dtype == np.float64 and set(np.unique(m)) == {0.0, 1.0} and m[0, 15] == 1
    with pytest.raises(ValueError, match="31 x 21 pixels; the geometry image is 30 x 21"):
        load_mask(png, (21, 30))
    with pytest.raises(FileNotFoundError, match="mask"):
        load_mask(tmp_path / "none.png", (21, 31))
    with pytest.raises(ValueError, match="centre"):
        uv_region((5, 5), (0.5,), 0.1)


# --- surface-domain partial smoothing (paper 4.5) ---------------------------------------------------

def test_varying_s_smooths_a_region_and_keeps_normals_exact(mountain, mountain_surface):
    param = geoimg.parametrize(mountain, "heightfield", axis="y")
    centre = mountain.vertices[np.argmax(mountain.vertices[:, 1])]          # around the summit
    diag = mountain.bounding_box_diagonal()
    s_face = smoothness_field(mountain, centre, 0.1 * diag, inside=6.0, outside=2.0, feather=0.1 * diag)
    assert s_face.shape == (mountain.n_faces,) and s_face.min() == 2 and s_face.max() == 6
    varied = geoimg.fit_surface(mountain, param, geoimg.GaussianWeights(s=s_face))
    assert varied.s == 2.0
    u, v = varied.grid(65)
    uu, vv = np.meshgrid(u, v)
    uv = np.stack([uu.ravel(), vv.ravel()], 1)
    change = np.linalg.norm(varied.evaluate(uv) - mountain_surface.evaluate(uv), axis=1)
    near = image_region(geoimg.GeometryImage(mountain_surface.evaluate(uv).reshape(65, 65, 3).astype(np.float32)),
                        centre, 0.1 * diag).ravel() > 0
    far = image_region(geoimg.GeometryImage(mountain_surface.evaluate(uv).reshape(65, 65, 3).astype(np.float32)),
                       centre, 0.45 * diag).ravel() == 0
    assert near.sum() > 20 and far.sum() > 100
    assert np.median(change[near]) > 100 * np.median(change[far])
    # exact normals: analytic derivatives agree with finite differences of the varied surface
    pts = uv[near][:5]
    pu, pv = varied.derivatives(pts)
    fd_u, fd_v = finite_differences(varied, pts)
    assert np.abs(pu - fd_u).max() < 1e-5 * np.abs(pu).max() and np.abs(pv - fd_v).max() < 1e-5 * np.abs(pv).max()
    # truncation stays certified: the truncated sum equals the exact one
    assert np.abs(varied.evaluate(uv[::7]) - varied.evaluate(uv[::7], exact=True)).max() < 1e-9 * diag


def test_varying_s_on_the_sphere(spot):
    mesh, param, surf, img = spot
    s_face = np.where(np.arange(mesh.n_faces) % 2 == 0, 1.0, 1.5)
    varied = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=s_face))
    assert varied.s == 1.0 and varied.sample(9).metadata["s_max"] == 1.5
    q = geoimg.parametrization.grid_directions(17).reshape(-1, 3)
    assert np.abs(varied.evaluate_directions(q)[0] - varied.evaluate_directions(q, exact=True)[0]).max() < 1e-9


@pytest.mark.parametrize("s, message", [
    (np.ones(3), "per-face values"), (-np.ones(4), "positive"), ("1", "per-face values"), (np.nan, "positive finite")])
def test_bad_smoothness_is_refused(s, message):
    m = geoimg.Mesh(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], [[0, 1, 2], [0, 2, 3], [1, 4, 2], [0, 1, 3]]
    )
    with pytest.raises(ValueError, match=message):
        geoimg.fit_surface(m, geoimg.Parametrization(m.vertices[:, :2] / 2, (1, 1)), geoimg.GaussianWeights(s=s))


# --- curvature --------------------------------------------------------------------------------------

def test_surface_curvature_of_a_sphere_mesh():
    mesh = load_data("sphere.obj")
    surf = geoimg.fit_surface(mesh, geoimg.parametrize(mesh, "sphere"), geoimg.GaussianWeights())
    K, H = surface_curvature(surf, 33)
    r = np.linalg.norm(mesh.vertices, axis=1).mean()
    assert np.median(K) == pytest.approx(1 / r ** 2, rel=0.03) and np.median(H) == pytest.approx(-1 / r, rel=0.03)
    assert np.mean(np.abs(K * r * r - 1) < 0.15) > 0.98
    # the grid's curvature reads the octahedron's creases; the surface's has no such lines
    Kg, _ = image_curvature(surf.sample(33))
    assert np.abs(Kg - 1 / r ** 2).max() > 2 * np.abs(K - 1 / r ** 2).max()


def test_grid_and_surface_curvature_agree_on_terrain(mountain_surface):
    K, H = surface_curvature(mountain_surface, 129)
    Kg, Hg = image_curvature(mountain_surface.sample(129))
    inner = (slice(3, -3), slice(3, -3))
    assert np.corrcoef(H[inner].ravel(), Hg[inner].ravel())[0, 1] > 0.95
    assert np.corrcoef(K[inner].ravel(), Kg[inner].ravel())[0, 1] > 0.9


def _neighbour_correlation(H):
    return np.corrcoef(H[2:-2, 2:-3].ravel(), H[2:-2, 3:-2].ravel())[0, 1]


def test_curvature_at_a_scale_shows_features_not_facets(mountain):
    from geoimg.image._curvature import curvature_sigma
    img = geoimg.mesh_to_image(mountain, 129, fidelity=False)            # faithful: nearly the facets
    raw = image_curvature(img)[1]
    at_scale = image_curvature(img, 0.01)[1]
    # pixel noise has neighbours that barely agree; ridges and valleys a few pixels wide do
    assert _neighbour_correlation(raw) < 0.7 and _neighbour_correlation(at_scale) > 0.9
    assert np.array_equal(image_curvature(img, 0.0)[1], raw)
    # on a sphere the smoothing at a small scale leaves H = -1 and K = 1
    d = geoimg.OctahedralDomain()
    ball = geoimg.GeometryImage(d.directions(65).astype(np.float32), None, d)
    K, H = image_curvature(ball, 0.01)
    assert abs(np.median(H) + 1) < 0.01 and abs(np.median(K) - 1) < 0.01
    x, y = np.meshgrid(np.linspace(0, 1, 101), np.linspace(0, 1, 101))
    assert np.isclose(curvature_sigma(geoimg.GeometryImage(np.stack([x, y, 0 * x], -1)), 0.01), np.sqrt(2))
    for bad in (-0.1, 0.5, float("nan"), True, "1%"):
        with pytest.raises(geoimg.InputError, match="scale"):
            image_curvature(ball, bad)


def test_colour_maps_say_what_they_show(tmp_path):
    from geoimg.image import save_colormap
    values = np.linspace(-1, 1, 64 * 80).reshape(64, 80)
    plain = save_colormap(values, tmp_path / "a.png")
    titled = save_colormap(values, tmp_path / "b.png", title="mean curvature")
    import imageio.v3 as iio
    pa, pb = iio.imread(plain), iio.imread(titled)
    assert pa.shape == pb.shape and (pa != pb).any() and np.array_equal(pa[40:], pb[40:])   # text at the top only


# --- command line -----------------------------------------------------------------------------------

def test_cli_filter_and_curvature(tmp_path, spot, capsys):
    *_, img = spot
    src = img.save(tmp_path / "spot.exr")
    rc = main(["filter", str(src), "-o", str(tmp_path / "f.exr"), "--mean", "5", "--sharpen", "3",
               "--region", *map(str, img.pixels[32, 32]), "0.2", "--mesh", str(tmp_path / "f.obj")])
    assert rc == 0
    out = geoimg.load_image(tmp_path / "f.exr")
    assert out.metadata["filters"][0].startswith("mean_filter(5") and out.metadata["filters"][1].startswith(
        "inverse_filter"
    )
    topo = topology(geoimg.load_mesh(tmp_path / "f.obj"))
    assert topo.closed and topo.genus == 0
    assert main(["curvature", str(src), "-o", str(tmp_path / "c")]) == 0
    assert (tmp_path / "c_gaussian.exr").is_file() and (tmp_path / "c_mean.png").is_file()
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(tmp_path / "c_mean.exr"))
    H_file = np.asarray(inp.read_image(oiio.FLOAT)).reshape(65, 65)
    inp.close()
    assert np.array_equal(H_file, image_curvature(img, 0.01)[1].astype(np.float32))     # the default scale
    assert main(["curvature", str(src), "-o", str(tmp_path / "r"), "--scale", "0"]) == 0
    inp = oiio.ImageInput.open(str(tmp_path / "r_mean.exr"))
    H_raw = np.asarray(inp.read_image(oiio.FLOAT)).reshape(65, 65)
    inp.close()
    assert np.array_equal(H_raw, image_curvature(img)[1].astype(np.float32))
    assert main(["curvature", str(src), "-o", str(tmp_path / "bad"), "--scale", "-1"]) == 2
    assert not list(tmp_path.glob("bad_*"))
    nmap = oiio.ImageInput.open(str(tmp_path / "c_normals.png"))
    assert nmap.spec().nchannels == 3 and nmap.spec().width == 65
    nmap.close()
    capsys.readouterr()
    assert main(["filter", str(src), "-o", str(tmp_path / "g.exr")]) == 2
    assert "no operation given" in capsys.readouterr().err
    assert main(["filter", str(src), "-o", str(tmp_path / "g.exr"), "--mean", "4"]) == 2
    assert "odd size" in capsys.readouterr().err
    assert (
        main(["filter", str(src), "-o", str(tmp_path / "g.exr"), "--mean", "3", "--region", "9", "9", "9", "0.1"]) == 2
    )
    assert "selects no pixel" in capsys.readouterr().err
    assert main(["filter", str(src), "-o", str(tmp_path / "f.exr"), "--mean", "3"]) == 2    # exists, no --force
    assert not (tmp_path / "g.exr").exists()


def test_a_smoothness_map_keeps_a_region_sharp_and_normals_exact(mountain, mountain_surface):
    from geoimg.surface import uv_smoothness
    param = geoimg.parametrize(mountain, "heightfield", axis="y")
    smap = uv_smoothness((0.5, 0.5), 0.15, inside=2.0, outside=6.0, feather=0.1)
    varied = geoimg.fit_surface(mountain, param, geoimg.GaussianWeights(s=smap))
    six = geoimg.fit_surface(mountain, param, geoimg.GaussianWeights(s=6.0))
    rng = np.random.default_rng(4)
    uv = rng.uniform(0.02, 0.98, (400, 2)) * param.extent
    r = np.linalg.norm(uv - 0.5, axis=1)
    diag = mountain.bounding_box_diagonal()
    inside, outside = uv[r < 0.14], uv[r > 0.26]
    # where s(u, v) is 2 the surface is the s = 2 surface, where it is 6 the s = 6 one: no reach across
    assert np.abs(varied.evaluate(inside) - mountain_surface.evaluate(inside)).max() < 1e-9 * diag
    assert np.abs(varied.evaluate(outside) - six.evaluate(outside)).max() < 1e-9 * diag
    ring = uv[(r > 0.16) & (r < 0.24)][:20]                       # in the blend, where s varies
    pu, pv = varied.derivatives(ring)
    fd_u, fd_v = finite_differences(varied, ring)
    assert np.abs(pu - fd_u).max() < 1e-6 * np.abs(pu).max() and np.abs(pv - fd_v).max() < 1e-6 * np.abs(pv).max()
    assert np.abs(varied.evaluate(uv[::9]) - varied.evaluate(uv[::9], exact=True)).max() < 1e-9 * diag
    img = varied.sample(33)
    assert img.metadata["s"] == 2.0 and img.metadata["s_max"] == 6.0


def test_a_smoothness_map_is_refused_on_the_sphere_and_checked(spot):
    from geoimg.surface import uv_smoothness
    mesh, param, *_ = spot
    with pytest.raises(ValueError, match="planar parametrizations"):
        geoimg.fit_surface(mesh, param, geoimg.GaussianWeights(s=uv_smoothness((0.5, 0.5), 0.1, 2.0)))
    with pytest.raises(ValueError, match="feather"):
        uv_smoothness((0.5, 0.5), 0.1, 2.0, feather=0)
    with pytest.raises(ValueError, match="centre"):
        uv_smoothness((0.5,), 0.1, 2.0)
