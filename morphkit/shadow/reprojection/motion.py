"""How a map's pixels move (:class:`Reprojection`), the reprojection's measured
constants, and the per-row analysis of a map that bounds where its rows land
(conventions: :mod:`morphkit.shadow.reprojection`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...errors import ValidationError, expected_got

__all__ = ["EARLY_Z_TEXELS", "LAYER_TEXELS", "PARALLEL_MIN_SOURCE_PIXELS", "STRETCH_PX",
           "Reprojection", "orphans", "row_depth_range", "row_spans", "support_box"]

#: A reprojected triangle whose bounding box is wider or taller than this
#: (destination pixels) spans a depth jump and is not drawn. Source triangles
#: are 1 px; a surface stretched by more than 4x by the motion is taken for a
#: disocclusion: limits of 3 to 5 px give the same shadow, while no limit lets
#: triangles bridge the chair's slat gaps (``morphkit bench shadows``; docs/RESULTS.md,
#: "Warped shadow maps").
STRETCH_PX = 4.0

#: Maps after the first draw a quad at a centre only if it could make the depth
#: there nearer by more than this many texels' world size (the texel size at
#: that depth, ``z / fx``): the first map has already covered most centres with
#: the same surface, and a difference far below the lookup's bias
#: (:class:`~morphkit.shadow.lookup.ShadowBias`, 1 texel constant) is invisible.
#: Coverage is never affected. 0 draws every quad (exact z-buffer minimum).
EARLY_Z_TEXELS = 0.25

#: Reproject in :data:`morphkit.warp.WARP_THREADS` bands when a frame's sources
#: hold at least this many object pixels, else in one thread: below it handing the
#: bands to the threads costs more than the pixels do (``morphkit bench shadows``).
PARALLEL_MIN_SOURCE_PIXELS = 1 << 14

#: A neighbour's pixel is *explained* by the primary map (not part of its
#: :func:`hidden_layer`) when its depth, moved to the primary's sample, is within
#: this many texels' world size of the primary's surface interpolated there.
#: The layers then give the whole maps' shadow (0.5 and 2 texels alike); a 3 x 3
#: min/max window instead of the interpolation would explain away the neighbours'
#: pixels just past the primary's silhouette, whose union draws the finer outline
#: (measured: docs/RESULTS.md, "Warped shadow maps").
LAYER_TEXELS = 1.0


class Reprojection:
    """How one source map moves: intrinsics of source and destination, and ``e``.

    Parameters
    ----------
    perspective : bool
        Perspective (point light) or orthographic (directional light) maps.
    fx, fy : float
        Focal lengths (pixels; orthographic: pixels per unit), shared.
    c_src, c_dst : (2,)
        Principal points ``(cx, cy)`` of the source's and destination's cameras.
    e : (3,)
        The object's translation in the light camera frame (``R^T d``).
    """

    __slots__ = ("perspective", "params")

    def __init__(self, perspective: bool, fx: float, fy: float, c_src: Any, c_dst: Any,
                 e: Any) -> None:
        self.perspective = bool(perspective)
        self.params = np.array([fx, fy, c_src[0], c_src[1], c_dst[0], c_dst[1], e[0], e[1], e[2]],
                               dtype=np.float64)
        if not np.all(np.isfinite(self.params)) or fx <= 0 or fy <= 0:
            raise ValidationError(expected_got("reprojection", "finite parameters and fx, fy > 0",
                                               self.params.tolist()))

    @classmethod
    def unchecked(cls, perspective: bool, params: list[float]) -> Reprojection:
        """A reprojection from parameters the caller has already validated (the
        constructor's, in its order ``fx, fy, cx_s, cy_s, cx_d, cy_d, ex, ey, ez``),
        without checking them again: for the per-frame motions of a validated rig
        (:meth:`AtlasRuntime.moved <morphkit.shadow.runtime.AtlasRuntime.moved>`).

        Parameters
        ----------
        perspective : bool
            Perspective (point light) or orthographic maps.
        params : list of float
            The nine parameters, finite, ``fx, fy > 0``.

        Returns
        -------
        Reprojection
            The motion, built without validation.
        """
        rp = object.__new__(cls)
        rp.perspective = bool(perspective)
        rp.params = np.array(params, dtype=np.float64)
        return rp

    @property
    def identity(self) -> bool:
        """True when nothing moves: equal principal points and ``e = 0``."""
        p = self.params
        return bool(p[2] == p[4] and p[3] == p[5] and not np.any(p[6:]))

    def row_y_range(self, zrange: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bounds of the destination ``y`` of source rows' object pixels.

        Parameters
        ----------
        zrange : (K, 2) float
            Each row's smallest and largest object depth (rows of
            :func:`row_depth_range`; ``(+inf, -inf)`` for a row without one).
        rows : (K,) int
            The source rows (their ``y``).

        Returns
        -------
        lo, hi : (K,) float64
            ``lo <= y' <= hi`` for every object pixel of the row (``+inf, -inf``
            for an empty row). Exact bounds: ``y'`` depends on the row and the
            depth only, monotonically in the depth (perspective) or not at all
            (orthographic).
        """
        fx, fy, _cxs, cys, _cxd, cyd, _ex, ey, ez = self.params
        h = zrange.shape[0]
        yr = (np.asarray(rows, dtype=np.float64) - cys) / fy
        ok = zrange[:, 0] <= zrange[:, 1]
        lo = np.full(h, np.inf)
        hi = np.full(h, -np.inf)
        if self.perspective:
            with np.errstate(invalid="ignore", divide="ignore"):  # empty rows: masked below
                a = fy * (zrange[:, 0] * yr + ey) / (zrange[:, 0] + ez) + cyd
                b = fy * (zrange[:, 1] * yr + ey) / (zrange[:, 1] + ez) + cyd
            lo[ok] = np.minimum(a, b)[ok]
            hi[ok] = np.maximum(a, b)[ok]
        else:
            y = fy * (yr + ey) + cyd
            lo[ok] = hi[ok] = y[ok]
        return lo, hi

    def move(self, x: np.ndarray, y: np.ndarray, z: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Destination ``(x', y', z')`` of source pixels ``(x, y)`` at depths ``z`` (numpy).

        Parameters
        ----------
        x, y : array of float64
            Source pixel positions (pixel-centre convention of :mod:`morphkit.conventions`).
        z : array of float64, same shape
            Their depths in the source camera (``+inf`` background).

        Returns
        -------
        x, y, z : arrays of float64, same shape
            Destination pixel positions and depths.
        """
        fx, fy, cxs, cys, cxd, cyd, ex, ey, ez = self.params
        s = z if self.perspective else np.ones_like(z)
        zd = z + ez
        t = zd if self.perspective else np.ones_like(zd)
        with np.errstate(invalid="ignore"):  # background: inf * 0, inf / inf, never drawn
            X = s * (x - cxs) / fx + ex
            Y = s * (y - cys) / fy + ey
            return fx * X / t + cxd, fy * Y / t + cyd, zd


def support_box(depth: np.ndarray) -> tuple[int, int, int, int]:
    """``(r0, r1, c0, c1)``: the bounding box of a map's object (finite) pixels.

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.

    Returns
    -------
    tuple of int
        ``(r0, r1, c0, c1)``, ``(0, 0, 0, 0)`` when the map is empty.
    """
    fin = np.isfinite(depth)
    rows = np.flatnonzero(fin.any(1))
    if rows.size == 0:
        return (0, 0, 0, 0)
    cols = np.flatnonzero(fin.any(0))
    return int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1


def row_spans(depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``spans (H, 2)`` int64: each row's first and last + 1 object column (``(0, 0)``:
    none); ``cum (H + 1,)``: object pixels in the rows above each row (band splits).

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.

    Returns
    -------
    spans : (H, 2) int64
        Each row's object columns ``[first, last + 1)``.
    cum : (H + 1,) int64
        Object pixels above each row.
    """
    fin = np.isfinite(depth)
    h, w = fin.shape
    any_ = fin.any(1)
    first = np.where(any_, fin.argmax(1), 0)
    last = np.where(any_, w - fin[:, ::-1].argmax(1), 0)
    cum = np.zeros(h + 1, np.int64)
    np.cumsum(fin.sum(1), out=cum[1:])
    return np.stack([first, last], 1).astype(np.int64), cum


def row_depth_range(depth: np.ndarray) -> np.ndarray:
    """``(H, 2)`` float64: each row's smallest and largest object (finite) depth,
    ``(+inf, -inf)`` for a row without one.

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.

    Returns
    -------
    (H, 2) float64
        Per row, the smallest and largest object depth.
    """
    fin = np.isfinite(depth)
    d = depth.astype(np.float64)
    return np.stack([np.where(fin, d, np.inf).min(1), np.where(fin, d, -np.inf).max(1)], 1)


def orphans(depth: np.ndarray) -> np.ndarray:
    """``(K, 2)`` int64 ``(row, col)`` of object pixels in no quad that has 3 or more
    object pixels (they belong to no triangle and are drawn as points).

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.

    Returns
    -------
    (K, 2) int64
        ``(row, col)`` of the orphan pixels.
    """
    fin = np.isfinite(depth)
    h, w = fin.shape
    q = np.zeros((h + 1, w + 1), np.int8)  # object pixels per quad, padded by one quad
    f = fin.astype(np.int8)
    q[1:h, 1:w] = f[:-1, :-1] + f[:-1, 1:] + f[1:, :-1] + f[1:, 1:]
    good = q >= 3
    # a pixel (r, c) is a corner of quads (r-1..r, c-1..c) = padded (r..r+1, c..c+1)
    in_tri = good[:-1, :-1] | good[:-1, 1:] | good[1:, :-1] | good[1:, 1:]
    return np.argwhere(fin & ~in_tri).astype(np.int64)

