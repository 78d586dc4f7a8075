import numpy as np
import pytest

import geoimg
from geoimg import ParametrizationError, parametrize
from geoimg.parametrization._octahedral import weld_index
from geoimg.mesh import topology

from checks import check_sphere_map
import meshes
from helpers import load_data




@pytest.fixture(scope="module")
def spot_small():
    mesh = load_data("spot_low_resolution.obj")
    return mesh, parametrize(mesh, "sphere")


CLOSED = {"spot": lambda: load_data("spot.obj"), "sphere": lambda: load_data("sphere.obj"),
          "spot control mesh": lambda: load_data("spot_control_mesh.obj"), "bumpy": lambda: meshes.icosphere(3, 0.25),
          "chamfered cube": meshes.rhombicuboctahedron, "capped cylinder": meshes.capped_cylinder}


@pytest.mark.parametrize("name", CLOSED)
def test_sphere_map_folds_nothing_and_balances_area(name):
    check_sphere_map(CLOSED[name]())


def test_auto_picks_sphere_for_closed_genus_0(spot_small):
    mesh, p = spot_small
    assert parametrize(mesh).method == "sphere"
    assert p.domain == "octahedral" and p.coords.shape == (mesh.n_vertices, 3) and p.flipped_faces == 0


def test_octahedral_image_welds_into_a_closed_genus_0_quad_mesh(spot_small):
    mesh, p = spot_small
    for side, s in ((129, 1.0), (65, 0.5)):         # glued pixels are bit-identical, normals too (nothing averaged)
        img = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(s=s)).sample(side)
        w = weld_index(side).ravel()
        flat, nrm = img.pixels.reshape(-1, 3), img.normals.reshape(-1, 3)
        assert np.array_equal(flat, flat[w]) and np.array_equal(nrm, nrm[w]) and "glue_spread" not in img.metadata
    quads = img.to_mesh()
    topo = topology(quads)
    assert topo.closed and topo.genus == 0 and topo.components == 1
    assert quads.n_vertices == 64 ** 2 + 2 and quads.n_faces == 64 ** 2
    # consistently oriented outwards: positive enclosed volume close to the source mesh's
    def volume(m):
        t, _ = m.triangulate()
        v = m.vertices
        return np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum() / 6
    assert volume(quads) == pytest.approx(volume(mesh), rel=0.03)


def test_coarse_mesh_surface_stays_near_the_mesh():
    # 26 faces: each Gaussian spans a quarter of the sphere, so faces turned 90 degrees away carry weight;
    # their maps must stay bounded there (a central projection onto their planes put a pixel at y = -9.8)
    from geoimg.mesh import surface_distance
    mesh = meshes.rhombicuboctahedron()
    img = geoimg.fit_surface(mesh, parametrize(mesh, "sphere"), geoimg.GaussianWeights()).sample(65)
    half = np.abs(mesh.vertices).max()
    assert np.abs(img.pixels).max() < 1.5 * half
    assert surface_distance(mesh, img.to_mesh(), n=20000)["psnr_db"] > 20


def test_sphere_surface_truncation_derivatives_and_convergence(spot_small):
    mesh, p = spot_small
    surf = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights())
    uv = np.random.default_rng(3).uniform(0.02, 0.98, (200, 2))
    diag = mesh.bounding_box_diagonal()
    assert np.abs(surf.evaluate(uv) - surf.evaluate(uv, exact=True)).max() < 1e-9 * diag
    h = 1e-6
    pu, pv = surf.derivatives(uv)
    fu = (surf.evaluate(uv + [h, 0]) - surf.evaluate(uv - [h, 0])) / (2 * h)
    fv = (surf.evaluate(uv + [0, h]) - surf.evaluate(uv - [0, h])) / (2 * h)
    away = np.all(np.abs(np.abs(uv - 0.5)) > 0.01, axis=1) & (np.abs(np.abs(uv - 0.5).sum(1) - 0.5) > 0.01)
    scale = np.abs(pu).max()
    assert np.abs(pu - fu)[away].max() < 1e-5 * scale and np.abs(pv - fv)[away].max() < 1e-5 * scale
    # at the vertices' directions the surface approaches the vertices as s falls
    used = mesh.referenced_vertices()
    errs = []
    for s in (1.0, 0.5, 0.25):
        surf_s = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(s=s))
        errs.append(np.sqrt(np.mean((surf_s.evaluate_directions(p.coords[used])[0] - mesh.vertices[used]) ** 2)))
    assert errs[0] > errs[1] > errs[2] and errs[2] < 0.003 * diag


def test_positions_alone_are_the_same_points_as_with_derivatives(spot_small):
    mesh, p = spot_small
    surf = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights())
    q = np.random.default_rng(5).normal(size=(300, 3))
    for exact in (False, True):
        full = surf.evaluate_directions(q, exact=exact)
        alone = surf.evaluate_directions(q, exact=exact, derivatives=False)
        np.testing.assert_array_equal(alone[0], full[0])                 # the same sums, bit for bit
        np.testing.assert_array_equal(alone[5], full[5])
        assert not alone[1].any() and not alone[2].any() and full[1].any()
    plain, with_normals = surf.sample(33, normals=False), surf.sample(33)
    np.testing.assert_array_equal(plain.pixels, with_normals.pixels)


def test_octahedral_exr_round_trip(spot_small, tmp_path):
    mesh, p = spot_small
    img = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(s=2)).sample(17)
    back = geoimg.load_image(img.save(tmp_path / "spot.exr"))
    assert back.domain == img.domain and np.array_equal(back.pixels, img.pixels)
    assert back.to_mesh().n_faces == 256


def test_octahedral_errors(spot_small):
    mesh, p = spot_small
    surf = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(s=2))
    with pytest.raises(ValueError, match="odd side .* 18"):
        surf.sample(17 + 1)
    with pytest.raises(ValueError, match="only 'gaussian'"):
        geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(n=10))
    with pytest.raises(ValueError, match="must be square"):
        geoimg.GeometryImage(np.zeros((5, 7, 3), np.float32), domain="octahedral")
    with pytest.raises(ValueError, match="takes no mask"):
        geoimg.GeometryImage(np.zeros((5, 5, 3), np.float32), np.eye(5, dtype=bool), domain="octahedral")
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        surf.evaluate([[1.5, 0.2]])
    with pytest.raises(ParametrizationError, match="genus 1"):
        parametrize(load_data("torus.obj"), "sphere")


def test_balance_kernels_match_the_numpy_reference(spot_small):
    from geoimg.parametrization._balance_kernels import balance_energy, balance_gradient
    from reference import AreaBalanceNumpy
    mesh, p = spot_small
    tris, _ = mesh.triangulate()
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3)
    e0, st0 = ref.energy(p.coords)
    e1, st1 = balance_energy(p.coords, tris.astype(np.int64), ref.a, ref.cot, 0.3)
    assert e1 == pytest.approx(e0, rel=1e-12)
    g0, g1 = ref.gradient(st0), balance_gradient(p.coords, tris.astype(np.int64), ref.a, ref.cot, 0.3, st1)
    assert np.abs(g1 - g0).max() <= 1e-12 * np.abs(g0).max()
    flipped = p.coords.copy()
    flipped[tris[0, 0]] *= -1                                   # a triangle turned over: no energy
    assert balance_energy(flipped, tris.astype(np.int64), ref.a, ref.cot, 0.3)[0] == np.inf


def test_simplification_undoes_exactly():
    from geoimg.parametrization._progressive import simplify
    mesh = load_data("spot_low_resolution.obj")
    tris, _ = mesh.triangulate()
    alive, coarse, c = simplify(mesh.vertices, tris, 4)
    live = coarse[coarse[:, 0] >= 0]
    assert alive.sum() == 4 and len(live) == 4 and len(c.v) == mesh.n_vertices - 4
    assert set(c.v) == set(np.flatnonzero(~alive)) and len(set(c.v)) == len(c.v)
    cur = coarse.copy()
    for k in reversed(range(len(c.v))):
        v, u = c.v[k], c.u[k]
        changed = c.changed[c.changed_ptr[k]:c.changed_ptr[k + 1]]
        assert (cur[changed] == u).any(axis=1).all() and (cur[c.removed[k]] == -1).all()
        for f in changed:
            cur[f][cur[f] == u] = v
        cur[c.removed[k]] = c.rows[k]
        assert ((cur[c.removed[k]] == u).any(axis=1) & (cur[c.removed[k]] == v).any(axis=1)).all()
    assert np.array_equal(cur, tris)


def test_simplification_keeps_a_closed_manifold_and_collapses_shortest_edges_first():
    """Every intermediate mesh is closed with Euler characteristic 2 and no vertex above the valence cap
    (but those that started above it); the edges go shortest first, but where a collapse was refused."""
    from geoimg.parametrization._progressive import simplify
    mesh = load_data("spot_low_resolution.obj")
    tris, _ = mesh.triangulate()
    x = mesh.vertices
    alive, coarse, c = simplify(x, tris, 50, max_valence=9)
    assert alive.sum() == 50
    start_degree = np.bincount(tris.ravel(), minlength=len(x))          # a closed mesh: faces = neighbours
    cur = coarse.copy()
    for k in reversed(range(len(c.v))):
        live = cur[cur[:, 0] >= 0]
        edges = np.unique(np.sort(np.concatenate([live[:, [0, 1]], live[:, [1, 2]], live[:, [2, 0]]]), axis=1),
                          axis=0)
        verts = np.unique(live)
        assert len(verts) - len(edges) + len(live) == 2
        degree = np.bincount(edges.ravel(), minlength=len(x))
        assert (degree <= np.maximum(9, start_degree)).all()
        for f in c.changed[c.changed_ptr[k]:c.changed_ptr[k + 1]]:
            cur[f][cur[f] == c.u[k]] = c.v[k]
        cur[c.removed[k]] = c.rows[k]
    lengths = np.linalg.norm(x[c.v] - x[c.u], axis=1)
    assert np.median(np.diff(lengths) >= 0) == 1       # mostly in order (refusals and new edges aside)


@pytest.mark.slow
def test_coarse_to_fine_placement_matches_the_numpy_reference():
    """Every returning vertex of a coarse-to-fine map lands bit for bit where the numpy reference puts it,
    from a map that is only put back (never relaxed) as from one relaxed on the way; both sides see the
    same map before each vertex."""
    from geoimg.parametrization import _progressive as P
    from reference import place_numpy
    mesh = load_data("spot_low_resolution.obj")
    tris, _ = mesh.triangulate()
    alive, coarse, c = P.simplify(mesh.vertices, tris, 4)
    cos, sin = np.cos(P._DIRECTIONS), np.sin(P._DIRECTIONS)
    relaxed = parametrize(mesh, "sphere").coords                   # a good map: candidates compete closely
    for start in (P._tetrahedron(mesh.n_vertices, alive, coarse[coarse[:, 0] >= 0]), relaxed):
        s, cur, live = start.copy(), coarse.copy(), alive.copy()
        placed = 0
        for i in range(len(c.v)):
            k = len(c.v) - 1 - i                                    # the last collapse is undone first
            before = s.copy()
            ok = P._grow(s, cur, live, c, i, i + 1, cos, sin, P._HALVES) == 0
            changed = c.changed[c.changed_ptr[k]:c.changed_ptr[k + 1]]
            ref = before.copy()
            assert place_numpy(ref, c.v[k], c.u[k], cur[np.concatenate([c.removed[k], changed])], len(changed)) == ok
            assert np.array_equal(ref, s), k
            placed += ok
        assert placed > 0.9 * len(c.v)


def test_balance_gradient_matches_finite_differences(spot_small):
    from geoimg.parametrization._balance_kernels import balance_energy, balance_gradient
    from geoimg.parametrization._laplacian import corner_cotangents
    mesh, p = spot_small
    tris, _ = mesh.triangulate()
    tris = tris.astype(np.int64)
    x = mesh.vertices
    a3 = 0.5 * np.linalg.norm(np.cross(x[tris[:, 1]] - x[tris[:, 0]], x[tris[:, 2]] - x[tris[:, 0]]), axis=1)
    a, cot = a3 / a3.sum(), corner_cotangents(x, tris)
    s = p.coords
    e, state = balance_energy(s, tris, a, cot, 0.3)
    g = balance_gradient(s, tris, a, cot, 0.3, state)
    rng = np.random.default_rng(2)
    for v in rng.choice(mesh.n_vertices, 5, replace=False):
        for c in range(3):
            h = 1e-6
            sp, sm = s.copy(), s.copy()
            sp[v, c] += h
            sm[v, c] -= h
            fd = (balance_energy(sp, tris, a, cot, 0.3)[0] - balance_energy(sm, tris, a, cot, 0.3)[0]) / (2 * h)
            assert abs(g[v, c] - fd) <= 1e-6 * np.abs(g).max(), (v, c, g[v, c], fd)


def test_cell_lists_hold_every_face_within_reach_of_their_points():
    """The 3-D cells bin each face by where its ball reaches: a point's cell lists every face within that
    face's radius of it (the truncated sums miss nothing), and fewer than the balls' bounding boxes would."""
    from geoimg.surface._cells import build_cells_3d
    rng = np.random.default_rng(7)
    centres = rng.normal(size=(3000, 3))
    centres /= np.linalg.norm(centres, axis=1, keepdims=True)
    radius = rng.uniform(0.02, 0.3, 3000)
    h, n, ptr, faces = build_cells_3d(centres, radius)
    q = rng.normal(size=(2000, 3))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    ix = np.clip(np.floor((q + 1.0) / h).astype(int), 0, n - 1)
    cell = (ix[:, 2] * n + ix[:, 1]) * n + ix[:, 0]
    near = np.linalg.norm(q[:, None] - centres[None], axis=2) <= radius[None]
    for k in range(len(q)):
        assert set(np.flatnonzero(near[k])) <= set(faces[ptr[cell[k]]:ptr[cell[k] + 1]].tolist())
    boxes = np.prod(np.clip(np.floor((centres + radius[:, None] + 1) / h), 0, n - 1)
                    - np.clip(np.floor((centres - radius[:, None] + 1) / h), 0, n - 1) + 1, axis=1).sum()
    assert len(faces) < boxes



def test_vectorized_exp_matches_libm_to_a_few_ulps():
    import math
    from geoimg.surface._gaussian_fastexp import exp_inplace

    def exp_array(a):
        return exp_inplace(np.array(a, np.float64))
    x = np.concatenate([-np.random.default_rng(2).uniform(0, 708, 20001), [0.0, -1e-300, -708.0, -0.5 * math.log(2)]])
    ref = np.array([math.exp(v) for v in x])
    assert (np.abs(exp_array(x) - ref) <= 4 * np.spacing(ref)).all()
    assert exp_array(np.array([0.0]))[0] == 1.0
    assert (exp_array(np.array([-708.01, -745.0, -1e6, -np.inf])) == 0.0).all()      # below -708: 0


@pytest.mark.parametrize("side, tile", [(37, (16, 8)), (33, (8, 8)), (65, (16, 4)), (33, (32, 16))])
def test_tiled_sampling_equals_point_evaluation(spot_small, side, tile):
    """The image sampler (tiles of pixels, plain vectorized exponentials) gives the point evaluator's
    surface and derivatives, whatever the tiling; its candidate lists miss no face within reach."""
    from geoimg.surface import _gaussian_sphere_kernels as sk
    from geoimg.surface._cells import tangent_frames
    mesh, p = spot_small
    surf = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights())
    q = surf.domain.directions(side).reshape(-1, 3)
    t1, t2 = tangent_frames(q)
    P, P1, P2, st = sk.sample_sphere_grid(q, t1, t2, surf._faces, surf._cells, log_g_ref=surf.log_g_ref, tile=tile)
    R, R1, R2, _, _, _ = surf.evaluate_directions(q)
    scale = mesh.bounding_box_diagonal()
    assert (st == sk.TRUNCATED).all()
    assert np.abs(P - R).max() < 1e-12 * scale
    assert np.abs(P1 - R1).max() < 1e-9 * np.abs(R1).max() and np.abs(P2 - R2).max() < 1e-9 * np.abs(R2).max()
    alone = sk.sample_sphere_grid(q, None, None, surf._faces, surf._cells, log_g_ref=surf.log_g_ref, tile=tile,
                                  derivatives=False)
    np.testing.assert_array_equal(alone[0], P)
    centre, _, radius = surf._faces[:3]
    h, n, ptr, cells = surf._cells
    seen = np.full(len(centre), -1, np.int64)
    for k, first in enumerate((0, side * (side // 2) + side // 2, side * side - 1)):
        idx = np.unique(np.clip(first + np.add.outer(np.arange(3) * side, np.arange(3)).ravel(), 0, side * side - 1))
        cand = sk._tile_candidates(q, idx, len(idx), centre, radius, h, n, ptr, cells, seen, k)
        near = np.linalg.norm(q[idx][:, None] - centre[None], axis=2) <= radius[None]
        assert set(np.flatnonzero(near.any(axis=0))) <= set(cand.tolist())
        assert np.all(np.diff(cand) > 0)                          # in index order, once each


def test_tiled_sampling_recomputes_what_plain_exponentials_cannot_certify(spot_small):
    """At s = 0.005 a pixel between face centres gets weights below exp(-708) from every face: its plain
    sum underflows, and such pixels are recomputed over all faces in the log domain (and say so)."""
    from geoimg.surface import _gaussian_sphere_kernels as sk
    mesh, p = spot_small
    surf = geoimg.fit_surface(mesh, p, geoimg.GaussianWeights(s=0.005))
    img = surf.sample(33, normals=False)
    assert img.metadata["exact_pixels"] > 0 and np.isfinite(img.pixels).all()
    q = surf.domain.directions(33).reshape(-1, 3)
    exact = surf.evaluate_directions(q, exact=True, derivatives=False)[0]
    assert np.abs(img.pixels.reshape(-1, 3) - exact).max() < 1e-5 * mesh.bounding_box_diagonal()
    q_all = sk.sample_sphere_grid(q, None, None, surf._faces, surf._cells, log_g_ref=surf.log_g_ref,
                                  derivatives=False)
    assert (q_all[3] == sk.EXACT).sum() == img.metadata["exact_pixels"] < 33 * 33


def test_tangent_frames_are_the_cross_products_bit_for_bit():
    """The numba frames equal numpy's cross products of the axis of the smallest component (first on ties)."""
    from geoimg.surface._cells import tangent_frames
    rng = np.random.default_rng(4)
    q = rng.normal(size=(20000, 3))
    q = np.vstack([q, np.eye(3), -np.eye(3), [[0.6, 0.8, 0.0], [0.0, 0.6, 0.8], [1.0, 1.0, 1.0], [0.5, 0.5, -0.7]]])
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    helper = np.eye(3)[np.argmin(np.abs(q), axis=1)]
    t1 = np.cross(helper, q)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    a, b = tangent_frames(q)
    np.testing.assert_array_equal(a, t1)
    np.testing.assert_array_equal(b, np.cross(q, t1))


def test_simplification_refuses_a_vertex_beyond_its_row():
    """The collapses keep each vertex's neighbours in a fixed row sized for a closed manifold; a mesh that is
    not one (a vertex in more neighbours than faces) is refused instead of written past it."""
    from geoimg.parametrization._progressive import simplify
    tris = np.array([[0, 1, 2], [0, 3, 4], [0, 5, 6]])           # three separate triangles at vertex 0
    with pytest.raises(ValueError, match="more neighbours or faces than a closed manifold"):
        simplify(np.random.default_rng(0).normal(size=(7, 3)), tris, 4, max_valence=2)


def test_a_returning_vertex_whose_neighbours_surround_the_centre_is_still_placed():
    # v's neighbours (but u) are a regular tetrahedron's corners: their mean, one of the candidates' ends,
    # is the sphere's centre, which cannot be projected onto it (it divided by zero once)
    from geoimg.parametrization import _progressive as P
    s = np.zeros((6, 3))
    s[:4] = np.array([[-1, 1, 1], [-1, -1, -1], [1, 1, -1], [1, -1, 1]]) / np.sqrt(3)
    s[4] = np.array([0.05, -0.05, 1.0]) / np.linalg.norm([0.05, -0.05, 1.0])      # u
    faces = np.array([[5, 0, 4], [5, 4, 1], [5, 1, 2], [5, 2, 3], [5, 3, 0]])     # two on uv, three changed
    P._place(s, 5, 4, faces, 3, np.cos(P._DIRECTIONS), np.sin(P._DIRECTIONS), P._HALVES)
    assert np.isfinite(s[5]).all() and abs(np.linalg.norm(s[5]) - 1) < 1e-12


def _conformal_plane_that_folds(monkeypatch):
    """Make the conformal map fold (one vertex sent across the plane), as on the bust of Nefertiti's coarse copy;
    the mean-value map, taken instead, still folds nothing."""
    from geoimg.parametrization import _sphere as S
    conformal = S._conformal_plane

    def folded(x, tris, lap, f0, keep):
        z = conformal(x, tris, lap, f0, keep).copy()
        far = np.argmax(np.linalg.norm(z, axis=1))
        z[tris[len(tris) // 2, 0]] = -2.0 * z[far]
        return z
    monkeypatch.setattr(S, "_conformal_plane", folded)
    return S


def test_a_shape_whose_conformal_map_folds_is_mapped_coarse_to_fine_though_the_mean_value_map_does_not(monkeypatch):
    # the mean-value (Tutte) map squeezes what sticks out exponentially and the balancing can stall there
    # (Nefertiti's 8,000-triangle coarse copy: log area ratios of RMS 2.7 balanced from it, 0.28 coarse to fine)
    S = _conformal_plane_that_folds(monkeypatch)
    mesh = load_data("spot_low_resolution.obj")
    tris, _ = mesh.triangulate(quads="shorter")
    used = np.ones(mesh.n_vertices, bool)
    lap = S.laplacian(S.cotangent_weights(mesh.vertices, tris))
    start, name, _ = S._direct_start(mesh.vertices, tris, used, S.vertex_areas(mesh.vertices, tris), lap)
    assert name == "mean-value" and S._fold_count(start, tris) == 0
    s, info = S.sphere_coords(mesh)
    assert info["stages"] == ["mean-value", "progressive"] and info["start"] == "progressive"
    assert info["misplaced"] == 0 and info["flipped_triangles"] == 0 and (S.chord_orientation(s, tris) > 0).all()


def test_a_decimated_copy_whose_conformal_map_folds_is_mapped_coarse_to_fine(monkeypatch):
    S = _conformal_plane_that_folds(monkeypatch)
    progressive = S.progressive_sphere
    calls = []

    def spy(*args, **kwargs):
        calls.append(len(args[1]))
        return progressive(*args, **kwargs)
    monkeypatch.setattr(S, "progressive_sphere", spy)
    mesh = load_data("spot_low_resolution.obj")
    tris, _ = mesh.triangulate(quads="shorter")
    s = S._decimated_map(0.3)(mesh.vertices, tris)
    assert calls == [len(tris)] and s is not None and (S.chord_orientation(s, tris) > 0).all()


def test_a_conformal_map_with_a_few_folds_is_opened_and_balanced_by_gauss_newton_steps(monkeypatch):
    from geoimg.parametrization import _sphere
    control = load_data("spot_control_mesh.obj")               # its conformal map folds a few triangles
    mesh = geoimg.Mesh(control.vertices, control.triangulate()[0])
    # 360 triangles: under CONFORMAL_OPENED_FROM, coarse to fine as before (then Gauss-Newton steps)
    _, small = _sphere.sphere_coords(mesh)
    assert small["stages"] == ["mean-value", "progressive"] and small["gauss_newton"]
    with monkeypatch.context() as m:                          # opened where the mesh is large enough
        m.setattr(_sphere, "CONFORMAL_OPENED_FROM", 100)
        s, info = _sphere.sphere_coords(mesh)
        assert info["stages"] == ["conformal"] and info["gauss_newton"] and info["flipped_triangles"] == 0
        assert info["area_log_rms"] < 0.6                     # 0.48 when measured
        assert np.allclose(np.linalg.norm(s, axis=1), 1.0)
        m.setattr(_sphere, "CONFORMAL_FOLDS_OPENED", 0)       # none opened: the mean-value map, coarse to fine
        assert _sphere.sphere_coords(mesh)[1]["stages"] == ["mean-value", "progressive"]
    _, asked = _sphere.sphere_coords(mesh, steps=50)           # steps asked: the Sobolev steps, folds not opened
    assert not asked["gauss_newton"] and asked["stages"] == ["mean-value", "progressive"]
    _, multilevel = _sphere.sphere_coords(load_data("fish.obj"))   # from a coarse copy: the Sobolev steps
    assert multilevel["start"] == "multilevel" and not multilevel["gauss_newton"]


def test_where_the_gauss_newton_steps_stall_the_map_is_the_sobolev_ways(monkeypatch, spot_small):
    from geoimg.parametrization import _sphere
    mesh, p = spot_small
    assert p.info["gauss_newton"]
    with monkeypatch.context() as m:
        m.setattr(_sphere, "newton_balance", lambda s, *a, **k: (np.array(s), 0, (np.inf, np.inf), True))
        stalled, info = _sphere.sphere_coords(mesh)
        m.setattr(_sphere, "NEWTON_VERTICES", -1)
        sobolev, _ = _sphere.sphere_coords(mesh)
    assert not info["gauss_newton"] and np.array_equal(stalled, sobolev)
    assert not np.array_equal(stalled, _sphere.sphere_coords(mesh)[0])          # the steps' own map differs
