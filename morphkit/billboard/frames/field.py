"""A billboard scene: assets, instances and a backdrop; per frame, what to draw where.

:class:`BillboardScene` holds the assets (anything implementing
:class:`morphkit.billboard.protocols.Placeable`: ring assets and relightable ones), the
:class:`~.instances.Instances`,
the :class:`~.backdrop.Backdrop`, the :class:`~.facing.Facing` rule and the
smallest on-screen size worth drawing. :meth:`BillboardScene.plan` decides, for
one camera, which billboards are drawn and how -- "model only what a scene
needs" -- in five stages (:mod:`~morphkit.billboard.frames.planner`, one function each): frustum
**culling**, **facing** and viewing azimuth, **level of detail** from the
on-screen size, screen box and near-plane **clipping**, **back-to-front** order;
it adds the fog factor at each pivot's distance.

A :class:`~.frametypes.Placement` per drawn billboard comes out; a mode
(:mod:`~.modes`) picks each one's image and the compositor
(:mod:`~.compositor`) draws it. :meth:`BillboardScene.render` runs one frame
in a mode and returns a :class:`~.frametypes.Frame` with its :class:`~.frametypes.FrameStats`.
What a mode is, :class:`FrameMode`, is declared here next to the scene it draws:
the modes import the scene, the scene never imports the modes.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from ...camera import CameraModel
from ...errors import ValidationError, expected_got
from ...validate import as_positive
from ..protocols import Placeable
from .backdrop import Backdrop
from .facing import AxialFacing, Facing
from .frametypes import Frame, FramePlan, Placement
from .frustum import require_perspective
from .instances import Instances
from .planner import ScreenQuad, back_to_front, clip, cull, face, level_of_detail

__all__ = ["FrameMode", "BillboardScene"]


@runtime_checkable
class FrameMode(Protocol):
    """Draws a :class:`BillboardScene` for a camera (the modes of :mod:`~.modes`).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """One frame: its image, its billboard layer, its placements and stats.

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


@dataclass(eq=False)
class BillboardScene:
    """Assets, instances and a backdrop, with the rules that decide what a frame draws.

    Parameters
    ----------
    assets : mapping of str to Placeable
        Every asset named by ``instances.names``.
    instances : Instances
    backdrop : Backdrop
        Ground, sky and optional fog.
    facing : Facing
        :class:`~.facing.AxialFacing` (default, the paper's) or
        :class:`~.facing.ScreenFacing`.
    min_pixels : float
        Billboards under this on-screen height (pixels) are skipped.

    Raises
    ------
    ValidationError
        An instance names an asset that is missing, an asset does not implement
        :class:`~morphkit.billboard.protocols.Placeable`, a facing is not a
        :class:`~.facing.Facing`.
    """

    assets: Mapping[str, Placeable]
    instances: Instances
    backdrop: Backdrop = field(default_factory=Backdrop)
    facing: Facing = field(default_factory=AxialFacing)
    min_pixels: float = 2.0
    _pivots: np.ndarray = field(init=False, repr=False)
    _half: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.instances, Instances):
            raise ValidationError(expected_got("instances", "an Instances", type(self.instances).__name__))
        missing = [nm for nm in self.instances.names if nm not in self.assets]
        if missing:
            raise ValidationError(expected_got("assets", f"one for every instance's asset {missing}",
                                               f"only {sorted(self.assets)}"))
        for nm, a in self.assets.items():
            if not isinstance(a, Placeable):
                raise ValidationError(expected_got(
                    f"asset {nm!r}", "a billboard asset (morphkit.billboard.protocols.Placeable: "
                    "BillboardSource or SurfaceSource)", type(a).__name__))
        if not isinstance(self.facing, Facing):
            raise ValidationError(expected_got(
                "facing", "a Facing (AxialFacing, ScreenFacing or ViewpointFacing)",
                type(self.facing).__name__))
        self.min_pixels = as_positive(self.min_pixels, "min_pixels")
        used = [self.assets[nm] for nm in self.instances.names]
        self._pivots = self.instances.pivots([a.pivot for a in used])
        half = np.array([a.half_extent for a in used], dtype=np.float64).reshape(-1, 2)
        self._half = half[self.instances.asset] * self.instances.scale[:, None]

    def __len__(self) -> int:
        return len(self.instances)

    @property
    def pivots(self) -> np.ndarray:
        """World positions ``(N, 3)`` of the instances' quad centres."""
        return self._pivots

    def plan(self, camera: CameraModel) -> FramePlan:
        """Which billboards ``camera`` sees, how, and in what order (see the module notes).

        Parameters
        ----------
        camera : CameraModel
            A perspective camera.

        Returns
        -------
        FramePlan
        """
        require_perspective(camera)
        inst = self.instances
        n = len(inst)
        w2c = camera.world2cam
        vis, z = cull(camera, w2c, self._pivots, self._half)
        if len(vis) == 0:
            return FramePlan([], vis, n, n, 0, 0, 0, 0, 0)
        piv, hw, hh = self._pivots[vis], self._half[vis, 0], self._half[vis, 1]
        views, right, up = face(camera, self.facing, piv, inst.yaw_deg[vis])
        names, a_vis = inst.names, inst.asset[vis]
        h0 = np.array([self.assets[nm].size[0] for nm in names])[a_vis]
        nlev = np.array([self.assets[nm].levels for nm in names])[a_vis]
        height, keep, level = level_of_detail(camera, hh, z, self.min_pixels, h0, nlev)
        H_unit, quads = clip(camera, w2c, piv, right, up, hw, hh, keep)
        dist = np.linalg.norm(piv - camera.position, axis=1)
        fog = (self.backdrop.fog.factor(dist) if self.backdrop.fog is not None else np.zeros(len(vis)))
        skipped = {"behind": 0, "offscreen": 0, "small": len(vis) - len(keep)}
        placements: list[Placement] = []
        for m, k in enumerate(keep):
            q = quads[m]
            if not isinstance(q, ScreenQuad):
                skipped[q] += 1
                continue
            placements.append(Placement(int(vis[k]), names[int(a_vis[k])], float(views.azimuth_deg[k]),
                                        float(views.elevation_deg[k]), bool(views.above[k]), float(z[k]),
                                        float(dist[k]), float(height[k]), int(level[k]), H_unit[m], q.roi,
                                        q.clip_px, float(fog[k])))
        n_clipped = sum(p.clip_px is not None for p in placements)
        n_above = int(np.count_nonzero(views.above))
        return FramePlan(back_to_front(placements), vis, n, n - len(vis), skipped["behind"],
                         skipped["offscreen"], skipped["small"], n_clipped, n_above)

    def render(self, camera: CameraModel, mode: FrameMode) -> Frame:
        """One frame of this scene seen by ``camera`` in ``mode`` (see :mod:`~.modes`).

        Parameters
        ----------
        camera : CameraModel
            Perspective view, world frame.
        mode : FrameMode
            How to draw the instances.

        Returns
        -------
        Frame
            The frame.
        """
        return mode.render(self, camera)

    def render_path(self, cameras: Iterable[CameraModel], mode: FrameMode, *,
                    progress: bool = False, total: int | None = None) -> Iterator[Frame]:
        """The frames of a camera path, one at a time (a tqdm bar with ``progress``).

        Parameters
        ----------
        cameras : iterable of CameraModel
            Perspective views, world frame.
        mode : FrameMode
            How to draw the instances.
        progress : bool, optional
            Show a tqdm progress bar.
        total : int, optional
            Number of cameras, for the bar when ``cameras`` has no length.

        Yields
        ------
        Frame
            One frame per camera, in order.
        """
        it: Iterable[CameraModel] = cameras
        if progress:
            from tqdm import tqdm

            # on a terminal only (as every progress bar of morphkit's): a log or a pipe gets none
            it = tqdm(cameras, total=total, desc=f"billboards ({mode.name})", unit="frame", disable=None,
                      leave=False)
        for cam in it:
            yield mode.render(self, cam)
