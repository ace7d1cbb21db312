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
:class:`~morphkit.shadow.penumbra.PenumbraSoftShadow` methods differ only in
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

Speed. Per map, summed-area tables of occluder coverage and depth (one pass)
make a box's coverage and depth sum four bilinear reads each, whatever its size;
a max-depth pyramid tells in four reads whether every occluder texel under the
box is in front of the receiver (always so for a receiver below the object). Only
boxes that hold occluder texels both in front of and behind the point (a surface
shadowing itself) are summed texel by texel.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..settings import compile_kernel, use_compiled
from ..validate import as_finite_array
from .lookup import ShadowBias, check_depth_map

__all__ = ["DepthTables", "filtered_visibility", "cell_half_widths", "BlockerDepth"]

#: How a filtered lookup finds the occluders' depth per map: ``"mean"`` (one mean blocker depth
#: per map, PCF) or ``"search"`` (a blocker search per point, PCSS).
BlockerDepth = Literal["mean", "search"]
_MODES = {"mean": 0, "search": 1}
#: Contact hardening reach (texels) of the blocker search (module docstring): the point's
#: texel and its 8 neighbours, enough to catch a blocker the nearest-texel rounding misses.
CONTACT_TEXELS = 1


@dataclass(frozen=True)
class DepthTables:
    """Per-map tables of the filtered lookup (see the module docstring), over the
    window of the map that holds occluder texels (outside it the map is empty).

    Parameters
    ----------
    sat : (h + 1, w + 1, 2) float64
        Summed-area tables of occluder coverage (``[..., 0]``) and depth
        (``[..., 1]``) over the window (``sat[j, i]``: texels of window rows ``< j``
        and columns ``< i``).
    pyramid : (M,) float64
        Max-depth pyramid of the window, levels concatenated (``-inf``: no occluder).
    offsets : (L,) int64
        Start of each level in ``pyramid``.
    widths : (L,) int64
        Width of each level (level ``l`` has ``ceil(w / 2^l)`` columns).
    origin : (int, int)
        Map row and column of the window's first texel.
    z_min : float
        Nearest occluder depth (``+inf`` for an empty map).
    z_mean : float
        Mean occluder depth (``+inf`` for an empty map).
    """

    sat: np.ndarray
    pyramid: np.ndarray
    offsets: np.ndarray
    widths: np.ndarray
    origin: tuple[int, int]
    z_min: float
    z_mean: float

    @classmethod
    def of(cls, depth_map: np.ndarray) -> DepthTables:
        """The tables of a (checked) depth map.

        Parameters
        ----------
        depth_map : (H, W) float32 or float64
            Linear light depth, ``+inf`` where empty.

        Returns
        -------
        DepthTables
            Its summed-area tables, pyramid and depth statistics.
        """
        box = np.zeros(4, np.int64)
        (_bbox_kernel if use_compiled(_bbox_kernel) else _bbox_loop)(depth_map, box)
        r0, r1, c0, c1 = (int(v) for v in box)
        if r1 < r0:
            return cls(np.zeros((2, 2, 2)), np.full(1, -np.inf), np.zeros(1, np.int64),
                       np.ones(1, np.int64), (0, 0), np.inf, np.inf)
        sub = np.ascontiguousarray(depth_map[r0:r1 + 1, c0:c1 + 1], np.float64)
        h, w = sub.shape
        shapes = [(h, w)]
        while shapes[-1] != (1, 1):
            shapes.append(((shapes[-1][0] + 1) // 2, (shapes[-1][1] + 1) // 2))
        sizes = np.array([a * b for a, b in shapes], np.int64)
        offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        widths = np.array([b for _a, b in shapes], np.int64)
        sat = np.zeros((h + 1, w + 1, 2))
        pyramid = np.empty(int(sizes.sum()))
        stats = np.zeros(2)
        tables = _tables_kernel if use_compiled(_tables_kernel) else _tables_loop
        tables(sub, sat, pyramid, offsets, widths, stats)
        return cls(sat, pyramid, offsets, widths, (r0, c0), float(stats[0]),
                   float(stats[1] / sat[-1, -1, 0]))


def _bbox_loop(dm: np.ndarray, box: np.ndarray) -> None:
    """``box = (first row, last row, first column, last column)`` of the finite texels
    (last < first when there are none)."""
    h, w = dm.shape
    r0, r1, c0, c1 = h, -1, w, -1
    for j in range(h):
        for i in range(w):
            if dm[j, i] < np.inf:
                r0, r1 = min(r0, j), max(r1, j)
                c0, c1 = min(c0, i), max(c1, i)
    box[0], box[1], box[2], box[3] = r0, r1, c0, c1


def _tables_loop(sub: np.ndarray, sat: np.ndarray, pyr: np.ndarray, off: np.ndarray,
                 wid: np.ndarray, stats: np.ndarray) -> None:
    """Fill the summed-area tables and the pyramid; ``stats = (z_min, depth sum)``."""
    h, w = sub.shape
    z_min = np.inf
    for j in range(h):
        c_row, d_row = 0.0, 0.0
        for i in range(w):
            d = sub[j, i]
            if d < np.inf:
                c_row += 1.0
                d_row += d
                z_min = min(z_min, d)
                pyr[j * w + i] = d
            else:
                pyr[j * w + i] = -np.inf
            sat[j + 1, i + 1, 0] = sat[j, i + 1, 0] + c_row
            sat[j + 1, i + 1, 1] = sat[j, i + 1, 1] + d_row
    stats[0] = z_min
    stats[1] = sat[h, w, 1]
    ph, pw = h, w
    for lev in range(1, len(off)):
        nh, nw = (ph + 1) // 2, (pw + 1) // 2
        po, no = off[lev - 1], off[lev]
        for j in range(nh):
            for i in range(nw):
                m = -np.inf
                for jj in range(2 * j, min(2 * j + 2, ph)):
                    for ii in range(2 * i, min(2 * i + 2, pw)):
                        m = max(m, pyr[po + jj * pw + ii])
                pyr[no + j * nw + i] = m
        ph, pw = nh, nw


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


def filter_into(vis: np.ndarray, pts: np.ndarray, dm: np.ndarray, light_cam: CameraModel,
                k: tuple[float, float], mode: int, normals: np.ndarray | None, b: ShadowBias,
                t: DepthTables) -> None:
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
    """
    nrm = np.zeros((0, 3), np.float32) if normals is None else np.ascontiguousarray(normals,
                                                                                    np.float32)
    args = (vis, np.ascontiguousarray(pts, np.float64), nrm,
            np.ascontiguousarray(light_cam.texture_matrix(), np.float64),
            np.ascontiguousarray(dm, np.float32), t.sat, t.pyramid, t.offsets, t.widths,
            int(t.origin[0]), int(t.origin[1]), float(light_cam.fx),
            np.asarray(light_cam.position, np.float64), float(k[0]), float(k[1]), int(mode),
            float(t.z_mean), float(t.z_min), float(b.constant), float(b.slope), float(b.max_tan),
            float(tol.PENUMBRA_MIN_HALF_TEXEL), float(tol.PX_EQUAL), int(CONTACT_TEXELS),
            np.ascontiguousarray(light_cam.world2cam[:3, :3], np.float64), float(light_cam.cx),
            float(light_cam.cy), float(light_cam.fy))
    if use_compiled(_filter_kernel):
        _filter_kernel(*args)
    else:  # no numba: the same loop, interpreted (slow; correct)
        _filter_loop(*args)


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
             j1: int) -> float:
    """An upper bound of the occluder depths in window texels ``[i0, i1] x [j0, j1]``."""
    span = max(i1 - i0, j1 - j0) + 1
    lev = 0
    while (1 << lev) < span and lev < len(off) - 1:
        lev += 1
    o, w = off[lev], wid[lev]
    m = -np.inf
    for jj in range(j0 >> lev, (j1 >> lev) + 1):
        for ii in range(i0 >> lev, (i1 >> lev) + 1):
            m = max(m, pyr[o + jj * w + ii])
    return m


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


def _box_scan(sub_h: int, sub_w: int, pyr: np.ndarray, x0: float, x1: float, y0: float,
              y1: float, zt: float, plane: bool, dpl: float, ax: float, ay: float, a0: float,
              bias0: float, si0: int, si1: int, sj0: int, sj1: int) -> tuple[float, float]:
    """Texel by texel: (area, area x depth) of occluder texels under the box in front of
    the receiver (level 0 of the pyramid is the window's depths): closer than the
    receiver's plane minus ``bias0`` at the texel with ``plane``, else than ``zt``.
    Texels in ``[si0, si1] x [sj0, sj1]`` are skipped (counted by the caller)."""
    i0, i1 = max(int(np.floor(x0 + 0.5)), 0), min(int(np.floor(x1 + 0.5)), sub_w - 1)
    j0, j1 = max(int(np.floor(y0 + 0.5)), 0), min(int(np.floor(y1 + 0.5)), sub_h - 1)
    area, dsum = 0.0, 0.0
    for j in range(j0, j1 + 1):
        oy = min(y1, j + 0.5) - max(y0, j - 0.5)
        if oy <= 0:
            continue
        skip = sj0 <= j <= sj1
        for part in range(2 if skip else 1):
            ia, ib = i0, i1
            if skip:
                ia, ib = (i0, min(i1, si0 - 1)) if part == 0 else (max(i0, si1 + 1), i1)
            for i in range(ia, ib + 1):
                d = pyr[j * sub_w + i]
                if not d > -np.inf:  # empty
                    continue
                thr = zt
                if plane:
                    den = ax * i + ay * j + a0
                    if den * dpl > 0:
                        thr = dpl / den - bias0
                if not d < thr:  # not in front
                    continue
                ox = min(x1, i + 0.5) - max(x0, i - 0.5)
                if ox > 0:
                    area += ox * oy
                    dsum += ox * oy * d
    return area, dsum


def _search_tree(sat: np.ndarray, pyr: np.ndarray, off: np.ndarray, wid: np.ndarray,
                 stack: np.ndarray, i0: int, i1: int, j0: int, j1: int, zt: float, plane: bool,
                 dpl: float, ax: float, ay: float, a0: float, bias0: float
                 ) -> tuple[float, float]:
    """:func:`_box_scan` over the whole texels ``[i0, i1] x [j0, j1]``, block by block
    down the max-depth pyramid: a block whose every occluder texel is in front is
    summed from the tables, an empty one skipped, a mixed one split (cost grows with
    the mixed region's outline, not the box's area)."""
    sub_h, sub_w = sat.shape[0] - 1, sat.shape[1] - 1
    span = max(i1 - i0, j1 - j0) + 1
    lev = 0
    while (1 << lev) < span and lev < len(off) - 1:
        lev += 1
    n = 0
    for bj in range(j0 >> lev, (j1 >> lev) + 1):
        for bi in range(i0 >> lev, (i1 >> lev) + 1):
            stack[n, 0], stack[n, 1], stack[n, 2] = lev, bi, bj
            n += 1
    area, dsum = 0.0, 0.0
    while n > 0:
        n -= 1
        lv, bi, bj = stack[n, 0], stack[n, 1], stack[n, 2]
        x0, x1 = max(bi << lv, i0), min(((bi + 1) << lv) - 1, i1, sub_w - 1)
        y0, y1 = max(bj << lv, j0), min(((bj + 1) << lv) - 1, j1, sub_h - 1)
        if x0 > x1 or y0 > y1:
            continue
        m = pyr[off[lv] + bj * wid[lv] + bi]
        if m == -np.inf:
            continue
        if lv == 0:
            thr = zt
            if plane:
                den = ax * x0 + ay * y0 + a0
                if den * dpl > 0:
                    thr = dpl / den - bias0
            if m < thr:
                area += 1.0
                dsum += m
            continue
        thr = zt
        if plane:
            thr = _plane_min(dpl, ax, ay, a0, x0 - 0.5, x1 + 0.5, y0 - 0.5, y1 + 0.5) - bias0
        if m < thr:  # all in front: the tables
            area += sat[y1 + 1, x1 + 1, 0] - sat[y0, x1 + 1, 0] - sat[y1 + 1, x0, 0] + sat[y0, x0, 0]
            dsum += sat[y1 + 1, x1 + 1, 1] - sat[y0, x1 + 1, 1] - sat[y1 + 1, x0, 1] + sat[y0, x0, 1]
            continue
        for cj in range(2):
            for ci in range(2):
                stack[n, 0], stack[n, 1], stack[n, 2] = lv - 1, 2 * bi + ci, 2 * bj + cj
                n += 1
    return area, dsum


def _filter_loop(vis: np.ndarray, pts: np.ndarray, nrm: np.ndarray, T: np.ndarray,
                 dm: np.ndarray, sat: np.ndarray, pyr: np.ndarray, off: np.ndarray,
                 wid: np.ndarray, r0: int, c0: int, fx: float, L: np.ndarray, kx: float,
                 ky: float, mode: int, z_mean: float, z_min: float, b_const: float,
                 b_slope: float, b_max: float, min_half: float, area_floor: float, near: int,
                 R: np.ndarray, cx: float, cy: float, fy: float) -> None:
    """The per-point loop (module docstring); ``vis`` is written for every point."""
    h, w = dm.shape
    sub_h, sub_w = sat.shape[0] - 1, sat.shape[1] - 1
    has_nrm = nrm.shape[0] > 0
    stack = np.empty((4 + 3 * len(off), 3), np.int64)  # _search_tree's depth-first stack
    for k in range(pts.shape[0]):
        vis[k] = 1.0
        x, y, z0 = pts[k, 0], pts[k, 1], pts[k, 2]
        qw = T[3, 0] * x + T[3, 1] * y + T[3, 2] * z0 + T[3, 3]
        if not qw > tol.SHADOW_LOOKUP_W_MIN:
            continue
        z = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z0 + T[2, 3]
        s = 1.0 / (z_mean if mode == 0 else z_min) - 1.0 / z  # the widest box, per unit k
        # window coordinates of the point
        pxa = (T[0, 0] * x + T[0, 1] * y + T[0, 2] * z0 + T[0, 3]) / qw
        pya = (T[1, 0] * x + T[1, 1] * y + T[1, 2] * z0 + T[1, 3]) / qw
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
        if max(hx, hy) >= min_half:
            if plane:
                zs = _plane_min(dpl, ax, ay, a0, px - sx, px + sx, py - sy, py + sy) - bias_p
            else:  # no normal: the receiver may slope by tan = 1 across the box
                zs = zt - texel * slope * max(sx, sy)
            i0, i1 = max(int(np.floor(px - sx + 0.5)), 0), min(int(np.floor(px + sx + 0.5)), sub_w - 1)
            j0, j1 = max(int(np.floor(py - sy + 0.5)), 0), min(int(np.floor(py + sy + 0.5)), sub_h - 1)
            m = _box_max(pyr, off, wid, i0, i1, j0, j1)
            if m == -np.inf:
                continue  # no occluder texel under the widest box
            fast = m < zs  # every occluder texel under the box is in front: the tables answer
            if mode == 1:  # blocker search over the widest box
                if fast:  # whole texels (i0..i1, j0..j1): the mean depth needs no more
                    a = (sat[j1 + 1, i1 + 1, 0] - sat[j0, i1 + 1, 0] - sat[j1 + 1, i0, 0]
                         + sat[j0, i0, 0])
                    ds = (sat[j1 + 1, i1 + 1, 1] - sat[j0, i1 + 1, 1] - sat[j1 + 1, i0, 1]
                          + sat[j0, i0, 1])
                else:
                    a, ds = _search_tree(sat, pyr, off, wid, stack, i0, i1, j0, j1, zs, plane,
                                         dpl, ax, ay, a0, bias_p)
                if a <= area_floor:
                    continue  # no blocker in reach: the whole cell is seen
                s = 1.0 / (ds / a) - 1.0 / z
                # contact: a blocker next to the point (its texel and the 8 around)
                # nearer the point than the mean narrows the kernel to its depth
                c, r = int(np.rint(pxa)), int(np.rint(pya))
                for rr in range(max(r - near, 0), min(r + near + 1, h)):
                    for cc in range(max(c - near, 0), min(c + near + 1, w)):
                        occ = np.float64(dm[rr, cc])
                        if occ < zt:
                            s = min(s, 1.0 / occ - 1.0 / z)
                hx, hy = kx * s, ky * s
        if not max(hx, hy) >= min_half:  # the hard lookup (nearest texel)
            c, r = np.rint(pxa), np.rint(pya)
            if c >= 0 and c < w and r >= 0 and r < h:
                occ = np.float64(dm[int(r), int(c)])
                if np.isfinite(occ) and z > occ + texel * (b_const + slope):
                    vis[k] = 0.0
            continue
        hx, hy = max(hx, min_half), max(hy, min_half)
        if fast:  # the kernel box lies inside the widest box, with a smaller bias
            a, _ds = _box_sums(sat, px - hx, px + hx, py - hy, py + hy, False)
        else:
            zk = zt - texel * slope * max(hx, hy)
            # whole texels inside the box from the pyramid and tables, the border texel by texel
            si0, si1 = max(int(np.ceil(px - hx + 0.5)), 0), min(int(np.floor(px + hx - 0.5)), sub_w - 1)
            sj0, sj1 = max(int(np.ceil(py - hy + 0.5)), 0), min(int(np.floor(py + hy - 0.5)), sub_h - 1)
            a = 0.0
            if si0 <= si1 and sj0 <= sj1:
                a, _ds = _search_tree(sat, pyr, off, wid, stack, si0, si1, sj0, sj1, zk, plane,
                                      dpl, ax, ay, a0, bias_p)
            else:
                si0, si1 = 0, -1
            b, _ds = _box_scan(sub_h, sub_w, pyr, px - hx, px + hx, py - hy, py + hy, zk, plane,
                               dpl, ax, ay, a0, bias_p, si0, si1, sj0, sj1)
            a += b
        vis[k] = np.float32(min(max(1.0 - a / (4.0 * hx * hy), 0.0), 1.0))


# numba resolves the helpers when it compiles the loop (at its first call): rebind them first
_corner = compile_kernel(_corner) or _corner
_bilerp = compile_kernel(_bilerp) or _bilerp
_box_sums = compile_kernel(_box_sums) or _box_sums
_box_max = compile_kernel(_box_max) or _box_max
_plane_min = compile_kernel(_plane_min) or _plane_min
_box_scan = compile_kernel(_box_scan) or _box_scan
_search_tree = compile_kernel(_search_tree) or _search_tree
_filter_kernel = compile_kernel(_filter_loop)
_tables_kernel = compile_kernel(_tables_loop)
_bbox_kernel = compile_kernel(_bbox_loop)
