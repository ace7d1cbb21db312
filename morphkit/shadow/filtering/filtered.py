"""Filtered shadow-map lookup: the fraction of a light *cell* a point sees, from one depth map.

A depth map rendered from one point light sample ``L`` answers "does ``L`` see
this point?" (:func:`~morphkit.shadow.lookup.shadow_visibility`). Averaging ``N``
such answers gives ``N + 1`` levels of visibility: the penumbra bands. Here one
map answers for a whole *cell* of the area light around its sample (the part of
the light the sample stands for), by percentage-closer filtering (Reeves et al.
1987) with a kernel as wide as the shadow moves while the light sweeps the cell.

Why that kernel. For a perspective light camera with focal lengths ``fx, fy``
(pixels) and rotation ``R`` (world to camera), moving the light by ``d``
(world, parallel to its plane) moves the image of a point at linear depth ``z``
by ``-f (R d)_xy / z``. A receiver point at depth ``z_r`` and an occluder at
depth ``z_b`` thus slide against each other by ``f (R d)_xy (1/z_b - 1/z_r)``
pixels. If the cell is the parallelogram ``s + a e_u + b e_v`` (``|a|, |b| <= 1``,
``e_u, e_v`` its half-extent vectors), the receiver point sees the cell's light
exactly where a box of half-widths

    ``h_x = fx (|(R e_u)_x| + |(R e_v)_x|) (1/z_b - 1/z_r)`` (and ``h_y`` with ``fy``, ``_y``)

around its projection holds no occluder: the filtered lookup returns ``1 -``
(the box's area covered by occluder texels closer than the point) ``/`` (the
box's area). This is exact for an occluder at one depth ``z_b`` and an
axis-aligned cell (otherwise the box is the cell's bounding box); the two
:class:`~morphkit.shadow.filtering.penumbra.PenumbraSoftShadow` methods differ only in
where ``z_b`` comes from:

* ``blocker="mean"`` (PCF sized by the light-sample spacing): one depth per map,
  the mean depth of its occluder texels;
* ``blocker="search"`` (PCSS, Fernando 2005): per point, the mean depth of the
  occluder texels closer than the point inside the *search* box -- the box the
  nearest occluder depth ``z_min`` of the map would give, rounded out to whole
  texels. No blocker there: lit. Contact hardening: a blocker within
  ``CONTACT_TEXELS`` of the point's own texel that is nearer the point than
  that mean sets the depth instead (the one nearest the point), so where the
  object touches the receiver the mean of a leg and the body above it does not
  blur the leg's sharp contact shadow.

A blocker area below :data:`morphkit.tol.PX_EQUAL` texels² is the tables' rounding: no
blocker.

Texels are unit squares centred on integer pixel coordinates (texel ``i`` covers
``[i - 1/2, i + 1/2]``); the box has real-valued edges and each texel counts with
the area it shares with the box, so the visibility changes continuously as the
point moves (no texel-sized steps). Texels outside the map are empty, as the
hard lookup treats points outside the window as lit.

Depth comparison and bias. The hard lookup (nearest texel) keeps the bias of
:mod:`morphkit.shadow.lookup`, ``texel_world * (constant + slope * min(tan, max_tan))``.
A box spans many texels, and a receiver sloped to the light has its own texels
in front of it across the box. With a normal, an occluder texel counts when it is
closer than the receiver's *plane* at that texel (the plane through the point
with that normal, seen from the light: its depth is a ratio of affine functions
of the pixel) minus ``texel_world * constant`` (receiver-plane depth bias, as in
Isidoro 2006). Without a normal the receiver may slope by ``tan = 1``: the bias
then grows by ``texel_world * slope * h`` with ``h`` the larger half-width in
texels. When both half-widths are below
:data:`morphkit.tol.PENUMBRA_MIN_HALF_TEXEL` the lookup *is* the hard lookup, so
a light of zero extent gives the hard shadow exactly; wider boxes are at least
one texel wide.

Speed. Per map, summed-area tables of occluder coverage and depth (one pass,
:class:`~morphkit.shadow.filtering.depthtables.DepthTables`) make a box's coverage and depth
sum four bilinear reads each, whatever its size (a box without occluder texels is
lit after the four reads of its count); a max-depth pyramid bounds the depths under
the box (2 x 2 reads, then at most 25; none where the map's farthest occluder is
in front of the point), telling whether every occluder texel there is in front of
the receiver (always so for a receiver below the object). Where some may be behind
the point (a surface shadowing itself, an object touching the receiver), the
tables' sums less those of the texels behind answer, found block by block down the
pyramid (the blocker search keeps them for its kernel's smaller box, and one search
over a wider box and a lower depth serves the next points: ``BEHIND_SHARE_*``); a
point whose search box is all occluder in front is umbra at once. The points go in
runs of ``CHUNK_POINTS`` (and groups of runs): a run whose bounding box keeps every
widest box off the map's occluder window, or off every occluder texel, is lit
without projecting its points, and without normals a run whose widest boxes'
occluders all lie in front of its nearest threshold skips the pyramid point by
point; the cost follows the points near the shadow, not all points times all maps.
Every such test only picks the path: the visibility is the same either way. From
``PARALLEL_MIN_POINTS`` points the groups alternate between threads.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from ... import tol
from ...camera import CameraModel
from ...errors import ValidationError, expected_got
from ...settings import WARP_THREADS, compile_kernel, use_compiled
from ...validate import as_finite_array
from ...warp import band_pool
from ..lookup import ShadowBias, check_depth_map
from .depthtables import DepthTables

__all__ = ["filtered_visibility", "cell_half_widths", "BlockerDepth", "point_chunks"]

#: How a filtered lookup finds the occluders' depth per map: ``"mean"`` (one mean blocker depth
#: per map, PCF) or ``"search"`` (a blocker search per point, PCSS).
BlockerDepth = Literal["mean", "search"]
_MODES = {"mean": 0, "search": 1}
#: Contact hardening reach (texels) of the blocker search (module docstring): the point's
#: texel and its 8 neighbours, enough to catch a blocker the nearest-texel rounding misses.
CONTACT_TEXELS = 1
#: Points per run whose bounding box the lookup tests against a map first (module docstring):
#: a run whose every widest box misses the map's occluder window is lit without a look at
#: its points. Runs of ``CHUNK_GROUP`` runs are tested before their runs.
CHUNK_POINTS = 32
CHUNK_GROUP = 16
#: Texels of the behind-the-point occluders a blocker search keeps for its kernel's box.
BEHIND_KEEP = 256
#: The searches of neighbouring points share their texels behind: one search over the box
#: grown by ``BEHIND_SHARE_TEXELS`` (each side), for a depth ``BEHIND_SHARE_DEPTH`` texel
#: widths nearer, keeps up to ``BEHIND_SHARE_KEEP`` texels; the next points whose box and
#: depth lie within pick theirs from those (the same texels: exact) instead of walking the
#: pyramid again.
BEHIND_SHARE_TEXELS = 6
BEHIND_SHARE_DEPTH = 4.0
BEHIND_SHARE_KEEP = 1024
#: Points below which a filtered lookup runs in the calling thread alone; from it, the groups
#: of runs alternate between :data:`~morphkit.settings.WARP_THREADS` threads (the calling one
#: and :func:`~morphkit.warp.band_pool`'s).
PARALLEL_MIN_POINTS = 1 << 14


def cell_half_widths(cell: np.ndarray, light_cam: CameraModel) -> tuple[float, float]:
    """``(fx (|(R e_u)_x| + |(R e_v)_x|), fy (...)_y)``: the box half-widths in pixels
    per unit of ``1/z_b - 1/z_r`` (module docstring).

    Parameters
    ----------
    cell : (2, 3) float
        Half-extent vectors ``e_u, e_v`` of the light cell, world frame.
    light_cam : CameraModel
        The perspective light camera of the map.

    Returns
    -------
    (float, float)
        ``k_x, k_y`` (pixels x world units).
    """
    c = as_finite_array(cell, "cell", shape=(2, 3))
    if not isinstance(light_cam, CameraModel) or light_cam.projection != "perspective":
        raise ValidationError(expected_got(
            "light_cam", "a perspective CameraModel (a point light sample: the penumbra comes "
            "from the light's extent)", getattr(light_cam, "projection", type(light_cam).__name__)))
    rc = c @ light_cam.world2cam[:3, :3].T  # (2, 3): the cell vectors in the camera frame
    return (float(light_cam.fx * np.abs(rc[:, 0]).sum()),
            float(light_cam.fy * np.abs(rc[:, 1]).sum()))


def filtered_visibility(points: np.ndarray, depth_map: np.ndarray, light_cam: CameraModel,
                        cell: np.ndarray, *, blocker: BlockerDepth = "search",
                        normals: np.ndarray | None = None, bias: ShadowBias | None = None,
                        tables: DepthTables | None = None) -> np.ndarray:
    """Fraction ``(P,)`` float32 of a light cell that each world point sees, from
    the map of the cell's sample (module docstring).

    Parameters
    ----------
    points : (P, 3) float
        Points, world frame.
    depth_map : (H, W) float32
        Light-view linear depth of the occluder, ``+inf`` where empty.
    light_cam : CameraModel
        The perspective camera ``depth_map`` was made with (the sample's).
    cell : (2, 3) float
        Half-extent vectors of the light cell around the sample, world frame
        (zero: the hard lookup).
    blocker : {"search", "mean"}
        Where the occluder depth of the kernel comes from: a blocker search per
        point (PCSS) or the map's mean occluder depth (PCF).
    normals : (P, 3) float, optional
        Unit normals for the slope bias.
    bias : ShadowBias, optional
        Depth-comparison bias (None: the defaults).
    tables : DepthTables, optional
        The map's tables, if already made.

    Returns
    -------
    (P,) float32
        Visible fraction in ``[0, 1]``.
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    kx, ky = cell_half_widths(cell, light_cam)
    dm = check_depth_map(depth_map, light_cam.shape)
    if blocker not in _MODES:
        raise ValidationError(expected_got("blocker", "'search' or 'mean'", repr(blocker)))
    if normals is not None:
        normals = as_finite_array(normals, "normals", shape=(len(pts), 3), dtype=np.float32)
    vis = np.ones(len(pts), np.float32)
    filter_into(vis, pts, dm, light_cam, (kx, ky), _MODES[blocker], normals,
                ShadowBias() if bias is None else bias, DepthTables.of(dm) if tables is None else tables)
    return vis


def point_chunks(pts: np.ndarray) -> np.ndarray:
    """Bounding boxes of consecutive runs of ``CHUNK_POINTS`` points, then of runs of
    ``CHUNK_GROUP`` such runs, for ``filter_into`` (made once when several maps
    filter the same points).

    Parameters
    ----------
    pts : (P, 3) float64
        Points, world frame (validated).

    Returns
    -------
    (C + G, 6) float64
        Per run: least x, y, z, then greatest x, y, z; the ``C = ceil(P / CHUNK_POINTS)``
        runs, then the ``G = ceil(C / CHUNK_GROUP)`` groups.
    """
    pts = np.ascontiguousarray(pts, np.float64)
    n_c = -(-len(pts) // CHUNK_POINTS)
    out = np.empty((n_c + -(-n_c // CHUNK_GROUP), 6))
    (_chunk_bounds_kernel if use_compiled(_chunk_bounds_kernel) else _chunk_bounds_loop)(
        pts, CHUNK_POINTS, CHUNK_GROUP, out)
    return out


def filter_into(vis: np.ndarray, pts: np.ndarray, dm: np.ndarray, light_cam: CameraModel,
                k: tuple[float, float], mode: int, normals: np.ndarray | None, b: ShadowBias,
                t: DepthTables, chunks: np.ndarray | None = None) -> None:
    """Write the filtered visibility of every point into ``vis`` (inputs already
    validated; ``k`` from :func:`cell_half_widths`, ``mode`` 0 mean, 1 search).

    Parameters
    ----------
    vis : (P,) float32
        Output.
    pts : (P, 3) float64
        Points, world frame.
    dm : (H, W) float
        The depth map.
    light_cam : CameraModel
        Its perspective camera.
    k : (float, float)
        Box half-widths per unit of ``1/z_b - 1/z_r``.
    mode : int
        0: the map's mean occluder depth; 1: blocker search.
    normals : (P, 3) float32 or None
        Unit normals for the slope bias.
    b : ShadowBias
        The bias.
    t : DepthTables
        The map's tables.
    chunks : (C, 6) float64, optional
        :func:`point_chunks` of ``pts`` (made here if not given).
    """
    pts = np.ascontiguousarray(pts, np.float64)
    if chunks is None:
        chunks = point_chunks(pts)
    nrm = np.zeros((0, 3), np.float32) if normals is None else np.ascontiguousarray(normals,
                                                                                    np.float32)
    head = (vis, pts, nrm,
            np.ascontiguousarray(light_cam.texture_matrix(), np.float64),
            np.ascontiguousarray(dm, np.float32), t.sat, t.pyramid, t.offsets, t.widths,
            int(t.origin[0]), int(t.origin[1]), float(light_cam.fx),
            np.asarray(light_cam.position, np.float64), float(k[0]), float(k[1]), int(mode),
            float(t.z_mean), float(t.z_min), float(b.constant), float(b.slope), float(b.max_tan),
            float(tol.PENUMBRA_MIN_HALF_TEXEL), float(tol.PX_EQUAL), int(CONTACT_TEXELS),
            np.ascontiguousarray(light_cam.world2cam[:3, :3], np.float64), float(light_cam.cx),
            float(light_cam.cy), float(light_cam.fy), chunks, CHUNK_POINTS, CHUNK_GROUP)
    kernel = _filter_kernel if use_compiled(_filter_kernel) else _filter_loop  # no numba: slow; correct
    n = WARP_THREADS if kernel is _filter_kernel and len(pts) >= PARALLEL_MIN_POINTS else 1
    # thread b: groups b, b + n, ... (the points' groups lie in bands: each thread gets its share)
    vis.fill(1.0)  # the points of runs that miss the map are left as they are
    futures = [band_pool().submit(kernel, *head, b, n, np.empty((BEHIND_KEEP, 3)),
                                  np.empty((BEHIND_SHARE_KEEP, 3))) for b in range(1, n)]
    kernel(*head, 0, n, np.empty((BEHIND_KEEP, 3)), np.empty((BEHIND_SHARE_KEEP, 3)))
    for f in futures:
        f.result()


# ----------------------------------------------------------------- the kernel
def _corner(g: float, n: int) -> tuple[int, float]:
    """Cell index and fraction of a corner coordinate ``g`` clamped into ``[0, n]``."""
    g = min(max(g, 0.0), float(n))
    i = min(int(g), n - 1)
    return i, g - i


def _bilerp(sat: np.ndarray, j: int, fy: float, i: int, fx: float, c: int) -> float:
    return ((sat[j, i, c] * (1 - fx) + sat[j, i + 1, c] * fx) * (1 - fy)
            + (sat[j + 1, i, c] * (1 - fx) + sat[j + 1, i + 1, c] * fx) * fy)


def _box_sums(sat: np.ndarray, x0: float, x1: float, y0: float, y1: float, depth: bool
              ) -> tuple[float, float]:
    """(coverage, depth) integrals of the texel image over the box (window coordinates):
    the summed-area tables read bilinearly at its corners (exact: the integral is
    bilinear inside a texel). The depth integral only when ``depth``."""
    h1, w1 = sat.shape[0] - 1, sat.shape[1] - 1
    i0, fx0 = _corner(x0 + 0.5, w1)
    i1, fx1 = _corner(x1 + 0.5, w1)
    j0, fy0 = _corner(y0 + 0.5, h1)
    j1, fy1 = _corner(y1 + 0.5, h1)
    cov = (_bilerp(sat, j1, fy1, i1, fx1, 0) - _bilerp(sat, j1, fy1, i0, fx0, 0)
           - _bilerp(sat, j0, fy0, i1, fx1, 0) + _bilerp(sat, j0, fy0, i0, fx0, 0))
    if not depth:
        return cov, 0.0
    dep = (_bilerp(sat, j1, fy1, i1, fx1, 1) - _bilerp(sat, j1, fy1, i0, fx0, 1)
           - _bilerp(sat, j0, fy0, i1, fx1, 1) + _bilerp(sat, j0, fy0, i0, fx0, 1))
    return cov, dep


def _box_max(pyr: np.ndarray, off: np.ndarray, wid: np.ndarray, i0: int, i1: int, j0: int,
             j1: int, fine: int) -> float:
    """An upper bound of the occluder depths in window texels ``[i0, i1] x [j0, j1]``: the
    blocks of the pyramid level ``2^-fine`` times the span wide (``fine = 2``: at most 5 x 5
    reads; ``fine = 0``: 2 x 2, a looser bound)."""
    span = max(i1 - i0, j1 - j0) + 1
    lev = 0
    while (1 << (lev + fine)) < span and lev < len(off) - 1:
        lev += 1
    o, w = off[lev], wid[lev]
    m = -np.inf
    for jj in range(j0 >> lev, (j1 >> lev) + 1):
        for ii in range(i0 >> lev, (i1 >> lev) + 1):
            m = max(m, pyr[o + jj * w + ii])
    return m


def _texel_threshold(i: float, j: float, zt: float, plane: bool, ax: float, ay: float, a0: float,
                     dpl: float, bias0: float) -> float:
    """The depth a texel ``(i, j)`` must be nearer than to hide the point: ``zt``, or with
    ``plane`` the receiver's plane through it (where the plane is in front of the light) less
    ``bias0``."""
    if plane:
        den = ax * i + ay * j + a0
        if den * dpl > 0:
            return dpl / den - bias0
    return zt


def _plane_min(dpl: float, ax: float, ay: float, a0: float, x0: float, x1: float, y0: float,
               y1: float) -> float:
    """The least depth of the receiver's plane over the box (at a corner: the depth is
    a ratio of affine functions of the pixel); ``-inf`` where the plane turns away."""
    m = np.inf
    for xx in (x0, x1):
        for yy in (y0, y1):
            den = ax * xx + ay * yy + a0
            if not den * dpl > 0:
                return -np.inf
            m = min(m, dpl / den)
    return m


def _behind(pyr: np.ndarray, off: np.ndarray, wid: np.ndarray, stack: np.ndarray, sub_w: int,
            sub_h: int, x0: float, x1: float, y0: float, y1: float, zt: float, plane: bool,
            dpl: float, ax: float, ay: float, a0: float, bias0: float, kept: np.ndarray
            ) -> tuple[float, float, int]:
    """(area, area x depth) of the occluder texels under the box (window coordinates, real
    edges) that are *not* in front of the receiver, each with the area it shares with the
    box: the tables' sums over the box less these are the sums over the occluders in
    front. In front: closer than the receiver's plane minus ``bias0`` at the texel with
    ``plane`` (where the plane faces the light), else than ``zt``. Block by block down the
    max-depth pyramid (level 0 is the window's depths): a block whose every occluder
    texel is in front, or that is empty, is skipped, so the cost grows with the texels
    behind the receiver (a surface shadowing itself, an object touching it), not with the
    box. The texels found go to ``kept`` (column, row, depth) as far as it has room; the
    third value is their count (all of them are there when it is at most ``len(kept)``)."""
    i0, i1 = max(int(np.floor(x0 + 0.5)), 0), min(int(np.floor(x1 + 0.5)), sub_w - 1)
    j0, j1 = max(int(np.floor(y0 + 0.5)), 0), min(int(np.floor(y1 + 0.5)), sub_h - 1)
    area, dsum, nk = 0.0, 0.0, 0
    if i0 > i1 or j0 > j1:
        return area, dsum, nk
    span = max(i1 - i0, j1 - j0) + 1
    lev = 0
    while (1 << lev) < span and lev < len(off) - 1:
        lev += 1
    n = 0
    for bj in range(j0 >> lev, (j1 >> lev) + 1):
        for bi in range(i0 >> lev, (i1 >> lev) + 1):
            stack[n, 0], stack[n, 1], stack[n, 2] = lev, bi, bj
            n += 1
    while n > 0:
        n -= 1
        lv, bi, bj = stack[n, 0], stack[n, 1], stack[n, 2]
        m = pyr[off[lv] + bj * wid[lv] + bi]
        if m == -np.inf:  # empty
            continue
        if lv == 0:
            if m < _texel_threshold(bi, bj, zt, plane, ax, ay, a0, dpl, bias0):  # in front
                continue
            if nk < kept.shape[0]:
                kept[nk, 0], kept[nk, 1], kept[nk, 2] = bi, bj, m
            nk += 1
            ox = min(x1, bi + 0.5) - max(x0, bi - 0.5)
            oy = min(y1, bj + 0.5) - max(y0, bj - 0.5)
            if ox > 0 and oy > 0:
                area += ox * oy
                dsum += ox * oy * m
            continue
        bx0, bx1 = max(bi << lv, i0), min(((bi + 1) << lv) - 1, i1)
        by0, by1 = max(bj << lv, j0), min(((bj + 1) << lv) - 1, j1)
        thr = zt
        if plane:
            thr = _plane_min(dpl, ax, ay, a0, bx0 - 0.5, bx1 + 0.5, by0 - 0.5, by1 + 0.5) - bias0
        if m < thr:  # all in front
            continue
        for cj in range(2):
            for ci in range(2):
                ci_, cj_ = 2 * bi + ci, 2 * bj + cj
                if (ci_ << (lv - 1)) <= i1 and (((ci_ + 1) << (lv - 1)) - 1) >= i0 and \
                        (cj_ << (lv - 1)) <= j1 and (((cj_ + 1) << (lv - 1)) - 1) >= j0:
                    stack[n, 0], stack[n, 1], stack[n, 2] = lv - 1, ci_, cj_
                    n += 1
    return area, dsum, nk


def _behind_kept(kept: np.ndarray, nk: int, x0: float, x1: float, y0: float, y1: float,
                 zt: float, plane: bool, dpl: float, ax: float, ay: float, a0: float,
                 bias0: float) -> float:
    """:func:`_behind`'s area over a smaller box with a higher threshold, from the texels a
    search over a box holding it kept (every texel behind then was behind there too)."""
    area = 0.0
    for q in range(nk):
        i, j, d = kept[q, 0], kept[q, 1], kept[q, 2]
        if d < _texel_threshold(i, j, zt, plane, ax, ay, a0, dpl, bias0):  # in front
            continue
        ox = min(x1, i + 0.5) - max(x0, i - 0.5)
        oy = min(y1, j + 0.5) - max(y0, j - 0.5)
        if ox > 0 and oy > 0:
            area += ox * oy
    return area


def _behind_shared(shared: np.ndarray, ns: int, i0: int, i1: int, j0: int, j1: int, zt: float,
                   plane: bool, dpl: float, ax: float, ay: float, a0: float, bias0: float,
                   kept: np.ndarray) -> tuple[float, float, int]:
    """:func:`_behind` over whole texels ``[i0, i1] x [j0, j1]`` from the ``ns`` texels of a
    wider search with a lower threshold (``shared``: every texel there behind any threshold
    at least that one): the same texels, tested alike (the same sums, in another order)."""
    area, dsum, nk = 0.0, 0.0, 0
    for q in range(ns):
        i, j, d = shared[q, 0], shared[q, 1], shared[q, 2]
        if i < i0 or i > i1 or j < j0 or j > j1:
            continue
        if d < _texel_threshold(i, j, zt, plane, ax, ay, a0, dpl, bias0):  # in front
            continue
        if nk < kept.shape[0]:
            kept[nk, 0], kept[nk, 1], kept[nk, 2] = i, j, d
        nk += 1
        area += 1.0
        dsum += d
    return area, dsum, nk


def _chunk_bounds_loop(pts: np.ndarray, size: int, group: int, out: np.ndarray) -> None:
    """:func:`point_chunks`: ``out[c] = (min x, min y, min z, max x, max y, max z)`` of
    points ``[c size, (c + 1) size)``, then of the groups of ``group`` runs."""
    n_c = -(-pts.shape[0] // size)
    for c in range(out.shape[0]):
        lo0, lo1, lo2 = np.inf, np.inf, np.inf
        hi0, hi1, hi2 = -np.inf, -np.inf, -np.inf
        if c < n_c:
            for k in range(c * size, min((c + 1) * size, pts.shape[0])):
                lo0, hi0 = min(lo0, pts[k, 0]), max(hi0, pts[k, 0])
                lo1, hi1 = min(lo1, pts[k, 1]), max(hi1, pts[k, 1])
                lo2, hi2 = min(lo2, pts[k, 2]), max(hi2, pts[k, 2])
        else:
            g = c - n_c
            for q in range(g * group, min((g + 1) * group, n_c)):
                lo0, lo1, lo2 = min(lo0, out[q, 0]), min(lo1, out[q, 1]), min(lo2, out[q, 2])
                hi0, hi1, hi2 = max(hi0, out[q, 3]), max(hi1, out[q, 4]), max(hi2, out[q, 5])
        out[c, 0], out[c, 1], out[c, 2], out[c, 3], out[c, 4], out[c, 5] = lo0, lo1, lo2, hi0, hi1, hi2


def _chunk_reach(T: np.ndarray, bounds: np.ndarray, c: int, inv_zb: float, kx: float,
                 ky: float, min_half: float) -> tuple[bool, float, float, float, float, float, float]:
    """``(ok, u0, u1, v0, v1, z0, z1)``: the map pixels ``[u0, u1] x [v0, v1]`` that the
    widest box of every point in bounding box ``c`` stays in, and the points' depths
    ``[z0, z1]`` (``ok`` False: some corner not in front of the camera). The box
    projects inside its corners' hull, and the widest box grows with depth."""
    ulo, uhi, vlo, vhi, zlo, zhi = np.inf, -np.inf, np.inf, -np.inf, np.inf, -np.inf
    for a in range(8):
        if ((a & 1 and bounds[c, 3] == bounds[c, 0]) or (a & 2 and bounds[c, 4] == bounds[c, 1])
                or (a & 4 and bounds[c, 5] == bounds[c, 2])):
            continue  # a flat box: the corner repeats one already projected
        x = bounds[c, 3] if a & 1 else bounds[c, 0]
        y = bounds[c, 4] if a & 2 else bounds[c, 1]
        z0 = bounds[c, 5] if a & 4 else bounds[c, 2]
        qw = T[3, 0] * x + T[3, 1] * y + T[3, 2] * z0 + T[3, 3]
        if not qw > tol.SHADOW_LOOKUP_W_MIN:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        iw = 1.0 / qw
        u = (T[0, 0] * x + T[0, 1] * y + T[0, 2] * z0 + T[0, 3]) * iw
        v = (T[1, 0] * x + T[1, 1] * y + T[1, 2] * z0 + T[1, 3]) * iw
        ulo, uhi, vlo, vhi = min(ulo, u), max(uhi, u), min(vlo, v), max(vhi, v)
        zc = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z0 + T[2, 3]
        zlo, zhi = min(zlo, zc), max(zhi, zc)
    if not zhi > 0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    s = inv_zb - 1.0 / zhi
    sx, sy = max(kx * s, min_half), max(ky * s, min_half)
    return True, ulo - sx, uhi + sx, vlo - sy, vhi + sy, zlo, zhi


def _chunk_misses(T: np.ndarray, bounds: np.ndarray, c: int, inv_zb: float, kx: float,
                  ky: float, min_half: float, xlo: float, xhi: float, ylo: float,
                  yhi: float) -> bool:
    """True when the widest box of every point in bounding box ``c`` misses the window
    ``[xlo, xhi] x [ylo, yhi]`` (map pixels, already widened by a margin)."""
    ok, u0, u1, v0, v1, _z0, _z1 = _chunk_reach(T, bounds, c, inv_zb, kx, ky, min_half)
    return ok and (u1 < xlo or v1 < ylo or u0 > xhi or v0 > yhi)


def _filter_loop(vis: np.ndarray, pts: np.ndarray, nrm: np.ndarray, T: np.ndarray,
                 dm: np.ndarray, sat: np.ndarray, pyr: np.ndarray, off: np.ndarray,
                 wid: np.ndarray, r0: int, c0: int, fx: float, L: np.ndarray, kx: float,
                 ky: float, mode: int, z_mean: float, z_min: float, b_const: float,
                 b_slope: float, b_max: float, min_half: float, area_floor: float, near: int,
                 R: np.ndarray, cx: float, cy: float, fy: float, bounds: np.ndarray,
                 chunk: int, group: int, g_first: int, g_step: int, kept: np.ndarray,
                 shared: np.ndarray) -> None:
    """The per-point loop (module docstring); ``vis`` (ones on entry) is written for the
    points of groups ``g_first, g_first + g_step, ...`` that may see an occluder.
    ``bounds``: :func:`_chunk_bounds_loop` of ``pts`` by ``chunk`` points and ``group``
    runs; ``kept``: room for the texels behind a point that its blocker search finds;
    ``shared``: room for those of a wider search that the next points share."""
    h, w = dm.shape
    sub_h, sub_w = sat.shape[0] - 1, sat.shape[1] - 1
    has_nrm = nrm.shape[0] > 0
    stack = np.empty((4 + 3 * len(off), 3), np.int64)  # _behind's depth-first stack
    inv_zb = 1.0 / (z_mean if mode == 0 else z_min)
    z_far = pyr[len(pyr) - 1]  # the pyramid's top: the farthest occluder texel
    # the occluder window in map pixels, widened by a texel against rounding
    xlo, xhi = c0 - 1.5, c0 + sub_w + 0.5
    ylo, yhi = r0 - 1.5, r0 + sub_h + 0.5
    n_p = pts.shape[0]
    n_c = -(-n_p // chunk)
    # the shared search: its texels' window box, threshold and count (-1: none)
    si0, si1, sj0, sj1, s_thr, ns = 0, -1, 0, -1, np.inf, -1
    share_m, share_d = BEHIND_SHARE_TEXELS, BEHIND_SHARE_DEPTH
    for g in range(g_first, bounds.shape[0] - n_c, g_step):
        if _chunk_misses(T, bounds, n_c + g, inv_zb, kx, ky, min_half, xlo, xhi, ylo, yhi):
            continue  # lit (the caller filled vis with ones)
        for ch in range(g * group, min((g + 1) * group, n_c)):
            k_end = min((ch + 1) * chunk, n_p)
            ok, u0, u1, v0, v1, zlo, zhi = _chunk_reach(T, bounds, ch, inv_zb, kx, ky, min_half)
            if ok and (u1 < xlo or v1 < ylo or u0 > xhi or v0 > yhi):
                continue  # every widest box misses the occluder window
            all_fast = False
            if ok and zlo > 0:  # the run's widest boxes in whole window texels (a texel wider)
                ri0 = max(int(np.floor(u0 - c0 + 0.5)) - 1, 0)
                ri1 = min(int(np.floor(u1 - c0 + 0.5)) + 1, sub_w - 1)
                rj0 = max(int(np.floor(v0 - r0 + 0.5)) - 1, 0)
                rj1 = min(int(np.floor(v1 - r0 + 0.5)) + 1, sub_h - 1)
                if ri0 > ri1 or rj0 > rj1 or sat[rj1 + 1, ri1 + 1, 0] - sat[rj0, ri1 + 1, 0] \
                        - sat[rj1 + 1, ri0, 0] + sat[rj0, ri0, 0] == 0:
                    continue  # no occluder texel under any widest box: lit
                if not has_nrm:  # the least depth a point of the run tests against (zs below)
                    t_hi = zhi / fx
                    slope1 = b_slope * min(1.0, b_max)
                    s_hi = inv_zb - 1.0 / zhi  # every point's sx, sy is at most sw
                    sw = max(max(kx * s_hi, ky * s_hi), min_half)
                    z_lo = zlo - t_hi * (b_const + slope1) - t_hi * slope1 * sw
                    z_lo -= abs(z_lo) * tol.REL_EQUAL
                    all_fast = _box_max(pyr, off, wid, ri0, ri1, rj0, rj1, 2) < z_lo
            for k in range(ch * chunk, k_end):
                vis[k] = 1.0
                x, y, z0 = pts[k, 0], pts[k, 1], pts[k, 2]
                qw = T[3, 0] * x + T[3, 1] * y + T[3, 2] * z0 + T[3, 3]
                if not qw > tol.SHADOW_LOOKUP_W_MIN:
                    continue
                z = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z0 + T[2, 3]
                inv_w = 1.0 / qw  # one division: a perspective camera's w is its linear depth
                inv_z = inv_w if z == qw else 1.0 / z
                s = inv_zb - inv_z  # the widest box, per unit k
                # window coordinates of the point
                pxa = (T[0, 0] * x + T[0, 1] * y + T[0, 2] * z0 + T[0, 3]) * inv_w
                pya = (T[1, 0] * x + T[1, 1] * y + T[1, 2] * z0 + T[1, 3]) * inv_w
                px, py = pxa - c0, pya - r0
                sx, sy = max(kx * s, min_half), max(ky * s, min_half)
                if px + sx < -0.5 or py + sy < -0.5 or px - sx > sub_w - 0.5 or py - sy > sub_h - 0.5:
                    continue  # the widest box misses every occluder texel
                texel = abs(z) / fx
                tan = 1.0
                n0, n1, n2 = 0.0, 0.0, 0.0
                if has_nrm:
                    n0, n1, n2 = np.float64(nrm[k, 0]), np.float64(nrm[k, 1]), np.float64(nrm[k, 2])
                    if n0 * n0 + n1 * n1 + n2 * n2 > 0:
                        t0, t1, t2 = L[0] - x, L[1] - y, L[2] - z0
                        tl = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
                        cos = abs(n0 * (t0 / tl) + n1 * (t1 / tl) + n2 * (t2 / tl))
                        tan = np.sqrt(max(1 - cos * cos, 0.0)) / max(cos, tol.SHADOW_GRAZING_COS)
                slope = b_slope * min(tan, b_max)
                bias0 = texel * (b_const + slope)
                zt = z - bias0  # occluders closer than this block
                # the receiver's plane (with a normal): depth dpl / (ax i + ay j + a0) at window texel (i, j)
                plane = has_nrm and (n0 * n0 + n1 * n1 + n2 * n2 > 0)
                dpl, ax, ay, a0, bias_p = 0.0, 0.0, 0.0, 0.0, bias0
                if plane:
                    m0 = R[0, 0] * n0 + R[0, 1] * n1 + R[0, 2] * n2
                    m1 = R[1, 0] * n0 + R[1, 1] * n1 + R[1, 2] * n2
                    m2 = R[2, 0] * n0 + R[2, 1] * n1 + R[2, 2] * n2
                    dpl = m0 * (pxa - cx) * z / fx + m1 * (pya - cy) * z / fy + m2 * z
                    ax, ay = m0 / fx, m1 / fy
                    a0 = m2 + m0 * (c0 - cx) / fx + m1 * (r0 - cy) / fy
                    bias_p = texel * b_const
                hx, hy = kx * s, ky * s
                fast = False
                nk = kept.shape[0] + 1  # no texels kept yet
                if max(hx, hy) >= min_half:
                    if plane:
                        zs = _plane_min(dpl, ax, ay, a0, px - sx, px + sx, py - sy, py + sy) - bias_p
                    else:  # no normal: the receiver may slope by tan = 1 across the box
                        zs = zt - texel * slope * max(sx, sy)
                    i0 = max(int(np.floor(px - sx + 0.5)), 0)
                    i1 = min(int(np.floor(px + sx + 0.5)), sub_w - 1)
                    j0 = max(int(np.floor(py - sy + 0.5)), 0)
                    j1 = min(int(np.floor(py + sy + 0.5)), sub_h - 1)
                    # occluder texels under the widest box (whole texels i0..i1, j0..j1): a count, exact
                    a = sat[j1 + 1, i1 + 1, 0] - sat[j0, i1 + 1, 0] - sat[j1 + 1, i0, 0] + sat[j0, i0, 0]
                    if a == 0:
                        continue  # no occluder texel under the widest box
                    # every occluder texel under the box in front: the tables answer. Any upper
                    # bound of their depths decides it (a loose one only sends more points to the
                    # exact search below): the map's farthest, 2 x 2 blocks as wide as the box, 5 x 5
                    fast = all_fast or z_far < zs or _box_max(pyr, off, wid, i0, i1, j0, j1, 0) < zs \
                        or _box_max(pyr, off, wid, i0, i1, j0, j1, 2) < zs
                    if mode == 1:  # blocker search over the widest box's whole texels
                        ds = sat[j1 + 1, i1 + 1, 1] - sat[j0, i1 + 1, 1] - sat[j1 + 1, i0, 1] + sat[j0, i0, 1]
                        if not fast:  # less the occluder texels behind the point
                            # the least threshold of a texel of the box (texel centres reach
                            # half a texel past the box: the plane's least over them too)
                            lo = zs
                            if plane:
                                lo = min(zs, _plane_min(dpl, ax, ay, a0, i0, i1, j0, j1) - bias_p)
                            lo -= abs(lo) * tol.REL_EQUAL  # rounding inside the box
                            inside = si0 <= i0 and i1 <= si1 and sj0 <= j0 and j1 <= sj1 and lo >= s_thr
                            if not inside and lo > -np.inf:  # a new shared search (-1: too many)
                                si0, si1 = max(i0 - share_m, 0), min(i1 + share_m, sub_w - 1)
                                sj0, sj1 = max(j0 - share_m, 0), min(j1 + share_m, sub_h - 1)
                                s_thr = lo - share_d * texel
                                _ba, _bd, ns = _behind(pyr, off, wid, stack, sub_w, sub_h, si0 - 0.5,
                                                       si1 + 0.5, sj0 - 0.5, sj1 + 0.5, s_thr, False,
                                                       0.0, 0.0, 0.0, 0.0, 0.0, shared)
                                ns = ns if ns <= shared.shape[0] else -1
                                inside = True
                            if inside and ns >= 0:
                                ba, bd, nk = _behind_shared(shared, ns, i0, i1, j0, j1, zs, plane, dpl,
                                                            ax, ay, a0, bias_p, kept)
                            else:
                                ba, bd, nk = _behind(pyr, off, wid, stack, sub_w, sub_h, i0 - 0.5,
                                                     i1 + 0.5, j0 - 0.5, j1 + 0.5, zs, plane, dpl,
                                                     ax, ay, a0, bias_p, kept)
                            a -= ba
                            ds -= bd
                        if a <= area_floor:
                            continue  # no blocker in reach: the whole cell is seen
                        if (fast and zs <= zt and a == (i1 - i0 + 1) * (j1 - j0 + 1)
                                and px - sx >= i0 - 0.5 and px + sx <= i1 + 0.5
                                and py - sy >= j0 - 0.5 and py + sy <= j1 + 0.5):
                            # umbra: every texel under the widest box (which holds the kernel's
                            # box and the nearest texel) is an occluder in front of the point
                            vis[k] = 0.0
                            continue
                        s = a / ds - inv_z
                        # contact: a blocker next to the point (its texel and the 8 around)
                        # nearer the point than the mean narrows the kernel to its depth (the
                        # farthest such blocker: 1/occ - 1/z falls as occ grows)
                        c, r = int(np.rint(pxa)), int(np.rint(pya))
                        far = -np.inf
                        for rr in range(max(r - near, 0), min(r + near + 1, h)):
                            for cc in range(max(c - near, 0), min(c + near + 1, w)):
                                occ = np.float64(dm[rr, cc])
                                if occ < zt and occ > far:
                                    far = occ
                        if far > -np.inf:
                            s = min(s, 1.0 / far - inv_z)
                        hx, hy = kx * s, ky * s
                if not max(hx, hy) >= min_half:  # the hard lookup (nearest texel)
                    c, r = np.rint(pxa), np.rint(pya)
                    if c >= 0 and c < w and r >= 0 and r < h:
                        occ = np.float64(dm[int(r), int(c)])
                        if np.isfinite(occ) and z > occ + texel * (b_const + slope):
                            vis[k] = 0.0
                    continue
                hx, hy = max(hx, min_half), max(hy, min_half)
                # the kernel box lies inside the widest box: with fast, every occluder under it
                # is in front (with a smaller bias); else less those behind the point
                a, _ds = _box_sums(sat, px - hx, px + hx, py - hy, py + hy, False)
                if not fast:
                    zk = zt - texel * slope * max(hx, hy)
                    if nk <= kept.shape[0]:  # the search kept every texel behind (a superset)
                        a -= _behind_kept(kept, nk, px - hx, px + hx, py - hy, py + hy, zk, plane,
                                          dpl, ax, ay, a0, bias_p)
                    else:
                        ba, _bd, _nk = _behind(pyr, off, wid, stack, sub_w, sub_h, px - hx, px + hx,
                                               py - hy, py + hy, zk, plane, dpl, ax, ay, a0, bias_p,
                                               kept)
                        a -= ba
                vis[k] = np.float32(min(max(1.0 - a / (4.0 * hx * hy), 0.0), 1.0))


# numba resolves the helpers when it compiles the loop (at its first call): rebind them first
_corner = compile_kernel(_corner) or _corner
_bilerp = compile_kernel(_bilerp) or _bilerp
_box_sums = compile_kernel(_box_sums) or _box_sums
_box_max = compile_kernel(_box_max) or _box_max
_plane_min = compile_kernel(_plane_min) or _plane_min
_texel_threshold = compile_kernel(_texel_threshold) or _texel_threshold
_behind = compile_kernel(_behind) or _behind
_behind_kept = compile_kernel(_behind_kept) or _behind_kept
_behind_shared = compile_kernel(_behind_shared) or _behind_shared
_chunk_reach = compile_kernel(_chunk_reach) or _chunk_reach
_chunk_misses = compile_kernel(_chunk_misses) or _chunk_misses
_filter_kernel = compile_kernel(_filter_loop)
_chunk_bounds_kernel = compile_kernel(_chunk_bounds_loop)
