"""Compiled scanline fill of piecewise-affine warp maps (numba).

One pass over the destination triangles writes, for every output pixel centre a
triangle covers, its source position ``A_src_dst[t] @ (x, y, 1)``; pixels no
triangle covers get :data:`OUTSIDE`. The coverage rule and the edge arithmetic
are exactly those of :func:`morphkit.warp._build_maps`' numpy path (the
reference implementation, kept for tests and for machines without numba): rows
``[ceil(y_top), ceil(y_bottom))``, columns ``[ceil(x_left), ceil(x_right))``,
each edge crossing computed as ``s * y + q`` from the edge's own top end, so
triangles sharing an edge agree bit for bit. Each pixel counts the triangles
covering it; a count above 1 is a fold-over, reported by the caller.

numba earns its place here: the numpy path needs ~10 full-image passes (runs,
sort, repeat, LUTs, products); the kernel touches each pixel once. The rows are
split into bands filled in parallel (one per numba thread, ``prange``); a row's
values depend only on the triangles' edges, so the bands change no value.
"""

from __future__ import annotations

import math
import os

import numpy as np

# numba's parallel bands run on OpenMP (libgomp) where available, whose idle
# threads spin-wait by default: measured here, they halved the speed of the
# cv2.remap that follows every fill (0.48 vs 0.25 ms at 512^2 on 2 cores).
# Passive waiting keeps the cores free for OpenCV; set before libgomp loads, and
# a value the user set wins.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

try:  # optional at import time; morphkit.warp falls back to numpy without it
    import numba
except ImportError:  # pragma: no cover - numba is a dependency
    numba = None

__all__ = ["AVAILABLE", "fill_maps"]

AVAILABLE = numba is not None

#: ``MORPHKIT_WARP_NUMPY=1`` forces the numpy reference path of every compiled
#: kernel (warp maps, shadow lookup, fold relaxation); tests compare the two.
NUMPY_ONLY = bool(os.environ.get("MORPHKIT_WARP_NUMPY"))


def _fill_band(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
               c1: int, b0: int, b1: int, out_outside: float, mx: np.ndarray, my: np.ndarray,
               count: np.ndarray) -> int:
    """Fill rows ``[b0, b1)`` (absolute, inside ``[r0, r1)``) of ``mx``, ``my``
    (``(r1 - r0, c1 - c0)`` float32) and ``count`` (uint8: how many triangles
    cover each pixel; more than 1 is a fold-over, which the caller checks; the
    maps then hold the last triangle's values). Returns the band's largest count.
    Each row is computed from the triangle's edges alone, so splitting the image
    into bands changes no value.
    """
    w = c1 - c0
    for i in range(b0 - r0, b1 - r0):
        for j in range(w):
            count[i, j] = 0
    M = tris.shape[0]
    for t in range(M):
        ia = tris[t, 0]
        ib = tris[t, 1]
        ic = tris[t, 2]
        # sort the three vertices by y (stable, as numpy's argsort on 3 elements)
        v0, v1, v2 = ia, ib, ic
        if cov[v1, 1] < cov[v0, 1]:
            v0, v1 = v1, v0
        if cov[v2, 1] < cov[v1, 1]:
            v1, v2 = v2, v1
            if cov[v1, 1] < cov[v0, 1]:
                v0, v1 = v1, v0
        x0 = cov[v0, 0]
        y0 = cov[v0, 1]
        x1 = cov[v1, 0]
        y1 = cov[v1, 1]
        x2 = cov[v2, 0]
        y2 = cov[v2, 1]
        sl = (x2 - x0) / (y2 - y0)
        ql = x0 - y0 * sl
        su = (x1 - x0) / (y1 - y0)
        qu = x0 - y0 * su
        sd = (x2 - x1) / (y2 - y1)
        qd = x1 - y1 * sd
        ya = min(max(math.ceil(y0), b0), b1)
        yb = min(max(math.ceil(y1), b0), b1)
        yc = min(max(math.ceil(y2), b0), b1)
        a00 = coef[t, 0]
        a10 = coef[t, 1]
        a01 = coef[t, 2]
        a11 = coef[t, 3]
        bx = coef[t, 4]
        by = coef[t, 5]
        for piece in range(2):
            if piece == 0:
                ys, ye, s, q = ya, yb, su, qu
            else:
                ys, ye, s, q = yb, yc, sd, qd
            for y in range(ys, ye):
                yf = float(y)
                xa = sl * yf
                xa += ql
                xb = s * yf
                xb += q
                xl = min(max(math.ceil(min(xa, xb)), c0), c1)
                xr = min(max(math.ceil(max(xa, xb)), c0), c1)
                if xr <= xl:
                    continue
                ox = a01 * yf + bx
                oy = a11 * yf + by
                row = y - r0
                for x in range(xl, xr):
                    col = x - c0
                    count[row, col] += 1
                    xf = float(x)
                    mx[row, col] = a00 * xf + ox
                    my[row, col] = a10 * xf + oy
    top = 0
    for i in range(b0 - r0, b1 - r0):  # pixels no triangle covers
        for j in range(w):
            c = count[i, j]
            if c == 0:
                mx[i, j] = out_outside
                my[i, j] = out_outside
            elif c > top:
                top = c
    return top


def _fill_maps(cov: np.ndarray, tris: np.ndarray, coef: np.ndarray, r0: int, r1: int, c0: int,
               c1: int, out_outside: float, mx: np.ndarray, my: np.ndarray, count: np.ndarray,
               n_bands: int) -> int:
    """Fill the maps in ``n_bands`` bands of rows, in parallel (numba ``prange``:
    the bands write disjoint rows); returns the largest count (0: nothing covered,
    > 1: a fold-over)."""
    tops = np.zeros(n_bands, np.int64)
    h = r1 - r0
    for b in _prange(n_bands):
        tops[b] = _fill_band(cov, tris, coef, r0, r1, c0, c1, r0 + (h * b) // n_bands,
                             r0 + (h * (b + 1)) // n_bands, out_outside, mx, my, count)
    return int(tops.max())


#: Rows per band below which the fill runs in one band (thread start-up costs more).
MIN_BAND_ROWS = 64


def n_bands(rows: int) -> int:
    """How many bands to fill ``rows`` rows in: one per numba thread, at least
    :data:`MIN_BAND_ROWS` rows each."""
    threads = numba.get_num_threads() if numba is not None else 1
    return max(1, min(threads, rows // MIN_BAND_ROWS))


if numba is not None:
    _prange = numba.prange
    _fill_band = numba.njit(cache=True, nogil=True, error_model="numpy")(_fill_band)
    fill_maps = numba.njit(cache=True, nogil=True, parallel=True, error_model="numpy")(_fill_maps)
else:  # pragma: no cover
    _prange = range
    fill_maps = _fill_maps
