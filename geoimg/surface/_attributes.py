"""Colours of a parametrized mesh resampled onto a geometry image's grid.

Each pixel's parameter is located in the parametrized face that holds it, and the face's vertex colours,
or its texture read at its corners' texture coordinates, are interpolated linearly there (barycentric
coordinates in the plane, or of the central projection onto the face's chord on the sphere). Colours are
not blended by the weighted mean as positions are: a blend would smear a texture's edges and average
texture coordinates across UV seams into other parts of the texture.
"""
from __future__ import annotations

import warnings

import numpy as np

from .._budget import check_memory
from ..image import Domain
from ..mesh import Mesh
from ..parametrization import Parametrization
from ._fit import _parametrized_mesh

__all__ = ["locate", "sample_colors", "CANDIDATES"]

CANDIDATES = 16          # nearest faces (by centroid) tried for each point ...
RETRY_LIMIT = 1024       # ... and at most this many for a point that none of those holds
_CHUNK = 1 << 15


def locate(points: np.ndarray, corners: np.ndarray, candidates: int = CANDIDATES) -> tuple[np.ndarray, np.ndarray]:
    """The triangle holding each point and the point's barycentric coordinates in it.

    Parameters
    ----------
    points : numpy.ndarray, shape (P, 2) or (P, 3)
        Points in the plane, or unit directions.
    corners : numpy.ndarray, shape (T, 3, 2) or (T, 3, 3)
        The triangles' corners in the same space.

    Returns
    -------
    triangle : numpy.ndarray of int64, shape (P,)
    bary : numpy.ndarray, shape (P, 3)
        Non-negative, summing to 1. The triangles tried are those whose centroids are nearest the point
        (:data:`CANDIDATES`, then 8 times as many while none holds it, up to :data:`RETRY_LIMIT`); a point
        that none holds (outside the parametrized region, or a gap of rounding between faces) gets the
        one it is least outside of, clipped to its edge.

    Examples
    --------
    >>> tri = np.array([[[0.0, 0], [1, 0], [0, 1]], [[1.0, 0], [1, 1], [0, 1]]])
    >>> t, b = locate(np.array([[0.25, 0.25], [0.75, 0.75]]), tri)
    >>> t.tolist(), np.round(b, 3).tolist()
    ([0, 1], [[0.5, 0.25, 0.25], [0.25, 0.5, 0.25]])
    """
    lifted = corners if corners.shape[2] == 3 else np.concatenate([corners, np.ones(corners.shape[:2] + (1,))], 2)
    q_all = points if points.shape[1] == 3 else np.concatenate([points, np.ones((len(points), 1))], 1)
    det = np.linalg.det(lifted)
    scale = np.abs(lifted).max(axis=(1, 2)) ** 3
    ok = np.abs(det) > 1e-14 * np.maximum(scale, 1e-300)
    inverse = np.zeros_like(lifted)
    inverse[ok] = np.linalg.inv(lifted[ok])              # q = b @ M  =>  b = q @ M^-1
    from scipy.spatial import cKDTree      # here: a conversion without attributes starts without it

    tree = cKDTree(corners.mean(axis=1))
    triangle = np.empty(len(points), np.int64)
    bary = np.empty((len(points), 3))
    score = np.full(len(points), -np.inf)
    todo = np.arange(len(points))
    k = min(candidates, len(corners))
    while True:
        step = max(1, _CHUNK * candidates // k)              # about the same memory whatever k
        for start in range(0, len(todo), step):
            rows = todo[start:start + step]
            cand = tree.query(points[rows], k=k)[1].reshape(len(rows), k)
            b = np.einsum("pi,pkij->pkj", q_all[rows], inverse[cand])
            total = b.sum(axis=2)
            usable = ok[cand] & (total > 0)
            b = b / np.where(usable, total, 1.0)[..., None]
            s = np.where(usable, b.min(axis=2), -np.inf)
            best = np.argmax(s, axis=1)
            pick = np.arange(len(rows))
            better = s[pick, best] > score[rows]
            rows, best, pick = rows[better], best[better], pick[better]
            triangle[rows], bary[rows], score[rows] = cand[pick, best], b[pick, best], s[pick, best]
        if k >= min(len(corners), RETRY_LIMIT):
            break
        k = min(8 * k, len(corners), RETRY_LIMIT)          # points no nearby face holds: more faces
        todo = np.flatnonzero(score < -1e-9)
        if not len(todo):
            break
    lost = ~np.isfinite(score)                 # no usable face near it at all (all of zero area): the nearest
    if lost.any():
        triangle[lost] = tree.query(points[lost], k=1)[1]
        bary[lost] = 1.0 / 3.0
    chosen = np.clip(bary, 0.0, None)
    return triangle, chosen / np.maximum(chosen.sum(axis=1, keepdims=True), 1e-300)


def _texture_lookup(texture: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Bilinear texture colours in [0, 1] at texture coordinates (P, 2), OBJ's (0, 0) the bottom-left
    corner; coordinates outside [0, 1] repeat the texture.
    """
    import cv2          # here: a conversion without a texture starts without OpenCV

    h, w = texture.shape[:2]
    n = len(uv)
    width = 1024                                          # OpenCV's maps: under 32767 pixels a side
    rows = -(-n // width)
    x = np.zeros(rows * width, np.float32)
    y = np.zeros(rows * width, np.float32)
    x[:n] = uv[:, 0] * w - 0.5
    y[:n] = (1.0 - uv[:, 1]) * h - 0.5
    # only the part of the texture the lookups reach (a piece of a model reads a corner of its atlas), when
    # they need no wrapping: shifted by whole pixels, the same colours from a fraction of the memory
    x0, x1 = int(np.floor(x[:n].min())) - 1, int(np.ceil(x[:n].max())) + 2
    y0, y1 = int(np.floor(y[:n].min())) - 1, int(np.ceil(y[:n].max())) + 2
    if x0 >= 0 and y0 >= 0 and x1 <= w and y1 <= h:
        texture = texture[y0:y1, x0:x1]
        x[:n] -= x0
        y[:n] -= y0
    check_memory(texture.size * 4.0, f"a float copy of the {w} x {h} texture's part that the colours read")
    out = cv2.remap(texture.astype(np.float32), x.reshape(rows, width), y.reshape(rows, width),  # float: unrounded
                    cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP).reshape(rows * width, -1)[:n]
    return out.astype(np.float32) / 255.0


def sample_colors(mesh: Mesh, param: Parametrization, domain: Domain, shape, valid=None) -> np.ndarray | None:
    """The colours (H, W, 3 or 4) float32 in [0, 1] of a parametrized mesh on the grid of ``domain`` and
    ``shape`` (0 outside ``valid``, an (H, W) mask): its texture where it has one, else its vertex colours; None when
    it has neither. A mesh cut
    open by its parametrization keeps its vertex colours but not its texture (its texture coordinates
    belong to the uncut faces), with a warning.

    Examples
    --------
    >>> from geoimg.image import PlanarDomain
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]], colors=np.eye(4, 3))
    >>> from geoimg.parametrization import Parametrization
    >>> c = sample_colors(m, Parametrization(m.vertices[:, :2], (1, 1)), PlanarDomain(), (3, 3))
    >>> c[1, 1].round(3).tolist()      # the quad's centre: halfway between corners 0 and 2
    [0.5, 0.0, 0.5]
    """
    if mesh.texture is None and mesh.colors is None:
        return None
    if param.mesh is not None and mesh.texture is not None:
        warnings.warn("the texture is not carried onto a cut-open image (its texture coordinates belong to the "
                      "uncut faces)" + ("; the vertex colours are" if mesh.colors is not None else ""), stacklevel=3)
    mesh = _parametrized_mesh(mesh, param)
    if mesh.colors is None and mesh.texture is None:
        return None
    tris, owner, corner = mesh.triangle_corners()
    valid = np.ones(shape, bool) if valid is None else np.asarray(valid, bool)
    tri, bary = locate(domain.parameter_points(shape)[valid.ravel()], param.coords[tris])
    if mesh.texture is not None and mesh.face_uv is not None:
        uv = mesh.face_uv[owner[tri][:, None], corner[tri]]               # (P, 3, 2)
        values = _texture_lookup(mesh.texture, np.einsum("pk,pkc->pc", bary, uv))
    else:
        assert mesh.colors is not None
        values = np.einsum("pk,pkc->pc", bary, mesh.colors[tris[tri]])
    out = np.zeros(tuple(shape) + (values.shape[1],), np.float32)
    out[valid] = np.clip(values, 0.0, 1.0)
    return out
