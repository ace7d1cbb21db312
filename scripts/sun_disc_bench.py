"""A soft sun over a field: one map filtered (PCSS) against N maps averaged (issue #26, #27).

Scene: N_INST instances of the tree and the cow (sample meshes, random yaws and scales, seed 26
+ n), their sun atlases (21 directions, 128 texels), the field's light view at the atlases'
resolution; suns at 25 and 55 degrees up; disc radii 0.267 (the real sun), 1, 2 and 4 degrees.
Truth: the fraction of 64 directions over the disc (a golden-angle spiral,
:func:`morphkit.sunlit.receivers.sun_disc`) that the ray cast from each ground point sees
(Embree); the 32-direction truth against it on one case shows how far it has converged.
Methods: ``avg-K`` -- K field maps over the disc (the same spiral), their hard lookups averaged (alpha 1/K);
``pcss`` -- one map along the centre at :data:`morphkit.tol.SUN_DISC_MAP_SCALE` times the
atlases' texels (as :class:`morphkit.sunlit.receivers.FilteredAtlasShadow` draws it),
:func:`morphkit.sunlit.sundisc.disc_visibility`.
Metrics on a GRID^2 ground grid over the field: ``mae`` -- mean |visibility error| over the
points that the truth or the estimate do not see fully lit; ``banding`` --
:func:`morphkit.bench.soft_suite.banding`; ``ms`` -- the maps and the lookups, median of 3.

Usage: PYTHONPATH=. python scripts/sun_disc_bench.py [--n 30] [--grid 256]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from morphkit import tol
from morphkit.bench.soft_suite import banding
from morphkit.billboard.frames.instances import Instances, place_random
from morphkit.meshes import sample_mesh
from morphkit.render import Renderer
from morphkit.sunlit.fieldbaselines import posed_asset_meshes, ray_cast_field
from morphkit.sunlit.fieldshadow import FieldShadow
from morphkit.sunlit.receivers import sun_disc
from morphkit.sunlit.sunatlas import bake_sun_atlas, sun_direction
from morphkit.sunlit.sundisc import disc_visibility
from morphkit.views.dome import ViewDome

SPARSE = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
ASSETS = ("tree", "cow")


def _truth(meshes: dict, inst: Instances, posed: list, d: np.ndarray, radius: float, k: int,
           pts: np.ndarray) -> np.ndarray:
    seen = [ray_cast_field(meshes, inst, s, pts, posed=posed) for s in sun_disc(d, k, radius)]
    return np.mean(seen, axis=0)


def _score(est: np.ndarray, truth: np.ndarray, g: int) -> tuple[float, float]:
    region = (truth < 1.0 - tol.PENUMBRA_EPS) | (est < 1.0 - tol.PENUMBRA_EPS)
    return float(np.abs(est - truth)[region].mean()), banding(est.reshape(g, g), truth.reshape(g, g))


def _estimate(fs: FieldShadow, inst: Instances, d: np.ndarray, radius: float, tpu: float,
              rect: tuple[float, float, float, float], pts: np.ndarray, k: int) -> np.ndarray:
    """``k`` maps averaged, or (``k = 0``) one map filtered."""
    if k == 0:
        m = fs.build(inst, d, tpu * tol.SUN_DISC_MAP_SCALE, rect)  # as FilteredAtlasShadow draws it
        return disc_visibility(pts, m.depth, m.camera, radius)
    maps = [fs.build(inst, s, tpu, rect) for s in sun_disc(d, k, radius)]
    return np.mean([m.visibility(pts) for m in maps], axis=0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=30)
    ap.add_argument("--grid", type=int, default=256)
    ap.add_argument("--radii", type=float, nargs="+", default=[0.267, 1.0, 2.0, 4.0])
    args = ap.parse_args()
    meshes = {nm: sample_mesh(nm) for nm in ASSETS}
    with Renderer() as r:
        atlases = {nm: bake_sun_atlas(meshes[nm], r, dome=SPARSE, size=128) for nm in ASSETS}
    tpu = min(a.size / (2.0 * a.cameras.half_extent[0]) for a in atlases.values())
    inst = place_random(ASSETS, args.n, np.random.default_rng(26 + args.n))
    half = max(1.0, 1.5 * np.sqrt(args.n) / 2) + 1.0
    rect = (-half, -half, half, half)
    xs = np.linspace(-half, half, args.grid)
    X, Y = np.meshgrid(xs, xs)
    pts = np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)
    posed = posed_asset_meshes(meshes, inst)
    fs = FieldShadow(atlases)
    print("| sun el | disc deg | method | mae (shadow + penumbra) | banding | ms |")
    print("|---|---|---|---|---|---|")
    for el in (25.0, 55.0):
        d = sun_direction(-35.0, el)
        for radius in args.radii:
            truth = _truth(meshes, inst, posed, d, radius, 64, pts)
            if el == 25.0 and radius == 2.0:
                half = _truth(meshes, inst, posed, d, radius, 32, pts)
                m, b = _score(half, truth, args.grid)
                print(f"| {el:.0f} | {radius:g} | truth-32 vs truth-64 | {m:.4f} | {b:.4f} | - |")
            for k in (4, 8, 16, 0):
                times = []
                for _ in range(3):
                    fs.clear()
                    t0 = time.perf_counter()
                    est = _estimate(fs, inst, d, radius, tpu, rect, pts, k)
                    times.append(time.perf_counter() - t0)
                m, b = _score(est, truth, args.grid)
                name = f"avg-{k}" if k else "pcss"
                ms = 1e3 * np.median(times)
                print(f"| {el:.0f} | {radius:g} | {name} | {m:.4f} | {b:.4f} | {ms:.0f} |", flush=True)


if __name__ == "__main__":
    main()
