"""Helpers shared by the sample scripts: bundled data, hillshades, captions, contact sheets, wireframes."""
from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

import geoimg
from geoimg.mesh import grid_mesh, load_dem

DATA = Path(__file__).resolve().parent / "data"
TEST_DATA = Path(__file__).resolve().parents[1] / "tests" / "data"   # meshes bundled for the tests
MOUNTAIN = Path(geoimg.__file__).resolve().parent / "data" / "mountain.obj"   # the package's sample terrain
CELL = 10.0     # the Mount St. Helens DEMs' 10 m cells


def st_helens(year: int, step: int = 1, window=None) -> geoimg.Mesh:
    """The crater DEM of 2004 or 2007 as a z-up grid mesh, every ``step``-th cell, optionally a
    ``(row0, row1, col0, col1)`` window.
    """
    name = {2004: "msh_nad83_2_2004-10-04.tif", 2007: "msh_nad83_27_2007-07-05.tif"}[year]
    h = load_dem(DATA / name)
    if window is not None:
        r0, r1, c0, c1 = window
        h = h[r0:r1, c0:c1]
    return grid_mesh(h[::step, ::step], (CELL * step, CELL * step))


def hillshade(normals: np.ndarray, up: str = "z") -> np.ndarray:
    """Half-Lambert shading (0..1) of unit normals under a sun 50 degrees up from the north-west."""
    light = {"z": [-0.45, 0.45, 0.77], "y": [-0.45, 0.77, -0.45]}[up]
    light = np.asarray(light) / np.linalg.norm(light)
    return 0.5 + 0.5 * np.clip(np.asarray(normals, np.float64) @ light, -1.0, 1.0)


def gray(values: np.ndarray) -> np.ndarray:
    return cv2.cvtColor(np.round(np.clip(values, 0, 1) * 255).astype(np.uint8), cv2.COLOR_GRAY2RGB)


def caption(rgb: np.ndarray, text: str, height: int = 22) -> np.ndarray:
    """The picture with a white strip and a line of text above it."""
    strip = np.full((height, rgb.shape[1], 3), 255, np.uint8)
    cv2.putText(strip, text, (4, height - 7), cv2.FONT_HERSHEY_SIMPLEX, 0.42, (20, 20, 20), 1, cv2.LINE_AA)
    return np.vstack([strip, rgb])


def sheet(rows, gap: int = 4) -> np.ndarray:
    """A contact sheet: rows of RGB pictures, each row's pictures of one height, padded to one width."""
    lines = []
    for row in rows:
        h = max(p.shape[0] for p in row)
        padded = [np.pad(p, ((0, h - p.shape[0]), (0, gap), (0, 0)), constant_values=255) for p in row]
        lines.append(np.hstack(padded))
    w = max(line.shape[1] for line in lines)
    lines = [np.pad(line, ((0, gap), (0, w - line.shape[1]), (0, 0)), constant_values=255) for line in lines]
    return np.vstack(lines)


def fit_width(rgb: np.ndarray, width: int) -> np.ndarray:
    h = int(round(rgb.shape[0] * width / rgb.shape[1]))
    return cv2.resize(rgb, (width, h), interpolation=cv2.INTER_AREA)


def wireframe(rgb: np.ndarray, mesh: geoimg.Mesh, camera, color=(200, 30, 30)) -> np.ndarray:
    """Draw the mesh's edges over a picture rendered with ``camera`` (no hidden-line removal)."""
    h, w = rgb.shape[:2]
    m = camera.matrices(w / h)
    v = np.hstack([mesh.vertices, np.ones((mesh.n_vertices, 1))]) @ m.T
    xy = v[:, :2] / v[:, 3:4]
    px = np.stack([(xy[:, 0] + 1) * 0.5 * w, (1 - xy[:, 1]) * 0.5 * h], axis=1)
    out = rgb.copy()
    for f, k in zip(mesh.faces, mesh.face_sizes):
        pts = np.round(px[f[:k]]).astype(np.int32)
        cv2.polylines(out, [pts], True, color, 1, cv2.LINE_AA)
    return out


def save(rgb: np.ndarray, path: Path) -> Path:
    """Write an RGB picture as PNG (replacing an older one)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(path), np.ascontiguousarray(rgb[..., ::-1]), [cv2.IMWRITE_PNG_COMPRESSION, 9])
    return path


def _shown(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, dict):
        return ", ".join(f"{k} {_shown(v)}" for k, v in value.items())
    if isinstance(value, (tuple, list)):
        return "(" + ", ".join(_shown(v) for v in value) + ")"
    return str(value)


def sample_main(run, doc: str, argv=None, **options):
    """The command line of a sample: ``OUT_DIR`` and its ``--options`` (name=default); runs it and prints
    what it measured, then the picture it wrote.
    """
    # no __doc__ when sphinx-gallery runs the script
    ap = argparse.ArgumentParser(description=(doc or "").strip().split("\n", 1)[0] or None)
    ap.add_argument("out_dir", nargs="?", default="samples-out")
    for name, default in options.items():
        ap.add_argument(f"--{name}", type=type(default), default=default)
    args = ap.parse_args(argv)
    stats = run(Path(args.out_dir), **{name: getattr(args, name) for name in options})
    for name, value in stats.items():
        if name != "png":
            print(f"{name}: {_shown(value)}")
    print(f"wrote {stats['png']}")
