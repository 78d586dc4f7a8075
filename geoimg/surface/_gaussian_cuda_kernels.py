"""The planar grid kernel on a CUDA GPU (numba.cuda): the same truncated sums as
:func:`geoimg.surface._gaussian_kernels.sample_grid_gaussian`, one GPU thread per pixel.

The image is cut into tiles of ``TILE x TILE`` pixels, one thread block each. The host lists, per tile,
the faces whose truncation box reaches it (in face order, so every pixel adds its faces in the order
the CPU kernel adds them); each thread adds the faces of its tile whose box holds its pixel. Imported
only when a caller asks for ``backend="cuda"``.
"""
from __future__ import annotations

import math
import time

import numpy as np
from numba import cuda, njit, prange

from ..errors import InputError
from ._gaussian_fastexp import plain_sum_floor
from ._grid import _band_lists
from ._gaussian_kernels import truncation_boxes

__all__ = ["sample_grid_gaussian_cuda", "cuda_unavailable", "TILE"]

TILE = 16                       # pixels along a tile's side: a block of 256 threads
BYTES_PER_PIXEL = 8 * 9 + 1     # positions and two derivatives in float64, and the certificate
PINNED = False                  # download into page-locked host memory (slower end to end: its allocation)


def cuda_unavailable() -> str | None:
    """Why no CUDA GPU can run the kernel here (None when one can)."""
    try:
        if cuda.is_available():
            return None
        return "numba finds no CUDA GPU or driver on this machine"
    except Exception as exc:   # pragma: no cover - a broken driver install
        return f"numba's CUDA support failed: {exc}"


@njit(parallel=True, cache=True)
def _tile_counts(row_ptr, row_faces, n_tx, tile, c0, c1, counts):
    """``counts[t + 1]``: how many faces' boxes reach tile ``t`` (tile rows in parallel)."""
    for ty in prange(row_ptr.shape[0] - 1):
        for q in range(row_ptr[ty], row_ptr[ty + 1]):
            f = row_faces[q]
            for tx in range(c0[f] // tile, (c1[f] - 1) // tile + 1):
                counts[ty * n_tx + tx + 1] += 1


@njit(parallel=True, cache=True)
def _tile_fill(row_ptr, row_faces, n_tx, tile, c0, c1, ptr, out):
    """Each tile's faces in face order, at ``out[ptr[t]:ptr[t + 1]]`` (tile rows in parallel)."""
    for ty in prange(row_ptr.shape[0] - 1):
        fill = ptr[ty * n_tx:(ty + 1) * n_tx].copy()
        for q in range(row_ptr[ty], row_ptr[ty + 1]):
            f = row_faces[q]
            for tx in range(c0[f] // tile, (c1[f] - 1) // tile + 1):
                out[fill[tx]] = f
                fill[tx] += 1


def tile_lists(shape, live, c0, c1, r0, r1, tile=TILE):
    """CSR lists of the ``live`` faces (in their order) by the tiles of ``shape`` their index boxes
    ``[r0, r1) x [c0, c1)`` reach; tile ``t = ty * n_tx + tx``. Returns ``(ptr, faces, n_tx, n_ty)``.
    """
    H, W = shape
    n_tx, n_ty = -(-W // tile), -(-H // tile)
    row_ptr, row_faces = _band_lists(n_ty, tile, live, r0, r1)
    counts = np.zeros(n_tx * n_ty + 1, np.int64)
    _tile_counts(row_ptr, row_faces, n_tx, tile, c0, c1, counts)
    ptr = np.cumsum(counts)
    faces = np.empty(ptr[-1], np.int32)
    _tile_fill(row_ptr, row_faces, n_tx, tile, c0, c1, ptr, faces)
    return ptr, faces, n_tx, n_ty


@cuda.jit(cache=True)
def _tile_kernel(u, v, uc, vc, inv2s, C, A, B, c0, c1, r0, r1, tile_ptr, tile_faces, n_tx, derivs, floor,
                 P, Pu, Pv, ok):
    """One thread per pixel: the sums of ``sample_grid_gaussian``'s kernel over its tile's faces."""
    j = cuda.blockIdx.x * cuda.blockDim.x + cuda.threadIdx.x
    i = cuda.blockIdx.y * cuda.blockDim.y + cuda.threadIdx.y
    if i >= v.shape[0] or j >= u.shape[0]:
        return
    pu = u[j]
    pv = v[i]
    s = n0 = n1 = n2 = 0.0
    su = sv = nu0 = nu1 = nu2 = nv0 = nv1 = nv2 = 0.0
    t = cuda.blockIdx.y * n_tx + cuda.blockIdx.x
    for q in range(tile_ptr[t], tile_ptr[t + 1]):
        f = tile_faces[q]
        if j < c0[f] or j >= c1[f] or i < r0[f] or i >= r1[f]:
            continue
        du = pu - uc[f]
        dv = pv - vc[f]
        k = inv2s[f]
        g = math.exp(-(du * du + dv * dv) * k)
        ax, ay, az = A[f, 0], A[f, 1], A[f, 2]
        bx, by, bz = B[f, 0], B[f, 1], B[f, 2]
        px = C[f, 0] + bx * dv + ax * du
        py = C[f, 1] + by * dv + ay * du
        pz = C[f, 2] + bz * dv + az * du
        s += g
        n0 += g * px
        n1 += g * py
        n2 += g * pz
        if derivs:
            gu_ = g * (-2.0 * k) * du
            gv_ = g * (-2.0 * dv * k)
            su += gu_
            sv += gv_
            nu0 += gu_ * px + g * ax
            nu1 += gu_ * py + g * ay
            nu2 += gu_ * pz + g * az
            nv0 += gv_ * px + g * bx
            nv1 += gv_ * py + g * by
            nv2 += gv_ * pz + g * bz
    ok[i, j] = s >= floor
    if not s >= floor:          # left to the exact sum; zeros, as the CPU kernel leaves
        s = math.inf
    p0, p1, p2 = n0 / s, n1 / s, n2 / s
    P[i, j, 0] = p0
    P[i, j, 1] = p1
    P[i, j, 2] = p2
    if derivs:
        Pu[i, j, 0] = (nu0 - p0 * su) / s
        Pu[i, j, 1] = (nu1 - p1 * su) / s
        Pu[i, j, 2] = (nu2 - p2 * su) / s
        Pv[i, j, 0] = (nv0 - p0 * sv) / s
        Pv[i, j, 1] = (nv1 - p1 * sv) / s
        Pv[i, j, 2] = (nv2 - p2 * sv) / s


def _check_device_memory(need: int) -> None:
    free, _total = cuda.current_context().get_memory_info()
    if need > free:
        raise InputError(f"backend 'cuda': this image needs about {need / 2**20:.0f} MiB of GPU memory, "
                         f"{free / 2**20:.0f} MiB are free; sample fewer pixels or use backend='cpu'")


def sample_grid_gaussian_cuda(u, v, centres, sigma, radius, C, A, B, *, derivatives, log_g_ref, profile=None):
    """:func:`~geoimg.surface._gaussian_kernels.sample_grid_gaussian` on a CUDA GPU (the caller has checked that one is
    usable, :func:`geoimg.surface._base.check_backend`): same arguments, same returns.

    The sums differ from the CPU kernel's by rounding alone (each pixel adds the same faces in the same
    order; the GPU's exponential is the CUDA library's), and the same pixels are certified except where
    a sum lies within rounding of the certificate. ``profile``, a dict, receives the seconds of the
    host's work (``host_s``), the uploads, the kernel and the downloads, and the tile lists' length.
    """
    clock = _Clock(profile)
    u = np.ascontiguousarray(u, np.float64)
    v = np.ascontiguousarray(v, np.float64)
    H, W = v.shape[0], u.shape[0]
    uc = np.ascontiguousarray(centres[:, 0], np.float64)
    vc = np.ascontiguousarray(centres[:, 1], np.float64)
    c0, c1, r0, r1, live = truncation_boxes(u, v, centres, radius)
    ptr, faces, n_tx, n_ty = tile_lists((H, W), live, c0, c1, r0, r1)
    clock("host_s", tile_entries=int(faces.shape[0]))
    face_arrays = [uc, vc, 0.5 / np.asarray(sigma, np.float64) ** 2, np.ascontiguousarray(C, np.float64),
                   np.ascontiguousarray(A, np.float64), np.ascontiguousarray(B, np.float64)]
    index_arrays = [a.astype(np.int32) for a in (c0, c1, r0, r1)]
    out_pixels = H * W * (BYTES_PER_PIXEL if derivatives else 8 * 3 + 1)
    _check_device_memory(out_pixels + sum(a.nbytes for a in face_arrays + index_arrays) + ptr.nbytes
                         + faces.nbytes + u.nbytes + v.nbytes)
    d_face = [cuda.to_device(a) for a in face_arrays]
    d_index = [cuda.to_device(a) for a in index_arrays]
    d_P = cuda.device_array((H, W, 3), np.float64)
    d_Pu = cuda.device_array((H, W, 3) if derivatives else (1, 1, 3), np.float64)
    d_Pv = cuda.device_array((H, W, 3) if derivatives else (1, 1, 3), np.float64)
    d_ok = cuda.device_array((H, W), np.bool_)
    d_grid = [cuda.to_device(a) for a in (u, v)]
    d_lists = [cuda.to_device(a) for a in (ptr, faces)]
    clock("upload_s")
    _tile_kernel[(n_tx, n_ty), (TILE, TILE)](*d_grid, *d_face, *d_index, *d_lists, n_tx, bool(derivatives),
                                             plain_sum_floor(log_g_ref), d_P, d_Pu, d_Pv, d_ok)
    clock("kernel_s")
    P, ok = _download(d_P), _download(d_ok)
    Pu, Pv = (_download(d_Pu), _download(d_Pv)) if derivatives else (None, None)
    clock("download_s")
    return P, Pu, Pv, ok


def _download(d):
    """A device array's copy on the host, in page-locked memory when :data:`PINNED` (faster copies, a
    slower allocation).
    """
    host = cuda.pinned_array(d.shape, d.dtype) if PINNED else np.empty(d.shape, d.dtype)
    d.copy_to_host(host)
    return host


class _Clock:
    """Records into ``profile`` the seconds since its last call (the GPU synchronized first)."""

    def __init__(self, profile):
        self.profile = profile
        self.t = time.perf_counter()

    def __call__(self, name, **extra):
        if self.profile is None:
            return
        cuda.synchronize()
        t = time.perf_counter()
        self.profile[name] = t - self.t
        self.profile.update(extra)
        self.t = t
