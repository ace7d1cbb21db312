"""Shadows in a relit billboard frame against the real meshes' frame with ray-cast shadows (#26).

Scene: N instances of the tree and the cow (dome assets, sun atlases of 21 directions at 128
texels, baked here), random yaws and scales, one camera looking over the field, three suns.
For each sun:

* the billboard frame with the atlases' shadows (:class:`~morphkit.sunlit.receivers.AtlasShadow`)
  and without, and the real-mesh frame (:class:`~morphkit.sunlit.litmesh.LitMeshMode`) with
  ray-cast shadows (:class:`~morphkit.sunlit.raycast.RayCastShadow`, the truth) and without;
* a frame's **shadowed pixels**: those its shadow darkens by at least ``--dark`` levels (of 255,
  in any channel) against the same frame without shadows (so a pixel turned away from the sun,
  which no shadow can darken, counts as neither);
* **shadow IoU** of the billboard frame's shadowed pixels against the mesh frame's, on **ground
  pixels** (the backdrop seen in both frames: layer alpha < 0.5 in both) and on **billboard
  pixels** (an object in both: alpha > 0.5 in both); and, to tell the atlases' error from the
  billboards', the real-mesh frame shadowed by the *atlases* against the truth on its object
  pixels ("mesh+atlas"), and the billboard frame shadowed by the *ray cast* (exact visibility at
  the billboards' own points): against the atlas-shadowed billboard frame on its billboard
  pixels ("bb atlas vs bb ray") and against the truth ("bb ray vs truth": what the billboards'
  geometry and normals allow at best);
* **visibility error**: mean |atlas visibility - ray-cast visibility| at every ground pixel's
  point (the lookups themselves, not the pixels);
* **ms a frame**, billboard frame with and without shadows, interleaved, medians of ``--reps``:
  "cached" re-renders the same sun (the field builder's light views made), "new sun" moves the
  sun by a few degrees each repetition (the field map built afresh).

``--offsets`` sweeps the receivers' normal offset (texels;
:data:`morphkit.tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS`).

Usage: ``PYTHONPATH=. python scripts/billboard_shadow_bench.py [--n 20] [--soft 1] [--pcss] [--size 320x240]``
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from morphkit import tol
from morphkit.billboard import Backdrop, BillboardScene, place_random
from morphkit.billboard.baking.bakelook import BAKE_AMBIENT
from morphkit.billboard.frames.facing import ViewpointFacing
from morphkit.camera import look_at, perspective
from morphkit.imaging.metrics import shadow_iou
from morphkit.imaging.shading import Lighting
from morphkit.programs.fixtures import FIELD_MESHES, field_domes
from morphkit.render import Renderer
from morphkit.sunlit.litmesh import LitMeshMode
from morphkit.sunlit.litmodes import LitMode
from morphkit.sunlit.raycast import RayCastShadow
from morphkit.sunlit.receivers import AtlasShadow, FilteredAtlasShadow, bake_scene_atlases
from morphkit.sunlit.shadowing import DARK_LEVELS, darkened
from morphkit.sunpath import sun

SUNS = ((30.0, 35.0), (120.0, 60.0), (-60.0, 20.0))  # (azimuth, elevation), degrees


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--soft", type=int, default=1)
    ap.add_argument("--pcss", action="store_true",
                    help="the atlas side's soft sun filtered from one map (FilteredAtlasShadow, "
                         "`billboards --soft`); the truth ray-casts --soft directions over the disc")
    ap.add_argument("--disc", type=float, default=0.267, help="sun disc radius, degrees")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--asset-size", type=int, default=128)
    ap.add_argument("--atlas-size", type=int, default=128)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--dark", type=int, default=DARK_LEVELS)
    ap.add_argument("--offsets", default=None, help="normal offsets to sweep, e.g. 0,1,2,3")
    ap.add_argument("--seed", type=int, default=3)
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split("x"))
    names = list(FIELD_MESHES)
    with Renderer() as r:
        meshes, assets, items = field_domes(r, a.asset_size)
        t0 = time.perf_counter()
        atlases = bake_scene_atlases(meshes, r, size=a.atlas_size)
        print(f"atlases baked in {time.perf_counter() - t0:.1f} s ({a.atlas_size} texels, 21 directions)")
        inst = place_random(names, a.n, np.random.default_rng(a.seed), half_size=max(2.0, 0.6 * np.sqrt(a.n)))
        scene = BillboardScene(assets, inst, backdrop=Backdrop(), facing=ViewpointFacing())
        half = float(np.abs(inst.xy).max()) if len(inst) else 1.0
        eye = np.array([0.0, -half - 2.0, 1.6])  # low, over the field's near edge
        cam = perspective(np.radians(50.0), (h, w), look_at(eye, np.array([0.0, 0.0, 0.3]),
                                                            up=np.array([0.0, 0.0, 1.0])))
        atlas = FilteredAtlasShadow(atlases, disc_deg=a.disc) if a.pcss else \
            AtlasShadow(atlases, samples=a.soft, disc_deg=a.disc)
        truth = RayCastShadow(meshes, samples=a.soft, disc_deg=a.disc)
        offsets = [tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS] if a.offsets is None else \
            [float(v) for v in a.offsets.split(",")]
        print(f"scene: {a.n} instances of tree + cow, {w}x{h}, soft {a.soft} (disc {a.disc} deg)"
              f"{', atlas side filtered (pcss)' if a.pcss else ''}, "
              f"dark >= {a.dark}/255")
        print("| sun (az/el) | offset | ground IoU | billboard IoU | mesh+atlas IoU | bb atlas vs bb ray | "
              "bb ray vs truth | ground vis. error | ms no shadow | ms shadow (cached) | "
              "ms shadow (new sun) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        moved = 0
        for az, el in SUNS:
            lighting = Lighting(BAKE_AMBIENT, (sun(az, el),))
            m_plain = LitMeshMode(r, items, lighting)
            m_shad = LitMeshMode(r, items, lighting, shadow=truth)
            fm0, fm1 = m_plain.render(scene, cam), m_shad.render(scene, cam)
            dark_m = darkened(fm0.rgb, fm1.rgb, a.dark)
            for off in offsets:
                tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS = off
                plain, shad = LitMode(lighting=lighting), LitMode(lighting=lighting, shadow=atlas)
                fb0, fb1 = plain.render(scene, cam), shad.render(scene, cam)
                dark_b = darkened(fb0.rgb, fb1.rgb, a.dark)
                fma = LitMeshMode(r, items, lighting, shadow=atlas).render(scene, cam)
                dark_ma = darkened(fm0.rgb, fma.rgb, a.dark)
                fbr = LitMode(lighting=lighting, shadow=truth).render(scene, cam)
                dark_br = darkened(fb0.rgb, fbr.rgb, a.dark)
                ab, am = fb1.layer[..., 3], fm1.layer[..., 3]
                ground = (ab < 0.5) & (am < 0.5)
                objs = (ab > 0.5) & (am > 0.5)
                iou_g = shadow_iou(dark_b[ground], dark_m[ground])
                iou_b = shadow_iou(dark_b[objs], dark_m[objs])
                mesh_objs = am > 0.5
                iou_ma = shadow_iou(dark_ma[mesh_objs], dark_m[mesh_objs])
                bb_objs = ab > 0.5
                iou_bab = shadow_iou(dark_b[bb_objs], dark_br[bb_objs])
                iou_brt = shadow_iou(dark_br[objs], dark_m[objs])
                _, gp = scene.backdrop.ground_points(cam)
                d = -lighting.lights[0].direction
                va = atlas.frame(inst, [d], gp, np.arange(len(inst))).visibility(gp)[0]
                vt = truth.frame(inst, [d], gp, np.arange(len(inst))).visibility(gp)[0]
                verr = float(np.abs(va - vt).mean())
                # its own builder: the moving sun empties its light-view cache, not the cached one's
                own = FilteredAtlasShadow(atlases, disc_deg=a.disc) if a.pcss else \
                    AtlasShadow(atlases, samples=a.soft, disc_deg=a.disc)
                moving = LitMode(lighting=lighting, shadow=own)
                t_plain, t_cached, t_new = [], [], []
                for _ in range(a.reps):
                    t0 = time.perf_counter()
                    plain.render(scene, cam)
                    t1 = time.perf_counter()
                    shad.render(scene, cam)
                    t2 = time.perf_counter()
                    moved += 1  # a sun never used before: every light view morphed afresh
                    moving.lighting = Lighting(BAKE_AMBIENT, (sun(az + 3.0 * moved, el + 0.05 * moved),))
                    moving.render(scene, cam)
                    t3 = time.perf_counter()
                    t_plain.append(t1 - t0)
                    t_cached.append(t2 - t1)
                    t_new.append(t3 - t2)
                print(f"| {az:g}/{el:g} | {off:g} | {iou_g:.3f} | {iou_b:.3f} | {iou_ma:.3f} | "
                      f"{iou_bab:.3f} | {iou_brt:.3f} | {verr:.4f} | "
                      f"{1e3 * statistics.median(t_plain):.0f} | {1e3 * statistics.median(t_cached):.0f} | "
                      f"{1e3 * statistics.median(t_new):.0f} |")


if __name__ == "__main__":
    main()
