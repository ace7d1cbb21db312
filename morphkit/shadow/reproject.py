"""Per-pixel 3-D reprojection of light depth maps (forward, z-buffered).

A piecewise-affine mesh warp (:mod:`morphkit.shadow.atlas`, the paper's) moves
every pixel of a triangle with one affine motion, so it cannot follow parallax
*inside* a triangle: where a triangle straddles surfaces at different depths
(the chair's back slats in front of its seat) the warped silhouette is wrong by
up to the parallax difference. A depth map, though, holds the 3-D position of
every pixel: with the object translated by ``d`` and a light camera of fixed
orientation, each pixel can be moved exactly. This module does that for the
atlas's maps ("3-D image warping", McMillan & Bishop 1995; the mesh
reconstruction of Mark, McMillan & Bishop 1997):

1. **Move each pixel.** Source pixel ``(x, y)`` of depth ``z`` is the camera
   point ``P = (z (x - cx_s) / fx, z (y - cy_s) / fy, z)`` (perspective; for
   orthographic ``((x - cx_s) / fx, (y - cy_s) / fy, z)``); the object moved by
   ``d`` puts it at ``P + e`` with ``e = R^T d`` (``R`` the light camera's
   rotation, the same for every map of a :class:`~morphkit.shadow.rig.LightRig`),
   which projects with the destination camera's principal point to
   ``(x', y')`` at depth ``z + e_z``. Exact for every surface point a map saw.
2. **Reconnect the pixels.** Neighbouring pixel centres form quads, split into
   two triangles (along the ``(x+1, y)``-``(x, y+1)`` diagonal; a quad with
   only 3 object pixels gives their triangle), each rasterised at the
   destination pixel centres it covers, depth interpolated linearly. A triangle
   with a bounding box wider or taller than :data:`STRETCH_PX` pixels is not
   drawn: its vertices moved apart by parallax, so it spans a depth jump (a
   disocclusion), not a surface. Pixels that belong to no triangle of three
   object pixels (one-pixel-wide features) are drawn as points, at the nearest
   pixel centre.
3. **Several sources, one z-buffer.** A surface hidden in one map (disoccluded
   by the motion) is usually seen by another: the cell's maps are all
   reprojected into one z-buffer, which keeps the nearest depth. What none of
   them saw stays a hole (the method's error).
4. **Only what is new.** Most of a neighbour map repeats what the primary map
   (the largest weight) holds. :func:`hidden_layer` keeps, once per pair of
   neighbouring samples, only the neighbour's pixels that the primary's map
   does not explain (hidden from its position, or at its silhouette): a layered
   depth image (Shade, Gortler, He & Szeliski 1998). A frame then reprojects
   the primary whole and its neighbours' layers: the same shadow as the whole
   maps (IoU within 0.0003 at 512^2) from about a third of their pixels, and a
   layer costs only a list of runs of quads (:class:`Layer`).

At a sample position the reprojection is the identity and reproduces the baked
map exactly (every object pixel is a vertex of a drawn triangle or a point).

Threads and determinism: :func:`reproject_maps` splits the *output* rows into
bands, one per thread; a band draws, in the single-threaded order, every quad
that can reach its rows (found from bounds on each source row's destination
``y``: :meth:`Reprojection.row_y_range`) and writes only its own rows. Every
output pixel then sees the same sequence of writes and early-z tests whatever
the thread count: the z-buffer is bit-identical for 1, 2 or 4 threads.

Convention: pixel centres at integer ``(x, y)``, origin at the top-left pixel
centre (:mod:`morphkit.conventions`); a triangle covers the centres inside or
on its edges. Depths are linear light-camera ``Z``; ``+inf`` is background.

The kernel is compiled (numba); :func:`reproject_numpy` is an independent
vectorised reference used by the tests (``MORPHKIT_WARP_NUMPY=1`` selects it).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..settings import NUMBA_AVAILABLE, compile_kernel, use_compiled

__all__ = ["EARLY_Z_TEXELS", "LAYER_TEXELS", "PARALLEL_MIN_SOURCE_PIXELS", "STRETCH_PX",
           "Layer", "Reprojection", "Source", "hidden_layer", "orphans", "reproject_maps",
           "reproject_numpy", "row_depth_range", "row_spans", "support_box"]

#: A reprojected triangle whose bounding box is wider or taller than this
#: (destination pixels) spans a depth jump and is not drawn. Source triangles
#: are 1 px; a surface stretched by more than 4x by the motion is taken for a
#: disocclusion. Measured (``morphkit bench shadows``, chair, 512^2, 50
#: positions): 3, 4 and 5 px give IoU within 0.0005 of each other; no limit lets
#: triangles bridge the slats' gaps (0.948).
STRETCH_PX = 4.0

#: Maps after the first draw a quad at a centre only if it could make the depth
#: there nearer by more than this many texels' world size (the texel size at
#: that depth, ``z / fx``): the first map has already covered most centres with
#: the same surface, and a difference far below the lookup's bias
#: (:class:`~morphkit.shadow.lookup.ShadowBias`, 1 texel constant) is invisible.
#: Coverage is never affected. 0 draws every quad (exact z-buffer minimum).
EARLY_Z_TEXELS = 0.25

#: Reproject in :data:`morphkit.warp.WARP_THREADS` bands when a frame's sources
#: hold at least this many object pixels, else in one thread. Measured (cow and
#: chair, point light, 128^2 and 256^2): the split pays from ~20k pixels (a
#: thread hand-off costs ~0.1 ms; a pixel ~25 ns per map).
PARALLEL_MIN_SOURCE_PIXELS = 1 << 14

#: A neighbour's pixel is *explained* by the primary map (not part of its
#: :func:`hidden_layer`) when its depth, moved to the primary's sample, is within
#: this many texels' world size of the primary's surface interpolated there.
#: Measured (512^2, point light, the 50 positions of ``morphkit bench shadows``,
#: IoU vs ray cast, teapot / chair / cow): 0.9899 / 0.9898 / 0.9938 against the
#: whole maps' 0.9900 / 0.9901 / 0.9938 (0.5 and 2 texels: within 0.0003 of
#: that); a 3 x 3 min/max window instead of the interpolation explains away the
#: neighbours' pixels just past the primary's silhouette, whose union draws the
#: finer outline (0.9852 / 0.9825 / 0.9927).
LAYER_TEXELS = 1.0

#: Barycentric tolerance (~ pixels, triangles being ~1 px): centres on a shared
#: edge count for both triangles (the z-buffer keeps the nearer), so none falls
#: between them, and centres on the mesh's boundary stay covered under a
#: vanishing motion (the boundary runs through the border pixels' centres), as
#: :data:`morphkit.tol.MESH_BOUNDARY_PX` does for the mesh warp.
_EDGE_EPS = tol.MESH_BOUNDARY_PX


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


# ----------------------------------------------------------------- compiled kernel
def _tri(px: float, py: float, x0: float, y0: float, z0: float, x1: float, y1: float, z1: float,
         x2: float, y2: float, z2: float) -> float:
    """Depth at centre ``(px, py)`` of the triangle, or ``+inf`` outside it (edges count)."""
    ax = x1 - x0
    ay = y1 - y0
    bx = x2 - x0
    by = y2 - y0
    den = ax * by - bx * ay
    qx = px - x0
    qy = py - y0
    w1 = qx * by - bx * qy  # l1 * den
    w2 = ax * qy - qx * ay  # l2 * den
    if den < 0.0:
        den = -den
        w1 = -w1
        w2 = -w2
    eps = _EDGE_EPS * den
    if den > 0.0 and w1 >= -eps and w2 >= -eps and w1 + w2 <= den + eps:
        return z0 + (w1 * (z1 - z0) + w2 * (z2 - z0)) / den
    return np.inf


def _grow(xmin: float, xmax: float, ymin: float, ymax: float, x: float, y: float, valid: bool
          ) -> tuple[float, float, float, float]:
    """The box ``(xmin, xmax, ymin, ymax)`` grown by ``(x, y)`` if ``valid``."""
    if valid:
        return min(xmin, x), max(xmax, x), min(ymin, y), max(ymax, y)
    return xmin, xmax, ymin, ymax


def _fits(x0: float, y0: float, x1: float, y1: float, x2: float, y2: float, lim: float) -> bool:
    """Whether the triangle's bounding box is at most ``lim`` wide and tall."""
    return (max(x0, x1, x2) - min(x0, x1, x2) <= lim
            and max(y0, y1, y2) - min(y0, y1, y2) <= lim)


def _project_row(src: np.ndarray, r: int, c0: int, c1: int, persp: bool, p: np.ndarray,
                 X: np.ndarray, Y: np.ndarray, Z: np.ndarray, lo: int, hi: int) -> None:
    """Destination ``X, Y`` and depth ``Z`` (``+inf``: background) of
    ``src[r, c0:c1]``; only columns in ``[lo, hi)`` can hold the object."""
    Z[:] = np.inf
    lo = max(lo, c0)
    fx = p[0]
    fy = p[1]
    cxs = p[2]
    cys = p[3]
    cxd = p[4]
    cyd = p[5]
    ex = p[6]
    ey = p[7]
    ez = p[8]
    row = src[r]
    yr = (r - cys) / fy
    for c in range(lo, min(hi, c1)):
        k = c - c0
        z = np.float64(row[c])
        if z < np.inf:
            zd = z + ez
            xr = (c - cxs) / fx
            if persp:
                t = 1.0 / zd
                X[k] = fx * (z * xr + ex) * t + cxd
                Y[k] = fy * (z * yr + ey) * t + cyd
            else:
                X[k] = fx * (xr + ex) + cxd
                Y[k] = fy * (yr + ey) + cyd
            Z[k] = zd


def _draw_quads(Xa: np.ndarray, Ya: np.ndarray, Za: np.ndarray, Xb: np.ndarray, Yb: np.ndarray,
                Zb: np.ndarray, k0: int, k1: int, stretch: float, early_z: float, persp: bool,
                zbuf: np.ndarray, jlo: int, jhi: int, ilo: int, ihi: int, jmin: int, jmax: int
                ) -> tuple[int, int, int, int]:
    """Draw quads ``k0 .. k1 - 1`` between two projected rows (``Xa, Ya, Za`` the
    upper, ``Xb, Yb, Zb`` the lower; quad ``k`` joins their entries ``k, k + 1``)
    into rows ``[jmin, jmax)`` of ``zbuf``; returns the written-pixel bounds
    ``(jlo, jhi, ilo, ihi)`` grown. ``early_z``: skip a quad at a centre already
    holding a depth no farther than the quad's nearest vertex plus ``early_z``
    (relative to that depth for perspective, absolute for orthographic): it
    could lower that depth by at most that much, and cannot change coverage."""
    h, w = zbuf.shape
    for k in range(k0, k1):
        za = Za[k]
        zb = Za[k + 1]
        zc = Zb[k]
        zd = Zb[k + 1]
        va = za < np.inf
        vb = zb < np.inf
        vc = zc < np.inf
        vd = zd < np.inf
        if va + vb + vc + vd < 3:
            continue
        xa = Xa[k]
        ya = Ya[k]
        xb = Xa[k + 1]
        yb = Ya[k + 1]
        xc = Xb[k]
        yc = Yb[k]
        xd = Xb[k + 1]
        yd = Yb[k + 1]
        # the quad's bounding box over its object vertices (3 or 4)
        xmin, xmax, ymin, ymax = np.inf, -np.inf, np.inf, -np.inf
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xa, ya, va)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xb, yb, vb)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xc, yc, vc)
        xmin, xmax, ymin, ymax = _grow(xmin, xmax, ymin, ymax, xd, yd, vd)
        ia = max(math.ceil(xmin - _EDGE_EPS), 0)
        ib = min(math.floor(xmax + _EDGE_EPS), w - 1)
        ja = max(math.ceil(ymin - _EDGE_EPS), 0, jmin)
        jb = min(math.floor(ymax + _EDGE_EPS), h - 1, jmax - 1)
        if ib < ia or jb < ja:
            continue
        # which triangles: split along b-c; with 3 object pixels, their triangle.
        # A triangle wider or taller than `stretch` spans a depth jump: not drawn.
        t0 = va and vb and vc
        t1 = vb and vc and vd
        t2 = (not (vb and vc)) and va and vb and vd
        t3 = (not (vb and vc)) and va and vc and vd
        if xmax - xmin > stretch or ymax - ymin > stretch:
            t0 = t0 and _fits(xa, ya, xb, yb, xc, yc, stretch)
            t1 = t1 and _fits(xb, yb, xd, yd, xc, yc, stretch)
            t2 = t2 and _fits(xa, ya, xb, yb, xd, yd, stretch)
            t3 = t3 and _fits(xa, ya, xd, yd, xc, yc, stretch)
            if not (t0 or t1 or t2 or t3):
                continue
        jlo = min(jlo, ja)
        jhi = max(jhi, jb + 1)
        ilo = min(ilo, ia)
        ihi = max(ihi, ib + 1)
        znear = min(za, zb, zc, zd)
        zskip = znear + early_z * (znear if persp else 1.0)
        for j in range(ja, jb + 1):
            for i in range(ia, ib + 1):
                if zbuf[j, i] <= zskip:
                    continue
                # t0/t1 share only their diagonal unless the quad folds (then
                # the first that holds the centre gives its depth); t2, t3
                # exclude each other and t0, t1
                z = np.inf
                if t0:
                    z = _tri(i, j, xa, ya, za, xb, yb, zb, xc, yc, zc)
                if t1 and z == np.inf:
                    z = _tri(i, j, xb, yb, zb, xd, yd, zd, xc, yc, zc)
                if t2:
                    z = _tri(i, j, xa, ya, za, xb, yb, zb, xd, yd, zd)
                elif t3:
                    z = _tri(i, j, xa, ya, za, xd, yd, zd, xc, yc, zc)
                if z < zbuf[j, i]:
                    zbuf[j, i] = z
    return jlo, jhi, ilo, ihi


def _reproject_loop(src: np.ndarray, spans: np.ndarray, q0: int, q1: int, c0: int, c1: int,
                    persp: bool, p: np.ndarray, orph: np.ndarray, stretch: float,
                    early_z: float, zbuf: np.ndarray, box: np.ndarray, jmin: int, jmax: int) -> None:
    """Draw the quads with top row in ``[q0, q1)`` and columns ``[c0, c1)`` of
    ``src`` (rows ``q0 .. q1`` are read; ``spans[r]`` holds row ``r``'s first and
    last + 1 object columns), and the points ``orph``, into rows ``[jmin, jmax)``
    of ``zbuf``; ``box`` grows to hold every pixel that may have been written
    (``early_z``: :func:`_draw_quads`; 0 skips only what cannot change the result)."""
    n = c1 - c0
    rows = np.empty((6, n))  # two projected rows: X, Y, Z of each
    Xa, Ya, Za, Xb, Yb, Zb = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    h, w = zbuf.shape
    jlo, jhi, ilo, ihi = box[0], box[1], box[2], box[3]
    if q1 > q0:
        _project_row(src, q0, c0, c1, persp, p, Xa, Ya, Za, spans[q0, 0], spans[q0, 1])
    for r in range(q0, q1):
        if r + 1 >= src.shape[0]:
            break
        _project_row(src, r + 1, c0, c1, persp, p, Xb, Yb, Zb, spans[r + 1, 0], spans[r + 1, 1])
        lo = min(spans[r, 0], spans[r + 1, 0])
        hi = max(spans[r, 1], spans[r + 1, 1])
        if hi > lo:
            jlo, jhi, ilo, ihi = _draw_quads(Xa, Ya, Za, Xb, Yb, Zb, max(lo - c0 - 1, 0),
                                             min(hi - c0, n - 1), stretch, early_z, persp, zbuf,
                                             jlo, jhi, ilo, ihi, jmin, jmax)
        Xa, Xb = Xb, Xa
        Ya, Yb = Yb, Ya
        Za, Zb = Zb, Za
    one_x = np.empty(1)
    one_y = np.empty(1)
    one_z = np.empty(1)
    for k in range(orph.shape[0]):
        r = orph[k, 0]
        c = orph[k, 1]
        _project_row(src, r, c, c + 1, persp, p, one_x, one_y, one_z, c, c + 1)
        if one_z[0] < np.inf:
            i = math.floor(one_x[0] + 0.5)
            j = math.floor(one_y[0] + 0.5)
            if 0 <= i < w and max(jmin, 0) <= j < min(jmax, h) and one_z[0] < zbuf[j, i]:
                zbuf[j, i] = one_z[0]
                jlo = min(jlo, j)
                jhi = max(jhi, j + 1)
                ilo = min(ilo, i)
                ihi = max(ihi, i + 1)
    box[0] = jlo
    box[1] = jhi
    box[2] = ilo
    box[3] = ihi


def _runs_loop(src: np.ndarray, runs: np.ndarray, t0: int, t1: int, persp: bool, p: np.ndarray,
               stretch: float, early_z: float, zbuf: np.ndarray, box: np.ndarray, jmin: int,
               jmax: int) -> None:
    """Draw the quads of ``src`` listed by ``runs[t0:t1]`` (rows ``(r, a, b)``: the
    quads with top row ``r`` and left columns ``a .. b - 1``) into rows
    ``[jmin, jmax)`` of ``zbuf``, as :func:`_reproject_loop` draws them; ``box``
    grows likewise."""
    n = 1
    for t in range(t0, t1):
        n = max(n, runs[t, 2] - runs[t, 1] + 1)
    rows = np.empty((6, n))  # two projected rows: X, Y, Z of each
    Xa, Ya, Za, Xb, Yb, Zb = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5]
    jlo, jhi, ilo, ihi = box[0], box[1], box[2], box[3]
    for t in range(t0, t1):
        r = runs[t, 0]
        a = runs[t, 1]
        b = runs[t, 2] + 1
        _project_row(src, r, a, b, persp, p, Xa, Ya, Za, a, b)
        _project_row(src, r + 1, a, b, persp, p, Xb, Yb, Zb, a, b)
        jlo, jhi, ilo, ihi = _draw_quads(Xa, Ya, Za, Xb, Yb, Zb, 0, b - a - 1, stretch, early_z,
                                         persp, zbuf, jlo, jhi, ilo, ihi, jmin, jmax)
    box[0] = jlo
    box[1] = jhi
    box[2] = ilo
    box[3] = ihi


def _quad_hull(zrange: np.ndarray, persp: bool, p: np.ndarray, q0: int, q1: int, jmin: int, jmax: int
               ) -> tuple[int, int]:
    """The first and last + 1 quad rows in ``[q0, q1)`` whose quads (or points) can
    write a destination row in ``[jmin, jmax)`` (``(0, 0)``: none). A quad row's
    destination ``y`` lies within the bounds of its two source rows' (exact, as
    :meth:`Reprojection.row_y_range`), widened by a pixel for the rounding."""
    fy = p[1]
    cys = p[3]
    cyd = p[5]
    ey = p[7]
    ez = p[8]
    h = zrange.shape[0]
    first = -1
    last = -1
    for q in range(q0, q1):
        lo = np.inf
        hi = -np.inf
        for r in range(q, min(q + 2, h)):
            za = zrange[r, 0]
            zb = zrange[r, 1]
            if za > zb:
                continue
            yr = (r - cys) / fy
            if persp:
                ya = fy * (za * yr + ey) / (za + ez) + cyd
                yb = fy * (zb * yr + ey) / (zb + ez) + cyd
            else:
                ya = fy * (yr + ey) + cyd
                yb = ya
            lo = min(lo, ya, yb)
            hi = max(hi, ya, yb)
        if hi + 1.0 >= jmin and lo - 1.0 < jmax:
            if first < 0:
                first = q
            last = q
    if first < 0:
        return 0, 0
    return first, last + 1


def _work_rows(zrange: np.ndarray, work: np.ndarray, persp: bool, p: np.ndarray, hist: np.ndarray) -> None:
    """Add each source row's ``work`` to ``hist`` at the middle of its destination rows."""
    fy = p[1]
    cys = p[3]
    cyd = p[5]
    ey = p[7]
    ez = p[8]
    n = hist.shape[0]
    for r in range(zrange.shape[0]):
        za = zrange[r, 0]
        zb = zrange[r, 1]
        if work[r] <= 0 or za > zb:
            continue
        yr = (r - cys) / fy
        if persp:
            y = 0.5 * (fy * (za * yr + ey) / (za + ez) + fy * (zb * yr + ey) / (zb + ez)) + cyd
        else:
            y = fy * (yr + ey) + cyd
        j = min(max(int(math.floor(y)), 0), n - 1)
        hist[j] += work[r]


if NUMBA_AVAILABLE:  # inlined helpers first: the kernels resolve them when they compile
    _tri = compile_kernel(_tri, inline="always")
    _grow = compile_kernel(_grow, inline="always")
    _fits = compile_kernel(_fits, inline="always")
    _project_row = compile_kernel(_project_row, inline="always")
    _draw_quads = compile_kernel(_draw_quads, inline="always")
_reproject_kernel = compile_kernel(_reproject_loop)
_runs_kernel = compile_kernel(_runs_loop)
_hull_kernel = compile_kernel(_quad_hull)
_work_kernel = compile_kernel(_work_rows)


# ----------------------------------------------------------------- numpy reference
def reproject_numpy(src: np.ndarray, rp: Reprojection, zbuf: np.ndarray, *,
                    stretch: float = STRETCH_PX, quads: np.ndarray | None = None) -> None:
    """The same drawing as the compiled kernel, vectorised over triangles: every
    triangle's candidate centres in its bounding box are tested at once, and the
    z-buffer minimum is taken with ``np.minimum.at``. An independent reference
    (tests compare the two) and the fallback without numba. ``quads``
    (``(H - 1, W - 1)`` bool): draw only those quads, and no orphan points (a
    :class:`Layer`).

    Parameters
    ----------
    src : (h, w) float32
        Source map, linear depth, ``+inf`` background.
    rp : Reprojection
        How its pixels move.
    zbuf : (H, W) float32
        Destination z-buffer, lowered in place (min).
    stretch : float
        Longest triangle edge drawn, in destination pixels (longer ones span a
        depth discontinuity and are dropped).
    quads : (h - 1, w - 1) bool, optional
        The quads to draw (None: all, and the orphan points).
    """
    h, w = src.shape
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float64)
    X, Y, Z = rp.move(xs, ys, src.astype(np.float64))
    fin = np.isfinite(src)
    a = (slice(None, -1), slice(None, -1))
    b = (slice(None, -1), slice(1, None))
    c = (slice(1, None), slice(None, -1))
    d = (slice(1, None), slice(1, None))
    va, vb, vc, vd = fin[a], fin[b], fin[c], fin[d]
    tris = [(a, b, c, vb & vc & va), (b, d, c, vb & vc & vd),
            (a, b, d, ~(vb & vc) & va & vd & vb), (a, d, c, ~(vb & vc) & va & vd & vc)]
    for p0, p1, p2, ok in tris:
        if quads is not None:
            ok = ok & quads
        P = [np.stack([M[s][ok] for M in (X, Y, Z)]) for s in (p0, p1, p2)]
        _raster_numpy(P[0], P[1], P[2], zbuf, stretch)
    orph = orphans(src) if quads is None else np.empty((0, 2), np.int64)
    h, w = zbuf.shape
    if len(orph):
        r, cc = orph[:, 0], orph[:, 1]
        i = np.floor(X[r, cc] + 0.5).astype(np.int64)
        j = np.floor(Y[r, cc] + 0.5).astype(np.int64)
        ok = (i >= 0) & (i < w) & (j >= 0) & (j < h)
        np.minimum.at(zbuf, (j[ok], i[ok]), Z[r, cc][ok].astype(zbuf.dtype))


def _raster_numpy(p0: np.ndarray, p1: np.ndarray, p2: np.ndarray, zbuf: np.ndarray,
                  stretch: float) -> None:
    h, w = zbuf.shape
    xs = np.stack([p0[0], p1[0], p2[0]])
    ys = np.stack([p0[1], p1[1], p2[1]])
    keep = (xs.max(0) - xs.min(0) <= stretch) & (ys.max(0) - ys.min(0) <= stretch)
    p0, p1, p2, xs, ys = p0[:, keep], p1[:, keep], p2[:, keep], xs[:, keep], ys[:, keep]
    ax, ay = p1[0] - p0[0], p1[1] - p0[1]
    bx, by = p2[0] - p0[0], p2[1] - p0[1]
    den = ax * by - bx * ay
    ia = np.ceil(xs.min(0) - _EDGE_EPS).astype(np.int64)
    ja = np.ceil(ys.min(0) - _EDGE_EPS).astype(np.int64)
    span = int(math.floor(stretch)) + 1
    for dj in range(span + 1):
        for di in range(span + 1):
            i, j = ia + di, ja + dj
            px, py = i - p0[0], j - p0[1]
            with np.errstate(divide="ignore", invalid="ignore"):
                l1 = (px * by - bx * py) / den
                l2 = (ax * py - px * ay) / den
            z = p0[2] + l1 * (p1[2] - p0[2]) + l2 * (p2[2] - p0[2])
            ok = ((den != 0) & (l1 >= -_EDGE_EPS) & (l2 >= -_EDGE_EPS) & (l1 + l2 <= 1 + _EDGE_EPS)
                  & (i >= 0) & (i < w) & (j >= 0) & (j < h))
            np.minimum.at(zbuf, (j[ok], i[ok]), z[ok].astype(zbuf.dtype))


def _check_depth(depth: np.ndarray) -> np.ndarray:
    if depth.dtype != np.float32 or depth.ndim != 2:
        raise ValidationError(expected_got("depth map", "float32 (H, W)",
                                           f"{depth.dtype} {depth.shape}"))
    return depth


class Source:
    """A map prepared for reprojection (what does not change per frame): its
    :func:`support_box`, :func:`row_spans`, :func:`orphans` and
    :func:`row_depth_range`.

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.
    """

    __slots__ = ("depth", "box", "spans", "cum", "orphans", "zrange", "row_work")

    def __init__(self, depth: np.ndarray) -> None:
        self.depth = _check_depth(depth)
        self.box = support_box(depth)
        self.spans, self.cum = row_spans(depth)
        self.orphans = orphans(depth)
        self.zrange = row_depth_range(depth)
        self.row_work = np.diff(self.cum).astype(np.float64)  # object pixels per row


class Layer:
    """The quads of a map that a frame draws, not the whole map (a
    :func:`hidden_layer`): ``runs (K, 3)`` int64 rows ``(r, a, b)``, the quads with
    top row ``r`` and left columns ``a`` to ``b - 1``, in row-major order; ``cum
    (K + 1,)`` the quads before each run (band splits). The map is shared, not
    copied: a layer costs only its runs (:attr:`nbytes`).

    Parameters
    ----------
    depth : (H, W) float32
        The map, linear depth, ``+inf`` background (shared, not copied).
    quads : (H - 1, W - 1) bool
        The quads of the layer.
    """

    __slots__ = ("depth", "runs", "cum", "zrange", "row_work")

    def __init__(self, depth: np.ndarray, quads: np.ndarray) -> None:
        self.depth = _check_depth(depth)
        h, w = depth.shape
        if quads.shape != (max(h - 1, 0), max(w - 1, 0)):
            raise ValidationError(expected_got("quads", f"a ({h - 1}, {w - 1}) mask", str(quads.shape)))
        pad = np.zeros((quads.shape[0], quads.shape[1] + 2), np.int8)
        pad[:, 1:-1] = quads
        step = np.diff(pad, axis=1)
        r, a = np.nonzero(step == 1)
        _r, b = np.nonzero(step == -1)  # row-major, so starts and ends pair up
        self.runs = np.stack([r, a, b], 1).astype(np.int64).reshape(-1, 3)
        self.cum = np.zeros(len(self.runs) + 1, np.int64)
        np.cumsum(b - a, out=self.cum[1:])
        self.zrange = row_depth_range(depth)
        self.row_work = np.bincount(r, weights=b - a, minlength=h).astype(np.float64)  # quads per row

    @property
    def nbytes(self) -> int:
        """Bytes the layer keeps (its runs and their cumulative quad counts; the map is shared)."""
        return int(self.runs.nbytes + self.cum.nbytes)

    def quads(self) -> np.ndarray:
        """The ``(H - 1, W - 1)`` bool mask of the quads drawn.

        Returns
        -------
        (H - 1, W - 1) bool
            True for each quad of the layer.
        """
        h, w = self.depth.shape
        q = np.zeros((max(h - 1, 0), max(w - 1, 0)), bool)
        for r, a, b in self.runs:
            q[r, a:b] = True
        return q



def hidden_layer(primary: np.ndarray, secondary: np.ndarray, rp: Reprojection, *,
                 texels: float = LAYER_TEXELS) -> Layer:
    """What ``secondary`` holds that ``primary`` does not: one layer of a layered
    depth image (Shade et al. 1998), so that a frame reprojects the primary map
    whole and only this part of its neighbour.

    ``rp`` moves ``secondary``'s pixels to ``primary``'s sample position (exact:
    both are baked maps). A secondary pixel is *explained* when it lands inside
    the map and the primary's depth interpolated bilinearly there (its 4
    neighbouring pixels all object) is within ``texels`` texels' world size
    (``z / fx``; orthographic ``1 / fx``) of the pixel's moved depth: the
    primary saw that surface there (bilinear: exact on a plane). The others
    (hidden from the primary's position, or at or past its silhouette, where
    the union of maps draws a finer outline than any one) are *new*. The layer
    is every quad of ``secondary`` with a new pixel among its corners (and 3 or
    more object pixels), drawn as in the whole map.

    Parameters
    ----------
    primary, secondary : (H, W) float32
        The two maps, linear depth, ``+inf`` background.
    rp : Reprojection
        Moves ``secondary``'s pixels to ``primary``'s sample position.
    texels : float
        Depth tolerance, in texel world sizes.

    Returns
    -------
    Layer
        ``secondary``'s new quads.
    """
    primary = _check_depth(primary)
    if primary.shape != _check_depth(secondary).shape:
        raise ValidationError(expected_got("secondary map", f"the primary's shape {primary.shape}",
                                           str(secondary.shape)))
    h, w = secondary.shape
    fin = np.isfinite(secondary)
    r, c = np.nonzero(fin)
    x, y, z = rp.move(c.astype(np.float64), r.astype(np.float64), secondary[r, c].astype(np.float64))
    i0 = np.floor(x)
    j0 = np.floor(y)
    inside = (i0 >= 0) & (i0 < w - 1) & (j0 >= 0) & (j0 < h - 1)
    ax = np.where(inside, x - i0, 0.0)
    ay = np.where(inside, y - j0, 0.0)
    i0 = np.where(inside, i0, 0).astype(np.int64)
    j0 = np.where(inside, j0, 0).astype(np.int64)
    p = primary.astype(np.float64)
    with np.errstate(invalid="ignore"):  # inf * 0 where a neighbour is background: nan
        zi = ((p[j0, i0] * (1 - ax) + p[j0, i0 + 1] * ax) * (1 - ay)
              + (p[j0 + 1, i0] * (1 - ax) + p[j0 + 1, i0 + 1] * ax) * ay)
        tau = texels * (z if rp.perspective else 1.0) / rp.params[0]
        explained = inside & (np.abs(z - zi) <= tau)  # nan, inf: not explained
    new = np.zeros((h, w), bool)
    new[r[~explained], c[~explained]] = True
    f = fin.astype(np.int8)
    solid = (f[:-1, :-1] + f[:-1, 1:] + f[1:, :-1] + f[1:, 1:]) >= 3
    touched = new[:-1, :-1] | new[:-1, 1:] | new[1:, :-1] | new[1:, 1:]
    return Layer(secondary, touched & solid)


Job = tuple[Source | Layer, Reprojection]


def _output_bands(plan: list[tuple[int, Source | Layer, Reprojection]], h: int, n: int) -> np.ndarray:
    """``n + 1`` output-row edges (``0 .. h``) splitting the frame's work (object
    pixels, quads) about evenly: each source row's work counted at the middle of
    its destination rows. Only the balance depends on this, never the result."""
    hist = np.zeros(h)
    for _k, src, rp in plan:
        _work_kernel(src.zrange, src.row_work, rp.perspective, rp.params, hist)
    cum = np.cumsum(hist)
    if cum[-1] <= 0:
        return np.linspace(0, h, n + 1).astype(np.int64)
    edges = np.searchsorted(cum, cum[-1] * np.arange(1, n) / n, side="left") + 1
    return np.r_[0, np.clip(edges, 0, h), h].astype(np.int64)


def reproject_maps(jobs: list[Job], out: np.ndarray, *, threads: int = 1, stretch: float = STRETCH_PX,
                   early_z: float = EARLY_Z_TEXELS) -> tuple[int, int, int, int]:
    """Reproject every ``(source, rp)`` of ``jobs`` into the z-buffer ``out``
    (``(H, W)`` float32, min), the first job with its orphan points, the others
    (they mostly fill what the first one leaves open; whole maps or
    :func:`hidden_layer` s) with ``early_z``. Returns the ROI
    ``(r0, r1, c0, c1)`` holding every pixel written.

    With ``threads > 1`` the output rows are split into that many bands of
    about equal work; each band draws, in the order one thread would, every
    quad and point whose destination can reach its rows
    (:meth:`Reprojection.row_y_range`) and writes only its rows. Each output
    pixel so sees the same writes and early-z tests as with one thread: the
    result is bit-identical for any ``threads``. Compiled (numba) unless
    ``MORPHKIT_WARP_NUMPY=1``: then :func:`reproject_numpy` per map, in one
    thread, with every map's orphans and no early z (the exact union).

    Parameters
    ----------
    jobs : list of (Source or Layer, Reprojection)
        The maps (or layers) and their motions, first job first.
    out : (H, W) float32
        Z-buffer, lowered in place (min); ``+inf`` where empty.
    threads : int
        Bands drawn in parallel.
    stretch : float
        Longest triangle edge drawn, in destination pixels.
    early_z : float
        Early-z margin for the jobs after the first, in texels.

    Returns
    -------
    tuple of int
        ``(r0, r1, c0, c1)``.
    """
    if out.dtype != np.float32 or out.ndim != 2:
        raise ValidationError(expected_got("out", "a float32 (H, W) z-buffer", f"{out.dtype} {out.shape}"))
    box = np.array([out.shape[0], 0, out.shape[1], 0], np.int64)
    if not use_compiled(_reproject_kernel):
        for src, rp in jobs:
            before = out.copy()
            reproject_numpy(src.depth, rp, out, stretch=stretch,
                            quads=src.quads() if isinstance(src, Layer) else None)
            changed = np.argwhere(out != before)
            if len(changed):
                box[:] = (min(box[0], changed[:, 0].min()), max(box[1], changed[:, 0].max() + 1),
                          min(box[2], changed[:, 1].min()), max(box[3], changed[:, 1].max() + 1))
        return _box(box)
    no_points = np.empty((0, 2), np.int64)
    h = out.shape[0]
    n = max(1, min(int(threads), h))
    plan = [(k, src, rp) for k, (src, rp) in enumerate(jobs) if src.cum[-1] > 0]
    rows = np.array([0, h], np.int64) if n == 1 else _output_bands(plan, h, n)

    def band(b: int) -> np.ndarray:
        jmin, jmax = int(rows[b]), int(rows[b + 1])
        bx = np.array([h, 0, out.shape[1], 0], np.int64)
        if jmax <= jmin:
            return bx
        for k, src, rp in plan:
            ez = early_z / rp.params[0] if k > 0 else 0.0
            if isinstance(src, Layer):
                t0, t1 = 0, len(src.runs)
                if n > 1:  # the runs whose quad rows can reach this band's rows
                    qa, qb = _hull_kernel(src.zrange, rp.perspective, rp.params, int(src.runs[0, 0]),
                                          int(src.runs[-1, 0]) + 1, jmin, jmax)
                    t0 = int(np.searchsorted(src.runs[:, 0], qa, side="left"))
                    t1 = int(np.searchsorted(src.runs[:, 0], qb, side="left"))
                if t1 > t0:
                    _runs_kernel(src.depth, src.runs, t0, t1, rp.perspective, rp.params, float(stretch), ez,
                                 out, bx, jmin, jmax)
                continue
            r0, r1, c0, c1 = src.box
            if rp.identity:  # a sample position: the map itself
                a, z = max(r0, jmin), min(r1, jmax)
                if z > a:
                    o, m = out[a:z, c0:c1], src.depth[a:z, c0:c1]
                    np.minimum(o, m, out=o)
                    bx[:] = (min(bx[0], a), max(bx[1], z), min(bx[2], c0), max(bx[3], c1))
                continue
            q0, q1 = r0, max(r1 - 1, r0)
            if n > 1:  # the quad rows that can reach this band's rows (points: checked one by one)
                q0, q1 = _hull_kernel(src.zrange, rp.perspective, rp.params, q0, q1, jmin, jmax)
            _reproject_kernel(src.depth, src.spans, q0, q1, c0, c1, rp.perspective, rp.params,
                              src.orphans if k == 0 else no_points, float(stretch), ez, out, bx, jmin, jmax)
        return bx

    if n == 1:
        return _box(band(0))
    from ..warp import band_pool

    futures = [band_pool().submit(band, b) for b in range(1, n)]
    boxes = [band(0)] + [f.result() for f in futures]
    for bx in boxes:
        if bx[1] > bx[0] and bx[3] > bx[2]:
            box[:] = (min(box[0], bx[0]), max(box[1], bx[1]), min(box[2], bx[2]), max(box[3], bx[3]))
    return _box(box)


def _box(b: np.ndarray) -> tuple[int, int, int, int]:
    return (0, 0, 0, 0) if b[1] <= b[0] or b[3] <= b[2] else (int(b[0]), int(b[1]), int(b[2]), int(b[3]))
