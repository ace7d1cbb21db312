"""Ground-truth shadows
=====================

Write an image pair per sample mesh: the frame without shadows, and with
exact ray-cast hard shadows (the ground truth every shadow method in morphkit
is measured against).

Usage::

    python samples/ground_truth_shadows.py OUT_DIR [--size 384]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from morphkit.files.fileio import write_image
from morphkit.meshes import sample_mesh
from morphkit.programs.fixtures import DEMO_MESHES, demo_scene, ground_truth_frame
from morphkit.render import Renderer


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.partition("\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--size", type=int, default=384)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    with Renderer() as r:
        for name in DEMO_MESHES:
            f = ground_truth_frame(r, demo_scene(sample_mesh(name), args.size))
            pair = np.concatenate([f["lit"], f["shaded"]], axis=1)
            path = args.out / f"{name}_pair_noshadow_vs_raycast.png"
            write_image(path, pair)
            print(path)


if __name__ == "__main__":
    main()
