"""The area-balancing descent shared by the sphere and the plane: its kernels against the numpy twin and finite
differences on the plane, the scaled step's scale, and the sliding boundary of a disk map."""
import numpy as np
import pytest

import geoimg
from geoimg.parametrization._balance import SCALE_SMOOTHING, neighbour_mean, squeeze_scale
from geoimg.parametrization._laplacian import vertex_shares
from geoimg.parametrization._balance_kernels import balance_energy, balance_gradient
from geoimg.parametrization._disk import PLANAR_SWEEP_ROUNDS

import meshes
from helpers import load_data
from reference import AreaBalanceNumpy


@pytest.fixture(scope="module")
def finger_map():
    """The synthetic finger (a disk) and its plain mean-value map onto the square, as points (u, v, 0)."""
    mesh = meshes.finger(segments=12, rows=12)
    p = geoimg.parametrize(mesh, "disk", balance="none")
    tris, _ = mesh.triangulate()
    return mesh, np.ascontiguousarray(tris, np.int64), np.column_stack([p.coords, np.zeros(mesh.n_vertices)])


def test_planar_kernels_match_the_numpy_reference(finger_map):
    mesh, tris, s = finger_map
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3, planar=True)
    e0, st0 = ref.energy(s)
    e1, st1 = balance_energy(s, tris, ref.a, ref.cot, 0.3, True)
    assert np.isfinite(e0) and e1 == pytest.approx(e0, rel=1e-12)
    g0, g1 = ref.gradient(st0), balance_gradient(s, tris, ref.a, ref.cot, 0.3, st1)
    assert np.abs(g1 - g0).max() <= 1e-12 * np.abs(g0).max() and np.all(g1[:, 2] == 0.0)
    # the same points read as chords of the sphere give another energy: the flag is what decides
    assert balance_energy(s + [0, 0, 1], tris, ref.a, ref.cot, 0.3, True)[0] == pytest.approx(e1, rel=1e-12)
    mirrored = s * [1, -1, 0]                                    # every triangle turned over: no energy
    assert balance_energy(mirrored, tris, ref.a, ref.cot, 0.3, True)[0] == np.inf


def test_planar_gradient_matches_finite_differences(finger_map):
    mesh, tris, s = finger_map
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3, planar=True)
    e, state = balance_energy(s, tris, ref.a, ref.cot, 0.3, True)
    g = balance_gradient(s, tris, ref.a, ref.cot, 0.3, state)
    rng = np.random.default_rng(5)
    for v in rng.choice(mesh.n_vertices, 6, replace=False):
        for c in range(2):
            h = 1e-7 * max(1e-3, np.abs(s[tris[np.any(tris == v, axis=1)]][..., :2] - s[v, :2]).max())
            sp, sm = s.copy(), s.copy()
            sp[v, c] += h
            sm[v, c] -= h
            fd = (balance_energy(sp, tris, ref.a, ref.cot, 0.3, True)[0]
                  - balance_energy(sm, tris, ref.a, ref.cot, 0.3, True)[0]) / (2 * h)
            assert abs(g[v, c] - fd) <= 1e-5 * np.abs(g).max(), (v, c, g[v, c], fd)


def test_the_balancing_step_slows_only_squeezed_parts_by_their_linear_scale():
    # the scale behind every other balancing step: sqrt(share of the sphere / share of the mesh), at most 1
    mesh = meshes.icosphere(3)
    tris = np.asarray(mesh.faces, np.int64)
    p = mesh.vertices[tris]
    a = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    a /= a.sum()
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    used = np.ones(mesh.n_vertices, bool)
    smooth = neighbour_mean(edges, mesh.n_vertices)
    share = vertex_shares(a, tris, mesh.n_vertices)
    assert np.allclose(squeeze_scale(a, share, tris, used, smooth), 1.0)
    # a cap squeezed to 1e-4 of its share, the rest stretched: sqrt(1e-4) deep inside the cap, 1 outside
    centre = mesh.vertices[tris].mean(axis=1)
    squeezed = centre[:, 2] > 0.5
    area = a * np.where(squeezed, 1e-4, 1.0)
    area /= area.sum()
    sigma = squeeze_scale(area, share, tris, used, smooth).ravel()
    hops = np.full(mesh.n_vertices, np.inf)          # edge hops from the cap's rim
    rim = np.unique(tris[squeezed][np.isin(tris[squeezed], tris[~squeezed])])
    hops[rim] = 0
    for k in range(1, 2 * SCALE_SMOOTHING + 2):
        ring = np.unique(edges[np.isin(edges[:, 0], np.flatnonzero(hops == k - 1)), 1])
        hops[ring[np.isinf(hops[ring])]] = k
    inside = np.isin(np.arange(mesh.n_vertices), tris[squeezed]) & (hops > SCALE_SMOOTHING)
    outside = ~np.isin(np.arange(mesh.n_vertices), tris[squeezed]) & (hops > SCALE_SMOOTHING)
    assert inside.any() and outside.any()
    assert np.allclose(sigma[inside], 1e-2 * np.sqrt(1.0 / (1 - (a[squeezed].sum() * (1 - 1e-4)))), rtol=1e-9)
    assert np.all(sigma[outside] == 1.0) and np.all(sigma <= 1.0)


def test_area_balancing_of_a_disk_slides_its_boundary_along_the_sides_and_folds_nothing():
    from geoimg.mesh import boundary_loops
    m = meshes.finger()
    plain = geoimg.parametrize(m, "disk", balance="none")
    p = geoimg.parametrize(m, "disk", balance="area")
    assert p.info["balance"] == "area" and p.info["balance_steps"] > 0 and p.info["slim_steps"] == 0
    assert p.flipped_faces == 0 and p.degenerate_faces == 0
    assert p.info["area_log_rms"] < plain.info["area_log_rms"] / 5       # 9.8 -> 0.9 when measured
    loop = boundary_loops(m)[0]
    corners = p.info["corners"]
    np.testing.assert_array_equal(p.coords[corners], plain.coords[corners])   # the corners stay, exactly
    b, b0 = p.coords[loop], plain.coords[loop]
    on_side = np.isin(b0, [0.0, 1.0])                       # the coordinate that puts a vertex on its side
    np.testing.assert_array_equal(b[on_side], b0[on_side])  # ... is kept exactly: it slid along the side
    assert np.all((b >= 0) & (b <= 1))
    assert np.abs(b - b0).max() > 1e-3                      # and the boundary did slide
    inside = np.setdiff1d(np.arange(m.n_vertices), loop)
    assert np.abs(p.coords[inside] - plain.coords[inside]).max() > 1e-3


def test_area_balancing_holds_a_kept_outline():
    from geoimg.mesh import boundary_loops
    m = meshes.cap(90.0, rings=8, segments=16)               # a hemisphere: its rim is a flat circle
    loop = boundary_loops(m)[0]
    plain = geoimg.parametrize(m, "disk", boundary="keep", balance="none")
    p = geoimg.parametrize(m, "disk", boundary="keep", balance="area")
    assert p.flipped_faces == 0 and p.info["balance_steps"] > 0
    np.testing.assert_array_equal(p.coords[loop], plain.coords[loop])      # the outline is held exactly
    assert p.info["area_log_rms"] < plain.info["area_log_rms"]


def test_the_default_disk_balance_is_the_area_balancing_everywhere():
    import inspect
    from geoimg.batch import BatchOptions
    from geoimg.cli import build_parser
    assert inspect.signature(geoimg.parametrize).parameters["balance"].default == "area"
    assert geoimg.ConversionOptions().balance == "area"
    assert BatchOptions().balance == "area"
    assert build_parser().parse_args(["image", "m.obj", "-o", "m.exr"]).balance == "area"
    p = geoimg.parametrize(meshes.finger(rows=8), "disk")
    assert p.info["balance"] == "area" and p.info["balance_steps"] > 0


def _with_a_zero_area_pair(mesh):
    """The mesh with edge (a, b) of its first face split at a copy of ``a``: two faces of exactly no area."""
    v, f = mesh.vertices, np.asarray(mesh.faces)
    a, b, c = f[0]
    k = len(v)
    other = next(i for i, t in enumerate(f) if a in t and b in t and i != 0)
    d = next(x for x in f[other] if x not in (a, b))
    faces = [t for i, t in enumerate(f.tolist()) if i not in (0, other)]
    return geoimg.Mesh(np.vstack([v, v[a]]), faces + [[a, k, c], [k, b, c], [b, k, d], [k, a, d]])


def test_faces_of_no_area_carry_no_energy_and_do_not_stop_the_balancing():
    from geoimg.parametrization._sphere import sphere_coords
    mesh = _with_a_zero_area_pair(meshes.icosphere(3, 0.25))
    tris = np.asarray(mesh.faces, np.int64)
    s, info = sphere_coords(mesh)
    # before, a face of no area made the energy infinite everywhere: 0 steps, the conformal map kept
    assert info["balance_steps"] > 0 and info["flipped_triangles"] == 0
    assert info["area_log_rms"] < info["start_area_log_rms"] / 3
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3)
    assert np.sum(ref.a == 0) == 2
    e0, st0 = ref.energy(s)
    e1, st1 = balance_energy(s, tris, ref.a, ref.cot, 0.3)
    assert np.isfinite(e1) and e1 == pytest.approx(e0, rel=1e-12)
    g0, g1 = ref.gradient(st0), balance_gradient(s, tris, ref.a, ref.cot, 0.3, st1)
    assert np.all(np.isfinite(g1)) and np.abs(g1 - g0).max() <= 1e-12 * np.abs(g0).max()


def test_the_cut_open_square_is_balanced_with_its_boundary_held():
    from geoimg.mesh import boundary_loops
    from geoimg.parametrization import cut_coords
    torus = meshes.torus_grid(24, 12, 1.0, 0.3)
    maps = {b: cut_coords(torus, balance=b) for b in ("none", "slim", "area")}
    disk, plain, _, layout, info = maps["none"]
    on_rim = np.zeros(disk.n_vertices, bool)
    on_rim[boundary_loops(disk)[0]] = True
    for b, (d, coords, _, lay, inf) in maps.items():
        assert inf["balance"] == b and lay == layout and d.n_vertices == disk.n_vertices
        np.testing.assert_array_equal(coords[on_rim], plain[on_rim])      # twins stay twins
        e1, e2 = coords[d.faces[:, 1]] - coords[d.faces[:, 0]], coords[d.faces[:, 2]] - coords[d.faces[:, 0]]
        assert np.all(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0)       # folds nothing
    assert maps["none"][4]["balance_steps"] == 0 and maps["area"][4]["balance_steps"] > 0
    assert np.abs(maps["area"][1] - plain).max() > 1e-3
    with pytest.raises(geoimg.ParametrizationError, match="balance: expected one of"):
        cut_coords(torus, balance="stretch")
    assert geoimg.parametrize(torus).info["balance"] == "area"


def test_a_small_sphere_map_balances_until_it_has_converged(monkeypatch):
    from geoimg.parametrization import _sphere
    from helpers import load_data
    control = load_data("spot_control_mesh.obj")               # 180 quads, fanned: 360 triangles
    mesh = geoimg.Mesh(control.vertices, control.triangulate()[0])
    # its conformal map folds; from the mean-value map (what was taken before coarse to fine) the Sobolev
    # balancing needs more than 200 steps
    with monkeypatch.context() as m:
        m.setattr(_sphere, "_wants_coarse_to_fine", lambda start, folds: folds > 0)
        m.setattr(_sphere, "NEWTON_VERTICES", -1)               # the Sobolev steps, not Gauss-Newton steps
        _, capped = _sphere.sphere_coords(mesh, steps=200)
        s, info = _sphere.sphere_coords(mesh)                  # the default lets a small mesh converge
    assert info["stages"] == capped["stages"] == ["mean-value"]
    assert 200 < info["balance_steps"] < 2000 and info["flipped_triangles"] == 0
    assert info["balance_energy"][1] < capped["balance_energy"][1]
    assert info["area_log_rms"] < 1.0 < capped["area_log_rms"]  # 0.43 against 2.5 when measured
    # mapped coarse to fine (the default where the conformal map folds), 200 steps are enough
    _, coarse_to_fine = _sphere.sphere_coords(mesh, steps=200)
    assert coarse_to_fine["stages"] == ["mean-value", "progressive"] and coarse_to_fine["area_log_rms"] < 1.0
    with pytest.raises(geoimg.InputError, match="steps"):
        _sphere.sphere_coords(mesh, steps=-1)


def test_the_step_kernels_match_numpy():
    from geoimg.parametrization._balance_kernels import project_moves, step_to
    rng = np.random.default_rng(3)
    s = rng.normal(size=(50, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    v = rng.normal(size=(50, 3))
    moves = rng.random(50) > 0.2
    along = np.zeros((50, 3))
    along[:10, 0] = 1.0
    along[10:20, 1] = -1.0
    on_sphere = v.copy()
    project_moves(on_sphere, s, False, moves, along)              # along is for the plane only
    want = v - np.einsum("ij,ij->i", v, s)[:, None] * s
    want[~moves] = 0.0
    np.testing.assert_allclose(on_sphere, want, rtol=0, atol=1e-15)
    on_plane = v.copy()
    project_moves(on_plane, s, True, moves, along)
    want = v * [1.0, 1.0, 0.0]
    want[:10, 1] = 0.0
    want[10:20, 0] = 0.0
    want[~moves] = 0.0
    np.testing.assert_array_equal(on_plane, want)
    out = np.empty_like(s)
    step_to(s, v, 0.3, False, out)
    np.testing.assert_allclose(out, (s + 0.3 * v) / np.linalg.norm(s + 0.3 * v, axis=1, keepdims=True), atol=1e-15)
    step_to(s, v, 0.3, True, out)
    np.testing.assert_array_equal(out, s + 0.3 * v)


def test_disk_and_cut_maps_report_their_balancing_as_it_goes():
    from geoimg.parametrization._disk import NEWTON_FIRST_STEPS, START_WEIGHTS
    for mesh, method in ((meshes.finger(rows=10), "disk"), (meshes.torus_grid(24, 12, 1.0, 0.3), "cut")):
        heard: list = []
        p = geoimg.parametrize(mesh, method, progress=heard.append)
        assert p.info["balance_steps"] > 0 and heard and p.info["gauss_newton"]
        assert "by Gauss-Newton steps" in p.info["stages"][0]
        counted = {}
        for start in START_WEIGHTS:                  # each start is relaxed, and heard from, in turn
            mine = [m[len(start) + 8:] for m in heard if m.startswith(f"{start} start: ")]
            assert mine and all(m.startswith("Gauss-Newton step ") for m in mine)    # no sweeps
            numbers = [int(m.split()[2].rstrip(":")) for m in mine]
            runs = np.split(numbers, np.flatnonzero(np.diff(numbers) != 1) + 1)     # each relaxing counts from 0
            assert all(r[0] == 0 for r in runs) and 0 < len(runs[0]) <= NEWTON_FIRST_STEPS
            counted[start] = len(mine)
        assert sum(m.startswith(f"{s} start: ") for s in START_WEIGHTS for m in heard) == len(heard)
        assert counted[p.info["start"]] == p.info["balance_steps"]


@pytest.mark.slow
def test_where_gauss_newton_stalls_the_sobolev_steps_and_sweeps_relax_the_map():
    # trimesh's CAD plate: its fans squeezed to 1e-9 of the square stall the Gauss-Newton steps at once
    plate = geoimg.mesh.repair(load_data("plate_holes.STL"))[0].mesh
    heard: list = []
    p = geoimg.parametrize(plate, "cut", progress=heard.append)
    assert not p.info["gauss_newton"] and p.flipped_faces == 0 and "Gauss-Newton" not in p.info["stages"][0]
    kept = [m for m in heard if m.startswith(f"{p.info['start']} start: ")]
    assert any("area balancing step" in m for m in kept)
    assert sum(m.endswith("single-vertex sweeps") for m in kept) == PLANAR_SWEEP_ROUNDS


def test_one_step_rule_for_every_domain(monkeypatch):
    from geoimg.parametrization._balance import DEFAULT_STEPS, default_steps
    assert default_steps(10_000) == default_steps(10**6) == DEFAULT_STEPS == 200
    assert default_steps(4_000) == 500 and default_steps(1) == 2000
    # a small cut-open square runs past 200 Sobolev steps when it has not converged by then (389 when
    # measured), here with every Gauss-Newton step made to stall
    import geoimg.parametrization._newton as newton
    monkeypatch.setattr(newton, "SHORTEST_STEP", 2.0)
    p = geoimg.parametrize(meshes.torus_grid(48, 16, 1.0, 0.25), "cut")
    assert not p.info["gauss_newton"]
    assert DEFAULT_STEPS < p.info["balance_steps"] < default_steps(p.mesh.n_faces)


def _squeezed_sphere_map():
    """A bumpy icosphere mapped onto the sphere by its radial projection, then crowded towards one pole by a
    Moebius map (one-to-one, every triangle positive, the far side squeezed)."""
    mesh = meshes.icosphere(3, bumps=0.2)
    s = mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)
    a = np.array([0.0, 0.0, 0.6])
    d = s - a
    s = (1.0 - a @ a) * d / (d ** 2).sum(axis=1, keepdims=True) - a
    return mesh, np.ascontiguousarray(mesh.faces, np.int64), s / np.linalg.norm(s, axis=1, keepdims=True)


def test_single_vertex_sweeps_lower_the_energy_keep_the_map_one_to_one_and_leave_the_input():
    from geoimg.parametrization._balance import relax_locally
    from geoimg.parametrization._orientation import chord_orientation
    mesh, tris, s = _squeezed_sphere_map()
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3)
    before = s.copy()
    assert (chord_orientation(s, tris) > 0).all()
    out = relax_locally(s, mesh.vertices, tris, beta=0.3, sweeps=30)
    assert np.array_equal(s, before)
    assert (chord_orientation(out, tris) > 0).all()
    assert np.allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-12)
    e0, e1 = ref.energy(s)[0], ref.energy(out)[0]
    assert e1 < 0.5 * e0, (e0, e1)
    # more sweeps go further down
    assert ref.energy(relax_locally(out, mesh.vertices, tris, beta=0.3, sweeps=30))[0] < e1
    # the same bits every time (one vertex after another, in order)
    assert np.array_equal(out, relax_locally(s, mesh.vertices, tris, beta=0.3, sweeps=30))


def test_single_vertex_sweeps_hold_held_and_unused_vertices_and_slide_along_their_lines():
    from geoimg.parametrization._balance import relax_locally
    x = np.array([[0., 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0], [0.5, 0, 0]])
    tris = np.array([[0, 5, 4], [5, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    start = x.copy()
    start[4, :2] = [0.3, 0.6]
    start[5, 0] = 0.2                                   # on the bottom side, off its place
    held = np.array([True, True, True, True, False, False])
    along = np.zeros((6, 3))
    along[5] = [1, 0, 0]
    out = relax_locally(start, x, tris, planar=True, held=held, along=along, sweeps=200)
    assert np.array_equal(out[:4], start[:4])
    assert out[5, 1] == 0.0 and abs(out[5, 0] - 0.5) < 1e-3     # slid back along the side, not off it
    assert np.abs(out[4, :2] - [0.5, 0.5]).max() < 1e-3
    used = np.ones(6, bool)
    used[4] = False                                     # an unused vertex does not move
    assert np.array_equal(relax_locally(start, x, tris, used, planar=True, held=held, along=along)[4], start[4])


def test_a_planar_map_with_a_triangle_of_no_area_is_still_relaxed(finger_map):
    """Triangles of no area stop every step of all vertices at once (the energy is infinite); the
    single-vertex sweeps move the other vertices, and then open those triangles too."""
    from geoimg.parametrization._disk import relax_planar
    from geoimg.parametrization._slim import area_log_rms
    mesh, tris, s = finger_map
    loop = geoimg.mesh.boundary_loops(mesh)[0]
    inner = np.setdiff1d(np.arange(mesh.n_vertices), loop)
    v = int(inner[len(inner) // 2])
    ring = tris[np.any(tris == v, axis=1)]
    a = [w for w in ring[0] if w != v][0]
    uv = s[:, :2].copy()
    uv[v] = uv[a]                                       # on a neighbour: its two triangles have no area
    def signed(c):
        return np.cross(c[tris[:, 1]] - c[tris[:, 0]], c[tris[:, 2]] - c[tris[:, 0]])
    assert np.sum(signed(uv) == 0) == 2 and np.sum(signed(uv) < 0) == 0
    ref = AreaBalanceNumpy(mesh.vertices, tris, mesh.n_vertices, 0.3, planar=True)
    assert ref.energy(np.column_stack([uv, np.zeros(len(uv))]))[0] == np.inf
    out, steps, newton = relax_planar(mesh.vertices, tris, uv, loop, "area")
    assert not newton                                   # no finite energy: the Sobolev steps and sweeps
    assert (signed(out) > 0).all()
    x = mesh.vertices
    area3 = 0.5 * np.linalg.norm(np.cross(x[tris[:, 1]] - x[tris[:, 0]], x[tris[:, 2]] - x[tris[:, 0]]), axis=1)
    assert area_log_rms(area3, out, tris) < 0.8 * area_log_rms(area3, uv, tris)
    assert np.array_equal(out[loop], uv[loop])          # the boundary held


def test_sweeps_go_colour_by_colour_and_give_one_map_on_any_thread_count():
    # no triangle has two corners of one colour (so one colour's vertices move in parallel without reading
    # what another writes), and the sweeps' map is the same bits on one thread as on two
    import numba
    from geoimg.parametrization._balance import relax_locally, vertex_triangles
    from geoimg.parametrization._balance_kernels import colouring
    mesh = meshes.icosphere(3, bumps=0.2)
    tris = np.ascontiguousarray(mesh.triangulate()[0], np.int64)
    ptr, ring = vertex_triangles(tris, mesh.n_vertices)
    colour, count = colouring(tris, ptr, ring, mesh.n_vertices)
    c = colour[tris]
    assert (c[:, 0] != c[:, 1]).all() and (c[:, 1] != c[:, 2]).all() and (c[:, 0] != c[:, 2]).all()
    assert 3 <= count == colour.max() + 1 <= 10
    start = mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)
    start = start + 0.05 * np.random.default_rng(0).normal(size=start.shape)
    start /= np.linalg.norm(start, axis=1, keepdims=True)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = relax_locally(start, mesh.vertices, tris, sweeps=5)
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = relax_locally(start, mesh.vertices, tris, sweeps=5)
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(one, two) and not np.array_equal(one, start)


def test_balancings_sharing_a_cache_factor_once_and_give_the_same_map(finger_map, monkeypatch):
    from geoimg.parametrization import _balance
    mesh, tris, start = finger_map
    held = np.zeros(mesh.n_vertices, bool)
    held[geoimg.mesh.boundary_loops(mesh)[0]] = True
    plain = [_balance.balance(start, mesh.vertices, tris, planar=True, held=held, steps=s)[0] for s in (5, 9)]
    calls = []
    factor = _balance.factor_symmetric
    monkeypatch.setattr(_balance, "factor_symmetric", lambda a: calls.append(1) or factor(a))
    cache: dict = {}
    shared = [_balance.balance(start, mesh.vertices, tris, planar=True, held=held, steps=s, cache=cache)[0]
              for s in (5, 9)]
    assert len(calls) == 1 and "sobolev" in cache
    assert all(np.array_equal(a, b) for a, b in zip(plain, shared)) and not np.array_equal(plain[1], start)

