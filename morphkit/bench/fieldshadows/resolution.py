"""Section ``receivers-resolution`` of ``morphkit bench scene``: the shadow on the instances' own
surfaces against the field map's resolution (why the ``receivers`` IoU stays under the
ground's).

The ``receivers`` section scores the atlas and the direct render at the suite's one resolution (the
atlases' texel, :func:`~morphkit.bench.fieldshadows.fields.field_tpu`). Here the same surface points, suns
and ray-cast truth (:func:`surface_scores`) are scored for each of the plan's
``resolution_sizes``: the atlases baked at that many texels a side (``atlas``), and the meshes
rendered from the sun into a map of the same texels a unit (``direct``: the best any map of that
resolution can do, with the same lookup and normal offset), and ``atlas-squares``: the atlas
drawn with squares only (``SplatDrawer(quads=False)``, the drawer before its quads,
:mod:`morphkit.sunlit.fieldsplat`). Metrics: ``iou`` / ``iou_min`` (the
worst sun), ``mae``, ``tpu`` (field texels a unit), ``kib`` (both assets' atlases); ``ms`` a build
and the lookup, one a sun.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ... import tol
from ...imaging.metrics import shadow_iou
from ...sunlit.fieldbaselines import ray_cast_field
from ...sunlit.fieldshadow import FieldMap, FieldShadow
from ...sunlit.fieldsplat import SplatDrawer
from ..harness import Timing, make_row, markdown_table
from .fields import Field, SceneKit, day_suns, field_tpu, surface_receivers

__all__ = ["surface_scores", "receivers_resolution_rows", "receivers_resolution_table", "SUN_FACING_COS",
           "RESOLUTION_METHODS"]

#: A surface point receives when its normal is at least this cosine towards the sun (84 degrees):
#: one facing away is shadowed by its own body whatever the method (a card's two sides are two
#: faces, one of them kept).
SUN_FACING_COS = 0.1

#: The ways of making the map compared at each resolution (module docstring).
RESOLUTION_METHODS = ("atlas", "atlas-squares", "direct")


def surface_scores(fld: Field, points: np.ndarray, normals: np.ndarray, suns: list[np.ndarray],
                   fns: dict[str, Callable[[np.ndarray], FieldMap]], tpu: float
                   ) -> tuple[dict[str, dict[str, list[float]]], list[int]]:
    """IoU, error and time of each method's map on the sun-facing surface points, a sun at a time.

    A point faces a sun when its normal's cosine towards it is at least :data:`SUN_FACING_COS`;
    the truth is Embree's ray cast from the point moved by :data:`~morphkit.tol.SUN_RAY_NORMAL_OFFSET`
    along its normal; each map is looked up at the point moved by
    :data:`~morphkit.tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS` texels of ``tpu`` along it.

    Parameters
    ----------
    fld : Field
        The field (its meshes and instances cast the truth).
    points, normals : (M, 3) float
        Surface points and their unit normals, world frame
        (:func:`~morphkit.bench.fieldshadows.fields.surface_receivers`).
    suns : list of (3,) float
        Unit directions towards the sun.
    fns : dict of str to callable
        ``sun -> FieldMap`` per method.
    tpu : float
        The maps' texels a unit (the normal offset's unit).

    Returns
    -------
    scores : dict of str to dict
        Per method, lists ``iou``, ``mae`` and ``s`` (seconds: the build and the lookup), one a sun.
    used : list of int
        The points facing each sun.
    """
    got: dict[str, dict[str, list[float]]] = {m: {"iou": [], "mae": [], "s": []} for m in fns}
    used = []
    for sun in suns:
        facing = normals @ np.asarray(sun, np.float64) >= SUN_FACING_COS
        p, q = points[facing], normals[facing]
        used.append(int(facing.sum()))
        truth = ray_cast_field(fld.meshes, fld.instances, sun, p + tol.SUN_RAY_NORMAL_OFFSET * q,
                               posed=fld.posed)
        looked = p + (tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS / tpu) * q
        for m, fn in fns.items():
            t0 = time.perf_counter()
            vis = fn(sun).visibility(looked)
            got[m]["s"].append(time.perf_counter() - t0)
            got[m]["iou"].append(shadow_iou(vis < 0.5, truth < 0.5))
            got[m]["mae"].append(float(np.abs(vis - truth).mean()))
    return got, used


def receivers_resolution_rows(kit: SceneKit, plan: Any) -> list[dict[str, Any]]:
    """The surfaces' IoU per atlas size and per direct map of the same resolution (module docstring).

    Parameters
    ----------
    kit : SceneKit
        Assets and fields.
    plan : ScenePlan
        The cases (its ``receiver_counts``, ``receiver_points``, ``suns``, ``grid`` and
        ``resolution_sizes``).

    Returns
    -------
    list of dict
        One row per count, size and method.
    """
    rows: list[dict[str, Any]] = []
    suns = day_suns(plan.suns)
    for n in plan.receiver_counts:
        fld = kit.field(n, plan.grid)
        pts, nrm = surface_receivers(fld, plan.receiver_points, np.random.default_rng(kit.seed + n))
        for size in plan.resolution_sizes:
            atl = kit.atlases(None, "sparse", size)
            fs = FieldShadow(atl)
            tpu = field_tpu(atl, fld.rect)
            fns = {m: kit.method(m, fs, fld, tpu) for m in ("atlas", "direct")}
            fns["atlas-squares"] = kit.method("atlas", FieldShadow(atl, SplatDrawer(quads=False)), fld, tpu)
            got, used = surface_scores(fld, pts, nrm, suns, fns, tpu)
            side = max(fns["atlas"](suns[0]).camera.shape)
            for m in RESOLUTION_METHODS:
                g = got[m]
                metrics = {"iou": float(np.mean(g["iou"])), "iou_min": float(np.min(g["iou"])),
                           "mae": float(np.mean(g["mae"])), "tpu": float(tpu), "field_side": float(side),
                           "kib": sum(a.nbytes for a in atl.values()) / 1024.0 if m != "direct" else 0.0}
                params = {"section": "receivers-resolution", "instances": n, "texels": size,
                          "suns": len(suns), "points": int(np.median(used))}
                note = {"atlas": "both assets' atlases", "atlas-squares": "the atlases drawn as squares only",
                        "direct": "the meshes drawn at its resolution"}[m]
                rows.append(make_row("scene", m, params, Timing.from_seconds(g["s"]), metrics=metrics,
                                     note=note + "; ms: a build and the lookup"))
    return rows


def receivers_resolution_table(rows: list[dict[str, Any]]) -> list[str]:
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
    rr = [r for r in rows if r["params"].get("section") == "receivers-resolution"]
    if not rr:
        return []
    head = ["instances", "atlas texels", "texels/unit", "field side", "method", "KiB", "IoU mean / min",
            "vis. error", "ms"]
    lines = []
    for r in rr:
        m, p = r["metrics"], r["params"]
        lines.append([str(p["instances"]), str(p["texels"]), f"{m['tpu']:.1f}", f"{m['field_side']:.0f}",
                      r["method"], f"{m['kib']:.0f}" if m["kib"] else "-",
                      f"{m['iou']:.3f} / {m['iou_min']:.3f}", f"{m['mae']:.4f}", f"{r['ms_median']:.0f}"])
    return (["receivers by resolution (the instances' own sun-facing surfaces; atlas against the meshes "
             "drawn at its resolution):", "", *markdown_table(head, lines), ""])
