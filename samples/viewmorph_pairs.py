"""View morphing against the rendered in-between view
====================================================

Write view-morphing sample pairs: the two references, the morph and the ground truth.

For each sample mesh and baseline this renders the bench scene
(:mod:`morphkit.bench.viewmorph_suite`), view-morphs the pair at ``s = 0.5``
(geometric correspondences, post-warp to the true intermediate camera) and
writes, under OUT/<mesh>_<baseline>deg/:

* ``left.png``, ``right.png`` -- the references (try ``morphkit viewmorph
  left.png right.png -o mid.png`` on them: SIFT correspondences);
* ``points.json`` -- the geometric correspondences (``--points``);
* ``morph.png`` and ``truth.png`` -- the view-morphed (one mesh on the mesh's
  vertices) and the rendered middle view;
* ``layered.png`` -- the view morph on dense depth-map pairs with
  ``layers="auto"`` (two depth layers where parts cross: the chair);
* ``strip.png`` -- left | morph | layered | truth | right side by side.

Usage: ``python samples/viewmorph_pairs.py [OUT] [--size 256]`` (needs GL).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from morphkit.files.fileio import write_image
from morphkit.programs.fixtures import circle_camera, render_pair, textured_items
from morphkit.render import Renderer
from morphkit.viewmorph import ViewMorpher, from_depth, from_geometry, pair_depth, save_points

CENTRE = 60.0


def write(path: Path, rgba: np.ndarray) -> None:
    write_image(path, rgba)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", nargs="?", default="viewmorph-samples")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--meshes", nargs="+", default=["teapot", "chair", "cow"])
    ap.add_argument("--baselines", nargs="+", type=float, default=[20.0, 40.0])
    args = ap.parse_args()
    out = Path(args.out)
    with Renderer() as r:
        for name in args.meshes:
            mesh, items = textured_items(name)
            for base in args.baselines:
                c0 = circle_camera(CENTRE - base / 2, args.size)
                c1 = circle_camera(CENTRE + base / 2, args.size)
                cm = circle_camera(CENTRE, args.size)
                (i0, d0), (i1, d1), (gt, _) = render_pair(r, items, [c0, c1, cm])
                corr = from_geometry(mesh, c0, c1, depth0=d0, depth1=d1, max_points=600)
                vm = ViewMorpher.from_estimate(i0, i1, corr)
                mid = vm.morph(0.5, post=cm, frame="fixed")
                vl = ViewMorpher.from_estimate(i0, i1, from_depth(c0, c1, d0, d1), layers="auto",
                                               layer_depth=pair_depth(c0, c1, d0, d1))
                lay = vl.morph(0.5, post=cm, frame="fixed")
                folder = out / f"{name}_{base:g}deg"
                folder.mkdir(parents=True, exist_ok=True)
                for fname, img in (("left", i0), ("right", i1), ("morph", mid), ("layered", lay),
                                   ("truth", gt)):
                    write(folder / f"{fname}.png", img)
                write(folder / "strip.png", np.concatenate([i0, mid, lay, gt, i1], axis=1))
                save_points(folder / "points.json", corr)
                g = gt[..., 3] > 127
                iou = [((im[..., 3] > 127) & g).sum() / max(((im[..., 3] > 127) | g).sum(), 1)
                       for im in (mid, lay)]
                print(f"{folder}: {vm.mode}/{vm.rectification.method}, silhouette IoU one mesh {iou[0]:.3f}, "
                      f"{vl.report.layers} layer(s) {iou[1]:.3f}")


if __name__ == "__main__":
    main()
