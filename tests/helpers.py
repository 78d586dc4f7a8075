"""Test helpers: the bundled meshes (tests/data, samples/data, the package's sample terrain), the larger
real meshes of ../shared/data (beside the checkout; only tests/test_real_meshes.py uses them, where they are
present) and small synthetic meshes."""
import warnings
from pathlib import Path

import numpy as np

import geoimg

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data"
SAMPLES = ROOT / "samples" / "data"
DATA = ROOT / "tests" / "data"
MOUNTAIN = ROOT / "geoimg" / "data" / "mountain.obj"
BUNDLED = (DATA, SAMPLES, MOUNTAIN.parent)


def data_file(name: str) -> Path:
    """A bundled mesh or raster by file name (tests/data, samples/data or geoimg/data)."""
    for folder in BUNDLED:
        if (folder / name).is_file():
            return folder / name
    raise FileNotFoundError(f"{name} is not bundled in {', '.join(str(f) for f in BUNDLED)}")


def shared_file(rel: str) -> Path:
    """A file of ../shared/data (tests/test_real_meshes.py asks only for those that are present)."""
    path = SHARED / rel
    if not path.is_file():
        raise FileNotFoundError(f"shared test data {path} not present")
    return path


def finite_differences(surface, pts, h: float = 1e-6):
    """Central differences ``(dP/du, dP/dv)`` of a planar surface at parameter points (k, 2)."""
    fu = (surface.evaluate(pts + [h, 0]) - surface.evaluate(pts - [h, 0])) / (2 * h)
    fv = (surface.evaluate(pts + [0, h]) - surface.evaluate(pts - [0, h])) / (2 * h)
    return fu, fv


def load_quietly(path) -> geoimg.Mesh:
    """A mesh file, read without its warnings (some files warn of UV seams, which the tests do not need)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return geoimg.load_mesh(path)


def load_data(name: str) -> geoimg.Mesh:
    """A bundled mesh by file name, quietly."""
    return load_quietly(data_file(name))


def load_shared(rel: str) -> geoimg.Mesh:
    """A mesh of ../shared/data, quietly."""
    return load_quietly(shared_file(rel))


def _real_name(row) -> str:
    return row if isinstance(row, str) else row[0]


def real_meshes(*rows) -> list:
    """The rows (a mesh's name, or a tuple that starts with it) whose mesh is here: every bundled one (a file
    name) and those of ../shared/data/meshes (a path with its folder) where that folder is beside the checkout.

    A test parametrized over them runs on the bundled meshes in a clone on its own, and on both beside
    ../shared."""
    return [row for row in rows if "/" not in _real_name(row) or (SHARED / "meshes" / _real_name(row)).is_file()]


def load_real(name: str) -> geoimg.Mesh:
    """A mesh of :func:`real_meshes`: bundled (a file name) or of ../shared/data/meshes (a path), quietly."""
    return load_shared(f"meshes/{name}") if "/" in name else load_data(name)


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


def glue_spread(image, pixels):
    """Largest difference between pixels that are one point of the surface."""
    reps, group = image.domain.glue(image.shape)
    flat = np.asarray(pixels, np.float64).reshape(len(group), -1)
    means = np.stack([np.bincount(group, flat[:, c]) / np.bincount(group) for c in range(flat.shape[1])], 1)
    return float(np.abs(flat - means[group]).max())


def textured_spot(folder: Path) -> Path:
    """Spot (bundled) with its bundled public-domain texture, as an OBJ + MTL + PNG in ``folder``."""
    folder = Path(folder)
    (folder / "spot.mtl").write_text("newmtl spot\nKd 1 1 1\nmap_Kd spot_texture.png\n")
    (folder / "spot_texture.png").write_bytes(data_file("spot_texture.png").read_bytes())
    obj = folder / "spot.obj"
    obj.write_text("mtllib spot.mtl\nusemtl spot\n" + data_file("spot.obj").read_text())
    return obj
