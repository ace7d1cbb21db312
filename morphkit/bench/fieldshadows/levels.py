"""Section ``levels`` of ``morphkit bench scene``: the field's splat at per-instance point levels
against every atlas texel splatted, on the suite's fields (small or far casters get
coarser maps).

For each of the plan's instance counts and three field resolutions -- ``suite`` (the suite's own,
:func:`~morphkit.bench.fieldshadows.fields.field_tpu`: the atlases' texel), ``frame`` (the rule of a
billboard frame's map, :meth:`~morphkit.sunlit.receivers.AtlasShadow.resolution`: capped at
:data:`~morphkit.tol.SUN_FIELD_MAX_SIDE` a side, the smallest over the suns) and ``suite/4`` (a
field seen from four times as far) -- two builders of the same light view: ``splat-l0``
(:class:`~morphkit.sunlit.fieldsplat.SplatDrawer` ``(max_level=0)``, every atlas texel, the drawer
before levels) and ``splat-levels`` (the default drawer: each instance at the coarsest level whose
texel fits :data:`~morphkit.tol.SPLAT_LEVEL_MAX_TEXELS` field texels). Metrics: ``iou`` / ``iou_min``
/ ``mae`` against the ray cast on the suite's ground grid (as ``accuracy``), ``level_mean`` and
``coarse`` (the fraction of instances above level 0); ``ms`` a cold build (a new sun, the atlas's
levels already made), the two interleaved over the suns (:func:`~morphkit.bench.harness.time_cycling`),
medians; ``vs_l0`` the ratio to ``splat-l0``'s median.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...sunlit.fieldshadow import FieldShadow
from ...sunlit.fieldsplat import SplatDrawer
from ...sunlit.receivers import AtlasShadow
from ..harness import make_row, markdown_table, time_cycling
from .fields import SceneKit, day_suns, field_tpu, score

__all__ = ["levels_rows", "levels_table", "LEVEL_METHODS", "FAR_FACTOR"]

#: The two builders compared (module docstring).
LEVEL_METHODS = ("splat-l0", "splat-levels")
#: ``suite/4``: the suite's resolution divided by this.
FAR_FACTOR = 4.0


def _drawer(method: str) -> SplatDrawer:
    return SplatDrawer(max_level=0) if method == "splat-l0" else SplatDrawer()


def levels_rows(kit: SceneKit, plan: Any) -> list[dict[str, Any]]:
    """Level 0 against per-instance levels, IoU and time, per count and resolution (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases (its ``counts``, ``suns``, ``grid`` and ``change_repeats``).

    Returns
    -------
    list of dict
        One row per count, resolution and method.
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.suns)
    atl = kit.atlases()
    for n in plan.counts:
        fld = kit.field(n, plan.grid)
        frame = AtlasShadow(FieldShadow(atl))
        own = field_tpu(atl, fld.rect)
        res = {"suite": own, "frame": min(frame.resolution(fld.instances, s, fld.rect) for s in suns),
               "suite/4": own / FAR_FACTOR}
        for rname, tpu in res.items():
            drawers = {m: _drawer(m) for m in LEVEL_METHODS}
            fss = {m: FieldShadow(atl, d) for m, d in drawers.items()}
            fns = {m: kit.method("atlas", fss[m], fld, tpu, cold=True) for m in LEVEL_METHODS}
            got: dict[str, dict[str, list[float]]] = {m: {"iou": [], "mae": [], "level": [], "coarse": []}
                                                      for m in LEVEL_METHODS}
            side = 0
            for sun in suns:  # also makes the atlases' levels before the timing
                for m, fn in fns.items():
                    fm = fn(sun)
                    iou, mae, _ = score(fm, fld, sun)
                    lv = drawers[m].last_levels
                    got[m]["iou"].append(iou)
                    got[m]["mae"].append(mae)
                    got[m]["level"].append(float(lv.mean()) if len(lv) else 0.0)
                    got[m]["coarse"].append(float((lv > 0).mean()) if len(lv) else 0.0)
                    side = max(side, max(fm.camera.shape) if fm.camera is not None else 0)
            timings = time_cycling(fns, suns, repeats=plan.change_repeats * len(suns), warmup=1)
            base = timings["splat-l0"].ms_median
            for m in LEVEL_METHODS:
                g = got[m]
                metrics = {"iou": float(np.mean(g["iou"])), "iou_min": float(np.min(g["iou"])),
                           "mae": float(np.mean(g["mae"])), "level_mean": float(np.mean(g["level"])),
                           "coarse": float(np.mean(g["coarse"])), "tpu": float(tpu),
                           "field_side": float(side),
                           "vs_l0": timings[m].ms_median / base}
                params = {"section": "levels", "instances": n, "resolution": rname, "suns": len(suns),
                          "grid": plan.grid}
                note = "every atlas texel (the drawer before levels)" if m == "splat-l0" else (
                    f"IoU {metrics['iou'] - float(np.mean(got['splat-l0']['iou'])):+.4f} vs level 0")
                rows.append(make_row("scene", m, params, timings[m], metrics=metrics, note=note))
    return rows


def levels_table(rows: list[dict[str, Any]]) -> list[str]:
    """The section's markdown table (empty without its rows).

    Parameters
    ----------
    rows : list of dict
        Rows of the suite (other sections' are ignored).

    Returns
    -------
    list of str
        Lines: a title, a blank, the table, a blank.
    """
    lv = [r for r in rows if r["params"].get("section") == "levels"]
    if not lv:
        return []
    head = ["instances", "resolution (texels/unit)", "field side", "method", "coarse instances",
            "IoU mean / min", "vis. error", "ms a cold build", "ms / level 0"]
    lines = []
    for r in lv:
        m = r["metrics"]
        lines.append([str(r["params"]["instances"]), f"{r['params']['resolution']} ({m['tpu']:.1f})",
                      f"{m['field_side']:.0f}", r["method"],
                      f"{m['coarse']:.2f} (level {m['level_mean']:.2f})",
                      f"{m['iou']:.4f} / {m['iou_min']:.4f}", f"{m['mae']:.4f}", f"{r['ms_median']:.1f}",
                      f"{m['vs_l0']:.2f}"])
    return (["levels (the splat at level 0 against per-instance point levels; IoU against the ray cast, "
             "ms interleaved):", "", *markdown_table(head, lines), ""])
