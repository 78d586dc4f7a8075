"""How close geometry images lie to their meshes: geoimg's default conversion against the reference code of
spherical geometry images (Praun & Hoppe 2003: hhoppe/Mesh-processing-library, SphereParam + SphereSample
-domain octaflat -scheme best), both scored by geoimg's exact metric (and by MeshDistance -bothdir 1 for the
reference, to check the metric), with the linear resampling of the mesh through geoimg's own map as the bound
a point sampler reaches.

    python benchmarks/bench_fidelity.py [--res 257 513] [--meshes PATH ...] [--prefilter 0.35 0.5 0.7]
                                        [--reference DIR_WITH_MPL_BINARIES] [--samples 200000]

The reference binaries are built as ../shared/tools/praun-hoppe.md says; without them (or with
--no-reference) only geoimg's figures are printed. Disk and cut-open meshes have no reference: there the bound
is the linear resampling through the same map. A mesh with quads is split along its shorter diagonals for
both (the reference reads triangles). PSNR = 20 log10(bounding-box diagonal / RMS), RMS of exact
closest-point distances, both directions pooled, quads of the images split along their shorter diagonal.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path


import geoimg
from geoimg.mesh import surface_distance
from geoimg.surface import _coverage

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"
DEFAULT_MESHES = ["closed_genus0/bunny.off", "closed_genus0/bunny.obj", "closed_genus0/armadillo.obj",
                  "polygonal/horse_quad.obj", "closed_genus0/spot.obj", "closed_genus0/bumpy.off",
                  "closed_genus0/human_man.obj", "polygonal/sword-quad-dominant.obj",
                  "open_disk/camelhead.off", "open_disk/hemisphere.off", "closed_higher_genus/bob_tri.obj",
                  "closed_higher_genus/torus.obj"]


def write_m(mesh: geoimg.Mesh, path: Path) -> None:
    """Hoppe's .m text format, 1-based, triangles (quads split along their shorter diagonal)."""
    tris, _ = mesh.triangulate(quads="shorter")
    with open(path, "w") as f:
        f.writelines(f"Vertex {i + 1} {x:.17g} {y:.17g} {z:.17g}\n" for i, (x, y, z) in enumerate(mesh.vertices))
        f.writelines(f"Face {j + 1} {a + 1} {b + 1} {c + 1}\n" for j, (a, b, c) in enumerate(tris))


def read_m(path: Path) -> geoimg.Mesh:
    ids, verts, faces = {}, [], []
    for line in open(path):
        if line.startswith("Vertex "):
            p = line.split()
            ids[int(p[1])] = len(verts)
            verts.append([float(p[2]), float(p[3]), float(p[4])])
        elif line.startswith("Face "):
            p = line.split()
            faces.append([ids[int(x)] for x in p[2:] if not x.startswith("{")])
    return geoimg.Mesh(verts, faces)


def reference(mesh: geoimg.Mesh, name: str, resolutions, bindir: Path, work: Path) -> dict:
    """The reference's remeshes of ``mesh`` at each resolution, and MeshDistance's PSNR of each."""
    env = {**os.environ, "PATH": f"{bindir}{os.pathsep}{os.environ['PATH']}"}
    orig = work / f"{name}.orig.m"
    write_m(mesh, orig)
    meshtopm = bindir.parents[1] / "demos" / "bin" / "meshtopm.sh"
    t0 = time.perf_counter()
    with open(work / f"{name}.pm", "w") as pm:
        subprocess.run(["bash", str(meshtopm), str(orig), "-minqem", "-vsgeom", "-dihallow"], stdout=pm,
                       stderr=subprocess.DEVNULL, env=env, check=True)
    with open(work / f"{name}.sph.m", "w") as sph:
        subprocess.run(["SphereParam", str(work / f"{name}.pm")], stdout=sph, stderr=subprocess.DEVNULL, env=env,
                       check=True)
    t_param = time.perf_counter() - t0
    out = {}
    for res in resolutions:
        remesh = work / f"{name}.remesh{res}.m"
        with open(remesh, "w") as f:
            subprocess.run(["SphereSample", "-egrid", str(res - 1), "-domain", "octaflat", "-scheme", "best",
                            "-param", str(work / f"{name}.sph.m"), "-remesh"], stdout=f, stderr=subprocess.DEVNULL,
                           env=env, check=True)
        md = subprocess.run(["MeshDistance", "-mfile", str(orig), "-mfile", str(remesh), "-bothdir", "1",
                             "-maxerror", "1", "-distance"], capture_output=True, text=True, env=env, check=True)
        found = re.search(r"PSNR=([\d.]+)", md.stdout + md.stderr)
        out[res] = (read_m(remesh), float(found.group(1)) if found else float("nan"))
    out["t_param"] = t_param
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--res", type=int, nargs="+", default=[257, 513])
    ap.add_argument("--meshes", nargs="+", default=None, help="mesh files (default: six of ../shared/data)")
    ap.add_argument("--prefilter", type=float, nargs="+", default=None,
                    help="sigma in pixel spacings to try (default: geoimg's PREFILTER only)")
    ap.add_argument("--reference", default="/work/ph/mpl/bin/unix", help="folder of the reference's binaries")
    ap.add_argument("--no-reference", action="store_true")
    ap.add_argument("--samples", type=int, default=200000)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    paths = [Path(p) for p in args.meshes] if args.meshes else [SHARED / m for m in DEFAULT_MESHES]
    bindir = Path(args.reference)
    use_ref = not args.no_reference and (bindir / "SphereParam").exists() and shutil.which("bash")
    kappas = args.prefilter or [_coverage.PREFILTER]
    cols = ["mesh", "faces", "res", "reference", "MeshDistance", "linear", *[f"geoimg k={k:g}" for k in kappas],
            "chosen", "paper s=1", "t_geoimg"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    work = Path(tempfile.mkdtemp(prefix="fidelity-"))
    for path in paths:
        mesh = geoimg.load_mesh(path)
        name = path.stem + "_" + path.suffix[1:]
        tris, _ = mesh.triangulate(quads="shorter")
        tri_mesh = geoimg.Mesh(mesh.vertices, tris)
        param = geoimg.parametrize(mesh)
        ref = reference(tri_mesh, name, args.res, bindir, work) if use_ref and param.method == "sphere" else {}
        for res in args.res:
            row = [path.name, str(mesh.n_faces), str(res)]
            if ref:
                remesh, md_psnr = ref[res]
                row += [f"{surface_distance(tri_mesh, remesh, args.samples)['psnr_db']:.2f}", f"{md_psnr:.1f}"]
            else:
                row += ["", ""]
            linear = geoimg.mesh_to_image(mesh, res, parametrization=param, fidelity=False,
                                          weights=geoimg.CoverageWeights(s=1e-4))
            row.append(f"{surface_distance(tri_mesh, linear.to_mesh(), args.samples)['psnr_db']:.2f}")
            t_geo = 0.0
            for k in kappas:
                _coverage.PREFILTER = k
                t0 = time.perf_counter()
                img = geoimg.mesh_to_image(mesh, res, parametrization=param)     # the default, as a user gets it
                t_geo = time.perf_counter() - t0
                row.append(f"{surface_distance(tri_mesh, img.to_mesh(), args.samples)['psnr_db']:.2f}")
            row.append("prefilter" if img.metadata["s"] > geoimg._convert.LIMIT_S else "as it is")
            try:
                paper = geoimg.mesh_to_image(mesh, res, parametrization=param, fidelity=False,
                                             weights=geoimg.GaussianWeights())
                row.append(f"{surface_distance(tri_mesh, paper.to_mesh(), args.samples)['psnr_db']:.2f}")
            except geoimg.InputError:           # a charts image takes the coverage weights only
                row.append("n/a")
            row.append(f"{t_geo:.2f}")
            print("| " + " | ".join(row) + " |", flush=True)
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
