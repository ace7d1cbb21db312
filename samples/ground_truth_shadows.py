"""Ground-truth shadows
=====================

Write an image pair per sample mesh: the frame without shadows, and with
exact ray-cast hard shadows (the ground truth every shadow method in morphkit
is measured against).

The scene is made here from morphkit's public names: the mesh on a ground square
under a directional light, seen by a 3/4 view camera (the demo's scene). Put your
own mesh in it with ``morphkit.load_mesh("model.glb")``.

Usage::

    python samples/ground_truth_shadows.py OUT_DIR [--size 384]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import trimesh

import morphkit

MESHES = ("teapot", "chair", "cow")
#: The light travels along this direction: from the upper right-front, shadows fall back-left.
LIGHT_DIRECTION = (-0.55, 0.35, -1.0)


def shadow_scene(mesh: trimesh.Trimesh, size: int) -> morphkit.Scene:
    """``mesh`` (normalised: size 1, on the ground) at the origin on a 4 x 4 ground square, the
    light, and a camera looking down at it from the front right (40 degrees field of view)."""
    cam = morphkit.perspective(np.deg2rad(40), (size, size),
                               morphkit.look_at([1.45, -1.35, 1.05], [-0.2, 0.2, 0.2]), znear=0.1, zfar=20.0)
    light = morphkit.DirectionalLight(LIGHT_DIRECTION, intensity=2.2)
    ground = morphkit.Receiver(half_size=2.0)
    return morphkit.Scene(morphkit.SceneObject(mesh), light, cam, ground, ambient=0.3)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=384)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    with morphkit.Renderer() as r:
        for name in MESHES:
            scene = shadow_scene(morphkit.sample_mesh(name), args.size)
            # the truth: a ray from every visible point towards the light, against the mesh
            f = morphkit.render_frame(r, scene, lambda pts, _normals, s=scene: morphkit.hard_visibility(
                pts, s.light, s.obj))
            pair = np.concatenate([f["lit"], f["shaded"]], axis=1)
            path = args.out / f"{name}_pair_noshadow_vs_raycast.png"
            morphkit.write_image(path, pair)
            print(path)


if __name__ == "__main__":
    main()
