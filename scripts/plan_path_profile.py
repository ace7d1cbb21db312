"""Every frame of a scene drawn with each of some representations everywhere and measured against the
real meshes, as `morphkit plan` measures a frame (`planverify.verify_frames`: billboard-psnr and
billboard-iou over the billboards' boxes): how a representation's error moves along the whole path,
and the fraction of the frames a budget's figures hold on, where a plan sees only a few frames.

With --phase (ring assets): each billboard's box IoU by its phase between its two ring views (0 at
a view, 0.5 midway), and how the representations' frame IoU move together: whether a frame's error
follows its billboards' phases or the frame itself.

With --offsets PLAN (a plan's output folder of the same scene, whose tables predict the frames):
each representation's offsets, measured less predicted, frame by frame; their autocorrelation by
lag (how far along the path one frame's offset tells another's); and the median gap on the plan's
held-out frames were its own frames every K-th planning frame, their offsets interpolated along
the path (`plan.calibration.path_offsets`) or their median taken for every frame.

Usage: python scripts/plan_path_profile.py SCENE [--rep classic --rep nearest ...]
       [--budget billboard-iou=0.7 ...] [--every K] [--phase] [--offsets PLAN]
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

import morphkit
from morphkit.billboard import BillboardScene
from morphkit.plan import Budget
from morphkit.plan.calibration import path_offsets
from morphkit.plan.errortable import ErrorTable
from morphkit.plan.mixed import banded_mode
from morphkit.plan.planner import predict_frames
from morphkit.plan.representations import REPRESENTATIONS, BandChoice
from morphkit.programs.planning.planverify import verify_frames
from morphkit.programs.scenerender import prepare_scene, scene_choices
from morphkit.render import Renderer


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--rep", action="append", help="a representation (default: classic, nearest)")
    ap.add_argument("--budget", action="append", default=[], help="KEY=VALUE (billboard-psnr, billboard-iou)")
    ap.add_argument("--every", type=int, default=1, help="every K-th frame")
    ap.add_argument("--phase", action="store_true", help="box IoU by phase between ring views")
    ap.add_argument("--offsets", metavar="PLAN", help="a plan's folder: offsets, their lags, the gap")
    a = ap.parse_args()
    reps = a.rep or ["classic", "nearest"]
    budget = Budget.parse(a.budget) if a.budget else None
    scene = morphkit.load_scene(a.scene)
    sun, views, cams, _label, _chosen = scene_choices(scene, "plan")
    frames = list(range(0, len(cams), max(1, a.every)))
    with Renderer() as r:
        prep = prepare_scene(scene, r, views, head="profile: ", command="plan", sun=sun)
        modes = {nm: banded_mode(BandChoice(default=nm), prep.relit, prep.base, prep.shadow, prep.meshes())
                 for nm in reps}
        got = verify_frames(prep, cams, frames, modes, boxes=a.phase)
        if a.offsets:
            folder = Path(a.offsets)
            tables = {(nm, r.name): ErrorTable.load(folder / "tables" / f"{nm}.{r.name}.npz")
                      for nm in prep.scene.assets for r in REPRESENTATIONS}
            pred = predict_frames(tables, prep.scene, [cams[k] for k in frames])
            held = json.loads((folder / "plan.json").read_text())["held_out_frames"]
            for nm in reps:
                _offsets(nm, frames, pred.frame_errors(pred.pick_of(BandChoice(default=nm))),
                         got[nm]["errors"], held)
    print("frame " + " ".join(f"{nm + ' dB/IoU':>18}" for nm in reps))
    for i, k in enumerate(frames):
        cells = []
        for nm in reps:
            e = got[nm]["errors"][i]
            cells.append(f"{'-':>18}" if e["billboard-psnr"] is None
                         else f"{e['billboard-psnr']:9.2f}/{e['billboard-iou']:.3f}".rjust(18))
        print(f"{k:5d} " + " ".join(cells))
    for nm in reps:
        drawn = [e for e in got[nm]["errors"] if e["billboard-psnr"] is not None]
        held = [e for e in drawn if budget is None or budget.meets(e)]
        print(f"{nm}: {len(held)} of {len(drawn)} frames with billboards within "
              f"{budget.to_json() if budget else 'no budget'}"
              + (f" ({len(held) / len(drawn):.1%})" if drawn else ""))
    if a.phase:
        _phases(prep.scene, got, reps)


def _offsets(
    rep: str, frames: Sequence[int], predicted: Sequence[dict[str, Any]], measured: Sequence[dict[str, Any]],
    held: Sequence[int],
) -> None:
    """A representation's offsets along the path: autocorrelation by lag, and the held-out gap were the
    plan's own frames every K-th planning frame, interpolated along the path or their median."""
    at = {k: i for i, k in enumerate(frames)}
    keys = ("billboard-psnr", "billboard-iou")
    off = np.array([[np.nan if p[key] is None or m[key] is None else m[key] - p[key] for key in keys]
                    for p, m in zip(predicted, measured, strict=True)])
    for j, key in enumerate(keys):
        o = off[:, j] - np.nanmean(off[:, j])
        lags = []
        for lag in range(1, 9):
            x, y = o[:-lag], o[lag:]
            ok = ~np.isnan(x) & ~np.isnan(y)
            lags.append(f"{np.corrcoef(x[ok], y[ok])[0, 1]:+.2f}" if ok.sum() > 2 else "-")
        print(f"{rep} {key} offsets: sd {np.nanstd(off[:, j]):.3f}, autocorrelation by lag 1..8 "
              + " ".join(lags))
    held = [k for k in held if k in at]
    planning = [k for k in frames if k not in held]
    for every in (8, 6, 4, 2, 1):
        own = planning[::every]
        path = path_offsets(own, [predicted[at[k]] for k in own], [measured[at[k]] for k in own], held)
        med = np.nanmedian(off[[at[k] for k in own]], axis=0)
        gaps = []
        for j in range(2):
            for moved in ([o[j] for o in path], [med[j]] * len(held)):
                g = [abs(off[at[k], j] - v) for k, v in zip(held, moved, strict=True)
                     if not np.isnan(off[at[k], j])]
                gaps.append(float(np.median(g)) if g else float("nan"))
        print(f"{rep}, own frames every {every} ({len(own)}): held-out median gap, along the path / "
              f"their median: {gaps[0]:.2f} / {gaps[1]:.2f} dB, IoU {gaps[2]:.3f} / {gaps[3]:.3f}")


def _phases(scene: BillboardScene, got: dict[str, dict[str, list[Any]]], reps: list[str]) -> None:
    """Box IoU by phase between ring views, per representation; the frames' IoU correlated."""
    inst = scene.instances
    for nm in reps:
        ph, iou = [], []
        for boxes in got[nm]["boxes"]:
            for b in boxes:
                _i, _j, s, _out = scene.assets[inst.names[inst.asset[b["index"]]]].ring.pair(b["azimuth_deg"])
                ph.append(min(s, 1.0 - s))
                iou.append(b["iou"])
        p, q = np.asarray(ph), np.asarray(iou)
        quarters = [q[(p >= lo) & (p < lo + 0.125)].mean() for lo in (0.0, 0.125, 0.25, 0.375)]
        print(f"{nm}: {len(q)} billboards, box IoU by phase quarter "
              + " ".join(f"{v:.3f}" for v in quarters) + f", correlation {np.corrcoef(p, q)[0, 1]:+.3f}")
    frame = {nm: [e["billboard-iou"] for e in got[nm]["errors"]] for nm in reps}
    drawn = [i for i in range(len(frame[reps[0]])) if all(frame[nm][i] is not None for nm in reps)]
    for k, x in enumerate(reps):
        for y in reps[k + 1:]:
            r = np.corrcoef([frame[x][i] for i in drawn], [frame[y][i] for i in drawn])[0, 1]
            print(f"frame IoU of {x} and {y} over {len(drawn)} frames: correlation {r:+.3f}")


if __name__ == "__main__":
    main()
