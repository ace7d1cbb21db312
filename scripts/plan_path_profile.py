"""Every frame of a scene drawn with each of some representations everywhere and measured against the
real meshes, as `morphkit plan` measures a frame (`planverify.verify_frames`: billboard-psnr and
billboard-iou over the billboards' boxes): how a representation's error moves along the whole path,
and the fraction of the frames a budget's figures hold on, where a plan sees only a few frames.

Usage: python scripts/plan_path_profile.py SCENE [--rep classic --rep nearest ...]
       [--budget billboard-iou=0.7 ...] [--every K]
"""

from __future__ import annotations

import argparse

import morphkit
from morphkit.plan import Budget
from morphkit.plan.mixed import banded_mode
from morphkit.plan.representations import BandChoice
from morphkit.programs.planning.planverify import verify_frames
from morphkit.programs.scenerender import prepare_scene, scene_choices
from morphkit.render import Renderer


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--rep", action="append", help="a representation (default: classic, nearest)")
    ap.add_argument("--budget", action="append", default=[], help="KEY=VALUE (billboard-psnr, billboard-iou)")
    ap.add_argument("--every", type=int, default=1, help="every K-th frame")
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
        got = verify_frames(prep, cams, frames, modes)
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


if __name__ == "__main__":
    main()
