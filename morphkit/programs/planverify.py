"""A plan's frames drawn and measured: each frame in several modes and in the truth, the modes'
order turned each frame (so none is always first to warm the caches), timed in the same run, and
each frame's figures of a budget against the truth's frame (:mod:`morphkit.programs.planrun`).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

from ..billboard import BillboardScene
from ..billboard.compare import box_errors, frame_errors
from ..sunlit.litmodes import Relit
from .scenerender import PreparedScene

__all__ = ["frame_figures", "verify_frames"]


def frame_figures(frame: Any, truth: Any) -> dict[str, float | None]:
    """A frame's ``billboard-psnr`` and ``billboard-iou`` against the truth's frame (None: no
    billboard drawn): :func:`~morphkit.billboard.compare.frame_errors` over the billboards' boxes."""
    m = frame_errors(frame, truth)
    if not m["n"]:
        return {"billboard-psnr": None, "billboard-iou": None}
    return {"billboard-psnr": float(m["psnr"]), "billboard-iou": float(m["iou"])}


def verify_frames(
    prep: PreparedScene,
    cameras: Sequence[Any],
    picks: Sequence[int],
    modes: Mapping[str, Any],
    scene: BillboardScene | None = None,
    boxes: bool = False,
    truths: dict[int, Any] | None = None,
) -> dict[str, dict[str, list[Any]]]:
    """Each held-out frame drawn in every mode (the order turned each frame, so none is always first
    to warm the caches) and in the truth; each mode's figures and times per frame. ``scene``: the
    instances drawn (default the prepared scene's); ``boxes``: each frame's billboards' own figures too
    (``"boxes"``, :func:`~morphkit.billboard.compare.box_errors`); ``truths``: the truth's frames by
    frame index, drawn once (read where there, kept where not)."""
    scene = prep.scene if scene is None else scene
    out: dict[str, dict[str, list[Any]]] = {nm: {"errors": [], "time_ms": [], "boxes": []} for nm in modes}
    order = list(modes)
    for n, k in enumerate(picks):
        cam = cameras[k]
        if prep.lighting is not None:
            for m in (*modes.values(), prep.truth):
                if isinstance(m, Relit):
                    m.lighting = prep.lighting[k]
        truth = truths.get(k) if truths is not None else None
        if truth is None:
            truth = scene.render(cam, prep.truth)
            if truths is not None:
                truths[k] = truth
        turn = order[n % len(order) :] + order[: n % len(order)]
        for nm in turn:
            t0 = time.perf_counter()
            frame = scene.render(cam, modes[nm])
            out[nm]["time_ms"].append(1e3 * (time.perf_counter() - t0))
            out[nm]["errors"].append(frame_figures(frame, truth))
            if boxes:
                out[nm]["boxes"].append(box_errors(frame, truth))
    return out
