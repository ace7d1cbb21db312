"""Building :class:`~morphkit.warp.WarpMaps`: fold test, per-triangle affines,
the compiled scanline fill and the numpy reference path."""

from __future__ import annotations

import cv2
import numpy as np

from .. import tol
from ..errors import FoldOverError
from ..settings import use_compiled
from . import scanline
from .maps import OUTSIDE, WarpMaps
from .mesh import list_indices
from .pool import coordinate_planes, map_buffer, pixel_x_pairs

__all__ = ["prepare", "build_maps"]

_LUT_MAX_TRIANGLES = 255


def _expand_boundary(dst: np.ndarray, boundary: np.ndarray) -> np.ndarray:
    """``dst`` with boundary vertices pushed outwards by ``tol.MESH_BOUNDARY_PX`` (closed coverage)."""
    if boundary.size == 0:
        return dst
    pa, pb, pc = dst[boundary[:, 0]], dst[boundary[:, 1]], dst[boundary[:, 2]]
    e = pb - pa
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    n /= np.maximum(np.hypot(n[:, 0], n[:, 1]), tol.ZERO)[:, None]
    inward = np.einsum("ij,ij->i", n, pc - pa) > 0
    n[inward] *= -1.0
    off = np.zeros_like(dst)
    np.add.at(off, boundary[:, 0], n)
    np.add.at(off, boundary[:, 1], n)
    return dst + tol.MESH_BOUNDARY_PX * off


def prepare(dst: np.ndarray, tris: np.ndarray, src_v: np.ndarray, src_sign: np.ndarray,
            boundary: np.ndarray, shape: tuple[int, int]
            ) -> tuple[np.ndarray, np.ndarray, tuple[int, int, int, int]]:
    """Fold test, coverage geometry and per-triangle affines of one warp.

    Compiled (:func:`morphkit.warp.scanline.prepare_warp`) unless the numpy
    reference is forced (:func:`morphkit.settings.use_compiled`); this numpy
    body also writes the fold-over message.

    Parameters
    ----------
    dst : numpy.ndarray
        ``(N, 2)`` float64 destination points ``(x, y)``, output pixels.
    tris : numpy.ndarray
        ``(M, 3)`` int64 vertex indices.
    src_v : numpy.ndarray
        ``(M, 3, 2)`` float64 source triangle vertices, input pixels.
    src_sign : numpy.ndarray
        ``(M,)`` float64 orientation of each source triangle (``-1`` or ``1``).
    boundary : numpy.ndarray
        ``(B, 3)`` boundary edges (:func:`morphkit.warp.mesh.boundary_edges`).
    shape : tuple[int, int]
        ``(H, W)`` of the output.

    Returns
    -------
    cov : numpy.ndarray
        ``(N, 2)`` float64: ``dst`` with the boundary pushed out by
        :data:`morphkit.tol.MESH_BOUNDARY_PX` (the coverage geometry).
    coef : numpy.ndarray
        ``(M, 6)`` float64 affines ``A_src_dst`` as ``[jxx, jyx, jxy, jyy, cx, cy]``
        (unset when ``roi`` is empty).
    roi : tuple[int, int, int, int]
        ``(r0, r1, c0, c1)`` of the pixel centres the mesh can cover; empty
        (``r1 <= r0`` or ``c1 <= c0``) when it covers none.

    Raises
    ------
    FoldOverError
        A destination triangle flips or has ``|area| < tol.TRIANGLE_AREA_PX2``.
    """
    H, W = shape
    M = tris.shape[0]
    if use_compiled(scanline.prepare_warp):
        cov = np.empty_like(dst)
        coef = np.empty((M, 6))
        n_bad, r0, r1, c0, c1 = scanline.prepare_warp(
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
            f"|area| < {tol.TRIANGLE_AREA_PX2} px^2): triangles {list_indices(bad)}"
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


def build_maps(dst: np.ndarray, tris: np.ndarray, src_v: np.ndarray, src_sign: np.ndarray,
               boundary: np.ndarray, shape: tuple[int, int], loop: np.ndarray | None = None
               ) -> WarpMaps:
    """The :class:`~morphkit.warp.WarpMaps` of one warp (:func:`prepare`, then the fill).

    By the compiled scanline unless the numpy reference is forced
    (:func:`morphkit.settings.use_compiled`); both cover the same pixel centres.

    Parameters
    ----------
    dst, tris, src_v, src_sign, boundary, shape
        As :func:`prepare`.
    loop : numpy.ndarray or None
        ``(B,)`` boundary cycle of a disk mesh (:func:`morphkit.warp.mesh.disk_boundary`):
        the compiled fill then skips counting coverage when the warp provably
        does not overlap itself.

    Returns
    -------
    WarpMaps

    Raises
    ------
    FoldOverError
        Flipped or ~zero-area destination triangles, or overlapping ones.
    """
    cov, coef, roi = prepare(dst, tris, src_v, src_sign, boundary, shape)
    r0, r1, c0, c1 = roi
    if r1 <= r0 or c1 <= c0:
        return WarpMaps(shape, roi, None, None, None)
    h, w = r1 - r0, c1 - c0
    M = tris.shape[0]
    if use_compiled(scanline.fill_maps):
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
            f"orientation): triangles {list_indices(pair)} both cover pixels of row "
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
        tables[4:6, 255] = OUTSIDE
        X, Y, scratch = coordinate_planes(shape)
        X, Y, t = X[r0:r1, c0:c1], Y[r0:r1, c0:c1], scratch[:h, :w]
        maps = []
        for j in range(2):  # x then y: A[j,0] * X + A[j,1] * Y + c[j]
            mj = map_buffer((h, w))
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
    off = np.full((2 * k + 1, 2), OUTSIDE, dtype=np.float32)
    slope[1::2] = c[:, 0:2]
    off[1::2] = c[:, 2:4] * run_y[:, None] + c[:, 4:6]
    m = np.repeat(slope, lens, axis=0)
    np.multiply(m, pixel_x_pairs(c0, c1, h), out=m)
    m += np.repeat(off, lens, axis=0)
    return WarpMaps(shape, roi, m.reshape(h, w, 2), None, lens)


_NO_COUNT = np.empty((0, 0), dtype=np.uint8)


def _compiled_maps(shape: tuple[int, int], roi: tuple[int, int, int, int], cov: np.ndarray,
                   tris: np.ndarray, coef: np.ndarray, sign: np.ndarray,
                   loop: np.ndarray | None) -> WarpMaps:
    """Maps by the compiled scanline (:mod:`morphkit.warp.scanline`): same coverage
    rule and edge arithmetic as the numpy path below, one pass over the pixels.
    A disk mesh (``loop``, :func:`morphkit.warp.mesh.disk_boundary`) that provably does not
    overlap itself is filled without counting coverage per pixel."""
    r0, r1, c0, c1 = roi
    h, w = r1 - r0, c1 - c0
    mx, my = map_buffer((h, w)), map_buffer((h, w))
    if loop is not None and scanline.mesh_injective(cov, tris, sign, loop):
        # No overlap possible: fill without counting; the mask, when asked for,
        # is counted then (the same kernel as below).
        top = scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, OUTSIDE, mx, my, _NO_COUNT,
                                  scanline.n_bands(h, w), False)
        if top == 0:
            return WarpMaps(shape, roi, None, None, None)

        def covered() -> np.ndarray:
            count = np.empty((h, w), dtype=np.uint8)
            sx, sy = np.empty((h, w), np.float32), np.empty((h, w), np.float32)
            scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, OUTSIDE, sx, sy, count,
                                scanline.n_bands(h, w), True)
            return count.view(bool)

        return WarpMaps(shape, roi, mx, my, None, covered)
    count = np.empty((h, w), dtype=np.uint8)
    top = scanline.fill_maps(cov, tris, coef, r0, r1, c0, c1, OUTSIDE, mx, my, count,
                              scanline.n_bands(h, w), True)
    if top > 1:
        y, x = np.unravel_index(int(np.argmax(count > 1)), count.shape)
        y, x = int(y) + r0, int(x) + c0
        raise FoldOverError(
            "destination triangles overlap (the mesh folds over although each triangle keeps its "
            f"orientation): triangles {list_indices(_covering(cov, tris, x, y))} both cover "
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
    eps = tol.REL_EQUAL  # px^2: on an edge up to rounding of pixel-scale coordinates
    return np.flatnonzero(np.all(d >= -eps, axis=1) | np.all(d <= eps, axis=1))
