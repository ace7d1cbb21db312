"""Soft shadows: warped, re-rendered and ray cast
===============================================

Write soft-shadow image pairs: for each sample mesh under a square area light,
the top-down soft shadow on the ground made by warping one 3 x 3 atlas per light
sample, next to the one made by re-rendering per sample and the ray-cast ground
truth, for 5, 9 and 16 light samples; prints the mean abs visibility error.

Usage::

    python samples/soft_shadows.py OUT_DIR [--size 256] [--ground 256] [--dense 16]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from morphkit.files.fileio import write_image
from morphkit.imaging.groundtruth import area_visibility, receiver_grid
from morphkit.meshes import sample_mesh
from morphkit.programs.fixtures import DEMO_MESHES, SOFT_LIGHT, WARP_POSITION, WARP_RANGE
from morphkit.render import Renderer
from morphkit.scene import SceneObject
from morphkit.shadow import DirectShadow, MotionRange, SoftShadow, bake_soft_atlas
from morphkit.shadow.soft import FIVE_SAMPLES


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=256, help="shadow-map size")
    ap.add_argument("--ground", type=int, default=256, help="ground image size")
    ap.add_argument("--dense", type=int, default=16, help="ray-cast light samples per axis")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    light = SOFT_LIGHT
    xy = np.array(WARP_POSITION)
    g = receiver_grid(1.7, (args.ground, args.ground)).reshape(-1, 3)
    with Renderer() as r:
        for name in DEMO_MESHES:
            mesh = sample_mesh(name)
            atlas = bake_soft_atlas(mesh, np.eye(4), MotionRange(*WARP_RANGE), light,
                                    (args.size, args.size), renderer=r)
            direct = DirectShadow(atlas.rig, mesh, r)
            pose = np.eye(4)
            pose[:2, 3] = xy
            truth = area_visibility(g, light, SceneObject(mesh, pose), args.dense)
            for n, samples in ((5, FIVE_SAMPLES), (9, (3, 3)), (16, (4, 4))):
                vis = {k: SoftShadow(m, light, samples).visibility(xy, g)
                       for k, m in (("warped", atlas), ("direct", direct))}
                strip = np.concatenate([vis["warped"], vis["direct"], truth]).reshape(
                    3, args.ground, args.ground)
                path = args.out / f"{name}_soft{n}_warped_direct_raycast.png"
                write_image(path, np.rint(np.concatenate(list(strip), 1) * 255).astype(np.uint8))
                err = {k: float(np.abs(v - truth).mean()) for k, v in vis.items()}
                print(f"{path}  mean abs visibility error vs ray cast ({args.dense}^2 samples, "
                      f"ground [-1.7, 1.7]^2): warped {err['warped']:.4f}, direct {err['direct']:.4f}")


if __name__ == "__main__":
    main()
