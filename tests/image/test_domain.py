"""Domains: the grid, the glue map, mask symmetrization, averaging and welding, file fields."""
import numpy as np
import pytest

import geoimg
from geoimg import Domain, GeometryImage, ImageError, OctahedralDomain, PlanarDomain
from geoimg.mesh import topology
from geoimg.parametrization._octahedral import weld_index


def test_planar_domain_glues_nothing_and_keeps_the_aspect():
    d = PlanarDomain(extent=(1.0, 0.5), orientation=-1)
    assert d.grid_shape(9) == (5, 9) and d.glue((5, 9)) is None
    u, v = d.pixel_uv((5, 9))
    assert u[-1] == 1.0 and v[-1] == 0.5
    w = np.random.default_rng(0).random((5, 9))
    assert np.array_equal(d.symmetric_mask(w), w) and np.array_equal(d.average_glued(w), w)
    assert Domain.from_metadata("planar", d.to_metadata()) == d


def test_octahedral_glue_is_the_weld_index():
    d = OctahedralDomain()
    reps, group = d.glue((9, 9))
    weld = weld_index(9).ravel()
    # two pixels are in one group exactly when the weld index joins them
    assert np.array_equal(group[:, None] == group[None, :], weld[:, None] == weld[None, :])
    assert len(reps) == 8 ** 2 + 2
    w = np.zeros((9, 9))
    w[0, 2] = 0.7
    sym = d.symmetric_mask(w)
    assert sym[0, 6] == 0.7 and sym.sum() == pytest.approx(1.4)


def test_welding_gives_the_input_topology_and_no_cracks():
    n = 17
    q = geoimg.parametrization.grid_directions(n)
    img = GeometryImage((q * 2.0).astype(np.float32), domain="octahedral")
    quads = img.to_mesh()
    t = topology(quads)
    assert t.closed and t.genus == 0 and t.components == 1 and t.boundary_edges == 0
    plane = GeometryImage(np.dstack(list(np.meshgrid(np.arange(4.0), np.arange(3.0))) + [np.zeros((3, 4))]))
    assert topology(plane.to_mesh()).boundary_loops == 1


def test_domain_fields_travel_through_files(tmp_path):
    img = GeometryImage(np.zeros((3, 5, 3), np.float32), domain=PlanarDomain(extent=(1.0, 0.5), orientation=-1),
                        metadata={"s": 2.0})
    back = geoimg.load_image(img.save(tmp_path / "a.exr"))
    assert back.domain == img.domain and back.metadata == {"s": 2.0}
    assert back.to_mesh().faces[0].tolist() == img.to_mesh().faces[0].tolist()


def test_kind_names_read_their_fields_from_the_metadata():
    img = GeometryImage(
        np.zeros((3, 3, 3), np.float32), domain="planar", metadata={"orientation": -1, "extent": [1, 1]}
    )
    assert img.domain == PlanarDomain(orientation=-1) and "orientation" not in img.metadata


@pytest.mark.parametrize("make, message", [
    (lambda: PlanarDomain(extent=(1.0, 0.0)), "extent"),
    (lambda: PlanarDomain(extent=(1.0, np.inf)), "extent"),
    (lambda: PlanarDomain(extent="ab"), "extent"),
    (lambda: PlanarDomain(orientation=2), "orientation"),
    (lambda: OctahedralDomain(orientation=True), "orientation"),
    (lambda: Domain.named("torus"), "domain: expected one of"),
    (lambda: PlanarDomain().grid_shape(1), "resolution"),
    (lambda: OctahedralDomain().grid_shape(8), "odd side"),
    (lambda: GeometryImage(np.zeros((3, 3, 3)), domain=PlanarDomain(), metadata={"orientation": -1}), "contradicts"),
    (lambda: GeometryImage(np.zeros((3, 3, 3)), domain=3), "domain"),
])
def test_bad_domains_are_refused(make, message):
    with pytest.raises((ImageError, TypeError, ValueError), match=message):
        make()


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_averaging_glued_pixels_gives_the_whole_images_group_means_to_the_byte(dtype):
    """Only pixels in groups of two or more are averaged, over the same pixels in the same order as the means
    over every group of the image: the same bytes (a lone -0 becomes 0 as its sum did; NaN stays)."""
    from geoimg.parametrization._octahedral import group_means
    domain = OctahedralDomain()
    a = np.random.default_rng(5).normal(size=(33, 33, 3)).astype(dtype)
    a.flat[::7] = -0.0
    a.flat[::11] = np.nan
    group = domain.glue(a.shape[:2])[1]
    whole = group_means(a, group)[group].reshape(a.shape).astype(a.dtype)
    assert domain.average_glued(a).tobytes() == whole.tobytes()
