"""Calibrating a plan's error tables to a scene: each representation's offsets between the tables'
prediction and the scene's measure (:func:`calibration_offsets` over frames, :func:`band_offsets`
band by band) and its cost (:func:`frame_cost`), from frames drawn in it everywhere; and a plan's
own offsets frame by frame along the path (:func:`path_offsets`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from .. import tol
from ..billboard.compare import PSNR_CAP_DB
from .planner import FramePredictions
from .representations import Band
from .shadowchoice import interpolate_frames

__all__ = ["Calibration", "calibration_offsets", "frame_cost", "band_offsets", "path_offsets"]


class Calibration(NamedTuple):
    """One representation's calibration to a scene (:func:`calibration_offsets`).

    Parameters
    ----------
    db, iou : float
        The offsets, measured less predicted: the medians over the frames.
    frames : int
        Frames used.
    spread_db, spread_iou : float
        How far the worst frame's measure fell short of its prediction moved by the offset (zero when
        none did): what the offset leaves unexplained on the side that matters to a budget.
    """

    db: float
    iou: float
    frames: int
    spread_db: float
    spread_iou: float


def calibration_offsets(
    predicted: Sequence[Mapping[str, float | None]], measured: Sequence[Mapping[str, float | None]]
) -> Calibration:
    """One representation's calibration: the median over frames drawn in it everywhere of measured
    less predicted. Adding a constant to every billboard's PSNR moves the frame's by that constant,
    and to every IoU the frame's too, so the median is the constant that best closes the gap; frames
    measured at the PSNR cap (nothing wrong to measure) or without billboards are left out (a frame
    predicted at the cap and measured below it is not: e.g. the real mesh's, whose table is exact and
    whose frames are not, their shadows being the frame's own).

    Parameters
    ----------
    predicted, measured : sequence of mapping
        The same frames' figures (:meth:`FramePredictions.frame_errors` and as measured).

    Returns
    -------
    Calibration
        All zero when no frame serves.

    Examples
    --------
    >>> from morphkit.plan.calibration import calibration_offsets
    >>> p = [{"billboard-psnr": 26.0, "billboard-iou": 0.90}, {"billboard-psnr": 30.0, "billboard-iou": 0.95},
    ...      {"billboard-psnr": 28.0, "billboard-iou": 0.90}]
    >>> m = [{"billboard-psnr": 24.0, "billboard-iou": 0.88}, {"billboard-psnr": 100.0, "billboard-iou": 1.0},
    ...      {"billboard-psnr": 27.0, "billboard-iou": 0.90}]
    >>> c = calibration_offsets(p, m)
    >>> c.db, c.frames, c.spread_db, round(c.iou, 3)
    (-1.5, 2, 0.5, -0.01)
    """
    db, iou = [], []
    for p, m in zip(predicted, measured, strict=True):
        mp, pp = m.get("billboard-psnr"), p.get("billboard-psnr")
        if mp is None or pp is None or mp >= PSNR_CAP_DB:
            continue
        db.append(mp - pp)
        iou.append(m["billboard-iou"] - p["billboard-iou"])  # type: ignore[operator]
    if not db:
        return Calibration(0.0, 0.0, 0, 0.0, 0.0)
    d, q = float(np.median(db)), float(np.median(iou))
    return Calibration(d, q, len(db), max(0.0, d - float(np.min(db))), max(0.0, q - float(np.min(iou))))


def path_offsets(
    frames: Sequence[int],
    predicted: Sequence[Mapping[str, float | None]],
    measured: Sequence[Mapping[str, float | None]],
    at: Sequence[int],
) -> list[tuple[float, float]]:
    """Each frame of ``at``'s offset, measured less predicted, from the calibration ``frames`` around
    it along the path (:func:`~.shadowchoice.interpolate_frames`: linear in the frame's index between
    the two nearest, the nearest's beyond them). The frames of a path change slowly, and what one
    offset for all of them leaves unexplained -- the shadows a frame's boxes hold, the billboards
    that overlap -- changes with them. The frames serving are those :func:`calibration_offsets` takes
    (below the PSNR cap, with billboards).

    Parameters
    ----------
    frames : sequence of int
        The calibration frames' indices on the path.
    predicted, measured : sequence of mapping
        Those frames' figures (as :func:`calibration_offsets`).
    at : sequence of int
        The frames whose offsets are wanted.

    Returns
    -------
    list of (float, float)
        ``(dB, IoU)`` per frame of ``at``; ``(0, 0)`` when no calibration frame serves.

    Examples
    --------
    >>> from morphkit.plan.calibration import path_offsets
    >>> p = [{"billboard-psnr": 26.0, "billboard-iou": 0.90}, {"billboard-psnr": 30.0, "billboard-iou": 0.90}]
    >>> m = [{"billboard-psnr": 24.0, "billboard-iou": 0.88}, {"billboard-psnr": 29.0, "billboard-iou": 0.92}]
    >>> [(round(d, 2), round(q, 3)) for d, q in path_offsets([0, 10], p, m, [0, 5, 20])]
    [(-2.0, -0.02), (-1.5, 0.0), (-1.0, 0.02)]
    """
    db: list[float | None] = []
    iou: list[float | None] = []
    for p, m in zip(predicted, measured, strict=True):
        mp, pp = m.get("billboard-psnr"), p.get("billboard-psnr")
        serves = mp is not None and pp is not None and mp < PSNR_CAP_DB
        db.append(float(mp) - float(pp) if serves else None)  # type: ignore[arg-type]
        iou.append(float(m["billboard-iou"]) - float(p["billboard-iou"]) if serves else None)  # type: ignore[arg-type]
    d = interpolate_frames(frames, db, at)
    q = interpolate_frames(frames, iou, at)
    return [(a or 0.0, b or 0.0) for a, b in zip(d, q, strict=True)]


def frame_cost(billboards: Sequence[int], times_ms: Sequence[float], fallback: float) -> tuple[float, float]:
    """A representation's cost from frames drawn in it everywhere: ``(per frame, per billboard)``,
    milliseconds, the least-squares line of the frames' times over their billboards (each part at
    least 0). Frames whose billboards hardly vary (a spread under a tenth of their mean) cannot
    tell the two apart: all of it is then per billboard (the median of time over billboards).

    Parameters
    ----------
    billboards : sequence of int
        Each frame's billboards drawn.
    times_ms : sequence of float
        Each frame's time.
    fallback : float
        The cost per billboard when no frame drew one.

    Returns
    -------
    per_frame, per_billboard : float

    Examples
    --------
    >>> from morphkit.plan.calibration import frame_cost
    >>> frame_cost([10, 20, 40], [70.0, 120.0, 220.0], 1.0)  # 20 ms a frame, 5 a billboard
    (20.0, 5.0)
    >>> frame_cost([10, 10], [70.0, 72.0], 1.0)  # no spread: all of it per billboard
    (0.0, 7.1)
    """
    n = np.asarray(billboards, np.float64)
    t = np.asarray(times_ms, np.float64)
    drawn = n > 0
    if not drawn.any():
        return 0.0, float(fallback)
    if len(n) < 3 or n.std() < 0.1 * n.mean():
        return 0.0, float(np.median(t[drawn] / n[drawn]))
    slope, intercept = np.polyfit(n, t, 1)
    if slope <= 0:  # no cost per billboard seen: all of it per frame
        return float(t.mean()), 0.0
    if intercept < 0:  # no cost per frame: all of it per billboard, through the origin
        return 0.0, float(np.sum(n * t) / np.sum(n * n))
    return round(float(intercept), 9), round(float(slope), 9)


def band_offsets(
    pred: FramePredictions, representation: str, measured: Sequence[Sequence[Mapping[str, float]] | None]
) -> dict[tuple[str, Band], tuple[float, float]]:
    """One representation's offsets per band: the median over the band's billboards, in frames drawn
    in it everywhere, of each billboard's measured box figures less its table's (what the table of one
    billboard alone does not know of the scene, band by band: a card that holds at eye level and
    fails from above is corrected apart in each). A band of fewer than
    :data:`morphkit.tol.PLAN_MIN_BAND_BILLBOARDS` measured billboards gets none (the representation's
    offset over the frames serves it); billboards measured at the PSNR cap (nothing wrong to measure)
    are left out of the PSNR's.

    Parameters
    ----------
    pred : FramePredictions
        The frames' predictions (unshifted).
    representation : str
        The representation the frames were drawn in.
    measured : sequence of (sequence of mapping or None)
        Per frame of ``pred``, each drawn billboard's ``psnr`` and ``iou``
        (:func:`~morphkit.billboard.compare.box_errors`), in the frame's placement order; None for
        a frame not measured.

    Returns
    -------
    dict of (str, Band) to (float, float)
    """
    r = pred.representations.index(representation)
    db: dict[int, list[float]] = {}
    iou: dict[int, list[float]] = {}
    for b, p, q, m in zip(pred.band_index, pred.psnr_db, pred.iou, measured, strict=True):
        if m is None or len(m) != len(b):
            continue
        for i, e in enumerate(m):
            k = int(b[i])
            iou.setdefault(k, []).append(float(e["iou"]) - float(q[r, i]))
            if e["psnr"] < PSNR_CAP_DB:
                db.setdefault(k, []).append(float(e["psnr"]) - float(p[r, i]))
    out: dict[tuple[str, Band], tuple[float, float]] = {}
    for k, qs in iou.items():
        ds = db.get(k, [])
        if min(len(qs), len(ds)) >= tol.PLAN_MIN_BAND_BILLBOARDS:
            out[(representation, pred.bands[k])] = (float(np.median(ds)), float(np.median(qs)))
    return out
