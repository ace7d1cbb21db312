"""A field's light view by splatting its instances' atlas points: the cheap sun change.

:class:`SplatDrawer` draws the depth of a field's light view (:mod:`.fieldshadow`) by
**reprojecting the atlas views' texels per point** (Kang & Ihm's per-pixel warp of the
neighbouring maps, here forward): for each instance, the sun is turned into its object frame
(:func:`~morphkit.shadow.sunatlas.sun_in_object`: the same elevation, the azimuth minus its
yaw), the atlas views of the dome triangle around that direction are chosen
(:meth:`~morphkit.billboard.dome.ViewDome.weights_many`), and each drawn texel of each of
those views, a surface point of the object (:meth:`~morphkit.shadow.sunatlas.SunAtlas.view_points`),
is taken by the instance's pose and the field camera's texture matrix to a field texel and
its depth along the light; the field keeps the nearest (``min``). Nothing is morphed or
cached per sun: a sun change costs one pass over the points, whatever the yaws and the
meshes' face counts (the points are the atlas's texels).

**Splat size.** A point stands for one atlas texel of its view: a patch of surface whose
area, seen from the view head-on, is one texel. In the field that texel is a square of
``f = scale * field texels per unit / atlas texels per unit`` texels a side, and the patch,
seen from the sun instead, is foreshortened by ``|n . s| / |n . d|`` (its normal ``n``
estimated from the view's depth, :meth:`~morphkit.shadow.sunatlas.SunAtlas.view_points`;
``s`` the sun, ``d`` the view, object frame; ``|n . d|`` at least
:data:`~morphkit.tol.SPLAT_MIN_COS`). The point fills the field texels whose centres lie in
a square of side ``f * sqrt(min(1, |n . s| / |n . d|))`` centred on it (none when the square
falls between centres: its neighbours' squares hold them). So the drawn texels are about
those whose centres the surface covers, the coverage a rasteriser gives: a full square at
a patch the sun grazes (the shadow's outline) would reach half a texel past it, and "every
texel a point lands in" would grow the shadow by half a texel all round. A patch the sun
sees more squarely than its view is not grown (the other two views' points fill it).

**Holes** between points (a surface the views see obliquely, a grid turned by the yaw) are
closed afterwards: an empty texel between two drawn ones (left and right, or above and
below) takes the nearest depth of its four neighbours (``cv2.erode``). A ``3 x 3``
morphological closing would also fill every step of a slanted silhouette, a shadow grown
by up to a texel along every edge that is not axis-aligned.

**Convention.** The field camera's :meth:`~morphkit.camera.CameraModel.texture_matrix`
``T_pix_world``; the pose ``object2world = translation(x, y, 0) Rz(yaw) scale``
(:meth:`~morphkit.billboard.instances.Instances.object2world`); field texel ``(u, v)`` holds
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
from ..billboard.domecameras import direction
from ..billboard.instances import Instances
from ..camera import CameraModel
from ..settings import compile_kernel, use_compiled
from .sunatlas import SunAtlas

__all__ = ["SplatDrawer", "splat_points", "close_holes"]


def _splat(depth: np.ndarray, points: np.ndarray, normals: np.ndarray, seg_start: np.ndarray,
           seg_len: np.ndarray, seg_dir: np.ndarray, inst_T: np.ndarray, inst_seg: np.ndarray,
           inst_half: np.ndarray, inst_sun: np.ndarray, min_cos: float) -> None:
    """Min each instance's segments of points, posed by its ``(3, 4)``, into ``depth`` (in place)."""
    H, W = depth.shape
    for i in range(inst_T.shape[0]):
        T = inst_T[i]
        sx, sy, sz = inst_sun[i, 0], inst_sun[i, 1], inst_sun[i, 2]
        for j in range(inst_seg.shape[1]):
            sg = inst_seg[i, j]
            if sg < 0:
                continue
            a = seg_start[sg]
            dx, dy, dz = seg_dir[sg, 0], seg_dir[sg, 1], seg_dir[sg, 2]
            for p in range(a, a + seg_len[sg]):
                x, y, z = points[p, 0], points[p, 1], points[p, 2]
                nx, ny, nz = normals[p, 0], normals[p, 1], normals[p, 2]
                h = inst_half[i]
                if nx != 0.0 or ny != 0.0 or nz != 0.0:
                    cs = abs(nx * sx + ny * sy + nz * sz)
                    ck = max(abs(nx * dx + ny * dy + nz * dz), min_cos)
                    if cs < ck:
                        h *= math.sqrt(cs / ck)
                u = T[0, 0] * x + T[0, 1] * y + T[0, 2] * z + T[0, 3]
                v = T[1, 0] * x + T[1, 1] * y + T[1, 2] * z + T[1, 3]
                d = np.float32(T[2, 0] * x + T[2, 1] * y + T[2, 2] * z + T[2, 3])
                c0, c1 = int(math.ceil(u - h)), int(math.ceil(u + h)) - 1
                r0, r1 = int(math.ceil(v - h)), int(math.ceil(v + h)) - 1
                for r in range(max(r0, 0), min(r1 + 1, H)):
                    for c in range(max(c0, 0), min(c1 + 1, W)):
                        if d < depth[r, c]:
                            depth[r, c] = d


_splat_jit = compile_kernel(_splat, error_model="numpy")


def _splat_numpy(depth: np.ndarray, points: np.ndarray, normals: np.ndarray, seg_start: np.ndarray,
                 seg_len: np.ndarray, seg_dir: np.ndarray, inst_T: np.ndarray, inst_seg: np.ndarray,
                 inst_half: np.ndarray, inst_sun: np.ndarray, min_cos: float) -> None:
    """The reference of :func:`_splat` (same texels, same minimum)."""
    H, W = depth.shape
    for i in range(len(inst_T)):
        for sg in inst_seg[i]:
            if sg < 0:
                continue
            sl = slice(int(seg_start[sg]), int(seg_start[sg] + seg_len[sg]))
            p = points[sl].astype(np.float64)
            n = normals[sl].astype(np.float64)
            q = p @ inst_T[i][:, :3].T + inst_T[i][:, 3]
            cs = np.abs(n @ inst_sun[i])
            ck = np.maximum(np.abs(n @ seg_dir[sg]), min_cos)
            known = np.any(n != 0.0, axis=1)
            h = inst_half[i] * np.where(known & (cs < ck), np.sqrt(cs / ck), 1.0)
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
                 inst_half: np.ndarray, inst_sun: np.ndarray) -> None:
    """Splat segments of points, posed per instance, into a depth map by minimum (in place).

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
    """
    args = (depth, points, normals, seg_start, seg_len, seg_dir, inst_T, inst_seg, inst_half, inst_sun,
            float(tol.SPLAT_MIN_COS))
    if use_compiled(_splat_jit):
        _splat_jit(*args)  # type: ignore[misc]
    else:
        _splat_numpy(*args)


def _close_loop(depth: np.ndarray, out: np.ndarray) -> None:
    """:func:`close_holes` into ``out`` (a copy of ``depth``), one pass."""
    H, W = depth.shape
    inf = np.float32(np.inf)
    for r in range(H):
        for c in range(W):
            if depth[r, c] < inf:
                continue
            lft = depth[r, c - 1] if c > 0 else inf
            rgt = depth[r, c + 1] if c < W - 1 else inf
            up = depth[r - 1, c] if r > 0 else inf
            dn = depth[r + 1, c] if r < H - 1 else inf
            if (lft < inf and rgt < inf) or (up < inf and dn < inf):
                out[r, c] = min(min(lft, rgt), min(up, dn))


_close_jit = compile_kernel(_close_loop, error_model="numpy")


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
    out = depth.copy()
    if use_compiled(_close_jit):
        _close_jit(depth, out)  # type: ignore[misc]
        return out
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


class SplatDrawer:
    """Draws a field's light view by splatting atlas points (module docstring).

    Examples
    --------
    >>> from morphkit.shadow.fieldsplat import SplatDrawer
    >>> SplatDrawer().name
    'splat'
    """

    name = "splat"

    def clear(self) -> None:
        """Nothing to drop: the drawer keeps nothing between draws (each atlas keeps its own
        points, :meth:`~morphkit.shadow.sunatlas.SunAtlas.packed_points`)."""

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
        depth = np.full(camera.shape, np.inf, np.float32)
        T = camera.texture_matrix()[:3]
        names: Sequence[str] = instances.names
        offsets, blocks = {}, []
        base = 0
        for a, nm in enumerate(names):
            if not np.any(instances.asset[kept] == a):
                continue
            pts, nrm, starts, lens, dirs = atlases[nm].packed_points()
            offsets[a] = len(blocks)
            blocks.append((pts, nrm, starts + base, lens, dirs))
            base += len(pts)
        if not blocks:
            return depth
        points, normals, seg_start, seg_len, seg_dir = (
            np.concatenate([b[j] for b in blocks]) if len(blocks) > 1 else blocks[0][j] for j in range(5))
        seg_base = np.concatenate([[0], np.cumsum([len(b[2]) for b in blocks])[:-1]]).astype(np.int64)

        asset = instances.asset[kept]
        yaw = np.radians(instances.yaw_deg[kept])
        scale = instances.scale[kept]
        c, s = np.cos(yaw), np.sin(yaw)
        o2w = np.zeros((len(kept), 4, 4))
        o2w[:, 0, 0], o2w[:, 0, 1] = scale * c, -scale * s
        o2w[:, 1, 0], o2w[:, 1, 1] = scale * s, scale * c
        o2w[:, 2, 2] = scale
        o2w[:, :2, 3] = instances.xy[kept]
        o2w[:, 3, 3] = 1.0
        inst_T = np.ascontiguousarray(np.einsum("ij,mjk->mik", T, o2w))
        inst_seg = np.full((len(kept), 3), -1, np.int64)
        inst_half = np.zeros(len(kept), np.float64)
        az_sun, el_sun = sun
        az_obj = az_sun - np.degrees(yaw)
        inst_sun = np.ascontiguousarray(direction(az_obj, np.full_like(az_obj, el_sun)).reshape(-1, 3))
        for a, row in offsets.items():
            mine = np.flatnonzero(asset == a)
            atlas = atlases[names[a]]
            views, weights = atlas.dome.weights_many(az_obj[mine], el_sun)
            inst_seg[mine] = np.where(weights > 0.0, views + seg_base[row], -1)
            texel = 2.0 * float(atlas.cameras.half_extent[0]) / atlas.size  # object units per atlas texel
            inst_half[mine] = 0.5 * scale[mine] * texel * camera.fx
        splat_points(depth, points, normals, seg_start, seg_len, np.ascontiguousarray(seg_dir, np.float64),
                     inst_T, inst_seg, inst_half, inst_sun)
        return close_holes(depth)
