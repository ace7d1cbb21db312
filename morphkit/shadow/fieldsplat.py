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

**Splat size.** A point stands for one atlas texel; in the field that texel is a square of
``f = scale * field texels per unit / atlas texels per unit`` texels a side. The point fills
the field texels whose centres lie in a square of :data:`~morphkit.tol.SPLAT_FOOTPRINT`
times that side, centred on it (none when the square falls between centres: its
neighbours' squares hold them), so the drawn texels are about those whose centres the
surface covers, the coverage a rasteriser gives, not every texel a point lands in (a
shadow half a texel too large all round); the factor's reason and measurement: its note.
**Holes** between points (a surface the views see obliquely, a grid turned by the yaw) are
closed afterwards: a texel left empty inside a ``3 x 3`` morphological closing of the drawn
texels takes the nearest depth of its ``3 x 3`` neighbours (``cv2.morphologyEx``,
``cv2.erode``).

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
from ..billboard.instances import Instances
from ..camera import CameraModel
from ..settings import compile_kernel, use_compiled
from .sunatlas import SunAtlas

__all__ = ["SplatDrawer", "splat_points", "close_holes"]


def _splat(depth: np.ndarray, points: np.ndarray, seg_start: np.ndarray, seg_len: np.ndarray,
           inst_T: np.ndarray, inst_seg: np.ndarray, inst_half: np.ndarray) -> None:
    """Min each instance's segments of points, posed by its ``(3, 4)``, into ``depth`` (in place)."""
    H, W = depth.shape
    for i in range(inst_T.shape[0]):
        T = inst_T[i]
        h = inst_half[i]
        for j in range(inst_seg.shape[1]):
            sg = inst_seg[i, j]
            if sg < 0:
                continue
            a = seg_start[sg]
            for p in range(a, a + seg_len[sg]):
                x, y, z = points[p, 0], points[p, 1], points[p, 2]
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


def _span(x: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """First and last texel whose centre is in ``[x - h, x + h)`` (last < first if none)."""
    return np.ceil(x - h).astype(np.int64), np.ceil(x + h).astype(np.int64) - 1


def _splat_numpy(depth: np.ndarray, points: np.ndarray, seg_start: np.ndarray, seg_len: np.ndarray,
                 inst_T: np.ndarray, inst_seg: np.ndarray, inst_half: np.ndarray) -> None:
    """The reference of :func:`_splat` (same texels, same minimum)."""
    H, W = depth.shape
    for i in range(len(inst_T)):
        segs = [int(s) for s in inst_seg[i] if s >= 0]
        if not segs:
            continue
        p = np.concatenate([points[seg_start[s]:seg_start[s] + seg_len[s]] for s in segs]).astype(np.float64)
        q = p @ inst_T[i][:, :3].T + inst_T[i][:, 3]
        h = float(inst_half[i])
        c0, c1 = _span(q[:, 0], h)
        r0, r1 = _span(q[:, 1], h)
        d = q[:, 2].astype(np.float32)
        for dr in range(max(int((r1 - r0).max()), -1) + 1):
            for dc in range(max(int((c1 - c0).max()), -1) + 1):
                r, c = r0 + dr, c0 + dc
                ok = (r <= r1) & (c <= c1) & (r >= 0) & (r < H) & (c >= 0) & (c < W)
                np.minimum.at(depth, (r[ok], c[ok]), d[ok])


def splat_points(depth: np.ndarray, points: np.ndarray, seg_start: np.ndarray, seg_len: np.ndarray,
                 inst_T: np.ndarray, inst_seg: np.ndarray, inst_half: np.ndarray) -> None:
    """Splat segments of points, posed per instance, into a depth map by minimum (in place).

    Parameters
    ----------
    depth : (H, W) float32
        The map, ``+inf`` where empty; updated in place.
    points : (P, 3) float32
        All segments' points, concatenated (object frames).
    seg_start, seg_len : (S,) int64
        Each segment's first point and count.
    inst_T : (M, 3, 4) float64
        Each instance's object point to ``(u, v, depth)`` of the map.
    inst_seg : (M, J) int64
        Each instance's segments (``-1``: none).
    inst_half : (M,) float64
        Half each instance's splat side, texels: a point fills the texels whose centres lie
        in ``[u - h, u + h) x [v - h, v + h)`` (none, when it falls between centres).
    """
    args = (depth, points, seg_start, seg_len, inst_T, inst_seg, inst_half)
    if use_compiled(_splat_jit):
        _splat_jit(*args)  # type: ignore[misc]
    else:
        _splat_numpy(*args)


def close_holes(depth: np.ndarray) -> np.ndarray:
    """``depth`` with one-texel holes closed (module docstring, "Holes"); a new array.

    Parameters
    ----------
    depth : (H, W) float32
        ``+inf`` where empty.

    Returns
    -------
    (H, W) float32
        Empty texels inside the ``3 x 3`` closing of the drawn ones hold their neighbours' minimum.
    """
    drawn = np.isfinite(depth).astype(np.uint8)
    kernel = np.ones((3, 3), np.uint8)
    closed = cv2.morphologyEx(drawn, cv2.MORPH_CLOSE, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=0)
    fill = (closed > 0) & (drawn == 0)
    if not fill.any():
        return depth
    nearest = cv2.erode(depth, kernel, borderType=cv2.BORDER_CONSTANT, borderValue=float("inf"))
    return np.where(fill, nearest, depth)


class SplatDrawer:
    """Draws a field's light view by splatting atlas points (module docstring).

    Examples
    --------
    >>> from morphkit.shadow.fieldsplat import SplatDrawer
    >>> SplatDrawer().name
    'splat'
    """

    name = "splat"

    def __init__(self) -> None:
        self._packed: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def clear(self) -> None:
        """Drop the packed atlas points (made again on the next draw)."""
        self._packed.clear()

    def _pack(self, atlas: SunAtlas) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """All of an atlas's view points, concatenated: ``(points, starts, lengths)`` by view."""
        got = self._packed.get(id(atlas))
        if got is None:
            parts = [atlas.view_points(k) for k in range(atlas.dome.views)]
            lens = np.array([len(p) for p in parts], np.int64)
            starts = np.concatenate([[0], np.cumsum(lens)[:-1]]).astype(np.int64)
            pts = np.ascontiguousarray(np.concatenate(parts), dtype=np.float32)
            got = self._packed[id(atlas)] = (pts, starts, lens)
        return got

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
            pts, starts, lens = self._pack(atlases[nm])
            offsets[a] = len(blocks)
            blocks.append((pts, starts + base, lens))
            base += len(pts)
        if not blocks:
            return depth
        points = np.concatenate([b[0] for b in blocks]) if len(blocks) > 1 else blocks[0][0]
        seg_start = np.concatenate([b[1] for b in blocks])
        seg_len = np.concatenate([b[2] for b in blocks])
        seg_base = np.concatenate([[0], np.cumsum([len(b[1]) for b in blocks])[:-1]]).astype(np.int64)

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
        for a, row in offsets.items():
            mine = np.flatnonzero(asset == a)
            atlas = atlases[names[a]]
            views, weights = atlas.dome.weights_many(az_sun - np.degrees(yaw[mine]), el_sun)
            inst_seg[mine] = np.where(weights > 0.0, views + seg_base[row], -1)
            texel = 2.0 * float(atlas.cameras.half_extent[0]) / atlas.size  # object units per atlas texel
            inst_half[mine] = 0.5 * tol.SPLAT_FOOTPRINT * scale[mine] * texel * camera.fx
        splat_points(depth, points, seg_start, seg_len, inst_T, inst_seg, inst_half)
        return close_holes(depth)
