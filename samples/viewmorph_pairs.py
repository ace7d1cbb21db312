"""View morphing against the rendered in-between view
====================================================

Write view-morphing sample pairs: the two references, the morph and the ground truth.

For each sample mesh and baseline this renders the mesh in a 3-D colour checker
(:func:`morphkit.imaging.appearance.checker_items`) from two cameras on a circle around it,
``baseline`` degrees apart, and from the camera half-way (the scene of ``morphkit
bench viewmorph``, made here from morphkit's public names), view-morphs the pair at
``s = 0.5`` (geometric correspondences, post-warp to the true intermediate camera)
and writes, under OUT/<mesh>_<baseline>deg/:

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

import morphkit
from morphkit.imaging.appearance import checker_items
from morphkit.viewmorph import from_depth, pair_depth, save_points

#: The middle view's azimuth, degrees about ``+z`` from ``+x``.
CENTRE = 60.0
#: The cameras' circle: radius and height (world units), and the point they look at.
RADIUS, HEIGHT, LOOK_AT = 2.2, 1.0, (0.0, 0.0, 0.25)
#: The light the references are rendered under (the direction it travels).
LIGHT = morphkit.DirectionalLight([-1.0, -0.5, -1.0])


def circle_camera(azimuth_deg: float, size: int) -> morphkit.CameraModel:
    """A camera on the circle at ``azimuth_deg``, looking at its centre (30 degrees field of view)."""
    a = np.radians(azimuth_deg)
    eye = np.array([RADIUS * np.cos(a), RADIUS * np.sin(a), HEIGHT])
    return morphkit.perspective(np.radians(30.0), (size, size), morphkit.look_at(eye, np.array(LOOK_AT)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", nargs="?", default="viewmorph-samples")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--meshes", nargs="+", default=["teapot", "chair", "cow"])
    ap.add_argument("--baselines", nargs="+", type=float, default=[20.0, 40.0])
    args = ap.parse_args()
    out = Path(args.out)
    with morphkit.Renderer() as r:
        for name in args.meshes:
            mesh = morphkit.sample_mesh(name)
            items = checker_items(mesh)  # the mesh's colour groups, identity pose: world = object frame
            for base in args.baselines:
                c0 = circle_camera(CENTRE - base / 2, args.size)
                c1 = circle_camera(CENTRE + base / 2, args.size)
                cm = circle_camera(CENTRE, args.size)
                (i0, d0), (i1, d1), (gt, _) = [(r.source_view(c, items, [LIGHT]), r.depth(c, items))
                                               for c in (c0, c1, cm)]
                corr = morphkit.from_geometry(mesh, c0, c1, depth0=d0, depth1=d1, max_points=600)
                vm = morphkit.ViewMorpher.from_estimate(i0, i1, corr)
                mid = vm.morph(0.5, post=cm, frame="fixed")
                vl = morphkit.ViewMorpher.from_estimate(i0, i1, from_depth(c0, c1, d0, d1), layers="auto",
                                                        layer_depth=pair_depth(c0, c1, d0, d1))
                lay = vl.morph(0.5, post=cm, frame="fixed")
                folder = out / f"{name}_{base:g}deg"
                folder.mkdir(parents=True, exist_ok=True)
                for fname, img in (("left", i0), ("right", i1), ("morph", mid), ("layered", lay),
                                   ("truth", gt)):
                    morphkit.write_image(folder / f"{fname}.png", img)
                morphkit.write_image(folder / "strip.png", np.concatenate([i0, mid, lay, gt, i1], axis=1))
                save_points(folder / "points.json", corr)
                g = gt[..., 3] > 127
                iou = [((im[..., 3] > 127) & g).sum() / max(((im[..., 3] > 127) | g).sum(), 1)
                       for im in (mid, lay)]
                print(f"{folder}: {vm.mode}/{vm.rectification.method}, silhouette IoU one mesh {iou[0]:.3f}, "
                      f"{vl.report.layers} layer(s) {iou[1]:.3f}")


if __name__ == "__main__":
    main()
