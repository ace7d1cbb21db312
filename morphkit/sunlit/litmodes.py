"""Relit billboards: each billboard's surface for its viewing direction, shaded by the scene's lights.

A :class:`LitMode` draws a scene of relightable assets
(:class:`~morphkit.billboard.protocols.SurfaceSource`: :class:`~.domeasset.DomeAsset`,
:class:`~.impostor.OctahedralImpostor`) whose quads face the eye
(:class:`~.facing.ViewpointFacing`): per placement, the asset's unshaded surface for
the instance's viewing direction (azimuth and elevation in its object frame) comes
from a bounded LRU :class:`~.cache.MorphCache` keyed by the direction rounded to
``quantum_deg``, and is shaded with the mode's :class:`~morphkit.imaging.shading.Lighting`
turned into the instance's object frame (:meth:`~morphkit.imaging.shading.Lighting.in_frame`):
the lights can change every frame (a sun path) while the cached surfaces stay. Suns
below the horizon give no light (:meth:`~morphkit.imaging.shading.Lighting.above_horizon`).

Which surface is a family of objects (:class:`SurfaceChoice`):

* :class:`MorphSurface` -- ``asset.surface`` (the dome's per-pixel view morph of three
  views; the impostor's own three-frame blend with parallax);
* :class:`NearestSurface`, :class:`CrossfadeSurface`, :class:`ClassicSurface` -- the
  dome asset's baselines (one view on its card, three blended on their cards, the
  front view everywhere).

The ground truth under the same lights is :class:`~.litmesh.LitMeshMode` (the same
shading of the meshes' own passes, :mod:`morphkit.imaging.shading`).

**Depth.** Every surface carries its depth, so the billboards are composited pixel by
pixel against each other (:mod:`.compositor`, "Depth"): overlapping instances hide each
other where their surfaces are, not where their pivots' order says.

**Shadows.** With a ``shadow`` (:class:`~morphkit.sunlit.receivers.SceneShadow`: the
assets' sun atlases, or the ray cast), each billboard pixel's sun terms are multiplied by
the sun's visibility at the pixel's world point (from its surface's depth) and the ground
is darkened by the light its shadows take (:mod:`.shadowing`).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ..billboard.baking.bakelook import BAKE_AMBIENT, bake_lights
from ..billboard.domeasset import DomeAsset
from ..billboard.frames.cache import MorphCache
from ..billboard.frames.compositor import draw, entangled, finish, new_depth, new_layer, surface_depth
from ..billboard.frames.facing import ViewpointFacing
from ..billboard.frames.field import BillboardScene
from ..billboard.frames.frametypes import Frame, FrameStats, Placement
from ..billboard.protocols import SurfaceSource
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..imaging.shading import (
    Lighting,
    encode_premultiplied,
    shade,
    shade_suns,
    sun_terms,
)
from ..scene import PointLight
from ..views.gbuffer import ViewSurface
from .receivers import FrameShadow, SceneShadow
from .shadowing import frame_shadow, shadowed_backdrop, surface_visibility

__all__ = ["Relit", "SurfaceChoice", "MorphSurface", "NearestSurface", "CrossfadeSurface", "ClassicSurface",
           "LitMode", "pack_surface", "unpack_surface"]


@runtime_checkable
class Relit(Protocol):
    """A frame mode lit by a :class:`~morphkit.imaging.shading.Lighting` that can change between
    frames (:class:`LitMode`, :class:`~.litmesh.LitMeshMode`).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str
    lighting: Lighting

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """One frame under :attr:`lighting`.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
            The frame.
        """
        ...


@runtime_checkable
class SurfaceChoice(Protocol):
    """Which unshaded surface of an asset a :class:`LitMode` draws for a direction.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str

    def surface(self, asset: SurfaceSource, azimuth_deg: float, elevation_deg: float,
                level: int) -> ViewSurface:
        """The surface of ``asset`` for a direction at ``level``.

        Parameters
        ----------
        asset : SurfaceSource
            The instance's asset.
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame.
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        ...


def _dome(asset: SurfaceSource, what: str) -> DomeAsset:
    if not isinstance(asset, DomeAsset):
        raise ValidationError(expected_got(f"asset {asset.name!r} for the {what} surface",
                                           "a DomeAsset (its views)", type(asset).__name__))
    return asset


@dataclass(frozen=True)
class MorphSurface:
    """``asset.surface``: the asset's own image for the direction (see the module docstring).

    Parameters
    ----------
    name : str
        The mode name it gives (e.g. ``"impostor"`` for an impostor asset).
    """

    name: str = "morph"

    def surface(self, asset: SurfaceSource, azimuth_deg: float, elevation_deg: float,
                level: int) -> ViewSurface:
        """See :class:`SurfaceChoice`.

        Parameters
        ----------
        asset : SurfaceSource
            The asset.
        azimuth_deg, elevation_deg : float
            Direction, degrees.
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        return asset.surface(azimuth_deg, elevation_deg, level)


@dataclass(frozen=True)
class NearestSurface:
    """The dome's nearest view on its card (:meth:`DomeAsset.nearest_surface`).

    Parameters
    ----------
    name : str
        The mode name it gives.
    """

    name: str = "nearest"

    def surface(self, asset: SurfaceSource, azimuth_deg: float, elevation_deg: float,
                level: int) -> ViewSurface:
        """See :class:`SurfaceChoice`.

        Parameters
        ----------
        asset : SurfaceSource
            A :class:`DomeAsset`.
        azimuth_deg, elevation_deg : float
            Direction, degrees.
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        return _dome(asset, self.name).nearest_surface(azimuth_deg, elevation_deg, level)


@dataclass(frozen=True)
class CrossfadeSurface:
    """The dome's three views on their cards, blended (:meth:`DomeAsset.crossfade_surface`).

    Parameters
    ----------
    name : str
        The mode name it gives.
    """

    name: str = "crossfade"

    def surface(self, asset: SurfaceSource, azimuth_deg: float, elevation_deg: float,
                level: int) -> ViewSurface:
        """See :class:`SurfaceChoice`.

        Parameters
        ----------
        asset : SurfaceSource
            A :class:`DomeAsset`.
        azimuth_deg, elevation_deg : float
            Direction, degrees.
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        return _dome(asset, self.name).crossfade_surface(azimuth_deg, elevation_deg, level)


@dataclass(frozen=True)
class ClassicSurface:
    """The dome's front view for every direction (:meth:`DomeAsset.classic_surface`).

    Parameters
    ----------
    name : str
        The mode name it gives.
    """

    name: str = "classic"

    def surface(self, asset: SurfaceSource, azimuth_deg: float, elevation_deg: float,
                level: int) -> ViewSurface:
        """See :class:`SurfaceChoice`.

        Parameters
        ----------
        asset : SurfaceSource
            A :class:`DomeAsset`.
        azimuth_deg, elevation_deg : float
            Direction, degrees (not used).
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        return _dome(asset, self.name).classic_surface(level)


def pack_surface(surface: ViewSurface) -> np.ndarray:
    """One ``(h, w, 8)`` float32 array of a surface (albedo, normal, depth), for the cache.

    Parameters
    ----------
    surface : ViewSurface
        The surface.

    Returns
    -------
    (h, w, 8) float32
        Channels: albedo RGBA, normal xyz, depth.
    """
    return np.concatenate([surface.albedo, surface.normal, surface.depth[..., None]], axis=2)


def unpack_surface(packed: np.ndarray) -> ViewSurface:
    """The surface of :func:`pack_surface` (views of ``packed``).

    Parameters
    ----------
    packed : (h, w, 8) float32
        A packed surface.

    Returns
    -------
    ViewSurface
        Views into ``packed``.
    """
    return ViewSurface(packed[..., :4], packed[..., 4:7], packed[..., 7])


class LitMode:
    """Relit billboards of relightable assets (module docstring).

    Parameters
    ----------
    choice : SurfaceChoice
        Which surface (default :class:`MorphSurface`).
    lighting : Lighting, optional
        World-frame lights; replace the ``lighting`` attribute between frames to move them. Default:
        the bake's light and ambient (:func:`~.bakelook.bake_lights`).
    cache : MorphCache, optional
        Default ``MorphCache()``.
    quantum_deg : float
        Directions are rounded to this grid (degrees of azimuth and of elevation) for the
        cache; 0: exact directions, one entry each.
    name : str, optional
        The mode's name (default: the choice's).
    shadow : SceneShadow, optional
        What shadows the frame's suns (module docstring, "Shadows"); default none.
    """

    def __init__(self, choice: SurfaceChoice | None = None, lighting: Lighting | None = None, *,
                 cache: MorphCache | None = None, quantum_deg: float = 1.0, name: str | None = None,
                 shadow: SceneShadow | None = None) -> None:
        self.choice = MorphSurface() if choice is None else choice
        if not isinstance(self.choice, SurfaceChoice):
            raise ValidationError(expected_got("choice", "a SurfaceChoice", type(choice).__name__))
        self.lighting = Lighting(BAKE_AMBIENT, tuple(bake_lights())) if lighting is None else lighting
        if not isinstance(self.lighting, Lighting):
            raise ValidationError(expected_got("lighting", "a morphkit.imaging.shading.Lighting",
                                               type(lighting).__name__))
        self._cache = MorphCache() if cache is None else cache
        if not isinstance(self._cache, MorphCache):
            raise ValidationError(expected_got("cache", "a MorphCache", type(cache).__name__))
        q = float(quantum_deg)
        if not np.isfinite(q) or q < 0:
            raise ValidationError(expected_got("quantum_deg", "a finite number >= 0", quantum_deg))
        self.quantum_deg = q
        self.name = self.choice.name if name is None else str(name)
        if shadow is not None and not isinstance(shadow, SceneShadow):
            raise ValidationError(expected_got("shadow", "a morphkit.sunlit.receivers.SceneShadow",
                                               type(shadow).__name__))
        self.shadow = shadow

    @property
    def cache(self) -> MorphCache:
        """The surface cache."""
        return self._cache

    def direction(self, pl: Placement) -> tuple[float, float]:
        """The direction ``pl`` is drawn from: its azimuth and elevation rounded to
        ``quantum_deg`` (the cache's key), the elevation at most 90 degrees.

        Parameters
        ----------
        pl : Placement
            A placement.

        Returns
        -------
        azimuth_deg, elevation_deg : float
        """
        a, e = pl.azimuth_deg, pl.elevation_deg
        q = self.quantum_deg
        if q > 0:
            a = (round(a / q) * q + 180.0) % 360.0 - 180.0
            e = round(e / q) * q
        return a, min(e, 90.0)

    def surface(self, asset: SurfaceSource, pl: Placement) -> ViewSurface:
        """The (cached) unshaded surface of one placement.

        Parameters
        ----------
        asset : SurfaceSource
            The instance's asset.
        pl : Placement
            Its placement.

        Returns
        -------
        ViewSurface
            Read-only views of the cached surface.
        """
        a, e = self.direction(pl)
        key = (self.name, asset.name, a, e, pl.level)
        packed = self._cache.get(key, lambda: pack_surface(self.choice.surface(asset, a, e, pl.level)))
        return unpack_surface(packed)

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """Plan, shade every placement's surface, draw back to front over the backdrop.

        Parameters
        ----------
        scene : BillboardScene
            A scene of relightable assets with :class:`~.facing.ViewpointFacing`.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
            The frame.

        Raises
        ------
        ValidationError
            A scene whose facing is not :class:`ViewpointFacing`, an asset that is not a
            :class:`SurfaceSource`.
        """
        t0 = time.perf_counter()
        if not isinstance(scene.facing, ViewpointFacing):
            raise ValidationError(expected_got("scene facing for relit billboards",
                                               "ViewpointFacing (quads facing the eye in elevation too)",
                                               type(scene.facing).__name__))
        before = self._cache.counts
        plan = scene.plan(camera)
        layer, zbuf = new_layer(camera.shape), new_depth(camera.shape)
        lit = self.lighting.above_horizon()
        ground = None if self.shadow is None else frame_shadow(
            self.shadow, scene, camera, lit, np.array([pl.index for pl in plan.placements], np.int64))
        fs = None if ground is None else ground.shadow
        self.draw_placements(scene, camera, plan.placements, layer, zbuf, fs)
        back = (scene.backdrop.draw(camera) if ground is None
                else shadowed_backdrop(scene, camera, lit, ground, layer[:, :, 3]))
        rgb = finish(layer, back)
        counts = self._cache.counts - before
        stats = FrameStats(self.name, plan.n_instances, len(plan.placements), plan.n_frustum_culled,
                           plan.n_behind, plan.n_offscreen, plan.n_small, plan.n_near_clipped, plan.n_above,
                           counts.hits, counts.misses, counts.evictions, len(self._cache), self._cache.nbytes,
                           0.0, 1e3 * (time.perf_counter() - t0))
        return Frame(rgb, layer, plan.placements, stats)

    def draw_placements(self, scene: BillboardScene, camera: CameraModel, placements: Sequence[Placement],
                        layer: np.ndarray, zbuf: np.ndarray, sun_shadow: FrameShadow | None = None) -> None:
        """Shade and composite ``placements`` (back to front) into ``layer``, depth-tested against
        ``zbuf`` where a billboard meets another or a pixel ``zbuf`` already holds (what was drawn
        before: e.g. real meshes, :mod:`morphkit.plan.mixed`).

        Parameters
        ----------
        scene : BillboardScene
            The scene (facing checked by :meth:`render`).
        camera : CameraModel
            The frame's camera.
        placements : sequence of Placement
            Back to front (a frame plan's order).
        layer : (H, W, 4) float32
            Premultiplied layer, updated in place.
        zbuf : (H, W) float32
            The frame's depth buffer (:func:`~morphkit.billboard.frames.compositor.new_depth`),
            updated in place.
        sun_shadow : FrameShadow, optional
            The frame's shadow of the sun (the ``shadow`` of the ground
            :func:`~.shadowing.frame_shadow` gives), or None.

        Raises
        ------
        ValidationError
            An asset that is not a :class:`SurfaceSource`.
        """
        # each image is shaded in linear light and encoded before it is fogged and composited:
        # the backdrop's one fog model (backdrop.Fog.blend), as for the ground and the meshes
        fog = scene.backdrop.fog
        fog_color = (0.0, 0.0, 0.0) if fog is None else fog.color
        lit = self.lighting.above_horizon()
        points_lit = any(isinstance(lt, PointLight) for lt in lit.lights)
        ambient, terms = sun_terms(lit)
        inst = scene.instances
        fs = sun_shadow
        checked: set[str] = set()
        radii = [scene.assets[pl.asset].half_extent[0] * inst.scale[pl.index] for pl in placements]
        by_depth = entangled(placements, np.array(radii))
        if np.isfinite(zbuf).any():  # something drawn before: every billboard meeting it is tested too
            for n, pl in enumerate(placements):
                r0, r1, c0, c1 = pl.roi
                by_depth[n] |= bool(np.isfinite(zbuf[r0:r1, c0:c1]).any())
        for pl, deep in zip(placements, by_depth, strict=True):
            asset = scene.assets[pl.asset]
            if pl.asset not in checked:
                if not isinstance(asset, SurfaceSource):
                    raise ValidationError(expected_got(f"asset {pl.asset!r}", "a SurfaceSource (relightable)",
                                                       type(asset).__name__))
                checked.add(pl.asset)
            surf = self.surface(asset, pl)
            needs_view = deep or fs is not None or points_lit
            view = asset.camera(*self.direction(pl), pl.level) if needs_view else None
            pose = inst.object2world(pl.index)
            vis = None if fs is None else surface_visibility(fs, surf, view, pose)
            if points_lit:  # point lights: the general model, at the surface's points
                local = lit.in_frame(np.linalg.inv(pose))
                points = view.unproject(surf.depth)[0]
                image = shade(surf, local, points, vis)  # encoded
            else:  # suns: their rows turned into the instance's frame by its yaw (rows times Rz)
                yaw = np.radians(inst.yaw_deg[pl.index])
                c, s_ = np.cos(yaw), np.sin(yaw)
                rz = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]], np.float32)
                image = encode_premultiplied(shade_suns(surf, ambient, terms @ rz, vis))
            if deep:
                z = surface_depth(view, surf.depth, pose, camera)
                draw(layer, pl, image, fog_color, zbuf=zbuf, depth=z)
            else:
                draw(layer, pl, image, fog_color)

