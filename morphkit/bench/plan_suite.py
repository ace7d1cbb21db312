"""``morphkit bench plan``: a frame's error predicted from the error tables, against measuring it.

The scene: a tree ring asset (8 views, 64 px; the tree sample mesh, normalised) and seven
instances 4 to 13 units from the camera (23 to 72 px high), random yaws, seen by a 50-degree
320 x 240 camera from eye heights giving elevations of 5 to 32 degrees, between the tables' bins.
For the classic card and the ring morph:

* ``what=table``: :func:`~morphkit.plan.errortable.measure_error_table` over 4 heights (16 to
  128 px) x 6 elevations x 3 azimuths (the bake-time cost of one table);
* ``what=predict``, per eye height: ``predict_<mode>`` times
  :func:`~morphkit.plan.predict.predict_frame_error` and carries the predicted mean per-billboard
  box PSNR and silhouette IoU and their gaps to the measured (``gap_db``, ``gap_iou``);
  ``measure_<mode>`` times the measurement itself (the mode's frame, the real meshes' frame and
  the per-billboard errors, as :func:`~morphkit.billboard.compare.compare_modes`) and carries the
  measured figures. The truth is the real meshes' frame (:class:`~morphkit.billboard.MeshMode`).
* ``what=planning``, per instance count (1,000 and 100,000 trees scattered on the field their count
  needs, :func:`~morphkit.billboard.place_random`; 10,000 with ``--quick``): ``plan_<n>`` times the
  planner proper with warm tables, :func:`~morphkit.plan.planner.predict_frames` over the 36 frames of
  the ``flyover`` path at 640 x 480 and :func:`~morphkit.plan.planner.choose` to a 22 dB budget. Its
  tables are of constant figures (the planner's time does not depend on them): the row times the
  planning, not its error. A scene over :data:`morphkit.tol.PLAN_MAX_INSTANCES` instances is
  predicted from a sample of that many, which the row's ``drawn`` (billboards predicted) shows.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..billboard import (
    BAKE_AMBIENT,
    BillboardScene,
    ClassicMode,
    Instances,
    MeshMode,
    MorphCache,
    MorphMode,
    bake_asset,
    bake_lights,
)
from ..billboard.compare import box_errors, mean_errors
from ..billboard.frames.instances import place_random
from ..billboard.frames.paths import make_path
from ..camera import look_at, perspective
from ..meshes import normalize, sample_mesh
from ..plan import Budget, ErrorTable, measure_error_table, predict_frame_error
from ..plan.planner import choose, predict_frames
from ..render import Renderer
from .harness import make_row, time_call

__all__ = ["run", "FLOOR_METHOD", "PLOT_OPTIONS"]

SUITE = "plan"
#: The method the table's ratio column divides by: measuring the morph's frame error.
FLOOR_METHOD = "measure_morph"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS = {"size_key": "eye_z", "panel_keys": ("what",), "error_key": "gap_db"}

SHAPE = (240, 320)
YFOV_DEG = 50.0


def _scene(asset: Any) -> BillboardScene:
    ang = np.radians([-24, -15, -7, 0, 8, 16, 25])
    dist = np.array([4.0, 6.5, 9.0, 5.0, 11.0, 7.5, 13.0])
    xy = np.stack([dist * np.sin(ang), dist * np.cos(ang) - 2.0], 1)
    yaw = np.random.default_rng(1).uniform(0, 360, len(xy))
    inst = Instances(("tree",), np.zeros(len(xy), np.int64), xy, yaw, np.ones(len(xy)))
    return BillboardScene({"tree": asset}, inst)


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """The suite's rows (module notes).

    Parameters
    ----------
    quick : bool
        One eye height, one repeat and tables of two heights instead of three, five and four.

    Returns
    -------
    list of dict
        Rows of :func:`~morphkit.bench.harness.make_row`.
    """
    rows: list[dict[str, Any]] = []
    repeats = 1 if quick else 5
    heights = (1.6,) if quick else (1.6, 2.2, 3.0)
    bins = (16.0, 64.0) if quick else (16.0, 32.0, 64.0, 128.0)
    fy = SHAPE[0] / (2.0 * np.tan(np.radians(YFOV_DEG) / 2.0))
    with Renderer() as r:
        mesh = normalize(sample_mesh("tree"))
        asset = bake_asset(mesh, r, name="tree", views=8, size=64, levels=2)
        items = asset.items(mesh)
        modes = {"classic": ClassicMode(), "morph": MorphMode(MorphCache())}
        truth = MeshMode(r, {"tree": items}, bake_lights(), BAKE_AMBIENT)
        tables = {}
        for nm, mode in modes.items():
            params = {"what": "table", "mode": nm, "heights": len(bins), "elevations": 6, "azimuths": 3}

            def table(nm: str = nm, mode: Any = mode) -> Any:
                return measure_error_table(asset, items, r, mode, None, heights_px=bins,
                                           focal_px=fy, representation=f"ring-{nm}-64", params={"views": 8})

            tables[nm] = table()
            rows.append(make_row(SUITE, f"table_{nm}", params, time_call(table, repeats=1, warmup=0)))
        scene = _scene(asset)
        for eye_z in heights:
            cam = perspective(np.radians(YFOV_DEG), SHAPE, look_at([0.0, -2.0, eye_z], [0.0, 7.0, 0.0]),
                              znear=0.1, zfar=200.0)
            for nm, mode in modes.items():
                params = {"what": "predict", "mode": nm, "eye_z": eye_z}

                def measure(mode: Any = mode, cam: Any = cam) -> dict[str, float]:
                    return mean_errors(box_errors(scene.render(cam, mode), scene.render(cam, truth)))

                def predict(nm: str = nm, cam: Any = cam) -> dict[str, float]:
                    return predict_frame_error({"tree": tables[nm]}, scene, cam)

                got = measure()
                pred = predict()
                gaps = {"gap_db": abs(pred["psnr"] - got["psnr"]), "gap_iou": abs(pred["iou"] - got["iou"])}
                rows.append(make_row(SUITE, f"predict_{nm}", params, time_call(predict, repeats=repeats),
                                     metrics={"psnr": pred["psnr"], "iou": pred["iou"], **gaps}))
                rows.append(make_row(SUITE, f"measure_{nm}", params, time_call(measure, repeats=repeats),
                                     metrics={"psnr": got["psnr"], "iou": got["iou"]}))
    rows += _planning(asset, (10_000,) if quick else (1_000, 100_000), repeats)
    return rows


def _planning(asset: Any, counts: tuple[int, ...], repeats: int) -> list[dict[str, Any]]:
    """The ``what=planning`` rows (module notes)."""
    h = np.array([16.0, 32.0, 64.0, 128.0, 256.0])
    e = np.array([0.0, 40.0, 80.0])
    flat = {"cull": 10.0, "classic": 20.0, "nearest": 24.0, "morph": 28.0, "mesh": 60.0}
    tables = {("tree", rep): ErrorTable("tree", asset.mesh_hash, rep, h, e, np.full((5, 3), db),
                                        np.full((5, 3), 0.9))
              for rep, db in flat.items()}
    budget = Budget(billboard_psnr=22.0)
    rows = []
    for n in counts:
        inst = place_random(["tree"], n, np.random.default_rng(n))
        scene = BillboardScene({"tree": asset}, inst)
        cams = make_path("flyover", float(np.abs(inst.xy).max())).cameras(36, (480, 640))
        drawn: list[int] = []

        def plan(scene: Any = scene, cams: Any = cams, drawn: list[int] = drawn) -> Any:
            pred = predict_frames(tables, scene, cams)
            drawn[:] = [sum(len(b) for b in pred.band_index)]
            return choose(pred, budget)

        timing = time_call(plan, repeats=repeats, warmup=0)
        rows.append(make_row(SUITE, f"plan_{n}", {"what": "planning", "instances": n, "frames": len(cams)},
                             timing, metrics={"drawn": float(drawn[0])}))
    return rows
