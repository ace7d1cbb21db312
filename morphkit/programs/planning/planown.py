"""The chosen plan drawn on frames of its own (:func:`plan_offset`): its offsets, measured less
predicted, frame by frame along the path (:class:`PlanCalibration`), and how far those frames fall
short of the budget (:func:`shortfall`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

from ... import tol
from ...billboard.compare import PSNR_CAP_DB
from ...plan import Budget
from ...plan.calibration import Calibration, calibration_offsets, path_offsets
from ...plan.errortable import ErrorTable
from ...plan.planfile import ScenePlan
from ...plan.planner import predict_frames, reached, sample_scene
from ..scenerender import PreparedScene
from .planverify import verify_frames

__all__ = ["PlanCalibration", "less_margin", "plan_offset", "shortfall"]


class PlanCalibration(NamedTuple):
    """The chosen plan drawn on frames of its own (:func:`plan_offset`).

    Parameters
    ----------
    offset : Calibration
        The median offset, measured less predicted, over the frames
        (:func:`~morphkit.plan.calibration.calibration_offsets`).
    frames : list of int
        The frames' indices on the path.
    predicted, measured : list of dict
        Each frame's figures (``billboard-psnr``, ``billboard-iou``; None: nothing drawn), predicted
        and as drawn with the plan.
    time_ms : tuple of float, optional
        Each frame's drawing time with the plan (milliseconds; the truth's not counted).
    """

    offset: Calibration
    frames: list[int]
    predicted: list[dict[str, float | None]]
    measured: list[dict[str, float | None]]
    time_ms: tuple[float, ...] = ()

    def at(self, frames: Sequence[int]) -> list[tuple[float, float]]:
        """The offsets of ``frames``, from the plan's frames around each along the path.

        Parameters
        ----------
        frames : sequence of int
            Indices on the path.

        Returns
        -------
        list of (float, float)
            ``(dB, IoU)`` per frame (:func:`~morphkit.plan.calibration.path_offsets`).
        """
        return path_offsets(self.frames, self.predicted, self.measured, frames)

    def along(self, predicted: Sequence[Mapping[str, float | None]], frames: Sequence[int]
              ) -> list[dict[str, float | None]]:
        """The plan's figures on ``frames`` along the path: a frame it was drawn on, as measured; any
        other, as ``predicted`` moved by its offset (:meth:`at`; a frame predicted at the PSNR cap
        keeps its PSNR: nothing wrong predicted, and the offsets were taken without such frames).

        Parameters
        ----------
        predicted : sequence of mapping
            Each frame's predicted figures (``billboard-psnr``, ``billboard-iou``).
        frames : sequence of int
            Their indices on the path.

        Returns
        -------
        list of dict
            Each frame's figures, the IoU clipped to ``[0, 1]`` and the PSNR to the cap.
        """
        drawn = dict(zip(self.frames, self.measured, strict=True))
        out: list[dict[str, float | None]] = []
        for k, f, (d, q) in zip(frames, predicted, self.at(frames), strict=True):
            db, iou = f.get("billboard-psnr"), f.get("billboard-iou")
            if k in drawn:
                out.append(dict(drawn[k]))
                continue
            moved = db if db is None or db >= PSNR_CAP_DB else min(db + d, PSNR_CAP_DB)
            out.append({"billboard-psnr": moved,
                        "billboard-iou": None if iou is None else float(np.clip(iou + q, 0.0, 1.0))})
        return out

    def to_json(self) -> dict[str, Any]:
        """``plan.json``'s ``calibration.plan``: the median offset and the frames' figures.

        Returns
        -------
        dict
        """
        o = self.offset
        return {"db": o.db, "iou": o.iou, "frames_used": o.frames, "frames": self.frames,
                "predicted": self.predicted, "measured": self.measured}


def plan_offset(
    prep: PreparedScene,
    cameras: Sequence[Any],
    frames: Sequence[int],
    plan: ScenePlan,
    tables: Mapping[tuple[str, str], ErrorTable],
    offsets: Mapping[Any, tuple[float, float]],
    truths: dict[int, Any],
) -> PlanCalibration:
    """The chosen plan's own offsets, measured less predicted, on its calibration ``frames`` drawn
    with it: the representations were calibrated each everywhere, and a frame mixing them is not the
    sum of those (a card's box among exact meshes holds fewer errors than among cards). Its median
    (:func:`~morphkit.plan.calibration.calibration_offsets`) is reported; the held-out frames'
    predictions are moved by the calibration frames' around each
    (:func:`~morphkit.plan.calibration.path_offsets`).

    Parameters
    ----------
    prep : PreparedScene
        The scene, its truth and its lights.
    cameras : sequence of CameraModel
        The path's frames.
    frames : sequence of int
        The frames the plan is drawn on.
    plan : ScenePlan
        The plan.
    tables : mapping of (asset, representation) to ErrorTable
        The error tables.
    offsets : mapping
        The representations' calibrated offsets (:meth:`~morphkit.plan.planner.FramePredictions.shifted`).
    truths : dict
        The truth's frames by index, drawn once (read where there, kept where not).

    Returns
    -------
    PlanCalibration
    """
    sample = sample_scene(prep.scene)
    mode = plan.mode(prep.relit, prep.base, prep.shadow, prep.meshes())
    got = verify_frames(prep, cameras, frames, {"plan": mode}, sample, truths=truths)
    pred = predict_frames(tables, sample, [cameras[k] for k in frames]).shifted(offsets)
    p, m = pred.frame_errors(pred.pick_of(plan.choice)), got["plan"]["errors"]
    return PlanCalibration(calibration_offsets(p, m), [int(k) for k in frames], p, list(m),
                           tuple(got["plan"]["time_ms"]))


def shortfall(budget: Budget, measured: Sequence[Mapping[str, float | None]]) -> tuple[float, float]:
    """How far, in dB and in IoU, the figures ``budget.frames`` of the ``measured`` frames reach fall
    short of the budget (zero where they meet it), at least the planner's margins where they do not.

    Parameters
    ----------
    budget : Budget
        The budget.
    measured : sequence of mapping
        The frames' figures.

    Returns
    -------
    db, iou : float
    """
    got = reached(budget, measured)
    out = [0.0, 0.0]
    keys = (("billboard-psnr", tol.PLAN_MARGIN_DB), ("billboard-iou", tol.PLAN_MARGIN_IOU))
    for i, (key, unit) in enumerate(keys):
        want, have = getattr(budget, key.replace("-", "_")), got.get(key)
        if want is not None and have is not None and have < want:
            out[i] = max(float(want - have), unit)
    return out[0], out[1]


def less_margin(
    figures: Sequence[Mapping[str, float | None]],
    margin: tuple[float, float] = (tol.PLAN_MARGIN_DB, tol.PLAN_MARGIN_IOU),
) -> list[dict[str, float | None]]:
    """``figures`` less ``margin``: what a budget is held to where its figures are measured on a few
    frames or predicted between them (a frame next to one measured just within it is not).

    Parameters
    ----------
    figures : sequence of mapping
        Each frame's figures (``billboard-psnr``, ``billboard-iou``; None: nothing drawn).
    margin : (float, float), optional
        dB and IoU taken off (default: the tolerance's, :data:`morphkit.tol.PLAN_MARGIN_DB` and
        :data:`morphkit.tol.PLAN_MARGIN_IOU`).

    Returns
    -------
    list of dict

    Examples
    --------
    >>> less_margin([{"billboard-psnr": 20.0, "billboard-iou": None}], (0.5, 0.01))
    [{'billboard-psnr': 19.5, 'billboard-iou': None}]
    """
    off = {"billboard-psnr": margin[0], "billboard-iou": margin[1]}
    return [{k: None if v is None else v - off.get(k, 0.0) for k, v in f.items()} for f in figures]
