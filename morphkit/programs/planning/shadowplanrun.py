"""A plan's shadow measured and chosen (``morphkit plan SCENE --budget shadow-iou=V``).

Every shadow candidate of the scene (:func:`~morphkit.plan.shadowchoice.shadow_candidates`) is drawn
on the plan's calibration frames with the real meshes
(:meth:`~morphkit.programs.scenerender.PreparedScene.meshes` with the candidate's shadow: the
frame's shadow on the ground is then the candidate's own error, the billboards' left to the
billboard keys), interleaved with the others and timed in the same run, and measured against the
truth, the meshes under the scene's ray cast (:func:`~morphkit.programs.planning.planverify.verify_frames`,
``shadow-iou``); the candidates' atlases are read from the assets' bakes or baked once a size
(:class:`~morphkit.programs.sceneshadows.SceneCasters`). The least work that meets the budget is the
plan's (:func:`~morphkit.plan.shadowchoice.choose_shadow`), and what a frame pays for it above the
scene's own shadow (the candidates' median frame times' difference) is added to the plan's predicted
frame time.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ValidationError, expected_got
from ...plan import Budget
from ...plan.planner import sample_scene
from ...plan.shadowchoice import ShadowMeasure, choose_shadow, shadow_candidates, shadow_name
from ...render import Renderer
from ...scenes.description import SceneShadows
from ..scenerender import PreparedScene
from .planverify import verify_frames

__all__ = ["measure_shadows", "plan_shadow", "shadow_report", "SHADOW_TIMING_ROUNDS"]

#: Times each candidate's calibration frames are drawn (interleaved with the others' each time): a
#: candidate's cost is the median of them all (the candidates differ by tens of milliseconds a
#: frame, about the shared machine's noise on one drawing).
SHADOW_TIMING_ROUNDS = 2


def measure_shadows(
    prep: PreparedScene,
    shadows: SceneShadows,
    renderer: Renderer,
    cameras: Sequence[Any],
    frames: Sequence[int],
    truths: dict[Any, Any],
    cache: str | os.PathLike[str] | None = None,
) -> list[ShadowMeasure]:
    """Each shadow candidate of ``shadows`` measured on ``frames`` (the module notes).

    Parameters
    ----------
    prep : PreparedScene
        The scene, with its casters and truth.
    shadows : SceneShadows
        The scene's own shadows.
    renderer : Renderer
        Bakes the candidates' atlases not read.
    cameras : sequence of CameraModel
        The path's frames.
    frames : sequence of int
        The frames measured on.
    truths : dict
        The truth's frames by index, drawn once
        (:func:`~morphkit.programs.planning.planverify.verify_frames`).
    cache : path-like, optional
        Where the candidates' atlases are kept between runs
        (:attr:`~morphkit.programs.sceneshadows.SceneCasters.cache`).

    Returns
    -------
    list of ShadowMeasure
        In the candidates' order (the scene's own first).

    Raises
    ------
    ValidationError
        A scene without shadows or without meshes.
    """
    if prep.casters is None or prep.truth is None or not prep.relit:
        raise ValidationError(
            expected_got(
                "--budget shadow-iou",
                "a scene with shadows (its 'shadows' entry) and every asset's mesh",
                "a scene without shadows" if prep.casters is None else "assets without meshes",
            )
        )
    receivers = prep.meshes()
    if cache is not None:
        prep.casters.cache = Path(cache)
    cands = shadow_candidates(shadows)
    modes = {
        shadow_name(c): dataclasses.replace(receivers, shadow=prep.casters.shadow(c, renderer)) for c in cands
    }
    plain = prep.meshes()
    sample = sample_scene(prep.scene)
    twins = dict.fromkeys(modes, plain)  # one plain frame a frame: every candidate shares it
    rounds = [
        verify_frames(prep, cameras, frames, modes, sample, truths=truths, plain=twins)
        for _ in range(SHADOW_TIMING_ROUNDS)
    ]
    return [
        ShadowMeasure(
            c,
            tuple(int(k) for k in frames),
            tuple(f["shadow-iou"] for f in rounds[0][shadow_name(c)]["errors"]),
            float(np.median([t for got in rounds for t in got[shadow_name(c)]["time_ms"]])),
        )
        for c in cands
    ]


def plan_shadow(measures: Sequence[ShadowMeasure], budget: Budget) -> tuple[ShadowMeasure, float]:
    """The plan's shadow (:func:`~morphkit.plan.shadowchoice.choose_shadow`) and what a frame pays for
    it above the scene's own (milliseconds, the first of ``measures``; negative when cheaper).

    Parameters
    ----------
    measures : sequence of ShadowMeasure
        The candidates measured, the scene's own first.
    budget : Budget
        With ``shadow-iou``.

    Returns
    -------
    chosen : ShadowMeasure
    extra_ms : float

    Raises
    ------
    BudgetError
        No candidate meets the budget.
    """
    chosen = choose_shadow(measures, budget)
    return chosen, chosen.ms - measures[0].ms


def shadow_report(measures: Sequence[ShadowMeasure], chosen: ShadowMeasure, budget: Budget) -> dict[str, Any]:
    """What ``plan.json``'s ``"shadow"`` entry says of the candidates and the choice.

    Parameters
    ----------
    measures : sequence of ShadowMeasure
        The candidates measured, the scene's own first.
    chosen : ShadowMeasure
        The plan's.
    budget : Budget
        The budget.

    Returns
    -------
    dict
        ``soft``, ``sun_atlas_size`` and ``name`` of the choice, ``scene`` (the scene's own shadow's
        name), ``frames`` (the calibration frames) and ``candidates``: per name the frames'
        ``shadow-iou`` (``median``, ``at_fraction``, ``per_frame``), its ``margin``
        (:meth:`~morphkit.plan.shadowchoice.ShadowMeasure.margin`), the median ``ms`` and whether it
        ``meets`` the budget by the margin.
    """
    out: dict[str, Any] = {
        "name": chosen.name,
        "soft": chosen.shadows.soft,
        "sun_atlas_size": chosen.shadows.sun_atlas_size,
        "scene": measures[0].name,
        "frames": list(chosen.frames),
        "drawn_with": "the real meshes (the shadow's own error)",
        "candidates": {},
    }
    for m in measures:
        vals = [v for v in m.iou if v is not None]
        out["candidates"][m.name] = {
            "shadow-iou": {
                "median": float(np.median(vals)) if vals else None,
                "at_fraction": m.reached(budget),
                "per_frame": list(m.iou),
            },
            "margin": m.margin(),
            "ms": m.ms,
            "meets": m.meets(budget),
        }
    return out
