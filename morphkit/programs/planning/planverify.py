"""A plan's frames drawn and measured: each frame in several modes and in the truth, the modes'
order turned each frame (so none is always first to warm the caches), timed in the same run, and
each frame's figures of a budget against the truth's frame (:mod:`morphkit.programs.planning.planrun`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from ...billboard import BillboardScene
from ...billboard.compare import box_errors, frame_errors
from ...sunlit.litmodes import Relit
from ...sunlit.shadowing import darkened_iou
from ..scenerender import PreparedScene

__all__ = ["frame_figures", "time_frames", "timed_again", "verify_frames"]


def frame_figures(frame: Any, truth: Any) -> dict[str, float | None]:
    """A frame's ``billboard-psnr`` and ``billboard-iou`` against the truth's frame (None: no
    billboard drawn): :func:`~morphkit.billboard.compare.frame_errors` over the billboards' boxes.

    Parameters
    ----------
    frame, truth : Frame
        The frame and the truth's.

    Returns
    -------
    dict of str to float or None
    """
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
    truths: dict[Any, Any] | None = None,
    plain: Mapping[str, Any] | None = None,
) -> dict[str, dict[str, list[Any]]]:
    """Each held-out frame drawn in every mode (the order turned each frame, so none is always first
    to warm the caches) and in the truth; each mode's figures and times per frame. ``scene``: the
    instances drawn (default the prepared scene's); ``boxes``: each frame's billboards' own figures too
    (``"boxes"``, :func:`~morphkit.billboard.compare.box_errors`); ``truths``: the truth's frames by
    frame index, drawn once (read where there, kept where not); ``plain``: each mode's twin drawing
    the same without shadows (one object for modes that share it: drawn once a frame, not timed),
    and each frame's ``shadow-iou`` measured too (:func:`~morphkit.sunlit.shadowing.darkened_iou`
    against the truth drawn without and with its ray cast; the truth's plain frame kept in ``truths``
    under ``("plain", index)``).

    Parameters
    ----------
    prep : PreparedScene
        The scene, its truth and its lights.
    cameras : sequence of CameraModel
        The path's frames.
    picks : sequence of int
        The frames drawn.
    modes : mapping of str to FrameMode
        The configurations.
    scene : BillboardScene, optional
        The instances drawn.
    boxes : bool, optional
        Also each billboard's own figures.
    truths : dict, optional
        The truth's frames, drawn once.
    plain : mapping of str to FrameMode, optional
        Each mode's twin without shadows.

    Returns
    -------
    dict of str to dict
        Per mode ``{"errors", "time_ms", "boxes"}``, a list each, one entry a frame.
    """
    scene = prep.scene if scene is None else scene
    out: dict[str, dict[str, list[Any]]] = {nm: {"errors": [], "time_ms": [], "boxes": []} for nm in modes}
    order = list(modes)
    twins = [] if plain is None else list({id(m): m for m in plain.values()}.values())
    truth_plain = prep.meshes() if plain is not None else None
    for n, k in enumerate(picks):
        cam = cameras[k]
        _relight(prep, k, (*modes.values(), *twins, prep.truth, truth_plain))
        truth = _drawn(truths, k, scene, cam, prep.truth)
        if plain is not None:
            t_plain = _drawn(truths, ("plain", k), scene, cam, truth_plain)
            drawn = {id(m): scene.render(cam, m) for m in twins}
        turn = order[n % len(order) :] + order[: n % len(order)]
        for nm in turn:
            t0 = time.perf_counter()
            frame = scene.render(cam, modes[nm])
            out[nm]["time_ms"].append(1e3 * (time.perf_counter() - t0))
            figures = frame_figures(frame, truth)
            if plain is not None:
                figures["shadow-iou"] = darkened_iou(drawn[id(plain[nm])], frame, t_plain, truth)
            out[nm]["errors"].append(figures)
            if boxes:
                out[nm]["boxes"].append(box_errors(frame, truth))
    return out


def time_frames(
    prep: PreparedScene,
    cameras: Sequence[Any],
    picks: Sequence[int],
    modes: Mapping[str, Any],
    scene: BillboardScene,
    turn: int = 0,
) -> dict[str, list[float]]:
    """Each frame drawn in every mode and timed, nothing measured (no truth drawn): the modes' order
    turned each frame, starting ``turn`` places on (so none is always first to warm the caches).

    Parameters
    ----------
    prep : PreparedScene
        The scene and its lights.
    cameras : sequence of CameraModel
        Every frame's camera, by the frame's index.
    picks : sequence of int
        The frames timed.
    modes : mapping of str to FrameMode
        The configurations timed.
    scene : BillboardScene
        The instances drawn.
    turn : int, optional
        The places the first frame's order is turned by.

    Returns
    -------
    dict of str to list of float
        Per mode, each frame's time (milliseconds).
    """
    out: dict[str, list[float]] = {nm: [] for nm in modes}
    order = list(modes)
    for n, k in enumerate(picks):
        cam = cameras[k]
        _relight(prep, k, modes.values())
        at = (n + turn) % len(order)
        for nm in order[at:] + order[:at]:
            t0 = time.perf_counter()
            scene.render(cam, modes[nm])
            out[nm].append(1e3 * (time.perf_counter() - t0))
    return out


def timed_again(
    prep: PreparedScene,
    cameras: Sequence[Any],
    picks: Sequence[int],
    modes: Callable[[], Mapping[str, Any]],
    scene: BillboardScene,
    times: Mapping[str, Sequence[float]],
    draws: int,
) -> dict[str, list[float]]:
    """Each mode's frame times ``times`` (one draw of each frame of ``picks``) with the frames drawn
    again, timed only (:func:`time_frames`, the order turned on each time), until each mode has at
    least ``draws`` draws in all, each time by new ``modes()`` (their caches cold, as a frame seen once
    is drawn): each frame's median over its draws.

    Parameters
    ----------
    prep : PreparedScene
        The scene and its lights.
    cameras : sequence of CameraModel
        Every frame's camera, by the frame's index.
    picks : sequence of int
        The frames.
    modes : callable
        Returns new modes by name (the names of ``times``).
    scene : BillboardScene
        The instances drawn.
    times : mapping of str to sequence of float
        Each mode's first time of each frame (milliseconds).
    draws : int
        The fewest draws of each mode in all.

    Returns
    -------
    dict of str to list of float
        Per mode, each frame's median time (milliseconds).
    """
    again = [time_frames(prep, cameras, picks, modes(), scene, turn=i + 1)
             for i in range(-(-draws // len(picks)) - 1)] if picks else []
    return {nm: [float(np.median([t, *(a[nm][j] for a in again)])) for j, t in enumerate(ts)]
            for nm, ts in times.items()}


def _relight(prep: PreparedScene, k: int, modes: Iterable[Any]) -> None:
    """The relit ones of ``modes`` lit as frame ``k`` is (where the scene's lights change by frame)."""
    if prep.lighting is not None:
        for m in modes:
            if isinstance(m, Relit):
                m.lighting = prep.lighting[k]


def _drawn(kept: dict[Any, Any] | None, key: Any, scene: BillboardScene, cam: Any, mode: Any) -> Any:
    """The frame kept under ``key``, else ``scene`` drawn by ``mode`` (and kept, where ``kept`` is a
    dict)."""
    got = kept.get(key) if kept is not None else None
    if got is None:
        got = scene.render(cam, mode)
        if kept is not None:
            kept[key] = got
    return got
