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
The run-time algorithms are shadow methods of their own
(:class:`~morphkit.shadow.method.ShadowMethod`), built by :meth:`ShadowAtlas.method`:
:class:`~morphkit.shadow.warped.ComposedWarp` (default),
:class:`~morphkit.shadow.warped.ThreeWarps` and
:class:`~morphkit.shadow.reprojected.ReprojectedMaps`; the atlas holds the data
and the per-map building blocks they share (sources, warpers, destination
control points, hidden layers), each built once and cached.

For an object position, the 4 surrounding maps are each warped (piecewise
affine, :class:`~morphkit.warp.MeshWarper`, built once per map) from their
control points to the destination control points, and blended with bilinear
weights (``"composed"``: each source resampled once). ``"three"`` does the
paper's three warps instead (two row morphs, then a column morph). Destination
control points are the anchors projected at the exact position (``"project"``,
default) or bilinearly interpolated from the 4 maps (``"interpolate"``, the
paper). Maps are warped as premultiplied ``[coverage, coverage * depth]``
(:func:`~morphkit.shadow.planes.depth_planes`), so bilinear sampling never
mixes object depth with the background; the blended coverage is thresholded at 0.5.

Only what can hold the shadow is warped: a map's triangles whose source
footprint holds no object pixel (computed once per map,
:meth:`~morphkit.warp.MeshWarper.triangles_touching`) would add zeros and are
skipped, and the composed warps run as one fused, compiled pass per map
(sampling positions, bilinear taps and the weighted sum; no map images), split
into bands of rows over the CPUs (:func:`morphkit.warp.accumulate_warps`), with
the same result as ``cv2.remap`` up to its 1/32 px quantisation
(``morphkit bench shadows`` and ``docs/RESULTS.md`` have the figures). ``"three"``
uses the same pass for each of its warps, over whole images.

``warps="reproject"`` replaces the mesh by a per-pixel 3-D motion of the maps'
pixels into one z-buffer (:mod:`morphkit.shadow.reprojection`; no control points
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

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel
from ..errors import FoldOverError, ValidationError, expected_got
from ..meshes import check_mesh
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, PointLight
from ..validate import as_int, as_shape
from ..warp import (
    MeshWarper,
    grid_triangles,
)
from .controls import anchor_depths, lift, silhouette_box
from .fold import RELAX_ROUNDS, any_folded, relax_folds, signed_areas
from .method import ShadowMethod
from .planes import depth_planes
from .reprojected import ReprojectedMaps
from .reprojection import Layer, Reprojection, Source, hidden_layer
from .rig import LightRig, MotionRange, RangeClampWarning, sample_axis
from .warped import ComposedWarp, ThreeWarps, check_flag

__all__ = ["ShadowAtlas", "bake_atlas", "RangeClampWarning"]



@dataclass
class ShadowAtlas:
    """A baked k x k set of light-view depth maps with control points.

    Build with :func:`bake_atlas`; save with :meth:`save`, load with :meth:`load`.

    Parameters
    ----------
    rig : morphkit.shadow.rig.LightRig
        The light, object and motion range the maps were rendered for.
    xs, ys : (kx,) and (ky,) float64
        Sample positions of the object's ground translation along x and y
        (world units, ascending).
    maps : (ky, kx, H, W) float32
        Light-view linear depth maps, ``+inf`` background.
    anchors : (ky, kx, N, 3) float64
        Each map's control points lifted to 3-D, world frame, with the object
        at translation ``(0, 0)``.
    plane_anchors : (ky, kx, N, 3) float64
        The same control points lifted onto the plane through the object's
        anchor depth (the fold fallback).
    control_grid : (rows, cols)
        Control points per map, ``N = rows * cols``.
    anchor_kind : {"sample", "shared", "plane"}
        How the anchors were lifted (:func:`bake_atlas`).
    _warpers, _tex, _split, _touching, _support, _layers : dict
        Run-time caches; leave them out (they start empty).

    Attributes
    ----------
    fallbacks : int
        Map warps that would have folded and used the plane anchors instead, counted since
        the atlas was made or loaded (a run-time count, not saved).
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
    name: str = field(default="warp", init=False)

    def __post_init__(self) -> None:
        self.triangles = grid_triangles(*self.control_grid)
        ky, kx = self.maps.shape[:2]
        self.control = np.stack([np.stack([self.project((self.xs[i], self.ys[j]), self.anchors[j, i])
                                           for i in range(kx)]) for j in range(ky)])
        # orientation of each map's source triangles, for the fold test per frame
        self._src_sign = np.sign(np.stack([np.stack([signed_areas(self.control[j, i], self.triangles)
                                                     for i in range(kx)]) for j in range(ky)]))
        self.fallbacks = 0
        self.relaxed = 0
        self._methods: dict[tuple[Any, ...], ShadowMethod] = {}

    # ------------------------------------------------------------ geometry
    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of every map (the light rig's image shape)."""
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
        """Pixel positions ``(N, 2)`` of ``anchors (N, 3)`` with the object at ``xy``.

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
        T = self._texture(xy)
        q = (anchors + np.r_[xy, 0.0]) @ T[:, :3].T + T[:, 3]
        return q[:, :2] / q[:, 3:]

    def dst_points(self, j: int, i: int, eq: np.ndarray) -> np.ndarray:
        """Destination control points of map ``(j, i)`` for the object at ``eq``.

        Where the surface anchors' parallax would fold a triangle (an occlusion
        change), the offending vertices are pulled towards their plane-anchor
        positions (``plane + a (surface - plane)``, ``a`` halved per round) until
        no triangle folds: exact motion everywhere else, a projective motion at
        the fold.

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
        surf = self.project(eq, self.anchors[j, i])
        if self.anchor_kind == "plane":
            return surf
        tri = self.triangles
        sign = self._src_sign[j, i]
        min_area = 4 * tol.TRIANGLE_AREA_PX2
        if not any_folded(surf, tri, sign, min_area):
            return surf
        plane = self.project(eq, self.plane_anchors[j, i])
        dst = np.empty_like(surf)
        rounds = relax_folds(surf, plane, tri, sign, min_area, RELAX_ROUNDS, dst)
        self.relaxed += abs(rounds)
        return dst if rounds > 0 else plane

    def warper(self, j: int, i: int) -> MeshWarper:
        """The :class:`~morphkit.warp.MeshWarper` of map ``(j, i)``'s control points (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        morphkit.warp.MeshWarper
            The warper over the map's control points and ``triangles``.
        """
        w = self._warpers.get((j, i))
        if w is None:
            w = self._warpers[(j, i)] = MeshWarper(self.control[j, i], self.triangles)
        return w

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
        T = self._texture(xy)
        return float(T[2, :3] @ (self.rig.anchor0 + np.r_[np.asarray(xy, float), 0.0]) + T[2, 3])

    def active_triangles(self, j: int, i: int) -> np.ndarray:
        """Triangles of map ``(j, i)``'s mesh whose source holds the object (cached).

        Parameters
        ----------
        j, i : int
            The map's sample indices.

        Returns
        -------
        (M,) bool
            True for the triangles of ``triangles`` to warp.
        """
        a = self._touching.get((j, i))
        if a is None:
            a = self._touching[(j, i)] = self.warper(j, i).triangles_touching(self.source_planes(j, i)[0])
        return a

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
        s = self._split.get((j, i))
        if s is None:
            ref = self.anchor_depth((self.xs[i], self.ys[j]))
            s = self._split[(j, i)] = depth_planes(self.maps[j, i], ref)
        return s

    def cell(self, xy: np.ndarray) -> tuple[int, int, float, float]:
        """``(j, i, v, u)``: the cell's lower sample indices and the fractions in it.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).

        Returns
        -------
        tuple
            ``(j, i, v, u)``: ints, then fractions in ``[0, 1]`` (clamped).
        """
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
        ``light_offset``), and the light camera it belongs to: a convenience over
        the atlas's shadow methods (:meth:`method`).

        ``warps`` picks the algorithm: ``"composed"`` (default,
        :class:`~morphkit.shadow.warped.ComposedWarp`), ``"three"`` (the paper's,
        :class:`~morphkit.shadow.warped.ThreeWarps`) or ``"reproject"``
        (:class:`~morphkit.shadow.reprojected.ReprojectedMaps`); ``dst="interpolate"``
        interpolates the destination control points (the paper), ``blend="nearest"``
        uses only the nearest sample's map, ``layers`` (reproject only) reprojects
        the other maps' hidden layers instead of whole maps. Accuracy and speed of
        each: ``morphkit bench shadows`` and ``docs/RESULTS.md``.

        Returns ``(depth (H, W) float32 with +inf background, camera)``.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane (None: none).
        clamp : bool
            Clamp ``xy`` into the motion range instead of refusing it.
        warps : {"composed", "three", "reproject"}
            The algorithm (above).
        dst : {"project", "interpolate"}
            How destination control points are made.
        blend : {"bilinear", "nearest"}
            Blend of the cell's samples.
        layers : bool
            Reproject hidden layers (``warps="reproject"`` only).

        Returns
        -------
        depth : (H, W) float32
            Light-view linear depth, ``+inf`` background.
        camera : morphkit.camera.CameraModel
            The light camera of ``depth``.
        """
        return self.method(warps=warps, dst=dst, blend=blend, layers=layers).shadow_map(
            xy, light_offset=light_offset, clamp=clamp)

    def method(self, *, warps: Literal["composed", "three", "reproject"] = "composed",
               dst: Literal["project", "interpolate"] = "project",
               blend: Literal["bilinear", "nearest"] = "bilinear", layers: bool = True) -> ShadowMethod:
        """This atlas as the :class:`~morphkit.shadow.method.ShadowMethod` named by the
        options of :meth:`shadow_map` (checked now), for
        :class:`~morphkit.shadow.soft.SoftShadow`,
        :func:`~morphkit.shadow.frame.compare_frames` and the benchmarks.

        The object is built once per set of options and kept (it holds the
        run-time buffers); one object serves one thread at a time.

        Parameters
        ----------
        warps, dst, blend, layers
            As in :meth:`shadow_map`.

        Returns
        -------
        morphkit.shadow.method.ShadowMethod
            The method object (cached per option set).

        Raises
        ------
        ValidationError
            Unknown option values or combinations that have no algorithm
            (``blend="nearest"`` with ``warps="three"``, ``dst="interpolate"`` with
            ``warps="reproject"``), or ``dst="interpolate"``/``warps="three"`` on
            an atlas of ``"sample"`` anchors.
        """
        key = (warps, dst, blend, layers)
        m = self._methods.get(key) if isinstance(layers, bool) else None
        if m is None:
            m = _make_method(self, warps, dst, blend, layers)
            self._methods[key] = m
        return m

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
        prep = self._support.get((j, i))
        if prep is None:
            prep = self._support[(j, i)] = (
                Source(self.maps[j, i]), self.rig.camera_at(np.array([self.xs[i], self.ys[j]])))
        return prep

    def reprojection(self, src_cam: CameraModel, dst_cam: CameraModel, dxy: np.ndarray
                      ) -> Reprojection:
        """How a map of ``src_cam`` moves into ``dst_cam`` with the object moved by
        ``dxy`` on the ground: ``e = R^T d`` in the light frame; a directional
        light's camera moves with the object (rig model), so there ``e = 0``.

        Parameters
        ----------
        src_cam, dst_cam : morphkit.camera.CameraModel
            Light cameras of the source map and of the destination.
        dxy : (2,) float
            Object translation from the source to the destination (world units).

        Returns
        -------
        morphkit.shadow.reprojection.Reprojection
            The per-pixel motion.
        """
        persp = dst_cam.projection == "perspective"
        e = self.rig.R.T @ np.array([dxy[0], dxy[1], 0.0]) if persp else np.zeros(3)
        return Reprojection(persp, self.rig.fx, self.rig.fy, (src_cam.cx, src_cam.cy),
                                (dst_cam.cx, dst_cam.cy), e)

    def hidden_layer(self, primary: tuple[int, int], other: tuple[int, int]) -> Layer:
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
        lay = self._layers.get((primary, other))
        if lay is None:
            (jk, ik), (jn, i_n) = primary, other
            rp = self.reprojection(self.reprojection_source(jn, i_n)[1], self.reprojection_source(jk, ik)[1],
                                    np.array([self.xs[ik] - self.xs[i_n], self.ys[jk] - self.ys[jn]]))
            lay = self._layers[(primary, other)] = hidden_layer(
                self.maps[jk, ik], self.maps[jn, i_n], rp)
        return lay

    def prepare(self) -> float:
        """Build now what ``warps="reproject"`` otherwise builds on first use:
        every map as a reprojection source and the hidden layer of every pair
        of samples that share a cell. Returns the seconds it took (``morphkit
        bench shadows`` reports it as ``prep_ms``).

        Returns
        -------
        float
            Seconds spent.
        """
        t0 = time.perf_counter()
        ky, kx = self.grid
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

    def warp_job(self, j: int, i: int, c_dst: np.ndarray, eq: np.ndarray, weight: float
             ) -> tuple[Any, np.ndarray, np.ndarray, float]:
        """``(plan, source, active triangles, weight)`` of source ``(j, i)`` warped to
        ``c_dst`` (:func:`morphkit.warp.accumulate_warps`): premultiplied, and only
        the triangles whose source holds the object are warped (the rest add 0).

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
        src = self.source_planes(j, i)
        warper = self.warper(j, i)
        try:
            return warper.accumulation(c_dst, self.shape), src, self.active_triangles(j, i), weight
        except FoldOverError:
            # An occlusion change too large for the mesh: warp with plane anchors,
            # whose motion is projective and cannot fold (documented fallback).
            self.fallbacks += 1
            src_pts = self.project((self.xs[i], self.ys[j]), self.plane_anchors[j, i])
            dst_pts = self.project(eq, self.plane_anchors[j, i])
            warper = MeshWarper(src_pts, self.triangles)
            return (warper.accumulation(dst_pts, self.shape), src,
                    warper.triangles_touching(src[0]), weight)

    # ------------------------------------------------------------ file I/O
    def save(self, path: str | Path) -> Path:
        """Write the atlas to one ``.npz`` file, atomically (:func:`morphkit.shadow.atlasfile.save_atlas`).

        Parameters
        ----------
        path : str or pathlib.Path
            The ``.npz`` file to write.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        from .atlasfile import save_atlas

        return save_atlas(self, path)

    @classmethod
    def load(cls, path: str | Path, *, light: DirectionalLight | PointLight | None = None
             ) -> ShadowAtlas:
        """Read an atlas written by :meth:`save` (:func:`morphkit.shadow.atlasfile.load_atlas`).

        Parameters
        ----------
        path : str or pathlib.Path
            The ``.npz`` file.
        light : DirectionalLight or PointLight, optional
            A light replacing the saved one (must be the same kind).

        Returns
        -------
        ShadowAtlas
            The atlas.
        """
        from .atlasfile import load_atlas

        return load_atlas(path, light=light)


def bake_atlas(mesh: trimesh.Trimesh, base_pose: np.ndarray, motion: MotionRange,
               light: DirectionalLight | PointLight, shape: tuple[int, int], *, renderer: SceneRenderer,
               grid: int | tuple[int, int] = 3, control_grid: tuple[int, int] = (17, 17),
               anchors: Literal["sample", "shared", "plane"] = "sample", margin: float = 0.04,
               smooth: float = 0.0, uniform: bool = False, progress: bool = True) -> ShadowAtlas:
    """Render the k x k light depth maps over ``motion`` and derive control points.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The occluder, object frame.
    base_pose : (4, 4) float
        ``object2world`` at translation ``(0, 0)``.
    motion : morphkit.shadow.rig.MotionRange
        The ground translations the atlas covers (world units).
    light : DirectionalLight or PointLight
        The light.
    shape : (H, W)
        Size of each depth map.
    margin : float
        Extra border of the light view around the object, a fraction of its size.
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

    Returns
    -------
    ShadowAtlas
        The atlas.

    Raises
    ------
    MeshError
        ``mesh`` cannot be drawn (:func:`morphkit.meshes.check_mesh`).
    ValidationError
        Bad options; a non-integral ``shape``, ``grid`` or ``control_grid``; a
        map above :data:`morphkit.tol.MAX_IMAGE_PIXELS` or maps above
        :data:`morphkit.tol.MAX_BUFFER_BYTES` in all (checked before anything
        is rendered or allocated).
    """
    from tqdm import tqdm

    from ..scene import Item

    mesh = check_mesh(mesh, "mesh")
    ky, kx = _pair(grid, "grid", 2, "k >= 2 samples per axis (an integer, or a pair (ky, kx))")
    rows, cols = _pair(control_grid, "control_grid", 2, "(rows, cols) >= (2, 2) of integers")
    if anchors not in ("sample", "shared", "plane"):
        raise ValidationError(expected_got("anchors", "'sample', 'shared' or 'plane'", anchors))
    H, W = as_shape(shape, "shadow map shape")
    nbytes = ky * kx * H * W * np.dtype(np.float32).itemsize
    if nbytes > tol.MAX_BUFFER_BYTES:  # before LightRig or the maps allocate anything
        raise ValidationError(expected_got(
            "atlas maps", f"at most {tol.MAX_BUFFER_BYTES} bytes (morphkit.tol.MAX_BUFFER_BYTES)",
            f"{ky} x {kx} maps of {H} x {W} float32 = {nbytes} bytes"))
    rig = LightRig(light, mesh, base_pose, motion, shape, margin=margin)
    mid = None
    if isinstance(light, PointLight) and not uniform:
        mid = light.position[:2] - rig.anchor0[:2]  # object centre under the light
    xs = sample_axis(motion.lo[0], motion.hi[0], kx, None if mid is None else mid[0])
    ys = sample_axis(motion.lo[1], motion.hi[1], ky, None if mid is None else mid[1])
    maps = np.empty((ky, kx, H, W), np.float32)
    bar = tqdm(total=ky * kx, desc="baking shadow atlas", unit="map", disable=None if progress else True,
               leave=False)
    for j in range(ky):
        for i in range(kx):
            xy = np.array([xs[i], ys[j]])
            maps[j, i] = renderer.depth(rig.camera_at(xy), [Item(mesh, rig.object_pose(xy))])
            bar.update()
    bar.close()
    boxes = np.array([[silhouette_box(maps[j, i]) for i in range(kx)] for j in range(ky)])
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
            z = anchor_depths(maps[j, i], pts, (rows, cols), anchor_z, smooth)
            surf[j, i] = lift(cam, pts, z) - np.r_[xy, 0.0]
            plane[j, i] = lift(cam, pts, np.full(len(pts), anchor_z)) - np.r_[xy, 0.0]
    if anchors == "shared":
        surf[:] = surf[ky // 2, kx // 2]
        plane[:] = plane[ky // 2, kx // 2]
    elif anchors == "plane":
        surf = plane
    return ShadowAtlas(rig, xs, ys, maps, surf, plane, (rows, cols), anchors)




_WARPS = ("composed", "three", "reproject")


def _pair(v: Any, name: str, lo: int, want: str) -> tuple[int, int]:
    """``v`` (an int, or a pair of ints) as a pair of ints >= ``lo``; ``2.5`` is refused."""
    vals = (v, v) if np.isscalar(v) else tuple(v) if isinstance(v, tuple | list | np.ndarray) else None
    if vals is None or len(vals) != 2:
        raise ValidationError(expected_got(name, want, repr(v)[:120]))
    try:
        a, b = (as_int(x, name) for x in vals)
    except ValidationError as exc:
        raise ValidationError(expected_got(name, want, repr(v)[:120])) from exc
    if a < lo or b < lo:
        raise ValidationError(expected_got(name, want, repr(v)[:120]))
    return a, b


def _make_method(atlas: ShadowAtlas, warps: str, dst: str, blend: str, layers: Any) -> ShadowMethod:
    """The shadow method object for :meth:`ShadowAtlas.method`'s options."""
    if warps not in _WARPS or dst not in ("project", "interpolate") or blend not in ("bilinear", "nearest"):
        raise ValidationError(expected_got(
            "warps/dst/blend", "'composed'|'three'|'reproject', 'project'|'interpolate' and "
            "'bilinear'|'nearest'", f"{warps!r}/{dst!r}/{blend!r}"))
    layers = check_flag(layers, "layers")
    interpolate, nearest = dst == "interpolate", blend == "nearest"
    if warps == "reproject":
        if interpolate:
            raise ValidationError(expected_got("dst", "'project' with warps='reproject' (it moves "
                                               "pixels, not control points)", repr(dst)))
        return ReprojectedMaps(atlas, nearest=nearest, layers=layers)
    if warps == "three":
        if nearest:
            raise ValidationError(expected_got("warps", "'composed' with blend='nearest' (one map "
                                               "is warped once)", "'three'"))
        return ThreeWarps(atlas, interpolate=interpolate)
    return ComposedWarp(atlas, interpolate=interpolate, nearest=nearest)
