"""Sampling backends: the CUDA grid kernel against the CPU one (in numba's CUDA simulator, so that a machine
without a GPU checks it too), its tile lists, and every refusal; the image post-processing kernels
(normals, coverage) against numpy; the float32 check."""
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import geoimg
import pytest
from scipy.spatial import Delaunay

from geoimg import Mesh, Parametrization, fit_surface
from geoimg.errors import ImageError, InputError
from geoimg.surface import _grid as grid
from geoimg.surface._base import unit
import meshes

ROOT = Path(__file__).resolve().parents[2]


def partial_tin(seed=0, n=120):
    """A bumpy TIN over a triangle-shaped part of the unit square: the pixels beyond it are not certified
    at small s."""
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 2))
    pts = np.vstack([pts[pts.sum(1) < 1.1], [[0, 0], [1, 0], [0, 1]]])
    z = np.sin(5 * pts[:, 0]) * pts[:, 1] + 0.3 * pts[:, 0]
    return Mesh(np.column_stack([pts, z]), Delaunay(pts).simplices), Parametrization(pts, (1, 1))


COMPARE = textwrap.dedent('''
    import json, sys, warnings
    import numpy as np
    sys.path.insert(0, sys.argv[1])
    warnings.simplefilter("ignore")
    from test_backend import partial_tin
    from geoimg import fit_surface
    from geoimg.surface import _gaussian_kernels as kernels, _gaussian_cuda_kernels as cu
    scale = int(sys.argv[2])                    # 1 in the simulator; more pixels on a real GPU
    mesh, param = partial_tin()
    out = []
    for s, res in ((0.15, 19 * scale), (1.0, 21 * scale), (2.5, 18 * scale)):
        surf = fit_surface(mesh, param, s)
        args = surf._grid_arguments(*surf.grid(res))
        a = kernels.sample_grid_gaussian(*args, derivatives=True, log_g_ref=surf.log_g_ref)
        b = cu.sample_grid_gaussian_cuda(*args, derivatives=True, log_g_ref=surf.log_g_ref)
        c = cu.sample_grid_gaussian_cuda(*args, derivatives=False, log_g_ref=surf.log_g_ref)
        img_a, img_b = surf.sample(res), surf.sample(res, backend="cuda")
        ok = a[3]
        out.append({"s": s, "uncertified": int((~ok).sum()), "same_ok": bool((a[3] == b[3]).all()),
                    "same_ok_positions": bool((c[3] == a[3]).all()),
                    "zeros_left": bool((b[0][~ok] == 0).all() and (b[1][~ok] == 0).all()),
                    "dP": float(np.abs(a[0] - b[0])[ok].max()), "dP_positions": float(np.abs(a[0] - c[0])[ok].max()),
                    "dPu": float(np.abs(a[1] - b[1])[ok].max() / np.abs(a[1][ok]).max()),
                    "dPv": float(np.abs(a[2] - b[2])[ok].max() / np.abs(a[2][ok]).max()),
                    "no_derivs": c[1] is None and c[2] is None,
                    "image_d": float(np.abs(img_a.pixels - img_b.pixels).max()),
                    "normals_d": float(np.abs(img_a.normals - img_b.normals).max()),
                    "same_mask": bool((img_a.mask == img_b.mask).all()),
                    "same_exact": img_a.metadata["exact_pixels"] == img_b.metadata["exact_pixels"]})
    print(json.dumps(out))
''')


def _compare_kernels(simulated: bool, scale: int) -> list:
    path = [str(ROOT), str(ROOT / "tests")] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path))
    if simulated:
        env["NUMBA_ENABLE_CUDASIM"] = "1"
    res = subprocess.run([sys.executable, "-c", COMPARE, str(Path(__file__).parent), str(scale)], env=env,
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    return __import__("json").loads(res.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_cuda_kernel_matches_the_cpu_kernel():
    """In numba's CUDA simulator everywhere, and where a CUDA GPU is usable (never in CI) on it too, with
    five times the pixels along each side."""
    runs = [_compare_kernels(True, 1)] + ([_compare_kernels(False, 5)] if _cuda_usable() else [])
    for rows in runs:
        assert rows[0]["uncertified"] > 0 and rows[-1]["uncertified"] == 0     # both branches are exercised
        for r in rows:
            assert r["same_ok"] and r["same_ok_positions"] and r["zeros_left"] and r["no_derivs"], r
            assert r["dP"] < 1e-14 and r["dP_positions"] < 1e-14, r
            assert r["dPu"] < 1e-11 and r["dPv"] < 1e-11, r
            assert r["image_d"] < 1e-6 and r["normals_d"] < 1e-6 and r["same_mask"] and r["same_exact"], r


def _tile_lists_brute(shape, live, c0, c1, r0, r1, tile):
    H, W = shape
    n_tx, n_ty = -(-W // tile), -(-H // tile)
    lists = []
    for ty in range(n_ty):
        for tx in range(n_tx):
            hit = (c0[live] < (tx + 1) * tile) & (c1[live] > tx * tile) & (r0[live] < (ty + 1) * tile) \
                & (r1[live] > ty * tile)
            lists.append(live[hit])
    return lists


@pytest.mark.parametrize("shape, tile", [((37, 50), 16), ((16, 16), 16), ((5, 70), 8), ((1, 1), 16)])
def test_tile_lists_hold_each_tiles_faces_in_order(shape, tile):
    from geoimg.surface._gaussian_cuda_kernels import tile_lists
    rng = np.random.default_rng(shape[0])
    F = 300
    H, W = shape
    c0 = rng.integers(0, W, F)
    c1 = np.minimum(W, c0 + rng.integers(0, 30, F))
    r0 = rng.integers(0, H, F)
    r1 = np.minimum(H, r0 + rng.integers(0, 30, F))
    live = np.flatnonzero((c1 > c0) & (r1 > r0)).astype(np.int64)
    ptr, faces, n_tx, n_ty = tile_lists(shape, live, c0, c1, r0, r1, tile)
    expected = _tile_lists_brute(shape, live, c0, c1, r0, r1, tile)
    assert len(ptr) == n_tx * n_ty + 1 == len(expected) + 1
    for t, want in enumerate(expected):
        assert faces[ptr[t]:ptr[t + 1]].tolist() == want.tolist()


def _cuda_usable():
    from geoimg.surface._gaussian_cuda_kernels import cuda_unavailable
    return cuda_unavailable() is None


def test_cuda_backend_without_a_gpu_is_refused_before_any_work(tmp_path):
    if _cuda_usable():
        pytest.skip("this machine has a CUDA GPU")
    mesh, param = partial_tin()
    surf = fit_surface(mesh, param, geoimg.GaussianWeights())
    with pytest.raises(InputError, match="backend 'cuda': .*no CUDA GPU.*'cpu'"):
        surf.sample(9, backend="cuda")
    from geoimg import mesh_to_image
    with pytest.raises(InputError, match="backend 'cuda'"):
        mesh_to_image(mesh, 9, method="heightfield", axis="z", backend="cuda")
    out = tmp_path / "t.exr"
    res = subprocess.run([sys.executable, "-m", "geoimg", "image", str(ROOT / "geoimg/data/mountain.obj"), "-o",
                          str(out), "--res", "33", "--backend", "cuda"], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 2 and "backend 'cuda'" in res.stderr and not out.exists()


@pytest.mark.parametrize("backend", ["gpu", "CUDA", "", None, 1])
def test_unknown_backends_are_refused(backend):
    surf = fit_surface(*partial_tin(), 1.0)
    with pytest.raises(InputError, match="backend: expected one of"):
        surf.sample(9, backend=backend)


def test_cuda_backend_is_refused_where_only_the_cpu_samples():
    mesh, param = partial_tin()
    for weights in (geoimg.GaussianWeights(n=10), geoimg.GaussianWeights(tol=0.0)):
        with pytest.raises(InputError, match="backend 'cuda': samples Gaussian weights"):
            fit_surface(mesh, param, weights)._sample_grid((9, 9), False, "cuda")
    ball = meshes.icosphere(1)
    d = ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True)
    sphere = fit_surface(Mesh(d, ball.faces), Parametrization(d, (1.0, 1.0), "octahedral", "sphere"),
                         geoimg.GaussianWeights())
    with pytest.raises(InputError, match="octahedral .* CPU only"):
        sphere._sample_grid((9, 9), False, "cuda")


def test_unit_normals_are_numpys_bit_for_bit():
    rng = np.random.default_rng(5)
    for scale in (1.0, 1e-150, 1e150):
        a = rng.normal(size=(4000, 3)) * scale
        b = rng.normal(size=(4000, 3))
        a[:5] = 0
        b[5:10] = 2 * a[5:10]                        # parallel: a zero cross product stays zero
        a[10:15] = [1e-170, 0, 0]                    # its square underflows
        for sign in (1, -1):
            got = grid.unit_normals(a.reshape(40, 100, 3), b.reshape(40, 100, 3), sign)
            assert got.shape == (40, 100, 3)
            assert np.array_equal(got.reshape(-1, 3), unit(np.cross(a, b) * sign))
    assert not np.any(grid.unit_normals(a[:5], b[:5], 1))


def test_face_coverage_marks_the_pixels_inside_or_near_each_polygon():
    """The banded kernel against a plain even-odd test and edge distance per pixel and polygon."""
    rng = np.random.default_rng(2)
    u, v = np.linspace(0, 1, 53), np.linspace(0, 0.7, 31)
    F, K = 40, 5
    centres = rng.random((F, 2)) * [1, 0.7]
    ang = np.sort(rng.random((F, K)) * 2 * np.pi, axis=1)
    rad = 0.02 + 0.08 * rng.random((F, K))
    poly = centres[:, None] + rad[..., None] * np.stack([np.cos(ang), np.sin(ang)], -1)
    sizes = rng.integers(3, K + 1, F)
    eps = 0.01
    got = grid.face_coverage(u, v, poly, sizes, eps)
    uu, vv = np.meshgrid(u, v)
    want = np.zeros_like(got)
    for f in range(F):
        pts = poly[f, :sizes[f]]
        a, b = pts, np.roll(pts, -1, axis=0)
        inside = np.zeros(uu.shape, bool)
        near = np.zeros(uu.shape, bool)
        for (ax, ay), (bx, by) in zip(a, b):
            cross = (ay > vv) != (by > vv)
            with np.errstate(divide="ignore", invalid="ignore"):
                xc = ax + (vv - ay) * (bx - ax) / (by - ay)
            inside ^= cross & (uu < xc)
            ex, ey = bx - ax, by - ay
            t = np.clip(((uu - ax) * ex + (vv - ay) * ey) / (ex * ex + ey * ey), 0, 1)
            near |= (uu - ax - t * ex) ** 2 + (vv - ay - t * ey) ** 2 <= eps * eps
        want |= inside | near
    assert want.any() and not want.all()
    assert np.array_equal(got, want)


def test_float32_check_passes_coordinates_near_zero_and_refuses_tiny_or_huge_surfaces():
    mesh, param = partial_tin(n=300)
    surf = fit_surface(mesh, param, geoimg.GaussianWeights(s=0.08))   # far pixels: exact sums, some near 1e-40
    img = surf.sample(64)
    assert np.isfinite(img.pixels).all() and img.metadata["exact_pixels"] > 0
    for scale in (1e-33, 1e39):
        scaled = Mesh(mesh.vertices * scale, mesh.faces)
        with pytest.raises(ImageError, match="cannot be held in a float32 image"):
            fit_surface(scaled, param, geoimg.GaussianWeights()).sample(9)


@pytest.mark.parametrize("values, held", [([1.0, 2.0], True), ([1e-40, 1.0], True), ([0.0, 0.0], True),
                                          ([-3e38, 1.0], True), ([np.nan, 1.0], False), ([np.inf, 1.0], False),
                                          ([-np.inf, 0.0], False), ([1e39, 0.0], False), ([-1e39, 0.0], False),
                                          ([1e-33, 0.0], False), ([-1e-35, 0.0], False)])
def test_float32_check_by_value(values, held):
    from geoimg.surface._base import _check_float32
    P = np.array(values)
    if held:
        _check_float32(P)
    else:
        with pytest.raises(ImageError, match="cannot be held"):
            _check_float32(P)
