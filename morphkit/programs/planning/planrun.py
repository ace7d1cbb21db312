"""``morphkit plan SCENE --budget KEY=VALUE -o OUT``: a scene planned to an error budget and
the plan verified against the real meshes.

:func:`plan_scene` prepares the scene as ``morphkit render`` does
(:func:`~morphkit.programs.scenerender.prepare_scene`), then:

1. **measures** each asset's error table in every representation of
   :data:`~morphkit.plan.representations.REPRESENTATIONS`
   (:func:`~morphkit.plan.errortable.measure_error_table`:
   the asset alone against its own mesh, under the scene's focal length, backdrop and middle frame's sun),
   or reads the tables a previous plan into the same folder measured for the same mesh and conditions
   (:func:`~.plantables.scene_tables`);
2. **calibrates** the tables on a few planning frames drawn in each representation everywhere (each
   one's offsets, margin and measured cost per frame and per billboard, and whether it met the budget
   there; a path of fewer than :data:`PLAN_COST_FRAMES` calibration frames cannot tell the two costs
   apart, so its frames are drawn again, timed only, with :data:`PLAN_COST_FRACTIONS` of their instances).
   With a ``shadow-iou`` budget, each shadow candidate (sun-atlas texels, hard, filtered or N
   directions: :mod:`morphkit.plan.shadowchoice`) is measured on the same frames with the real
   meshes and the least work meeting it chosen (:mod:`morphkit.programs.planning.shadowplanrun`;
   refused with one line when none does); its cost above the scene's own shadow is added to every
   frame's predicted time;
3. **predicts** the planning frames (every frame but the verification frames) and **chooses** each
   band's cheapest representation predicted to meet the budget (:func:`~morphkit.plan.planner.choose`);
   a budget it cannot meet stops here with one line and nothing written. The plan is then drawn on
   its own calibration frames (:data:`PLAN_OWN_FRAMES`: the calibration frames and the planning frames
   midway between them), and its figures along the path follow: those frames' as measured, every
   other planning frame's predicted and moved by the offsets of the drawn frames around it
   (:meth:`~.planown.PlanCalibration.along`). One that misses the budget's fraction of the planning
   frames so, held by the tolerance's margin (:func:`~.planown.less_margin`), is chosen again with
   the margins of the representations it drew widened by its shortfall, a representation everywhere
   that so missed no longer a start
   (:data:`morphkit.tol.PLAN_RECHOICES` times at most), then given up for each representation
   everywhere measured to meet it on the calibration frames or predicted to along the path by its
   margins, the cheapest first, until one meets it along the path too. A plan that meets it is
   weighed against each representation everywhere measured or predicted to meet it (a frame mixing
   representations pays each one's pass, which their cost lines do not predict): by their draws so
   far on the calibration frames (``calibration.plan.first_ms``), then those so told faster by
   :data:`morphkit.tol.PLAN_TIMED_FASTER` timed again with it on its own frames (interleaved, at
   least :data:`PLAN_TIME_DRAWS` draws each: ``calibration.plan.timed_ms``); one faster so too is
   drawn as the plan and taken where it meets the budget along the path, the fastest first
   (``calibration.plan.chosen_again`` in ``plan.json`` says what was done);
4. **verifies** on the held-out frames (``verify`` of them, spread over the path, never used to
   choose): each is drawn with the plan, with today's default (the view morph everywhere) and, with
   ``sweep``, with each representation everywhere, interleaved frame by frame and timed in the same
   run (drawn again, timed only, to :data:`PLAN_TIME_DRAWS` draws in all), and measured against
   the real meshes (relit, with the scene's ray-cast shadows): the PSNR and silhouette IoU over the
   pixels of the billboards' boxes (:func:`~morphkit.billboard.compare.frame_errors`) are the
   frame's ``billboard-psnr`` and ``billboard-iou``, the plan's predicted from its tables moved by
   what the plan measured less predicted on its calibration frames around it
   (:func:`~morphkit.plan.calibration.path_offsets`);
   with a ``shadow-iou`` budget, the plan draws the chosen shadow (the default
   the scene's own, a sweep's configurations the chosen), each frame is drawn again without its
   shadows and its ``shadow-iou`` is the IoU of the ground pixels its shadows darken against the
   truth's (:func:`~morphkit.sunlit.shadowing.darkened_iou`), predicted from the calibration frames
   around it;
5. writes ``OUT/plan.json`` (:mod:`morphkit.plan.planfile`), ``OUT/plan.png`` (the configurations'
   error against their median frame time, predicted beside measured) and ``OUT/tables/``.

The tables are kept between runs in a cache (``--tables DIR``; default ``tables`` in
:data:`morphkit.settings.CACHE_DIR`), named by what they were measured of and under, and written as
soon as measured: a plan that fails its budget writes nothing to ``OUT`` but keeps its tables (and
the shadow candidates' sun atlases, in its ``sun_atlases`` subfolder).

A ``time-ms`` budget plans the least error whose predicted median frame time is within it
(:func:`~morphkit.plan.planner.choose`, "Time"), verified as the held-out frames' measured median.
Not chosen among yet: the octahedral impostor (at equal bytes the dome's morph costs as much and
errs less: docs/RESULTS.md, "Billboards: ring, dome, impostor"), the billboards' texels and views
(the scene's own are kept).
"""

from __future__ import annotations

import dataclasses
import os
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ... import settings, tol
from ...billboard.compare import PSNR_CAP_DB
from ...errors import BudgetError, ValidationError, expected_got
from ...files.outfolder import PLAN_OUTPUT, OutputClaim, claim_output
from ...plan import Budget
from ...plan.calibration import band_offsets, calibration_offsets, frame_cost
from ...plan.errortable import ErrorTable
from ...plan.mixed import uniform_mode
from ...plan.planfile import PLAN_NAME, ScenePlan
from ...plan.planner import FramePredictions, choose, predict_frames, sample_scene
from ...plan.representations import (
    REPRESENTATIONS,
    BandChoice,
    RealMesh,
    Representation,
    band_label,
    representation,
)
from ...plan.shadowchoice import interpolate_frames
from ...render import Renderer
from ...scenes.description import SceneDescription
from ..scenerender import PreparedScene, prepare_scene, scene_choices
from ..sequence import compare_indices
from .planown import less_margin, plan_offset, shortfall
from .planreport import budget_figures, plot_plan, prediction_gap, shown_budget
from .plantables import scene_tables, table_grids
from .planverify import time_frames, timed_again, verify_frames
from .shadowplanrun import measure_shadows, plan_shadow, shadow_report

__all__ = [
    "plan_scene", "PLAN_OWN_FRAMES", "PLAN_COST_FRAMES",
    "PLAN_COST_FRACTIONS", "PLAN_TIME_DRAWS", "TABLES_FOLDER", "DEFAULT_VERIFY",
]

#: The error tables' subfolder of a plan's output folder.
TABLES_FOLDER = "tables"
#: The subfolder of the tables' cache the shadow candidates' sun atlases are kept in.
SUN_ATLASES_FOLDER = "sun_atlases"
#: Planning frames drawn in every representation to calibrate the tables' predictions to the scene.
PLAN_CALIBRATION_FRAMES = 4
#: Planning frames the chosen plan is drawn on, for its own offsets along the path and its check against
#: the budget: the calibration frames and those midway between them (``2 * 4 - 1`` frames spread over
#: the planning frames hold the 4 spread so). A plan's error changes along a path faster than four
#: frames follow (a day's sun moving its meshes' shadows, a few large cards coming and going).
PLAN_OWN_FRAMES = 2 * PLAN_CALIBRATION_FRAMES - 1
#: Calibration frames a representation's cost per frame and per billboard are told apart on (the
#: least-squares line of their times over their billboards needs three points).
PLAN_COST_FRAMES = 3
#: The fractions of a scene's instances its calibration frames are drawn again with, timed only, where
#: they are fewer than :data:`PLAN_COST_FRAMES` (a one-frame scene: how else would its frame's cost, the
#: real mesh's render pass, be told from its billboards'?).
PLAN_COST_FRACTIONS: tuple[float, ...] = (1.0, 0.5, 0.25)
#: Held-out frames verified by default.
DEFAULT_VERIFY = 6
#: The fewest draws in all a configuration's verified frame times are taken from: the held-out frames
#: are drawn again by new modes (their caches cold, as a frame seen once is drawn), timed only, until
#: each configuration has this many, and a frame's time is the median of its draws: 3 of each of 6
#: held-out frames, 18 of a one-frame scene's (one draw of a frame is one sample of a shared machine's
#: noise: fly-shadows' plan, the nearest view everywhere, measured 1.11x the same representation's
#: sweep over 6 frames of one draw each, its frames' times 20 % apart).
PLAN_TIME_DRAWS = 18


def _uniform(prep: PreparedScene, rep: Representation) -> Any:
    """The mode drawing every billboard of the scene as ``rep``, under its shadow."""
    return uniform_mode(rep, prep.relit, prep.base, prep.shadow, prep.meshes())


def _cost_draws(
    prep: PreparedScene,
    cameras: Sequence[Any],
    frames: Sequence[int],
    sample: Any,
    tables: Mapping[tuple[str, str], ErrorTable],
) -> tuple[list[int], dict[str, list[float]]]:
    """The calibration frames drawn again in every representation everywhere, timed only, with
    :data:`PLAN_COST_FRACTIONS` of ``sample``'s instances (the same draw of them on every run), each
    fraction by new modes (their caches cold, as a one-frame scene's frame is drawn): each draw's
    billboards (predicted in bands, as the calibration counts them) and each representation's times."""
    counts: list[int] = []
    times: dict[str, list[float]] = {r.name: [] for r in REPRESENTATIONS}
    rng = np.random.default_rng(0)
    for n, f in enumerate(PLAN_COST_FRACTIONS):
        sub = sample_scene(sample, max(1, round(f * len(sample))), rng)
        counts += [len(b) for b in predict_frames(tables, sub, [cameras[k] for k in frames]).band_index]
        got = time_frames(prep, cameras, frames, {r.name: _uniform(prep, r) for r in REPRESENTATIONS}, sub, n)
        for nm, t in got.items():
            times[nm] += t
    return counts, times


def _calibrate(
    prep: PreparedScene,
    cameras: Sequence[Any],
    planning: Sequence[int],
    tables: Mapping[tuple[str, str], ErrorTable],
    budget: Budget,
    head: str,
    truths: dict[int, Any],
) -> tuple[
    dict[Any, tuple[float, float]],
    dict[str, float],
    dict[str, tuple[float, float]],
    list[str],
    dict[str, Any],
]:
    """Each representation's offsets between the tables' prediction and the scene's measure, on a few
    planning frames drawn in it everywhere: each band's from its billboards' own figures
    (:func:`~morphkit.plan.calibration.band_offsets`), then the frames' for what is left and for the bands
    too little seen (:func:`~morphkit.plan.calibration.calibration_offsets`): what
    a table of one billboard alone cannot know of the scene (the billboards behind a silhouette, the
    frame's edges, overlaps); each representation's cost per frame and per billboard drawn
    (:func:`~morphkit.plan.calibration.frame_cost` of its frames' times, or of :func:`_cost_draws`'
    where the frames are too few); each representation's margin, how far its worst calibration frame fell
    short of the calibrated prediction (at least the tolerance's); and the representations *proven*:
    measured on the calibration frames to meet the budget by the tolerance's margin."""
    frames = [
        planning[i] for i in compare_indices(len(planning), min(PLAN_CALIBRATION_FRAMES, len(planning)))
    ]
    sample = sample_scene(prep.scene)  # a large scene calibrated on the instances it is predicted from
    got = verify_frames(
        prep,
        cameras,
        frames,
        {r.name: _uniform(prep, r) for r in REPRESENTATIONS},
        sample,
        boxes=True,
        truths=truths,
    )
    pred = predict_frames(tables, sample, [cameras[k] for k in frames])
    counts = [len(b) for b in pred.band_index]
    times = {r.name: got[r.name]["time_ms"] for r in REPRESENTATIONS}
    if len(frames) < PLAN_COST_FRAMES:
        counts, times = _cost_draws(prep, cameras, frames, sample, tables)
    offsets: dict[Any, tuple[float, float]] = {}
    costs: dict[str, float] = {}
    whole: dict[str, float] = {}
    margins: dict[str, tuple[float, float]] = {}
    proven: list[str] = []
    report: dict[str, Any] = {"frames": list(frames), "cost_billboards": counts}
    for r in REPRESENTATIONS:
        # a billboard's (or a culled band's) table is held to what a scene can move it by; the real
        # mesh's is exact (the truth against itself), so all its frames' error is the scene's (their
        # shadows): not held
        lim = (
            np.array([tol.PLAN_MAX_OFFSET_DB, tol.PLAN_MAX_OFFSET_IOU])
            if not isinstance(r, RealMesh)
            else np.array([PSNR_CAP_DB, 1.0])
        )
        uniform = pred.pick_of(BandChoice(default=r.name))
        measured = got[r.name]["errors"]
        c0 = calibration_offsets(pred.frame_errors(uniform), measured)  # the frames' offset
        bands = band_offsets(pred, r.name, got[r.name]["boxes"])  # each band's, where it has billboards
        first: dict[Any, tuple[float, float]] = {r.name: (c0.db, c0.iou), **bands}
        c = calibration_offsets(pred.shifted(first).frame_errors(uniform), measured)  # what is left
        mine = {k: (v[0] + c.db, v[1] + c.iou) for k, v in first.items()}
        kept = {
            k: (float(np.clip(v[0], -lim[0], lim[0])), float(np.clip(v[1], -lim[1], lim[1])))
            for k, v in mine.items()
        }
        if kept != mine:
            print(
                f"{head}{r.name}'s calibration held to +-{lim[0]:g} dB, IoU +-{lim[1]:g} in "
                f"{sum(kept[k] != mine[k] for k in mine)} of its {len(mine)} offsets: the tables describe "
                "this scene's billboards poorly",
                flush=True,
            )
        offsets.update(kept)
        margins[r.name] = (
            max(tol.PLAN_MARGIN_DB, min(c.spread_db, lim[0])),
            max(tol.PLAN_MARGIN_IOU, min(c.spread_iou, lim[1])),
        )
        if budget.error_keys() and budget.verdict(less_margin(measured))["met"]:  # time alone: none
            proven.append(r.name)
        whole[r.name], costs[r.name] = frame_cost(counts, times[r.name], float(r.cost + 1))
        report[r.name] = {
            "db": kept[r.name][0],
            "iou": kept[r.name][1],
            "measured_db": c0.db,
            "measured_iou": c0.iou,
            "bands": {
                band_label(k[1], pred.base_height[k[1][0]]): {"db": v[0], "iou": v[1]}
                for k, v in kept.items()
                if k != r.name
            },
            "spread_db": c.spread_db,
            "spread_iou": c.spread_iou,
            "frames_used": c.frames,
            "ms_per_billboard": costs[r.name],
            "ms_per_frame": whole[r.name],
            "margin_db": margins[r.name][0],
            "margin_iou": margins[r.name][1],
            "measured_meets": r.name in proven,
            "time_ms": got[r.name]["time_ms"],
        }
    print(
        f"{head}calibrated on {len(frames)} planning frames (measured less predicted): "
        + "; ".join(
            f"{nm} {db:+.2f} dB, IoU {iou:+.3f} (margin {margins[nm][0]:.2f} dB, {margins[nm][1]:.3f}), "
            f"{costs[nm]:.2f} ms a billboard + {whole[nm]:.0f} ms a frame"
            f"{', meets the budget' if nm in proven else ''}"
            for nm, (db, iou) in offsets.items()
            if isinstance(nm, str)
        )
        + f" ({sum(not isinstance(k, str) for k in offsets)} bands calibrated apart)",
        flush=True,
    )
    # what a frame pays for drawing a representation at all, above what every frame pays (the
    # cheapest's): the real mesh's render of the frame, which a frame mixing it with billboards pays
    floor = min(whole.values())
    fixed = {nm: w - floor for nm, w in whole.items()}
    report["frame_ms"] = floor
    return offsets, costs, fixed, floor, margins, proven, report


def _cheapest_everywhere(
    pred: FramePredictions, names: Sequence[str], costs: Mapping[str, float], fixed: Mapping[str, float],
    base_ms: float,
) -> str:
    """Of ``names``, the representation whose frames drawn in it everywhere are predicted fastest
    (the median frame)."""
    cost = np.array([costs[n] for n in pred.representations])
    per_frame = np.array([fixed[n] for n in pred.representations])
    return min(
        names,
        key=lambda nm: float(
            np.median(pred.frame_times(pred.pick_of(BandChoice(default=nm)), cost, per_frame, base_ms))
        ),
    )


def _timed_rivals(
    prep: PreparedScene,
    cameras: Sequence[Any],
    frames: Sequence[int],
    plan: ScenePlan,
    plan_ms: float,
    rivals_ms: Mapping[str, float],
) -> dict[str, float]:
    """The plan timed against each representation everywhere of ``rivals_ms`` that its first draws
    tell faster by :data:`morphkit.tol.PLAN_TIMED_FASTER` (``rivals_ms`` against ``plan_ms``: their
    median frame times, drawn apart), all drawn on ``frames`` interleaved, the order turned each frame,
    by new modes each draw (at least :data:`PLAN_TIME_DRAWS` draws each), timed only: each one's median
    frame time, the plan's as ``plan`` (none timed: empty)."""
    names = [nm for nm, t in rivals_ms.items() if t * tol.PLAN_TIMED_FASTER < plan_ms]
    if not names:
        return {}
    sample = sample_scene(prep.scene)  # as the plan's own frames are measured

    def modes() -> dict[str, Any]:
        return {"plan": plan.mode(prep.relit, prep.base, prep.shadow, prep.meshes()),
                **{nm: _uniform(prep, representation(nm)) for nm in names}}

    first = time_frames(prep, cameras, frames, modes(), sample)
    got = timed_again(prep, cameras, frames, modes, sample, first, PLAN_TIME_DRAWS)
    return {nm: float(np.median(t)) for nm, t in got.items()}


def plan_scene(
    scene: SceneDescription,
    budget: Budget,
    out: OutputClaim | str | os.PathLike[str],
    *,
    overwrite: bool = False,
    sweep: bool = False,
    verify: int = DEFAULT_VERIFY,
    tables_cache: str | os.PathLike[str] | None = None,
) -> dict[str, Any]:
    """Plan ``scene`` to ``budget`` and verify the plan on held-out frames (the module notes).

    Parameters
    ----------
    scene : SceneDescription
        With at least one asset, every asset with a mesh (the truth).
    budget : Budget
        ``billboard-psnr``, ``billboard-iou``, ``shadow-iou``, ``time-ms``, and ``frames``.
    out : OutputClaim or path-like
        The output folder (``plan.json``, ``plan.png``, ``tables/``).
    overwrite : bool, optional
        Replace a previous plan in ``out`` (its tables are reused where they match).
    sweep : bool, optional
        Also draw the held-out frames with each representation everywhere (``time_ms.cheapest_sweep``).
    verify : int, optional
        Held-out frames verified (>= 1; at most the scene's frames).
    tables_cache : path-like, optional
        Where the error tables are kept between runs (default ``tables`` in
        :data:`morphkit.settings.CACHE_DIR`).

    Returns
    -------
    dict
        What ``plan.json`` holds.

    Raises
    ------
    BudgetError
        No choice is predicted to meet the budget (nothing written).
    ValidationError
        A ``shadow-iou`` budget for a scene without shadows, a scene without assets or meshes,
        ``verify < 1``.

    Examples
    --------
    The example forest, planned to 17 dB and an IoU of 0.75 in 95 % of its frames
    (``morphkit plan samples/scenes/forest.json --budget billboard-psnr=17 --budget billboard-iou=0.75
    -o OUT``)::

        import morphkit

        scene = morphkit.load_scene("samples/scenes/forest.json")
        budget = morphkit.Budget(billboard_psnr=17, billboard_iou=0.75)
        report = morphkit.plan_scene(scene, budget, "plan-out")
        print(report["verified"], report["time_ms"])
    """
    claim = out if isinstance(out, OutputClaim) else claim_output(out, PLAN_OUTPUT, overwrite=overwrite)
    head = "morphkit plan: "
    tables_cache = Path(settings.CACHE_DIR) / TABLES_FOLDER if tables_cache is None else Path(tables_cache)
    if budget.shadow_iou is not None and scene.shadows is None:
        raise ValidationError(
            expected_got("--budget shadow-iou", "a scene with shadows (its 'shadows' entry)", "none")
        )
    if verify < 1:
        raise ValidationError(expected_got("--verify", "an int >= 1", verify))
    sun, views, cams, _label, chosen = scene_choices(scene, "plan")
    if chosen:
        print(chosen, flush=True)
    picks = compare_indices(len(cams), min(verify, len(cams)))
    planning = [k for k in range(len(cams)) if k not in picks] or list(picks)
    if planning == list(picks):
        print(
            f"{head}the scene's {len(cams)} frame(s) are all verified: none is held out from planning",
            flush=True,
        )
    with Renderer() as r:
        prep = prepare_scene(scene, r, views, head=head, command="plan", sun=sun)
        if prep.truth is None or not len(prep.scene):
            raise ValidationError(
                expected_got(
                    "scene",
                    "instances of assets with meshes (the truth to plan against)",
                    "no instances" if not len(prep.scene) else "no meshes",
                )
            )
        t0 = time.perf_counter()
        grids = table_grids(prep, cams)
        tables, measured = scene_tables(
            prep, r, float(cams[0].fy), grids, Path(tables_cache), claim.path / TABLES_FOLDER, head
        )
        t_tables = time.perf_counter() - t0
        t0 = time.perf_counter()
        truths: dict[int, Any] = {}  # the calibration frames' truth, drawn once
        offsets, costs, fixed, floor, margins, proven, calibration = _calibrate(
            prep, cams, planning, tables, budget, head, truths
        )
        shadows = extra_ms = plan_prep = None
        if budget.shadow_iou is not None:  # the frames' shadow: measured on the calibration frames
            kept = Path(tables_cache) / SUN_ATLASES_FOLDER
            shadows = measure_shadows(prep, scene.shadows, r, cams, calibration["frames"], truths, kept)
            chosen_shadow, extra_ms = plan_shadow(shadows, budget)
            plan_prep = dataclasses.replace(prep, shadow=prep.casters.shadow(chosen_shadow.shadows, r))
            print(
                f"{head}shadows: {len(shadows)} candidates on {len(calibration['frames'])} calibration "
                f"frames (drawn with the real meshes); {chosen_shadow.name} chosen, shadow-iou "
                f"{chosen_shadow.reached(budget):.3f} in {budget.frames:.0%} of them, {extra_ms:+.0f} ms a "
                f"frame against the scene's own ({shadows[0].name}: {shadows[0].reached(budget):.3f})",
                flush=True,
            )
        plan_prep = prep if plan_prep is None else plan_prep
        t_calibrate = time.perf_counter() - t0
        t0 = time.perf_counter()
        pred = predict_frames(tables, prep.scene, [cams[k] for k in planning]).shifted(offsets)
        at = floor + (extra_ms or 0.0)  # every frame pays the plan's shadow
        picked = choose(pred, budget, costs=costs, margin=margins, proven=proven, fixed=fixed, base_ms=at)
        t_plan = time.perf_counter() - t0

        def as_plan(choice: BandChoice) -> ScenePlan:
            return ScenePlan(
                budget,
                choice,
                prep.relit,
                tuple(prep.scene.assets),
                {b: int(c) for b, c in zip(pred.bands, pred.counts(), strict=True)},
                pred.base_height,
                shadows=None if shadows is None else chosen_shadow.shadows,
                shape=tuple(cams[0].shape),
            )

        plan = as_plan(picked.choice)
        # the plan itself on its own calibration frames: what mixing its representations does to the
        # frames (a card among exact meshes shares its box with fewer errors than among cards); a plan
        # that misses the budget along the path is chosen again with wider margins, then given up for
        # each representation everywhere measured or predicted to meet it, the cheapest first
        t1 = time.perf_counter()
        own_frames = [planning[i] for i in compare_indices(len(planning), PLAN_OWN_FRAMES)]
        own = plan_offset(plan_prep, cams, own_frames, plan, tables, offsets, truths)
        checked = budget.time_ms is None and (budget.billboard_psnr, budget.billboard_iou) != (None, None)
        billboards_only = dataclasses.replace(budget, shadow_iou=None) if checked else budget
        rechosen: list[str] = []
        tried: list[str] = []  # the representations drawn everywhere as the plan
        exhausted = False  # no wider choice predicted to meet the budget
        missed = f"{head}the plan missed the budget along the path: "

        def everywhere(name: str) -> BandChoice:
            return pred.choice_of(pred.pick_of(BandChoice(default=name)))

        def along() -> list[dict[str, float | None]]:  # the plan's figures on the planning frames
            return own.along(pred.frame_errors(pred.pick_of(picked.choice)), planning)

        def viable(name: str) -> bool:  # measured to meet it, or predicted to by its margins along the path
            less = less_margin(pred.frame_errors(pred.pick_of(BandChoice(default=name))), margins[name])
            return name in proven or billboards_only.verdict(less)["met"]

        # held by the tolerance's margin, as a representation proven on its calibration frames is
        while checked and not billboards_only.verdict(figures := less_margin(along()))["met"]:
            # a representation everywhere drawn as the plan and missing is measured to miss: no more a start
            tried += [nm for nm in pred.representations
                      if nm not in tried and everywhere(nm) == picked.choice]
            again = None
            if len(rechosen) < tol.PLAN_RECHOICES and not exhausted:
                short = shortfall(billboards_only, figures)
                # the margins of the representations the plan drew: its miss says nothing of the others
                drawn = [nm for nm in pred.representations if nm in picked.choice.choices.values()]
                wider = {nm: (m[0] + short[0], m[1] + short[1]) if nm in drawn else m
                         for nm, m in margins.items()}
                starts = [nm for nm in proven if nm not in tried]
                try:
                    again = choose(pred, budget, costs=costs, margin=wider, proven=starts, fixed=fixed,
                                   base_ms=at)
                except BudgetError:  # none predicted to meet it by wider margins: on to the fallback
                    exhausted = True
                    rechosen.append("no choice is predicted to meet the budget by wider margins")
                    print(missed + rechosen[-1], flush=True)
            if again is not None:
                picked, margins = again, wider
                rechosen.append(f"chosen again, the margins of {', '.join(drawn)} widened by "
                                f"{short[0]:.2f} dB, IoU {short[1]:.3f}")
            elif untried := [nm for nm in pred.representations if nm not in tried and viable(nm)]:
                best = _cheapest_everywhere(pred, untried, costs, fixed, at)
                tried.append(best)
                picked = dataclasses.replace(picked, choice=everywhere(best))
                rechosen.append(f"{best} everywhere (" + ("measured to meet the budget on the "
                                "representations' calibration frames)" if best in proven else
                                "predicted to meet the budget along the path by its margins)"))
            else:
                why = ("every representation everywhere measured or predicted to meet it misses it here"
                       if any(map(viable, tried))
                       else "no representation everywhere was measured or predicted to meet it")
                rechosen.append(f"kept: {why}")
                print(missed + rechosen[-1], flush=True)
                break
            print(missed + rechosen[-1], flush=True)
            plan = as_plan(picked.choice)
            own = plan_offset(plan_prep, cams, own_frames, plan, tables, offsets, truths)
        timed: dict[str, float] = {}
        first: dict[str, float] = {}
        if checked and billboards_only.verdict(less_margin(along()))["met"]:
            # the plan against each representation everywhere that may stand for it, on its own frames
            # (a frame mixing representations pays each one's pass, which no cost line predicts): first
            # by their draws so far on the calibration frames (the representations' under the scene's
            # shadow, moved by the plan's shadow's cost), then those told faster timed again together
            at_cal = [t for f, t in zip(own.frames, own.time_ms, strict=True) if f in calibration["frames"]]
            rivals = {nm: float(np.median(calibration[nm]["time_ms"])) + (extra_ms or 0.0)
                      for nm in pred.representations
                      if nm not in tried and viable(nm) and everywhere(nm) != picked.choice}
            plan_ms = float(np.median(at_cal or own.time_ms))
            timed = _timed_rivals(plan_prep, cams, own_frames, plan, plan_ms, rivals)
            first = {"plan": plan_ms, **rivals}
            faster = [nm for nm, t in timed.items()
                      if nm != "plan" and t * tol.PLAN_TIMED_FASTER < timed["plan"]]
            for nm in sorted(faster, key=timed.__getitem__)[: tol.PLAN_RECHOICES]:
                kept_plan = picked, plan, own
                picked = dataclasses.replace(picked, choice=everywhere(nm))
                plan = as_plan(picked.choice)
                own = plan_offset(plan_prep, cams, own_frames, plan, tables, offsets, truths)
                met = billboards_only.verdict(less_margin(along()))["met"]
                print(f"{head}{nm} everywhere timed {timed[nm]:.0f} ms a frame on the plan's own frames "
                      f"against its {timed['plan']:.0f} ms: {'meets' if met else 'misses'} the budget "
                      f"along the path{', taken' if met else ''}", flush=True)
                if met:
                    rechosen.append(f"{nm} everywhere (timed {timed[nm]:.0f} ms a frame on the plan's "
                                    f"own frames against its {timed['plan']:.0f} ms)")
                    break
                picked, plan, own = kept_plan
        truths.clear()
        calibration["plan"] = {**own.to_json(), "chosen_again": rechosen, "first_ms": first,
                               "timed_ms": timed}
        t_calibrate += time.perf_counter() - t1
        taken = [sum(v == r.name for v in picked.choice.choices.values()) for r in REPRESENTATIONS]
        print(
            f"{head}{len(pred.bands)} bands over {len(planning)} planning frames: "
            + (", ".join(f"{n} {r.name}" for r, n in zip(REPRESENTATIONS, taken, strict=True) if n) or "none")
            + f" (tables {t_tables:.1f} s, calibration {t_calibrate:.1f} s, choice {t_plan:.2f} s)",
            flush=True,
        )
        swept = [rep for rep in REPRESENTATIONS if sweep and rep.name != "morph"]  # morph: the default

        unshadowed = dataclasses.replace(prep, shadow=None)

        def configurations(shadowed: bool = True) -> dict[str, Any]:
            """New modes (their caches cold): the default under the scene's shadow, the plan and the
            swept under the plan's; or each without shadows."""
            own, chosen = (prep, plan_prep) if shadowed else (unshadowed, unshadowed)
            return {"plan": plan.mode(prep.relit, prep.base, chosen.shadow, prep.meshes()),
                    "default": own.mode(), **{rep.name: _uniform(chosen, rep) for rep in swept}}

        modes, plain = configurations(), configurations(shadowed=False)
        print(
            f"{head}verifying on {len(picks)} held-out frames: {', '.join(modes)} against the real meshes",
            flush=True,
        )
        got = verify_frames(prep, cams, picks, modes, plain=plain if shadows is not None else None)
        # one draw of a frame is one sample of the machine's noise: drawn again by new modes, timed only
        times = timed_again(prep, cams, picks, configurations, prep.scene,
                            {nm: g["time_ms"] for nm, g in got.items()}, PLAN_TIME_DRAWS)
        for nm, g in got.items():
            g["time_ms"] = times[nm]
        held = predict_frames(tables, prep.scene, [cams[k] for k in picks]).shifted(offsets)
        predicted = {
            "plan": own.along(held.frame_errors(held.pick_of(plan.choice)), picks),
            "default": held.frame_errors(held.pick_of(BandChoice())),
        }
        held_picks = {"plan": held.pick_of(plan.choice), "default": held.pick_of(BandChoice())}
        for nm in modes:
            if nm not in held_picks:  # a sweep's: one representation everywhere
                held_picks[nm] = held.pick_of(BandChoice(default=nm))
                predicted[nm] = held.frame_errors(held_picks[nm])
        cost = np.array([costs[n] for n in held.representations])
        per_frame = np.array([fixed[n] for n in held.representations])
        predicted_ms = {
            nm: float(np.median(held.frame_times(pk, cost, per_frame, floor))) if held.band_index else 0.0
            for nm, pk in held_picks.items()
        }
        if shadows is not None:  # the shadow's own prediction: its calibration frames around each frame
            for nm in predicted:
                m = shadows[0] if nm == "default" else chosen_shadow
                for f, v in zip(predicted[nm], interpolate_frames(m.frames, m.iou, picks), strict=True):
                    f["shadow-iou"] = v
                if nm != "default":
                    predicted_ms[nm] += extra_ms
    shown = shown_budget(budget)
    rows: dict[str, dict[str, Any]] = {}
    for nm, g in got.items():
        v = budget.verdict(g["errors"])
        t_med = float(np.median(g["time_ms"]))
        if budget.time_ms is not None:  # the time is part of the budget: the median frame's
            v = {**v, "time_met": t_med <= budget.time_ms, "met": v["met"] and t_med <= budget.time_ms}
        rows[nm] = {
            "time_ms": t_med,
            "predicted_ms": predicted_ms[nm],
            "measured": budget_figures(shown, g["errors"]),
            "predicted": budget_figures(shown, predicted[nm]),
            "verified": v,
            "gap": prediction_gap(predicted[nm], g["errors"]),
            "per_frame": {"measured": g["errors"], "predicted": predicted[nm], "time_ms": g["time_ms"]},
        }
    meeting = [nm for nm, row in rows.items() if nm != "plan" and row["verified"]["met"]]
    cheapest = min(meeting, key=lambda nm: rows[nm]["time_ms"]) if sweep and meeting else None
    v = rows["plan"]["verified"]
    report = {
        "scene_frames": len(cams),
        "planning_frames": planning,
        "held_out_frames": list(picks),
        "held_out": planning != list(picks),
        "verified": {
            "frames": v["frames"],
            "within": v["within"],
            "fraction": v["fraction"],
            "met": v["met"],
            **({"time_met": v["time_met"]} if "time_met" in v else {}),
        },
        "time_ms": {
            "plan": rows["plan"]["time_ms"],
            "plan_predicted": rows["plan"]["predicted_ms"],
            "default": rows["default"]["time_ms"],
            "cheapest_sweep": rows[cheapest]["time_ms"] if cheapest else None,
            "cheapest_sweep_name": cheapest,
            "planning": 1e3 * t_plan,
            "calibration": 1e3 * t_calibrate,
            "tables": 1e3 * t_tables,
        },
        "error": {"plan": rows["plan"]["measured"], "default": rows["default"]["measured"]},
        "predicted": {
            "plan": rows["plan"]["predicted"],
            "default": rows["default"]["predicted"],
            "gap": {"plan": rows["plan"]["gap"], "default": rows["default"]["gap"]},
        },
        "configurations": rows,
        "tables_measured": measured,
        "calibration": calibration,
    }
    if shadows is not None:
        report["shadow"] = shadow_report(shadows, chosen_shadow, budget)
    plan = dataclasses.replace(plan, report=report)
    with claim.writing() as o:
        (o / TABLES_FOLDER).mkdir(exist_ok=True)
        for (nm, rep), t in tables.items():
            t.save(o / TABLES_FOLDER / f"{nm}.{rep}.npz")
        plot_plan(o / "plan.png", budget, shown, rows)
        plan.save(o / PLAN_NAME)
    d = rows["default"]
    print(
        f"{head}plan verified on {v['frames']} held-out frames: {v['within']} within the budget "
        f"({v['fraction']:.0%}; {'met' if v['met'] else 'NOT met'}); "
        f"median frame {rows['plan']['time_ms']:.0f} ms "
        f"against the default's {d['time_ms']:.0f} ms ({d['time_ms'] / rows['plan']['time_ms']:.2f}x), "
        f"which {'meets' if d['verified']['met'] else 'misses'} it"
    )
    print(f"wrote {PLAN_NAME}, plan.png and {len(tables)} tables to {claim.path}")
    return plan.to_json()
