"""The Gauss-Newton metric's factorization (issue 53): SuperLU's symmetric mode (what the steps used before),
qdldl afresh and refactored on the same pattern (what they use now), and cholespy's CHOLMOD where installed,
on the metrics of real maps: the terrain's and the camel's head's disk maps (u's system), a 17,800-face
bunny's sphere map (2 x 2 blocks) when a path to one is given. Each the best of 5 after a warm-up, one
solve checked against SuperLU's.

    python benchmarks/bench_factor.py [--sphere PATH]
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy import sparse

import geoimg
from geoimg.parametrization import _newton
from geoimg.parametrization._laplacian import SymmetricFactor, factor_symmetric

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_coverage import _best  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "meshes"


def captured_metric(mesh: geoimg.Mesh, method: str) -> sparse.csc_matrix:
    """The first metric a Gauss-Newton step of ``mesh``'s map factors, as its upper triangle (CSC)."""
    kept: list = []
    real = _newton._factor

    def spy(block, values, factor=None):
        if not kept:
            kept.append(_newton._metric_block(block, values))
        return real(block, values, factor)

    _newton._factor = spy
    try:
        geoimg.parametrize(mesh, method)
    finally:
        _newton._factor = real
    return kept[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sphere", type=Path, help="a closed genus-0 mesh of at most 20,000 vertices")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    cases = [("mountain.obj disk", ROOT / "geoimg" / "data" / "mountain.obj", "disk"),
             ("camelhead.off disk", SHARED / "open_disk" / "camelhead.off", "disk")]
    if args.sphere:
        cases.append((f"{args.sphere.name} sphere", args.sphere, "sphere"))
    print("| metric | unknowns | SuperLU | qdldl | qdldl refactored | CHOLMOD (cholespy) |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, path, method in cases:
        if not path.exists():
            continue
        upper = captured_metric(geoimg.load_mesh(path), method)
        full = (upper + sparse.triu(upper, 1).T).tocsc()
        n = upper.shape[0]
        b = np.random.default_rng(0).normal(size=n)
        reference = factor_symmetric(full).solve(b)
        f = SymmetricFactor(upper)
        assert np.allclose(f.solve(b), reference, rtol=1e-8, atol=1e-10 * np.abs(reference).max())
        cells = [_best(lambda: factor_symmetric(full), 5), _best(lambda: SymmetricFactor(upper), 5),
                 _best(lambda: f.refactor(upper), 5)]
        try:
            from cholespy import CholeskySolverD, MatrixType
            cells.append(_best(lambda: CholeskySolverD(n, full.indptr, full.indices, full.data, MatrixType.CSC), 5))
        except ImportError:
            cells.append(float("nan"))
        print(f"| {name} | {n:,} | " + " | ".join(f"{c:.4f} s" for c in cells) + " |", flush=True)


if __name__ == "__main__":
    main()
