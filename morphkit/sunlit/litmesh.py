"""The relit ground truth of a billboard scene: the real meshes shaded by the scene's lights.

:class:`LitMeshMode` is :class:`~.modes.MeshMode` with morphkit's shading instead of
the renderer's lighting: the meshes at every instance's pose are drawn as deferred
passes (albedo, world normals, depth, coverage: in one draw where the renderer is a
:class:`~morphkit.protocols.GBufferRenderer`, :meth:`Renderer.gbuffer_pass
<morphkit.render.Renderer.gbuffer_pass>`, else :meth:`Renderer.passes
<morphkit.render.Renderer.passes>`; ``source_passes`` when supersampled) and
shaded by :func:`morphkit.imaging.shading.shade_passes` under a world-frame
:class:`~morphkit.imaging.shading.Lighting` -- the one model (:mod:`morphkit.imaging.shading`) that
also shades the relit billboards, so the two compare like with like under any sun.
The layer is composited over the scene's backdrop as the billboards' is.
:attr:`LitMeshMode.lighting` may be replaced between frames (a moving sun,
:class:`~morphkit.sunpath.SunPath`).

**Shadows.** With a ``shadow`` (:class:`~morphkit.sunlit.receivers.SceneShadow`), the sun
terms of every mesh pixel are multiplied by the sun's visibility at its world point (the
depth pass unprojected through the frame's camera, the normal pass for the normal offset)
and the ground gets its shadows as in the billboard frames (:mod:`.shadowing`): with
:class:`~morphkit.sunlit.raycast.RayCastShadow` this is the truth of a shadowed billboard
frame.

Fog, when the scene has it, is applied per pixel from the depth pass's distance,
at every ``supersample`` (the passes always carry depth; at a supersampled edge
pixel the depth is its nearest sample's).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..billboard.frames.compositor import finish
from ..billboard.frames.field import BillboardScene
from ..billboard.frames.frametypes import Frame, FrameStats
from ..billboard.modes import MeshMode
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..imaging.shading import Lighting, shade_passes
from ..protocols import GBufferRenderer, PassRenderer
from ..scene import Item
from ..validate import as_flag, as_int
from .receivers import FrameShadow, SceneShadow
from .shadowing import frame_shadow, points_visibility, shadowed_backdrop

__all__ = ["LitMeshMode"]


@dataclass
class LitMeshMode:
    """The real meshes at every instance's pose, shaded by :func:`~morphkit.imaging.shading.shade_passes`
    (module docstring).

    Parameters
    ----------
    renderer : PassRenderer
        Draws the passes (:class:`morphkit.render.Renderer`).
    meshes : mapping of str to sequence of Item
        Per asset name, its items in the asset's look, as for :class:`~.modes.MeshMode`.
    lighting : Lighting
        World frame; replace it between frames to move the sun.
    supersample : int
        1: one sample a pixel (coverage 0 or 1, :meth:`~morphkit.protocols.GBufferRenderer.gbuffer_pass`
        or :meth:`~morphkit.protocols.PassRenderer.passes`: ``gbuffer``); ``s > 1``:
        supersampled passes (coverage alpha, :meth:`~morphkit.protocols.PassRenderer.source_passes`).
    cull : bool
        Draw only the instances whose bounding sphere meets the frustum; False draws all.
    name : str, optional
        The mode's name in frames, strips and reports.
    shadow : SceneShadow, optional
        What shadows the suns (module docstring, "Shadows"); default none.
    gbuffer : bool, optional
        At ``supersample`` 1, draw the passes in one draw where the renderer is a
        :class:`~morphkit.protocols.GBufferRenderer` (default); False: always
        :meth:`~morphkit.protocols.PassRenderer.passes` (three draws with
        :class:`morphkit.render.Renderer`, whose lit colour is not used).
    """

    renderer: PassRenderer
    meshes: Mapping[str, Sequence[Item]]
    lighting: Lighting
    supersample: int = 1
    cull: bool = True
    name: str = "litmesh"
    shadow: SceneShadow | None = None
    gbuffer: bool = True

    def __post_init__(self) -> None:
        if self.shadow is not None and not isinstance(self.shadow, SceneShadow):
            raise ValidationError(expected_got("shadow", "a morphkit.sunlit.receivers.SceneShadow",
                                               type(self.shadow).__name__))
        if not isinstance(self.renderer, PassRenderer):
            raise ValidationError(expected_got("renderer", "a renderer with passes and source_passes",
                                               type(self.renderer).__name__))
        self.supersample = as_int(self.supersample, "supersample", lo=1)
        self.cull = as_flag(self.cull, "cull")
        self.gbuffer = as_flag(self.gbuffer, "gbuffer")
        # the posing of MeshMode (and its checks of the items); its lights are never used
        self._posed = MeshMode(self.renderer, self.meshes, cull=self.cull)

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """Draw the passes, shade them under :attr:`lighting`, composite over the backdrop.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
            The frame; ``layer`` is the shaded meshes (premultiplied, sRGB-encoded colour).

        Raises
        ------
        ValidationError
            :attr:`lighting` is not a :class:`~morphkit.imaging.shading.Lighting`.
        """
        if not isinstance(self.lighting, Lighting):
            raise ValidationError(expected_got("lighting", "a morphkit.imaging.shading.Lighting",
                                               type(self.lighting).__name__))
        t0 = time.perf_counter()
        plan = scene.plan(camera)
        idx = plan.visible if self.cull else np.arange(len(scene))
        ground = None
        if self.shadow is not None:
            ground = frame_shadow(self.shadow, scene, camera, self.lighting, np.asarray(idx, np.int64))
        layer, _ = self.shaded_layer(scene, camera, idx, None if ground is None else ground.shadow)
        back = (scene.backdrop.draw(camera) if ground is None
                else shadowed_backdrop(scene, camera, self.lighting, ground, layer[:, :, 3]))
        rgb = finish(layer, back)
        stats = FrameStats(self.name, plan.n_instances, len(plan.placements), plan.n_frustum_culled,
                           plan.n_behind, plan.n_offscreen, plan.n_small, plan.n_near_clipped, plan.n_above,
                           ms=1e3 * (time.perf_counter() - t0))
        return Frame(rgb, layer, plan.placements, stats)

    def shaded_layer(self, scene: BillboardScene, camera: CameraModel, indices: np.ndarray,
                     sun_shadow: FrameShadow | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The meshes of instances ``indices`` drawn, shaded under :attr:`lighting` (the sun's
        visibility from ``sun_shadow`` at each pixel's point) and fogged: the layer :meth:`render`
        puts over the backdrop, and its depth.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.
        indices : (M,) int
            The instances drawn.
        sun_shadow : FrameShadow, optional
            The frame's shadow of the sun (the ``shadow`` of the ground
            :func:`~.shadowing.frame_shadow` gives); None: unshadowed.

        Returns
        -------
        layer : (H, W, 4) float32
            Premultiplied, sRGB-encoded colour.
        depth : (H, W) float32
            Camera depth ``Z``, ``+inf`` where no mesh is drawn.
        """
        items = self._posed.items(scene, np.asarray(indices, np.int64))
        if self.supersample == 1 and self.gbuffer and isinstance(self.renderer, GBufferRenderer):
            passes = self.renderer.gbuffer_pass(camera, items)
        elif self.supersample == 1:
            passes = self.renderer.passes(camera, items, ())
        else:
            passes = self.renderer.source_passes(camera, items, (), supersample=self.supersample)
        vis = None
        if sun_shadow is not None:
            points, valid = camera.unproject(passes.depth)
            vis = points_visibility(sun_shadow, points, np.asarray(passes.normal, np.float64),
                                    valid & (np.asarray(passes.alpha) > 0))
        layer = shade_passes(passes, self.lighting, camera, vis)
        fog = scene.backdrop.fog
        if fog is not None:
            fog.blend_layer(layer, passes.depth, camera)
        return layer, np.asarray(passes.depth, np.float32)
