"""A frame's error predicted from error tables, before it is drawn.

:func:`instance_views` says, for every instance of a :class:`~morphkit.billboard.BillboardScene` and one
camera, how it is seen: its on-screen height (:func:`~morphkit.billboard.frames.lod.screen_height_px`,
``2 fy half_height / Z`` with the pivot's camera depth ``Z``), its viewing elevation (the angle of the
eye above the pivot's horizontal plane, :func:`~morphkit.billboard.frames.facing.view_directions`: the
pivot is the quad's centre, so an eye at the instance's mid height sees it at elevation 0) and whether
the frame draws it -- the scene's own plan (:meth:`~morphkit.billboard.BillboardScene.plan`: frustum
culling, the ``min_pixels`` floor, near-plane and off-screen quads), so exactly the billboards that
:func:`~morphkit.billboard.compare.box_errors` measures.

:func:`predict_frame_error` looks each drawn billboard up in its asset's table
(:meth:`~.errortable.ErrorTable.lookup`) and aggregates as :func:`~morphkit.billboard.compare.mean_errors`
does: the plain mean over the drawn billboards (each one counts once, whatever its size), ``n`` their
count, NaN means when none is drawn.

What a table cannot know: each of its cells is one billboard, whole and alone in its frame. In a
scene, a billboard cut by the frame's edge is measured over the part of its box the frame shows
(down to background alone, at the PSNR cap), and one overlapped by others over a box they
share; both are predicted as if whole and alone.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..billboard import BillboardScene
from ..billboard.frames.facing import view_directions
from ..billboard.frames.lod import screen_height_px
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from .errortable import ErrorTable

__all__ = ["instance_views", "predict_frame_error"]


def instance_views(scene: BillboardScene, camera: CameraModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How ``camera`` sees each instance of ``scene`` (see the module notes).

    Parameters
    ----------
    scene : BillboardScene
        The scene.
    camera : CameraModel
        A perspective camera.

    Returns
    -------
    height_px : (N,) float64
        On-screen height of each instance's quad, pixels (``inf`` at or before the near plane,
        negative depth included).
    elevation_deg : (N,) float64
        Elevation of the eye above each pivot's horizon, degrees (90 straight above).
    visible : (N,) bool
        The frame draws the instance's billboard (the scene's plan places it).

    Notes
    -----
    A quad ``2 h`` high whose pivot lies straight ahead at distance ``d`` (depth ``Z = d``) is
    ``2 fy h / d`` pixels high; seen from an eye at the pivot's height, at elevation 0.
    """
    n = len(scene)
    if n == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, bool)
    inst = scene.instances
    half_h = np.array([scene.assets[nm].half_extent[1] for nm in inst.names], np.float64)[inst.asset]
    half_h = half_h * inst.scale
    piv = scene.pivots
    z = piv @ camera.world2cam[2, :3] + camera.world2cam[2, 3]
    height = screen_height_px(camera.fy, half_h, z, camera.znear)
    elevation = view_directions(camera.position, piv, inst.yaw_deg).elevation_deg
    visible = np.zeros(n, bool)
    visible[[pl.index for pl in scene.plan(camera).placements]] = True
    return height, np.asarray(elevation, np.float64), visible


def predict_frame_error(tables: Mapping[str, ErrorTable], scene: BillboardScene,
                        camera: CameraModel) -> dict[str, float]:
    """The frame's mean per-billboard error predicted from each asset's table.

    Parameters
    ----------
    tables : mapping of str to ErrorTable
        One table per asset name of the scene's drawn instances (the representation the frame
        draws that asset with).
    scene : BillboardScene
        The scene.
    camera : CameraModel
        A perspective camera.

    Returns
    -------
    dict of str to float
        ``psnr`` (dB) and ``iou``: the means over the drawn billboards of their tables' lookups at
        their height and elevation; ``n``: how many (as :func:`~morphkit.billboard.compare.mean_errors`:
        NaN means and ``n = 0`` when none is drawn).

    Raises
    ------
    ValidationError
        A drawn instance's asset has no table.
    """
    height, elevation, visible = instance_views(scene, camera)
    idx = np.flatnonzero(visible)
    if len(idx) == 0:
        return {"iou": float("nan"), "psnr": float("nan"), "n": 0.0}
    names = scene.instances.names
    kinds = scene.instances.asset[idx]
    missing = sorted({names[k] for k in kinds} - set(tables))
    if missing:
        raise ValidationError(expected_got("tables", f"an ErrorTable for every drawn asset {missing}",
                                           f"tables of {sorted(tables)}"))
    psnr = np.empty(len(idx))
    iou = np.empty(len(idx))
    for k in np.unique(kinds):
        sel = kinds == k
        p, q = tables[names[k]].lookup(height[idx[sel]], elevation[idx[sel]])
        psnr[sel], iou[sel] = p, q
    out: dict[str, Any] = {"iou": float(np.mean(iou)), "psnr": float(np.mean(psnr)), "n": float(len(idx))}
    return out
