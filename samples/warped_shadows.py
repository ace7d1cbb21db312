"""Warped shadow maps: mesh warp, reprojection, re-render and ray cast
=====================================================================

Write warped-shadow image pairs: for each sample mesh and a few positions between
the 3 x 3 samples, the frame shadowed by the warped map (the paper's mesh warp,
and the per-pixel reprojection) next to the frame shadowed by a re-rendered map
and by the ray cast (the ground truth), and the warped, reprojected and
re-rendered light depth maps.

The scene is made here from morphkit's public names (the demo's: the mesh on a
ground square, a 3/4 view camera) with a point light above the object's range of
motion, the defaults of ``morphkit bake``. Put your own mesh in it with
``morphkit.load_mesh("model.glb")``.

Usage::

    python samples/warped_shadows.py OUT_DIR [--size 384] [--positions 3]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import trimesh

import morphkit
from morphkit.programs.visualize import colorize_depth

MESHES = ("teapot", "chair", "cow")
#: The point light, world units: above the range of motion, a little off its centre.
LIGHT_POSITION = (0.25, -0.2, 2.4)
#: The object's range of motion on the ground, ``(lo, hi)`` corners ``(x, y)``.
MOTION = ((-0.6, -0.6), (0.6, 0.6))


def shadow_scene(mesh: trimesh.Trimesh, light: morphkit.PointLight, size: int) -> morphkit.Scene:
    """``mesh`` (normalised: size 1, on the ground) at the origin on a 4 x 4 ground square under
    ``light``, and a camera looking down at it from the front right (40 degrees field of view)."""
    cam = morphkit.perspective(np.deg2rad(40), (size, size),
                               morphkit.look_at([1.45, -1.35, 1.05], [-0.2, 0.2, 0.2]), znear=0.1, zfar=20.0)
    ground = morphkit.Receiver(half_size=2.0)
    return morphkit.Scene(morphkit.SceneObject(mesh), light, cam, ground, ambient=0.3)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=384)
    ap.add_argument("--positions", type=int, default=3)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    light, motion = morphkit.PointLight(LIGHT_POSITION), morphkit.MotionRange(*MOTION)
    xys = np.random.default_rng(0).uniform(motion.lo, motion.hi, (args.positions, 2))
    with morphkit.Renderer() as r:
        for name in MESHES:
            mesh = morphkit.sample_mesh(name)
            atlas = morphkit.bake_atlas(mesh, np.eye(4), motion, light, (args.size, args.size), renderer=r)
            direct = morphkit.DirectShadow(atlas.rig, mesh, r)
            scene = shadow_scene(mesh, light, args.size)
            methods = {"warped": atlas, "reprojected": atlas.method(warps="reproject"),
                       "direct": direct}
            for k, xy in enumerate(xys):
                f = morphkit.compare_frames(r, scene, methods, xy)
                strip = np.concatenate([f[m]["shaded"] for m in (*methods, "raycast")], 1)
                path = args.out / f"{name}_{k}_warped_reprojected_direct_raycast.png"
                morphkit.write_image(path, strip)
                maps = [colorize_depth(m.shadow_map(xy)[0]) for m in methods.values()]
                morphkit.write_image(args.out / f"{name}_{k}_lightmap_warped_reprojected_direct.png",
                                     np.concatenate(maps, 1))
                gt = f["raycast"]["visibility"] < 0.5
                ious = {m: morphkit.shadow_iou(f[m]["visibility"] < 0.5, gt, mask=f["raycast"]["facing"])
                        for m in methods}
                print(f"{path}  position {np.round(xy, 3).tolist()}  IoU vs ray cast (light-facing "
                      "pixels): " + ", ".join(f"{m} {ious[m]:.3f}" for m in methods))


if __name__ == "__main__":
    main()
