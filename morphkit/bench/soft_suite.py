"""``morphkit bench soft``: soft shadows of an area light, warped vs re-rendered.

Scene (stated once; every figure names it): a sample mesh (normalised: largest
extent 1, resting on the ground) moving over ``[-0.6, 0.6]^2`` of the ground
plane, lit by a square **area light** ``0.6 x 0.6`` parallel to the ground,
centred at ``(0.25, -0.2, 2.4)`` (the shadow suite's point light, grown). The
atlas is baked for a point light at the centre over the range grown by the
light's extent, ``[-0.9, 0.9]^2`` (:func:`morphkit.shadow.soft.bake_soft_atlas`;
3 x 3 maps, 17 x 17 control grid).

Methods (timed in the same run, interleaved), each with ``N`` light samples
(the number in the name: 5 = the paper's centre + corners, 9 = 3 x 3 and
16 = 4 x 4 cell centres): ``warp_N`` (one warp of the atlas per sample,
:class:`~morphkit.shadow.soft.SoftShadow`), ``direct_N`` (one depth render per
sample: Heckbert & Herf), and ``hard`` (one warped map for the light's centre:
what ignoring the light's size costs). ``ms_median`` is the time to produce the
soft visibility of the ``256 x 256`` ground grid (all maps and lookups).

Ground truth: the ray-cast fraction of the light seen by each ground point, over
the ground square ``[-1.7, 1.7]^2`` sampled at ``256 x 256`` pixel centres, with
``16 x 16`` light samples (``8 x 8`` in ``--quick``). Metrics, averaged over
seeded random positions: ``mae`` (mean abs visibility error over the grid),
``mae_shadow`` (the same over the points that truth or estimate do not see
fully lit: the shadow and penumbra, where the error lives), ``mae_same`` (against
the ray cast with the method's *own* ``N`` samples: the method's error without
the sampling error, zero for a perfect shadow map).
"""

from __future__ import annotations

import gc
import time
from typing import Any

import numpy as np

from ..groundtruth import area_visibility, receiver_grid, sampled_visibility
from ..meshes import sample_mesh
from ..protocols import SceneRenderer
from ..scene import AreaLight, SceneObject
from ..shadow import DirectShadow, MotionRange, SoftShadow, bake_soft_atlas
from ..shadow.soft import FIVE_SAMPLES
from .harness import make_row, time_cycling

__all__ = ["run", "FLOOR_METHOD", "PLOT_OPTIONS"]

SUITE = "soft"
#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "direct_9"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS = {"size_key": "size", "error_key": "mae_shadow", "panel_keys": ("mesh", "what")}

MOTION = MotionRange([-0.6, -0.6], [0.6, 0.6])
AREA = AreaLight([0.25, -0.2, 2.4], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])
GROUND_HALF, GROUND_N = 1.7, 256
SAMPLES: dict[int, Any] = {5: FIVE_SAMPLES, 9: (3, 3), 16: (4, 4)}


def _positions(n: int, seed: int = 2026) -> np.ndarray:
    return np.random.default_rng(seed).uniform(MOTION.lo, MOTION.hi, (n, 2))


class _Truth:
    """Ray-cast area-light visibility per (mesh, position, samples), computed once."""

    def __init__(self, dense: int) -> None:
        self.grid = receiver_grid(GROUND_HALF, (GROUND_N, GROUND_N)).reshape(-1, 3)
        self.dense = dense
        self._cache: dict[tuple[Any, ...], np.ndarray] = {}

    def __call__(self, mesh_name: str, mesh: Any, xy: np.ndarray,
                 same_as: SoftShadow | None = None) -> np.ndarray:
        """Dense truth, or with ``same_as`` the truth with that method's own samples."""
        key = (mesh_name, xy.tobytes(), None if same_as is None else same_as.offsets.tobytes())
        if key not in self._cache:
            pose = np.eye(4)
            pose[:2, 3] = xy
            obj = SceneObject(mesh, pose)
            self._cache[key] = (area_visibility(self.grid, AREA, obj, self.dense) if same_as is None
                                else sampled_visibility(self.grid, same_as.point_lights(), obj))
        return self._cache[key]


def _errors(soft: SoftShadow, mesh_name: str, mesh: Any, xys: np.ndarray, truth: _Truth
            ) -> dict[str, float]:
    mae, mae_shadow, mae_same = [], [], []
    for xy in xys:
        est = soft.visibility(xy, truth.grid)
        gt = truth(mesh_name, mesh, xy)
        err = np.abs(est - gt)
        mae.append(float(err.mean()))
        region = (gt < 1) | (est < 1)
        mae_shadow.append(float(err[region].mean()) if region.any() else 0.0)
        mae_same.append(float(np.abs(est - truth(mesh_name, mesh, xy, soft)).mean()))
    return {"mae": float(np.mean(mae)), "mae_shadow": float(np.mean(mae_shadow)),
            "mae_same": float(np.mean(mae_same))}


def _time(methods: dict[str, SoftShadow], xys: np.ndarray, grid: np.ndarray, repeats: int
          ) -> dict[str, Any]:
    """Time one soft visibility of ``grid`` per call, cycling through positions."""
    fns = {name: (lambda xy, m=m: m.visibility(xy, grid)) for name, m in methods.items()}
    return time_cycling(fns, xys, repeats=repeats, warmup=1)


def _methods(atlas: Any, direct: DirectShadow, ns: list[int]) -> dict[str, SoftShadow]:
    methods = {"hard": SoftShadow(atlas, AREA, np.zeros((1, 2)))}
    for n in ns:
        for kind, m in (("warp", atlas), ("direct", direct)):
            methods[f"{kind}_{n}"] = SoftShadow(m, AREA, SAMPLES[n])
    return methods


def _accuracy_rows(renderer: SceneRenderer, quick: bool, truth: _Truth) -> list[dict[str, Any]]:
    rows = []
    meshes = ["cow"] if quick else ["teapot", "chair", "cow"]
    sizes = [128, 256] if quick else [128, 256, 512]
    ns = [5, 9] if quick else [5, 9, 16]
    xys = _positions(3 if quick else 10)
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        for size in sizes:
            atlas = bake_soft_atlas(mesh, np.eye(4), MOTION, AREA, (size, size), renderer=renderer,
                                    progress=False)
            methods = _methods(atlas, DirectShadow(atlas.rig, mesh, renderer), ns)
            timings = _time(methods, xys, truth.grid, repeats=3 if quick else 7)
            for name, m in methods.items():
                err = _errors(m, mesh_name, mesh, xys, truth)
                err["mem_mb"] = (atlas.memory_bytes if not name.startswith("direct") else 0) / 2**20
                rows.append(make_row(SUITE, name, {"what": "soft", "mesh": mesh_name, "size": size,
                                                   "samples": m.n_samples,
                                                   "faces": len(mesh.faces)},
                                     timings[name], metrics=err))
            del atlas, methods
            gc.collect()
    return rows


def _complexity_rows(renderer: SceneRenderer, quick: bool) -> list[dict[str, Any]]:
    """Cow from ~6k to ~1M faces, 256^2 maps, 9 samples: time of one soft shadow."""
    rows = []
    faces = [6000, 50000] if quick else [6000, 50000, 300000, 1000000]
    size = 256
    xys = _positions(6, seed=11)
    grid = receiver_grid(GROUND_HALF, (GROUND_N, GROUND_N)).reshape(-1, 3)
    for f in faces:
        mesh = sample_mesh("cow", faces=f)
        atlas = bake_soft_atlas(mesh, np.eye(4), MOTION, AREA, (size, size), renderer=renderer,
                                progress=False)
        methods = {"warp_9": SoftShadow(atlas, AREA, (3, 3)),
                   "direct_9": SoftShadow(DirectShadow(atlas.rig, mesh, renderer), AREA, (3, 3))}
        timings = _time(methods, xys, grid, repeats=3 if quick else 7)
        for name in methods:
            rows.append(make_row(SUITE, name, {"what": "complexity", "mesh": "cow", "size": size,
                                               "samples": 9, "faces": len(mesh.faces)},
                                 timings[name]))
    return rows


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """All soft-shadow rows: accuracy + time per mesh and map size, complexity sweep.

    Parameters
    ----------
    quick : bool
        Fewer and smaller cases (a smoke run).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    t0 = time.perf_counter()
    truth = _Truth(dense=8 if quick else 16)
    with Renderer() as renderer:
        rows = _accuracy_rows(renderer, quick, truth)
        rows += _complexity_rows(renderer, quick)
    print(f"soft suite: {len(rows)} rows in {time.perf_counter() - t0:.0f} s", flush=True)
    return rows
