"""A frame's silhouette IoU over its billboards' boxes (`billboard-iou`, as `morphkit plan` measures
it: `billboard.compare.frame_errors`) against what its billboards measure *alone*: which rule of
combining them reproduces the frame.

Every K-th frame of the path is drawn in one representation everywhere and in the truth, and every
drawn billboard again alone in its frame (the scene of that one instance: the billboard's box, cut
by the frame's edge where the frame cuts it, with nothing behind or before it), which gives its
box's fractions covered by the representation (a), by the truth (b) and by both (i) -- what a
plan's table cell knows of one billboard, whole and alone. Rules, each frame's figure against the
frame's measured IoU (the offsets' median, spread, and median distance from their median, the
figure a path of calibrated frames leaves as the gap):

* `box mean`: the alone IoUs weighted by the pixels of their boxes (the plan's rule today), with
  each billboard's own fractions or its cell's means (below);
* `coverage`: `morphkit.plan.framecoverage.union_iou`, each pixel of the boxes' union covered by
  the representation with probability 1 - prod(1 - a_k) over the boxes on it, by the truth
  1 - prod(1 - b_k), by neither prod(1 - a_k - b_k + i_k) (each box's silhouettes spread evenly over
  it, independent of the others'); the frame's IoU is the sum of the pixels' intersection
  probabilities over that of their union's;
* `coverage, cell means`: the same with each billboard's fractions replaced by the mean over the
  uncut boxes of its asset, height (log2, rounded) and elevation (10-degree bins) -- a table's
  cell -- for every box, or only for the uncut ones (a cut box keeps its own: what a table of
  coverage maps over the box, integrated over the part the frame shows, would give).

Usage: python scripts/plan_frame_model.py SCENE [--rep nearest] [--every 2] [--step 4]
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from collections.abc import Callable
from typing import Any

import numpy as np

import morphkit
from morphkit.billboard import BillboardScene, Instances
from morphkit.billboard.compare import frame_errors
from morphkit.plan.framecoverage import union_iou
from morphkit.plan.mixed import banded_mode
from morphkit.plan.representations import BandChoice
from morphkit.programs.scenerender import prepare_scene, scene_choices
from morphkit.render import Renderer

Fractions = tuple[float, float, float]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--rep", default="nearest", help="the representation drawn everywhere")
    ap.add_argument("--every", type=int, default=2, help="every K-th frame")
    ap.add_argument("--step", type=int, default=4, help="pixels per cell of the coverage rule's grid")
    a = ap.parse_args()
    scene = morphkit.load_scene(a.scene)
    sun, views, cams, _label, _chosen = scene_choices(scene, "plan")
    frames = []
    with Renderer() as r:
        prep = prepare_scene(scene, r, views, head="frame model: ", command="plan", sun=sun)
        mode = banded_mode(BandChoice(default=a.rep), prep.relit, prep.base, prep.shadow, prep.meshes())
        for k in range(0, len(cams), max(1, a.every)):
            got = _frame(prep, cams[k], mode)
            if got is not None:
                frames.append(got)
    if not frames:
        raise SystemExit("no frame draws a billboard")
    measured = np.array([f["iou"] for f in frames])
    cells: dict[Any, list[Fractions]] = defaultdict(list)
    assets: dict[str, list[Fractions]] = defaultdict(list)
    for f in frames:
        for b in f["boxes"]:
            if not b["cut"]:
                cells[_cell(b)].append(b["abi"])
                assets[b["asset"]].append(b["abi"])
    mean = {k: tuple(np.mean(v, axis=0)) for k, v in cells.items()}
    amean = {k: tuple(np.mean(v, axis=0)) for k, v in assets.items()}

    def cell(b: dict[str, Any]) -> Fractions:
        return mean.get(_cell(b), amean.get(b["asset"], b["abi"]))

    rules: dict[str, Callable[[dict[str, Any]], float]] = {
        "box mean": lambda f: _box_mean(f, lambda b: b["abi"]),
        "box mean, cell means": lambda f: _box_mean(f, cell),
        "coverage": lambda f: _coverage(f, lambda b: b["abi"], a.step),
        "coverage, cell means": lambda f: _coverage(f, cell, a.step),
        "coverage, cell means uncut": lambda f: _coverage(
            f, lambda b: b["abi"] if b["cut"] else cell(b), a.step),
    }
    cut = sum(b["cut"] for f in frames for b in f["boxes"])
    n = sum(len(f["boxes"]) for f in frames)
    print(f"{a.scene}, {a.rep} everywhere: {len(frames)} frames, {n} billboards "
          f"({cut} cut by the frame's edge), measured frame IoU {measured.min():.3f}-{measured.max():.3f}")
    print(f"{'rule':28s} {'median offset':>13s} {'sd':>6s} {'|off - median|: median':>23s} "
          f"{'p90':>6s} {'max':>6s}")
    for name, rule in rules.items():
        d = np.array([rule(f) for f in frames]) - measured
        dd = np.abs(d - np.median(d))
        print(f"{name:28s} {np.median(d):+13.3f} {d.std():6.3f} {np.median(dd):23.3f} "
              f"{np.quantile(dd, 0.9):6.3f} {dd.max():6.3f}")


def _frame(prep: Any, cam: Any, mode: Any) -> dict[str, Any] | None:
    """One frame's measured IoU and each drawn billboard's alone fractions (or None: none drawn)."""
    sc = prep.scene
    frame, truth = sc.render(cam, mode), sc.render(cam, prep.truth)
    if not frame.placements:
        return None
    inst = sc.instances
    boxes = []
    for pl in frame.placements:
        keep = np.array([pl.index])
        alone = Instances(inst.names, inst.asset[keep], inst.xy[keep], inst.yaw_deg[keep], inst.scale[keep])
        one = BillboardScene(sc.assets, alone, backdrop=sc.backdrop, facing=sc.facing,
                             min_pixels=sc.min_pixels)
        r0, r1, c0, c1 = pl.roi
        aa = one.render(cam, mode).layer[r0:r1, c0:c1, 3] > 0.5
        bb = one.render(cam, prep.truth).layer[r0:r1, c0:c1, 3] > 0.5
        h, w = frame.rgb.shape[:2]
        boxes.append({"asset": pl.asset, "height_px": pl.height_px, "elevation_deg": pl.elevation_deg,
                      "roi": pl.roi, "cut": r0 == 0 or c0 == 0 or r1 == h or c1 == w,
                      "abi": (aa.mean(), bb.mean(), (aa & bb).mean())})
    return {"iou": frame_errors(frame, truth)["iou"], "boxes": boxes, "shape": frame.rgb.shape[:2]}


def _cell(b: dict[str, Any]) -> tuple[str, int, int]:
    octave = int(np.round(np.log2(np.clip(b["height_px"], 1.0, 4096.0))))  # inf at the near plane
    return b["asset"], octave, int(b["elevation_deg"] // 10)


def _box_mean(f: dict[str, Any], fractions: Callable[[dict[str, Any]], Fractions]) -> float:
    w = np.array([(b["roi"][1] - b["roi"][0]) * (b["roi"][3] - b["roi"][2]) for b in f["boxes"]], float)
    # an empty union is an IoU of 1, as box_errors measures it
    q = np.array([i / u if (u := a + b_ - i) > 0 else 1.0 for a, b_, i in map(fractions, f["boxes"])])
    return float((w * q).sum() / w.sum())


def _coverage(f: dict[str, Any], fractions: Callable[[dict[str, Any]], Fractions], step: int) -> float:
    rois = np.array([b["roi"] for b in f["boxes"]], np.int64)
    return union_iou(rois, np.array([fractions(b) for b in f["boxes"]]), f["shape"], step=step)


if __name__ == "__main__":
    main()
