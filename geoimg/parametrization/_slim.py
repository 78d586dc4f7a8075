"""Lower a disk map's distortion with libigl's SLIM (symmetric Dirichlet energy, Rabinovich et al. 2017), the
boundary held: what the disk and cut-open parametrizations run after the mean-value map with ``balance="slim"``
(the default is the area balancing of :mod:`._balance`). Every SLIM step keeps
every triangle the right way round, and the symmetric Dirichlet energy grows without bound as a triangle
shrinks, so triangles that the mean-value map squeezed (what sticks out of a disk: fingers, ears, a snout)
are opened up.
"""
from __future__ import annotations

import igl
import numpy as np

from ._laplacian import planar_cross, triangle_areas

__all__ = ["relax", "area_log_rms", "SLIM_MAX_STEPS", "SLIM_PROGRESS"]

SLIM_MAX_STEPS = 20          # SLIM steps at most (about 0.7 s a step per 70,000 faces on this project's machines)
SLIM_PROGRESS = 0.02         # ... and only while each lowers the area distortion by 2 %
SLIM_STIFFNESS = 1e11


def area_log_rms(area3: np.ndarray, uv: np.ndarray, f: np.ndarray) -> float:
    """RMS of the log of each triangle's share of the parameter area over its share of the surface area."""
    a2 = np.abs(planar_cross(uv, f))
    ok = (a2 > 0) & (area3 > 0)
    if not ok.any():                         # no triangle left with an area (a map that has collapsed)
        return float("inf")
    r = (a2[ok] / a2[ok].sum()) / (area3[ok] / area3[ok].sum())
    return float(np.sqrt(np.mean(np.log(r) ** 2)))


def relax(v: np.ndarray, f: np.ndarray, coords: np.ndarray, loop: np.ndarray):
    """Lower the map's distortion with libigl's SLIM (symmetric Dirichlet energy, Rabinovich et al. 2017),
    the boundary held where it is: every step keeps every triangle the right way round. Steps go on while
    the area distortion (log-RMS) falls by more than 2 % a step, at most ``SLIM_MAX_STEPS``. The boundary,
    held by a stiff penalty, is put back exactly afterwards; if that would turn a triangle over, the map
    before the steps is kept. Returns the coordinates and the steps taken.
    """
    area3 = triangle_areas(v, f)
    total = float(area3.sum())
    if not total > 0:
        return coords, 0
    data = igl.slim_precompute(np.asfortranarray(v / np.sqrt(total)), np.asfortranarray(f, np.int32),
                               np.asfortranarray(coords), igl.MappingEnergyType.SYMMETRIC_DIRICHLET,
                               np.ascontiguousarray(loop, np.int32), np.asfortranarray(coords[loop]), SLIM_STIFFNESS)
    distortion = area_log_rms(area3, coords, f)
    out, steps = coords, 0
    while steps < SLIM_MAX_STEPS:
        out = np.array(igl.slim_solve(data, 1), dtype=np.float64)[:, :2]
        steps += 1
        now = area_log_rms(area3, out, f)
        if not np.isfinite(now) or distortion - now < SLIM_PROGRESS * distortion:
            break
        distortion = now
    out[loop] = coords[loop]
    sign = np.sign(planar_cross(coords, f))
    if not np.isfinite(out).all() or np.any(planar_cross(out, f) * sign <= 0):
        return coords, 0
    return out, steps


