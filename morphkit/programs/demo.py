"""``morphkit demo``: the sample scenes with ray-cast ground-truth shadows.

For each sample mesh (teapot, chair, cow) on a ground plane, lit by a
directional light, this writes to the output folder:

* ``<mesh>_scene.png``: the camera view with exact hard shadows (ray cast per
  camera pixel towards the light, self-shadowing included), composited by
  :func:`morphkit.imaging.composite.shade`;
* ``<mesh>_noshadow.png``: the same frame without shadows;
* ``<mesh>_visibility.png``: the ray-cast light visibility per camera pixel;
* ``<mesh>_light_depth.png``: the light-view depth map (orthographic, fitted
  tightly to the object), colour-mapped, background black;
* ``<mesh>_ground_shadow.png``: the ray-cast shadow on a top-down image of the
  ground square (white lit, black shadowed);

and, under a point light, ``<mesh>_warped_direct_raycast.png`` (hard shadow: warped
3 x 3 atlas | re-rendered map | ray cast) and ``<mesh>_reprojected_direct_raycast.png``
(the same atlas with ``warps="reproject"``), under an area light,
``<mesh>_soft_warped_direct_raycast.png`` (soft shadow, 9 light samples: PCSS on
reprojected maps | re-rendered, averaged | ray cast), and ``<mesh>_viewmorph.png`` (view morphing);
``billboards_compare.png`` (a scene of trees and people as classic | view-morphed
billboards | real meshes, the second paper's Fig. 5) and ``billboards_error.png``
(the absolute difference of classic and of view-morphed billboards from the meshes),
``billboards_textured.png`` (a textured asset, ``morphkit/data/photo_crate.glb`` baked
in its own look, as a view-morphed billboard beside its real mesh);
``billboards_shadowed.png`` (a field of trees and cows under a sun: relit billboards with
the shadows of their assets' sun atlases | the real meshes with ray-cast shadows);
plus ``overview.png`` and ``index.json`` (every file with what it shows, the
scene parameters and timings). Later features add their outputs here.

Every file is written atomically (:mod:`morphkit.files.fileio`), ``index.json`` last. The
output folder follows :mod:`morphkit.files.outfolder`'s rule: new or empty, or a folder that
already holds a demo (an ``index.json``, or the output marker of an unfinished one),
which is replaced only when asked (``overwrite=True``, ``morphkit demo --overwrite``);
the previous demo's files (PNGs) that the new one does not write again are then
removed, other files stay. A folder holding anything else is refused.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import trimesh

from ..files.fileio import write_image, write_json
from ..files.outfolder import DEMO_OUTPUT, claim_output, previous_run
from ..imaging.groundtruth import area_visibility, hard_visibility, receiver_grid
from ..meshes import sample_mesh
from ..protocols import PassRenderer, SceneRenderer
from ..render import Renderer
from ..scene import (
    Item,
    PointLight,
    Scene,
    SceneObject,
    light_view,
)
from ..shadow.frame import SKY, compare_frames, render_frame
from ..shadow.lookup import shadow_visibility
from .fixtures import (
    DEMO_LIGHT_DIRECTION,
    DEMO_MESHES,
    SOFT_LIGHT,
    VIEWMORPH_BASELINE_DEG,
    WARP_LIGHT,
    WARP_POSITION,
    WARP_RANGE,
    demo_scene,
    ground_truth_frame,
)
from .visualize import colorize_depth

__all__ = ["run_demo", "previous_demo", "overview_row", "OVERVIEW_TILE"]

#: Height (pixels) of each image in ``overview.png``.
OVERVIEW_TILE = 256


def _on_white(img: np.ndarray) -> np.ndarray:
    """RGB uint8 of an RGB or straight-alpha RGBA uint8 image, composited over white."""
    if img.shape[2] == 3:
        return img
    a = img[..., 3:].astype(np.float32) / 255.0
    return np.rint(img[..., :3] * a + 255.0 * (1.0 - a)).astype(np.uint8)


def overview_row(what: str, ours: np.ndarray, truth: np.ndarray, truth_name: str, figure: str) -> np.ndarray:
    """One row of ``overview.png``: morphkit's image | the ground truth, captioned with the error.

    Parameters
    ----------
    what : str
        The technique and scene, e.g. ``"warped hard shadow (cow)"``.
    ours, truth : numpy.ndarray
        uint8 ``(H, W, 3)`` RGB or ``(H, W, 4)`` straight-alpha RGBA (shown over white).
    truth_name : str
        What the truth is, e.g. ``"ray cast"``.
    figure : str
        The error figure, printed on the caption.

    Returns
    -------
    numpy.ndarray
        uint8 ``(OVERVIEW_TILE + 44, W', 3)`` RGB: a two-line caption over the two images.
    """
    tiles = []
    for img in (ours, truth):
        img = _on_white(img)
        w = round(img.shape[1] * OVERVIEW_TILE / img.shape[0])
        tiles.append(cv2.resize(img, (w, OVERVIEW_TILE), interpolation=cv2.INTER_AREA))
    body = np.concatenate([tiles[0], np.full((OVERVIEW_TILE, 6, 3), 255, np.uint8), tiles[1]], axis=1)
    lines = [what, f"left: morphkit | right: {truth_name} | {figure}"]
    font, scale = cv2.FONT_HERSHEY_SIMPLEX, 0.5
    width = max(body.shape[1], *(cv2.getTextSize(t, font, scale, 1)[0][0] + 12 for t in lines))
    body = np.pad(body, ((0, 0), (0, width - body.shape[1]), (0, 0)), constant_values=255)
    bar = np.full((44, width, 3), 255, np.uint8)
    for k, t in enumerate(lines):
        cv2.putText(bar, t, (6, 17 + 20 * k), font, scale, (20, 20, 20), 1, cv2.LINE_AA)
    return np.concatenate([bar, body], axis=0)


def _stack_rows(rows: list[np.ndarray]) -> np.ndarray:
    """Rows of different widths one under the other, padded with white on the right."""
    w = max(r.shape[1] for r in rows)
    return np.concatenate([np.pad(r, ((0, 4), (0, w - r.shape[1]), (0, 0)), constant_values=255)
                           for r in rows], axis=0)


def _warped_shadow_section(renderer: SceneRenderer, size: int, add: Any, rows: list[np.ndarray]
                           ) -> dict[str, Any]:
    """Per mesh: a 3 x 3 atlas, and the frame at a position between samples shadowed
    by the warped map, a re-rendered map and the ray cast, side by side."""
    from ..imaging.metrics import shadow_iou
    from ..shadow import DirectShadow, MotionRange, bake_atlas

    light = PointLight(WARP_LIGHT)
    motion = MotionRange(*WARP_RANGE)
    xy = np.array(WARP_POSITION)
    report: dict[str, Any] = {"light_position": list(WARP_LIGHT), "range": WARP_RANGE,
                              "position": list(WARP_POSITION), "grid": [3, 3]}
    for name in DEMO_MESHES:
        mesh = sample_mesh(name)
        t0 = time.perf_counter()
        atlas = bake_atlas(mesh, np.eye(4), motion, light, (size, size), renderer=renderer,
                           progress=False)
        bake_ms = 1e3 * (time.perf_counter() - t0)
        scene = demo_scene(mesh, size)
        scene = Scene(scene.obj, light, scene.camera, scene.receiver, ambient=scene.ambient)
        frames = compare_frames(renderer, scene, {
            "warped": atlas, "reprojected": atlas.method(warps="reproject"),
            "direct": DirectShadow(atlas.rig, mesh, renderer)}, xy)
        gt = frames["raycast"]["visibility"] < 0.5
        facing = frames["raycast"]["facing"]  # where a shadow changes the image
        report[name] = {"bake_ms": bake_ms, **{
            f"iou_{k}_vs_raycast_lightfacing_pixels": shadow_iou(
                frames[k]["visibility"] < 0.5, gt, mask=facing)
            for k in ("warped", "reprojected", "direct")}}
        write_image(add(f"{name}_warped_direct_raycast.png", "warped_shadow", name,
                        "point-light shadow at a position between the 3x3 samples: warped map | "
                        "re-rendered map | ray cast"),
                    np.concatenate([frames[k]["shaded"] for k in ("warped", "direct", "raycast")], 1))
        if name == "cow":
            _shadow_path_strip(renderer, scene, atlas, add)
            rows.append(overview_row("warped hard shadow, point light (cow, 3x3 atlas)",
                                     frames["warped"]["shaded"], frames["raycast"]["shaded"], "ray cast",
                                     "shadow IoU {:.3f}".format(
                                         report[name]["iou_warped_vs_raycast_lightfacing_pixels"])))
        write_image(add(f"{name}_reprojected_direct_raycast.png", "warped_shadow", name,
                        "the same with warps='reproject' (per-pixel 3-D reprojection): "
                        "reprojected map | re-rendered map | ray cast"),
                    np.concatenate([frames[k]["shaded"] for k in ("reprojected", "direct", "raycast")],
                                   1))
    return report


def _shadow_path_strip(renderer: SceneRenderer, scene: Scene, atlas: Any, add: Any, frames: int = 5
                       ) -> None:
    """The cow moving along the range's diagonal with its warped shadow: ``frames`` frames side by side."""
    lo, hi = np.array(WARP_RANGE[0]), np.array(WARP_RANGE[1])
    tiles = []
    for t in np.linspace(0.3, 0.7, frames):  # the middle of the diagonal: the cow stays in view
        xy = lo + t * (hi - lo)
        pose = scene.obj.pose.copy()
        pose[:2, 3] = xy
        moved = scene.with_object_pose(pose)
        depth, cam = atlas.shadow_map(xy)
        frame = render_frame(renderer, moved, lambda p, n, d=depth, c=cam: shadow_visibility(
            p, d, c, normals=n), background=SKY)
        img = frame["shaded"]
        tiles.append(cv2.resize(img, (OVERVIEW_TILE, OVERVIEW_TILE), interpolation=cv2.INTER_AREA))
    write_image(add("shadow_path_strip.png", "warped_shadow", "cow",
                    f"the cow moving along the range's diagonal, warped 3x3-atlas shadow, {frames} frames"),
                np.concatenate(tiles, axis=1))


def _soft_shadow_section(renderer: SceneRenderer, size: int, add: Any, rows: list[np.ndarray], *,
                         quick: bool) -> dict[str, Any]:
    """Per mesh: soft shadows of an area light at a position between samples, by
    warping one atlas per light sample (9), by re-rendering per sample (9), and
    by ray casting (8 x 8 samples; 4 x 4 with ``quick``), side by side."""
    from ..shadow import DirectShadow, MotionRange, SoftShadow, bake_soft_atlas, default_soft_shadow

    light = SOFT_LIGHT
    motion = MotionRange(*WARP_RANGE)
    xy = np.array(WARP_POSITION)
    dense = 4 if quick else 8
    map_size = min(size, 256)  # penumbrae are soft: 256^2 maps suffice (morphkit bench soft)
    report: dict[str, Any] = {"light_center": light.center.tolist(),
                              "half_extents": [light.u.tolist(), light.v.tolist()],
                              "position": list(WARP_POSITION), "samples": 9,
                              "map_size": map_size, "raycast_samples": dense * dense}
    for name in DEMO_MESHES:
        mesh = sample_mesh(name)
        atlas = bake_soft_atlas(mesh, np.eye(4), motion, light, (map_size, map_size),
                                renderer=renderer, progress=False)
        base = demo_scene(mesh, size)
        pose = base.obj.pose.copy()
        pose[:2, 3] = xy
        scene = Scene(SceneObject(mesh, pose), light, base.camera, base.receiver,
                      ambient=base.ambient)
        methods = {"warped": default_soft_shadow(atlas, light, (3, 3)),  # PCSS, reprojected maps
                   "direct": SoftShadow(DirectShadow(atlas.rig, mesh, renderer), light, (3, 3))}
        frames, ms = {}, {}
        for k, m in methods.items():
            t0 = time.perf_counter()
            frames[k] = render_frame(renderer, scene, m.visibility_fn(xy))
            ms[k] = 1e3 * (time.perf_counter() - t0)
        frames["raycast"] = render_frame(renderer, scene, lambda p, _n, obj=scene.obj: area_visibility(
            p, light, obj, dense))
        facing = frames["raycast"]["facing"]
        truth = frames["raycast"]["visibility"][facing]
        report[name] = {f"frame_ms_{k}": v for k, v in ms.items()} | {
            f"mae_{k}_vs_raycast_lightfacing_pixels": float(np.abs(
                frames[k]["visibility"][facing] - truth).mean()) for k in methods}
        if name == "teapot":
            rows.append(overview_row("soft shadow, area light (teapot, 9 samples, PCSS)",
                                     frames["warped"]["shaded"], frames["raycast"]["shaded"],
                                     f"ray cast {dense}x{dense}", "mean |visibility error| "
                                     f"{report[name]['mae_warped_vs_raycast_lightfacing_pixels']:.4f}"))
        write_image(add(f"{name}_soft_warped_direct_raycast.png", "soft_shadow", name,
                        "area-light soft shadow: PCSS on 9 reprojected samples | "
                        "re-rendered (9 samples, averaged) | "
                        f"ray cast ({dense}x{dense} samples)"),
                    np.concatenate([frames[k]["shaded"] for k in ("warped", "direct", "raycast")], 1))
    return report


def _viewmorph_section(renderer: SceneRenderer, size: int, add: Any, rows: list[np.ndarray]
                       ) -> dict[str, Any]:
    """Per mesh: left and right reference views, the view morph at s = 0.5 and the
    rendered middle view (ground truth), side by side, with the silhouette IoU.

    The morph uses dense pairs from the two depth maps and ``layers="auto"``
    (two depth layers where one mesh cannot follow crossing parts: the chair)."""
    from ..imaging.metrics import shadow_iou
    from ..viewmorph import ViewMorpher, from_depth, pair_depth
    from .fixtures import CENTRE_AZIMUTH, circle_camera, render_pair, textured_items

    report: dict[str, Any] = {"baseline_deg": VIEWMORPH_BASELINE_DEG, "s": 0.5}
    for name in DEMO_MESHES:
        mesh, items = textured_items(name)
        cams = [circle_camera(CENTRE_AZIMUTH + d * VIEWMORPH_BASELINE_DEG / 2, size) for d in (-1, 1, 0)]
        (i0, d0), (i1, d1), (gt, _) = render_pair(renderer, items, cams)
        corr = from_depth(cams[0], cams[1], d0, d1)
        t0 = time.perf_counter()
        vm = ViewMorpher.from_estimate(i0, i1, corr, layers="auto",
                                       layer_depth=pair_depth(cams[0], cams[1], d0, d1))
        t1 = time.perf_counter()
        mid = vm.morph(0.5, post=cams[2], frame="fixed")
        t2 = time.perf_counter()
        report[name] = {"silhouette_iou": shadow_iou(mid[..., 3] > 127, gt[..., 3] > 127),
                        "build_ms": 1e3 * (t1 - t0), "morph_ms": 1e3 * (t2 - t1), "mode": vm.mode,
                        "layers": vm.report.layers}
        if name == "chair":
            rows.append(overview_row(f"view morph s=0.5, {VIEWMORPH_BASELINE_DEG:g} deg apart (chair)",
                                     mid, gt, "rendered middle view",
                                     f"silhouette IoU {report[name]['silhouette_iou']:.3f}"))
        strip = np.concatenate([i0, mid, gt, i1], axis=1)
        write_image(add(f"{name}_viewmorph.png", "viewmorph", name,
                        "left reference | view morph s=0.5 | rendered middle view | right reference"),
                    strip)
    return report


def _billboard_section(renderer: SceneRenderer, size: int, add: Any, rows: list[np.ndarray], *,
                       quick: bool) -> dict[str, Any]:
    """A field of trees and people (K = 8 rings), one camera of the paper's pan: classic |
    view-morphed | real meshes, the per-billboard errors against the meshes, and an error figure."""
    from ..billboard import Backdrop, BillboardScene, ClassicMode, MeshMode, MorphMode, PanPath, place_random
    from ..billboard.asset import BAKE_AMBIENT, bake_lights
    from ..billboard.compare import compare_modes
    from .sources import resolve_assets

    t0 = time.perf_counter()
    res = resolve_assets(["tree", "person"], renderer, views=8, size=64 if quick else 128,
                         levels=2 if quick else 3)
    bake_ms = 1e3 * (time.perf_counter() - t0)
    n = 12 if quick else 30
    inst = place_random(list(res.assets), n, np.random.default_rng(0))
    scene = BillboardScene(res.assets, inst, backdrop=Backdrop())
    cam = PanPath.over(float(np.abs(inst.xy).max())).camera_at(0.5, (size * 3 // 4, size))
    cmp = compare_modes(scene, cam, {"classic": ClassicMode(), "morph": MorphMode()},
                        MeshMode(renderer, res.items, bake_lights(), BAKE_AMBIENT, supersample=2))
    write_image(add("billboards_compare.png", "billboards", "tree+person",
                    "billboard scene: classic | view-morphed | real meshes (paper 2, Fig. 5)"), cmp.strip)
    pan = [scene.render(c, MorphMode()).rgb
           for c in PanPath.over(float(np.abs(inst.xy).max())).cameras(5, (size * 3 // 8, size // 2))]
    write_image(add("billboards_pan_strip.png", "billboards", "tree+person",
                    "view-morphed billboards along the paper's pan (its Fig. 6), 5 cameras"),
                np.concatenate(pan, axis=1))
    e = cmp.errors["morph"]
    rows.append(overview_row(f"view-morphed billboards (trees, people; {n} instances, K = 8)",
                             cmp.frames["morph"].rgb, cmp.frames["mesh"].rgb, "real meshes",
                             f"per billboard IoU {e['iou']:.3f}, PSNR {e['psnr']:.1f} dB"))
    truth = cmp.frames["mesh"].rgb.astype(np.int16)
    diffs = [np.abs(cmp.frames[m].rgb.astype(np.int16) - truth).max(axis=2).astype(np.uint8)
             for m in ("classic", "morph")]
    err = cv2.cvtColor(cv2.applyColorMap(cv2.convertScaleAbs(np.concatenate(diffs, axis=1), alpha=2.0),
                                         cv2.COLORMAP_INFERNO), cv2.COLOR_BGR2RGB)  # OpenCV's map is BGR
    write_image(add("billboards_error.png", "billboards", "tree+person",
                    "largest channel difference from the meshes (x2, inferno): classic | view-morphed"), err)
    return {"instances": n, "views": 8, "bake_ms": bake_ms,
            "frame_ms": {m: f.stats.ms for m, f in cmp.frames.items()},
            "per_billboard_vs_mesh": cmp.errors}


def _textured_billboard_section(renderer: SceneRenderer, add: Any, *, quick: bool) -> dict[str, Any]:
    """The packaged textured asset (``photo_crate.glb``, loaded ``+z`` up) baked in its own look
    (K = 8): its view-morphed billboard beside the real textured mesh at three azimuths between
    references, over grey, and their IoU / PSNR (:func:`morphkit.bench.billboard_suite.quality`'s
    definitions: alpha > 1/2, premultiplied colour)."""
    from ..billboard import bake_asset, bake_lights
    from ..billboard.asset import BAKE_AMBIENT
    from ..imaging.metrics import psnr, shadow_iou
    from ..meshes import load_mesh, resolve_up
    from .fixtures import textured_demo_asset

    path = textured_demo_asset()
    mesh = load_mesh(path)
    size = 96 if quick else 192
    t0 = time.perf_counter()
    asset = bake_asset(mesh, renderer, name=path.stem, views=8, size=size, levels=1,
                       source_up=resolve_up(path, "auto"))
    bake_ms = 1e3 * (time.perf_counter() - t0)
    items = asset.items(mesh)
    grey = np.float32(0.5)
    tiles, per_az = [], {}
    for az in (22.5, 67.5, 157.5):
        i, j, s, _ = asset.ring.pair(az)
        bb = asset.morph(i, j, s)
        gt = renderer.source_view(asset.camera(az), items, bake_lights(), ambient=BAKE_AMBIENT)
        g = gt.astype(np.float32) / 255.0
        g = np.concatenate([g[..., :3] * g[..., 3:], g[..., 3:]], axis=2)
        per_az[str(az)] = {"iou": shadow_iou(bb[..., 3] > 0.5, g[..., 3] > 0.5),
                           "psnr": psnr(bb[..., :3], g[..., :3], data_range=1.0)}
        for im in (bb, g):
            tiles.append(np.rint(255 * (im[..., :3] + (1 - im[..., 3:]) * grey)).astype(np.uint8))
    write_image(add("billboards_textured.png", "billboards", path.stem,
                    "a textured asset (photo_crate.glb, own look, K = 8) at azimuths 22.5, 67.5, 157.5: "
                    "view-morphed billboard | real mesh, pairs left to right"), np.concatenate(tiles, axis=1))
    return {"asset": path.name, "appearance": asset.appearance, "source_up": asset.source_up, "views": 8,
            "size": size, "bake_ms": bake_ms, "morph_vs_mesh": per_az}


def _relit_billboard_section(renderer: PassRenderer, add: Any, *, quick: bool) -> dict[str, Any]:
    """A tree seen from three heights under three suns: the dome asset's view morph |
    the engines' octahedral impostor at equal bytes | the real mesh, each shaded by
    :mod:`morphkit.imaging.shading` (one model), over grey; IoU / PSNR as the billboard tiles'."""
    from ..billboard.baking.bakelook import BAKE_AMBIENT
    from ..billboard.domeasset import DOME_SUPERSAMPLE, bake_dome
    from ..billboard.impostor import bake_impostor, impostor_frame_size
    from ..imaging.metrics import psnr, shadow_iou
    from ..imaging.shading import Lighting, shade, shade_passes
    from ..sunpath import sun

    mesh = sample_mesh("tree")
    size = 64 if quick else 128
    t0 = time.perf_counter()
    dome = bake_dome(mesh, renderer, name="tree", size=size, appearance="checker")
    bake_ms = 1e3 * (time.perf_counter() - t0)
    frame = impostor_frame_size(dome.memory_bytes, 12, dome.levels)
    imp = bake_impostor(mesh, renderer, name="tree", frames=12, frame_size=frame, levels=dome.levels,
                        out_size=size, appearance="checker")
    items = dome.items(mesh)
    grey = np.float32(0.5)
    tiles, per_view = [], {}
    views = ((30.0, 15.0, 80.0, 25.0), (-70.0, 50.0, 200.0, 45.0), (120.0, 80.0, 0.0, 70.0))
    for az, el, sun_az, sun_el in views:  # viewing azimuth, elevation; the sun's
        lighting = Lighting(BAKE_AMBIENT, (sun(sun_az, sun_el),))
        cam = dome.camera(az, el)
        truth = shade_passes(renderer.source_passes(cam, items, lighting.lights, ambient=BAKE_AMBIENT,
                                                    supersample=DOME_SUPERSAMPLE), lighting, cam)
        row = {}
        for name, img in (("morph", shade(dome.surface(az, el), lighting)),
                          ("impostor", shade(imp.surface(az, el), lighting)), ("mesh", truth)):
            if name != "mesh":
                row[name] = {"iou": shadow_iou(img[..., 3] > 0.5, truth[..., 3] > 0.5),
                             "psnr": psnr(img[..., :3], truth[..., :3], data_range=1.0)}
            tiles.append(np.rint(255 * (img[..., :3] + (1 - img[..., 3:]) * grey)).astype(np.uint8))
        per_view[f"azimuth {az:g}, elevation {el:g}, sun {sun_az:g}/{sun_el:g}"] = row
    write_image(add("billboards_relit.png", "billboards", "tree",
                    "a tree seen from 15, 50 and 80 degrees up under three suns: view-morphed dome asset | "
                    "octahedral impostor at equal bytes | real mesh, relit by one shading model"),
                np.concatenate(tiles, axis=1))
    return {"size": size, "views": dome.dome.views, "bytes": dome.memory_bytes, "impostor_frame": frame,
            "impostor_bytes": imp.memory_bytes, "bake_ms": bake_ms, "vs_mesh": per_view}


def _shadowed_billboard_section(renderer: PassRenderer, add: Any, *, quick: bool) -> dict[str, Any]:
    """A field of trees and cows under one sun: relit billboards shadowed by their
    assets' sun atlases (:class:`~morphkit.sunlit.receivers.AtlasShadow`) | the real meshes
    shadowed by the ray cast (the truth); shadow IoU of the darkened pixels on the ground and on
    the objects (:func:`~morphkit.sunlit.shadowing.darkened`)."""
    from ..billboard import Backdrop, BillboardScene, place_random
    from ..billboard.baking.bakelook import BAKE_AMBIENT
    from ..billboard.frames.facing import ViewpointFacing
    from ..camera import look_at, perspective
    from ..imaging.metrics import shadow_iou
    from ..imaging.shading import Lighting
    from ..sunlit.litmesh import LitMeshMode
    from ..sunlit.litmodes import LitMode
    from ..sunlit.raycast import RayCastShadow
    from ..sunlit.receivers import AtlasShadow, bake_scene_atlases
    from ..sunlit.shadowing import darkened
    from ..sunpath import sun
    from .fixtures import FIELD_MESHES, field_domes

    t0 = time.perf_counter()
    names = FIELD_MESHES
    size, atlas_size, shape = (48, 64, (96, 128)) if quick else (96, 128, (288, 384))
    meshes, assets, items = field_domes(renderer, size, names)
    atlases = bake_scene_atlases(meshes, renderer, size=atlas_size)
    inst = place_random(names, 16, np.random.default_rng(3), half_size=2.5)
    scene = BillboardScene(assets, inst, backdrop=Backdrop(), facing=ViewpointFacing())
    cam = perspective(np.radians(50.0), shape, look_at(np.array([0.0, -4.8, 1.9]), np.array([0.0, 0.0, 0.3]),
                                                       up=np.array([0.0, 0.0, 1.0])))
    lighting = Lighting(BAKE_AMBIENT, (sun(30.0, 35.0),))
    t1 = time.perf_counter()
    bb = LitMode(lighting=lighting, shadow=AtlasShadow(atlases)).render(scene, cam)
    t2 = time.perf_counter()
    mesh = LitMeshMode(renderer, items, lighting, shadow=RayCastShadow(meshes)).render(scene, cam)
    t3 = time.perf_counter()
    bb0 = LitMode(lighting=lighting).render(scene, cam)
    mesh0 = LitMeshMode(renderer, items, lighting).render(scene, cam)
    db, dm = darkened(bb0.rgb, bb.rgb), darkened(mesh0.rgb, mesh.rgb)
    ab, am = bb.layer[..., 3], mesh.layer[..., 3]
    ground, objects = (ab < 0.5) & (am < 0.5), (ab > 0.5) & (am > 0.5)
    write_image(add("billboards_shadowed.png", "billboards", "tree+cow",
                    "16 trees and cows under a sun at 35 degrees: relit view-morphed billboards shadowed by "
                    "their assets' sun atlases (21 directions) | the real meshes with ray-cast shadows"),
                np.concatenate([bb.rgb, mesh.rgb], axis=1))
    return {"instances": len(inst), "sun": [30.0, 35.0], "asset_size": size, "atlas_size": atlas_size,
            "shadow_iou_ground": shadow_iou(db[ground], dm[ground]),
            "shadow_iou_objects": shadow_iou(db[objects], dm[objects]),
            "setup_ms": 1e3 * (t1 - t0), "billboard_frame_ms": 1e3 * (t2 - t1),
            "mesh_raycast_frame_ms": 1e3 * (t3 - t2), "section_ms": 1e3 * (time.perf_counter() - t0)}


def previous_demo(out: str | Path) -> Path | None:
    """The ``index.json`` of a demo already in folder ``out``, or None.

    Parameters
    ----------
    out : str or pathlib.Path
        A demo output folder (need not exist).

    Returns
    -------
    pathlib.Path or None
        ``<out>/index.json`` when it is a file, else the output marker of an unfinished demo
        (:func:`morphkit.files.outfolder.previous_run`), else None.
    """
    return previous_run(out, DEMO_OUTPUT)


def run_demo(out: str | Path, *, size: int = 512, quick: bool = False,
             overwrite: bool = False) -> dict[str, Any]:
    """Render the demo scenes into folder ``out`` (created); return (and write) the index.

    Parameters
    ----------
    out : path-like
        Output folder.
    size : int
        Image side in pixels (128 at most with ``quick``).
    quick : bool
        Smaller images, for a smoke test.
    overwrite : bool
        Replace a previous demo in ``out`` (module docstring).

    Returns
    -------
    dict
        The index written to ``<out>/index.json``: ``size``, ``light_direction``, ``files`` (path,
        kind, mesh, description of each image), ``timings_ms`` and one summary per section
        (``warped_shadows``, ``soft_shadows``, ``view_morphing``, ``billboards``).

    Raises
    ------
    ValidationError
        ``out`` is a file, or holds a previous demo and ``overwrite`` is False
        (checked before anything is rendered or written).
    OSError
        ``out`` cannot be created or written (read-only, a file on its path, ...).
    """
    claim = claim_output(out, DEMO_OUTPUT, overwrite=overwrite)
    with claim.writing() as folder:
        return _render_demo(folder, size, quick)


def _render_demo(out: Path, size: int, quick: bool) -> dict[str, Any]:
    """The body of :func:`run_demo` once its output folder is claimed."""
    if quick:
        size = min(size, 128)
    files: list[dict[str, Any]] = []
    timings: dict[str, dict[str, float]] = {}
    overview = []

    def add(name: str, kind: str, mesh: str, desc: str) -> Path:
        files.append({"path": name, "kind": kind, "mesh": mesh, "description": desc})
        return out / name

    with Renderer() as renderer:
        for name in DEMO_MESHES:
            mesh = sample_mesh(name)
            scene = demo_scene(mesh, size)
            t0 = time.perf_counter()
            frame = ground_truth_frame(renderer, scene)
            t1 = time.perf_counter()
            lo, hi = scene.obj.world_bounds()
            lcam = light_view(scene.light, trimesh.bounds.corners(np.array([lo, hi])), (size, size))
            ldepth = renderer.depth(lcam, [Item(mesh, scene.obj.pose)])
            t2 = time.perf_counter()
            g = receiver_grid(scene.receiver.half_size, (size, size))
            gvis = hard_visibility(g.reshape(-1, 3), scene.light, scene.obj).reshape(size, size)
            t3 = time.perf_counter()
            timings[name] = {"faces": int(len(mesh.faces)), "frame_and_raycast_ms": 1e3 * (t1 - t0),
                             "light_depth_ms": 1e3 * (t2 - t1), "ground_raycast_ms": 1e3 * (t3 - t2)}
            write_image(add(f"{name}_scene.png", "scene", name,
                            "camera view with ray-cast hard shadows (ground truth)"), frame["shaded"])
            write_image(add(f"{name}_noshadow.png", "scene", name, "camera view without shadows"),
                        frame["lit"])
            write_image(add(f"{name}_visibility.png", "visibility", name,
                            "ray-cast light visibility per camera pixel (white = lit)"),
                        np.rint(frame["visibility"] * 255).astype(np.uint8))
            write_image(add(f"{name}_light_depth.png", "light_depth", name,
                            "light-view depth map, orthographic, fitted to the object"),
                        colorize_depth(ldepth))
            write_image(add(f"{name}_ground_shadow.png", "ground_shadow", name,
                            "ray-cast shadow on a top-down image of the ground (black = shadow)"),
                        np.rint(gvis * 255).astype(np.uint8))
            overview.append(frame["shaded"])
        rows: list[np.ndarray] = []
        warped = _warped_shadow_section(renderer, size, add, rows)
        soft = _soft_shadow_section(renderer, size, add, rows, quick=quick)
        morphs = _viewmorph_section(renderer, min(size, 384), add, rows)
        billboards = _billboard_section(renderer, min(size, 512), add, rows, quick=quick)
        billboards["textured"] = _textured_billboard_section(renderer, add, quick=quick)
        billboards["relit"] = _relit_billboard_section(renderer, add, quick=quick)
        billboards["shadowed"] = _shadowed_billboard_section(renderer, add, quick=quick)
    from .preview import preview_page

    desc = ("one self-contained page: the relit tree morphed in the browser (WebGL 2), its shadow from "
            "its sun atlas; drag to orbit, sliders move the sun")
    page = preview_page("tree", add("tree_preview.html", "preview", "tree", desc), overwrite=True)
    billboards["preview"] = {"path": "tree_preview.html", "bytes": page["bytes"],
                             "fragment": page["fragment"]}
    write_image(add("overview.png", "overview", "all", "morphkit's results beside their ground truth, "
                    "each with its error: warped hard shadow, soft shadow, view morph, billboards"),
                _stack_rows(rows))
    write_image(add("groundtruth_overview.png", "overview", "all",
                    "the three demo scenes with ray-cast (exact) hard shadows side by side"),
                np.concatenate(overview, axis=1))
    index = {
        "morphkit_demo": 1,
        "size": size,
        "light_direction": list(DEMO_LIGHT_DIRECTION),
        "files": files,
        "timings_ms": timings,
        "warped_shadows": warped,
        "soft_shadows": soft,
        "view_morphing": morphs,
        "billboards": billboards,
    }
    write_json(out / "index.json", index)
    return index
