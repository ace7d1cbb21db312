"""A field of instances' ground shadow (issue 26): sun atlases placed into one light view.

For fields of 10 and 100 instances (tree and cow sample meshes, random positions, yaws and
scales from a seeded rng, :func:`morphkit.billboard.frames.instances.place_random`) under 4 suns
(elevations 20..70 degrees): the field's light view built from the atlases (sparse dome,
128 texels; :class:`morphkit.sunlit.fieldshadow.FieldShadow`) and rendered directly (all
posed meshes, one depth draw into the same view), each looked up on a GRID x GRID ground
grid over the field and scored against the ray cast of the grid towards the sun against all
posed meshes (Embree): shadow IoU (visibility < 0.5). Times per sun change (building the
field map): the atlas way with an empty light-view cache (cold) and with the cache warm
(the same sun again: every view cached), and the direct render (the renderer's context
warmed first). Medians over the suns.

The field view's resolution is the atlases' (texels per unit of a 128-texel view of an
instance at scale 1, the larger asset's), so both ways see the same texel size.

``--yaw-classes K`` draws the yaws from K values (instances of one asset and class share a light
view per sun); ``--tpu-scale`` sets the field view's resolution against the atlases'.

Usage: PYTHONPATH=. python scripts/field_shadow_bench.py [--counts 10 100] [--grid 512]
[--yaw-classes K] [--tpu-scale S] [--max-level L] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from morphkit.billboard.frames.instances import Instances, place_random
from morphkit.imaging.metrics import shadow_iou
from morphkit.meshes import normalize, sample_mesh
from morphkit.render import Renderer
from morphkit.sunlit.fieldbaselines import direct_field_map, posed_asset_meshes, ray_cast_field
from morphkit.sunlit.fieldshadow import FieldShadow, MorphDrawer
from morphkit.sunlit.fieldsplat import SplatDrawer
from morphkit.sunlit.sunatlas import bake_sun_atlas, sun_direction
from morphkit.views.dome import ViewDome

SPARSE = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
SUNS = [sun_direction(az, el) for az, el in ((-140.0, 20.0), (-35.0, 37.0), (62.0, 53.0), (151.0, 70.0))]
ASSETS = ("tree", "cow")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", type=int, nargs="+", default=[10, 100])
    ap.add_argument("--grid", type=int, default=512)
    ap.add_argument("--seed", type=int, default=26)
    ap.add_argument("--yaw-classes", type=int, default=0,
                    help="yaws from K evenly spaced values (0: uniform); a class shares its light views")
    ap.add_argument("--tpu-scale", type=float, default=1.0,
                    help="the field view at S x the atlases' resolution")
    ap.add_argument("--drawer", choices=("splat", "morph"), default="splat",
                    help="how the field view is drawn: points splatted (default) or views morphed and placed")
    ap.add_argument("--max-level", type=int, default=None,
                    help="splat: the coarsest atlas point level (0: every atlas texel; default the drawer's)")
    ap.add_argument("--faces", type=int, default=0,
                    help="build the sample meshes at about this many faces (0: the stored ~6k)")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args()
    meshes = {nm: sample_mesh(nm, **({'faces': args.faces} if args.faces else {})) for nm in ASSETS}
    norm = {nm: normalize(m) for nm, m in meshes.items()}
    rows = []
    with Renderer() as r:
        t0 = time.perf_counter()
        atlases = {nm: bake_sun_atlas(meshes[nm], r, dome=SPARSE, size=128) for nm in ASSETS}
        t_bake = time.perf_counter() - t0
        tpu = args.tpu_scale * min(a.size / (2.0 * a.cameras.half_extent[0]) for a in atlases.values())
        for n in args.counts:
            rng = np.random.default_rng(args.seed + n)
            inst = place_random(ASSETS, n, rng)
            if args.yaw_classes:
                k = args.yaw_classes
                yaws = (360.0 / k) * rng.integers(0, k, n)
                inst = Instances(inst.names, inst.asset, inst.xy, yaws, inst.scale)
            half = max(1.0, 1.5 * np.sqrt(n) / 2)
            rect = (-half - 1.0, -half - 1.0, half + 1.0, half + 1.0)
            xs = np.linspace(rect[0], rect[2], args.grid)
            X, Y = np.meshgrid(xs, xs)
            pts = np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)
            posed = posed_asset_meshes(meshes, inst)
            splat = SplatDrawer() if args.max_level is None else SplatDrawer(max_level=args.max_level)
            fs = FieldShadow(atlases, splat if args.drawer == "splat" else MorphDrawer())
            direct_field_map(fs, norm, r, inst, SUNS[0], tpu, rect)  # warm the context at this size
            sc, t_cold, t_warm, t_direct, t_truth, shapes, views = [], [], [], [], [], [], []
            for sun in SUNS:
                t = time.perf_counter()
                truth = ray_cast_field(meshes, inst, sun, pts, posed=posed) < 0.5
                t_truth.append(time.perf_counter() - t)
                fs.clear()
                t = time.perf_counter()
                fm = fs.build(inst, sun, tpu, rect)
                t_cold.append(time.perf_counter() - t)
                views.append(fs.drawer.misses if isinstance(fs.drawer, MorphDrawer) else 0)
                t = time.perf_counter()
                fm = fs.build(inst, sun, tpu, rect)
                t_warm.append(time.perf_counter() - t)
                t = time.perf_counter()
                dm = direct_field_map(fs, norm, r, inst, sun, tpu, rect)
                t_direct.append(time.perf_counter() - t)
                shapes.append(fm.camera.shape)
                sc.append((shadow_iou(fm.visibility(pts) < 0.5, truth),
                           shadow_iou(dm.visibility(pts) < 0.5, truth)))
            sc = np.array(sc)
            row = dict(instances=n, faces={nm: len(m.faces) for nm, m in meshes.items()},
                       yaw_classes=args.yaw_classes, suns=len(SUNS), grid=args.grid, tpu=tpu,
                       field_side_max=int(max(max(s) for s in shapes)),
                       light_views_per_sun=float(np.mean(views)),
                       iou_atlas=sc[:, 0].tolist(), iou_direct=sc[:, 1].tolist(),
                       iou_atlas_mean=float(sc[:, 0].mean()), iou_atlas_min=float(sc[:, 0].min()),
                       iou_direct_mean=float(sc[:, 1].mean()), iou_direct_min=float(sc[:, 1].min()),
                       ms_cold=1e3 * float(np.median(t_cold)), ms_warm=1e3 * float(np.median(t_warm)),
                       ms_direct=1e3 * float(np.median(t_direct)), ms_truth=1e3 * float(np.median(t_truth)),
                       s_bake_both=t_bake)
            rows.append(row)
            print(json.dumps(row), flush=True)
    print()
    print("| instances (yaw classes) | field view (max side) | light views/sun | atlas IoU mean / min "
          "| direct IoU mean / min | ms atlas cold | ms atlas warm | ms direct | ms ray cast |")
    print("|---|---|---|---|---|---|---|---|---|")
    for w in rows:
        print(f"| {w['instances']} ({w['yaw_classes'] or 'any'}) | {w['field_side_max']} "
              f"| {w['light_views_per_sun']:.0f} "
              f"| {w['iou_atlas_mean']:.3f} / {w['iou_atlas_min']:.3f} "
              f"| {w['iou_direct_mean']:.3f} / {w['iou_direct_min']:.3f} "
              f"| {w['ms_cold']:.0f} | {w['ms_warm']:.0f} | {w['ms_direct']:.0f} | {w['ms_truth']:.0f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
