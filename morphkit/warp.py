"""Piecewise-affine mesh warping: fast, exact at pixel centres, and reusable.

Convention
----------
* **Direction.** A warp is given by a *source* mesh ``src_pts`` (in the input
  image) and a *destination* mesh ``dst_pts`` (in the output image) with the same
  triangles. Each output pixel ``p`` inside destination triangle ``t`` is filled by
  sampling the input image at ``A_src_dst[t] @ (x, y, 1)``, the affine map taking
  the destination triangle onto the source triangle (a *backward* warp, like
  ``cv2.remap``/``skimage.transform.warp``). Points move *from* ``src_pts`` *to*
  ``dst_pts``.
* **Pixels.** ``(x, y)`` order, ``x`` = column, ``y`` = row, origin at the
  **centre** of the top-left pixel (see :mod:`morphkit.conventions`): the same
  convention as ``cv2.warpAffine`` and ``skimage.transform.warp``.
* **Coverage.** Output pixel centres are assigned to triangles exactly, with a
  top-left fill rule: a pixel centre ``(x, y)`` belongs to the triangle whose
  row section ``[x_left(y), x_right(y))`` contains ``x`` and whose rows
  ``[y_min, y_max)`` contain ``y``. Each covered centre belongs to exactly one
  triangle of a mesh without fold-overs; shared edges give both sides the same,
  bit-identical crossing. The mesh as a whole is *closed*: for coverage its
  boundary is pushed outwards by :data:`morphkit.tol.MESH_BOUNDARY_PX`, so
  centres on the boundary (e.g. the last row and column of an identity warp)
  are covered. Pixels outside every destination triangle get ``fill`` and
  ``mask == False``.
* **Sampling.** ``cv2.remap`` with ``BORDER_CONSTANT``: source positions outside
  the input image read ``fill`` (linearly blended at the image border). Like
  ``cv2.warpAffine``, OpenCV quantises sub-pixel positions to 1/32 px for
  ``"linear"``; the maps themselves are exact (float32).
* **Non-finite pixels** (e.g. depth maps whose background is ``+inf``) are safe
  with ``"linear"``: an output pixel whose bilinear footprint touches a non-finite
  source value (or a non-finite ``fill`` at the image border) takes the
  ``"nearest"`` value instead, so ``inf * 0`` never produces NaN. ``"nearest"``
  never mixes values and is the right choice for depth at silhouettes.

Fold-over policy
----------------
morphkit refuses degenerate warps rather than repairing them:
:class:`~morphkit.errors.FoldOverError` (naming the triangle indices) is raised
when a destination triangle's orientation differs from its source triangle's,
when its ``|area|`` is below :data:`morphkit.tol.TRIANGLE_AREA_PX2`, or when two
destination triangles cover the same output pixel centre (a mesh that folds over
while each triangle keeps its orientation). A source triangle of ~zero area is
refused the same way when the :class:`MeshWarper` is built. Bad arguments
(mismatched counts, NaN/inf points, triangle indices out of range, unknown
interpolation) raise :class:`~morphkit.errors.ValidationError`.

Reuse
-----
:class:`MeshWarper` keeps what depends on the source mesh only (validated points,
triangles, source orientation, boundary edges). :meth:`MeshWarper.maps` turns
destination points into :class:`WarpMaps` (per-pixel sampling maps of the mesh's
bounding box plus the coverage mask), which :meth:`WarpMaps.apply` applies to any
number of images or channels at the cost of one ``cv2.remap`` each.

How the maps are built (per call): per-triangle affines ``A_src_dst``, then by
default one compiled pass (:mod:`morphkit._scanline`, numba) that walks every
destination triangle's pixel rows and writes each covered pixel's source
position, counting coverage to detect overlaps unless the mesh is a disk
whose boundary stays simple (it then cannot overlap: no count needed, and
:attr:`WarpMaps.mask` is counted only when asked for). The numpy path below is the
reference (same coverage rule and edge arithmetic; ``tests/test_warp.py``
checks the two agree) and runs when numba is missing or
``MORPHKIT_WARP_NUMPY=1``: exact scanline runs ``[x_left, x_right)`` for every
(triangle, pixel row) pair; one integer sort of the runs along the image; then
either (<= 255 triangles) a uint8 triangle-label image expanded from the runs and
per-pixel affines by ``cv2.LUT`` + ``cv2.multiply``/``cv2.add``, or (more
triangles) the runs' slopes and offsets expanded with ``np.repeat``. Coordinate
planes and scratch buffers are kept per thread and output shape, and the map
buffers of a dropped :class:`WarpMaps` are recycled (only if nothing else refers
to them): on this kind of machine fresh page-faulted memory costs as much as the
arithmetic. ``MeshWarper`` and ``WarpMaps`` are safe to use from several
threads only if each thread has its own objects.

Fused accumulation (for callers that blend several warped sources, e.g. the
shadow atlas): :func:`_accumulate_warps` adds ``weight * warp(src)`` of
two-plane float32 sources straight into an accumulator, sampling each pixel's
source position bilinearly in the same compiled pass that finds it
(:func:`morphkit._scanline.accumulate`): no map images, no remap, only the
triangles :meth:`MeshWarper.triangles_touching` says can read nonzero source
pixels, and bands of rows on :data:`WARP_THREADS` threads. Source positions are
exact there (OpenCV quantises them to 1/32 px); meshes that might overlap
themselves, and the numpy reference mode, go through :meth:`MeshWarper.maps`.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from functools import lru_cache
from typing import Any, NamedTuple

import cv2
import numpy as np

from . import _scanline, tol
from .errors import FoldOverError, ValidationError, expected_got
from .validate import as_image, as_points, as_shape

__all__ = ["warp_mesh", "MeshWarper", "WarpMaps", "grid_triangles", "delaunay_triangles", "grid_shape"]

_INTERP = {"linear": cv2.INTER_LINEAR, "nearest": cv2.INTER_NEAREST}

#: Map coordinate given to output pixels outside the mesh: far enough outside any
#: image that cv2.remap writes the border value exactly (no blending).
_OUTSIDE = -64.0

#: dtypes cv2.remap handles natively; others are converted (see _to_cv).
_LUT_MAX_TRIANGLES = 255
_CV_DTYPES = (np.uint8, np.uint16, np.int16, np.float32, np.float64)


# --------------------------------------------------------------------------- topology


def grid_triangles(rows: int, cols: int) -> np.ndarray:
    """Triangles of a regular ``rows x cols`` grid of points in row-major order.

    Point ``(r, c)`` has index ``r * cols + c``. Each cell is split along its
    top-left to bottom-right diagonal into two triangles, listed cell by cell in
    row-major order.

    Parameters
    ----------
    rows, cols : int
        Number of point rows and columns, each ``>= 2``.

    Returns
    -------
    numpy.ndarray
        ``(2 * (rows - 1) * (cols - 1), 3)`` int32 vertex indices.
    """
    rows, cols = int(rows), int(cols)
    if rows < 2 or cols < 2:
        raise ValidationError(expected_got("grid_triangles rows, cols", ">= 2 each", (rows, cols)))
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(cols - 1), indexing="ij")
    a = (r * cols + c).ravel()
    b, d = a + 1, a + cols
    e = d + 1
    tris = np.empty((a.size, 2, 3), dtype=np.int32)
    tris[:, 0] = np.stack([a, b, e], axis=1)
    tris[:, 1] = np.stack([a, e, d], axis=1)
    return tris.reshape(-1, 3)


def delaunay_triangles(points: Any) -> np.ndarray:
    """Delaunay triangulation of ``points`` (``(N, 2)``, ``N >= 3``, not collinear).

    Returns ``(M, 3)`` int32 vertex indices, every triangle with positive signed
    area in the pixel frame (``x`` right, ``y`` down).
    """
    from scipy.spatial import Delaunay, QhullError

    pts = as_points(points, "points", min_count=3)
    try:
        tris = Delaunay(pts).simplices.astype(np.int32)
    except QhullError as exc:
        raise ValidationError(
            expected_got("points", "points spanning a 2-D area", "degenerate (e.g. collinear) points")
        ) from exc
    neg = _signed_area(pts[tris]) < 0
    tris[neg] = tris[neg][:, [0, 2, 1]]
    return tris


def grid_shape(points: Any) -> tuple[int, int] | None:
    """Return ``(rows, cols)`` if ``points`` is a row-major axis-aligned lattice, else None.

    A lattice here has ``rows, cols >= 2``, every row sharing one ``y`` and the
    same strictly monotonic ``x`` sequence, and rows strictly monotonic in ``y``
    (the spacing need not be uniform).
    """
    pts = np.asarray(points, dtype=np.float64)
    n = pts.shape[0]
    if pts.ndim != 2 or pts.shape[1] != 2 or n < 4:
        return None
    scale = max(1.0, float(np.max(np.abs(pts))))
    eps = 1e-9 * scale
    same_y = np.abs(pts[:, 1] - pts[0, 1]) <= eps
    cols = int(np.argmin(same_y)) if not same_y.all() else n
    if cols < 2 or n % cols:
        return None
    rows = n // cols
    if rows < 2:
        return None
    g = pts.reshape(rows, cols, 2)
    if np.max(np.abs(g[:, :, 1] - g[:, :1, 1])) > eps or np.max(np.abs(g[:, :, 0] - g[:1, :, 0])) > eps:
        return None
    dx, dy = np.diff(g[0, :, 0]), np.diff(g[:, 0, 1])
    if not ((dx > eps).all() or (dx < -eps).all()) or not ((dy > eps).all() or (dy < -eps).all()):
        return None
    return rows, cols


def _signed_area(v: np.ndarray) -> np.ndarray:
    """Signed areas of triangles ``v`` (M, 3, 2); positive = clockwise on screen."""
    d1 = v[:, 1] - v[:, 0]
    d2 = v[:, 2] - v[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def _list_indices(idx: np.ndarray, limit: int = 10) -> str:
    head = ", ".join(str(int(i)) for i in idx[:limit])
    return f"[{head}{', ...' if idx.size > limit else ''}] ({idx.size} in all)"


def _as_triangles(triangles: Any, n_points: int) -> np.ndarray:
    try:
        arr = np.asarray(triangles)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got("triangles", "an (M, 3) integer array", repr(triangles))) from exc
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] < 1:
        raise ValidationError(expected_got("triangles", "shape (M, 3) with M >= 1", f"shape {arr.shape}"))
    if arr.dtype.kind not in "iu":
        if arr.dtype.kind == "f" and np.all(np.isfinite(arr)) and np.all(arr == np.round(arr)):
            arr = arr.astype(np.int64)
        else:
            raise ValidationError(expected_got("triangles", "integer vertex indices", f"dtype {arr.dtype}"))
    bad = np.flatnonzero(((arr < 0) | (arr >= n_points)).any(axis=1))
    if bad.size:
        raise ValidationError(
            expected_got("triangles", f"indices in [0, {n_points})",
                         f"out-of-range indices in triangles {_list_indices(bad)}")
        )
    rep = np.flatnonzero((arr[:, 0] == arr[:, 1]) | (arr[:, 1] == arr[:, 2]) | (arr[:, 0] == arr[:, 2]))
    if rep.size:
        raise ValidationError(
            expected_got("triangles", "three distinct vertices each",
                         f"repeated vertices in triangles {_list_indices(rep)}")
        )
    return np.ascontiguousarray(arr, dtype=np.int32)


def _default_triangles(src: np.ndarray) -> np.ndarray:
    shape = grid_shape(src)
    if shape is not None:
        return grid_triangles(*shape)
    return delaunay_triangles(src)


# --------------------------------------------------------------------------- images


def _interp_flag(interpolation: Any) -> int:
    if interpolation not in _INTERP:
        raise ValidationError(expected_got("interpolation", "'linear' or 'nearest'", repr(interpolation)))
    return _INTERP[interpolation]


def _fill_values(fill: Any, channels: int, dtype: np.dtype) -> tuple[float, ...]:
    try:
        vals = np.broadcast_to(np.asarray(fill, dtype=np.float64).ravel(), (channels,))
    except (TypeError, ValueError) as exc:
        raise ValidationError(
            expected_got("fill", f"a number or {channels} numbers (one per channel)", repr(fill))
        ) from exc
    if dtype.kind != "f" and not np.all(np.isfinite(vals)):
        raise ValidationError(expected_got("fill", f"finite values for a {dtype} image", repr(fill)))
    return tuple(float(v) for v in vals)


def _to_cv(image: np.ndarray) -> np.ndarray:
    """Return ``image`` in a dtype cv2.remap accepts (values preserved exactly)."""
    dt = image.dtype
    if dt in _CV_DTYPES:
        return np.ascontiguousarray(image)
    if dt == np.bool_:
        return image.astype(np.uint8) * np.uint8(255)
    if dt == np.int8:
        return image.astype(np.int16)
    if dt == np.float16:
        return image.astype(np.float32)
    return image.astype(np.float64)  # (u)int32/64: exact below 2**53


def _from_cv(out: np.ndarray, dtype: np.dtype) -> np.ndarray:
    if out.dtype == dtype:
        return out
    if dtype == np.bool_:
        return out > 127
    if dtype.kind in "iu":
        info = np.iinfo(dtype)
        return np.clip(np.rint(out), info.min, info.max).astype(dtype)
    return out.astype(dtype)


def _remap(img: np.ndarray, m1: np.ndarray, m2: np.ndarray | None, flag: int,
           fill: tuple[float, ...]) -> np.ndarray:
    """cv2.remap with constant border ``fill``; any channel count (cv2 borders take <= 4).

    Channels go to OpenCV in groups of 4, 3 or 1, never 2: its vectorised remap
    covers 1, 3 and 4 channels, and a two-channel image takes a slower path that
    also samples with 1/32-pixel fixed-point weights (512^2 float32: 0.85 ms,
    against 2 x 0.25 ms one plane at a time), so every channel count gets the
    same interpolation.
    """
    c = 1 if img.ndim == 2 else img.shape[2]
    if c <= 4 and c != 2:
        border = fill + (0.0,) * (4 - c)
        return cv2.remap(img, m1, m2, flag, borderMode=cv2.BORDER_CONSTANT, borderValue=border)
    step = 1 if c == 2 else 4
    parts = [
        _remap(np.ascontiguousarray(img[:, :, k:k + step]), m1, m2, flag, fill[k:k + step])
        for k in range(0, c, step)
    ]
    parts = [p[:, :, None] if p.ndim == 2 else p for p in parts]
    return np.concatenate(parts, axis=2)


# --------------------------------------------------------------------------- maps


@lru_cache(maxsize=16)
def _xx(c0: int, c1: int, h: int) -> np.ndarray:
    """(h * (c1 - c0), 2) float32: the pixel x coordinate, twice, for each ROI pixel."""
    x = np.arange(c0, c1, dtype=np.float32)
    out = np.repeat(np.tile(x, h), 2).reshape(-1, 2)
    out.setflags(write=False)
    return out


_local = threading.local()


def _planes(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(X, Y, scratch)`` float32 ``shape`` arrays: pixel x, pixel y, and a per-thread work buffer.

    Kept per thread for the last few output shapes: reusing the buffers avoids
    fresh page faults on every call (they cost as much as the arithmetic).
    """
    cache = getattr(_local, "planes", None)
    if cache is None:
        cache = _local.planes = {}
    hit = cache.get(shape)
    if hit is None:
        if len(cache) >= 4:
            cache.pop(next(iter(cache)))
        h, w = shape
        X = np.empty(shape, dtype=np.float32)
        X[...] = np.arange(w, dtype=np.float32)
        Y = np.empty(shape, dtype=np.float32)
        Y[...] = np.arange(h, dtype=np.float32)[:, None]
        X.setflags(write=False)
        Y.setflags(write=False)
        hit = cache[shape] = (X, Y, np.empty(shape, dtype=np.float32))
    return hit


def _pooled(shape: tuple[int, int]) -> np.ndarray:
    """A float32 ``shape`` array, recycled from dead :class:`WarpMaps` when possible."""
    pool = getattr(_local, "pool", None)
    if pool:
        free = pool.get(shape)
        if free:
            return free.pop()
    return np.empty(shape, dtype=np.float32)


def _recycle(arr: np.ndarray | None) -> None:
    """Return a map buffer to this thread's pool, unless anything else still refers to it.

    (Fresh page-faulted buffers cost as much as computing the maps; a frame loop
    that drops last frame's WarpMaps reuses its buffers.)
    """
    # references: the caller's local, the argument, getrefcount's own argument
    if arr is None or arr.base is not None or sys.getrefcount(arr) > 3:
        return
    pool = getattr(_local, "pool", None)
    if pool is None:
        pool = _local.pool = {}
    free = pool.setdefault(arr.shape, [])
    if len(free) < 4:
        if len(pool) > 4:
            pool.clear()
            pool[arr.shape] = free
        free.append(arr)


class WarpMaps:
    """Per-pixel sampling maps of one warp, reusable across images and channels.

    Built by :meth:`MeshWarper.maps`. The maps cover the bounding box of the
    destination mesh clipped to the output (``roi``); the rest of the output is
    ``fill``. See the module docstring for the convention.

    Attributes
    ----------
    out_shape : tuple[int, int]
        ``(H, W)`` of the outputs.
    roi : tuple[int, int, int, int]
        ``(r0, r1, c0, c1)``: the rows ``r0:r1`` and columns ``c0:c1`` the maps cover.
    map1, map2 : numpy.ndarray or None
        The ``cv2.remap`` maps of the ROI: float32 source ``x`` and ``y``
        planes ``(r1 - r0, c1 - c0)``, or an interleaved ``(..., 2)`` map1 and
        ``map2 = None``. Pixels outside the mesh hold a far-outside position.
        ``map1`` is None when the mesh covers no pixel centre.
    """

    __slots__ = ("out_shape", "roi", "map1", "map2", "_lens", "_mask", "_covered", "_pooled")

    def __init__(self, out_shape: tuple[int, int], roi: tuple[int, int, int, int],
                 map1: np.ndarray | None, map2: np.ndarray | None,
                 run_lens: np.ndarray | None, covered: np.ndarray | None = None) -> None:
        self.out_shape = out_shape
        self.roi = roi
        self.map1 = map1
        self.map2 = map2
        self._lens = run_lens
        self._covered = covered  # ROI coverage, when the maps come from the compiled scanline
        self._mask: np.ndarray | None = None
        self._pooled = map2 is not None and (run_lens is not None or covered is not None)

    def __del__(self) -> None:
        try:
            if self._pooled:
                m1, m2 = self.map1, self.map2
                self.map1 = self.map2 = None
                _recycle(m1)
                _recycle(m2)
        except Exception:  # pragma: no cover - interpreter shutdown
            pass

    @property
    def map_xy(self) -> np.ndarray | None:
        """``(r1 - r0, c1 - c0, 2)`` float32 source ``(x, y)`` of each ROI pixel (a copy when split)."""
        if self.map1 is None or self.map2 is None:
            return self.map1
        return np.stack([self.map1, self.map2], axis=2)

    @property
    def mask(self) -> np.ndarray:
        """``(H, W)`` bool: True where an output pixel centre lies in a destination triangle."""
        if self._mask is None:
            m = np.zeros(self.out_shape, dtype=bool)
            if self.map1 is not None:
                r0, r1, c0, c1 = self.roi
                if self._covered is not None:
                    m[r0:r1, c0:c1] = self._covered() if callable(self._covered) else self._covered
                else:
                    pattern = np.zeros(self._lens.size, dtype=bool)
                    pattern[1::2] = True
                    m[r0:r1, c0:c1] = np.repeat(pattern, self._lens).reshape(r1 - r0, c1 - c0)
            m.setflags(write=False)
            self._mask = m
        return self._mask

    def apply(self, image: Any, *, interpolation: str = "linear", fill: Any = 0.0) -> np.ndarray:
        """Warp ``image`` with these maps.

        Parameters
        ----------
        image : numpy.ndarray
            ``(h, w)`` or ``(h, w, C)`` of any numeric or bool dtype; float images
            may hold NaN/inf (see the module docstring).
        interpolation : {"linear", "nearest"}
            Sampling of the source image.
        fill : float or sequence of float
            Value of uncovered pixels and of source positions outside ``image``;
            one number or one per channel.

        Returns
        -------
        numpy.ndarray
            ``out_shape`` (+ ``(C,)``), same dtype as ``image``.
        """
        img = as_image(image, "image", allow_nonfinite=True)
        flag = _interp_flag(interpolation)
        c = 1 if img.ndim == 2 else img.shape[2]
        fills = _fill_values(fill, c, img.dtype)
        src = _to_cv(img)
        if src.dtype == np.uint8 and img.dtype == np.bool_:
            fills = tuple(255.0 * (v != 0) for v in fills)
        h, w = self.out_shape
        full_shape = (h, w) if img.ndim == 2 else (h, w, c)
        if self.map1 is None:
            out = np.empty(full_shape, dtype=src.dtype)
            out[...] = fills if c > 1 else fills[0]
            return _from_cv(out, img.dtype)
        res = _remap(src, self.map1, self.map2, flag, fills)
        if res.ndim == 2 and img.ndim == 3:
            res = res[:, :, None]
        # inf * 0 -> NaN guard: footprints touching a non-finite value go nearest.
        # Only a non-finite source can make one; check whichever array is
        # smaller (the source is also more likely cached than the fresh output).
        if (flag == cv2.INTER_LINEAR and src.dtype.kind == "f"
                and not np.isfinite(src if src.size <= res.size else res).all()):
            bad = ~np.isfinite(res)
            if bad.any():
                near = _remap(src, self.map1, self.map2, cv2.INTER_NEAREST, fills)
                if near.ndim == 2 and img.ndim == 3:
                    near = near[:, :, None]
                res = np.where(bad, near, res)
        r0, r1, c0, c1 = self.roi
        if (r0, r1, c0, c1) != (0, h, 0, w):
            out = np.empty(full_shape, dtype=res.dtype)
            out[...] = fills if c > 1 else fills[0]
            out[r0:r1, c0:c1] = res
            res = out
        return _from_cv(res, img.dtype)


class _Fused(NamedTuple):
    """A warp for the compiled fused pass (:func:`morphkit._scanline.accumulate`):
    coverage geometry, per-triangle affines, triangles and ROI (``_prepare``)."""

    cov: np.ndarray
    coef: np.ndarray
    tris: np.ndarray
    roi: tuple[int, int, int, int]


#: Threads that share a fused accumulation (:func:`_accumulate_warps`), each
#: taking a band of rows: one per CPU this process may use, at most 4;
#: ``MORPHKIT_WARP_THREADS`` overrides.
WARP_THREADS = max(1, int(os.environ.get("MORPHKIT_WARP_THREADS", 0))
                   or min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                          else (os.cpu_count() or 1)))

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


class MeshWarper:
    """A reusable warp plan for a fixed source mesh (points + triangles).

    Parameters
    ----------
    src_pts : array_like
        ``(N, 2)`` source control points ``(x, y)`` in input-image pixels.
    triangles : array_like, optional
        ``(M, 3)`` vertex indices. Default: :func:`grid_triangles` when
        ``src_pts`` is a row-major axis-aligned lattice (:func:`grid_shape`),
        else :func:`delaunay_triangles` of ``src_pts``.

    Raises
    ------
    ValidationError
        Non-finite or malformed points, bad triangle indices.
    FoldOverError
        A source triangle has ``|area| < tol.TRIANGLE_AREA_PX2``.

    Notes
    -----
    Per call, :meth:`maps` costs O(M + covered rows) work for the per-triangle
    affines and the exact scanline runs, plus O(pixels in the mesh's bounding
    box) to expand the runs into float32 maps; applying them is one
    ``cv2.remap``. Measure with ``morphkit bench warp``.
    """

    def __init__(self, src_pts: Any, triangles: Any = None) -> None:
        self.src_pts = as_points(src_pts, "src_pts", min_count=3)
        self.src_pts.setflags(write=False)
        if triangles is None:
            tris = _default_triangles(self.src_pts)
        else:
            tris = _as_triangles(triangles, self.src_pts.shape[0])
        tris = np.ascontiguousarray(tris, dtype=np.int64)  # as the compiled kernels take them
        tris.setflags(write=False)
        self.triangles = tris
        self._src_v = self.src_pts[tris]  # (M, 3, 2)
        area = _signed_area(self._src_v)
        small = np.flatnonzero(np.abs(area) < tol.TRIANGLE_AREA_PX2)
        if small.size:
            raise FoldOverError(
                expected_got("source triangles", f"|area| >= {tol.TRIANGLE_AREA_PX2} px^2",
                             f"degenerate triangles {_list_indices(small)}")
            )
        self._src_sign = np.sign(area)
        self._boundary = _boundary_edges(tris, self.n_points)
        self._loop = _disk_boundary(tris, self._src_sign)

    @property
    def n_points(self) -> int:
        """Number of control points ``N``."""
        return int(self.src_pts.shape[0])

    def _check_dst(self, dst_pts: Any) -> np.ndarray:
        dst = as_points(dst_pts, "dst_pts")
        if dst.shape[0] != self.n_points:
            raise ValidationError(
                expected_got("dst_pts", f"{self.n_points} points (as many as src_pts)", f"{dst.shape[0]}")
            )
        return dst

    def maps(self, dst_pts: Any, out_shape: Sequence[int]) -> WarpMaps:
        """Compute the sampling maps (and coverage) for destination points ``dst_pts``.

        Parameters
        ----------
        dst_pts : array_like
            ``(N, 2)`` destination control points ``(x, y)`` in output pixels.
        out_shape : (int, int)
            ``(H, W)`` of the output.

        Returns
        -------
        WarpMaps

        Raises
        ------
        ValidationError
            Wrong point count, NaN/inf points, bad ``out_shape``.
        FoldOverError
            Flipped or ~zero-area destination triangles, or overlapping ones.
        """
        dst = self._check_dst(dst_pts)
        shape = as_shape(out_shape, "out_shape")
        return _build_maps(dst, self.triangles, self._src_v, self._src_sign, self._boundary, shape,
                           self._loop)

    def triangles_touching(self, support: Any) -> np.ndarray:
        """``(M,)`` bool: the triangles whose source footprint can read a nonzero
        pixel of ``support`` (``(h, w)``, the input image's nonzero pixels) with
        ``"linear"`` sampling: its bounding box, grown by 2 px, holds one. A warp
        of the other triangles only reads zeros (see :func:`_accumulate_warps`)."""
        sup = np.asarray(support)
        if sup.ndim != 2 or sup.size == 0:
            raise ValidationError(expected_got("support", "a non-empty (h, w) array", sup.shape))
        h, w = sup.shape
        ii = cv2.integral((sup != 0).view(np.uint8), sdepth=cv2.CV_32S)  # (h + 1, w + 1)
        lo = np.floor(self._src_v.min(axis=1)) - 2
        hi = np.ceil(self._src_v.max(axis=1)) + 3
        x0, x1 = (np.clip(v, 0, w).astype(np.intp) for v in (lo[:, 0], hi[:, 0]))
        y0, y1 = (np.clip(v, 0, h).astype(np.intp) for v in (lo[:, 1], hi[:, 1]))
        return (ii[y1, x1] - ii[y0, x1] - ii[y1, x0] + ii[y0, x0]) > 0

    def _accumulation(self, dst_pts: Any, shape: tuple[int, int]) -> _Fused | WarpMaps:
        """The plan of an accumulated warp to ``dst_pts`` (:func:`_accumulate_warps`):
        the compiled fused pass when the mesh provably does not overlap itself,
        else :meth:`maps` (also without numba, or with ``MORPHKIT_WARP_NUMPY=1``).

        Raises :class:`~morphkit.errors.FoldOverError` as :meth:`maps` does,
        before any pixel is touched."""
        dst = np.asarray(dst_pts, dtype=np.float64)
        if dst.shape != self.src_pts.shape or not np.isfinite(dst).all():
            dst = self._check_dst(dst_pts)  # raises the full message (a per-frame path: checked lean)
        if _scanline.AVAILABLE and not _NUMPY_ONLY and self._loop is not None:
            cov, coef, roi = _prepare(dst, self.triangles, self._src_v, self._src_sign,
                                      self._boundary, shape)
            r0, r1, c0, c1 = roi
            if r1 <= r0 or c1 <= c0:
                return WarpMaps(shape, roi, None, None, None)
            if _scanline.mesh_injective(cov, self.triangles, self._src_sign, self._loop):
                return _Fused(cov, coef, self.triangles, roi)
        return self.maps(dst, shape)

    def __call__(self, image: Any, dst_pts: Any, out_shape: Sequence[int], *,
                 interpolation: str = "linear", fill: Any = 0.0,
                 return_mask: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Warp ``image`` onto the destination mesh ``dst_pts``; see :func:`warp_mesh`."""
        _interp_flag(interpolation)
        wm = self.maps(dst_pts, out_shape)
        out = wm.apply(image, interpolation=interpolation, fill=fill)
        return (out, wm.mask) if return_mask else out


def _boundary_edges(tris: np.ndarray, n_points: int) -> np.ndarray:
    """``(B, 3)`` int: ``(a, b, c)`` for each mesh-boundary edge ``ab`` of triangle ``abc``."""
    a = tris.ravel()
    b = tris[:, [1, 2, 0]].ravel()
    c = tris[:, [2, 0, 1]].ravel()
    key = np.minimum(a, b).astype(np.int64) * n_points + np.maximum(a, b)
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    per_edge = counts[inverse]
    if per_edge.max() > 2:
        raise ValidationError(
            expected_got("triangles", "a manifold mesh (each edge in at most 2 triangles)",
                         f"an edge shared by {int(per_edge.max())} triangles")
        )
    once = per_edge == 1
    return np.stack([a[once], b[once], c[once]], axis=1)


def _disk_boundary(tris: np.ndarray, sign: np.ndarray) -> np.ndarray | None:
    """The boundary vertices of a mesh in cycle order, if the mesh is a
    consistently oriented topological disk; else None.

    With ``sign`` (each triangle's orientation in the source) each triangle is
    oriented ``(a, b, c)`` or ``(a, c, b)``; the mesh is a disk when no directed
    edge repeats (consistent orientation, a manifold), the directed edges without
    a reverse form one cycle through distinct vertices, the triangles are
    connected, and ``V - E + F == 1``. A disk whose warp keeps every triangle's
    orientation and maps the boundary to a simple polygon cannot overlap itself
    (:func:`morphkit._scanline.mesh_injective`): the compiled fill then skips
    counting coverage per pixel.
    """
    if len(tris) == 0:
        return None
    t = tris.astype(np.int64)
    flip = sign < 0
    t[flip] = t[flip][:, [0, 2, 1]]
    a = t.ravel()
    b = t[:, [1, 2, 0]].ravel()
    n = int(t.max()) + 1
    key = a * n + b
    if np.unique(key).size != key.size:
        return None
    bnd = ~np.isin(b * n + a, key)
    ba, bb = a[bnd], b[bnd]
    if ba.size < 3 or np.unique(ba).size != ba.size:
        return None
    nxt = dict(zip(ba.tolist(), bb.tolist(), strict=True))
    loop = [int(ba[0])]
    while True:
        v = nxt.get(loop[-1])
        if v is None:
            return None
        if v == loop[0]:
            break
        loop.append(v)
        if len(loop) > ba.size:
            return None
    if len(loop) != ba.size:
        return None  # several boundary loops (holes, several pieces)
    used = np.unique(t)
    n_edges = (key.size + ba.size) // 2
    if used.size - n_edges + len(t) != 1:
        return None
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    tri_id = np.repeat(np.arange(len(t)), 3)
    adj = coo_matrix((np.ones(key.size), (tri_id, a)), shape=(len(t), n)).tocsr()
    n_comp, _ = connected_components(adj @ adj.T, directed=False)
    if n_comp != 1:
        return None
    return np.asarray(loop, dtype=np.int64)


def _expand_boundary(dst: np.ndarray, boundary: np.ndarray) -> np.ndarray:
    """``dst`` with boundary vertices pushed outwards by ``tol.MESH_BOUNDARY_PX`` (closed coverage)."""
    if boundary.size == 0:
        return dst
    pa, pb, pc = dst[boundary[:, 0]], dst[boundary[:, 1]], dst[boundary[:, 2]]
    e = pb - pa
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    n /= np.maximum(np.hypot(n[:, 0], n[:, 1]), 1e-300)[:, None]
    inward = np.einsum("ij,ij->i", n, pc - pa) > 0
    n[inward] *= -1.0
    off = np.zeros_like(dst)
    np.add.at(off, boundary[:, 0], n)
    np.add.at(off, boundary[:, 1], n)
    return dst + tol.MESH_BOUNDARY_PX * off


def _prepare(dst: np.ndarray, tris: np.ndarray, src_v: np.ndarray, src_sign: np.ndarray,
             boundary: np.ndarray, shape: tuple[int, int]
             ) -> tuple[np.ndarray, np.ndarray, tuple[int, int, int, int]]:
    """Fold test, coverage geometry and per-triangle affines of one warp:
    ``(cov, coef, roi)``; ``roi`` is empty (``r1 <= r0`` or ``c1 <= c0``) when
    the mesh covers no pixel centre of the output (``coef`` is then unset).
    Compiled (:func:`morphkit._scanline.prepare_warp`) unless the numpy
    reference is forced; this numpy body also writes the fold-over message."""
    H, W = shape
    M = tris.shape[0]
    if _scanline.AVAILABLE and not _NUMPY_ONLY:
        cov = np.empty_like(dst)
        coef = np.empty((M, 6))
        n_bad, r0, r1, c0, c1 = _scanline.prepare_warp(
            dst, tris, src_v, src_sign, boundary, H, W, 2.0 * tol.TRIANGLE_AREA_PX2,
            tol.MESH_BOUNDARY_PX, cov, coef)
        if n_bad == 0:
            return cov, coef, (r0, r1, c0, c1)
    dv = dst[tris]  # (M, 3, 2)
    d1 = dv[:, 1] - dv[:, 0]
    d2 = dv[:, 2] - dv[:, 0]
    det = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]  # 2 * signed area
    bad = np.flatnonzero((np.sign(det) != src_sign) | (np.abs(det) < 2.0 * tol.TRIANGLE_AREA_PX2))
    if bad.size:
        raise FoldOverError(
            "destination triangles fold over (orientation flipped relative to the source, or "
            f"|area| < {tol.TRIANGLE_AREA_PX2} px^2): triangles {_list_indices(bad)}"
        )

    # Coverage geometry: the mesh closed at its boundary (pushed out by a hair).
    cov = _expand_boundary(dst, boundary)
    # ROI: bounding box of the pixel centres the mesh can cover (top-left rule).
    lo = cov.min(axis=0)
    hi = cov.max(axis=0)
    r0 = int(min(max(np.ceil(lo[1]), 0), H))
    r1 = int(min(max(np.ceil(hi[1]), 0), H))
    c0 = int(min(max(np.ceil(lo[0]), 0), W))
    c1 = int(min(max(np.ceil(hi[0]), 0), W))
    roi = (r0, r1, c0, c1)
    if r1 <= r0 or c1 <= c0:
        return cov, np.empty((0, 6)), roi

    # Affine A_src_dst per triangle: src = J (p - d0) + s0, J = S D^-1.
    sv = src_v
    s1 = sv[:, 1] - sv[:, 0]
    s2 = sv[:, 2] - sv[:, 0]
    inv = 1.0 / det
    # D^-1 = inv * [[d2y, -d2x], [-d1y, d1x]]
    i00, i01 = d2[:, 1] * inv, -d2[:, 0] * inv
    i10, i11 = -d1[:, 1] * inv, d1[:, 0] * inv
    coef = np.empty((M, 6))  # [jxx, jyx | jxy, jyy | cx, cy]
    coef[:, 0] = s1[:, 0] * i00 + s2[:, 0] * i10
    coef[:, 1] = s1[:, 1] * i00 + s2[:, 1] * i10
    coef[:, 2] = s1[:, 0] * i01 + s2[:, 0] * i11
    coef[:, 3] = s1[:, 1] * i01 + s2[:, 1] * i11
    coef[:, 4:] = sv[:, 0] - coef[:, 0:2] * dv[:, 0, 0:1] - coef[:, 2:4] * dv[:, 0, 1:2]
    return cov, coef, roi


def _build_maps(dst: np.ndarray, tris: np.ndarray, src_v: np.ndarray, src_sign: np.ndarray,
                boundary: np.ndarray, shape: tuple[int, int], loop: np.ndarray | None = None
                ) -> WarpMaps:
    cov, coef, roi = _prepare(dst, tris, src_v, src_sign, boundary, shape)
    r0, r1, c0, c1 = roi
    if r1 <= r0 or c1 <= c0:
        return WarpMaps(shape, roi, None, None, None)
    h, w = r1 - r0, c1 - c0
    M = tris.shape[0]
    if _scanline.AVAILABLE and not _NUMPY_ONLY:
        return _compiled_maps(shape, roi, cov, tris, coef, src_sign, loop)

    # Scanline runs, exact at pixel centres. Vertices sorted by y: v0 top, v2 bottom.
    cv_ = cov[tris]
    order = np.argsort(cv_[:, :, 1], axis=1)
    vs = np.take_along_axis(cv_, order[:, :, None], axis=1)
    x0, y0 = vs[:, 0, 0], vs[:, 0, 1]
    x1, y1 = vs[:, 1, 0], vs[:, 1, 1]
    x2, y2 = vs[:, 2, 0], vs[:, 2, 1]
    # Pieces: 2t = upper half (rows [y0, y1), edges v0v2 & v0v1), 2t+1 = lower half
    # (rows [y1, y2), edges v0v2 & v1v2). An edge with top end (xt, yt) and slope
    # s = dx/dy crosses row y at q + y * s, q = xt - yt * s: the two triangles
    # sharing an edge compute bit-identical crossings (same operands, same order).
    ys = np.empty((M, 3))
    ys[:, 0], ys[:, 1], ys[:, 2] = y0, y1, y2
    np.ceil(ys, out=ys)
    np.clip(ys, r0, r1, out=ys)
    yr = ys.astype(np.int64)
    ystart = yr[:, 0:2].ravel()  # (2M,) piece first rows
    cnt = np.maximum(yr[:, 1:3].ravel() - ystart, 0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        edge = np.empty((M, 3, 2))  # per triangle: edges v0v2, v0v1, v1v2 as (q, s)
        edge[:, 0, 1] = (x2 - x0) / (y2 - y0)
        edge[:, 1, 1] = (x1 - x0) / (y1 - y0)
        edge[:, 2, 1] = (x2 - x1) / (y2 - y1)
        edge[:, 0, 0] = x0 - y0 * edge[:, 0, 1]
        edge[:, 1, 0] = x0 - y0 * edge[:, 1, 1]
        edge[:, 2, 0] = x1 - y1 * edge[:, 2, 1]
    n = int(cnt.sum())
    if n == 0:
        return WarpMaps(shape, roi, None, None, None)
    long_ = np.repeat(np.repeat(edge[:, 0], 2, axis=0), cnt, axis=0)  # (n, 2)
    short = np.repeat(edge[:, 1:3].reshape(2 * M, 2), cnt, axis=0)
    yi = np.arange(n, dtype=np.int64)
    yi += np.repeat(ystart - (np.cumsum(cnt) - cnt), cnt)
    yf = yi.astype(np.float64)
    xa = long_[:, 1] * yf
    xa += long_[:, 0]
    xb = short[:, 1] * yf
    xb += short[:, 0]
    xl = np.minimum(xa, xb)
    xr = np.maximum(xa, xb, out=xa)
    np.ceil(xl, out=xl)
    np.ceil(xr, out=xr)
    np.clip(xl, c0, c1, out=xl)
    np.clip(xr, c0, c1, out=xr)
    rowbase = (yi - r0) * w - c0
    start = rowbase + xl.astype(np.int64)
    end = rowbase + xr.astype(np.int64)
    empty = end <= start
    k = n - int(np.count_nonzero(empty))
    if k == 0:
        return WarpMaps(shape, roi, None, None, None)
    # Sort runs by start with one int64 sort of start | length | triangle packed
    # into a key (no argsort, no gathers); argsort fallback for huge inputs.
    tri = np.repeat(np.arange(2 * M, dtype=np.int64) >> 1, cnt)
    lenb = int(w).bit_length()
    trib = max(1, (M - 1).bit_length())
    if (h * w).bit_length() + lenb + trib <= 62:
        key = start << (lenb + trib)
        key |= (end - start) << trib
        key |= tri
        key[empty] = np.iinfo(np.int64).max
        key.sort()
        key = key[:k]
        tri = key & ((1 << trib) - 1)
        start = key >> (lenb + trib)
        end = start + ((key >> trib) & ((1 << lenb) - 1))
    else:  # pragma: no cover - gigapixel outputs with millions of triangles
        start[empty] = np.iinfo(np.int64).max
        o = np.argsort(start)[:k]
        start, end, tri = start[o], end[o], tri[o]
    gaps = np.empty(k + 1, dtype=np.int64)
    gaps[0] = start[0]
    np.subtract(start[1:], end[:-1], out=gaps[1:-1])
    gaps[-1] = h * w - end[-1]
    if gaps.min() < 0:
        j = int(np.argmin(gaps[1:-1]))
        pair = np.unique(tri[j:j + 2])
        raise FoldOverError(
            "destination triangles overlap (the mesh folds over although each triangle keeps its "
            f"orientation): triangles {_list_indices(pair)} both cover pixels of row "
            f"{int(start[j + 1] // w) + r0}"
        )
    lens = np.empty(2 * k + 1, dtype=np.int64)
    lens[0::2] = gaps
    np.subtract(end, start, out=lens[1::2])
    if M <= _LUT_MAX_TRIANGLES:
        # Few triangles: expand uint8 triangle labels, then per-pixel affines by cv2.LUT.
        lab = np.full(2 * k + 1, 255, dtype=np.uint8)
        lab[1::2] = tri
        labels = np.repeat(lab, lens).reshape(h, w)
        tables = np.zeros((6, 256), dtype=np.float32)
        tables[:, :M] = coef.T
        tables[4:6, 255] = _OUTSIDE
        X, Y, scratch = _planes(shape)
        X, Y, t = X[r0:r1, c0:c1], Y[r0:r1, c0:c1], scratch[:h, :w]
        maps = []
        for j in range(2):  # x then y: A[j,0] * X + A[j,1] * Y + c[j]
            mj = _pooled((h, w))
            cv2.LUT(labels, tables[j], dst=mj)
            cv2.multiply(mj, X, dst=mj)
            cv2.LUT(labels, tables[2 + j], dst=t)
            cv2.multiply(t, Y, dst=t)
            cv2.add(mj, t, dst=mj)
            cv2.LUT(labels, tables[4 + j], dst=t)
            cv2.add(mj, t, dst=mj)
            maps.append(mj)
        return WarpMaps(shape, roi, maps[0], maps[1], lens)
    c = coef[tri]
    run_y = (start // w + r0).astype(np.float64)
    slope = np.zeros((2 * k + 1, 2), dtype=np.float32)
    off = np.full((2 * k + 1, 2), _OUTSIDE, dtype=np.float32)
    slope[1::2] = c[:, 0:2]
    off[1::2] = c[:, 2:4] * run_y[:, None] + c[:, 4:6]
    m = np.repeat(slope, lens, axis=0)
    np.multiply(m, _xx(c0, c1, h), out=m)
    m += np.repeat(off, lens, axis=0)
    return WarpMaps(shape, roi, m.reshape(h, w, 2), None, lens)


#: Force the numpy reference path (tests compare it with the compiled one).
_NUMPY_ONLY = _scanline.NUMPY_ONLY
_NO_COUNT = np.empty((0, 0), dtype=np.uint8)


def _compiled_maps(shape: tuple[int, int], roi: tuple[int, int, int, int], cov: np.ndarray,
                   tris: np.ndarray, coef: np.ndarray, sign: np.ndarray,
                   loop: np.ndarray | None) -> WarpMaps:
    """Maps by the compiled scanline (:mod:`morphkit._scanline`): same coverage
    rule and edge arithmetic as the numpy path below, one pass over the pixels.
    A disk mesh (``loop``, :func:`_disk_boundary`) that provably does not
    overlap itself is filled without counting coverage per pixel."""
    r0, r1, c0, c1 = roi
    h, w = r1 - r0, c1 - c0
    mx, my = _pooled((h, w)), _pooled((h, w))
    if loop is not None and _scanline.mesh_injective(cov, tris, sign, loop):
        # No overlap possible: fill without counting; the mask, when asked for,
        # is counted then (the same kernel as below).
        top = _scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, _OUTSIDE, mx, my, _NO_COUNT,
                                  _scanline.n_bands(h, w), False)
        if top == 0:
            return WarpMaps(shape, roi, None, None, None)

        def covered() -> np.ndarray:
            count = np.empty((h, w), dtype=np.uint8)
            sx, sy = np.empty((h, w), np.float32), np.empty((h, w), np.float32)
            _scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, _OUTSIDE, sx, sy, count,
                                _scanline.n_bands(h, w), True)
            return count.view(bool)

        return WarpMaps(shape, roi, mx, my, None, covered)
    count = np.empty((h, w), dtype=np.uint8)
    top = _scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, _OUTSIDE, mx, my, count,
                              _scanline.n_bands(h, w), True)
    if top > 1:
        y, x = np.unravel_index(int(np.argmax(count > 1)), count.shape)
        y, x = int(y) + r0, int(x) + c0
        raise FoldOverError(
            "destination triangles overlap (the mesh folds over although each triangle keeps its "
            f"orientation): triangles {_list_indices(_covering(cov, tris, x, y))} both cover "
            f"pixel ({x}, {y})"
        )
    if top == 0:
        return WarpMaps(shape, roi, None, None, None)
    return WarpMaps(shape, roi, mx, my, None, count.view(bool))


def _covering(cov: np.ndarray, tris: np.ndarray, x: int, y: int) -> np.ndarray:
    """Indices of the triangles whose closure contains the point ``(x, y)`` (error messages)."""
    v = cov[tris]
    p = np.array([x, y], dtype=np.float64)

    def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return (b[:, 0] - a[:, 0]) * (p[1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (p[0] - a[:, 0])

    d = np.stack([cross(v[:, 0], v[:, 1]), cross(v[:, 1], v[:, 2]), cross(v[:, 2], v[:, 0])], 1)
    return np.flatnonzero(np.all(d >= -1e-9, axis=1) | np.all(d <= 1e-9, axis=1))


def warp_mesh(image: Any, src_pts: Any, dst_pts: Any, out_shape: Sequence[int], *,
              triangles: Any = None, interpolation: str = "linear", fill: Any = 0.0,
              return_mask: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Piecewise-affine warp of ``image`` moving ``src_pts`` onto ``dst_pts``.

    Convention: each destination triangle ``dst_pts[tri]`` is filled by sampling
    ``image`` at the affinely corresponding point of the source triangle
    ``src_pts[tri]`` (a backward map, as ``cv2.remap``); points are ``(x, y)``
    with the origin at the centre of the top-left pixel. Details, fill rule and
    the fold-over/non-finite policy: see :mod:`morphkit.warp`.

    Parameters
    ----------
    image : numpy.ndarray
        ``(h, w)`` or ``(h, w, C)``, any numeric or bool dtype (uint8 RGB/RGBA,
        float32 depth with ``+inf`` background, ...).
    src_pts, dst_pts : array_like
        ``(N, 2)`` control points in the input and the output image.
    out_shape : (int, int)
        ``(H, W)`` of the output.
    triangles : array_like, optional
        ``(M, 3)`` vertex indices; default grid topology for lattice ``src_pts``,
        else Delaunay of ``src_pts``.
    interpolation : {"linear", "nearest"}
    fill : float or sequence of float
        Value outside the mesh (and for source positions outside ``image``).
    return_mask : bool
        Also return the ``(H, W)`` bool mask of pixels covered by the mesh.

    Returns
    -------
    numpy.ndarray or (numpy.ndarray, numpy.ndarray)
        The warped image (``out_shape`` + channels, dtype of ``image``), and the
        mask when ``return_mask``.

    Raises
    ------
    ValidationError
        Mismatched point counts, NaN/inf points, bad triangles, bad interpolation.
    FoldOverError
        Flipped, ~zero-area or overlapping destination triangles.
    """
    return MeshWarper(src_pts, triangles)(image, dst_pts, out_shape, interpolation=interpolation,
                                          fill=fill, return_mask=return_mask)
