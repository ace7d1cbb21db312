"""The stages of a billboard frame's plan, one function each.

:meth:`~.field.BillboardScene.plan` runs them in this order for one camera
(every stage works on arrays over the instances the stage before kept):

1. :func:`cull` -- frustum culling of every instance's bounding sphere (one
   numpy pass over ``N``; billboards behind the camera or outside the view go);
2. :func:`face` -- the **viewing direction** of the survivors and the quad's
   axes by the scene's :class:`~.facing.Facing` rule (the directly-above
   fallback is documented in :mod:`~.facing`);
3. :func:`level_of_detail` -- the on-screen height; billboards under the
   scene's ``min_pixels`` go, the others get a pyramid **level** (:mod:`~morphkit.billboard.frames.lod`);
4. :func:`clip` -- each quad's screen homography, screen box and **near-plane
   clipping**: a quad cut by the near plane is drawn only inside its clipped
   polygon (:mod:`~.frustum`); a quad covering under
   :data:`morphkit.tol.BB_MIN_AREA_PX2` of screen (an axial quad seen edge-on),
   missing the image, or wholly behind the near plane goes, with its reason;
5. :func:`back_to_front` -- the drawing order, by camera depth of the pivot.

The scene puts the stages' results together into :class:`~.frametypes.Placement`\\ s
(with the fog factor at each pivot's distance) and counts what each stage left
out (:class:`~.frametypes.FramePlan`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import cv2
import numpy as np

from ... import tol
from ...camera import CameraModel
from .facing import Facing, ViewDirections, view_directions
from .frametypes import Placement
from .frustum import clip_near, quad_homographies, screen_box, sphere_in_frustum
from .lod import screen_height_px, select_levels

__all__ = ["Skip", "ScreenQuad", "cull", "face", "level_of_detail", "clip", "back_to_front"]

#: Why :func:`clip` left a quad out: under the area floor, off the image, behind the near plane.
Skip = Literal["small", "offscreen", "behind"]


@dataclass(frozen=True, eq=False)
class ScreenQuad:
    """Where one quad is drawn on screen.

    Parameters
    ----------
    roi : (r0, r1, c0, c1)
        Screen box of the (clipped) quad, inside the image.
    clip_px : (K, 2) float64 or None
        The quad's screen polygon after near-plane clipping; None when the quad
        lies wholly in front of the near plane.
    """

    roi: tuple[int, int, int, int]
    clip_px: np.ndarray | None


def cull(camera: CameraModel, world2cam: np.ndarray, pivots: np.ndarray,
         half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stage 1: the instances whose bounding sphere meets the view frustum.

    Parameters
    ----------
    camera : CameraModel
        A perspective camera.
    world2cam : (4, 4) float64
        ``camera.world2cam``.
    pivots : (N, 3) float64
        Quad centres, world frame.
    half : (N, 2) float64
        Quads' half width and half height, scene units (the sphere's radius is
        their hypotenuse).

    Returns
    -------
    visible : (M,) int64
        Indices of the instances kept.
    depth : (M,) float64
        Camera depth ``Z`` of their pivots.
    """
    radii = np.hypot(half[:, 0], half[:, 1])
    inside, z_all = sphere_in_frustum(camera, world2cam, pivots, radii)
    visible = np.flatnonzero(inside)
    return visible, z_all[visible]


def face(camera: CameraModel, facing: Facing, pivots: np.ndarray,
         yaw_deg: np.ndarray) -> tuple[ViewDirections, np.ndarray, np.ndarray]:
    """Stage 2: how each instance is seen, and its quad's axes.

    Parameters
    ----------
    camera : CameraModel
        The camera (its eye position).
    facing : Facing
        The scene's facing rule.
    pivots : (M, 3) float64
        Quad centres, world frame.
    yaw_deg : (M,) float64
        Instance yaws, degrees.

    Returns
    -------
    views : ViewDirections
        Viewing azimuth, elevation and the directly-above flag per instance.
    right, up : (M, 3) float64
        The quads' unit axes, world frame.
    """
    views = view_directions(camera.position, pivots, yaw_deg)
    right, up = facing.axes(camera, views)
    return views, right, up


def level_of_detail(camera: CameraModel, half_h: np.ndarray, depth: np.ndarray, min_pixels: float,
                    base_height: np.ndarray, levels: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stage 3: on-screen heights, the billboards big enough to draw, their pyramid levels.

    Parameters
    ----------
    camera : CameraModel
        A perspective camera.
    half_h : (M,) float64
        Quads' half heights, scene units.
    depth : (M,) float64
        Camera depth of the pivots.
    min_pixels : float
        Billboards under this on-screen height (pixels) are left out.
    base_height : (M,) int
        Level-0 image height of each instance's asset.
    levels : (M,) int
        Pyramid levels of each instance's asset.

    Returns
    -------
    height_px : (M,) float64
        On-screen height (``inf`` at the near plane).
    keep : (K,) int64
        Indices (into the ``M``) of the billboards at least ``min_pixels`` high.
    level : (M,) int
        Pyramid level of each.
    """
    height = screen_height_px(camera.fy, half_h, depth, camera.znear)
    keep = np.flatnonzero(height >= min_pixels)
    return height, keep, select_levels(height, base_height, levels)


def clip(camera: CameraModel, world2cam: np.ndarray, pivots: np.ndarray, right: np.ndarray, up: np.ndarray,
         half_w: np.ndarray, half_h: np.ndarray, keep: np.ndarray
         ) -> tuple[np.ndarray, list[ScreenQuad | Skip]]:
    """Stage 4: the screen homography and screen box of the quads ``keep``, clipped by the near plane.

    Parameters
    ----------
    camera : CameraModel
        A perspective camera.
    world2cam : (4, 4) float64
        ``camera.world2cam``.
    pivots : (M, 3) float64
        Quad centres, world frame.
    right, up : (M, 3) float64
        The quads' unit axes (:func:`face`).
    half_w, half_h : (M,) float64
        Quads' half width and half height.
    keep : (K,) int64
        The quads to place (:func:`level_of_detail`).

    Returns
    -------
    H_screen_unit : (K, 3, 3) float64
        Each kept quad's unit square to screen pixels.
    quads : list of ScreenQuad or Skip
        Per kept quad, where it is drawn, or why it is not.
    """
    piv, hw, hh = pivots, half_w, half_h
    tl = piv - hw[:, None] * right + hh[:, None] * up
    corners = np.stack([tl, tl + 2 * hw[:, None] * right, piv + hw[:, None] * right - hh[:, None] * up,
                        piv - hw[:, None] * right - hh[:, None] * up], axis=1)[keep]  # TL TR BR BL
    cam = corners @ world2cam[:3, :3].T + world2cam[:3, 3]
    H_unit = quad_homographies(camera, world2cam, tl[keep], right[keep], up[keep], hw[keep], hh[keep])
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
    quads: list[ScreenQuad | Skip] = []
    for m in range(len(keep)):
        if front[m]:
            if area[m] < tol.BB_MIN_AREA_PX2:
                quads.append("small")
                continue
            r0, r1, c0, c1 = boxes[m].tolist()
            if r1 <= r0 or c1 <= c0:
                quads.append("offscreen")
                continue
            quads.append(ScreenQuad((r0, r1, c0, c1), None))
        else:
            poly = clip_near(cam[m], camera.znear)
            if len(poly) < 3:
                quads.append("behind")
                continue
            clip_px = (poly[:, :2] / poly[:, 2:3]) * (K[0, 0], K[1, 1]) + (K[0, 2], K[1, 2])
            if cv2.contourArea(clip_px.astype(np.float32)) < tol.BB_MIN_AREA_PX2:
                quads.append("small")
                continue
            box = screen_box(clip_px, camera.shape)
            if box is None:
                quads.append("offscreen")
                continue
            quads.append(ScreenQuad(box, clip_px))
    return H_unit, quads


def back_to_front(placements: list[Placement]) -> list[Placement]:
    """Stage 5: the drawing order, farthest pivot (camera depth) first; ties keep their order.

    Parameters
    ----------
    placements : list of Placement
        The billboards to draw.

    Returns
    -------
    list of Placement
        The same, back to front.
    """
    return sorted(placements, key=lambda p: -p.depth)
