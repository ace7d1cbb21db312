"""Warped shadow maps (Kang & Ihm 2002): the k x k shadow atlas and its run-time warp.

Bake
----
Light-view depth maps of the occluder are rendered at a ``k x k`` grid of
positions over its :class:`~morphkit.shadow.rig.MotionRange` (default 3 x 3:
the corners, and middle samples in line with the light), in the light camera
of a :class:`~morphkit.shadow.rig.LightRig` (resolution spent on the object).

Control points (automatic)
--------------------------
Kang & Ihm chose control points by hand. morphkit derives them from the known
object: a regular ``rows x cols`` grid of image points over a map is lifted to
3-D *anchors* that move rigidly with the object, so projecting them gives exact
correspondences at any position. A grid point is lifted with the map's depth
there, the depth field being extended beyond the silhouette by the nearest
object depth and blurred by ``smooth`` grid spacings (so control points move
with the parallax of the surface they cover, and depth jumps do not fold the
mesh). Anchor kinds:

* ``"sample"`` (default): every map lifts its own grid. A map's source control
  points are then exactly its regular grid, and its warp to a position follows
  the parallax of what *that* map sees.
* ``"shared"``: the middle map's anchors for all maps (one set of points in
  one-to-one correspondence across maps, as in the paper; needed by
  ``dst="interpolate"``).
* ``"plane"``: every grid point on the plane through the object's centre,
  parallel to the image: a projective motion, which cannot fold.

A warp that would fold (an occlusion change too large for the mesh) falls back
to the plane anchors for that map (documented fallback, counted in
:attr:`ShadowAtlas.fallbacks`).

Run time
--------
For an object position, the 4 surrounding maps are each warped (piecewise
affine, :class:`~morphkit.warp.MeshWarper`, built once per map) from their
control points to the destination control points, and blended with bilinear
weights (``"composed"``: each source resampled once). ``"three"`` does the
paper's three warps instead (two row morphs, then a column morph). Destination
control points are the anchors projected at the exact position (``"project"``,
default) or bilinearly interpolated from the 4 maps (``"interpolate"``, the
paper). Maps are warped as premultiplied ``[coverage, coverage * depth]``
(:func:`premultiply`), so bilinear sampling never mixes object depth with
the background; the blended coverage is thresholded at 0.5.

Only what can hold the shadow is warped: a map's triangles whose source
footprint holds no object pixel (computed once per map,
:meth:`~morphkit.warp.MeshWarper.triangles_touching`) would add zeros and are
skipped, and the composed warps run as one fused, compiled pass per map
(sampling positions, bilinear taps and the weighted sum; no map images), split
into bands of rows over the CPUs (:func:`morphkit.warp._accumulate_warps`).
Measured here (512^2, point light, 2-core VM), this took a bilinear map from
5.5 to 2.0 ms (cow) with the same result as ``cv2.remap`` up to its 1/32 px
quantisation; ``morphkit bench shadows`` has the current figures. ``"three"``
uses the same pass for each of its warps, over whole images.

``warps="reproject"`` replaces the mesh by a per-pixel 3-D motion of the maps'
pixels into one z-buffer (:mod:`morphkit.shadow.reproject`; no control points
used): the largest-weight map whole, its neighbours' hidden layers (built once,
:meth:`ShadowAtlas.prepare`).

Depth values follow the model of :mod:`morphkit.shadow.rig`: moving the object
by ``d`` moves every one of its light depths by the same amount, that of its
anchor. Sources hold depth relative to their anchor's depth; the result adds
the anchor depth at the run-time position.

Outside the baked range: :class:`~morphkit.errors.OutOfRangeError`, or with
``clamp=True`` the nearest position in range and a :class:`RangeClampWarning`.
"""

from __future__ import annotations

import io
import json
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import cv2
import numpy as np
import trimesh
from scipy import ndimage

from .. import tol
from .._scanline import NUMPY_ONLY as _NUMPY_ONLY
from .._scanline import numba as _numba
from ..camera import CameraModel
from ..errors import FileFormatError, FoldOverError, ValidationError, expected_got
from ..fileio import write_bytes
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, PointLight
from ..warp import (
    WARP_THREADS,
    MeshWarper,
    _accumulate_warps,
    _roi_union,
    grid_triangles,
)
from . import reproject as _rp
from .rig import LightRig, MotionRange, RangeClampWarning, sample_axis

__all__ = ["ShadowAtlas", "bake_atlas", "RangeClampWarning", "ATLAS_FORMAT", "ATLAS_VERSION",
           "premultiply"]

ATLAS_FORMAT = "morphkit-shadow-atlas"
ATLAS_VERSION = 1


def premultiply(depth: np.ndarray, ref: float = 0.0) -> np.ndarray:
    """``(2, H, W)`` float32 planes, premultiplied: ``[coverage, coverage * (depth - ref)]``;
    coverage is 1 on the object and 0 on the background.

    Bilinear interpolation of premultiplied channels blends object depths only:
    ``channel1 / channel0`` is the mean depth of the covered part of a footprint,
    never mixed with the background. ``ref`` (the object's anchor depth) makes
    depth relative, so that the same source serves every position (the depth
    model shifts all of an object's depths by the same amount).
    """
    cov = np.isfinite(depth)
    out = np.zeros((2, *depth.shape), np.float32)
    out[0] = cov
    out[1][cov] = depth[cov] - ref
    return out


def _merge(acc: np.ndarray, warped: tuple[tuple[int, int, int, int], np.ndarray], weight: float
           ) -> None:
    """``acc[:, roi] += weight * pixels`` for a ``(roi, pixels)`` pair (planes ``(2, h, w)``)."""
    (r0, r1, c0, c1), px = warped
    if px.size == 0:
        return
    for k in range(2):
        view = acc[k, r0:r1, c0:c1]  # rows strided, each row contiguous: a valid cv::Mat
        cv2.scaleAdd(px[k], float(weight), view, dst=view)


def _warp_planes(src: np.ndarray, src_pts: np.ndarray, dst_pts: np.ndarray,
                 triangles: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``(2, H, W)``: the premultiplied planes of ``src`` warped from ``src_pts`` to
    ``dst_pts`` (0 outside)."""
    warper = MeshWarper(src_pts, triangles)
    out = np.zeros((2, *shape), np.float32)
    _accumulate_warps([(warper._accumulation(dst_pts, shape), src,
                        warper.triangles_touching(src[0]), 1.0)], out)
    return out


def _finish_numpy(acc: np.ndarray, ref: float, out: np.ndarray, r0: int, r1: int, c0: int,
                  c1: int, clear: bool) -> None:
    cov, num = acc[0, r0:r1, c0:c1], acc[1, r0:r1, c0:c1]
    with np.errstate(divide="ignore", invalid="ignore"):
        out[r0:r1, c0:c1] = np.where(cov >= 0.5, num / cov + np.float32(ref), np.inf)
    if clear:
        acc[:, r0:r1, c0:c1] = 0.0


def _finish_loop(acc: np.ndarray, ref: float, out: np.ndarray, r0: int, r1: int, c0: int,
                 c1: int, clear: bool) -> None:
    for i in range(r0, r1):
        den_row = acc[0, i]
        num_row = acc[1, i]
        out_row = out[i]
        for j in range(c0, c1):
            den = den_row[j]
            out_row[j] = num_row[j] / den + ref if den >= 0.5 else np.inf
        if clear:
            den_row[c0:c1] = 0.0
            num_row[c0:c1] = 0.0


_finish_kernel = (_numba.njit(cache=True, nogil=True)(_finish_loop) if _numba is not None
                  else _finish_numpy)


def _finish(acc: np.ndarray, ref: float, roi: tuple[int, int, int, int] | None = None, *,
            clear: bool = False) -> np.ndarray:
    """Depth from premultiplied blended channels: ``cov * depth / cov + ref``, and
    ``+inf`` where the blended coverage is below 0.5 (one compiled pass); only
    over ``roi = (r0, r1, c0, c1)`` when given (``acc`` must be 0 elsewhere).
    ``clear``: set the ``acc`` it read back to 0 in the same pass."""
    h, w = acc.shape[1:]
    r0, r1, c0, c1 = (0, h, 0, w) if roi is None else roi
    out = np.full((h, w), np.inf, np.float32)
    if r1 > r0 and c1 > c0:
        _finish_kernel(acc, np.float32(ref), out, r0, r1, c0, c1, clear)
    return out


@dataclass
class ShadowAtlas:
    """A baked k x k set of light-view depth maps with control points.

    Build with :func:`bake_atlas`; save with :meth:`save`, load with :meth:`load`.
    """

    rig: LightRig
    xs: np.ndarray
    ys: np.ndarray
    maps: np.ndarray  # (ky, kx, H, W) float32, +inf background
    anchors: np.ndarray  # (ky, kx, N, 3) world points at translation (0, 0)
    plane_anchors: np.ndarray  # (ky, kx, N, 3)
    control_grid: tuple[int, int]
    anchor_kind: str = "sample"
    _warpers: dict[tuple[int, int], MeshWarper] = field(default_factory=dict, repr=False)
    _tex: dict[bytes, np.ndarray] = field(default_factory=dict, repr=False)
    _split: dict[tuple[int, int], np.ndarray] = field(default_factory=dict, repr=False)
    _touching: dict[tuple[int, int], np.ndarray] = field(default_factory=dict, repr=False)
    _support: dict[tuple[int, int], Any] = field(default_factory=dict, repr=False)
    _layers: dict[tuple[tuple[int, int], tuple[int, int]], Any] = field(default_factory=dict,
                                                                        repr=False)

    def __post_init__(self) -> None:
        self.triangles = grid_triangles(*self.control_grid)
        ky, kx = self.maps.shape[:2]
        self.control = np.stack([np.stack([self.project((self.xs[i], self.ys[j]), self.anchors[j, i])
                                           for i in range(kx)]) for j in range(ky)])
        # orientation of each map's source triangles, for the fold test per frame
        self._src_sign = np.sign(np.stack([np.stack([_signed_area(self.control[j, i], self.triangles)
                                                     for i in range(kx)]) for j in range(ky)]))
        self.fallbacks = 0
        self.relaxed = 0
        self._acc: np.ndarray | None = None
        self._scratch: list[np.ndarray] = []

    # ------------------------------------------------------------ geometry
    @property
    def shape(self) -> tuple[int, int]:
        return self.rig.shape

    @property
    def grid(self) -> tuple[int, int]:
        """``(ky, kx)`` sample grid."""
        return self.maps.shape[0], self.maps.shape[1]

    @property
    def memory_bytes(self) -> int:
        """Bytes of the precomputed, persisted data (maps + anchors + control points).

        At run time each map in use is also held premultiplied (2 channels), i.e.
        up to twice the maps' bytes more; the image-based baselines pay the same."""
        return int(self.maps.nbytes + self.anchors.nbytes + self.control.nbytes)

    def _texture(self, xy: Any) -> np.ndarray:
        """The light camera's texture matrix at ``xy`` (cached: each call of
        :meth:`shadow_map` needs it for the 4 samples and the position)."""
        xy = np.asarray(xy, dtype=np.float64)
        key = xy.tobytes()
        T = self._tex.get(key)
        if T is None:
            if len(self._tex) > 256:
                self._tex.clear()
            T = self._tex[key] = self.rig.camera_at(xy).texture_matrix()
        return T

    def project(self, xy: Any, anchors: np.ndarray) -> np.ndarray:
        """Pixel positions ``(N, 2)`` of ``anchors (N, 3)`` with the object at ``xy``."""
        xy = np.asarray(xy, dtype=np.float64)
        T = self._texture(xy)
        q = (anchors + np.r_[xy, 0.0]) @ T[:, :3].T + T[:, 3]
        return q[:, :2] / q[:, 3:]

    def _dst_points(self, j: int, i: int, eq: np.ndarray) -> np.ndarray:
        """Destination control points of map ``(j, i)`` for the object at ``eq``.

        Where the surface anchors' parallax would fold a triangle (an occlusion
        change), the offending vertices are pulled towards their plane-anchor
        positions (``plane + a (surface - plane)``, ``a`` halved per round) until
        no triangle folds: exact motion everywhere else, a projective motion at
        the fold."""
        surf = self.project(eq, self.anchors[j, i])
        if self.anchor_kind == "plane":
            return surf
        tri = self.triangles
        sign = self._src_sign[j, i]
        min_area = 4 * tol.TRIANGLE_AREA_PX2
        if not _any_folded(surf, tri, sign, min_area):
            return surf
        plane = self.project(eq, self.plane_anchors[j, i])
        dst = np.empty_like(surf)
        rounds = _relax(surf, plane, tri, sign, min_area, _RELAX_ROUNDS, dst)
        self.relaxed += abs(rounds)
        return dst if rounds > 0 else plane

    def _warper(self, j: int, i: int) -> MeshWarper:
        w = self._warpers.get((j, i))
        if w is None:
            w = self._warpers[(j, i)] = MeshWarper(self.control[j, i], self.triangles)
        return w

    def anchor_depth(self, xy: Any) -> float:
        """Light depth of the object's anchor (bounding-box centre) at ``xy``."""
        T = self._texture(xy)
        return float(T[2, :3] @ (self.rig.anchor0 + np.r_[np.asarray(xy, float), 0.0]) + T[2, 3])

    def _active(self, j: int, i: int) -> np.ndarray:
        """Triangles of map ``(j, i)``'s mesh whose source holds the object (cached)."""
        a = self._touching.get((j, i))
        if a is None:
            a = self._touching[(j, i)] = self._warper(j, i).triangles_touching(self._source(j, i)[0])
        return a

    def _source(self, j: int, i: int) -> np.ndarray:
        s = self._split.get((j, i))
        if s is None:
            ref = self.anchor_depth((self.xs[i], self.ys[j]))
            s = self._split[(j, i)] = premultiply(self.maps[j, i], ref)
        return s

    def cell(self, xy: np.ndarray) -> tuple[int, int, float, float]:
        """``(j, i, v, u)``: the cell's lower sample indices and the fractions in it."""
        i = int(np.clip(np.searchsorted(self.xs, xy[0], side="right") - 1, 0, len(self.xs) - 2))
        j = int(np.clip(np.searchsorted(self.ys, xy[1], side="right") - 1, 0, len(self.ys) - 2))
        u = float((xy[0] - self.xs[i]) / (self.xs[i + 1] - self.xs[i]))
        v = float((xy[1] - self.ys[j]) / (self.ys[j + 1] - self.ys[j]))
        return j, i, float(np.clip(v, 0, 1)), float(np.clip(u, 0, 1))

    # ------------------------------------------------------------ run time
    def shadow_map(self, xy: Any, *, light_offset: Any = None, clamp: bool = False,
                   warps: Literal["composed", "three", "reproject"] = "composed",
                   dst: Literal["project", "interpolate"] = "project",
                   blend: Literal["bilinear", "nearest"] = "bilinear",
                   layers: bool = True,
                   ) -> tuple[np.ndarray, CameraModel]:
        """The light depth map for the object at ``xy`` (and a point light moved by
        ``light_offset``), and the light camera it belongs to.

        ``blend="bilinear"`` (default, the paper) warps the cell's 4 maps and
        blends them with bilinear weights; ``"nearest"`` warps only the sample
        map with the largest weight (ties: the lower index): a quarter of the
        work, somewhat less accurate, and the shadow may change abruptly where
        the nearest sample changes (``morphkit bench shadows``, row
        ``warp_nearest``).

        ``warps="reproject"`` moves every pixel of the cell's maps in 3-D
        instead (exact for every surface point a map saw; no control points) and
        keeps the nearest depth (:mod:`morphkit.shadow.reproject`): closer to a
        re-render than the piecewise-affine warps where parallax varies inside
        a mesh triangle (the chair's slats over its seat), in about the time
        of ``"composed"`` (512^2: 2.1-3.1 ms against 2.3-2.8 ms).
        ``blend="nearest"`` reprojects one map (holes where it saw nothing).
        ``layers`` (reproject only): the largest-weight map is reprojected
        whole and of the others only what it does not hold
        (:func:`~morphkit.shadow.reproject.hidden_layer`, built once per pair of
        neighbouring samples, on first use or by :meth:`prepare`): the same
        shadow (IoU within 0.0003) in half the time or less; ``False``
        reprojects every map whole (``morphkit bench shadows``, rows
        ``reproject`` and ``reproject_full``).

        Returns ``(depth (H, W) float32 with +inf background, camera)``.
        """
        if (warps not in ("composed", "three", "reproject") or dst not in ("project", "interpolate")
                or blend not in ("bilinear", "nearest")):
            raise ValidationError(expected_got(
                "warps/dst/blend", "'composed'|'three'|'reproject', 'project'|'interpolate' and "
                "'bilinear'|'nearest'", f"{warps!r}/{dst!r}/{blend!r}"))
        if not isinstance(layers, bool | np.bool_):
            raise ValidationError(expected_got("layers", "a bool", repr(layers)))
        if warps == "reproject" and dst != "project":
            raise ValidationError(expected_got("dst", "'project' with warps='reproject' (it moves "
                                               "pixels, not control points)", repr(dst)))
        if blend == "nearest" and warps == "three":
            raise ValidationError(expected_got("warps", "'composed' with blend='nearest' (one map "
                                               "is warped once)", "'three'"))
        if (dst == "interpolate" or warps == "three") and self.anchor_kind == "sample":
            raise ValidationError(expected_got(
                "atlas anchors", "'shared' or 'plane' anchors for dst='interpolate' or "
                "warps='three' (they need control points in correspondence across maps)",
                "'sample' anchors"))
        eq, _pos, cam = self.rig.resolve(xy, light_offset, clamp=clamp)
        j, i, v, u = self.cell(eq)
        nb = [((j, i), (1 - u) * (1 - v)), ((j, i + 1), u * (1 - v)),
              ((j + 1, i), (1 - u) * v), ((j + 1, i + 1), u * v)]
        # the destination control points interpolated from all 4 maps (the paper)
        interp = sum(w * self.control[jj, ii] for (jj, ii), w in nb) if dst == "interpolate" else None
        if blend == "nearest":
            nb = [(max(nb, key=lambda n: n[1])[0], 1.0)]  # max() keeps the first of ties
        if warps == "three":
            return self._three_warps(eq, j, i, u, v, dst), cam
        if warps == "reproject":
            # the largest weight first: the others then mostly fill what it left
            order = sorted((n for n in nb if n[1] > 0.0), key=lambda n: -n[1])
            return self._reprojected(eq, [n for n, _w in order], bool(layers)), cam
        acc = self._acc  # kept between calls, all zeros (an atlas serves one thread at a time)
        if acc is None:
            acc = self._acc = np.zeros((2, *self.shape), np.float32)
        jobs = []
        box = (0, 0, 0, 0)
        for (jj, ii), w in nb:
            if w <= 0.0:
                continue
            c_dst = interp if interp is not None else self._dst_points(jj, ii, eq)
            if float(np.abs(c_dst - self.control[jj, ii]).max()) <= 1e-6:
                # identity: exact sample position, or a directional light
                box = (0, self.shape[0], 0, self.shape[1])
                _merge(acc, (box, self._source(jj, ii)), w)
            else:
                jobs.append(self._job(jj, ii, c_dst, eq, w))
        try:
            box = _roi_union(box, _accumulate_warps(jobs, acc))
            # clear=True: the buffer is all zeros again for the next call
            return _finish(acc, self.anchor_depth(eq), box, clear=True), cam
        except BaseException:
            acc.fill(0.0)
            raise

    def _reprojected(self, eq: np.ndarray, sources: list[tuple[int, int]], layers: bool
                     ) -> np.ndarray:
        """The maps ``sources`` reprojected per pixel to the object at ``eq`` into
        one z-buffer (:mod:`morphkit.shadow.reproject`); with ``layers`` the
        first whole and of the others their layers hidden from the first."""
        cam = self.rig.camera_at(eq)
        jobs = []
        pixels = 0
        for k, (jj, ii) in enumerate(sources):
            src, src_cam = self._prepared(jj, ii)
            if k > 0 and layers:
                src = self._layer(sources[0], (jj, ii))
            rp = self._reprojection(src_cam, cam, eq - np.array([self.xs[ii], self.ys[jj]]))
            pixels += int(src.cum[-1])
            jobs.append((src, rp))
        out = np.full(self.shape, np.inf, np.float32)
        threads = WARP_THREADS if pixels >= _rp.PARALLEL_MIN_SOURCE_PIXELS else 1
        while len(self._scratch) < threads - 1:
            self._scratch.append(np.full(self.shape, np.inf, np.float32))
        _rp.reproject_maps(jobs, out, self._scratch, threads=threads)
        return out

    def _prepared(self, j: int, i: int) -> tuple[_rp.Source, CameraModel]:
        """Map ``(j, i)`` as a reprojection source, and its camera (cached)."""
        prep = self._support.get((j, i))
        if prep is None:
            prep = self._support[(j, i)] = (
                _rp.Source(self.maps[j, i]), self.rig.camera_at(np.array([self.xs[i], self.ys[j]])))
        return prep

    def _reprojection(self, src_cam: CameraModel, dst_cam: CameraModel, dxy: np.ndarray
                      ) -> _rp.Reprojection:
        """How a map of ``src_cam`` moves into ``dst_cam`` with the object moved by
        ``dxy`` on the ground: ``e = R^T d`` in the light frame; a directional
        light's camera moves with the object (rig model), so there ``e = 0``."""
        persp = dst_cam.projection == "perspective"
        e = self.rig.R.T @ np.array([dxy[0], dxy[1], 0.0]) if persp else np.zeros(3)
        return _rp.Reprojection(persp, self.rig.fx, self.rig.fy, (src_cam.cx, src_cam.cy),
                                (dst_cam.cx, dst_cam.cy), e)

    def _layer(self, primary: tuple[int, int], other: tuple[int, int]) -> _rp.Layer:
        """What map ``other`` holds that map ``primary`` does not (cached per pair;
        :func:`morphkit.shadow.reproject.hidden_layer`)."""
        lay = self._layers.get((primary, other))
        if lay is None:
            (jk, ik), (jn, i_n) = primary, other
            rp = self._reprojection(self._prepared(jn, i_n)[1], self._prepared(jk, ik)[1],
                                    np.array([self.xs[ik] - self.xs[i_n], self.ys[jk] - self.ys[jn]]))
            lay = self._layers[(primary, other)] = _rp.hidden_layer(
                self.maps[jk, ik], self.maps[jn, i_n], rp)
        return lay

    def prepare(self) -> float:
        """Build now what ``warps="reproject"`` otherwise builds on first use:
        every map as a reprojection source and the hidden layer of every pair
        of samples that share a cell. Returns the seconds it took (``morphkit
        bench shadows`` reports it as ``prep_ms``)."""
        t0 = time.perf_counter()
        ky, kx = self.grid
        for j in range(ky):
            for i in range(kx):
                for jn in range(max(j - 1, 0), min(j + 2, ky)):
                    for i_n in range(max(i - 1, 0), min(i + 2, kx)):
                        if (jn, i_n) != (j, i):
                            self._layer((j, i), (jn, i_n))
        return time.perf_counter() - t0

    @property
    def layer_bytes(self) -> int:
        """Bytes of the hidden layers built so far (run-time cache, not persisted)."""
        return int(sum(lay.nbytes for lay in self._layers.values()))

    def method(self, **options: Any) -> AtlasMethod:
        """This atlas as a shadow method whose :meth:`shadow_map` uses ``options``
        (e.g. ``warps="reproject"``) unless a call overrides them: for
        :class:`~morphkit.shadow.soft.SoftShadow`,
        :func:`~morphkit.shadow.frame.compare_frames` and the benchmarks.
        Options are checked now, by one call at the range's first sample."""
        m = AtlasMethod(self, options)
        m.shadow_map(np.array([self.xs[0], self.ys[0]]))
        return m

    def _job(self, j: int, i: int, c_dst: np.ndarray, eq: np.ndarray, weight: float
             ) -> tuple[Any, np.ndarray, np.ndarray, float]:
        """``(plan, source, active triangles, weight)`` of source ``(j, i)`` warped to
        ``c_dst`` (:func:`morphkit.warp._accumulate_warps`): premultiplied, and only
        the triangles whose source holds the object are warped (the rest add 0)."""
        src = self._source(j, i)
        warper = self._warper(j, i)
        try:
            return warper._accumulation(c_dst, self.shape), src, self._active(j, i), weight
        except FoldOverError:
            # An occlusion change too large for the mesh: warp with plane anchors,
            # whose motion is projective and cannot fold (documented fallback).
            self.fallbacks += 1
            src_pts = self.project((self.xs[i], self.ys[j]), self.plane_anchors[j, i])
            dst_pts = self.project(eq, self.plane_anchors[j, i])
            warper = MeshWarper(src_pts, self.triangles)
            return (warper._accumulation(dst_pts, self.shape), src,
                    warper.triangles_touching(src[0]), weight)

    def _three_warps(self, eq: np.ndarray, j: int, i: int, u: float, v: float,
                     dst: str) -> np.ndarray:
        """Kang & Ihm's three warps: row morphs at fraction u, then a column morph at v.

        If a warp folds, the whole computation is redone with plane anchors
        (documented fallback, counted in :attr:`fallbacks`)."""
        try:
            return self._three_warps_with(self.control, self.anchors, eq, j, i, u, v, dst)
        except FoldOverError:
            self.fallbacks += 1
            ky, kx = self.grid
            plane = np.stack([np.stack([self.project((self.xs[b], self.ys[a]), self.plane_anchors[a, b])
                                        for b in range(kx)]) for a in range(ky)])
            return self._three_warps_with(plane, self.plane_anchors, eq, j, i, u, v, dst)

    def _three_warps_with(self, C: np.ndarray, anchors: np.ndarray, eq: np.ndarray, j: int, i: int,
                          u: float, v: float, dst: str) -> np.ndarray:
        c_dst = (self.project(eq, anchors[j, i]) if dst == "project" else
                 (1 - v) * ((1 - u) * C[j, i] + u * C[j, i + 1])
                 + v * ((1 - u) * C[j + 1, i] + u * C[j + 1, i + 1]))
        full = (0, self.shape[0], 0, self.shape[1])
        rows = []
        for jj in (j, j + 1):
            c_row = (1 - u) * C[jj, i] + u * C[jj, i + 1]
            row = np.zeros((2, *self.shape), np.float32)
            for ii, w in ((i, 1 - u), (i + 1, u)):
                if w > 0:
                    src = self._source(jj, ii)
                    warped = src if np.allclose(c_row, C[jj, ii], rtol=0, atol=1e-6) else _warp_planes(
                        src, C[jj, ii], c_row, self.triangles, self.shape)
                    _merge(row, (full, warped), w)
            rows.append((c_row, row))  # premultiplied: a row morph is again a source
        acc = np.zeros((2, *self.shape), np.float32)
        for (c_row, row), w in zip(rows, (1 - v, v), strict=True):
            if w > 0:
                warped = row if np.allclose(c_row, c_dst, rtol=0, atol=1e-6) else _warp_planes(
                    row, c_row, c_dst, self.triangles, self.shape)
                _merge(acc, (full, warped), w)
        return _finish(acc, self.anchor_depth(eq))

    # ------------------------------------------------------------ file I/O
    def save(self, path: str | Path) -> Path:
        """Write the atlas to one ``.npz`` file (maps, anchors, grid, light, range, rig, version)."""
        path = Path(path)
        meta = {
            "format": ATLAS_FORMAT, "version": ATLAS_VERSION,
            "light": _light_dict(self.rig.light),
            "rig": self.rig.params(),
            "control_grid": list(self.control_grid),
            "anchor_kind": self.anchor_kind,
        }
        buf = io.BytesIO()
        np.savez_compressed(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8),
                            xs=self.xs, ys=self.ys, maps=self.maps, anchors=self.anchors,
                            plane_anchors=self.plane_anchors, control=self.control,
                            triangles=self.triangles)
        return write_bytes(path, buf.getvalue())

    @classmethod
    def load(cls, path: str | Path, *, light: DirectionalLight | PointLight | None = None
             ) -> ShadowAtlas:
        """Read an atlas written by :meth:`save`.

        Raises
        ------
        FileFormatError
            Missing, truncated or corrupt file; another format or version; or,
            when ``light`` is given, an atlas baked for another light.
        """
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in ("meta", "xs", "ys", "maps", "anchors", "plane_anchors",
                                          "control", "triangles")}
            meta = json.loads(bytes(data["meta"]).decode())
        except FileNotFoundError as exc:
            raise FileFormatError(expected_got("atlas file", "an existing file", str(path))) from exc
        except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError, json.JSONDecodeError,
                UnicodeDecodeError) as exc:
            raise FileFormatError(expected_got(
                "atlas file", f"a complete {ATLAS_FORMAT} .npz file",
                f"an unreadable file {path.name} ({type(exc).__name__}: {exc})")) from exc
        if meta.get("format") != ATLAS_FORMAT:
            raise FileFormatError(expected_got("atlas format", ATLAS_FORMAT, meta.get("format")))
        if meta.get("version") != ATLAS_VERSION:
            raise FileFormatError(expected_got("atlas version", ATLAS_VERSION, meta.get("version")))
        stored = _light_from_dict(meta["light"])
        if light is not None and _light_dict(light) != meta["light"]:
            raise FileFormatError(expected_got("atlas light", f"the light it is used with "
                                               f"{_light_dict(light)}", f"baked for {meta['light']}"))
        rig = LightRig.from_params(stored, meta["rig"])
        atlas = cls(rig, data["xs"], data["ys"], data["maps"], data["anchors"], data["plane_anchors"],
                    tuple(meta["control_grid"]), meta["anchor_kind"])
        if atlas.maps.shape[2:] != rig.shape or atlas.maps.shape[:2] != (len(atlas.ys), len(atlas.xs)):
            raise FileFormatError(expected_got("atlas maps", f"shape ({len(atlas.ys)}, {len(atlas.xs)}, "
                                               f"{rig.shape[0]}, {rig.shape[1]})", atlas.maps.shape))
        # control points and triangles are stored for other readers; they must
        # agree with what the anchors and the light rig give
        if (data["control"].shape != atlas.control.shape
                or not np.allclose(data["control"], atlas.control, rtol=0, atol=1e-6)
                or not np.array_equal(data["triangles"], atlas.triangles)):
            raise FileFormatError(expected_got("atlas control points", "consistent with its anchors "
                                               "and light rig", "different values (corrupt file?)"))
        return atlas


class AtlasMethod:
    """A :class:`ShadowAtlas` with fixed run-time options (:meth:`ShadowAtlas.method`)."""

    def __init__(self, atlas: ShadowAtlas, options: dict[str, Any]) -> None:
        self.atlas, self.options = atlas, dict(options)

    @property
    def rig(self) -> LightRig:
        return self.atlas.rig

    @property
    def memory_bytes(self) -> int:
        return self.atlas.memory_bytes

    def shadow_map(self, xy: Any, **kw: Any) -> tuple[np.ndarray, CameraModel]:
        return self.atlas.shadow_map(xy, **{**self.options, **kw})


def _light_dict(light: DirectionalLight | PointLight) -> dict[str, Any]:
    if isinstance(light, DirectionalLight):
        return {"type": "directional", "direction": [round(float(v), 12) for v in light.direction]}
    return {"type": "point", "position": [round(float(v), 12) for v in light.position]}


def _light_from_dict(d: dict[str, Any]) -> DirectionalLight | PointLight:
    if d.get("type") == "directional":
        return DirectionalLight(np.array(d["direction"]))
    if d.get("type") == "point":
        return PointLight(np.array(d["position"]))
    raise FileFormatError(expected_got("atlas light type", "'directional' or 'point'", d.get("type")))


def bake_atlas(mesh: trimesh.Trimesh, base_pose: np.ndarray, motion: MotionRange,
               light: DirectionalLight | PointLight, shape: tuple[int, int], *, renderer: SceneRenderer,
               grid: int | tuple[int, int] = 3, control_grid: tuple[int, int] = (17, 17),
               anchors: Literal["sample", "shared", "plane"] = "sample", margin: float = 0.04,
               smooth: float = 0.0, uniform: bool = False, progress: bool = True) -> ShadowAtlas:
    """Render the k x k light depth maps over ``motion`` and derive control points.

    Parameters
    ----------
    renderer : morphkit.render.Renderer
        The rendering boundary (passed in, so this module needs no GL itself).
    grid : int or (ky, kx)
        Samples per axis (>= 2). Odd counts put the middle sample in line with a
        point light (Kang & Ihm); see :func:`~morphkit.shadow.rig.sample_axis`.
    control_grid : (rows, cols)
        Control points laid over each map's silhouette box (the paper used
        5 x 15 and 7 x 15; 17 x 17 measured best here, ``morphkit bench shadows``).
    anchors : {"sample", "shared", "plane"}
        How grid points are lifted to 3-D (module docstring).
    smooth : float
        Blur of the anchor depth field, in grid spacings (0: none).
    uniform : bool
        Evenly spaced samples even for odd ``grid`` (the image-based baseline).
    progress : bool
        Show a progress bar on a terminal (tqdm; silent when not a TTY).
    """
    from tqdm import tqdm

    from ..scene import Item

    ky, kx = (grid, grid) if np.isscalar(grid) else tuple(int(g) for g in grid)  # type: ignore[misc]
    rows, cols = (int(control_grid[0]), int(control_grid[1]))
    if rows < 2 or cols < 2:
        raise ValidationError(expected_got("control_grid", "(rows, cols) >= (2, 2)", control_grid))
    if anchors not in ("sample", "shared", "plane"):
        raise ValidationError(expected_got("anchors", "'sample', 'shared' or 'plane'", anchors))
    rig = LightRig(light, mesh, base_pose, motion, shape, margin=margin)
    mid = None
    if isinstance(light, PointLight) and not uniform:
        mid = light.position[:2] - rig.anchor0[:2]  # object centre under the light
    xs = sample_axis(motion.lo[0], motion.hi[0], kx, None if mid is None else mid[0])
    ys = sample_axis(motion.lo[1], motion.hi[1], ky, None if mid is None else mid[1])
    H, W = rig.shape
    maps = np.empty((ky, kx, H, W), np.float32)
    bar = tqdm(total=ky * kx, desc="baking shadow atlas", unit="map", disable=None if progress else True,
               leave=False)
    for j in range(ky):
        for i in range(kx):
            xy = np.array([xs[i], ys[j]])
            maps[j, i] = renderer.depth(rig.camera_at(xy), [Item(mesh, rig.object_pose(xy))])
            bar.update()
    bar.close()
    boxes = np.array([[_silhouette_box(maps[j, i]) for i in range(kx)] for j in range(ky)])
    if anchors != "sample":  # one grid for all maps: the union of the silhouettes' boxes
        boxes[:] = [boxes[..., 0].min(), boxes[..., 1].min(), boxes[..., 2].max(), boxes[..., 3].max()]
    surf = np.empty((ky, kx, rows * cols, 3))
    plane = np.empty_like(surf)
    for j in range(ky):
        for i in range(kx):
            x0, y0, x1, y1 = boxes[j, i]
            gx, gy = np.meshgrid(np.linspace(x0, x1, cols), np.linspace(y0, y1, rows))
            pts = np.c_[gx.ravel(), gy.ravel()]
            xy = np.array([xs[i], ys[j]])
            cam = rig.camera_at(xy)
            anchor_z = float((rig.anchor0 + np.r_[xy, 0.0] - cam.position) @ cam.axis)
            z = _anchor_depths(maps[j, i], pts, (rows, cols), anchor_z, smooth)
            surf[j, i] = _lift(cam, pts, z) - np.r_[xy, 0.0]
            plane[j, i] = _lift(cam, pts, np.full(len(pts), anchor_z)) - np.r_[xy, 0.0]
    if anchors == "shared":
        surf[:] = surf[ky // 2, kx // 2]
        plane[:] = plane[ky // 2, kx // 2]
    elif anchors == "plane":
        surf = plane
    return ShadowAtlas(rig, xs, ys, maps, surf, plane, (rows, cols), anchors)


def _silhouette_box(depth: np.ndarray, margin: float = 0.06) -> tuple[float, float, float, float]:
    """``(x0, y0, x1, y1)``: the bounding box of a map's covered pixels, grown by
    ``margin`` of the map size (at least 2 px) and clipped to the map; the whole
    map when nothing is covered. Control grids span it: the warp's work and its
    resolution go where the shadow is."""
    h, w = depth.shape
    rows = np.flatnonzero(np.isfinite(depth).any(1))
    cols = np.flatnonzero(np.isfinite(depth).any(0))
    if len(rows) == 0:
        return 0.0, 0.0, float(w - 1), float(h - 1)
    mx, my = max(2.0, margin * w), max(2.0, margin * h)
    return (max(0.0, cols[0] - mx), max(0.0, rows[0] - my), min(w - 1.0, cols[-1] + mx),
            min(h - 1.0, rows[-1] + my))


def _signed_area(pts: np.ndarray, tri: np.ndarray) -> np.ndarray:
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


#: Rounds of the fold relaxation before falling back to plane anchors.
_RELAX_ROUNDS = 16


def _folded_numpy(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                  ) -> np.ndarray:
    area = _signed_area(pts, tri)
    return (np.sign(area) != sign) | (np.abs(area) < min_area)


def _any_folded_numpy(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                      ) -> bool:
    return bool(_folded_numpy(pts, tri, sign, min_area).any())


def _relax_numpy(surf: np.ndarray, plane: np.ndarray, tri: np.ndarray, sign: np.ndarray,
                 min_area: float, rounds: int, out: np.ndarray) -> int:
    """Pull the vertices of folded triangles towards their plane positions,
    ``out = plane + a (surf - plane)`` with ``a`` halved per round for every vertex
    of a folded triangle, until nothing folds. Returns the number of rounds taken,
    negated when ``rounds`` did not suffice (``out`` is then meaningless).
    This is the reference for the compiled :func:`_relax_loop`."""
    alpha = np.ones(len(surf))
    bad = _folded_numpy(surf, tri, sign, min_area)
    for k in range(rounds):
        alpha[np.unique(tri[bad])] *= 0.5
        out[...] = plane + alpha[:, None] * (surf - plane)
        bad = _folded_numpy(out, tri, sign, min_area)
        if not bad.any():
            return k + 1
    return -rounds


def _tri_folded(p: np.ndarray, tri: np.ndarray, sign: np.ndarray, t: int, min_area: float
                ) -> bool:
    a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
    area = ((p[b, 0] - p[a, 0]) * (p[c, 1] - p[a, 1])
            - (p[b, 1] - p[a, 1]) * (p[c, 0] - p[a, 0]))
    s = 1.0 if area > 0 else (-1.0 if area < 0 else 0.0)
    return s != sign[t] or abs(area) < min_area


def _any_folded_loop(pts: np.ndarray, tri: np.ndarray, sign: np.ndarray, min_area: float
                     ) -> bool:
    for t in range(tri.shape[0]):
        if _tri_folded(pts, tri, sign, t, min_area):
            return True
    return False


def _relax_loop(surf: np.ndarray, plane: np.ndarray, tri: np.ndarray, sign: np.ndarray,
                min_area: float, rounds: int, out: np.ndarray) -> int:
    n, m = surf.shape[0], tri.shape[0]
    alpha = np.ones(n)
    mark = np.zeros(n, np.bool_)
    for t in range(m):
        if _tri_folded(surf, tri, sign, t, min_area):
            mark[tri[t, 0]] = mark[tri[t, 1]] = mark[tri[t, 2]] = True
    for k in range(rounds):
        for v in range(n):
            if mark[v]:
                alpha[v] *= 0.5
                mark[v] = False
            out[v, 0] = plane[v, 0] + alpha[v] * (surf[v, 0] - plane[v, 0])
            out[v, 1] = plane[v, 1] + alpha[v] * (surf[v, 1] - plane[v, 1])
        bad = False
        for t in range(m):
            if _tri_folded(out, tri, sign, t, min_area):
                bad = True
                mark[tri[t, 0]] = mark[tri[t, 1]] = mark[tri[t, 2]] = True
        if not bad:
            return k + 1
    return -rounds


if _numba is not None and not _NUMPY_ONLY:
    _jit = _numba.njit(cache=True, nogil=True)
    _tri_folded = _jit(_tri_folded)
    _any_folded = _jit(_any_folded_loop)
    _relax = _jit(_relax_loop)
else:  # the numpy reference
    _any_folded = _any_folded_numpy
    _relax = _relax_numpy


def _anchor_depths(depth: np.ndarray, pts: np.ndarray, grid: tuple[int, int], fallback: float,
                   smooth: float) -> np.ndarray:
    """Depths for surface anchors at grid points ``pts``: the map's depth extended
    beyond the silhouette by the nearest object depth (so the depth field, and
    with it the parallax of the control points, is continuous across the
    silhouette), blurred with a Gaussian of ``smooth`` grid spacings (so depth
    jumps inside the object, e.g. seat/legs, do not fold the mesh)."""
    cov = np.isfinite(depth)
    if not cov.any():
        return np.full(len(pts), fallback)
    idx = ndimage.distance_transform_edt(~cov, return_distances=False, return_indices=True)
    filled = depth[idx[0], idx[1]]
    if smooth > 0:
        sx = smooth * np.ptp(pts[:, 0]) / max(grid[1] - 1, 1)
        sy = smooth * np.ptp(pts[:, 1]) / max(grid[0] - 1, 1)
        filled = ndimage.gaussian_filter(filled, (sy, sx), mode="nearest")
    return filled[np.rint(pts[:, 1]).astype(int), np.rint(pts[:, 0]).astype(int)].astype(np.float64)


def _lift(cam: CameraModel, pts: np.ndarray, z: np.ndarray) -> np.ndarray:
    """World points at pixel ``pts`` and depth ``z`` of ``cam``."""
    X = (pts[:, 0] - cam.cx) / cam.fx
    Y = (pts[:, 1] - cam.cy) / cam.fy
    if cam.projection == "perspective":
        X, Y = X * z, Y * z
    return np.c_[X, Y, z] @ cam.cam2world[:3, :3].T + cam.cam2world[:3, 3]
