#!/usr/bin/env python3
"""The default soft shadow's filtered lookup, before and after a change, timed in one process.

Usage: ``PYTHONPATH=. python scripts/soft_lookup_ab.py REV [MESH,...] [REPEATS]`` (default:
teapot,chair,cow; 4), from the checkout to time (it prints which ``morphkit`` it imported).

The bench soft scene (``morphkit.bench.soft_suite``: 256^2 maps, N = 9, the 256^2 ground
grid, 6 seeded positions). Per mesh, interleaved call by call: ``warp_9`` (the time
target's baseline), PCSS on the reprojected maps with ``morphkit/shadow/filtering/filtered.py`` as
of git revision ``REV`` (``before``), and the working tree's ``default_soft_shadow``
(``after``); both filter the *same* reprojected maps, and their visibility must agree to
1e-4. Prints wall and CPU (all threads) medians and their ratio to ``warp_9``: run it on
one machine, as the machines are shared. ``MORPHKIT_WARP_THREADS=1`` keeps every pass in
the calling thread.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

import morphkit
from morphkit.bench import soft_suite as suite
from morphkit.imaging.groundtruth import receiver_grid
from morphkit.meshes import sample_mesh
from morphkit.render import Renderer
from morphkit.shadow import SoftShadow, bake_soft_atlas
from morphkit.shadow.filtering.penumbra import PcssSoftShadow
from morphkit.shadow.lookup import ShadowBias


def module_at(rev: str) -> ModuleType:
    """``morphkit/shadow/filtering/filtered.py`` at ``rev``, imported as a stand-alone module."""
    src = subprocess.run(["git", "show", f"{rev}:morphkit/shadow/filtering/filtered.py"], check=True,
                         capture_output=True, text=True).stdout
    src = (src.replace("from .. import tol", "from morphkit import tol")
           .replace("from ..", "from morphkit.").replace("from .", "from morphkit.shadow."))
    path = Path(tempfile.mkdtemp()) / "filtered_before.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("filtered_before", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


def main(argv: list[str]) -> None:
    """Run the comparison (module docstring)."""
    print(f"after: {Path(morphkit.__file__).parent}; before: filtered.py at {argv[1]}", flush=True)
    before = module_at(argv[1])
    meshes = argv[2].split(",") if len(argv) > 2 else ["teapot", "chair", "cow"]
    repeats = int(argv[3]) if len(argv) > 3 else 4
    grid = receiver_grid(suite.GROUND_HALF, (suite.GROUND_N, suite.GROUND_N)).reshape(-1, 3)
    xys = np.random.default_rng(2026).uniform(suite.MOTION.lo, suite.MOTION.hi, (6, 2))  # the suite's
    with Renderer() as renderer:
        for name in meshes:
            atlas = bake_soft_atlas(sample_mesh(name), np.eye(4), suite.MOTION, suite.AREA, (256, 256),
                                    renderer=renderer, progress=False)
            after = PcssSoftShadow(atlas.method(warps="reproject"), suite.AREA, (3, 3))
            warp = SoftShadow(atlas, suite.AREA, (3, 3))

            def old(xy: Any, after: PcssSoftShadow = after) -> np.ndarray:
                acc = np.zeros(len(grid), np.float32)
                lit = np.empty(len(grid), np.float32)
                for depth, cam in after.maps(xy):
                    before.filter_into(lit, grid, depth, cam, before.cell_half_widths(after.cell, cam), 1,
                                       None, ShadowBias(), before.DepthTables.of(depth))
                    acc += lit
                return np.clip(acc / np.float32(after.n_samples), 0, 1)

            fns = {"warp_9": lambda xy, w=warp: w.visibility(xy, grid), "before": old,
                   "after": lambda xy, a=after: a.visibility(xy, grid)}
            gap = float(np.abs(fns["before"](xys[0]) - fns["after"](xys[0])).max())
            assert gap < 1e-4, f"before and after differ by {gap}"
            wall: dict[str, list[float]] = {k: [] for k in fns}
            cpu: dict[str, list[float]] = {k: [] for k in fns}
            for _ in range(repeats):
                for xy in xys:
                    for k, f in fns.items():
                        c0, t0 = time.process_time(), time.perf_counter()
                        f(xy)
                        wall[k].append(time.perf_counter() - t0)
                        cpu[k].append(time.process_time() - c0)
            w0, c0 = np.median(wall["warp_9"]), np.median(cpu["warp_9"])
            cells = [f"{k} wall {1e3 * np.median(wall[k]):.1f} ms ({np.median(wall[k]) / w0:.2f}x), "
                     f"cpu {1e3 * np.median(cpu[k]):.1f} ms ({np.median(cpu[k]) / c0:.2f}x)" for k in fns]
            print(name + ": " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    main(sys.argv)
