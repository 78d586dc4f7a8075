"""A starting map of a large closed genus-0 mesh onto the sphere, made on a coarse copy of it.

1. The mesh is decimated (edge collapses to the midpoint, :mod:`._decimate`) to a few thousand triangles.
2. ``coarse_map(U, G)`` maps the coarse mesh and balances its areas: cheap, and it converges, where the
   fine mesh's balancing from its conformal map needs hundreds of slow steps (that map squeezes ears and
   limbs exponentially).
3. Each fine vertex takes the coarse map at its closest point on the coarse mesh (barycentric in the
   coarse triangle that holds that point).
4. Where that folds fine triangles (features thinner than a coarse triangle), the vertices around the
   folds are moved on the sphere by a local descent on ``sum max(0, eps - det)^2`` over their triangles
   (``det`` a chord triangle's orientation), until none is folded.

The caller balances the fine map from there. ``None`` comes back, with the reason, where a stage cannot
give a one-to-one map (the coarse map folds, the folds do not open); the caller then maps directly.

Examples
--------
>>> import trimesh
>>> from geoimg.parametrization._orientation import chord_orientation
>>> ball = trimesh.creation.icosphere(4)                # 5,120 triangles
>>> def exact(U, G):                                    # a coarse map that is already one-to-one
...     return U / np.linalg.norm(U, axis=1, keepdims=True)
>>> s, info = multilevel_start(ball.vertices, ball.faces, exact, coarse_triangles=500)
>>> bool((chord_orientation(s, ball.faces) > 0).all()), info["coarse_triangles"] <= 500
(True, True)
"""
from __future__ import annotations

from collections.abc import Callable

import igl
import numpy as np

from ..mesh import Mesh, topology
from ._balance import local_sizes
from ._decimate import decimate as collapse_edges
from ._orientation import chord_orientation

__all__ = ["multilevel_start", "decimate", "transfer", "untangle", "open_folds", "COARSE_TRIANGLES"]

COARSE_TRIANGLES = 8000        # the coarse copy's size
UNTANGLE_RINGS = (3, 6, 12)     # rings of vertices around the folds that may move, tried in turn
UNTANGLE_STEPS = 400
UNTANGLE_TARGET = 0.05         # folded triangles are pushed to this share of the median triangle's det ...
OPEN_SHARE = 1e-3              # ... and count as opened above this share of that


def decimate(x: np.ndarray, tris: np.ndarray, triangles: int):
    """Edge collapses (:func:`._decimate.decimate`) down to at most ``triangles``; ``(U, G)`` or None when the
    result is not a closed genus-0 surface in one piece.
    """
    U, G = collapse_edges(x, tris, triangles)
    topo = topology(Mesh(U, G)) if len(G) >= 4 else None
    if topo is None or not (topo.closed and topo.components == 1 and topo.genus == 0):
        return None
    return U, G


def transfer(x: np.ndarray, U: np.ndarray, G: np.ndarray, coarse: np.ndarray) -> np.ndarray:
    """Unit vectors for the points ``x``: the coarse map ``coarse`` (of the mesh ``U, G``) at each point's
    closest point on that mesh, barycentric in its triangle.
    """
    _, tri, closest = igl.point_mesh_squared_distance(np.asarray(x, np.float64), U, G)
    a, b, c = (U[G[tri, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    nn = np.maximum(np.einsum("ij,ij->i", n, n), 1e-300)
    w0 = np.einsum("ij,ij->i", np.cross(c - b, closest - b), n) / nn
    w1 = np.einsum("ij,ij->i", np.cross(a - c, closest - c), n) / nn
    s = (w0[:, None] * coarse[G[tri, 0]] + w1[:, None] * coarse[G[tri, 1]]
         + (1.0 - w0 - w1)[:, None] * coarse[G[tri, 2]])
    return s / np.maximum(np.linalg.norm(s, axis=1, keepdims=True), 1e-300)


def _rings(tris: np.ndarray, seeds: np.ndarray, n: int, rings: int) -> np.ndarray:
    """The vertices within ``rings`` triangle-rings of the vertices ``seeds`` (bool, (n,))."""
    inside = np.zeros(n, bool)
    inside[seeds] = True
    for _ in range(rings):
        inside[tris[inside[tris].any(axis=1)].ravel()] = True
    return inside


def untangle(s: np.ndarray, tris: np.ndarray, *, rings: int = UNTANGLE_RINGS[0], steps: int = UNTANGLE_STEPS,
             target: float = UNTANGLE_TARGET):
    """Open the folded triangles of a map onto the sphere: the vertices within ``rings`` of them descend on
    ``sum max(0, eps - det)^2`` over the triangles around them (each moving at most a fifth of its
    shortest edge a step), the rest stay, until every triangle's ``det`` is above ``OPEN_SHARE * eps``.
    Returns ``(s, steps taken, whether no triangle is folded)``.
    """
    det = chord_orientation(s, tris)
    positive = det[det > 0]
    eps = target * float(np.median(positive)) if len(positive) else 1e-6
    floor = OPEN_SHARE * eps            # opened: clear of 0 by more than rounding (a rotation moves det by ~1e-17)
    if (det > floor).all():
        return s, 0, True
    s = s.copy()
    moving = _rings(tris, np.unique(tris[~(det > floor)]), len(s), rings)
    near = tris[moving[tris].any(axis=1)]              # the triangles that moving vertices change
    verts = np.unique(near)                            # ... and their vertices: the descent works on them alone
    local, taken, opened = _local_descent(s[verts], np.searchsorted(verts, near), moving[verts], eps, floor, steps)
    s[verts] = local
    return s, taken, opened


def open_folds(s: np.ndarray, tris: np.ndarray, rings_tried: tuple[int, ...] = UNTANGLE_RINGS):
    """:func:`untangle` in wider and wider neighbourhoods (``rings_tried``, :data:`UNTANGLE_RINGS` by default),
    each from where the last left off; ``(s, steps taken, whether no triangle is folded)``.
    """
    taken, opened = 0, False
    for rings in rings_tried:
        s, steps, opened = untangle(s, tris, rings=rings)
        taken += steps
        if opened:
            break
    return s, taken, opened and bool(np.isfinite(s).all())


def _local_descent(s, near, moving, eps, floor, steps):
    """:func:`untangle`'s descent on the vertices ``s`` of the triangles ``near`` (renumbered), in place;
    returns ``(s, steps taken, whether opened)``.
    """
    edges = np.concatenate([near[:, [0, 1]], near[:, [1, 2]], near[:, [2, 0]]])
    for step in range(steps):
        a, b, c = s[near[:, 0]], s[near[:, 1]], s[near[:, 2]]
        d = np.einsum("ij,ij->i", a, np.cross(b, c))
        if (d > floor).all():
            return s, step, True
        low = d < eps
        r = (eps - d[low])[:, None]
        t, a, b, c = near[low], a[low], b[low], c[low]
        pull = np.concatenate([-r * np.cross(b, c), -r * np.cross(c, a), -r * np.cross(a, b)])
        at = t.T.ravel()                        # the corners in np.add.at's order: all first ones, then ...
        g = np.stack([np.bincount(at, pull[:, k], minlength=len(s)) for k in range(3)], axis=1)
        g[~moving] = 0.0
        g -= np.einsum("ij,ij->i", g, s)[:, None] * s             # tangent to the sphere
        h = local_sizes(s, edges, ignore_below=1e-9)       # vertices on one point move apart by other edges
        size = np.linalg.norm(g, axis=1)
        go = (size > 0) & np.isfinite(h)
        s[go] -= g[go] * (0.2 * h[go] / size[go])[:, None]
        s[go] /= np.linalg.norm(s[go], axis=1, keepdims=True)
    return s, steps, bool((chord_orientation(s, near) > floor).all())


def multilevel_start(x: np.ndarray, tris: np.ndarray, coarse_map: Callable, *,
                     coarse_triangles: int | None = None, progress: Callable | None = None):
    """A one-to-one starting map of the closed genus-0 triangle mesh ``x, tris`` made through a coarse copy
    (see the module's text), of ``coarse_triangles`` (default :data:`COARSE_TRIANGLES`); ``coarse_map(U, G)``
    returns unit vectors for the coarse mesh, or None; ``progress(message)`` hears of each stage.
    Returns ``(s, info)``, ``s`` None when no such map was found (``info["multilevel"]`` says why).
    """
    say = progress or (lambda message: None)
    tris = np.asarray(tris, np.int64)
    coarse = decimate(x, tris, COARSE_TRIANGLES if coarse_triangles is None else coarse_triangles)
    if coarse is None:
        return None, {"multilevel": "decimation failed"}
    U, G = coarse
    info: dict = {"coarse_triangles": int(len(G))}
    say(f"coarse copy of {len(G)} triangles made; mapping it")
    sc = coarse_map(U, G)
    if sc is None:
        return None, {**info, "multilevel": "the coarse mesh's direct maps fold"}
    s = transfer(x, U, G, sc)
    folds = int(np.sum(~(chord_orientation(s, tris) > 0)))
    info["transfer_folds"] = folds
    if folds:
        say(f"coarse map carried over to every vertex; opening its {folds} folded triangles")
    s, taken, opened = open_folds(s, tris)
    info["untangle_steps"] = taken
    if not opened:
        return None, {**info, "multilevel": f"{folds} folded triangles did not open"}
    return s, {**info, "multilevel": "used"}

