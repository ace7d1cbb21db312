"""``warps="reproject"`` gives the same shadow map, bit for bit, on 1, 2 or 4 threads (GL: a baked atlas).

Before the bands owned disjoint output rows, the early-z test of one band could not see what
another band had drawn, and one pixel in about 14k differed between thread counts (5.7e-5 in depth).
"""

from __future__ import annotations

import numpy as np
import pytest

from morphkit import settings
from morphkit.meshes import sample_mesh
from morphkit.scene import PointLight
from morphkit.shadow import MotionRange, bake_atlas
from morphkit.shadow.reprojection import method as reprojected_module

pytestmark = pytest.mark.gl


@pytest.mark.parametrize("name", ["cow", "chair"])
def test_reprojected_maps_do_not_depend_on_the_thread_count(renderer, monkeypatch, name):
    atlas = bake_atlas(sample_mesh(name), np.eye(4), MotionRange([-0.5, -0.4], [0.5, 0.4]),
                       PointLight([0.2, -0.1, 2.6]), (160, 192), renderer=renderer, control_grid=(9, 9),
                       progress=False)
    # split even these small maps into bands (the default threshold keeps them on one thread)
    monkeypatch.setattr(reprojected_module, "PARALLEL_MIN_SOURCE_PIXELS", 0)
    used = []
    real = reprojected_module.reproject_maps

    def spy(jobs, out, *, threads=1):
        used.append(threads)
        return real(jobs, out, threads=threads)

    monkeypatch.setattr(reprojected_module, "reproject_maps", spy)
    rng = np.random.default_rng(7)
    xys = rng.uniform([-0.5, -0.4], [0.5, 0.4], (12, 2))
    maps = {}
    for threads in (1, 2, 4):
        monkeypatch.setattr(settings, "WARP_THREADS", threads)
        for layers in (True, False):
            m = atlas.method(warps="reproject", layers=layers)
            maps[threads, layers] = [m.shadow_map(xy)[0] for xy in xys] + \
                [m.shadow_map(xys[0], light_offset=[0.05, -0.03])[0]]
    assert set(used) == {1, 2, 4}
    for layers in (True, False):
        ref = maps[1, layers]
        assert sum(int(np.isfinite(d).sum()) for d in ref) > 20000
        for threads in (2, 4):
            for a, b in zip(ref, maps[threads, layers], strict=True):
                np.testing.assert_array_equal(a, b)
