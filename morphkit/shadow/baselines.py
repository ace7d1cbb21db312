"""Baselines for warped shadow maps, with the same ``shadow_map`` API.

* :class:`DirectShadow` (``direct``): re-render the light depth map at the exact
  position every frame (through :mod:`morphkit.render`). No precomputed data.
* :class:`ImageBasedShadow` (``ibr_nearest`` / ``ibr_blend``): the image-based
  method of Kang & Ihm's ref. [4] (Lee & Ihm 2001): a dense ``k x k`` grid of
  pre-rendered maps over the range (32 x 32 by default), taking the nearest
  map, or blending the 4 neighbours with bilinear weights (no warping).

All methods share the :class:`~morphkit.shadow.rig.LightRig`, so they differ
only in what they store and how they produce a map. For fairness the image-based
maps get the same exact depth model as the warp (depths shifted with the
object's anchor), so their error is purely that of their shapes.

The image-based method: Lee & Ihm [1]_; shadow mapping: Williams [2]_.

References
----------
.. [1] J. Lee and I. Ihm, "Real-Time Shadow Generation using Image-Based Wavelet Techniques"
   (in Korean; title translated), Journal of the Korea Computer Graphics Society, 7(1),
   pp. 27-35, 2001; reference 4 of Kang & Ihm.
.. [2] L. Williams, "Casting Curved Shadows on Curved Surfaces", Computer Graphics (Proc. SIGGRAPH 78),
   12(3), pp. 270-274, 1978.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
import trimesh

from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..meshes import check_mesh
from ..protocols import SceneRenderer
from ..scene import Item
from .atlas import ShadowAtlas, bake_atlas
from .method import bilinear_weights
from .planes import add_planes, planes_to_depth
from .rig import LightRig

__all__ = ["DirectShadow", "ImageBasedShadow"]


class DirectShadow:
    """Re-render the light depth map at the exact position (``direct``).

    Parameters
    ----------
    rig : morphkit.shadow.rig.LightRig
        Light, object and motion range.
    mesh : trimesh.Trimesh
        The occluder, object frame.
    renderer : morphkit.render.Renderer
        Renders the depth maps.
    """

    name = "direct"
    memory_bytes = 0

    def __init__(self, rig: LightRig, mesh: trimesh.Trimesh, renderer: SceneRenderer) -> None:
        self.rig, self.mesh, self.renderer = rig, check_mesh(mesh, "mesh"), renderer

    def shadow_map(self, xy: Any, *, light_offset: Any = None, clamp: bool = False
                   ) -> tuple[np.ndarray, CameraModel]:
        """See :meth:`ShadowMethod.shadow_map <morphkit.shadow.method.ShadowMethod.shadow_map>`.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane.
        clamp : bool
            Clamp ``xy`` into the motion range instead of refusing it.

        Returns
        -------
        depth : (H, W) float32
            Light-view linear depth, ``+inf`` background.
        camera : morphkit.camera.CameraModel
            The light camera of ``depth``.
        """
        _eq, pos, cam = self.rig.resolve(xy, light_offset, clamp=clamp)
        return self.renderer.depth(cam, [Item(self.mesh, self.rig.object_pose(pos))]), cam


class ImageBasedShadow:
    """A dense grid of pre-rendered maps: nearest map, or a 4-neighbour blend.

    Parameters
    ----------
    atlas : morphkit.shadow.atlas.ShadowAtlas
        A dense atlas of plane-anchored maps (:meth:`bake`).
    mode : {"nearest", "blend"}
        Nearest sample's map, or the bilinear blend of the cell's four.
    """

    def __init__(self, atlas: ShadowAtlas, mode: Literal["nearest", "blend"] = "nearest") -> None:
        if mode not in ("nearest", "blend"):
            raise ValidationError(expected_got("mode", "'nearest' or 'blend'", repr(mode)))
        self.atlas, self.mode = atlas, mode
        self.name = f"ibr_{mode}"

    @classmethod
    def bake(cls, mesh: trimesh.Trimesh, base_pose: np.ndarray, motion: Any, light: Any,
             shape: tuple[int, int], *, renderer: SceneRenderer, grid: int = 32,
             mode: Literal["nearest", "blend"] = "nearest", progress: bool = True
             ) -> ImageBasedShadow:
        """Render a uniform ``grid x grid`` set of maps (even spacing, ends included).

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The occluder, object frame.
        base_pose : (4, 4) float
            ``object2world`` at translation ``(0, 0)``.
        motion : morphkit.shadow.rig.MotionRange
            The ground translations covered (world units).
        light : DirectionalLight or PointLight
            The light.
        shape : (H, W)
            Size of each map.
        renderer : morphkit.render.Renderer
            Renders the maps.
        grid : int
            Samples per axis.
        mode : {"nearest", "blend"}
            As in the constructor.
        progress : bool
            Show a progress bar on a terminal.

        Returns
        -------
        ImageBasedShadow
            The baseline.
        """
        atlas = bake_atlas(mesh, base_pose, motion, light, shape, renderer=renderer,
                           grid=(grid, grid), anchors="plane", control_grid=(2, 2),
                           uniform=True, progress=progress)
        return cls(atlas, mode)

    @property
    def rig(self) -> LightRig:
        """The grid's light rig."""
        return self.atlas.rig

    @property
    def memory_bytes(self) -> int:
        """Bytes of the stored maps."""
        return int(self.atlas.maps.nbytes)

    def shadow_map(self, xy: Any, *, light_offset: Any = None, clamp: bool = False
                   ) -> tuple[np.ndarray, CameraModel]:
        """See :meth:`ShadowMethod.shadow_map <morphkit.shadow.method.ShadowMethod.shadow_map>`.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane.
        clamp : bool
            Clamp ``xy`` into the motion range instead of refusing it.

        Returns
        -------
        depth : (H, W) float32
            Light-view linear depth, ``+inf`` background.
        camera : morphkit.camera.CameraModel
            The light camera of ``depth``.
        """
        a, rt = self.atlas.baked, self.atlas.runtime
        eq, _pos, cam = a.rig.resolve(xy, light_offset, clamp=clamp)
        j, i, v, u = a.cell(eq)
        if self.mode == "nearest":
            jj, ii = j + int(v > 0.5), i + int(u > 0.5)
            acc = rt.source_planes(jj, ii).copy()
        else:
            acc = np.zeros((2, *a.shape), np.float32)
            for (jj, ii), w in bilinear_weights(j, i, v, u):
                if w > 0:
                    add_planes(acc, ((0, a.shape[0], 0, a.shape[1]), rt.source_planes(jj, ii)), w)
        return planes_to_depth(acc, rt.anchor_depth(eq)), cam
