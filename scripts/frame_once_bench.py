"""The frame that draws its camera once (issue #26): whole-frame time against the two-render
frame and the direct frame, and the image difference.

Scene (as ``morphkit bench shadows``' frame rows): the cow subdivided to ~6k and ~1M faces
(``sample_mesh("cow", faces=...)``), the point light, a 512^2 camera, 512^2 shadow maps, six
object positions cycled, every method interleaved (medians of ``--repeats`` rounds):
``two_warp`` (camera drawn lit, then unlit; warped map), ``once_warp`` / ``once_reproject``
(camera drawn once), ``once_direct`` (camera drawn once, the light's map re-rendered every
frame), ``camera_once`` / ``camera_two`` (the camera draws alone). ``vs_direct``: median over
``once_direct``'s. ``mean_levels``: mean |shaded| difference of the one-pass frame against the
two-render frame, levels of 255 (the issue's bound: 1).

Usage: PYTHONPATH=. python scripts/frame_once_bench.py [--faces 6000 1000000] [--size 512]
[--repeats 9] [--receiver-only] [--json PATH]   (~2-4 min on 2 cores)
"""

from __future__ import annotations

import argparse
import json

from morphkit.bench.shadow_suite import frame_once_rows
from morphkit.render import Renderer, gl_info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--faces", type=int, nargs="+", default=[6000, 1000000])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--receiver-only", action="store_true", help="frames in the receiver-only mode")
    ap.add_argument("--json", default=None, help="write the rows here")
    args = ap.parse_args()
    with Renderer() as renderer:
        rows = frame_once_rows(renderer, tuple(args.faces), args.size, args.repeats,
                               receiver_only=args.receiver_only)
        print(f"GL: {gl_info()}")
    print(f"{'faces':>8} {'method':>15} {'ms median':>10} {'min-max':>15} {'vs_direct':>9} "
          f"{'mean_levels':>11}")
    for r in rows:
        m = r["metrics"]
        lv = f"{m['mean_levels']:.4f}" if "mean_levels" in m else ""
        print(f"{r['params']['faces']:>8} {r['method']:>15} {r['ms_median']:>10.1f} "
              f"{r['ms_min']:>7.1f}-{r['ms_max']:<7.1f} {m['vs_direct']:>9.3f} {lv:>11}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
