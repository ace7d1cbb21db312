"""Warped shadow maps: mesh warp, reprojection, re-render and ray cast
=====================================================================

Write warped-shadow image pairs: for each sample mesh and a few positions between
the 3 x 3 samples, the frame shadowed by the warped map (the paper's mesh warp,
and the per-pixel reprojection) next to the frame shadowed by a re-rendered map
and by the ray cast (the ground truth), and the warped, reprojected and
re-rendered light depth maps.

Usage::

    python samples/warped_shadows.py OUT_DIR [--size 384] [--positions 3]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from morphkit.files.fileio import write_image
from morphkit.imaging.metrics import shadow_iou
from morphkit.meshes import sample_mesh
from morphkit.programs.fixtures import DEMO_MESHES, WARP_LIGHT, WARP_RANGE, demo_scene
from morphkit.programs.visualize import colorize_depth
from morphkit.render import Renderer
from morphkit.scene import PointLight, Scene
from morphkit.shadow import DirectShadow, MotionRange, bake_atlas
from morphkit.shadow.frame import compare_frames


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=384)
    ap.add_argument("--positions", type=int, default=3)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    light, motion = PointLight(WARP_LIGHT), MotionRange(*WARP_RANGE)
    xys = np.random.default_rng(0).uniform(motion.lo, motion.hi, (args.positions, 2))
    with Renderer() as r:
        for name in DEMO_MESHES:
            mesh = sample_mesh(name)
            atlas = bake_atlas(mesh, np.eye(4), motion, light, (args.size, args.size), renderer=r)
            direct = DirectShadow(atlas.rig, mesh, r)
            base = demo_scene(mesh, args.size)
            scene = Scene(base.obj, light, base.camera, base.receiver, ambient=base.ambient)
            methods = {"warped": atlas, "reprojected": atlas.method(warps="reproject"),
                       "direct": direct}
            for k, xy in enumerate(xys):
                f = compare_frames(r, scene, methods, xy)
                strip = np.concatenate([f[m]["shaded"] for m in (*methods, "raycast")], 1)
                path = args.out / f"{name}_{k}_warped_reprojected_direct_raycast.png"
                write_image(path, strip)
                maps = [colorize_depth(m.shadow_map(xy)[0]) for m in methods.values()]
                write_image(args.out / f"{name}_{k}_lightmap_warped_reprojected_direct.png",
                            np.concatenate(maps, 1))
                gt = f["raycast"]["visibility"] < 0.5
                ious = {m: shadow_iou(f[m]["visibility"] < 0.5, gt, mask=f["raycast"]["facing"])
                        for m in methods}
                print(f"{path}  position {np.round(xy, 3).tolist()}  IoU vs ray cast (light-facing "
                      "pixels): " + ", ".join(f"{m} {ious[m]:.3f}" for m in methods))


if __name__ == "__main__":
    main()
