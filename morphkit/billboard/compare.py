"""Comparing the modes of one scene: per-billboard errors against the real meshes, side-by-side strips.

:func:`box_errors` measures a billboard frame against the mesh frame of the
same camera, billboard by billboard over each one's screen box: silhouette IoU
(coverage alpha > 0.5) and PSNR of the final RGB (data range 255). Both frames
are composited over the same backdrop, so the comparison is like with like.
:func:`compare_modes` renders one camera in several modes and the mesh mode and
returns the frames, a side-by-side strip (the paper's Fig. 5: classic |
view-morphed | real meshes) and the mean errors per mode.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..camera import CameraModel
from ..imaging.metrics import psnr, shadow_iou
from .frames.field import BillboardScene, FrameMode
from .frames.frametypes import Frame

__all__ = ["box_errors", "mean_errors", "frame_errors", "Comparison", "compare_modes", "PSNR_CAP_DB"]

#: PSNR of identical boxes is infinite; it is reported as this (JSON has no inf).
PSNR_CAP_DB = 100.0


def box_errors(frame: Frame, truth: Frame) -> list[dict[str, Any]]:
    """Per drawn billboard of ``frame``: silhouette IoU and PSNR over its screen box against ``truth``.

    Parameters
    ----------
    frame, truth : Frame
        The same scene and camera in a billboard mode and in the mesh mode.

    Returns
    -------
    list of dict
        One per placement of ``frame``: ``index`` (instance), ``azimuth_deg``,
        ``iou`` (alpha > 0.5 inside the box), ``psnr`` (final RGB inside the box,
        data range 255, at most :data:`PSNR_CAP_DB`).
    """
    out = []
    for pl in frame.placements:
        r0, r1, c0, c1 = pl.roi
        a = frame.layer[r0:r1, c0:c1, 3] > 0.5
        b = truth.layer[r0:r1, c0:c1, 3] > 0.5
        p = psnr(frame.rgb[r0:r1, c0:c1].astype(np.float64), truth.rgb[r0:r1, c0:c1].astype(np.float64),
                 data_range=255.0)
        out.append({"index": pl.index, "azimuth_deg": pl.azimuth_deg, "iou": shadow_iou(a, b),
                    "psnr": min(p, PSNR_CAP_DB)})
    return out


def mean_errors(errors: list[dict[str, Any]]) -> dict[str, float]:
    """Mean ``iou`` and ``psnr`` of :func:`box_errors` records and their count ``n``
    (``nan`` means when there are none).

    Parameters
    ----------
    errors : list of dict
        Records of :func:`box_errors`.

    Returns
    -------
    dict of str to float
        ``iou``, ``psnr`` (means) and ``n`` (the count).
    """
    if not errors:
        return {"iou": float("nan"), "psnr": float("nan"), "n": 0.0}
    return {"iou": float(np.mean([e["iou"] for e in errors])),
            "psnr": float(np.mean([e["psnr"] for e in errors])), "n": float(len(errors))}


def frame_errors(frame: Frame, truth: Frame) -> dict[str, float]:
    """The frame's billboards against ``truth`` as one: PSNR of the final RGB (data range 255, at
    most :data:`PSNR_CAP_DB`) and silhouette IoU (alpha > 0.5) over the pixels of the union of the
    drawn billboards' screen boxes, so each billboard counts by the pixels it shows (a billboard cut
    by the frame's edge by its part inside, overlapping ones once).

    Parameters
    ----------
    frame, truth : Frame
        The same scene and camera in a billboard mode and in the mesh mode.

    Returns
    -------
    dict of str to float
        ``psnr``, ``iou``, ``n`` (billboards drawn) and ``pixels`` (of the union); ``nan`` figures
        when nothing is drawn.

    Examples
    --------
    One billboard's box, wrong in a quarter of its pixels by 255 (an MSE of 255^2 / 4: 6.02 dB):

    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from morphkit.billboard.compare import frame_errors
    >>> pl = SimpleNamespace(roi=(0, 2, 0, 2))
    >>> rgb = np.zeros((4, 4, 3), np.uint8); layer = np.zeros((4, 4, 4), np.float32); layer[:2, :2, 3] = 1
    >>> got = rgb.copy(); got[0, 0] = 255
    >>> e = frame_errors(SimpleNamespace(rgb=got, layer=layer, placements=[pl]),
    ...                  SimpleNamespace(rgb=rgb, layer=layer, placements=[]))
    >>> round(e["psnr"], 2), e["iou"], e["pixels"]
    (6.02, 1.0, 4.0)
    """
    n = len(frame.placements)
    if n == 0:
        return {"psnr": float("nan"), "iou": float("nan"), "n": 0.0, "pixels": 0.0}
    mask = np.zeros(frame.rgb.shape[:2], bool)
    for pl in frame.placements:
        r0, r1, c0, c1 = pl.roi
        mask[r0:r1, c0:c1] = True
    a = frame.layer[..., 3][mask] > 0.5
    b = truth.layer[..., 3][mask] > 0.5
    p = psnr(frame.rgb[mask].astype(np.float64), truth.rgb[mask].astype(np.float64), data_range=255.0)
    return {"psnr": float(min(p, PSNR_CAP_DB)), "iou": float(shadow_iou(a, b)), "n": float(n),
            "pixels": float(np.count_nonzero(mask))}


@dataclass(frozen=True, eq=False)
class Comparison:
    """One camera of a scene in several modes.

    Parameters
    ----------
    frames : dict of str to Frame
        Each mode's frame, and ``"mesh"``'s.
    strip : (H, k W, 3) uint8
        The frames side by side, RGB, in the order the modes were given, mesh last.
    errors : dict of str to dict
        Per billboard mode, :func:`mean_errors` of its :func:`box_errors` against the mesh frame.
    """

    frames: dict[str, Frame]
    strip: np.ndarray
    errors: dict[str, dict[str, float]]


def compare_modes(scene: BillboardScene, camera: CameraModel, modes: Mapping[str, FrameMode],
                  truth: FrameMode) -> Comparison:
    """Render ``camera`` in each of ``modes`` and in ``truth`` (the mesh mode); see :class:`Comparison`.

    Parameters
    ----------
    scene : BillboardScene
        The scene.
    camera : CameraModel
        Perspective view, world frame.
    modes : mapping of str to FrameMode
        Billboard modes by label.
    truth : FrameMode
        The mesh mode (reference).

    Returns
    -------
    Comparison
        Frames, strip and errors.
    """
    frames = {name: scene.render(camera, m) for name, m in modes.items()}
    frames["mesh"] = scene.render(camera, truth)
    errors = {name: mean_errors(box_errors(frames[name], frames["mesh"])) for name in modes}
    return Comparison(frames, np.concatenate([f.rgb for f in frames.values()], axis=1), errors)
