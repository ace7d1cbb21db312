#!/usr/bin/env python3
"""The reprojected shadow maps of a base revision and of the working tree, compared bit for
bit and timed, interleaved, in one process.

Usage: ``PYTHONPATH=. python scripts/reproject_ab.py REV [check|time|both] [REPEATS]`` from
the checkout to test. ``REV``'s ``morphkit`` is extracted (``git archive``) into a temporary
folder as the package ``morphkit_base``; both load the *same* saved atlases (baked once
with the working tree, cached in ``$TMPDIR/reproject_ab``): the default soft shadow's
(``morphkit.bench.soft_suite``, 256^2, teapot and chair; its 9 light offsets), the
point-light shadow suite's (``morphkit.bench.shadow_suite``, cow, 512^2: the positions of
the 512^2 frame timing of issue #26) and a directional one (chair, 192^2; checked only).
The base's reprojection includes its own rig and cell code (``resolve``, ``cell``).

``check``: every map of ``ReprojectedMaps`` (``layers`` True and False, ``nearest``) at
seeded positions, with and without light offsets, on 1 and 2 threads
(``settings.WARP_THREADS``, the band split forced on), must equal the base's with
``np.array_equal`` (``+inf`` background included). ``time``: medians of one
``shadow_map`` call per map (the soft shadow's 9, the 512^2 map), base and working tree
interleaved call by call, and their ratio.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import tarfile
import tempfile
import time
import warnings
from io import BytesIO
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

import morphkit
from morphkit import settings
from morphkit.bench import shadow_suite, soft_suite
from morphkit.meshes import sample_mesh
from morphkit.render import Renderer
from morphkit.shadow import ShadowAtlas, bake_atlas, bake_soft_atlas
from morphkit.shadow.reprojection.method import ReprojectedMaps
from morphkit.shadow.soft import light_offsets

CACHE = Path(tempfile.gettempdir()) / "reproject_ab"


def base_package(rev: str) -> ModuleType:
    """``morphkit`` at ``rev``, imported as ``morphkit_base``."""
    root = Path(tempfile.mkdtemp())
    tar = subprocess.run(["git", "archive", rev, "morphkit"], check=True, capture_output=True).stdout
    with tarfile.open(fileobj=BytesIO(tar)) as t:
        t.extractall(root, filter="data")
    (root / "morphkit").rename(root / "morphkit_base")
    sys.path.insert(0, str(root))
    for name in ("shadow", "shadow.reprojected", "settings"):
        importlib.import_module(f"morphkit_base.{name}")
    return importlib.import_module("morphkit_base")


def atlases() -> dict[str, Path]:
    """The saved atlases (baked on first use)."""
    CACHE.mkdir(exist_ok=True)
    paths = {"teapot": CACHE / "teapot256.npz", "chair": CACHE / "chair256.npz", "cow": CACHE / "cow512.npz",
             "sun": CACHE / "chair_sun192.npz"}
    if all(p.exists() for p in paths.values()):
        return paths
    with Renderer() as r:
        for name in ("teapot", "chair"):
            if not paths[name].exists():
                bake_soft_atlas(sample_mesh(name), np.eye(4), soft_suite.MOTION, soft_suite.AREA, (256, 256),
                                renderer=r, progress=False).save(paths[name])
        if not paths["cow"].exists():
            bake_atlas(sample_mesh("cow"), np.eye(4), shadow_suite.MOTION, shadow_suite.POINT, (512, 512),
                       renderer=r, progress=False).save(paths["cow"])
        if not paths["sun"].exists():
            bake_atlas(sample_mesh("chair"), np.eye(4), shadow_suite.MOTION, shadow_suite.SUN, (192, 192),
                       renderer=r, progress=False).save(paths["sun"])
    return paths


def cases(name: str) -> tuple[np.ndarray, list[Any]]:
    """Positions and light offsets of a scene (None: the light itself)."""
    rng = np.random.default_rng(5 if name in ("cow", "sun") else 2026)
    if name == "sun":
        return rng.uniform(shadow_suite.MOTION.lo, shadow_suite.MOTION.hi, (12, 2)), [None]
    if name == "cow":  # the positions of /tmp/stage.py (the 512^2 frame of issue #26)
        xys = rng.uniform(shadow_suite.MOTION.lo, shadow_suite.MOTION.hi, (6, 2))
        return xys, [None, np.array([0.04, -0.03])]
    xys = rng.uniform(soft_suite.MOTION.lo, soft_suite.MOTION.hi, (6, 2))
    return xys, [None, *light_offsets(soft_suite.AREA, (3, 3))]


def check(base: ModuleType, paths: dict[str, Path]) -> None:
    """Bit-identity of every map (module docstring)."""
    bsettings = importlib.import_module("morphkit_base.settings")
    n = 0
    for name, path in paths.items():
        new = ShadowAtlas.load(path)
        old = base.shadow.ShadowAtlas.load(path)
        xys, offsets = cases(name)
        for threads in (1, 2):
            settings.WARP_THREADS = bsettings.WARP_THREADS = threads
            for kw in ({"layers": True}, {"layers": False}, {"nearest": True}):
                a = ReprojectedMaps(new.runtime, **kw)
                b = base.shadow.reprojected.ReprojectedMaps(old.runtime, **kw)
                for xy in xys:
                    for off in offsets:
                        da, ca = a.shadow_map(xy, light_offset=off, clamp=True)
                        db, cb = b.shadow_map(xy, light_offset=off, clamp=True)
                        assert da.dtype == db.dtype == np.float32 and da.shape == db.shape
                        assert np.array_equal(da, db), (name, threads, kw, xy, off,
                                                        int((da != db).sum()))
                        assert np.allclose(ca.K, cb.K, 0, 0)
                        n += 1
        print(f"{name}: identical ({n} maps so far)", flush=True)
    print(f"check: {n} maps bit-identical", flush=True)


def timing(base: ModuleType, paths: dict[str, Path], repeats: int) -> None:
    """Median ms per reprojected map, base and working tree interleaved."""
    for name, path in paths.items():
        new = ShadowAtlas.load(path)
        old = base.shadow.ShadowAtlas.load(path)
        new.prepare()
        old.prepare()
        a, b = new.method(warps="reproject"), old.method(warps="reproject")
        xys, offsets = cases(name)
        if name == "sun":
            continue
        offsets = offsets[:1] if name == "cow" else offsets[1:]
        for xy in xys:  # warm every cache (layers, compiled kernels)
            for off in offsets:
                a.shadow_map(xy, light_offset=off, clamp=True)
                b.shadow_map(xy, light_offset=off, clamp=True)
        t: dict[str, list[float]] = {"base": [], "new": []}
        frame: dict[str, list[float]] = {"base": [], "new": []}
        for _ in range(repeats):
            for xy in xys:
                for k, m in (("base", b), ("new", a)):
                    f0 = time.perf_counter()
                    for off in offsets:
                        t0 = time.perf_counter()
                        m.shadow_map(xy, light_offset=off, clamp=True)
                        t[k].append(time.perf_counter() - t0)
                    frame[k].append(time.perf_counter() - f0)
        mb, mn = np.median(t["base"]), np.median(t["new"])
        fb, fn = np.median(frame["base"]), np.median(frame["new"])
        print(f"{name} ({len(offsets)} map{'s' if len(offsets) > 1 else ''}/frame, threads "
              f"{settings.WARP_THREADS}): per map base {1e3 * mb:.3f} ms, new {1e3 * mn:.3f} ms "
              f"({mn / mb:.2f}x); per frame base {1e3 * fb:.2f} ms, new {1e3 * fn:.2f} ms ({fn / fb:.2f}x)",
              flush=True)


def main(argv: list[str]) -> None:
    """Run (module docstring)."""
    rev = argv[1]
    what = argv[2] if len(argv) > 2 else "both"
    repeats = int(argv[3]) if len(argv) > 3 else 5
    warnings.simplefilter("ignore")  # the clamped positions of the offset lights
    base = base_package(rev)
    print(f"new: {Path(morphkit.__file__).parent}; base: {rev} ({Path(base.__file__).parent})", flush=True)
    paths = atlases()
    if what in ("check", "both"):
        rp_new = importlib.import_module("morphkit.shadow.reprojection.method")
        rp_old = importlib.import_module("morphkit_base.shadow.reprojected")
        keep = rp_new.PARALLEL_MIN_SOURCE_PIXELS, rp_old.PARALLEL_MIN_SOURCE_PIXELS
        rp_new.PARALLEL_MIN_SOURCE_PIXELS = rp_old.PARALLEL_MIN_SOURCE_PIXELS = 0  # bands even when small
        threads = settings.WARP_THREADS
        check(base, paths)
        rp_new.PARALLEL_MIN_SOURCE_PIXELS, rp_old.PARALLEL_MIN_SOURCE_PIXELS = keep
        settings.WARP_THREADS = importlib.import_module("morphkit_base.settings").WARP_THREADS = threads
    if what in ("time", "both"):
        timing(base, paths, repeats)


if __name__ == "__main__":
    main(sys.argv)
