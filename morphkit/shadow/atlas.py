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

Data and run time
-----------------
What is baked is frozen data, :class:`~morphkit.shadow.baked.BakedAtlas`
(saved and loaded by :mod:`morphkit.shadow.formats.atlasfile`); what a frame builds
from it and keeps -- per-map building blocks, counts -- is an
:class:`~morphkit.shadow.runtime.AtlasRuntime`. A :class:`ShadowAtlas` holds
one of each (:attr:`ShadowAtlas.baked`, :attr:`ShadowAtlas.runtime`) and its
shadow methods (:mod:`morphkit.shadow.methods`).

Run time
--------
The run-time algorithms are shadow methods of their own
(:class:`~morphkit.shadow.method.ShadowMethod`), built by :meth:`ShadowAtlas.method`
(:mod:`morphkit.shadow.methods`):
:class:`~morphkit.shadow.warped.ComposedWarp` (default),
:class:`~morphkit.shadow.warped.ThreeWarps` and
:class:`~morphkit.shadow.reprojection.method.ReprojectedMaps`; the atlas's run time
(:class:`~morphkit.shadow.runtime.AtlasRuntime`) holds the per-map building
blocks they share (sources, warpers, destination control points, hidden
layers), each built once and cached.

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

The method: Kang & Ihm [1]_.

References
----------
.. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
   (digest: ``docs/papers.md``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import numpy as np
import trimesh
from tqdm import tqdm

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..meshes import check_mesh, shape_hash
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, Item, PointLight
from ..validate import as_int, as_shape
from .baked import BakedAtlas
from .baking.controls import anchor_depths, lift, silhouette_box
from .formats.atlasfile import load_atlas, save_atlas
from .method import ShadowMethod
from .methods import AtlasMethods
from .rig import LightRig, MotionRange, RangeClampWarning, sample_axis
from .runtime import AtlasRuntime

__all__ = ["ShadowAtlas", "bake_atlas", "RangeClampWarning"]


class ShadowAtlas:
    """A baked k x k set of light-view depth maps with control points, ready to use.

    The baked data (frozen, :class:`~morphkit.shadow.baked.BakedAtlas`) and the
    run time (caches and counts, :class:`~morphkit.shadow.runtime.AtlasRuntime`)
    together; as a :class:`~morphkit.shadow.method.ShadowMethod` it is the
    default method (``"warp"``). Build with :func:`bake_atlas`; save with
    :meth:`save`, load with :meth:`load`
    (:func:`morphkit.shadow.formats.atlasfile.save_atlas`,
    :func:`~morphkit.shadow.formats.atlasfile.load_atlas`).

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
    mesh_sha256 : str or None
        The occluder's :func:`morphkit.meshes.shape_hash` (:func:`bake_atlas` records it);
        None when not known.

    Attributes
    ----------
    baked : morphkit.shadow.baked.BakedAtlas
        The baked data (also read through the properties below).
    runtime : morphkit.shadow.runtime.AtlasRuntime
        Its run-time caches and counts.
    """

    name = "warp"

    def __init__(self, rig: LightRig, xs: np.ndarray, ys: np.ndarray, maps: np.ndarray,
                 anchors: np.ndarray, plane_anchors: np.ndarray, control_grid: tuple[int, int],
                 anchor_kind: str = "sample", mesh_sha256: str | None = None) -> None:
        self.baked = BakedAtlas(rig, xs, ys, maps, anchors, plane_anchors, control_grid, anchor_kind,
                                mesh_sha256)
        self.runtime = AtlasRuntime(self.baked)
        self._methods = AtlasMethods(self.runtime)

    @classmethod
    def from_baked(cls, baked: BakedAtlas) -> ShadowAtlas:
        """The atlas of baked data (a fresh run time).

        Parameters
        ----------
        baked : morphkit.shadow.baked.BakedAtlas
            The data.

        Returns
        -------
        ShadowAtlas
            The atlas.
        """
        return cls(baked.rig, baked.xs, baked.ys, baked.maps, baked.anchors, baked.plane_anchors,
                   baked.control_grid, baked.anchor_kind, baked.mesh_sha256)

    # ------------------------------------------------------------ the baked data
    @property
    def rig(self) -> LightRig:
        """The light, object and motion range the maps were rendered for."""
        return self.baked.rig

    @property
    def xs(self) -> np.ndarray:
        """Sample positions along x, ``(kx,)`` (world units, ascending)."""
        return self.baked.xs

    @property
    def ys(self) -> np.ndarray:
        """Sample positions along y, ``(ky,)`` (world units, ascending)."""
        return self.baked.ys

    @property
    def maps(self) -> np.ndarray:
        """The light depth maps ``(ky, kx, H, W)`` float32, ``+inf`` background."""
        return self.baked.maps

    @property
    def anchors(self) -> np.ndarray:
        """Each map's control points in 3-D ``(ky, kx, N, 3)``, object at ``(0, 0)``."""
        return self.baked.anchors

    @property
    def plane_anchors(self) -> np.ndarray:
        """The control points lifted onto the anchor plane ``(ky, kx, N, 3)`` (fold fallback)."""
        return self.baked.plane_anchors

    @property
    def control_grid(self) -> tuple[int, int]:
        """Control points per map, ``(rows, cols)``."""
        return self.baked.control_grid

    @property
    def anchor_kind(self) -> str:
        """How the anchors were lifted: ``"sample"``, ``"shared"`` or ``"plane"``."""
        return self.baked.anchor_kind

    @property
    def control(self) -> np.ndarray:
        """Each map's control points ``(ky, kx, N, 2)``, pixels at its own sample."""
        return self.baked.control

    @property
    def triangles(self) -> np.ndarray:
        """The control mesh's triangles ``(M, 3)``."""
        return self.baked.triangles

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of every map (the light rig's image shape)."""
        return self.baked.shape

    @property
    def grid(self) -> tuple[int, int]:
        """``(ky, kx)`` sample grid."""
        return self.baked.grid

    @property
    def memory_bytes(self) -> int:
        """Bytes of the precomputed, persisted data (:attr:`BakedAtlas.memory_bytes
        <morphkit.shadow.baked.BakedAtlas.memory_bytes>`)."""
        return self.baked.memory_bytes

    # ------------------------------------------------------------ run time
    @property
    def fallbacks(self) -> int:
        """Map warps that would have folded and used the plane anchors instead, counted since
        the atlas was made or loaded (a run-time count, not saved)."""
        return self.runtime.fallbacks

    @property
    def relaxed(self) -> int:
        """Rounds of fold relaxation of destination control points so far (run-time count)."""
        return self.runtime.relaxed

    @property
    def layer_bytes(self) -> int:
        """Bytes of the hidden layers built so far (run-time cache, not persisted)."""
        return self.runtime.layer_bytes

    def prepare(self) -> float:
        """Build now what ``warps="reproject"`` otherwise builds on first use
        (:meth:`AtlasRuntime.prepare <morphkit.shadow.runtime.AtlasRuntime.prepare>`).

        Returns
        -------
        float
            Seconds spent (``morphkit bench shadows`` reports it as ``prep_ms``).
        """
        return self.runtime.prepare()

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
        (:class:`~morphkit.shadow.reprojection.method.ReprojectedMaps`); ``dst="interpolate"``
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
        return self._methods.get(warps=warps, dst=dst, blend=blend, layers=layers)


    # ------------------------------------------------------------ file I/O
    def save(self, path: str | Path) -> Path:
        """Write the baked data to one ``.npz`` file, atomically
        (:func:`morphkit.shadow.formats.atlasfile.save_atlas`).

        Parameters
        ----------
        path : str or pathlib.Path
            The ``.npz`` file to write.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        return save_atlas(self.baked, path)

    @classmethod
    def load(cls, path: str | Path, *, light: DirectionalLight | PointLight | None = None
             ) -> ShadowAtlas:
        """Read an atlas written by :meth:`save` (:func:`morphkit.shadow.formats.atlasfile.load_atlas`).

        Parameters
        ----------
        path : str or pathlib.Path
            The ``.npz`` file.
        light : DirectionalLight or PointLight, optional
            A light replacing the saved one (must be the same kind).

        Returns
        -------
        ShadowAtlas
            The atlas (a fresh run time).
        """
        return cls.from_baked(load_atlas(path, light=light))


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

    References
    ----------
    .. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
       (digest: ``docs/papers.md``).

    Examples
    --------
    No GL is needed to bake: any object with the ``depth`` method of
    :class:`~morphkit.protocols.SceneRenderer` will do. This one casts one ray
    per pixel (trimesh) and keeps the linear depth ``Z`` of the nearest hit.

    >>> import numpy as np
    >>> import trimesh
    >>> from morphkit.scene import DirectionalLight, Item, translation
    >>> from morphkit.shadow import MotionRange, bake_atlas
    >>> class RayCaster:
    ...     def depth(self, camera, items):
    ...         origins, dirs = (a.reshape(-1, 3) for a in camera.rays())
    ...         out = np.full(camera.shape[0] * camera.shape[1], np.inf, np.float32)
    ...         for item in items:
    ...             mesh = item.mesh.copy().apply_transform(item.pose)
    ...             hit, ray, _ = mesh.ray.intersects_location(origins, dirs, multiple_hits=False)
    ...             out[ray] = np.minimum(out[ray], (hit - camera.position) @ camera.axis)
    ...         return out.reshape(camera.shape)

    A cube of side 0.5 at height 0.75, moving over ``[-1, 1]^2`` under a
    slanted sun: a 3 x 3 atlas of 32 x 32 maps, sampled at -1, 0 and 1 on each
    axis.

    >>> cube, lifted = trimesh.creation.box(extents=(0.5, 0.5, 0.5)), translation(0.0, 0.0, 0.75)
    >>> atlas = bake_atlas(cube, lifted, MotionRange([-1.0, -1.0], [1.0, 1.0]),
    ...                    DirectionalLight(np.array([0.3, 0.0, -1.0])), (32, 32),
    ...                    renderer=RayCaster(), control_grid=(5, 5), progress=False)
    >>> atlas.grid, atlas.maps.shape, atlas.xs
    ((3, 3), (3, 3, 32, 32), array([-1.,  0.,  1.]))

    Under a directional light the light camera moves with the object, so every
    map shows the same cube and the warp between them is exact: the map at
    ``(0.5, -0.3)``, between samples, is the cube rendered there.

    >>> depth, light_cam = atlas.shadow_map([0.5, -0.3])
    >>> truth = RayCaster().depth(light_cam, [Item(cube, translation(0.5, -0.3, 0.0) @ lifted)])
    >>> seen = np.isfinite(truth)
    >>> bool(np.array_equal(np.isfinite(depth), seen)), bool(np.abs(depth[seen] - truth[seen]).max() < 1e-5)
    (True, True)
    """
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
    return ShadowAtlas(rig, xs, ys, maps, surf, plane, (rows, cols), anchors, shape_hash(mesh))


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


