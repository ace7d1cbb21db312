"""Sun atlas grid vs error vs bytes (issue 26, first step): one instance's ground shadow.

For the tree and the cow sample meshes, three dome layouts of sun directions and two atlas
sizes, over 24 suns (azimuths on the golden angle, elevations 15..85 degrees, none on an atlas
direction) and 4 yaws of the instance: the ground shadow from the atlas's morphed light view
and from the direct orthographic depth render along the exact sun (same size), each against
the ray-cast truth (Embree) on a 256 x 256 grid of ground points over the shadow's extent (the
posed mesh's vertices projected along the sun onto the ground, plus a margin). Shadow IoU
(visibility < 0.5), mean |visibility error| over the grid, stored bytes of the atlas (float16
depth + uint8 coverage), the median time of a light view (morph) and of a direct render, and
the bake time (one run).

``--view-scale 2`` morphs the light views at twice the atlas's side (the direct render stays at
the atlas's side): what the morph's own resampling costs.

Usage: PYTHONPATH=. python scripts/sun_atlas_bench.py [--quick] [--view-scale K] [--json PATH]
(~3-5 min on 2 cores at K = 1)
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from morphkit.imaging.metrics import shadow_iou
from morphkit.meshes import normalize, sample_mesh
from morphkit.render import Renderer
from morphkit.sunlit.sunatlas import bake_sun_atlas, ground_visibility, sun_direction, sun_in_object
from morphkit.sunlit.sunbaselines import direct_light_view, ray_cast_ground_shadow
from morphkit.views.dome import DEFAULT_RINGS, ViewDome

DOMES = {
    "sparse": ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True),
    "default": ViewDome(DEFAULT_RINGS, top=True),
    "dense": ViewDome(((0.0, 16), (20.0, 16), (40.0, 12), (60.0, 8), (75.0, 6)), top=True),
}
GOLDEN_DEG = 180.0 * (3.0 - np.sqrt(5.0))
GRID = 256


def suns(n: int = 24) -> list[np.ndarray]:
    """World directions towards the sun: azimuths on the golden angle, elevations 15..85."""
    return [sun_direction((7.3 + k * GOLDEN_DEG) % 360.0 - 180.0, 15.0 + 70.0 * (k + 0.5) / n)
            for k in range(n)]


def yaw_pose(yaw_deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    pose = np.eye(4)
    pose[:2, :2] = [[c, -s], [s, c]]
    return pose


def ground_grid(verts: np.ndarray, pose: np.ndarray, sun: np.ndarray) -> np.ndarray:
    """(GRID^2, 3) ground points over the shadow's extent (vertices projected along the sun)."""
    w = verts @ pose[:3, :3].T + pose[:3, 3]
    g = w - (w[:, 2] / sun[2])[:, None] * sun
    lo, hi = g[:, :2].min(axis=0), g[:, :2].max(axis=0)
    pad = 0.05 * (hi - lo).max() + 0.05
    xs = np.linspace(lo[0] - pad, hi[0] + pad, GRID)
    ys = np.linspace(lo[1] - pad, hi[1] + pad, GRID)
    X, Y = np.meshgrid(xs, ys)
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def scores(vis: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    return shadow_iou(vis < 0.5, truth < 0.5), float(np.mean(np.abs(vis - truth)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="6 suns, 2 yaws, one mesh (a smoke run)")
    ap.add_argument("--view-scale", type=int, default=1, help="light views at K x the atlas side")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args()
    sun_list = suns(6 if args.quick else 24)
    yaws = [0.0, 90.0] if args.quick else [0.0, 37.0, 143.0, 251.0]
    meshes = ["tree"] if args.quick else ["tree", "cow"]
    for name, dome in DOMES.items():  # no sun on an atlas direction, in any instance's frame
        for sun in sun_list:
            for yaw in yaws:
                d = sun_in_object(yaw_pose(yaw), sun)
                az, el = np.degrees(np.arctan2(d[1], d[0])), np.degrees(np.arcsin(d[2]))
                assert dome.weights(az, el)[1].max() < 0.999, (name, az, el)
    rows = []
    with Renderer() as r:
        for mname in meshes:
            mesh = sample_mesh(mname)
            norm = normalize(mesh)
            verts = np.asarray(norm.vertices)
            cases = [(s, y, yaw_pose(y)) for s in sun_list for y in yaws]
            grids = [ground_grid(verts, pose, s) for s, _, pose in cases]
            t0 = time.perf_counter()
            truths = [ray_cast_ground_shadow(mesh, pose, s, g)
                      for (s, _, pose), g in zip(cases, grids, strict=True)]
            t_truth = (time.perf_counter() - t0) / len(cases)
            for size in (64, 128):
                direct, t_direct = [], []
                atlas0 = bake_sun_atlas(mesh, r, dome=DOMES["sparse"], size=size)  # warms the context
                for (s, _, pose), g in zip(cases, grids, strict=True):
                    t0 = time.perf_counter()
                    cam, dep = direct_light_view(atlas0, norm, r, sun_in_object(pose, s))
                    t_direct.append(time.perf_counter() - t0)
                    direct.append(ground_visibility(cam, dep, pose, g))
                d_sc = np.array([scores(v, t) for v, t in zip(direct, truths, strict=True)])
                for dname, dome in DOMES.items():
                    t0 = time.perf_counter()
                    atlas = bake_sun_atlas(mesh, r, dome=dome, size=size)
                    t_bake = time.perf_counter() - t0
                    sc, t_view = [], []
                    for (s, _, pose), g, truth in zip(cases, grids, truths, strict=True):
                        t0 = time.perf_counter()
                        side = args.view_scale * size
                        cam, dep = atlas.light_view(sun_in_object(pose, s), (side, side))
                        t_view.append(time.perf_counter() - t0)
                        sc.append(scores(ground_visibility(cam, dep, pose, g), truth))
                    sc = np.array(sc)
                    row = dict(mesh=mname, faces=len(mesh.faces), dome=dname, views=dome.views, size=size,
                               view_side=args.view_scale * size,
                               bytes=atlas.nbytes, iou_mean=float(sc[:, 0].mean()),
                               iou_min=float(sc[:, 0].min()), err_mean=float(sc[:, 1].mean()),
                               direct_iou_mean=float(d_sc[:, 0].mean()),
                               direct_iou_min=float(d_sc[:, 0].min()),
                               direct_err_mean=float(d_sc[:, 1].mean()),
                               ms_view=1e3 * float(np.median(t_view)),
                               ms_direct=1e3 * float(np.median(t_direct)),
                               ms_truth=1e3 * t_truth, s_bake=t_bake, cases=len(cases))
                    rows.append(row)
                    print(json.dumps(row), flush=True)
    print()
    print("| mesh | dome (views) | size (light view) | bytes | IoU mean / min | mean vis err "
          "| direct IoU mean / min | direct err | ms/light view | ms/direct | bake s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for w in rows:
        print(f"| {w['mesh']} | {w['dome']} ({w['views']}) | {w['size']} ({w['view_side']}) "
              f"| {w['bytes'] / 1024:.0f} KiB "
              f"| {w['iou_mean']:.3f} / {w['iou_min']:.3f} | {w['err_mean']:.4f} "
              f"| {w['direct_iou_mean']:.3f} / {w['direct_iou_min']:.3f} | {w['direct_err_mean']:.4f} "
              f"| {w['ms_view']:.0f} | {w['ms_direct']:.1f} | {w['s_bake']:.2f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
