"""The run-time side of a shadow atlas: :class:`AtlasRuntime`, the per-map building
blocks the shadow methods share, each built once and cached, and the run-time counts.

A :class:`~morphkit.shadow.baked.BakedAtlas` is frozen data; everything a frame
computes from it and keeps for the next frame lives here: texture matrices per
position, each map as coverage-depth planes (:func:`~morphkit.shadow.planes.depth_planes`),
its :class:`~morphkit.warp.MeshWarper` and the triangles that hold the object,
each map as a reprojection :class:`~morphkit.shadow.reprojection.Source` and
the hidden layers of neighbouring maps (:func:`~morphkit.shadow.reprojection.hidden_layer`).
The shadow methods (:mod:`morphkit.shadow.warped`, :mod:`morphkit.shadow.reprojection.method`)
read the baked data through :attr:`AtlasRuntime.baked` and these building
blocks, and report fallbacks here (:meth:`AtlasRuntime.count_fallback`); they
never change the baked data.

Caches hold what one atlas needs (a few entries per map, bounded by the grid);
one runtime serves one thread at a time.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import FoldOverError
from ..memo import Memo
from ..warp import MeshWarper
from .baked import BakedAtlas, anchor_depth_at, project_points
from .baking.fold import RELAX_ROUNDS, any_folded, relax_folds
from .planes import depth_planes
from .reprojection import Layer, Reprojection, Source, hidden_layer

__all__ = ["AtlasRuntime", "TEXTURE_CACHE_SIZE"]

#: Texture matrices kept per atlas (one per object position seen; a frame uses
#: the position and its cell's 4 samples).
TEXTURE_CACHE_SIZE = 256

Key = tuple[int, int]


class AtlasRuntime:
    """Caches and counts of one atlas at run time.

    Parameters
    ----------
    baked : morphkit.shadow.baked.BakedAtlas
        The baked data (read, never changed).

    Attributes
    ----------
    baked : morphkit.shadow.baked.BakedAtlas
        The baked data.
    fallbacks : int
        Map warps that would have folded and used the plane anchors instead,
        counted since this runtime was made (not saved).
    relaxed : int
        Rounds of fold relaxation of destination control points so far
        (:func:`~morphkit.shadow.baking.fold.relax_folds`).
    """

    def __init__(self, baked: BakedAtlas) -> None:
        self.baked = baked
        self.fallbacks = 0
        self.relaxed = 0
        self._tex: Memo[bytes, np.ndarray] = Memo(TEXTURE_CACHE_SIZE)
        self._warpers: Memo[Key, MeshWarper] = Memo()
        self._planes: Memo[Key, np.ndarray] = Memo()
        self._touching: Memo[Key, np.ndarray] = Memo()
        self._sources: Memo[Key, tuple[Source, CameraModel]] = Memo()
        self._layers: Memo[tuple[Key, Key], Layer] = Memo()

    def count_fallback(self) -> None:
        """Count one warp that fell back to the plane anchors (:attr:`fallbacks`)."""
        self.fallbacks += 1

    # ------------------------------------------------------------ geometry (cached)
    def texture(self, xy: Any) -> np.ndarray:
        """The light camera's texture matrix with the object at ``xy`` (cached: each
        frame needs it for the 4 samples and the position).

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).

        Returns
        -------
        (4, 4) float64
            :meth:`~morphkit.camera.CameraModel.texture_matrix` of the light camera there.
        """
        xy = np.asarray(xy, dtype=np.float64)
        return self._tex.get(xy.tobytes(), lambda: self.baked.rig.camera_at(xy).texture_matrix())

    def project(self, xy: Any, anchors: np.ndarray) -> np.ndarray:
        """Pixel positions ``(N, 2)`` of ``anchors (N, 3)`` with the object at ``xy``
        (:meth:`BakedAtlas.project <morphkit.shadow.baked.BakedAtlas.project>`, with
        the texture matrix cached).

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        anchors : (N, 3) float64
            Points in world frame at translation ``(0, 0)``.

        Returns
        -------
        (N, 2) float64
            Their pixel positions in the light camera at ``xy``.
        """
        xy = np.asarray(xy, dtype=np.float64)
        return project_points(self.texture(xy), xy, anchors)

    def anchor_depth(self, xy: Any) -> float:
        """Light depth of the object's anchor (bounding-box centre) at ``xy``.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).

        Returns
        -------
        float
            Depth of the anchor in the light camera at ``xy``.
        """
        return anchor_depth_at(self.texture(xy), self.baked.rig.anchor0, xy)

    def dst_points(self, j: int, i: int, eq: np.ndarray) -> np.ndarray:
        """Destination control points of map ``(j, i)`` for the object at ``eq``.

        Where the surface anchors' parallax would fold a triangle (an occlusion
        change), the offending vertices are pulled towards their plane-anchor
        positions (``plane + a (surface - plane)``, ``a`` halved per round) until
        no triangle folds: exact motion everywhere else, a projective motion at
        the fold (rounds counted in :attr:`relaxed`).

        Parameters
        ----------
        j, i : int
            The map's sample indices (row in ``ys``, column in ``xs``).
        eq : (2,) float
            The object's ground translation (world units).

        Returns
        -------
        (N, 2) float64
            Destination control points, pixels of the light camera at ``eq``.
        """
        b = self.baked
        surf = self.project(eq, b.anchors[j, i])
        if b.anchor_kind == "plane":
            return surf
        tri = b.triangles
        sign = b.src_sign[j, i]
        min_area = 4 * tol.TRIANGLE_AREA_PX2
        if not any_folded(surf, tri, sign, min_area):
            return surf
        plane = self.project(eq, b.plane_anchors[j, i])
        dst = np.empty_like(surf)
        rounds = relax_folds(surf, plane, tri, sign, min_area, RELAX_ROUNDS, dst)
        self.relaxed += abs(rounds)
        return dst if rounds > 0 else plane

    # ------------------------------------------------------------ mesh warps
    def warper(self, j: int, i: int) -> MeshWarper:
        """The :class:`~morphkit.warp.MeshWarper` of map ``(j, i)``'s control points (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        morphkit.warp.MeshWarper
            The warper over the map's control points and triangles.
        """
        b = self.baked
        return self._warpers.get((j, i), lambda: MeshWarper(b.control[j, i], b.triangles))

    def source_planes(self, j: int, i: int) -> np.ndarray:
        """Map ``(j, i)`` as coverage-depth planes ``(2, H, W)`` relative to its anchor depth (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        (2, H, W) float32
            Coverage and depth planes (:func:`morphkit.shadow.planes.depth_planes`).
        """
        b = self.baked
        return self._planes.get((j, i), lambda: depth_planes(
            b.maps[j, i], self.anchor_depth((b.xs[i], b.ys[j]))))

    def active_triangles(self, j: int, i: int) -> np.ndarray:
        """Triangles of map ``(j, i)``'s mesh whose source holds the object (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        (M,) bool
            True for the triangles to warp.
        """
        return self._touching.get((j, i), lambda: self.warper(j, i).triangles_touching(
            self.source_planes(j, i)[0]))

    def warp_job(self, j: int, i: int, c_dst: np.ndarray, eq: np.ndarray, weight: float
                 ) -> tuple[Any, np.ndarray, np.ndarray, float]:
        """``(plan, source, active triangles, weight)`` of source ``(j, i)`` warped to
        ``c_dst`` (:func:`morphkit.warp.accumulate_warps`): premultiplied, and only
        the triangles whose source holds the object are warped (the rest add 0).

        A warp that would fold (an occlusion change too large for the mesh) uses
        the plane anchors instead, whose motion is projective and cannot fold
        (documented fallback, counted in :attr:`fallbacks`).

        Parameters
        ----------
        j, i : int
            The source map's sample indices.
        c_dst : (N, 2) float64
            Destination control points, pixels.
        eq : (2,) float
            The object's ground translation (for the plane fallback).
        weight : float
            Blend weight of this source.

        Returns
        -------
        tuple
            ``(plan, source, active, weight)``: the
            ``morphkit.warp.Accumulation`` or ``morphkit.warp.WarpMaps`` plan, the
            source planes ``(2, H, W)`` float32, the ``(M,)`` bool triangles to warp
            and ``weight``.
        """
        b = self.baked
        src = self.source_planes(j, i)
        warper = self.warper(j, i)
        try:
            return warper.accumulation(c_dst, b.shape), src, self.active_triangles(j, i), weight
        except FoldOverError:
            self.count_fallback()
            src_pts = self.project((b.xs[i], b.ys[j]), b.plane_anchors[j, i])
            dst_pts = self.project(eq, b.plane_anchors[j, i])
            warper = MeshWarper(src_pts, b.triangles)
            return (warper.accumulation(dst_pts, b.shape), src,
                    warper.triangles_touching(src[0]), weight)

    # ------------------------------------------------------------ reprojection
    def reprojection_source(self, j: int, i: int) -> tuple[Source, CameraModel]:
        """Map ``(j, i)`` as a reprojection source, and its camera (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        source : morphkit.shadow.reprojection.Source
            The prepared map.
        camera : morphkit.camera.CameraModel
            The light camera at that sample.
        """
        b = self.baked
        return self._sources.get((j, i), lambda: (Source(b.maps[j, i]), b.rig.camera_at(b.sample_xy(j, i))))

    def moved(self, j: int, i: int, c_dst: tuple[float, float], dxy: np.ndarray) -> Reprojection:
        """How map ``(j, i)`` moves into the light camera of principal point ``c_dst``
        (:meth:`LightRig.principal_point <morphkit.shadow.rig.LightRig.principal_point>`, or
        another sample's camera) with the object moved by ``dxy`` on the ground: ``e = R^T d``
        in the light frame; a directional light's camera moves with the object (rig model), so
        there ``e = 0``. Not checked again (per frame): the map's camera and the rig were
        checked when they were made.

        Parameters
        ----------
        j, i : int
            The map's sample indices.
        c_dst : (float, float)
            The destination's principal point, pixels.
        dxy : (2,) float64
            Object translation from the map's sample to the destination (world units).

        Returns
        -------
        morphkit.shadow.reprojection.Reprojection
            The per-pixel motion.
        """
        cam = self.reprojection_source(j, i)[1]
        rig = self.baked.rig
        persp = cam.projection == "perspective"
        e = rig.R.T @ np.array([dxy[0], dxy[1], 0.0]) if persp else np.zeros(3)
        return Reprojection.unchecked(persp, [rig.fx, rig.fy, cam.cx, cam.cy, c_dst[0], c_dst[1],
                                              e[0], e[1], e[2]])

    def hidden_layer(self, primary: Key, other: Key) -> Layer:
        """What map ``other`` holds that map ``primary`` does not (cached per pair;
        :func:`morphkit.shadow.reprojection.hidden_layer`).

        Parameters
        ----------
        primary, other : (j, i)
            Sample indices of the two maps.

        Returns
        -------
        morphkit.shadow.reprojection.Layer
            ``other``'s hidden layer, in ``primary``'s pixels.
        """
        def make() -> Layer:
            b = self.baked
            (jk, ik), (jn, i_n) = primary, other
            dst = self.reprojection_source(jk, ik)[1]
            rp = self.moved(jn, i_n, (dst.cx, dst.cy), np.array([b.xs[ik] - b.xs[i_n], b.ys[jk] - b.ys[jn]]))
            return hidden_layer(b.maps[jk, ik], b.maps[jn, i_n], rp)

        return self._layers.get((primary, other), make)

    def prepare(self) -> float:
        """Build now what ``warps="reproject"`` otherwise builds on first use:
        every map as a reprojection source and the hidden layer of every pair
        of samples that share a cell.

        Returns
        -------
        float
            Seconds spent (``morphkit bench shadows`` reports it as ``prep_ms``).
        """
        t0 = time.perf_counter()
        ky, kx = self.baked.grid
        for j in range(ky):
            for i in range(kx):
                for jn in range(max(j - 1, 0), min(j + 2, ky)):
                    for i_n in range(max(i - 1, 0), min(i + 2, kx)):
                        if (jn, i_n) != (j, i):
                            self.hidden_layer((j, i), (jn, i_n))
        return time.perf_counter() - t0

    @property
    def layer_bytes(self) -> int:
        """Bytes of the hidden layers built so far (run-time cache, not persisted)."""
        return int(sum(lay.nbytes for lay in self._layers.values()))
