"""Multi-chart maps and images: every chart a disc on a square of its own, the charts' borders glued pixel for
pixel, so the quad mesh is watertight with the mesh's genus; nothing of one chart reaches another's tile."""
import numpy as np
import pytest

import filters
import geoimg
from geoimg import ChartsDomain, ImageError, InputError, ParametrizationError
from geoimg.mesh import point_mesh_distance, surface_distance, topology
from geoimg.parametrization import chart_coords
from geoimg.parametrization._charts import pack_squares, segment_charts
from geoimg.parametrization._layout import layout_extent, layout_span, tile_points, weld_defects
from geoimg.parametrization._laplacian import planar_cross, starved_share, triangle_areas
from geoimg.parametrization._parametrize import _charts, _image_error, _starved_to_charts
from geoimg.surface._attributes import locate

import meshes
from helpers import glue_spread, load_data

CASES = {"torus grid": lambda: meshes.torus_grid(16, 8), "plate with 5 holes (CAD, genus 5)":
         lambda: load_data("plate_holes.STL")}


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    mesh = CASES[request.param]()
    return mesh, _charts(mesh, charts=4)


def _linear(param, shape):
    """The charted mesh resampled linearly (barycentric) at every pixel, NaN off its triangles."""
    domain = geoimg.Domain.from_metadata("charts", dict(param.domain_fields))
    tris, _ = param.mesh.triangulate()
    tri, bary = locate(domain.parameter_points(shape), param.coords[tris])
    out = np.full((len(tri), 3), np.nan)
    ok = tri >= 0
    out[ok] = np.einsum("kc,kcd->kd", bary[ok], param.mesh.vertices[tris[tri[ok]]])
    return out.reshape(shape + (3,)), domain


def test_every_chart_is_a_disc_and_keeps_the_input(case):
    mesh, param = case
    before = mesh.vertices.copy()
    assert param.domain == "charts" and param.method == "charts"
    assert param.flipped_faces == 0 and param.degenerate_faces == 0
    assert param.info["charts"] >= 4 and len(param.info["chart_errors"]) == param.info["charts"]
    np.testing.assert_array_equal(mesh.vertices, before)
    src, w = param.source, param.source_weight
    again = (1 - w)[:, None] * mesh.vertices[src[:, 0]] + w[:, None] * mesh.vertices[src[:, 1]]
    np.testing.assert_allclose(param.mesh.vertices, again, atol=1e-12)


def test_twin_pixels_are_one_point_of_the_mesh(case):
    mesh, param = case
    domain = geoimg.Domain.from_metadata("charts", dict(param.domain_fields))
    shape = domain.grid_shape(domain.round_resolution(100))
    lin, _ = _linear(param, shape)
    reps, group = domain.glue(shape)
    glued = np.bincount(group) > 1
    assert glued.sum() > 4 * param.info["charts"]
    flat = lin.reshape(-1, 3)
    assert np.isfinite(flat[glued[group]]).all()         # every glued pixel is on a chart
    means = np.stack([np.bincount(group, flat[:, c].clip(-1e300, 1e300)) / np.bincount(group) for c in range(3)], 1)
    diag = np.linalg.norm(np.ptp(mesh.vertices, axis=0))
    assert np.abs(flat - means[group])[glued[group]].max() < 1e-9 * diag


def test_the_quad_mesh_is_watertight_with_the_genus(case):
    mesh, param = case
    img = geoimg.mesh_to_image(mesh, 129, parametrization=param)
    assert img.domain.kind == "charts" and max(img.shape) >= 129
    quads = img.to_mesh()
    t, t_in = topology(quads), topology(mesh)
    assert t.closed and t.components == 1 and t.genus == t_in.genus
    assert t.nonmanifold_edges == 0
    d = surface_distance(mesh, quads, 20000)
    assert d["psnr_db"] > 55 and d["hausdorff_rel"] < 0.03


def test_no_face_of_one_chart_reaches_another_tile():
    """A coarse torus has faces larger than the gutter; at s -> 0 every pixel must be on its own chart's
    triangles (copies across a border once reached through the gutter into the next tile, 1.9 units off)."""
    mesh = meshes.torus_grid(12, 6)
    param = _charts(mesh, charts=4)
    domain = geoimg.Domain.from_metadata("charts", dict(param.domain_fields))
    shape = domain.grid_shape(domain.round_resolution(60))
    lin, _ = _linear(param, shape)
    img = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1e-4)).sample(max(shape))
    ok = img.valid & np.isfinite(lin).all(axis=2)
    assert ok.sum() > 0.5 * img.valid.sum()
    assert np.abs(np.asarray(img.pixels, np.float64)[ok] - lin[ok]).max() < 1e-4      # float32 pixels, s > 0


def test_gutter_pixels_are_never_valid():
    mesh = meshes.torus_grid(16, 8)
    param = _charts(mesh, charts=3)
    img = geoimg.mesh_to_image(mesh, 100, parametrization=param)
    d = img.domain
    r0, c0, n = d._origins(img.shape)
    inside = np.zeros(img.shape, bool)
    for r, c, k in zip(r0, c0, n):
        inside[r:r + k, c:c + k] = True
    assert len(d.squares) == param.info["charts"] and (~inside).sum() > 0.1 * inside.size
    assert not (img.valid & ~inside).any()


def test_filters_read_across_a_border_the_twins_pixels():
    mesh = meshes.torus_grid(16, 8)
    img = geoimg.mesh_to_image(mesh, 100, parametrization=_charts(mesh, charts=4))
    d = img.domain
    px = np.asarray(img.pixels, np.float64)
    padded = d.pad(px, 2)
    n = d._origins(img.shape)[2]
    scale = d._scale(img.shape)
    tp, p, tq, q = d._twin_pairs(scale)
    nodes = {(k, a * scale) for k, a, _, _ in d.segments} | {(k, (a + m) * scale) for k, a, m, _ in d.segments}
    keep = (p % (n[tp] - 1) != 0) & (q % (n[tq] - 1) != 0) & np.array([(k, x) not in nodes for k, x in zip(tp, p)])
    assert keep.sum() > 100                                 # ends of segments: two twins, either may win
    rq, cq = d._pixel_of(img.shape, tq[keep], q[keep])
    rp, cp = d._pixel_of(img.shape, tp[keep], p[keep])
    from geoimg.image._perimeter import INWARD, perimeter_sides
    sp, sq = perimeter_sides(p[keep], n[tp[keep]]), perimeter_sides(q[keep], n[tq[keep]])
    got = padded[rp - INWARD[sp, 0] + 2, cp - INWARD[sp, 1] + 2]         # one step out of this side
    want = px[rq + INWARD[sq, 0], cq + INWARD[sq, 1]]                   # one step into the twin
    np.testing.assert_array_equal(got, want)
    smoothed = img.apply(filters.mean_filter, 3)
    assert glue_spread(smoothed, smoothed.pixels) < 1e-5


def test_the_paper_weights_are_refused_on_charts():
    mesh = meshes.torus_grid(12, 6)
    with pytest.raises(InputError, match="coverage"):
        geoimg.fit_surface(mesh, _charts(mesh, charts=2), geoimg.GaussianWeights())


def test_auto_takes_charts_only_where_one_chart_starves():
    mesh = meshes.torus_grid(16, 8)
    cut = geoimg.parametrize(mesh)
    assert cut.domain == "cut" and cut.info["starved_share"] <= 0.25
    topo = topology(mesh)
    assert _starved_to_charts(mesh, cut, topo, "area", None) is cut
    cut.info["starved_share"] = 0.9                        # as if one chart starved most of it: charts tried
    kept = _starved_to_charts(mesh, cut, topo, "area", None)
    assert kept is cut and cut.info["stages"][-1].startswith("charts tried, not kept (resampling error")
    charts = _charts(mesh, topo)                            # kept: the torus's cut is the closer image
    assert _image_error(mesh, charts) > _image_error(mesh, cut)


@pytest.mark.slow
def test_auto_takes_charts_for_a_disk_whose_map_starves_most_of_it():
    # a tube 80 times as long as it is wide, open at one end: the disk map gives its far end almost nothing
    # (76-78 % of the surface starved; 17.9 dB at 129^2), the charts give every part its share (80.4 dB); the
    # stage line says how much the disk's map starved
    mesh = meshes.finger(segments=8, rows=80, length=20.0)
    disk = geoimg.parametrize(mesh, "disk")
    assert _starved_to_charts(mesh, disk, topology(mesh), "area", None).domain == "charts"
    assert disk.info["starved_share"] > 0.5                         # measured there, for a disk's map
    auto = geoimg.parametrize(mesh)
    assert auto.domain == "charts" and auto.info["starved_share"] < 0.05
    assert auto.info["stages"][0].startswith(f"one chart starved {100 * disk.info['starved_share']:.0f} %")
    assert _image_error(mesh, auto) < _image_error(mesh, disk)
    near, far = (geoimg.mesh_to_image(mesh, 129, parametrization=p).metadata["psnr_db"] for p in (auto, disk))
    assert near > 60 > 30 > far


def test_save_and_load_keep_the_layout(tmp_path):
    mesh = meshes.torus_grid(16, 8)
    img = geoimg.mesh_to_image(mesh, 100, parametrization=_charts(mesh, charts=3))
    path = tmp_path / "charts.exr"
    geoimg.save_image(img, path)
    back = geoimg.load_image(path)
    assert back.domain == img.domain and back.domain.same_kind(img.domain)
    assert topology(back.to_mesh()).genus == 1


def test_segments_are_discs_on_a_torus_without_help():
    mesh = meshes.torus_grid(16, 8)
    tris, _ = mesh.triangulate()
    label, splits, opened = segment_charts(mesh.vertices, tris, 3)
    assert label.max() + 1 >= 3
    for k in range(label.max() + 1):
        t = topology(geoimg.Mesh(mesh.vertices, tris[label == k]))
        assert t.components == 1 and t.boundary_loops == 1 and t.genus == 0


def test_bad_arguments():
    mesh = meshes.torus_grid(12, 6)
    for bad in (0, -1, 1.5, True, 10 ** 6):
        with pytest.raises(ParametrizationError, match="charts"):
            chart_coords(mesh, charts=bad)
    with pytest.raises(ParametrizationError, match="balance"):
        chart_coords(mesh, balance="wobbly")
    with pytest.raises(ParametrizationError, match="one manifold piece"):
        _charts(meshes.three_pieces())


def test_layout_points_agree_with_the_domain():
    squares = ((0, 0, 4), (0, 6, 4), (6, 0, 2))
    d = ChartsDomain(squares=squares, gutter=2, segments=((0, 0, 16, 1), (1, 0, 16, 0), (2, 0, 8, -1)))
    uv = np.random.default_rng(1).random((7, 2))
    tile = np.array([0, 1, 2, 0, 1, 2, 1])
    np.testing.assert_array_equal(d.tile_points(tile, uv), tile_points(tile, uv, squares))
    assert d.extent == layout_extent(d.to_metadata()) == (1.0, 0.8)
    u, v = d.pixel_uv(d.grid_shape(d.round_resolution(30)))
    r0, c0, n = d._origins((len(v), len(u)))
    for k in range(3):
        np.testing.assert_allclose(u[c0[k]:c0[k] + n[k]][[0, -1]], d.tile_points([k, k], [[0, 0], [1, 1]])[:, 0])
        np.testing.assert_allclose(v[r0[k]:r0[k] + n[k]][[0, -1]], d.tile_points([k, k], [[0, 0], [1, 1]])[:, 1])


def test_squares_of_their_own_sizes_pack_apart():
    sides = [9, 1, 4, 4, 2, 7, 3, 3, 1]
    squares = pack_squares(sides, 2)
    assert [s for _, _, s in squares] == sides
    ChartsDomain(squares=tuple(squares), gutter=2,                 # refuses squares closer than the gutter
                 segments=tuple((k, 0, 4 * s, -1) for k, s in enumerate(sides)))
    across, down = layout_span(squares)
    assert max(across, down) ** 2 < 2.5 * sum((s + 2) ** 2 for s in sides)


TWO = ((0, 0, 4), (0, 6, 4))


@pytest.mark.parametrize("fields, message", [
    (dict(segments=()), "segments"),
    (dict(segments=((0, 0, 15, -1),)), "segments"),                         # not round the perimeter
    (dict(squares=TWO, segments=((0, 0, 16, 1), (1, 0, 8, 0), (1, 8, 8, -1))), "segments"),   # unequal twins
    (dict(segments=((1, 0, 16, -1),)), "segments"),                          # no such square
    (dict(squares=TWO, segments=((0, 0, 16, -1),)), "segments"),             # a square without segments
    (dict(gutter=0, segments=((0, 0, 16, -1),)), "gutter"),
    (dict(squares=((0, 0, 0),), segments=((0, 0, 0, -1),)), "squares"),
    (dict(squares=((0, 0, 4), (0, 5, 4)), segments=((0, 0, 16, -1), (1, 0, 16, -1))), "squares"),  # 1 apart
    (dict(squares=((0, 0, 4), (2, 2, 4)), segments=((0, 0, 16, -1), (1, 0, 16, -1))), "squares"),  # overlap
    (dict(squares=((-1, 0, 4),), segments=((0, 0, 16, -1),)), "squares"),
    (dict(squares=(("a", 0, 4),), segments=((0, 0, 16, -1),)), "squares"),
    (dict(segments=(("a", 0, 16, -1),)), "segments"),
])
def test_bad_layouts_are_refused(fields, message):
    with pytest.raises(ImageError, match=message):
        ChartsDomain(**{"squares": ((0, 0, 4),), **fields})


def test_a_border_glued_within_one_tile_is_allowed():
    assert ChartsDomain(squares=((0, 0, 4),), segments=((0, 0, 8, 1), (0, 8, 8, 0))).segments


def test_squares_of_two_sizes_glue_pixel_for_pixel():
    """A square of 4 quanta glued along its first row to the first row and last column of a square of 2:
    pixel j of the one is pixel 4 m - j round the other, whatever the corner between."""
    d = ChartsDomain(squares=((0, 0, 4), (0, 6, 2)), gutter=2,
                     segments=((0, 0, 4, 2), (0, 4, 12, -1), (1, 0, 4, 0), (1, 4, 4, -1)))
    shape = d.grid_shape(d.round_resolution(17))
    m = d._scale(shape)
    assert m >= 2
    reps, group = d.glue(shape)
    group = group.reshape(shape)
    r0, c0, n = d._origins(shape)
    assert n.tolist() == [4 * m + 1, 2 * m + 1]
    for j in range(4 * m + 1):
        t = 4 * m - j
        twin = (r0[1], c0[1] + t) if t <= 2 * m else (r0[1] + t - 2 * m, c0[1] + 2 * m)
        assert group[r0[0], c0[0] + j] == group[twin]
    assert len(np.unique(group)) == shape[0] * shape[1] - (4 * m + 1)


def test_bad_sizes_are_refused():
    d = ChartsDomain(squares=TWO, gutter=2, segments=((0, 0, 16, 1), (1, 0, 16, 0)))
    assert d.round_resolution(12) == 21 and d.grid_shape(21) == (9, 21)
    for bad in (12, 11, 1, True, 2.5):                       # 11: one pixel per quantum, too few
        with pytest.raises(ImageError, match="resolution"):
            d.grid_shape(bad)
    with pytest.raises(ImageError, match="multi-chart"):
        d.check_shape((9, 20))
    with pytest.raises(ImageError, match="multi-chart"):
        geoimg.GeometryImage(np.zeros((10, 21, 3)), domain=d)


def test_a_layout_that_would_not_weld_is_refused():
    """Two borders of one quantum side by side, glued crosswise to two on another tile (as trimesh's
    ADIS16480.STL's charts met): at one pixel per quantum three edges become one; at two, they weld."""
    rim = [(0, 2, 14, -1), (1, 2, 14, -1)]
    straight = [(0, 0, 1, 4), (0, 1, 1, 3), rim[0], (1, 0, 1, 1), (1, 1, 1, 0), rim[1]]
    crossed = [(0, 0, 1, 3), (0, 1, 1, 4), rim[0], (1, 0, 1, 0), (1, 1, 1, 1), rim[1]]
    assert [weld_defects(straight, [4, 4], m) for m in (1, 2)] == [0, 0]
    assert weld_defects(crossed, [4, 4], 1) > 0 and weld_defects(crossed, [4, 4], 2) == 0
    d = ChartsDomain(squares=TWO, segments=tuple(crossed))
    assert d.round_resolution(2) == 21                     # two pixels a quantum at least
    with pytest.raises(ImageError, match="multi-chart"):
        d.glue((5, 11))


@pytest.mark.slow
def test_points_of_an_image_lie_on_the_mesh():
    mesh = load_data("plate_holes.STL")
    img = geoimg.mesh_to_image(mesh, 129, parametrization=_charts(mesh, charts=4))
    px = np.asarray(img.pixels, np.float64)[img.valid]
    diag = np.linalg.norm(np.ptp(mesh.vertices, axis=0))
    assert np.percentile(point_mesh_distance(px, mesh), 99) < 0.01 * diag


def test_a_mesh_of_few_faces_is_not_split_into_single_triangles():
    """An L of four triangles asked for 8 charts: one chart per triangle left part of each square's
    triangle uncovered (14 % of the diagonal off); at most one chart per 8 faces maps it whole."""
    v = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 2, 0], [1, 1, 0], [0, 1, 0]])
    mesh = geoimg.Mesh(v, np.array([[5, 0, 1], [1, 2, 3], [1, 3, 4], [1, 4, 5]]))
    param = _charts(mesh, charts=8)
    assert param.info["charts"] == 1 and param.degenerate_faces == 0 and param.flipped_faces == 0
    img = geoimg.mesh_to_image(mesh, 129, parametrization=param)
    d = surface_distance(mesh, img.to_mesh(), 20000)
    assert d["hausdorff_rel"] < 0.01 and d["psnr_db"] > 60


@pytest.mark.slow
def test_the_starved_share_of_charts_is_of_the_image_they_share():
    # the squares differ in size: a triangle's share of the image is its area in the layout, not in its own
    # chart's unit square (the lion statue of odedstein/meshes: 56 % starved by the latter, 0.3 % by the former)
    mesh = load_data("plate_holes.STL")
    p = _charts(mesh, charts=6)
    assert len({side for _, _, side in p.domain_fields["squares"]}) > 1
    tris, _ = p.mesh.triangulate()
    want = starved_share(triangle_areas(p.mesh.vertices, tris), np.abs(planar_cross(p.coords, tris)))
    assert p.info["starved_share"] == pytest.approx(want, abs=1e-12)


@pytest.mark.slow
def test_a_narrow_surface_agrees_with_itself_across_glued_sides():
    # The surface at a chart's border sees copies of the twin's faces beyond it (ghosts). A face near the end of
    # a twin piece was copied too, and its copy spilled beside the next piece: on the plate at s = 1e-4 (the
    # mesh resampled as it is) a copy of its bottom face lay beside its top, two glued pairs 1.0 and 3.2 units
    # apart (0.3 % and 0.9 % of the diagonal) before the glue averaged them; 2.9e-4 units with the margin.
    # What is left depends on the charts' maps, not on ghosts: 0.65e-6 to 1.10e-6 of the diagonal on four
    # maps of the same charts (Sobolev steps; Gauss-Newton steps to 1e-2, 1e-3, 1e-4), so the bound sits
    # 10x above that and 300x below the ghosts' spread.
    mesh = load_data("plate_holes.STL")
    param = geoimg.parametrize(mesh, "charts")
    image = geoimg.fit_surface(mesh, param, geoimg.CoverageWeights(s=1e-4)).sample(129)
    diag = np.linalg.norm(np.ptp(mesh.vertices, axis=0))
    assert image.metadata.get("glue_spread", 0.0) < 1e-5 * diag
