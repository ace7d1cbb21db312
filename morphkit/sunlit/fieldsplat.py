"""A field's light view by splatting its instances' atlas points: the cheap sun change.

:class:`SplatDrawer` draws the depth of a field's light view (:mod:`.fieldshadow`) by
**reprojecting the atlas views' texels per point** (Kang & Ihm's per-pixel warp of the
neighbouring maps, here forward): for each instance, the sun is turned into its object frame
(:func:`~morphkit.sunlit.sunatlas.sun_in_object`: the same elevation, the azimuth minus its
yaw), the atlas views of the dome triangle around that direction are chosen
(:meth:`~morphkit.views.dome.ViewDome.weights_many`), and each drawn texel of each of
those views, a surface point of the object (:meth:`~morphkit.sunlit.sunatlas.SunAtlas.view_points`),
is taken by the instance's pose and the field camera's texture matrix to a field texel and
its depth along the light; the field keeps the nearest (``min``). Nothing is morphed or
cached per sun: a sun change costs one pass over the points, whatever the yaws and the
meshes' face counts (the points are the atlas's texels).

**Splat size.** A point stands for one atlas texel of its view: a patch of surface whose
area, seen from the view head-on, is one texel. In the field that texel is a square of
``f = scale * field texels per unit / atlas texels per unit`` texels a side, and the patch,
seen from the sun instead, is foreshortened by ``|n . s| / |n . d|`` (its normal ``n``
estimated from the view's depth, :meth:`~morphkit.sunlit.sunatlas.SunAtlas.view_points`;
``s`` the sun, ``d`` the view, object frame; ``|n . d|`` at least
:data:`~morphkit.tol.SPLAT_MIN_COS`). The point fills the field texels whose centres lie in
a square of side ``f * sqrt(min(1, |n . s| / |n . d|))`` centred on it (none when the square
falls between centres: its neighbours' squares hold them). So the drawn texels are about
those whose centres the surface covers, the coverage a rasteriser gives: a full square at
a patch the sun grazes (the shadow's outline) would reach half a texel past it, and "every
texel a point lands in" would grow the shadow by half a texel all round. A patch the sun
sees more squarely than its view is not grown (the other two views' points fill it).

**Quads** (instances drawn at level 0, below). A square about each point has one depth across
it and reaches up to half its side past the surface's edge: past a crease (a crate's top meeting
its side) it lies in front of the face beyond, which then shadows itself where the sun grazes it
(at 512 texels, nearly all the atlas's false shadows on the instances' own surfaces). So each
view's **quads**, four drawn texels meeting at a corner at nearby depths
(:meth:`~morphkit.sunlit.sunatlas.SunAtlas.packed_quads`, :func:`~morphkit.sunlit.pointlevels.grid_quads`),
are drawn as two triangles, their depth interpolated (the view's depth map drawn as a mesh: a
triangle covers the field texels whose centres it contains, edges included, as a rasteriser
does; a quad is rasterised as one, each texel centre in its box taking the first of its two
triangles that holds it, so a centre on the diagonal is drawn once); only the points not inside
four quads (the view's outline, a depth edge, a surface the view grazes) keep their squares.
Coarser levels have no grid and keep squares.
``SplatDrawer(quads=False)`` draws squares only (the drawer before quads).

**Holes** between points (a surface the views see obliquely, a grid turned by the yaw) are
closed afterwards: an empty texel between two drawn ones (left and right, or above and
below) takes the nearest depth of its four neighbours (``cv2.erode``). A ``3 x 3``
morphological closing would also fill every step of a slanted silhouette, a shadow grown
by up to a texel along every edge that is not axis-aligned.

**Levels** (only what a scene needs: small or far casters get coarser points). Where the field's
texel is wider than an atlas texel (``f < 1``: a wide field, a map capped at
:data:`~morphkit.tol.SUN_FIELD_MAX_SIDE`, a small instance) most points land on a texel another
point of the same view already holds. Each instance is drawn instead from the coarsest **level**
``l`` of its atlas's points (:meth:`~morphkit.sunlit.sunatlas.SunAtlas.packed_points`, one point
per ``2**l`` texels a side, :mod:`.pointlevels`; made once per atlas and level, kept by the atlas)
whose texel stays within :data:`~morphkit.tol.SPLAT_LEVEL_MAX_TEXELS` field texels,
``2**l * f <= SPLAT_LEVEL_MAX_TEXELS`` (:func:`splat_levels`; level 0 where ``f`` is larger: a
field as fine as its atlas keeps every point, the same map as without levels). A level's point
stands for a square of ``size`` atlas texels a side (its block's drawn area); its splat side is
``f * size`` with the same foreshortening. So the points a sun change splats fall with the field
texel's area, about ``1 / 4`` a level, while the outline moves by under a field texel.
``SplatDrawer(max_level=0)`` splats every texel (the drawer before levels, kept to compare with).

**Threads.** On maps of at least :data:`~morphkit.warp.PARALLEL_MIN_PIXELS` texels the splat and
the closing run in bands of rows on :data:`~morphkit.settings.WARP_THREADS` threads
(:func:`~morphkit.warp.in_bands`): a band draws the instances whose splats can reach its rows
(their points' ball about the origin, posed) and writes only its own rows, so the map is the
same, bit for bit, as one band's (the minimum does not depend on the order).

**Convention.** The field camera's :meth:`~morphkit.camera.CameraModel.texture_matrix`
``T_pix_world``; the pose ``object2world = translation(x, y, 0) Rz(yaw) scale``
(:meth:`~morphkit.billboard.frames.instances.Instances.object2world`); field texel ``(u, v)`` holds
the point when ``round(u) = column``, ``round(v) = row`` (pixel centres at integers,
:mod:`morphkit.conventions`).

The kernel is compiled (numba, :func:`morphkit.settings.compile_kernel`); its numpy reference
(``np.minimum.at``) runs without numba or with ``MORPHKIT_WARP_NUMPY=1``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import cv2
import numpy as np

from .. import tol
from ..billboard.frames.instances import Instances
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..settings import WARP_THREADS, compile_kernel, use_compiled
from ..validate import as_finite_array, as_int, as_positive
from ..views.domecameras import direction
from ..warp import PARALLEL_MIN_PIXELS, in_bands
from .sunatlas import MAX_POINT_LEVEL, AtlasPoints, AtlasQuads, SunAtlas, segment_reach

__all__ = ["SplatDrawer", "splat_points", "splat_levels", "close_holes", "empty_depth"]


def _splat(depth: np.ndarray, points: np.ndarray, normals: np.ndarray, sizes: np.ndarray, inner: np.ndarray,
           seg_start: np.ndarray, seg_len: np.ndarray, seg_dir: np.ndarray, seg_qstart: np.ndarray,
           seg_qlen: np.ndarray, quads: np.ndarray, inst_T: np.ndarray, inst_seg: np.ndarray,
           inst_half: np.ndarray, inst_sun: np.ndarray, min_cos: float, inst_rows: np.ndarray, r_lo: int,
           r_hi: int) -> None:
    """Min each instance's segments, posed by its ``(3, 4)``, into rows ``r_lo`` to ``r_hi - 1`` of
    ``depth`` (in place): their quads' triangles, then their points not ``inner`` as squares;
    ``inst_rows``: the rows each instance can reach."""
    H, W = depth.shape
    for i in range(inst_T.shape[0]):
        if inst_rows[i, 1] < r_lo or inst_rows[i, 0] >= r_hi:
            continue
        T = inst_T[i]
        sx, sy, sz = inst_sun[i, 0], inst_sun[i, 1], inst_sun[i, 2]
        for j in range(inst_seg.shape[1]):
            sg = inst_seg[i, j]
            if sg < 0:
                continue
            a = seg_start[sg]
            # the segment's points to the map once, then its quads' triangles and the other points' squares
            uvd = np.empty((seg_len[sg], 3))
            for p in range(a, a + seg_len[sg]):
                x, y, z = points[p, 0], points[p, 1], points[p, 2]
                uvd[p - a, 0] = T[0, 0] * x + T[0, 1] * y + T[0, 2] * z + T[0, 3]
                uvd[p - a, 1] = T[1, 0] * x + T[1, 1] * y + T[1, 2] * z + T[1, 3]
                uvd[p - a, 2] = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z + T[2, 3]
            for qi in range(seg_qstart[sg], seg_qstart[sg] + seg_qlen[sg]):
                p0, p1, p2, p3 = quads[qi, 0] - a, quads[qi, 1] - a, quads[qi, 2] - a, quads[qi, 3] - a
                u0, v0, d0 = uvd[p0, 0], uvd[p0, 1], uvd[p0, 2]
                u1, v1, d1 = uvd[p1, 0], uvd[p1, 1], uvd[p1, 2]
                u2, v2, d2 = uvd[p2, 0], uvd[p2, 1], uvd[p2, 2]
                u3, v3, d3 = uvd[p3, 0], uvd[p3, 1], uvd[p3, 2]
                c0 = max(int(math.ceil(min(min(u0, u1), min(u2, u3)))), 0)
                c1 = min(int(math.floor(max(max(u0, u1), max(u2, u3)))), W - 1)
                r0 = max(int(math.ceil(min(min(v0, v1), min(v2, v3)))), r_lo)
                r1 = min(int(math.floor(max(max(v0, v1), max(v2, v3)))), r_hi - 1)
                for r in range(r0, r1 + 1):  # the texel centres in the quad's box (most have 0 or 1)
                    for c in range(c0, c1 + 1):
                        for t in range(2):  # triangle (q0, q1, q2), else (q0, q2, q3)
                            if t == 0:
                                ub, vb, db, uc, vc, dc = u1, v1, d1, u2, v2, d2
                            else:
                                ub, vb, db, uc, vc, dc = u2, v2, d2, u3, v3, d3
                            area = (ub - u0) * (vc - v0) - (uc - u0) * (vb - v0)
                            if area == 0.0:
                                continue
                            ea = (ub - c) * (vc - r) - (uc - c) * (vb - r)
                            eb = (uc - c) * (v0 - r) - (u0 - c) * (vc - r)
                            ec = area - ea - eb
                            if area > 0.0:
                                inside = ea >= 0.0 and eb >= 0.0 and ec >= 0.0
                            else:
                                inside = ea <= 0.0 and eb <= 0.0 and ec <= 0.0
                            if inside:  # its depth interpolated; a centre on the diagonal: the first
                                d = np.float32((ea * d0 + eb * db + ec * dc) / area)
                                if d < depth[r, c]:
                                    depth[r, c] = d
                                break
            dx, dy, dz = seg_dir[sg, 0], seg_dir[sg, 1], seg_dir[sg, 2]
            for p in range(a, a + seg_len[sg]):
                if inner[p]:
                    continue
                nx, ny, nz = normals[p, 0], normals[p, 1], normals[p, 2]
                h = inst_half[i] * sizes[p]
                if nx != 0.0 or ny != 0.0 or nz != 0.0:
                    cs = abs(nx * sx + ny * sy + nz * sz)
                    ck = max(abs(nx * dx + ny * dy + nz * dz), min_cos)
                    if cs < ck:
                        h *= math.sqrt(cs / ck)
                u, v, d = uvd[p - a, 0], uvd[p - a, 1], np.float32(uvd[p - a, 2])
                c0, c1 = int(math.ceil(u - h)), int(math.ceil(u + h)) - 1
                r0, r1 = int(math.ceil(v - h)), int(math.ceil(v + h)) - 1
                for r in range(max(r0, r_lo), min(r1 + 1, r_hi)):
                    for c in range(max(c0, 0), min(c1 + 1, W)):
                        if d < depth[r, c]:
                            depth[r, c] = d


_splat_jit = compile_kernel(_splat, error_model="numpy")


def _uvd(points: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Map ``u``, ``v`` and depth of object points under one instance's ``(3, 4)`` (the kernel's sums)."""
    x, y, z = (points[:, k].astype(np.float64) for k in range(3))
    return tuple(T[k, 0] * x + T[k, 1] * y + T[k, 2] * z + T[k, 3] for k in range(3))  # type: ignore[return-value]


def _triangles_numpy(depth: np.ndarray, points: np.ndarray, quads: np.ndarray, T: np.ndarray) -> None:
    """The reference of :func:`_splat`'s quads: each texel centre in a quad's box takes the depth of
    the first of its two triangles that holds it, min into ``depth``."""
    H, W = depth.shape
    (u0, v0, d0), (u1, v1, d1), (u2, v2, d2), (u3, v3, d3) = (_uvd(points[quads[:, k]], T) for k in range(4))
    c0 = np.maximum(np.ceil(np.minimum(np.minimum(u0, u1), np.minimum(u2, u3))), 0).astype(np.int64)
    c1 = np.minimum(np.floor(np.maximum(np.maximum(u0, u1), np.maximum(u2, u3))), W - 1).astype(np.int64)
    r0 = np.maximum(np.ceil(np.minimum(np.minimum(v0, v1), np.minimum(v2, v3))), 0).astype(np.int64)
    r1 = np.minimum(np.floor(np.maximum(np.maximum(v0, v1), np.maximum(v2, v3))), H - 1).astype(np.int64)
    for dr in range(max(int((r1 - r0).max(initial=-1)), -1) + 1):
        for dcol in range(max(int((c1 - c0).max(initial=-1)), -1) + 1):
            r, c = r0 + dr, c0 + dcol
            rf, cf = r.astype(np.float64), c.astype(np.float64)
            got = np.zeros(len(r), bool)
            d = np.zeros(len(r), np.float32)
            for (ub, vb, db), (uc, vc, dc) in (((u1, v1, d1), (u2, v2, d2)), ((u2, v2, d2), (u3, v3, d3))):
                area = (ub - u0) * (vc - v0) - (uc - u0) * (vb - v0)
                ea = (ub - cf) * (vc - rf) - (uc - cf) * (vb - rf)
                eb = (uc - cf) * (v0 - rf) - (u0 - cf) * (vc - rf)
                ec = area - ea - eb
                inside = (area != 0.0) & np.where(area > 0.0, (ea >= 0.0) & (eb >= 0.0) & (ec >= 0.0),
                                                  (ea <= 0.0) & (eb <= 0.0) & (ec <= 0.0))
                new = inside & ~got
                at = ((ea * d0 + eb * db + ec * dc) / np.where(new, area, 1.0)).astype(np.float32)
                d = np.where(new, at, d)
                got |= inside
            sel = got & (r <= r1) & (c <= c1)
            np.minimum.at(depth, (r[sel], c[sel]), d[sel])


def _splat_numpy(depth: np.ndarray, points: np.ndarray, normals: np.ndarray, sizes: np.ndarray,
                 inner: np.ndarray, seg_start: np.ndarray, seg_len: np.ndarray, seg_dir: np.ndarray,
                 seg_qstart: np.ndarray, seg_qlen: np.ndarray, quads: np.ndarray, inst_T: np.ndarray,
                 inst_seg: np.ndarray, inst_half: np.ndarray, inst_sun: np.ndarray, min_cos: float) -> None:
    """The reference of :func:`_splat` (same texels, same minimum)."""
    H, W = depth.shape
    for i in range(len(inst_T)):
        for sg in inst_seg[i]:
            if sg < 0:
                continue
            q0 = int(seg_qstart[sg])
            if seg_qlen[sg]:
                _triangles_numpy(depth, points, quads[q0:q0 + int(seg_qlen[sg])], inst_T[i])
            sl = np.arange(int(seg_start[sg]), int(seg_start[sg] + seg_len[sg]))
            sl = sl[~inner[sl]]
            p = points[sl].astype(np.float64)
            n = normals[sl].astype(np.float64)
            q = p @ inst_T[i][:, :3].T + inst_T[i][:, 3]
            cs = np.abs(n @ inst_sun[i])
            ck = np.maximum(np.abs(n @ seg_dir[sg]), min_cos)
            known = np.any(n != 0.0, axis=1)
            h = inst_half[i] * sizes[sl].astype(np.float64)
            h = h * np.where(known & (cs < ck), np.sqrt(cs / ck), 1.0)
            c0, c1 = np.ceil(q[:, 0] - h).astype(np.int64), np.ceil(q[:, 0] + h).astype(np.int64) - 1
            r0, r1 = np.ceil(q[:, 1] - h).astype(np.int64), np.ceil(q[:, 1] + h).astype(np.int64) - 1
            d = q[:, 2].astype(np.float32)
            for dr in range(max(int((r1 - r0).max(initial=-1)), -1) + 1):
                for dc in range(max(int((c1 - c0).max(initial=-1)), -1) + 1):
                    r, c = r0 + dr, c0 + dc
                    ok = (r <= r1) & (c <= c1) & (r >= 0) & (r < H) & (c >= 0) & (c < W)
                    np.minimum.at(depth, (r[ok], c[ok]), d[ok])


def splat_points(depth: np.ndarray, points: np.ndarray, normals: np.ndarray, seg_start: np.ndarray,
                 seg_len: np.ndarray, seg_dir: np.ndarray, inst_T: np.ndarray, inst_seg: np.ndarray,
                 inst_half: np.ndarray, inst_sun: np.ndarray, sizes: np.ndarray | None = None,
                 seg_reach: np.ndarray | None = None, quads: AtlasQuads | None = None) -> None:
    """Splat segments of points, posed per instance, into a depth map by minimum (in place);
    with ``quads``, each segment's quads are drawn as triangles and its inner points skipped.

    Parameters
    ----------
    depth : (H, W) float32
        The map, ``+inf`` where empty; updated in place.
    points, normals : (P, 3) float32
        All segments' points and unit normals (zero: unknown), concatenated (object frames).
    seg_start, seg_len : (S,) int64
        Each segment's first point and count.
    seg_dir : (S, 3) float64
        Each segment's view direction (towards its view, object frame).
    inst_T : (M, 3, 4) float64
        Each instance's object point to ``(u, v, depth)`` of the map.
    inst_seg : (M, J) int64
        Each instance's segments (``-1``: none).
    inst_half : (M,) float64
        Half each instance's splat side, texels (module docstring, "Splat size").
    inst_sun : (M, 3) float64
        Each instance's sun direction in its object frame (unit).
    sizes : (P,) float32, optional
        Each point's footprint side in atlas texels, a factor of its instance's (module
        docstring, "Levels"); default 1 (every point one atlas texel).
    seg_reach : (S,) float, optional
        Each segment's farthest point from its object's origin (the ``reach`` of
        :class:`~morphkit.sunlit.sunatlas.AtlasPoints`, made when the atlas packs its points);
        default: found here (:func:`~morphkit.sunlit.sunatlas.segment_reach`).
    quads : AtlasQuads, optional
        Quads of the segments (module docstring, "Quads"): ``quads`` index ``points``,
        ``starts`` / ``lengths`` give each segment's (``(S,)``; a length 0 for a segment
        without), ``inner`` the points the quads alone draw (``(P,)``); default none (every
        point a square).
    """
    sizes = np.ones(len(points), np.float32) if sizes is None else np.asarray(sizes, np.float32)
    if quads is None:
        quads = AtlasQuads(np.zeros((0, 4), np.int64), np.zeros(len(seg_start), np.int64),
                           np.zeros(len(seg_start), np.int64), np.zeros(len(points), bool))
    args = (depth, points, normals, sizes, quads.inner, seg_start, seg_len, seg_dir, quads.starts,
            quads.lengths, quads.quads, inst_T, inst_seg, inst_half, inst_sun, float(tol.SPLAT_MIN_COS))
    if not use_compiled(_splat_jit):
        _splat_numpy(*args)
        return
    # bands of rows on WARP_THREADS threads, each instance drawn in the bands its points can
    # reach, each band writing its own rows: the same minimum (bit for bit) as one band
    H = depth.shape[0]
    reach = segment_reach(points, seg_start, seg_len) if seg_reach is None else \
        np.asarray(seg_reach, np.float64)
    rows = _instance_rows(reach, inst_T, inst_seg, inst_half, sizes)
    n = WARP_THREADS if depth.size >= PARALLEL_MIN_PIXELS else 1
    bands = [(H * b // n, H * (b + 1) // n) for b in range(n)]
    in_bands(lambda b: _splat_jit(*args, rows, *bands[b]), n)  # type: ignore[misc]


def _instance_rows(reach: np.ndarray, inst_T: np.ndarray, inst_seg: np.ndarray, inst_half: np.ndarray,
                   sizes: np.ndarray) -> np.ndarray:
    """``(M, 2)`` int64: the first and last map row each instance's splats can reach (its segments'
    points in a ball of their ``reach`` about its origin, posed; plus its largest splat's half side)."""
    radius = np.where(inst_seg >= 0, reach[np.maximum(inst_seg, 0)], 0.0).max(axis=1, initial=0.0)
    smax = float(sizes.max(initial=1.0))
    ext = np.linalg.norm(inst_T[:, 1, :3], axis=1) * radius + inst_half * smax + 1.0
    v = inst_T[:, 1, 3]
    return np.stack([np.floor(v - ext), np.ceil(v + ext)], axis=1).astype(np.int64)


def _close_loop(depth: np.ndarray, out: np.ndarray, r_lo: int, r_hi: int) -> None:
    """:func:`close_holes`: rows ``r_lo`` to ``r_hi - 1`` of ``depth`` into ``out``, closed."""
    H, W = depth.shape
    inf = np.float32(np.inf)
    for r in range(r_lo, r_hi):
        for c in range(W):
            out[r, c] = depth[r, c]
            if depth[r, c] < inf:
                continue
            lft = depth[r, c - 1] if c > 0 else inf
            rgt = depth[r, c + 1] if c < W - 1 else inf
            up = depth[r - 1, c] if r > 0 else inf
            dn = depth[r + 1, c] if r < H - 1 else inf
            if (lft < inf and rgt < inf) or (up < inf and dn < inf):
                out[r, c] = min(min(lft, rgt), min(up, dn))


_close_jit = compile_kernel(_close_loop, error_model="numpy")


def _fill_inf(depth: np.ndarray, r_lo: int, r_hi: int) -> None:
    """Rows ``r_lo`` to ``r_hi - 1`` of ``depth`` set to ``+inf``."""
    inf = np.float32(np.inf)
    for r in range(r_lo, r_hi):
        for c in range(depth.shape[1]):
            depth[r, c] = inf


_fill_jit = compile_kernel(_fill_inf)


def empty_depth(shape: tuple[int, int]) -> np.ndarray:
    """An empty field map: ``(H, W)`` float32 of ``+inf`` (filled in bands of rows on large maps,
    module docstring, "Threads").

    Parameters
    ----------
    shape : (H, W)
        The map's shape.

    Returns
    -------
    (H, W) float32
        ``+inf`` everywhere.
    """
    if not use_compiled(_fill_jit):
        return np.full(shape, np.inf, np.float32)
    depth = np.empty(shape, np.float32)
    n = WARP_THREADS if depth.size >= PARALLEL_MIN_PIXELS else 1
    bands = [(shape[0] * b // n, shape[0] * (b + 1) // n) for b in range(n)]
    in_bands(lambda b: _fill_jit(depth, *bands[b]), n)  # type: ignore[misc]
    return depth


def close_holes(depth: np.ndarray) -> np.ndarray:
    """``depth`` with one-texel holes closed (module docstring, "Holes"); a new array.

    Parameters
    ----------
    depth : (H, W) float32
        ``+inf`` where empty.

    Returns
    -------
    (H, W) float32
        Each empty texel whose two horizontal or two vertical neighbours are drawn holds the
        nearest depth of its four neighbours.
    """
    if use_compiled(_close_jit):
        out = np.empty_like(depth)  # each band copies its rows, then closes them
        H = depth.shape[0]
        n = WARP_THREADS if depth.size >= PARALLEL_MIN_PIXELS else 1
        bands = [(H * b // n, H * (b + 1) // n) for b in range(n)]
        in_bands(lambda b: _close_jit(depth, out, *bands[b]), n)  # type: ignore[misc]
        return out
    out = depth.copy()
    drawn = np.isfinite(depth).astype(np.uint8)
    both_h = cv2.erode(drawn, _PAIR_H, borderType=cv2.BORDER_CONSTANT, borderValue=0)
    both_v = cv2.erode(drawn, _PAIR_V, borderType=cv2.BORDER_CONSTANT, borderValue=0)
    fill = ((both_h | both_v) > 0) & (drawn == 0)
    nearest = cv2.erode(depth, _CROSS, borderType=cv2.BORDER_CONSTANT, borderValue=float("inf"))
    out[fill] = nearest[fill]
    return out


_PAIR_H = np.array([[1, 0, 1]], np.uint8)
_PAIR_V = _PAIR_H.T.copy()
_CROSS = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], np.uint8)


def splat_levels(footprint: np.ndarray, max_level: int, max_texels: float) -> np.ndarray:
    """Each instance's point level (module docstring, "Levels").

    Parameters
    ----------
    footprint : (M,) float
        Field texels a side of one atlas texel of each instance (``scale`` times the field's
        texels per unit over the atlas's).
    max_level : int
        The coarsest level allowed (0: every instance at level 0).
    max_texels : float
        The largest side, field texels, of a level's texel (``2**l`` atlas texels).

    Returns
    -------
    (M,) int64
        The coarsest ``l <= max_level`` with ``2**l * footprint <= max_texels``; 0 where even
        level 0's texel is larger (a field finer than the atlas).

    Raises
    ------
    ValidationError
        A footprint that is not positive and finite; a level outside ``0 ..``
        :data:`~morphkit.sunlit.sunatlas.MAX_POINT_LEVEL`; ``max_texels`` not positive.
    """
    f = as_finite_array(footprint, "footprint", shape=(None,))
    if np.any(f <= 0.0):
        raise ValidationError(expected_got("footprint", "positive field texels per atlas texel",
                                           float(f.min())))
    top = as_int(max_level, "max_level", lo=0, hi=MAX_POINT_LEVEL)
    cap = as_positive(max_texels, "max_texels")
    return np.clip(np.floor(np.log2(cap / f)), 0, top).astype(np.int64)


class SplatDrawer:
    """Draws a field's light view by splatting atlas points (module docstring).

    Parameters
    ----------
    max_level : int
        The coarsest point level an instance may be drawn at (module docstring, "Levels");
        default :data:`~morphkit.sunlit.sunatlas.MAX_POINT_LEVEL`; 0 splats every atlas texel
        (the drawer before levels, kept to compare with).
    max_texels : float
        The largest side, in field texels, of the level's texel an instance is drawn at
        (default :data:`~morphkit.tol.SPLAT_LEVEL_MAX_TEXELS`).
    quads : bool
        Instances drawn at level 0 draw their views' quads as triangles and square only the
        other points (module docstring, "Quads"); ``False``: every point a square (the drawer
        before quads, kept to compare with).

    Attributes
    ----------
    last_levels : (K,) int64
        The level of each instance of the last draw (the ``kept`` order).

    Raises
    ------
    ValidationError
        A level outside ``0 ..`` :data:`~morphkit.sunlit.sunatlas.MAX_POINT_LEVEL`;
        ``max_texels`` not positive.

    Examples
    --------
    >>> from morphkit.sunlit.fieldsplat import SplatDrawer
    >>> SplatDrawer().name
    'splat'
    >>> SplatDrawer(max_level=0).max_level
    0
    >>> SplatDrawer(quads=False).quads
    False
    """

    name = "splat"

    def __init__(self, max_level: int = MAX_POINT_LEVEL,
                 max_texels: float = tol.SPLAT_LEVEL_MAX_TEXELS, quads: bool = True) -> None:
        if not isinstance(quads, bool):
            raise ValidationError(expected_got("quads", "True or False", repr(quads)))
        self.quads = quads
        self.max_level = as_int(max_level, "max_level", lo=0, hi=MAX_POINT_LEVEL)
        self.max_texels = as_positive(max_texels, "max_texels")
        self.last_levels = np.zeros(0, np.int64)

    def clear(self) -> None:
        """Forget the last draw's levels; nothing else is kept between draws (each atlas keeps its
        own points and levels, :meth:`~morphkit.sunlit.sunatlas.SunAtlas.packed_points`)."""
        self.last_levels = np.zeros(0, np.int64)

    def draw(self, atlases: Mapping[str, SunAtlas], instances: Instances, kept: np.ndarray,
             camera: CameraModel, sun: tuple[float, float]) -> np.ndarray:
        """The field's light-view depth: the kept instances' atlas points splatted.

        Parameters
        ----------
        atlases : mapping of str to SunAtlas
            Each asset name's atlas.
        instances : Instances
            The field.
        kept : (K,) int64
            The instances to draw.
        camera : CameraModel
            The field's light view (orthographic, world frame).
        sun : (azimuth_deg, elevation_deg)
            The field's sun (clamped, above the horizon).

        Returns
        -------
        (H, W) float32
            Nearest caster's depth along the light (``+inf`` where none).
        """
        depth = empty_depth(camera.shape)
        T = camera.texture_matrix()[:3]
        names: Sequence[str] = instances.names
        asset = instances.asset[kept]
        yaw = np.radians(instances.yaw_deg[kept])
        scale = instances.scale[kept]
        # field texels a side of one atlas texel, per instance
        texel = np.array([2.0 * float(atlases[nm].cameras.half_extent[0]) / atlases[nm].size for nm in names])
        inst_half = np.ascontiguousarray(0.5 * scale * texel[asset] * camera.fx, np.float64)
        foot = 2.0 * inst_half
        level = splat_levels(foot, self.max_level, self.max_texels)
        self.last_levels = level
        groups = sorted(set(zip(asset.tolist(), level.tolist(), strict=True)))
        if not groups:
            return depth
        packs = [atlases[names[a]].packed_points(lv) for a, lv in groups]
        quads = [atlases[names[a]].packed_quads() if self.quads and lv == 0 else None for a, lv in groups]
        seg_base = np.concatenate([[0], np.cumsum([len(pk.starts) for pk in packs])[:-1]]).astype(np.int64)
        pt_base = np.concatenate([[0], np.cumsum([len(pk.points) for pk in packs])[:-1]]).astype(np.int64)
        if len(packs) == 1:
            pk = packs[0]
            points, normals, sizes, seg_start, seg_len, seg_dir, seg_reach = (
                pk.points, pk.normals, pk.sizes, pk.starts, pk.lengths, pk.directions, pk.reach)
        else:
            points, normals, sizes = (np.concatenate([getattr(pk, f) for pk in packs])
                                      for f in ("points", "normals", "sizes"))
            seg_start = np.concatenate([pk.starts + b for pk, b in zip(packs, pt_base, strict=True)])
            seg_len, seg_dir, seg_reach = (np.concatenate([getattr(pk, f) for pk in packs])
                                           for f in ("lengths", "directions", "reach"))
        quad = _joined_quads(packs, quads, pt_base) if any(q is not None for q in quads) else None

        inst_T = np.ascontiguousarray(np.einsum("ij,mjk->mik", T, instances.objects2world(kept)))
        inst_seg = np.full((len(kept), 3), -1, np.int64)
        az_sun, el_sun = sun
        az_obj = az_sun - np.degrees(yaw)
        inst_sun = np.ascontiguousarray(direction(az_obj, np.full_like(az_obj, el_sun)).reshape(-1, 3))
        for g, (a, lv) in enumerate(groups):
            mine = np.flatnonzero((asset == a) & (level == lv))
            views, weights = atlases[names[a]].dome.weights_many(az_obj[mine], el_sun)
            inst_seg[mine] = np.where(weights > 0.0, views + seg_base[g], -1)
        splat_points(depth, points, normals, seg_start, seg_len, np.ascontiguousarray(seg_dir, np.float64),
                     inst_T, inst_seg, inst_half, inst_sun, sizes, seg_reach, quad)
        return close_holes(depth)


def _joined_quads(packs: Sequence[AtlasPoints], quads: Sequence[AtlasQuads | None], pt_base: np.ndarray
                  ) -> AtlasQuads:
    """The groups' quads for their points concatenated (a group without quads: none, no inner point)."""
    if len(packs) == 1 and quads[0] is not None:
        return quads[0]
    qs, starts, lens, inner = [], [], [], []
    q_base = 0
    for pk, q, b in zip(packs, quads, pt_base, strict=True):
        if q is None:
            starts.append(np.zeros(len(pk.starts), np.int64))
            lens.append(np.zeros(len(pk.starts), np.int64))
            inner.append(np.zeros(len(pk.points), bool))
            continue
        qs.append((q.quads + b).astype(np.int32))
        starts.append(q.starts + q_base)
        lens.append(q.lengths)
        inner.append(q.inner)
        q_base += len(q.quads)
    return AtlasQuads(np.ascontiguousarray(np.concatenate(qs)), np.concatenate(starts), np.concatenate(lens),
                      np.concatenate(inner))
