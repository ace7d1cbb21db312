"""Suite ``scene``: a field's ground shadow from the sun atlases against the direct light
render, the impostor way and the ray cast, over a day's sun path.

Scene, methods and truth: :mod:`morphkit.bench.fieldshadows.fields` (two textured assets, the leaf plant
alpha-masked; random yaws; the receiver a ground grid over the field; truth the ray cast towards
the exact sun with the leaves' cut-outs; methods ``atlas``, ``direct``, ``card-camera``,
``card-light``). Metrics: ``iou`` -- shadow IoU (visibility < 0.5) against the ray cast, mean over
the suns (``iou_min`` the worst sun); ``mae`` -- mean absolute visibility error over the grid.

Sections (:data:`SECTIONS`, each ``(kit, plan) -> rows``; ``--sections`` picks some):

* ``accuracy`` -- 10, 100, 1000 instances under :func:`~morphkit.bench.fieldshadows.fields.day_suns`
  (a morning, 15 to 60 degrees up): every method's IoU and error; ``ms`` one build a sun (the
  atlas cold: cache emptied; not interleaved, the next section times). The atlas row carries
  ``iou_gain_card_camera`` / ``iou_gain_card_light`` (its mean IoU minus the card's) and a note
  on the targets (IoU >= 0.95; >= the impostor way + 0.15).
* ``per-asset`` -- ``accuracy`` on a field of one asset at a time (the plan's first count): where
  each method loses (the alpha-masked plant or the opaque crate).
* ``receivers`` -- the shadow on the instances themselves (their own and their neighbours'), the
  plan's ``receiver_counts``: points drawn on the posed meshes by area
  (:func:`~morphkit.bench.fieldshadows.fields.surface_receivers`, cut-out texels dropped), those
  facing the sun (:data:`~morphkit.bench.fieldshadows.resolution.SUN_FACING_COS`) looked up moved
  along their normal by
  :data:`~morphkit.tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS` field texels (as the billboard frames'
  receivers), the truth cast from them moved by :data:`~morphkit.tol.SUN_RAY_NORMAL_OFFSET`;
  IoU and error as ``accuracy``'s. A flat card's depth is where the impostor way loses here.
* ``sun-disc`` -- a soft sun: for the plan's radii and suns, ``avg-K`` (K field
  maps over the disc, :func:`~morphkit.sunlit.receivers.sun_disc`, averaged) and ``pcss`` (one
  map along the centre at :data:`~morphkit.tol.SUN_DISC_MAP_SCALE` times the field's texels, as
  :class:`~morphkit.sunlit.receivers.FilteredAtlasShadow` draws it, filtered:
  :func:`~morphkit.sunlit.sundisc.disc_visibility`) against the
  fraction of ``disc_truth`` directions the ray cast sees from each ground point; ``mae`` over
  the points the truth or the estimate do not see fully lit, ``banding``
  (:func:`~morphkit.bench.soft_suite.banding`), ``ms`` the maps and the lookups of a new sun.
* ``sun-change`` -- ms a sun change, 100 and 1000 instances, each asset subdivided to ~6k and
  >= 50k faces: ``atlas-cold`` (cache emptied, a new sun), ``atlas-warm`` (the same sun again
  right after: every view cached), ``direct`` (all posed meshes drawn from the sun; context
  warm); interleaved over distinct suns (:func:`~morphkit.bench.harness.time_cycling`), medians.
  ``vs_direct`` the ratio to the direct render of the same faces; ``flat`` max/min of the method's
  median over the face counts (target: the atlas at <= 1/10 of direct at >= 50k faces, flat <= 1.3).
* ``atlas-grid`` -- atlases over the sparse, default and dense domes at 64 and 128 texels on
  100 instances: IoU, error and bytes (``kib``, both assets), ``bake_s``; a ``direct`` row per
  texel size (the same view resolution).
* ``temporal`` -- the day's path in 24 suns (those above the horizon): per step, the fraction of
  ground points whose shadow flips (``step_median``, ``step_max``, ``spike`` = max/median, the
  target <= 2), and ``spike_vs_truth`` (max/median of the step over the ray cast's own step: the
  path's own unevenness taken out); ``spike_cutoff``: max/median over the steps between suns
  above the grazing cut-off (:data:`~morphkit.tol.SUN_MIN_ELEVATION_DEG`), where the atlas is not
  clamped; the atlas keeps its cache along the path (``ms``: a step).

* ``levels`` -- the splat at level 0 against per-instance point levels (small or far casters
  drawn from coarser atlas points), IoU and interleaved time at three field resolutions:
  :mod:`morphkit.bench.fieldshadows.levels`.
* ``receivers-resolution`` -- ``receivers`` at each of the plan's ``resolution_sizes`` (atlas
  texels a side), the atlas (with and without its quads) against the meshes drawn from the sun
  at the same resolution: :mod:`morphkit.bench.fieldshadows.resolution`.

``--quick``: 10 instances, 2 suns, a 160^2 grid, 64-texel atlases and 8 x 8-frame impostors
(no supersampling), faces 6k and 50k at 10 instances, 2 domes, 8 suns on the path, atlases of
64 and 128 texels in ``receivers-resolution``.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .. import tol
from ..sunlit.fieldbaselines import ray_cast_field
from ..sunlit.fieldshadow import FieldShadow
from ..sunlit.receivers import sun_disc
from ..sunlit.sundisc import disc_visibility
from ..validate import as_int
from .fieldshadows.fields import (
    ASSETS,
    DOMES,
    METHODS,
    Field,
    SceneKit,
    day_suns,
    field_tpu,
    path_suns,
    score,
    surface_receivers,
)
from .fieldshadows.levels import levels_rows, levels_table
from .fieldshadows.resolution import receivers_resolution_rows, receivers_resolution_table, surface_scores
from .harness import Timing, make_row, markdown_table, pick_sections, section_name, time_cycling
from .soft_suite import banding

__all__ = ["run", "SECTIONS", "ScenePlan", "FULL", "QUICK", "section_name", "selected_sections",
           "summary_tables", "SUITE", "FLOOR_METHOD", "PLOT_OPTIONS"]

#: The suite's name (``morphkit bench scene``).
SUITE = "scene"
#: The method the table's ratio column divides by.
FLOOR_METHOD = "direct"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite.
PLOT_OPTIONS: dict[str, Any] = {
    "size_key": "instances", "error_key": "mae", "panel_keys": ("section",),
    "scene_keys": ("section", "instances", "asset", "elevation_deg", "radius_deg"), "family": r"-\d+",
    "defaults": ({"method": "atlas", "texels": 128, "dome": "sparse"}, {"method": "pcss"}),
    "default_label": "default: atlas (21 views, 128 texels); pcss (the soft sun)"}

#: The targets the rows' notes say are met or not: IoU, gain over the impostor cards, time over
#: the direct render, flatness over face counts, the temporal spike.
TARGET_IOU, TARGET_GAIN, TARGET_SPEED, TARGET_FLAT, TARGET_SPIKE = 0.95, 0.15, 0.1, 1.3, 2.0


@dataclass(frozen=True)
class ScenePlan:
    """The cases of a run (:data:`FULL`, :data:`QUICK`).

    Parameters
    ----------
    counts : tuple of int
        Instance counts of ``accuracy``.
    suns : int
        Suns of ``accuracy`` (:func:`~morphkit.bench.fieldshadows.fields.day_suns`).
    grid : int
        Receiver points a side.
    atlas_size : int
        Atlas views' side (the impostor frames' too).
    impostor_frames, impostor_supersample : int
        The impostors' bake.
    change_counts, change_faces : tuple of int
        ``sun-change``'s instance counts and faces per asset.
    change_repeats : int
        Its timed rounds (one warm-up round first).
    grid_domes : tuple of str
        ``atlas-grid``'s domes (keys of :data:`~morphkit.bench.fieldshadows.fields.DOMES`).
    grid_sizes : tuple of int
        Its texels.
    grid_count, grid_suns : int
        Its instances and suns.
    path_suns, path_count : int
        ``temporal``'s suns (sunrise to sunset) and instances.
    receiver_counts : tuple of int
        ``receivers``' instance counts.
    receiver_points : int
        Its surface points drawn per asset.
    disc_count, disc_grid : int
        ``sun-disc``'s instances and ground points a side.
    disc_radii : tuple of float
        Its disc radii, degrees.
    disc_suns, disc_truth : int
        Its suns, and the directions over each disc its truth ray-casts.
    disc_averaged : tuple of int
        The map counts of its ``avg-K`` rows.
    resolution_sizes : tuple of int
        ``receivers-resolution``'s atlas texels a side.
    """

    counts: tuple[int, ...] = (10, 100, 1000)
    suns: int = 4
    grid: int = 512
    atlas_size: int = 128
    impostor_frames: int = 12
    impostor_supersample: int = 3
    change_counts: tuple[int, ...] = (100, 1000)
    change_faces: tuple[int, ...] = (6000, 50000)
    change_repeats: int = 3
    grid_domes: tuple[str, ...] = ("sparse", "default", "dense")
    grid_sizes: tuple[int, ...] = (64, 128)
    grid_count: int = 100
    grid_suns: int = 2
    path_suns: int = 24
    path_count: int = 100
    receiver_counts: tuple[int, ...] = (10, 100)
    receiver_points: int = 40000
    disc_count: int = 30
    disc_grid: int = 256
    disc_radii: tuple[float, ...] = (0.267, 1.0, 2.0, 4.0)
    disc_suns: int = 2
    disc_truth: int = 64
    disc_averaged: tuple[int, ...] = (4, 8, 16)
    resolution_sizes: tuple[int, ...] = (128, 256, 512)


#: The full run's cases.
FULL = ScenePlan()
#: ``--quick``'s cases (a short run).
QUICK = ScenePlan(counts=(10,), suns=2, grid=160, atlas_size=64, impostor_frames=8, impostor_supersample=1,
                  change_counts=(10,), change_repeats=2, grid_domes=("sparse", "default"), grid_sizes=(64,),
                  grid_count=10, grid_suns=1, path_suns=8, path_count=10, receiver_counts=(10,),
                  receiver_points=4000, disc_count=10, disc_grid=96, disc_radii=(2.0,), disc_suns=1,
                  disc_truth=16, disc_averaged=(4,), resolution_sizes=(64, 128))


def _summary(vals: list[float]) -> tuple[float, float]:
    return float(np.mean(vals)), float(np.min(vals))


def _met(ok: bool) -> str:
    return "met" if ok else "NOT met"


def _method_rows(got: dict[str, dict[str, list[float]]], params: dict[str, Any], note: str, *,
                 target_iou: bool, extra: dict[str, dict[str, float]] | None = None) -> list[dict[str, Any]]:
    """One row per method from its per-sun ``iou``, ``mae`` and ``s``; the atlas's row carries its
    IoU gains over the cards and the note on the targets."""
    mean_iou = {m: float(np.mean(got[m]["iou"])) for m in METHODS}
    rows = []
    for m in METHODS:
        iou, iou_min = _summary(got[m]["iou"])
        metrics = {"iou": iou, "iou_min": iou_min, "mae": float(np.mean(got[m]["mae"])),
                   **(extra or {}).get(m, {})}
        text = note + (", cache emptied" if m == "atlas" and target_iou else "")
        if m == "atlas":
            gains = {c: iou - mean_iou[c] for c in ("card-camera", "card-light")}
            metrics.update(iou_gain_card_camera=gains["card-camera"], iou_gain_card_light=gains["card-light"])
            text = ""
            if target_iou:
                text = f"IoU >= {TARGET_IOU}: {_met(iou >= TARGET_IOU)} (min {iou_min:.3f}); "
            text += (f">= card-camera + {TARGET_GAIN}: {_met(gains['card-camera'] >= TARGET_GAIN)}; "
                     f">= card-light + {TARGET_GAIN}: {_met(gains['card-light'] >= TARGET_GAIN)}")
        rows.append(make_row(SUITE, m, params, Timing.from_seconds(got[m]["s"]), metrics=metrics, note=text))
    return rows


def accuracy_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """Every method's IoU and error per instance count (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One row per method and count, and the ray cast's time.
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.suns)
    kit.impostors()  # baked before any timing
    for n in plan.counts:
        params = {"section": "accuracy", "instances": n, "suns": len(suns), "grid": plan.grid}
        rows += _accuracy_case(kit, kit.field(n, plan.grid), suns, params)
    return rows


def per_asset_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """``accuracy`` on a field of one asset at a time, the first count of the plan (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One row per asset and method, and the ray cast's time.
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.suns)
    kit.impostors()
    n = plan.counts[0]
    for asset in ASSETS:
        params = {"section": "per-asset", "asset": asset, "instances": n, "suns": len(suns),
                  "grid": plan.grid}
        rows += _accuracy_case(kit, kit.field(n, plan.grid, (asset,)), suns, params)
    return rows


def _accuracy_case(kit: SceneKit, fld: Field, suns: list[np.ndarray], params: dict[str, Any]
                   ) -> list[dict[str, Any]]:
    """Every method's IoU, error and build time on one field under the suns."""
    rows: list[dict[str, Any]] = []
    atl = kit.atlases()
    fs = FieldShadow(atl)
    tpu = field_tpu(atl, fld.rect)
    fns = {m: kit.method(m, fs, fld, tpu) for m in METHODS}
    fns["direct"](suns[0])  # the renderer's context at the view's size
    got: dict[str, dict[str, list[float]]] = {m: {"iou": [], "mae": [], "s": []} for m in METHODS}
    truth_s, side = [], 0
    for sun in suns:
        t0 = time.perf_counter()
        fld.truth(sun)
        truth_s.append(time.perf_counter() - t0)
        for m, fn in fns.items():
            t0 = time.perf_counter()
            fm = fn(sun)
            got[m]["s"].append(time.perf_counter() - t0)
            iou, mae, _ = score(fm, fld, sun)
            got[m]["iou"].append(iou)
            got[m]["mae"].append(mae)
            side = max(side, max(fm.camera.shape) if fm.camera is not None else 0)
    extra = {m: {"mae_max": float(np.max(got[m]["mae"])), "tpu": tpu, "field_side": side} for m in METHODS}
    rows += _method_rows(got, params, "one build a sun", target_iou=True, extra=extra)
    rows.append(make_row(SUITE, "ray-cast", params, Timing.from_seconds(truth_s),
                         note="the truth: Embree, the leaves' cut-outs honoured"))
    return rows


def receivers_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """Every method's IoU and error on the instances' own surfaces (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One row per method and count (``ms``: a build and the points' lookup, one a sun).
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.suns)
    kit.impostors()
    atl = kit.atlases()
    for n in plan.receiver_counts:
        fld = kit.field(n, plan.grid)
        pts, nrm = surface_receivers(fld, plan.receiver_points, np.random.default_rng(kit.seed + n))
        fs = FieldShadow(atl)
        tpu = field_tpu(atl, fld.rect)
        fns = {m: kit.method(m, fs, fld, tpu) for m in METHODS}
        got, used = surface_scores(fld, pts, nrm, suns, fns, tpu)
        params = {"section": "receivers", "instances": n, "suns": len(suns), "points": int(np.median(used))}
        rows += _method_rows(got, params, "ms: a build and the lookup", target_iou=False)
    return rows


def sun_change_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """Time of a sun change, atlas against the direct render, per count and faces (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        ``atlas-cold``, ``atlas-warm``, ``direct`` per count and face count.
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.change_repeats + 1)[::-1]  # distinct suns: the warm-up round and each timed one
    for n in plan.change_counts:
        fld = kit.field(n, plan.grid)
        tpu = field_tpu(kit.atlases(), fld.rect)
        fns: dict[str, Callable[[np.ndarray], Any]] = {}
        for f in plan.change_faces:
            fs = FieldShadow(kit.atlases(f))
            fns[f"atlas-cold@{f}"] = kit.method("atlas", fs, fld, tpu, f, cold=True)
            fns[f"atlas-warm@{f}"] = kit.method("atlas", fs, fld, tpu, f, cold=False)  # right after the cold
            fns[f"direct@{f}"] = kit.method("direct", fs, fld, tpu, f)
        timings = time_cycling(fns, suns, repeats=plan.change_repeats, warmup=1)
        for m in ("atlas-cold", "atlas-warm", "direct"):
            meds = [timings[f"{m}@{f}"].ms_median for f in plan.change_faces]
            flat = max(meds) / max(min(meds), tol.ZERO)
            for f in plan.change_faces:
                t, d = timings[f"{m}@{f}"], timings[f"direct@{f}"]
                metrics = {"vs_direct": t.ms_median / d.ms_median, "flat": flat,
                           "faces_min": float(min(len(mm.faces) for mm in kit.meshes(f).values()))}
                note = ""
                if m == "atlas-cold" and f == max(plan.change_faces):
                    note = (f"<= {TARGET_SPEED} x direct: {_met(metrics['vs_direct'] <= TARGET_SPEED)}; "
                            f"flat <= {TARGET_FLAT}: {_met(flat <= TARGET_FLAT)}")
                rows.append(make_row(SUITE, m, {"section": "sun-change", "instances": n, "faces": f}, t,
                                     metrics=metrics, note=note))
    return rows


def atlas_grid_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """Atlas grid vs error vs bytes on one field (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One ``atlas`` row per dome and texels, one ``direct`` row per texels.
    """
    rows: list[dict[str, Any]] = []
    fld = kit.field(plan.grid_count, plan.grid)
    suns = day_suns(plan.grid_suns)
    for size in plan.grid_sizes:
        fs = None
        tpu = 0.0
        for dome in plan.grid_domes:
            atl = kit.atlases(None, dome, size)
            fs = FieldShadow(atl)
            tpu = field_tpu(atl, fld.rect)
            fn = kit.method("atlas", fs, fld, tpu)
            ious, maes, secs = [], [], []
            for sun in suns:
                t0 = time.perf_counter()
                fm = fn(sun)
                secs.append(time.perf_counter() - t0)
                iou, mae, _ = score(fm, fld, sun)
                ious.append(iou)
                maes.append(mae)
            iou, iou_min = _summary(ious)
            rows.append(make_row(SUITE, "atlas", {"section": "atlas-grid", "instances": plan.grid_count,
                                                  "texels": size, "dome": dome}, Timing.from_seconds(secs),
                                 metrics={"views": float(DOMES[dome].views), "iou": iou, "iou_min": iou_min,
                                          "mae": float(np.mean(maes)),
                                          "kib": sum(a.nbytes for a in atl.values()) / 1024.0,
                                          "bake_s": kit.bake_seconds[(None, dome, size)]},
                                 note="both assets' atlases; ms: a cold build a sun"))
        assert fs is not None
        direct = kit.method("direct", fs, fld, tpu)
        direct(suns[0])
        ious, maes, secs = [], [], []
        for sun in suns:
            t0 = time.perf_counter()
            fm = direct(sun)
            secs.append(time.perf_counter() - t0)
            iou, mae, _ = score(fm, fld, sun)
            ious.append(iou)
            maes.append(mae)
        iou, iou_min = _summary(ious)
        rows.append(make_row(SUITE, "direct", {"section": "atlas-grid", "instances": plan.grid_count,
                                               "texels": size, "dome": "-"}, Timing.from_seconds(secs),
                             metrics={"iou": iou, "iou_min": iou_min, "mae": float(np.mean(maes))},
                             note="the same view resolution"))
    return rows


def _steps(masks: list[np.ndarray]) -> np.ndarray:
    return np.array([float(np.mean(a != b)) for a, b in zip(masks[:-1], masks[1:], strict=True)])


def sun_disc_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """A soft sun: K maps over the disc averaged against one map filtered (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One row per sun, radius and method (and the truth's time).
    """
    rows: list[dict[str, Any]] = []
    atl = kit.atlases()
    fld = kit.field(plan.disc_count, plan.disc_grid)
    fs = FieldShadow(atl)
    tpu = field_tpu(atl, fld.rect)
    tpu_disc = field_tpu(atl, fld.rect, tol.SUN_DISC_MAP_SCALE)  # the filtered disc's own map
    g = plan.disc_grid
    for sun in day_suns(plan.disc_suns):
        for radius in plan.disc_radii:
            t0 = time.perf_counter()
            seen = [ray_cast_field(fld.meshes, fld.instances, d, fld.points, posed=fld.posed)
                    for d in sun_disc(sun, plan.disc_truth, radius)]
            truth = np.mean(seen, axis=0)
            truth_s = time.perf_counter() - t0
            params = {"section": "sun-disc", "instances": plan.disc_count, "grid": g, "radius_deg": radius,
                      "elevation_deg": round(float(np.degrees(np.arcsin(sun[2]))), 1)}
            for k in (*plan.disc_averaged, 0):
                times, est = [], np.ones(len(fld.points), np.float32)
                for _ in range(2):  # the second is timed too: both are new builds (cache emptied)
                    fs.clear()
                    t0 = time.perf_counter()
                    if k:
                        maps = [fs.build(fld.instances, d, tpu, fld.rect) for d in sun_disc(sun, k, radius)]
                        est = np.mean([m.visibility(fld.points) for m in maps], axis=0)
                    else:
                        m = fs.build(fld.instances, sun, tpu_disc, fld.rect)
                        est = (disc_visibility(fld.points, m.depth, m.camera, radius) if m.camera is not None
                               else np.ones(len(fld.points), np.float32))
                    times.append(time.perf_counter() - t0)
                region = (truth < 1.0 - tol.PENUMBRA_EPS) | (est < 1.0 - tol.PENUMBRA_EPS)
                mae = float(np.abs(est - truth)[region].mean()) if region.any() else 0.0
                metrics = {"mae": mae, "banding": banding(est.reshape(g, g), truth.reshape(g, g))}
                rows.append(make_row(SUITE, f"avg-{k}" if k else "pcss", params, Timing.from_seconds(times),
                                     metrics=metrics, note="maps and lookups, a new sun"))
            rows.append(make_row(SUITE, "ray-cast", params, Timing.from_seconds([truth_s]),
                                 note=f"the truth: {plan.disc_truth} directions over the disc"))
    return rows


def temporal_rows(kit: SceneKit, plan: ScenePlan) -> list[dict[str, Any]]:
    """Shadow change per step along the day's path (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases.

    Returns
    -------
    list of dict
        One row per method and the ray cast.
    """
    fld = kit.field(plan.path_count, plan.grid)
    suns, elev = path_suns(plan.path_suns)
    up = [s for s, e in zip(suns, elev, strict=True) if e > 0.0]
    high = elev[elev > 0.0] >= tol.SUN_MIN_ELEVATION_DEG
    high_steps = high[:-1] & high[1:]  # steps between two suns above the grazing cut-off
    atl = kit.atlases()
    kit.impostors()
    fs = FieldShadow(atl)
    tpu = field_tpu(atl, fld.rect)
    fns = {m: kit.method(m, fs, fld, tpu, cold=False) for m in METHODS}  # the atlas keeps its cache
    fns["direct"](up[0])
    masks: dict[str, list[np.ndarray]] = {m: [] for m in (*METHODS, "ray-cast")}
    ious: dict[str, list[float]] = {m: [] for m in METHODS}
    secs: dict[str, list[float]] = {m: [] for m in (*METHODS, "ray-cast")}
    for sun in up:
        t0 = time.perf_counter()
        masks["ray-cast"].append(fld.truth(sun) < 0.5)
        secs["ray-cast"].append(time.perf_counter() - t0)
        for m, fn in fns.items():
            t0 = time.perf_counter()
            fm = fn(sun)
            secs[m].append(time.perf_counter() - t0)
            iou, _, shadow = score(fm, fld, sun)
            ious[m].append(iou)
            masks[m].append(shadow)
    truth_steps = _steps(masks["ray-cast"])
    rows = []
    params = {"section": "temporal", "instances": plan.path_count, "suns": len(up), "grid": plan.grid}
    for m in (*METHODS, "ray-cast"):
        st = _steps(masks[m])
        med = float(np.median(st))
        rel = st / np.maximum(truth_steps, 1.0 / len(fld.points))
        metrics = {"step_median": med, "step_max": float(st.max()),
                   "spike": float(st.max()) / max(med, tol.ZERO),
                   "spike_vs_truth": float(rel.max()) / max(float(np.median(rel)), tol.ZERO)}
        if high_steps.any():
            sh = st[high_steps]
            metrics["spike_cutoff"] = float(sh.max()) / max(float(np.median(sh)), tol.ZERO)
        if m in ious:
            metrics.update(iou=float(np.mean(ious[m])), iou_min=float(np.min(ious[m])))
        note = f"spike <= {TARGET_SPIKE}: {_met(metrics['spike'] <= TARGET_SPIKE)}"
        if m == "ray-cast":
            note = "the truth's own steps: the path's unevenness"
        if m == "atlas":
            note += "; cache kept along the path (ms: a step)"
        rows.append(make_row(SUITE, m, params, Timing.from_seconds(secs[m]), metrics=metrics, note=note))
    return rows


#: The suite's sections, in order; each ``(kit, plan) -> rows``.
SECTIONS: list[Callable[[SceneKit, ScenePlan], list[dict[str, Any]]]] = [
    accuracy_rows, per_asset_rows, receivers_rows, sun_change_rows, atlas_grid_rows, temporal_rows,
    sun_disc_rows, levels_rows, receivers_resolution_rows]


Section = Callable[[SceneKit, ScenePlan], list[dict[str, Any]]]


def selected_sections(names: str | None = None) -> list[Section]:
    """The sections named in ``names`` (comma-separated), in :data:`SECTIONS` order; all when empty.

    Parameters
    ----------
    names : str, optional
        E.g. ``"accuracy,temporal"``.

    Returns
    -------
    list of callable
        The sections.

    Raises
    ------
    ValidationError
        A name that is not a section's.
    """
    return pick_sections(names, SECTIONS)




def _iou(m: dict[str, float]) -> str:
    return f"{m['iou']:.3f} / {m['iou_min']:.3f}" if "iou" in m else "-"


def summary_tables(rows: list[dict[str, Any]]) -> str:
    """Markdown tables of the rows, one per section present (for ``docs/results/field_shadows.md``).

    Parameters
    ----------
    rows : list of dict
        Rows of this suite.

    Returns
    -------
    str
        The tables, each after a line naming its section.
    """
    def of(section: str) -> list[dict[str, Any]]:
        return [r for r in rows if r["params"].get("section") == section]

    out: list[str] = []
    acc = [r for r in of("accuracy") if r["method"] != "ray-cast"]
    if acc:
        out += ["accuracy (shadow IoU against the ray cast, mean / min over the suns):", ""]
        out += markdown_table(["instances", "method", "IoU mean / min", "vis. error", "ms a build"],
                              [[str(r["params"]["instances"]), r["method"], _iou(r["metrics"]),
                                f"{r['metrics']['mae']:.4f}", f"{r['ms_median']:.0f}"] for r in acc]) + [""]
    rec = of("receivers")
    if rec:
        out += ["receivers (the instances' own sun-facing surfaces; IoU mean / min over the suns):", ""]
        out += markdown_table(["instances", "points", "method", "IoU mean / min", "vis. error"],
                              [[str(r["params"]["instances"]), str(r["params"]["points"]), r["method"],
                                _iou(r["metrics"]), f"{r['metrics']['mae']:.4f}"] for r in rec]) + [""]
    per = [r for r in of("per-asset") if r["method"] != "ray-cast"]
    if per:
        out += ["per asset (one asset's field; IoU mean / min over the suns):", ""]
        out += markdown_table(["asset", "instances", "method", "IoU mean / min", "vis. error"],
                              [[r["params"]["asset"], str(r["params"]["instances"]), r["method"],
                                _iou(r["metrics"]), f"{r['metrics']['mae']:.4f}"] for r in per]) + [""]
    change = of("sun-change")
    if change:
        cases = list(dict.fromkeys((r["params"]["instances"], r["params"]["faces"]) for r in change))
        ms = {(r["params"]["instances"], r["params"]["faces"], r["method"]): r for r in change}
        lines = []
        for n, f in cases:
            c, w, d = (ms[(n, f, m)] for m in ("atlas-cold", "atlas-warm", "direct"))
            lines.append([str(n), str(f), f"{c['ms_median']:.0f}", f"{w['ms_median']:.1f}",
                          f"{d['ms_median']:.0f}", f"{c['metrics']['vs_direct']:.2f}",
                          f"{w['metrics']['vs_direct']:.3f}", f"{c['metrics']['flat']:.2f}",
                          f"{d['metrics']['flat']:.2f}"])
        out += ["sun change (ms, medians, interleaved):", ""]
        out += markdown_table(["instances", "faces an asset", "atlas cold", "atlas warm", "direct",
                               "cold / direct", "warm / direct", "atlas flat", "direct flat"], lines) + [""]
    disc = [r for r in of("sun-disc") if r["method"] != "ray-cast"]
    if disc:
        out += ["sun disc (a soft sun: K maps averaged or one filtered; error over shadow and penumbra):", ""]
        out += markdown_table(["sun elevation", "disc radius", "method", "mae", "banding", "ms"],
                   [[f"{r['params']['elevation_deg']:g}", f"{r['params']['radius_deg']:g}", r["method"],
                     f"{r['metrics']['mae']:.4f}", f"{r['metrics']['banding']:.4f}", f"{r['ms_median']:.0f}"]
                    for r in disc]) + [""]
    grid = of("atlas-grid")
    if grid:
        out += ["atlas grid vs error vs bytes:", ""]
        lines = []
        for r in grid:
            m = r["metrics"]
            what = f"{r['params']['dome']} ({m['views']:.0f})" if r["method"] == "atlas" else "direct"
            lines.append([str(r["params"]["texels"]), what, f"{m['kib']:.0f}" if "kib" in m else "-",
                          _iou(m), f"{m['mae']:.4f}", f"{r['ms_median']:.0f}"])
        out += markdown_table(["texels", "dome (views)", "KiB", "IoU mean / min", "vis. error",
                               "ms a cold build"], lines) + [""]
    temporal = of("temporal")
    if temporal:
        out += ["temporal (fraction of ground points whose shadow flips a step):", ""]
        lines = []
        for r in temporal:
            m = r["metrics"]
            cut = f"{m['spike_cutoff']:.2f}" if "spike_cutoff" in m else "-"
            lines.append([r["method"], f"{m['step_median']:.4f}", f"{m['step_max']:.4f}", f"{m['spike']:.2f}",
                          cut, f"{m['spike_vs_truth']:.2f}", _iou(m)])
        out += markdown_table(["method", "step median", "step max", "max / median",
                               "max / median above the cut-off", "max / median over the ray cast's",
                               "IoU mean / min"], lines) + [""]
    out += levels_table(rows)
    out += receivers_resolution_table(rows)
    return "\n".join(out)


def run(*, quick: bool = False, sections: str | None = None, instances: list[int] | None = None,
        suns: int | None = None, plan: ScenePlan | None = None) -> list[dict[str, Any]]:
    """Run the sections (module docstring).

    Parameters
    ----------
    quick : bool
        The small plan (:data:`QUICK`).
    sections : str, optional
        Comma-separated section names; all when None.
    instances : list of int, optional
        Instance counts of ``accuracy`` and ``sun-change`` (``morphkit bench scene --instances``).
    suns : int, optional
        Suns of ``accuracy``.
    plan : ScenePlan, optional
        The cases in full (overrides ``quick``).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    # a bad count or name fails before any work
    counts = tuple(as_int(v, "instances", lo=1, hi=tol.MAX_BENCH_INSTANCES) for v in instances or ())
    chosen = selected_sections(sections)
    p = plan if plan is not None else (QUICK if quick else FULL)
    if counts:
        p = replace(p, counts=counts, change_counts=counts)
    if suns is not None:
        p = replace(p, suns=int(suns))
    rows: list[dict[str, Any]] = []
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder, Renderer() as r:
        kit = SceneKit(r, folder, atlas_size=p.atlas_size, impostor_frames=p.impostor_frames,
                       impostor_supersample=p.impostor_supersample)
        for section in chosen:
            rows += section(kit, p)
    print(summary_tables(rows))
    print(f"scene suite: {len(rows)} rows in {time.perf_counter() - t0:.0f} s", flush=True)
    return rows
