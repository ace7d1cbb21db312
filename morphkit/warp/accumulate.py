"""Fused accumulation of several warps into one buffer (the shadow atlas's
run-time blend), in bands of rows over a thread pool."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import NamedTuple, TypeVar

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..settings import WARP_THREADS
from . import scanline
from .maps import WarpMaps

T = TypeVar("T")

__all__ = ["Accumulation", "accumulate_warps", "band_pool", "in_bands", "roi_union", "PARALLEL_MIN_PIXELS"]


class Accumulation(NamedTuple):
    """The plan of one warp for the compiled fused pass of :func:`accumulate_warps`
    (:func:`morphkit.warp.scanline.accumulate`), made by
    :meth:`~morphkit.warp.MeshWarper.accumulation` for a mesh that provably does
    not overlap itself.

    Parameters
    ----------
    cov : numpy.ndarray
        ``(N, 2)`` float64 coverage geometry: the destination points ``(x, y)``
        (output pixels), the boundary pushed out by :data:`morphkit.tol.MESH_BOUNDARY_PX`.
    coef : numpy.ndarray
        ``(M, 6)`` float64 per-triangle affines ``A_src_dst`` (output pixel to
        source pixel) as ``[jxx, jyx, jxy, jyy, cx, cy]``.
    tris : numpy.ndarray
        ``(M, 3)`` int64 vertex indices.
    roi : tuple[int, int, int, int]
        ``(r0, r1, c0, c1)``: the output rows and columns the mesh can cover.
    """

    cov: np.ndarray
    coef: np.ndarray
    tris: np.ndarray
    roi: tuple[int, int, int, int]


#: ROI pixels (summed over the warps of one call) below which a fused
#: accumulation runs in the calling thread: below it, handing a band to a pool
#: thread costs more than the band's work saves (figures: ``docs/RESULTS.md``,
#: soft shadows).
PARALLEL_MIN_PIXELS = 1 << 16

_pool: ThreadPoolExecutor | None = None
_pool_workers = 0


def accumulate_warps(jobs: Sequence[tuple[Accumulation | WarpMaps, np.ndarray, np.ndarray, float]],
                     acc: np.ndarray) -> tuple[int, int, int, int]:
    """``acc += sum(weight * warp(src))`` over several warped two-plane sources.

    :class:`Accumulation` plans run in one compiled pass per warp, split into
    bands of rows over :data:`~morphkit.settings.WARP_THREADS` threads when the
    warps cover at least :data:`PARALLEL_MIN_PIXELS` (the bands write disjoint
    rows, so the result does not depend on the split); :class:`WarpMaps` plans
    by one ``cv2.remap`` per plane and ``cv2.scaleAdd``. The two agree up to
    OpenCV's 1/32 px quantisation of source positions.

    Parameters
    ----------
    jobs : sequence of (plan, src, active, weight)
        ``plan``: from :meth:`~morphkit.warp.MeshWarper.accumulation` (same
        output shape as ``acc``). ``src``: ``(2, h, w)`` float32 finite planes
        in source pixels (premultiplied coverage and value; finiteness is not
        checked). ``active``: ``(M,)`` bool, the triangles to visit
        (:meth:`~morphkit.warp.MeshWarper.triangles_touching` of ``src``'s
        support: the others read only zeros). ``weight``: float.
    acc : numpy.ndarray
        ``(2, H, W)`` float32, C-contiguous, output pixels; added to in place.
        Sampling is linear, 0 outside the mesh and outside ``src``.

    Returns
    -------
    tuple[int, int, int, int]
        ``(r0, r1, c0, c1)``: a box of output pixels holding every pixel
        written (empty, ``r1 <= r0``, when none was).

    Raises
    ------
    ValidationError
        ``acc`` or a ``src`` of the wrong dtype or shape.
    """
    if acc.dtype != np.float32 or acc.ndim != 3 or acc.shape[0] != 2 or not acc.flags.c_contiguous:
        raise ValidationError(expected_got("acc", "C-contiguous float32 (2, H, W)",
                                           f"{acc.dtype} {acc.shape}"))
    box = (0, 0, 0, 0)
    fused = []
    for plan, src, active, weight in jobs:
        if src.dtype != np.float32 or src.ndim != 3 or src.shape[0] != 2:
            raise ValidationError(expected_got("src", "float32 (2, h, w)", f"{src.dtype} {src.shape}"))
        if isinstance(plan, Accumulation):
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
        box = roi_union(box, plan.roi)
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
            if hi > lo and scanline.accumulate(plan.cov, plan.tris, plan.coef, active, src,
                                                weight, acc, lo, hi, c0, c1, bx):
                out = roi_union(out, (int(bx[0]), int(bx[1]), int(bx[2]), int(bx[3])))
        return out

    if n == 1:
        return roi_union(box, band(0))
    futures = [band_pool().submit(band, b) for b in range(1, n)]
    box = roi_union(box, band(0))
    for f in futures:
        box = roi_union(box, f.result())
    return box


def band_pool() -> ThreadPoolExecutor:
    """The shared pool of threads that run bands ``1`` to ``WARP_THREADS - 1`` of a
    banded pass (band 0 runs in the calling thread): :func:`accumulate_warps` and
    the shadow reprojection (:mod:`morphkit.shadow.reprojection`).

    Returns
    -------
    concurrent.futures.ThreadPoolExecutor
        ``max(WARP_THREADS - 1, 1)`` workers, made on the first call and made
        again (the old pool finishing its work) if ``WARP_THREADS`` has changed.
    """
    global _pool, _pool_workers
    workers = max(WARP_THREADS - 1, 1)
    if _pool is None or _pool_workers != workers:
        if _pool is not None:
            _pool.shutdown(wait=False)
        _pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="morphkit-warp")
        _pool_workers = workers
    return _pool


def in_bands(fn: Callable[[int], T], n: int) -> list[T]:
    """``[fn(0), ..., fn(n - 1)]``: band 0 in the calling thread, the others in :func:`band_pool`
    (a banded pass whose bands write disjoint parts of its output).

    Parameters
    ----------
    fn : callable
        ``fn(band) -> result`` (a compiled kernel that releases the GIL, for the bands to overlap).
    n : int
        The number of bands (1: ``fn(0)`` alone, no pool).

    Returns
    -------
    list
        Each band's result, in band order.
    """
    if n == 1:
        return [fn(0)]
    futures = [band_pool().submit(fn, b) for b in range(1, n)]
    return [fn(0)] + [f.result() for f in futures]


def roi_union(a: tuple[int, int, int, int], b: tuple[int, int, int, int]
              ) -> tuple[int, int, int, int]:
    """Bounding box of two ROIs.

    Parameters
    ----------
    a, b : tuple[int, int, int, int]
        ``(r0, r1, c0, c1)`` boxes of pixel rows ``r0:r1`` and columns
        ``c0:c1``; an empty one (``r1 <= r0``) adds nothing.

    Returns
    -------
    tuple[int, int, int, int]
        ``(r0, r1, c0, c1)`` holding both.
    """
    if a[1] <= a[0]:
        return b
    if b[1] <= b[0]:
        return a
    return (min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3]))
