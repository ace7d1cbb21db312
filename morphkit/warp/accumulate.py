"""Fused accumulation of several warps into one buffer (the shadow atlas's
run-time blend), in bands of rows over a thread pool."""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..settings import WARP_THREADS
from . import scanline as _scanline
from .maps import WarpMaps


class _Fused(NamedTuple):
    """A warp for the compiled fused pass (:func:`morphkit._scanline.accumulate`):
    coverage geometry, per-triangle affines, triangles and ROI (``_prepare``)."""

    cov: np.ndarray
    coef: np.ndarray
    tris: np.ndarray
    roi: tuple[int, int, int, int]


#: ROI pixels (summed over the warps of one call) below which a fused
#: accumulation runs in the calling thread: handing a band to a pool thread
#: costs some 50 us here (2-core VM), as much as ~10k pixels of work.
PARALLEL_MIN_PIXELS = 1 << 16

_pool: ThreadPoolExecutor | None = None


def _accumulate_warps(jobs: Sequence[tuple[_Fused | WarpMaps, np.ndarray, np.ndarray, float]],
                      acc: np.ndarray) -> tuple[int, int, int, int]:
    """``acc += sum(weight * warp(src))`` over ``jobs`` of ``(plan, src, active,
    weight)``: ``plan`` from :meth:`MeshWarper._accumulation`; ``src`` two
    finite float32 planes ``(2, h, w)`` (premultiplied coverage and value; not
    checked: the callers' sources are); ``active`` the triangles to visit
    (:meth:`MeshWarper.triangles_touching` of ``src``'s support: the others read
    only zeros); ``acc (2, H, W)`` float32, C-contiguous. Sampling is linear,
    0 outside the mesh and outside ``src``. Returns the ROI ``(r0, r1, c0, c1)``
    holding every pixel written (empty: none).

    Fused plans run in one compiled pass per warp, split into bands of rows
    over :data:`WARP_THREADS` threads when large enough (the bands write
    disjoint rows, so the result does not depend on the split); map plans by one
    ``cv2.remap`` per plane and ``cv2.scaleAdd``. The two agree up to OpenCV's
    1/32 px quantisation of source positions."""
    if acc.dtype != np.float32 or acc.ndim != 3 or acc.shape[0] != 2 or not acc.flags.c_contiguous:
        raise ValidationError(expected_got("acc", "C-contiguous float32 (2, H, W)",
                                           f"{acc.dtype} {acc.shape}"))
    box = (0, 0, 0, 0)
    fused = []
    for plan, src, active, weight in jobs:
        if src.dtype != np.float32 or src.ndim != 3 or src.shape[0] != 2:
            raise ValidationError(expected_got("src", "float32 (2, h, w)", f"{src.dtype} {src.shape}"))
        if isinstance(plan, _Fused):
            fused.append((plan, src, active, np.float32(weight)))
            continue
        if plan.map1 is None:
            continue
        r0, r1, c0, c1 = plan.roi
        px = np.empty((r1 - r0, c1 - c0), np.float32)
        for k in range(2):
            cv2.remap(src[k], plan.map1, plan.map2, cv2.INTER_LINEAR, dst=px,
                      borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            view = acc[k, r0:r1, c0:c1]  # rows strided, each row contiguous: a valid cv::Mat
            cv2.scaleAdd(px, float(weight), view, dst=view)
        box = _roi_union(box, plan.roi)
    if not fused:
        return box
    pixels = sum((p.roi[1] - p.roi[0]) * (p.roi[3] - p.roi[2]) for p, *_ in fused)
    n = WARP_THREADS if pixels >= PARALLEL_MIN_PIXELS else 1
    # one split of rows for all warps: bands of different threads never share a row
    top = min(p.roi[0] for p, *_ in fused)
    rows = max(p.roi[1] for p, *_ in fused) - top

    def band(b: int) -> tuple[int, int, int, int]:
        out = (0, 0, 0, 0)
        bx = np.empty(4, np.int64)
        b0, b1 = top + rows * b // n, top + rows * (b + 1) // n
        for plan, src, active, weight in fused:
            r0, r1, c0, c1 = plan.roi
            lo, hi = max(r0, b0), min(r1, b1)
            bx[:] = (hi, lo, c1, c0)
            if hi > lo and _scanline.accumulate(plan.cov, plan.tris, plan.coef, active, src,
                                                weight, acc, lo, hi, c0, c1, bx):
                out = _roi_union(out, (int(bx[0]), int(bx[1]), int(bx[2]), int(bx[3])))
        return out

    if n == 1:
        return _roi_union(box, band(0))
    futures = [_band_pool().submit(band, b) for b in range(1, n)]
    box = _roi_union(box, band(0))
    for f in futures:
        box = _roi_union(box, f.result())
    return box


def _band_pool() -> ThreadPoolExecutor:
    """The threads that run bands ``1 .. WARP_THREADS - 1`` (band 0 runs in the caller)."""
    global _pool
    if _pool is None:
        _pool = ThreadPoolExecutor(max_workers=max(WARP_THREADS - 1, 1),
                                   thread_name_prefix="morphkit-warp")
    return _pool


def _roi_union(a: tuple[int, int, int, int], b: tuple[int, int, int, int]
               ) -> tuple[int, int, int, int]:
    """Bounding box of two ROIs ``(r0, r1, c0, c1)``; an empty one (``r1 <= r0``) adds nothing."""
    if a[1] <= a[0]:
        return b
    if b[1] <= b[0]:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))
