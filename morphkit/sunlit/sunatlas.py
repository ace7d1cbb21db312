"""A shadow atlas over the sun's direction in an asset's frame: one atlas, every yaw, every sun.

Paper 1's atlas samples a light view over the object's *translation*; a field of
billboards needs the other variable: the **direction of the sun in the asset's own
frame**. A :class:`SunAtlas` holds, for every direction ``d(a, e)`` of a
:class:`~morphkit.views.dome.ViewDome` (read here as directions *towards the sun*,
object frame, upper hemisphere: :mod:`morphkit.views.domecameras` for ``d``), the
orthographic light view of the normalised mesh along ``-d`` (the dome's
:meth:`~morphkit.views.domecameras.DomeCameras.ortho_camera`, a square covering
the bounding sphere) as a depth map and its coverage. :meth:`SunAtlas.light_view`
gives the light view along any sun direction: the three atlas views of the dome
triangle around it, morphed per pixel by marching their depth maps
(:func:`~morphkit.views.depthmorph.morph_views`; a light view is just a view),
exactly the stored view at an atlas direction. A texel of the morphed view holds the
caster where the views' weighted vote says so (the morph's coverage at least
:data:`~morphkit.tol.SUN_VIEW_MIN_COVERAGE`): the morph's own rule (any view's hit
covers) makes the union of three views' silhouettes, a shadow too large by about a
texel all round. A view's crossing of its surface is one the ray makes within
:data:`~morphkit.views.depthmorph.THICKNESS_STEPS` steps (the morph's rule): a ray
between two parts that view sees overlapping (a cow's legs) is not blocked by it, so the
gap another view sees through stays open in the shadow.

**The rule.** An instance's pose is ``x = s Rz(yaw) p + t`` (object point ``p``,
:meth:`~morphkit.billboard.frames.instances.Instances.object2world`). A sun in world direction
``l`` shines on it as a sun in direction ``Rz(-yaw) l`` shines on the unturned object:
a yawed instance under a sun is the object under the sun turned by ``-yaw`` (same
elevation, azimuth minus the yaw). So one atlas serves every instance of the asset,
whatever its yaw, scale and place, and every sun position (:func:`sun_in_object`).
Only turns about ``+z`` are served (a tilted instance would see the sun from below
its own horizon, which the atlas does not hold): other poses raise.

**Horizon and grazing sun.** A sun at or below the horizon (world elevation ``<= 0``)
has no light view: :meth:`SunAtlas.light_view` returns ``None`` and
:func:`ground_shadow` reports every point lit by this caster (no shadow; the ground
gets no direct sun light then anyway), without an error. A sun between the horizon
and :data:`~morphkit.tol.SUN_MIN_ELEVATION_DEG` is **clamped** to that elevation (its
azimuth kept): the shadow stops growing there instead of vanishing, so it does not
pop while the sun sets (the reason for the value: the tolerance's note).

**Lookup** (:func:`ground_visibility`): each ground point is taken into the object
frame, projected along the sun into the light view and shadowed where it lies behind
the stored depth by more than :data:`~morphkit.tol.SUN_GROUND_BIAS_TEXELS` texels
(the projective lookup of :mod:`.lookup`; points outside the view are lit: the view
holds the whole bounding sphere).

Storage: depth as float16 offsets from the camera distance (``+inf`` where nothing is
drawn) and coverage as uint8: :data:`BYTES_PER_TEXEL` bytes a texel
(:attr:`SunAtlas.nbytes`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import trimesh

from .. import tol
from ..billboard.baking.bakelook import mesh_hash
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..meshes import normalize
from ..protocols import SceneRenderer
from ..scene import Item
from ..shadow.lookup import ShadowBias, shadow_visibility
from ..validate import as_direction, as_finite_array, as_int, as_shape
from ..views.depthmorph import morph_views
from ..views.dome import ViewDome
from ..views.domecameras import DomeCameras, direction
from ..views.gbuffer import ViewSurface
from .pointlevels import block_points, grid_quads

__all__ = ["SunAtlas", "sphere_sun_atlas", "AtlasPoints", "AtlasQuads",
           "segment_reach", "bake_sun_atlas", "sun_in_object",
           "instance_frame", "ground_visibility", "ground_shadow", "sun_direction", "BYTES_PER_TEXEL",
           "MAX_POINT_LEVEL"]

#: Stored bytes per atlas texel: float16 depth and uint8 coverage.
BYTES_PER_TEXEL = 3
#: The coarsest level of :meth:`SunAtlas.packed_points` (blocks of ``2**6 = 64`` texels a side).
MAX_POINT_LEVEL = 6


def sun_direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """The unit direction towards a sun at ``(azimuth, elevation)`` (world or object frame).

    Parameters
    ----------
    azimuth_deg, elevation_deg : float
        Degrees (azimuth from ``+x`` counter-clockwise about ``+z``; elevation above the
        horizon).

    Returns
    -------
    (3,) float64
        ``(cos e cos a, cos e sin a, sin e)``.
    """
    a, e = np.radians(float(azimuth_deg)), np.radians(float(elevation_deg))
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def _angles(d: np.ndarray) -> tuple[float, float]:
    az = float(np.degrees(np.arctan2(d[1], d[0])))
    el = float(np.degrees(np.arcsin(np.clip(d[2], -1.0, 1.0))))
    return az, el


def instance_frame(pose: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Scale, yaw and translation of an instance's ``object2world`` pose (module docstring).

    Parameters
    ----------
    pose : (4, 4) float
        ``translation(t) @ Rz(yaw) @ scale(s)``, as
        :meth:`~morphkit.billboard.frames.instances.Instances.object2world` builds it.

    Returns
    -------
    scale : float
        ``s > 0``.
    yaw_deg : float
        Degrees.
    translation : (3,) float64
        ``t``.

    Raises
    ------
    ValidationError
        Not a 4x4 finite matrix; a last row other than ``0 0 0 1``; a rotation other
        than a turn about ``+z``, or a non-uniform scale.
    """
    T = as_finite_array(pose, "pose", shape=(4, 4))
    if not np.allclose(T[3], [0.0, 0.0, 0.0, 1.0], atol=tol.POSE_ORTHO):
        raise ValidationError(expected_got("pose", "a last row 0 0 0 1", T[3].tolist()))
    M = T[:3, :3]
    s = float(np.cbrt(np.linalg.det(M)))
    if not s > tol.MIN_EXTENT:
        raise ValidationError(expected_got("pose", "a positive uniform scale (det > 0)", f"det {s**3:g}"))
    R = M / s
    if (not np.allclose(R.T @ R, np.eye(3), atol=tol.POSE_ORTHO)
            or not np.allclose(R[:, 2], [0.0, 0.0, 1.0], atol=tol.SUN_YAW_ONLY_ATOL)):
        raise ValidationError(expected_got("pose", "translation @ Rz(yaw) @ uniform scale (a yaw only)",
                                           "a tilted or sheared pose"))
    return s, float(np.degrees(np.arctan2(R[1, 0], R[0, 0]))), T[:3, 3].copy()


def sun_in_object(pose: np.ndarray, sun_dir_world: np.ndarray) -> np.ndarray | None:
    """The direction towards the sun in the instance's object frame (the rule, module docstring).

    Parameters
    ----------
    pose : (4, 4) float
        The instance's ``object2world`` (:func:`instance_frame`).
    sun_dir_world : (3,) float
        Towards the sun, world frame (any length > 0).

    Returns
    -------
    (3,) float64 or None
        ``Rz(-yaw) l``, unit; ``None`` when the sun is at or below the horizon.

    Raises
    ------
    ValidationError
        A pose that is not a yaw (:func:`instance_frame`); a zero or non-finite direction.
    """
    _, yaw, _ = instance_frame(pose)
    d = as_direction(sun_dir_world, "sun_dir_world")
    if d[2] <= 0.0:
        return None
    c, s = np.cos(np.radians(yaw)), np.sin(np.radians(yaw))
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]])


class AtlasPoints(NamedTuple):
    """A sun atlas's surface points, all views concatenated (:meth:`SunAtlas.packed_points`).

    Parameters
    ----------
    points, normals : (P, 3) float32
        Object frame; a normal of zeros is unknown.
    starts, lengths : (V,) int64
        Each view's first point and count.
    directions : (V, 3) float64
        Each view's direction (towards the view, object frame).
    sizes : (P,) float32
        Each point's footprint side, atlas texels (1 at level 0; :mod:`.pointlevels`).
    reach : (V,) float64
        Each view's farthest point from the object origin (:func:`segment_reach`; 0: no point).
    """

    points: np.ndarray
    normals: np.ndarray
    starts: np.ndarray
    lengths: np.ndarray
    directions: np.ndarray
    sizes: np.ndarray
    reach: np.ndarray


class AtlasQuads(NamedTuple):
    """A sun atlas's level-0 quads, all views concatenated (:meth:`SunAtlas.packed_quads`).

    Parameters
    ----------
    quads : (Q, 4) int32
        Each quad's four points, indices into :meth:`SunAtlas.packed_points` ``(0).points``;
        its triangles ``(q0, q1, q2)`` and ``(q0, q2, q3)``
        (:func:`~morphkit.sunlit.pointlevels.grid_quads`).
    starts, lengths : (V,) int64
        Each view's first quad and count.
    inner : (P,) bool
        Per level-0 point: the quads alone draw it (no square).
    """

    quads: np.ndarray
    starts: np.ndarray
    lengths: np.ndarray
    inner: np.ndarray


def segment_reach(points: np.ndarray, starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Each segment's farthest point from the origin.

    Parameters
    ----------
    points : (P, 3) float
        All segments' points, concatenated.
    starts, lengths : (S,) int
        Each segment's first point and count.

    Returns
    -------
    (S,) float64
        The largest ``|p|`` of each segment's points (0 for an empty segment).
    """
    out = np.zeros(len(starts))
    for i, (a, n) in enumerate(zip(np.asarray(starts).tolist(), np.asarray(lengths).tolist(), strict=True)):
        if n:
            seg = np.asarray(points[a:a + n], np.float64)
            out[i] = float(np.sqrt(np.einsum("ij,ij->i", seg, seg).max()))
    return out


@dataclass(frozen=True, eq=False)
class SunAtlas:
    """Orthographic light views of one asset over the sun's direction (module docstring).

    Parameters
    ----------
    dome : ViewDome
        The sun directions (object frame), one view each.
    cameras : DomeCameras
        The camera rule; its ``shape`` is the views' (``(n, n)``).
    depth : (V, n, n) float16
        Depth along each view's axis minus ``cameras.distance``; ``+inf`` where empty.
    coverage : (V, n, n) uint8
        Coverage, 255 where the mesh is drawn.
    mesh_hash : str
        :func:`~morphkit.billboard.baking.bakelook.mesh_hash` of the mesh (``"0" * 64`` for
        analytic atlases).

    Raises
    ------
    ValidationError
        Arrays that do not fit the dome and the cameras.
    """

    dome: ViewDome
    cameras: DomeCameras
    depth: np.ndarray
    coverage: np.ndarray
    mesh_hash: str = "0" * 64
    _surfaces: dict = field(init=False, repr=False, default_factory=dict)
    _points: dict = field(init=False, repr=False, default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.dome, ViewDome):
            raise ValidationError(expected_got("dome", "a ViewDome", type(self.dome).__name__))
        if not isinstance(self.cameras, DomeCameras):
            raise ValidationError(expected_got("cameras", "a DomeCameras", type(self.cameras).__name__))
        want = (self.dome.views, *self.cameras.shape)
        d, c = np.asarray(self.depth), np.asarray(self.coverage)
        if d.shape != want or d.dtype != np.float16 or c.shape != want or c.dtype != np.uint8:
            raise ValidationError(expected_got("depth, coverage", f"float16 and uint8 arrays of {want}",
                                               f"{d.dtype} {d.shape}, {c.dtype} {c.shape}"))
        if np.isnan(d).any() or (d == -np.inf).any():
            raise ValidationError(expected_got("depth", "finite offsets or +inf", "NaN or -inf"))

    @classmethod
    def from_depths(cls, dome: ViewDome, cameras: DomeCameras, depths: np.ndarray,
                    mesh_hash: str = "0" * 64) -> SunAtlas:
        """An atlas from float depth maps of the dome's light views (``+inf`` where empty).

        Parameters
        ----------
        dome : ViewDome
            The sun directions.
        cameras : DomeCameras
            The camera rule the views were made with (:meth:`view_camera`).
        depths : (V, n, n) float
            Linear depth along each view's axis.
        mesh_hash : str
            The mesh's hash.

        Returns
        -------
        SunAtlas
            Stored at float16 / uint8 (coverage: the drawn texels).
        """
        d = np.asarray(depths, dtype=np.float32)
        drawn = np.isfinite(d)
        off = np.where(drawn, d - np.float32(cameras.distance), np.inf).astype(np.float16)
        return cls(dome, cameras, off, np.where(drawn, 255, 0).astype(np.uint8), mesh_hash)

    @property
    def size(self) -> int:
        """The views' side, texels."""
        return int(self.cameras.shape[0])

    @property
    def nbytes(self) -> int:
        """Stored bytes of the views (depth and coverage)."""
        return int(self.depth.nbytes + self.coverage.nbytes)

    def view_camera(self, k: int) -> CameraModel:
        """The light camera of atlas view ``k`` (object frame).

        Parameters
        ----------
        k : int
            View index.

        Returns
        -------
        CameraModel
            Orthographic, of the views' shape.
        """
        k = as_int(k, "view", lo=0, hi=self.dome.views - 1)
        return self.cameras.ortho_camera(float(self.dome.azimuths_deg()[k]),
                                         float(self.dome.elevations_deg()[k]), self.cameras.shape)

    def view_depth(self, k: int) -> np.ndarray:
        """Linear depth ``(n, n)`` float32 of atlas view ``k`` (``+inf`` where empty).

        Parameters
        ----------
        k : int
            View index.

        Returns
        -------
        (n, n) float32
            Along the view's axis.
        """
        return self._surface(as_int(k, "view", lo=0, hi=self.dome.views - 1)).depth

    def _surface(self, k: int) -> ViewSurface:
        s = self._surfaces.get(k)
        if s is None:
            n = self.size
            depth = self.depth[k].astype(np.float32) + np.float32(self.cameras.distance)
            albedo = np.zeros((n, n, 4), np.float32)
            albedo[..., 3] = self.coverage[k].astype(np.float32) * np.float32(1.0 / 255.0)
            s = self._surfaces[k] = ViewSurface(albedo, np.zeros((n, n, 3), np.float32), depth)
        return s

    def _drawn(self, k: int) -> np.ndarray:
        """View ``k``'s texels that hold a point: covered, at a finite positive depth (the texels
        :meth:`~morphkit.camera.CameraModel.unproject` finds valid)."""
        depth = self._surface(k).depth
        return np.isfinite(depth) & (depth > 0) & (self.coverage[k] > 0)

    def _view_grid(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """View ``k``'s texels' points ``(n, n, 3)``, drawn mask and normals (:meth:`view_points`)."""
        world = self.view_camera(k).unproject(self._surface(k).depth)[0]
        drawn = self._drawn(k)
        du, dv = (_grid_difference(world, drawn, axis) for axis in (1, 0))
        n = np.cross(du, dv)
        norm = np.linalg.norm(n, axis=-1, keepdims=True)
        ok = norm[..., 0] > tol.MIN_EXTENT
        n = np.where(ok[..., None], n / np.where(ok, norm[..., 0], 1.0)[..., None], 0.0)
        toward = direction(float(self.dome.azimuths_deg()[k]), float(self.dome.elevations_deg()[k]))
        n *= np.where(n @ toward < 0.0, -1.0, 1.0)[..., None]
        return world, drawn, n

    def view_points(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """The surface points atlas view ``k`` holds, and their normals.

        Points: the drawn texels' centres at their depth. Normals: from the depth map's
        neighbouring points (central differences, one-sided where a neighbour is empty),
        turned towards the view; ``0`` where a texel has no drawn neighbour along an axis.

        Parameters
        ----------
        k : int
            View index.

        Returns
        -------
        points : (M, 3) float32
            Object frame, one per drawn texel (read-only; cached).
        normals : (M, 3) float32
            Unit normals (object frame) or zero vectors (read-only; cached).
        """
        k = as_int(k, "view", lo=0, hi=self.dome.views - 1)
        got = self._points.get(k)
        if got is None:
            world, drawn, n = self._view_grid(k)
            pts = np.ascontiguousarray(world[drawn], dtype=np.float32)
            nrm = np.ascontiguousarray(n[drawn], dtype=np.float32)
            pts.setflags(write=False)
            nrm.setflags(write=False)
            got = self._points[k] = (pts, nrm)
        return got

    def _coarse_levels(self, k: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """View ``k``'s points and sizes at levels ``1 .. MAX_POINT_LEVEL`` (:mod:`.pointlevels`),
        from one pass over its texels."""
        world, drawn, n = self._view_grid(k)
        depth = self._surface(k).depth
        texel = 2.0 * float(self.cameras.half_extent[0]) / self.size
        return [block_points(world, drawn, n, depth, 2 ** lv, tol.SPLAT_LEVEL_DEPTH_GAP * 2 ** lv * texel)
                for lv in range(1, MAX_POINT_LEVEL + 1)]

    def packed_points(self, level: int = 0) -> AtlasPoints:
        """Every view's points at a level, concatenated in view order (made once, cached).

        Level 0 is made at its first call, the coarser levels all together at the first call of
        any of them (one pass over each view's texels).

        Parameters
        ----------
        level : int
            0: each view's :meth:`view_points` (size 1); ``l > 0``: one point per ``2**l``
            texels a side (:func:`~morphkit.sunlit.pointlevels.block_points`), at most
            :data:`MAX_POINT_LEVEL`.

        Returns
        -------
        AtlasPoints
            The points, their normals and sizes, each view's first point and count, and each
            view's direction (towards it, object frame).

        Raises
        ------
        ValidationError
            A level outside ``0 .. MAX_POINT_LEVEL``.
        """
        level = as_int(level, "level", lo=0, hi=MAX_POINT_LEVEL)
        got = self._points.get(("packed", level))
        if got is not None:
            return got
        if level == 0:
            per_level = {0: [(*self.view_points(k), np.ones(len(self.view_points(k)[0]), np.float32))
                             for k in range(self.dome.views)]}
        else:
            views = [self._coarse_levels(k) for k in range(self.dome.views)]
            per_level = {lv: [v[lv - 1] for v in views] for lv in range(1, MAX_POINT_LEVEL + 1)}
        dirs = np.ascontiguousarray(direction(self.dome.azimuths_deg(), self.dome.elevations_deg())
                                    .reshape(-1, 3), dtype=np.float64)
        for lv, parts in per_level.items():
            lens = np.array([len(p[0]) for p in parts], np.int64)
            arrays = [np.ascontiguousarray(np.concatenate([p[j] for p in parts]), dtype=np.float32)
                      for j in range(3)]
            for a in arrays:
                a.setflags(write=False)
            starts = np.concatenate([[0], np.cumsum(lens)[:-1]]).astype(np.int64)
            self._points[("packed", lv)] = AtlasPoints(arrays[0], arrays[1], starts, lens, dirs, arrays[2],
                                                       segment_reach(arrays[0], starts, lens))
        return self._points[("packed", level)]

    def packed_quads(self) -> AtlasQuads:
        """Every view's quads of level-0 points, concatenated in view order (made once, cached).

        A quad: four drawn texels meeting at a corner whose depths lie within
        :data:`~morphkit.tol.SPLAT_QUAD_DEPTH_GAP` texels of each other
        (:func:`~morphkit.sunlit.pointlevels.grid_quads`).

        Returns
        -------
        AtlasQuads
            The quads (indices into ``packed_points(0)``), each view's first quad and count,
            and the points the quads alone draw.
        """
        got = self._points.get("quads")
        if got is not None:
            return got
        pk = self.packed_points(0)
        texel = 2.0 * float(self.cameras.half_extent[0]) / self.size
        parts = []
        for k in range(self.dome.views):
            q, inner = grid_quads(self._drawn(k), self._surface(k).depth, tol.SPLAT_QUAD_DEPTH_GAP * texel)
            parts.append((q + pk.starts[k], inner))
        lens = np.array([len(q) for q, _ in parts], np.int64)
        quads = np.ascontiguousarray(np.concatenate([q for q, _ in parts]).reshape(-1, 4), np.int32)
        inner = np.ascontiguousarray(np.concatenate([i for _, i in parts]), bool)
        for a in (quads, inner):
            a.setflags(write=False)
        starts = np.concatenate([[0], np.cumsum(lens)[:-1]]).astype(np.int64)
        got = self._points["quads"] = AtlasQuads(quads, starts, lens, inner)
        return got

    def check_mesh(self, mesh: trimesh.Trimesh) -> None:
        """Raise unless ``mesh`` is the one this atlas was baked from (by hash).

        Parameters
        ----------
        mesh : trimesh.Trimesh
            Any mesh (normalised first, as the bake did).

        Raises
        ------
        ValidationError
            Another mesh (both hashes named).
        """
        got = mesh_hash(mesh)
        if got != self.mesh_hash:
            raise ValidationError(expected_got("mesh", f"the atlas's mesh (hash {self.mesh_hash[:12]})",
                                               f"hash {got[:12]}"))

    def light_view(self, sun_dir_object: np.ndarray, shape: tuple[int, int] | None = None
                   ) -> tuple[CameraModel, np.ndarray] | None:
        """The orthographic light view along a sun direction, object frame (module docstring).

        Parameters
        ----------
        sun_dir_object : (3,) float
            Towards the sun, object frame (any length > 0).
        shape : tuple of 2 int, optional
            ``(h, w)`` of the view (default: the atlas's).

        Returns
        -------
        (CameraModel, (h, w) float32) or None
            The light camera (object frame, looking along the sun's light) and the
            caster's linear depth along its axis (``+inf`` where empty); ``None`` for a sun
            at or below the horizon. A sun under
            :data:`~morphkit.tol.SUN_MIN_ELEVATION_DEG` is served at that elevation.

        Raises
        ------
        ValidationError
            A zero or non-finite direction, a bad shape.
        """
        d = as_direction(sun_dir_object, "sun_dir_object")
        shape = self.cameras.shape if shape is None else as_shape(shape, "shape")
        if d[2] <= 0.0:
            return None
        az, el = _angles(d)
        el = max(el, tol.SUN_MIN_ELEVATION_DEG)
        views, weights = self.dome.weights(az, el)
        live = [(int(k), float(w)) for k, w in zip(views, weights, strict=True) if w > 0.0]
        if len(live) == 1 and tuple(shape) == self.cameras.shape:
            k = live[0][0]
            return self.view_camera(k), self._surface(k).depth.copy()  # an atlas direction: exact
        target = self.cameras.ortho_camera(az, el, shape)
        refs = [(self.view_camera(k), self._surface(k), w) for k, w in live]
        morph = morph_views(target, self.cameras.pivot, self.cameras.radius, refs)
        held = morph.alpha >= np.float32(tol.SUN_VIEW_MIN_COVERAGE)
        return target, np.where(held, morph.depth, np.float32(np.inf))


def _grid_difference(points: np.ndarray, drawn: np.ndarray, axis: int) -> np.ndarray:
    """Per texel, the difference of its drawn neighbours' points along ``axis`` (central where
    both are drawn, one-sided where one is, 0 where none)."""
    p = np.where(drawn[..., None], points, 0.0)
    fwd = np.zeros_like(p)
    bwd = np.zeros_like(p)
    has_f = np.zeros_like(drawn)
    has_b = np.zeros_like(drawn)
    sl_a = [slice(None)] * 2
    sl_b = [slice(None)] * 2
    sl_a[axis], sl_b[axis] = slice(0, -1), slice(1, None)
    a, b = tuple(sl_a), tuple(sl_b)
    fwd[a] = p[b] - p[a]
    has_f[a] = drawn[b] & drawn[a]
    bwd[b] = p[b] - p[a]
    has_b[b] = drawn[b] & drawn[a]
    both = has_f & has_b
    out = np.where(both[..., None], 0.5 * (fwd + bwd), 0.0)
    out = np.where((has_f & ~has_b)[..., None], fwd, out)
    return np.where((has_b & ~has_f)[..., None], bwd, out)


def bake_sun_atlas(mesh: trimesh.Trimesh, renderer: SceneRenderer, *, dome: ViewDome | None = None,
                   size: int = 128) -> SunAtlas:
    """Render the light views of ``mesh`` over the sun's directions (module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh; normalised first (:func:`morphkit.meshes.normalize`), as
        :func:`~morphkit.billboard.domeasset.bake_dome` does.
    renderer : SceneRenderer
        E.g. :class:`morphkit.render.Renderer` (its ``depth``).
    dome : ViewDome, optional
        The sun directions (default :class:`ViewDome` ``()``).
    size : int
        Each view's side, texels.

    Returns
    -------
    SunAtlas
        The atlas.

    Raises
    ------
    ValidationError
        Bad arguments.
    MeshError
        Not a usable mesh.
    """
    dome = ViewDome() if dome is None else dome
    if not isinstance(dome, ViewDome):
        raise ValidationError(expected_got("dome", "a ViewDome", type(dome).__name__))
    size = as_int(size, "size", lo=8, hi=tol.MAX_BILLBOARD_SIDE)
    norm = normalize(mesh)
    cams = DomeCameras.fit(norm, size)
    items = [Item(norm)]
    az, el = dome.azimuths_deg(), dome.elevations_deg()
    depths = np.stack([renderer.depth(cams.ortho_camera(float(az[k]), float(el[k]), cams.shape), items)
                       for k in range(dome.views)])
    return SunAtlas.from_depths(dome, cams, depths, mesh_hash(norm))


def sphere_sun_atlas(dome: ViewDome | None = None, size: int = 32) -> SunAtlas:
    """The sun atlas of the analytic sphere (:mod:`morphkit.billboard.analytic`), its light views
    ray-cast exactly: the shadow caster of tests and examples that need no renderer.

    Parameters
    ----------
    dome : ViewDome, optional
        The sun directions (default: rings at 10, 40 and 70 degrees of 8, 8 and 4 views and a top view).
    size : int, optional
        Each view's side, texels.

    Returns
    -------
    SunAtlas
        About the sphere asset's pivot, radius 1, distance 12 (as
        :func:`~morphkit.billboard.analytic.sphere_dome_asset`).
    """
    from ..billboard.analytic import SPHERE_PIVOT, sphere_view

    dome = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True) if dome is None else dome
    n = as_int(size, "size", lo=8, hi=tol.MAX_BILLBOARD_SIDE)
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (n, n))
    depths = [sphere_view(cams.ortho_camera(a, e, (n, n)))[2]
              for a, e in zip(dome.azimuths_deg(), dome.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(dome, cams, np.stack(depths))


def ground_visibility(light_cam: CameraModel, depth: np.ndarray, pose: np.ndarray,
                      points: np.ndarray) -> np.ndarray:
    """Visibility of world points under one instance's light view (module docstring, "Lookup").

    Parameters
    ----------
    light_cam : CameraModel
        The light view's camera, object frame.
    depth : (h, w) float32
        Its depth map (``+inf`` where empty).
    pose : (4, 4) float
        The instance's ``object2world`` (:func:`instance_frame`).
    points : (N, 3) float
        Receiver points, world frame.

    Returns
    -------
    (N,) float32
        1 lit, 0 shadowed by this instance.
    """
    instance_frame(pose)
    pts = as_finite_array(points, "points", shape=(None, 3))
    inv = np.linalg.inv(np.asarray(pose, dtype=np.float64))
    local = pts @ inv[:3, :3].T + inv[:3, 3]
    bias = ShadowBias(constant=tol.SUN_GROUND_BIAS_TEXELS, slope=0.0)
    return shadow_visibility(local, depth, light_cam, bias=bias)


def ground_shadow(atlas: SunAtlas, pose: np.ndarray, sun_dir_world: np.ndarray, points: np.ndarray,
                  *, shape: tuple[int, int] | None = None) -> np.ndarray:
    """One instance's shadow on receiver points, from its asset's sun atlas.

    Parameters
    ----------
    atlas : SunAtlas
        The asset's atlas.
    pose : (4, 4) float
        The instance's ``object2world`` (a yaw, a uniform scale, a translation).
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    points : (N, 3) float
        Receiver points (e.g. the ground's), world frame.
    shape : tuple of 2 int, optional
        The light view's ``(h, w)`` (default: the atlas's).

    Returns
    -------
    (N,) float32
        1 lit, 0 shadowed; all 1 for a sun at or below the horizon.

    Raises
    ------
    ValidationError
        Not a SunAtlas; a pose that is not a yaw; bad points or direction.

    Examples
    --------
    The analytic sphere's atlas (radius 0.6 about ``(0, 0, 1)``) under a sun straight
    above shadows the ground under its centre, not a point 1 unit aside:

    >>> import numpy as np
    >>> from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_view
    >>> from morphkit.views.dome import ViewDome
    >>> from morphkit.views.domecameras import DomeCameras
    >>> from morphkit.sunlit.sunatlas import SunAtlas, ground_shadow
    >>> dome = ViewDome(((20.0, 6),), top=True)
    >>> cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (32, 32))
    >>> depths = [sphere_view(cams.ortho_camera(a, e, (32, 32)))[2]
    ...           for a, e in zip(dome.azimuths_deg(), dome.elevations_deg())]
    >>> atlas = SunAtlas.from_depths(dome, cams, np.stack(depths))
    >>> ground = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    >>> ground_shadow(atlas, np.eye(4), np.array([0.0, 0.0, 1.0]), ground)
    array([0., 1.], dtype=float32)
    """
    if not isinstance(atlas, SunAtlas):
        raise ValidationError(expected_got("atlas", "a SunAtlas", type(atlas).__name__))
    pts = as_finite_array(points, "points", shape=(None, 3))
    sun = sun_in_object(pose, sun_dir_world)
    if sun is None:
        return np.ones(len(pts), np.float32)
    view = atlas.light_view(sun, shape)
    if view is None:  # pragma: no cover - sun_in_object already refused it
        return np.ones(len(pts), np.float32)
    return ground_visibility(view[0], view[1], pose, pts)
