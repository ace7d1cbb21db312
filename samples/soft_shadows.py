"""Soft shadows: warped, re-rendered and ray cast
===============================================

Write soft-shadow image pairs: for each sample mesh under a square area light,
the top-down soft shadow on the ground made by warping one 3 x 3 atlas per light
sample, next to the one made by re-rendering per sample and the ray-cast ground
truth, for 5, 9 and 16 light samples; prints the mean abs visibility error.

The light, the range of motion and the position are set here (a 0.6 x 0.6 area
light centred on ``morphkit bake``'s default point light, its range of motion, a
position between the 3 x 3 samples); put your own mesh in with
``morphkit.load_mesh("model.glb")``.

Usage::

    python samples/soft_shadows.py OUT_DIR [--size 256] [--ground 256] [--dense 16]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import morphkit
from morphkit.shadow.soft import FIVE_SAMPLES

MESHES = ("teapot", "chair", "cow")
#: The area light: its centre and its two half-edge vectors, world units (0.6 x 0.6, level).
LIGHT = morphkit.AreaLight((0.25, -0.2, 2.4), [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])
#: The object's range of motion on the ground, ``(lo, hi)`` corners ``(x, y)``.
MOTION = ((-0.6, -0.6), (0.6, 0.6))
#: The object's position ``(x, y)`` shown: between the 3 x 3 samples.
POSITION = (0.23, -0.31)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=256, help="shadow-map size")
    ap.add_argument("--ground", type=int, default=256, help="ground image size")
    ap.add_argument("--dense", type=int, default=16, help="ray-cast light samples per axis")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    xy = np.array(POSITION)
    g = morphkit.receiver_grid(1.7, (args.ground, args.ground)).reshape(-1, 3)
    with morphkit.Renderer() as r:
        for name in MESHES:
            mesh = morphkit.sample_mesh(name)
            atlas = morphkit.bake_soft_atlas(mesh, np.eye(4), morphkit.MotionRange(*MOTION), LIGHT,
                                             (args.size, args.size), renderer=r)
            direct = morphkit.DirectShadow(atlas.rig, mesh, r)
            truth = morphkit.area_visibility(g, LIGHT, morphkit.SceneObject(mesh, morphkit.translation(*xy)),
                                             args.dense)
            for n, samples in ((5, FIVE_SAMPLES), (9, (3, 3)), (16, (4, 4))):
                vis = {k: morphkit.SoftShadow(m, LIGHT, samples).visibility(xy, g)
                       for k, m in (("warped", atlas), ("direct", direct))}
                strip = np.concatenate([vis["warped"], vis["direct"], truth]).reshape(
                    3, args.ground, args.ground)
                path = args.out / f"{name}_soft{n}_warped_direct_raycast.png"
                morphkit.write_image(path, np.rint(np.concatenate(list(strip), 1) * 255).astype(np.uint8))
                err = {k: float(np.abs(v - truth).mean()) for k, v in vis.items()}
                print(f"{path}  mean abs visibility error vs ray cast ({args.dense}^2 samples, "
                      f"ground [-1.7, 1.7]^2): warped {err['warped']:.4f}, direct {err['direct']:.4f}")


if __name__ == "__main__":
    main()
