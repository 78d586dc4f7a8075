"""Filters: speed on 1024^2 float32 images, seams, inverse filtering, the FFT border error, and smoothing a
geometry image against Laplacian/Taubin smoothing of the same mesh (trimesh).

Run by hand:  python benchmarks/bench_filters.py       (prints markdown tables for benchmarks/README.md)
"""
from __future__ import annotations

import statistics
import time
import warnings
from pathlib import Path

import numpy as np
import trimesh

import filters
import geoimg
from filters.inverse import blur_taps, blur_transfer
from geoimg.mesh import surface_distance
from geoimg.parametrization._octahedral import weld_index

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "meshes"
SAMPLE_MESH = Path(__file__).resolve().parents[1] / "geoimg" / "data" / "mountain.obj"


def timed(fn, repeat=5):
    fn()   # warm-up
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def speed_table():
    rng = np.random.default_rng(0)
    planar = rng.normal(size=(1024, 1024, 3)).astype(np.float32)
    octa = rng.normal(size=(1025, 1025, 3)).astype(np.float32)
    mask = np.zeros((1024, 1024), bool)
    mask[300:700, 300:700] = True
    ops = [
        ("pad 8 px", lambda a, m: filters.pad(a, 8, m)),
        ("mean 3x3", lambda a, m: filters.mean_filter(a, 3, m)),
        ("mean 9x9", lambda a, m: filters.mean_filter(a, 9, m)),
        ("Gaussian sigma 2", lambda a, m: filters.gaussian_filter(a, 2.0, m)),
        ("bilateral sigma 2", lambda a, m: filters.bilateral_filter(a, 2.0, 0.5, m)),
        ("guided r 4", lambda a, m: filters.guided_filter(a, 4, 1e-3, m)),
        ("low-pass (FFT)", lambda a, m: filters.lowpass(a, 0.1, m)),
        ("inverse filter (FFT)", lambda a, m: filters.inverse_filter(a, mode=m)),
        ("unsharp mask", lambda a, m: filters.unsharp_mask(a, 1.0, 1.0, m)),
        (
            "Gaussian, masked, feather 8",
            lambda a, m: filters.gaussian_filter(
                a, 2.0, m, mask=mask if a.shape[0] == 1024 else np.pad(mask, ((0, 1), (0, 1))), feather=8
            ),
        ),
        ("blend", lambda a, m: filters.blend(a, a[::-1], 0.3)),
        (
            "resize to 513^2",
            lambda a, m: filters.resize(a, (513, 513), "octahedral" if m == "octahedral" else "linear"),
        ),
    ]
    print("| operation | planar 1024^2, reflect (ms) | octahedral 1025^2 (ms) |")
    print("|---|---:|---:|")
    for name, fn in ops:
        tp = timed(lambda: fn(planar, "reflect"))
        to = timed(lambda: fn(octa, "octahedral"))
        print(f"| {name} | {tp * 1e3:.1f} | {to * 1e3:.1f} |")


def seam_and_inverse():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bunny = geoimg.load_mesh(DATA / "closed_genus0" / "bunny.obj")
    img = geoimg.fit_surface(bunny, geoimg.parametrize(bunny, "sphere"), geoimg.GaussianWeights()).sample(257)
    px = img.pixels
    w = weld_index(257).ravel()
    print("\nSeams (bunny.obj, 257^2 octahedral; largest difference between glued pixels before averaging, "
          "relative to the largest coordinate):\n")
    print("| operation | glued-pixel difference |")
    print("|---|---:|")
    for name, fn in (("mean 5x5 x 3", lambda a: filters.mean_filter(a, 5, "octahedral", iterations=3)),
                     ("Gaussian sigma 3", lambda a: filters.gaussian_filter(a, 3.0, "octahedral")),
                     ("bilateral", lambda a: filters.bilateral_filter(a, 2.0, 0.05, "octahedral")),
                     ("guided", lambda a: filters.guided_filter(a, 3, 1e-4, "octahedral")),
                     ("low-pass", lambda a: filters.lowpass(a, 0.05, "octahedral")),
                     ("inverse", lambda a: filters.inverse_filter(a, mode="octahedral"))):
        out = fn(px).reshape(-1, 3)
        print(f"| {name} | {np.abs(out - out[w]).max() / np.abs(px).max():.1e} |")

    mountain = geoimg.load_mesh(SAMPLE_MESH)
    surf = geoimg.fit_surface(mountain, geoimg.parametrize(mountain, "heightfield", axis="y"),
                              geoimg.GaussianWeights(s=2))
    p = surf.sample(257).pixels
    diag = mountain.bounding_box_diagonal()
    print("\nInverse filtering (mountain.obj, 257^2 planar, float32): blur, then undo it. RMS error relative to "
          "the bounding-box diagonal.\n")
    print("| blur | blurred | inverse, Wiener nsr 1e-3 | nsr 1e-6 | clamp, max gain 10 | unsharp sigma 1, amount 1 |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, blurred, kw in (("mean 3x3", filters.mean_filter(p, 3), dict()),
                              ("Gaussian sigma 1", filters.gaussian_filter(p, 1.0), dict(blur="gaussian", sigma=1.0))):
        def rms(a):
            return np.sqrt(((a.astype(np.float64) - p) ** 2).mean()) / diag
        row = [rms(blurred), rms(filters.inverse_filter(blurred, nsr=1e-3, **kw)),
               rms(filters.inverse_filter(blurred, nsr=1e-6, **kw)),
               rms(filters.inverse_filter(blurred, method="clamp", max_gain=10, **kw)),
               rms(filters.unsharp_mask(blurred, 1.0, 1.0))]
        print(f"| {name} | " + " | ".join(f"{x:.2e}" for x in row) + " |")

    print("\nFFT border error (mountain.obj 257^2, Gaussian sigma 3 applied in the Fourier domain, against the "
          "spatial filter with the symmetric rule; error relative to the diagonal):\n")
    pd = p.astype(np.float64)
    ref = filters.gaussian_filter(pd, 3.0)
    gain = blur_transfer(blur_taps("gaussian", sigma=3.0))
    rim = np.zeros(p.shape[:2], bool)
    rim[:10], rim[-10:], rim[:, :10], rim[:, -10:] = True, True, True, True
    print("| extension | max error, 10-pixel rim | max error, interior |")
    print("|---|---:|---:|")
    for mode, label in (("wrap", "none (naive periodic FFT)"), ("reflect", "symmetric")):
        err = np.abs(filters.fourier_filter(pd, gain, mode) - ref).max(axis=-1) / diag
        print(f"| {label} | {err[rim].max():.2e} | {err[~rim].max():.2e} |")


def versus_mesh_smoothing():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = geoimg.load_mesh(DATA / "closed_genus0" / "bunny.obj")
    param = geoimg.parametrize(mesh, "sphere")
    img = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights()).sample(257)
    tris, _ = mesh.triangulate()

    def volume(m):
        t, _ = m.triangulate()
        v = m.vertices
        return np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum() / 6

    v0 = volume(mesh)
    print("\nSmoothing bunny.obj (6,598 triangles) as a 257^2 octahedral geometry image vs as a mesh (trimesh). "
          "Distance: RMS, two-sided, to the input mesh, relative to the diagonal; time excludes the "
          "parametrization and sampling (0.3 + 0.4 s, once).\n")
    print("| method | time (ms) | RMS distance to input | volume change |")
    print("|---|---:|---:|---:|")
    rows = []
    for k in (3, 9):
        t = timed(lambda: img.apply(filters.mean_filter, 5, iterations=k).to_mesh(), 3)
        out = img.apply(filters.mean_filter, 5, iterations=k).to_mesh()
        rows.append((f"geometry image: mean 5x5 x {k}, to quads", t, out))
    for k in (1, 3):
        t = timed(lambda: img.apply(filters.gaussian_filter, float(k)).to_mesh(), 3)
        rows.append(
            (f"geometry image: Gaussian sigma {k}, to quads", t, img.apply(filters.gaussian_filter, float(k)).to_mesh())
        )
    for name, fn, it in (("trimesh Laplacian", trimesh.smoothing.filter_laplacian, 10),
                         ("trimesh Laplacian", trimesh.smoothing.filter_laplacian, 30),
                         ("trimesh Taubin", trimesh.smoothing.filter_taubin, 10),
                         ("trimesh Taubin", trimesh.smoothing.filter_taubin, 30)):
        def run():
            tm = trimesh.Trimesh(mesh.vertices.copy(), tris.copy(), process=False)
            fn(tm, iterations=it)
            return tm
        t = timed(run, 3)
        tm = run()
        rows.append((f"{name}, {it} iterations", t, geoimg.Mesh(np.asarray(tm.vertices), np.asarray(tm.faces))))
    for name, t, out in rows:
        d = surface_distance(mesh, out, n=50000)
        print(f"| {name} | {t * 1e3:.1f} | {d['rms'] / d['diagonal']:.2e} | {(volume(out) / v0 - 1) * 100:+.2f} % |")
    d = surface_distance(mesh, img.to_mesh(), n=50000)
    print(f"| (unfiltered geometry image, to quads) | - | {d['rms'] / d['diagonal']:.2e} | "
          f"{(volume(img.to_mesh()) / v0 - 1) * 100:+.2f} % |")


if __name__ == "__main__":
    speed_table()
    seam_and_inverse()
    versus_mesh_smoothing()
