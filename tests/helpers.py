"""Test helpers: real meshes from ../shared/data (beside the checkout) and small synthetic meshes."""
import warnings
from pathlib import Path

import numpy as np
import pytest

import geoimg

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data"
SAMPLES = ROOT / "samples" / "data"


def shared_file(rel: str) -> Path:
    path = SHARED / rel
    if not path.is_file():
        pytest.skip(f"shared test data {path} not present")
    return path


def finite_differences(surface, pts, h: float = 1e-6):
    """Central differences ``(dP/du, dP/dv)`` of a planar surface at parameter points (k, 2)."""
    fu = (surface.evaluate(pts + [h, 0]) - surface.evaluate(pts - [h, 0])) / (2 * h)
    fv = (surface.evaluate(pts + [0, h]) - surface.evaluate(pts - [0, h])) / (2 * h)
    return fu, fv


def load_shared(rel: str) -> geoimg.Mesh:
    """A mesh of the shared data, quietly (some files warn of UV seams, which the tests do not need)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return geoimg.load_mesh(shared_file(rel))


def mixed_mesh(seed: int = 0, n: int = 7):
    """An irregular planar mesh of triangles, quads and hexagons over the unit square, with its uv.

    A jittered n x n grid of quads; every other quad split into two triangles, and pairs of quads of
    the last row merged into hexagons.
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)
    uu, vv = np.meshgrid(t, t)
    uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
    inner = (uv > 0) & (uv < 1)
    jitter = rng.uniform(-0.3, 0.3, uv.shape) / (n - 1)
    uv = uv + np.where(inner.all(axis=1)[:, None], jitter, 0.0)
    idx = np.arange(n * n).reshape(n, n)
    faces = []
    for i in range(n - 2):
        for j in range(n - 1):
            a, b, c, d = idx[i, j], idx[i, j + 1], idx[i + 1, j + 1], idx[i + 1, j]
            if (i + j) % 2:
                faces += [[a, b, c], [a, c, d]]
            else:
                faces.append([a, b, c, d])
    i = n - 2
    for j in range(0, n - 2, 2):
        faces.append([idx[i, j], idx[i, j + 1], idx[i, j + 2], idx[i + 1, j + 2], idx[i + 1, j + 1], idx[i + 1, j]])
    if (n - 1) % 2:
        j = n - 2
        faces.append([idx[i, j], idx[i, j + 1], idx[i + 1, j + 1], idx[i + 1, j]])
    return uv, faces
