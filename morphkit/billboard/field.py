"""A billboard scene: assets, instances and a backdrop; per frame, what to draw where.

:class:`BillboardScene` holds the assets (anything implementing
:class:`morphkit.billboard.protocols.BillboardSource`), the :class:`~.instances.Instances`,
the :class:`~.backdrop.Backdrop`, the :class:`~.facing.Facing` rule and the
smallest on-screen size worth drawing. :meth:`BillboardScene.plan` decides, for
one camera, which billboards are drawn and how -- "model only what a scene
needs":

1. **frustum culling** of every instance's bounding sphere (one numpy pass over
   ``N``; billboards behind the camera or outside the view are skipped);
2. **facing** and the **viewing azimuth** of the survivors
   (:mod:`~.facing`; the directly-above fallback is documented there);
3. **size**: billboards under ``min_pixels`` of on-screen height, or whose quad
   covers under :data:`morphkit.tol.BB_MIN_AREA_PX2` of screen area (an axial quad
   seen edge-on, e.g. from directly above), are skipped; the others get a
   pyramid **level** from their on-screen height (:mod:`~.lod`);
4. the quad's screen homography, and **near-plane clipping**: a quad cut by
   the near plane is drawn only inside its clipped polygon (:mod:`~.frustum`);
5. **back-to-front order** by camera depth of the pivot, and the fog factor at
   the pivot's distance.

A :class:`~.frame.Placement` per drawn billboard comes out; a mode
(:mod:`~.modes`) picks each one's image and the compositor
(:mod:`~.compositor`) draws it. :meth:`BillboardScene.render` runs one frame
in a mode and returns a :class:`~.frame.Frame` with its :class:`~.frame.FrameStats`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..validate import as_positive
from .backdrop import Backdrop
from .facing import AxialFacing, Facing, view_directions
from .frame import Frame, FramePlan, Placement
from .frustum import clip_near, quad_homographies, require_perspective, screen_box, sphere_in_frustum
from .instances import Instances
from .lod import screen_height_px, select_levels
from .protocols import BillboardSource

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
    assets : mapping of str to BillboardSource
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
        :class:`~morphkit.billboard.protocols.BillboardSource`, a facing is not a
        :class:`~.facing.Facing`.
    """

    assets: Mapping[str, BillboardSource]
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
            if not isinstance(a, BillboardSource):
                raise ValidationError(expected_got(f"asset {nm!r}",
                                                   "a BillboardSource (morphkit.billboard.protocols)",
                                                   type(a).__name__))
        if not isinstance(self.facing, Facing):
            raise ValidationError(expected_got("facing", "a Facing (AxialFacing or ScreenFacing)",
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
        eye = camera.position
        radii = np.hypot(self._half[:, 0], self._half[:, 1])
        inside, z_all = sphere_in_frustum(camera, w2c, self._pivots, radii)
        vis = np.flatnonzero(inside)
        counts = {"behind": 0, "offscreen": 0, "small": 0, "clipped": 0}
        if len(vis) == 0:
            return FramePlan([], vis, n, n, 0, 0, 0, 0, 0)
        piv, z = self._pivots[vis], z_all[vis]
        views = view_directions(eye, piv, inst.yaw_deg[vis])
        right, up = self.facing.axes(camera, views)
        hw, hh = self._half[vis, 0], self._half[vis, 1]
        height = screen_height_px(camera.fy, hh, z, camera.znear)
        big = height >= self.min_pixels
        counts["small"] = int(np.count_nonzero(~big))
        keep = np.flatnonzero(big)
        tl = piv - hw[:, None] * right + hh[:, None] * up
        corners = np.stack([tl, tl + 2 * hw[:, None] * right, piv + hw[:, None] * right - hh[:, None] * up,
                            piv - hw[:, None] * right - hh[:, None] * up], axis=1)[keep]  # TL TR BR BL
        cam = corners @ w2c[:3, :3].T + w2c[:3, 3]
        H_unit = quad_homographies(camera, w2c, tl[keep], right[keep], up[keep], hw[keep], hh[keep])
        dist = np.linalg.norm(piv - eye, axis=1)
        fog = (self.backdrop.fog.factor(dist) if self.backdrop.fog is not None else np.zeros(len(vis)))
        names = inst.names
        a_vis = inst.asset[vis]
        h0 = np.array([self.assets[nm].size[0] for nm in names])[a_vis]
        nlev = np.array([self.assets[nm].levels for nm in names])[a_vis]
        level = select_levels(height, h0, nlev)
        K = camera.K
        hgt, wid = camera.shape
        front = np.all(cam[:, :, 2] >= camera.znear, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):  # rows cut by the near plane are redone below
            px_all = cam[:, :, :2] / cam[:, :, 2:3] * (K[0, 0], K[1, 1]) + (K[0, 2], K[1, 2])
        lo = np.floor(np.where(front[:, None], px_all.min(axis=1), 0.0))
        hi = np.ceil(np.where(front[:, None], px_all.max(axis=1), 0.0)) + 1
        x, y = px_all[:, :, 0], px_all[:, :, 1]
        area = 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))
        boxes = np.stack([np.maximum(lo[:, 1], 0), np.minimum(hi[:, 1], hgt),
                          np.maximum(lo[:, 0], 0), np.minimum(hi[:, 0], wid)], axis=1).astype(np.int64)
        placements: list[Placement] = []
        for m, k in enumerate(keep):
            clip = None
            if front[m]:
                if area[m] < tol.BB_MIN_AREA_PX2:
                    counts["small"] += 1
                    continue
                r0, r1, c0, c1 = boxes[m].tolist()
                if r1 <= r0 or c1 <= c0:
                    counts["offscreen"] += 1
                    continue
                roi = (r0, r1, c0, c1)
            else:
                poly = clip_near(cam[m], camera.znear)
                if len(poly) < 3:
                    counts["behind"] += 1
                    continue
                clip = (poly[:, :2] / poly[:, 2:3]) * (K[0, 0], K[1, 1]) + (K[0, 2], K[1, 2])
                if cv2.contourArea(clip.astype(np.float32)) < tol.BB_MIN_AREA_PX2:
                    counts["small"] += 1
                    continue
                box = screen_box(clip, camera.shape)
                if box is None:
                    counts["offscreen"] += 1
                    continue
                roi = box
                counts["clipped"] += 1
            placements.append(Placement(int(vis[k]), names[int(a_vis[k])], float(views.azimuth_deg[k]),
                                        float(views.elevation_deg[k]), bool(views.above[k]), float(z[k]),
                                        float(dist[k]), float(height[k]), int(level[k]), H_unit[m], roi,
                                        clip, float(fog[k])))
        placements.sort(key=lambda p: -p.depth)
        drawn_above = int(np.count_nonzero(views.above))
        return FramePlan(placements, vis, n, n - len(vis), counts["behind"], counts["offscreen"],
                         counts["small"], counts["clipped"], drawn_above)

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

            it = tqdm(cameras, total=total, desc=f"billboards ({mode.name})",
                      unit="frame")
        for cam in it:
            yield mode.render(self, cam)
