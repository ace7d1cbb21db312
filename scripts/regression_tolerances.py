"""Measure how much each image kind of tests/test_regression.py varies, to set its tolerance.

Renders the regression images (teapot scene and ray-cast visibility, 128^2; the
cow's warped and reprojected light depth maps, colour-mapped, and their
composites) in fresh processes under each setting that may change them -- the
compiled kernels and their numpy reference (``MORPHKIT_WARP_NUMPY=1``), 1, 2
and 4 threads (``MORPHKIT_WARP_THREADS``), and a repeated run -- and prints,
per image kind and setting, the metrics of ``tests/imgcompare.py`` against the
stored reference: mean absolute difference (grey levels), fraction of pixels
differing by more than 16 levels, and the largest difference.

It also prints what small errors the tests must catch look like in the same
metrics: the image shifted by one pixel; the teapot's light turned by 1 degree
(its shadow moves by about a pixel at its far end); the cow's shadow map made
for a position 0.01 off (1% of the object's size).

Run from the repository root::

    PYTHONPATH=$PWD python scripts/regression_tolerances.py

What it cannot measure: other Mesa versions (the GL rasteriser of the camera
frames and of the baked maps); the tolerances leave room for that on their own.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "tests" / "reference"
BAD_LEVEL = 16

SETTINGS = {
    "compiled, default threads": {},
    "compiled, default threads (again)": {},
    "numpy reference": {"MORPHKIT_WARP_NUMPY": "1"},
    "compiled, 1 thread": {"MORPHKIT_WARP_THREADS": "1"},
    "compiled, 2 threads": {"MORPHKIT_WARP_THREADS": "2"},
    "compiled, 4 threads": {"MORPHKIT_WARP_THREADS": "4"},
}

RENDER = r'''
import sys
from pathlib import Path

import cv2
import numpy as np

from morphkit.files.fileio import write_image
from morphkit.meshes import sample_mesh
from morphkit.render import Renderer
from morphkit.scene import PointLight, Scene
from morphkit.programs.fixtures import demo_scene, ground_truth_frame
from morphkit.shadow import MotionRange, bake_atlas
from morphkit.shadow.frame import compare_frames
from morphkit.programs.visualize import colorize_depth

class _Fixed:
    """A shadow method that returns one given map (for the error variants)."""

    def __init__(self, m, depth, lcam):
        self.name, self.rig, self.memory_bytes = m.name, m.rig, m.memory_bytes
        self._d = (depth, lcam)

    def shadow_map(self, xy, *, light_offset=None, clamp=False):
        return self._d


out, errors = Path(sys.argv[1]), sys.argv[2] == "errors"
with Renderer() as r:
    scenes = {"": demo_scene(sample_mesh("teapot"), size=128)}
    if errors:  # the light turned by 1 degree about the vertical axis
        from morphkit.scene import DirectionalLight
        s0 = scenes[""]
        c, s = np.cos(np.deg2rad(1)), np.sin(np.deg2rad(1))
        d = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ s0.light.direction
        scenes["__light_1deg"] = Scene(s0.obj, DirectionalLight(d, intensity=s0.light.intensity), s0.camera,
                                       s0.receiver, ambient=s0.ambient)
    for tag, sc in scenes.items():
        f = ground_truth_frame(r, sc)
        write_image(out / f"demo_teapot_scene_128{tag}.png", f["shaded"])
        write_image(out / f"demo_teapot_visibility_128{tag}.png",
                    np.rint(f["visibility"] * 255).astype(np.uint8))
    cow = sample_mesh("cow")
    light = PointLight([0.25, -0.2, 2.4])
    atlas = bake_atlas(cow, np.eye(4), MotionRange([-0.6, -0.6], [0.6, 0.6]), light, (128, 128),
                       renderer=r, control_grid=(9, 9), progress=False)
    xy = np.array([0.23, -0.31])
    base = demo_scene(cow, 128)
    scene = Scene(base.obj, light, base.camera, base.receiver, ambient=base.ambient)
    offsets = {"": np.zeros(2)} | ({"__pos_0.01_off": np.array([0.01, 0.0])} if errors else {})
    for name, opts in {"warped": {}, "reprojected": {"warps": "reproject"}}.items():
        m = atlas.method(**opts)
        for tag, off in offsets.items():
            # the map for a position 0.01 off, drawn as if at xy: a small error of the warp
            depth, lcam = m.shadow_map(xy + off)
            write_image(out / f"{name}_cow_depth_128{tag}.png", colorize_depth(depth))
            frame = compare_frames(r, scene, {"m": _Fixed(m, depth, lcam)}, xy)["m"]
            write_image(out / f"{name}_cow_composite_128{tag}.png", frame["shaded"])
'''


def compare(a: np.ndarray, b: np.ndarray) -> tuple[float, float, int]:
    d = np.abs(a.astype(np.int16) - b.astype(np.int16))
    per_px = d if d.ndim == 2 else d.max(axis=2)
    return float(d.mean()), float((per_px > BAD_LEVEL).mean()), int(d.max())


def main() -> None:
    names = sorted(p.stem for p in REFERENCE.glob("*.png"))
    refs = {n: cv2.imread(str(REFERENCE / f"{n}.png"), cv2.IMREAD_UNCHANGED) for n in names}
    results: dict[str, dict[str, tuple[float, float, int]]] = {n: {} for n in names}
    first: dict[str, np.ndarray] = {}
    for k, (label, env) in enumerate(SETTINGS.items()):
        with tempfile.TemporaryDirectory() as d:
            e = dict(os.environ, PYTHONPATH=str(ROOT), **env)
            subprocess.run([sys.executable, "-c", RENDER, d, "errors" if k == 0 else "-"], check=True,
                           env=e, cwd=ROOT)
            for n in names:
                got = cv2.imread(str(Path(d) / f"{n}.png"), cv2.IMREAD_UNCHANGED)
                results[n][label] = compare(got, refs[n])
                if k == 0:
                    first[n] = got
                    for err in Path(d).glob(f"{n}__*.png"):
                        tag = err.stem.split("__", 1)[1]
                        wrong = cv2.imread(str(err), cv2.IMREAD_UNCHANGED)
                        results[n][f"ERROR {tag}"] = compare(wrong, refs[n])
                else:
                    results[n][f"{label} vs first run"] = compare(got, first[n])
    for n in names:
        results[n]["ERROR shifted 1 px"] = compare(np.roll(refs[n], 1, axis=1)[:, 1:], refs[n][:, 1:])
    print(f"{'image':30s} {'setting (vs reference unless said)':44s} {'mean_abs':>9s} {'>16 frac':>9s} "
          f"{'max':>4s}")
    for n in names:
        for label, (m, f, mx) in results[n].items():
            print(f"{n:30s} {label:44s} {m:9.4f} {f:9.5f} {mx:4d}")


if __name__ == "__main__":
    main()
