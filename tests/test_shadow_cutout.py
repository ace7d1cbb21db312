"""Cut-out casters in the light's depth maps and in shadow frames (GL): holes at masked
texels, agreement with the cut-out-aware ray cast, the object's own look in frames."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import trimesh

from morphkit.imaging.groundtruth import hard_visibility, receiver_grid
from morphkit.imaging.metrics import shadow_iou
from morphkit.meshes import load_mesh, sample_mesh
from morphkit.programs.fixtures import alpha_card, checker_alpha, demo_scene, leaf_texture, write_leaf_plant
from morphkit.scene import DirectionalLight, Item, Scene, SceneObject, light_view, translation
from morphkit.shadow import DirectShadow, MotionRange, bake_atlas, shadow_visibility
from morphkit.shadow.frame import frame_items, render_frame

pytestmark = pytest.mark.gl

CELLS, TEXELS = 4, 8
DOWN = DirectionalLight([0.0, 0.0, -1.0])
SUN = DirectionalLight([-0.5, 0.35, -1.0])  # morphkit bench shadows' directional light
MOTION = MotionRange([-0.6, -0.6], [0.6, 0.6])


@pytest.fixture(scope="module")
def plant(tmp_path_factory):
    return load_mesh(write_leaf_plant(tmp_path_factory.mktemp("plant")))


def _card_map(renderer, card: trimesh.Trimesh, pose: np.ndarray, light, size: int):
    lo, hi = SceneObject(card, pose).world_bounds()
    lcam = light_view(light, trimesh.bounds.corners(np.array([lo, hi])), (size, size))
    return renderer.depth(lcam, [Item(card, pose)]), lcam


def test_light_depth_has_holes_at_masked_texels(renderer):
    """A checker card seen from a light straight above: depth at the opaque squares' pixels,
    background at the holes' (pixels a texel or more from the squares' edges)."""
    pose = translation(0.0, 0.0, 0.5)
    depth, lcam = _card_map(renderer, alpha_card(checker_alpha(CELLS, TEXELS)), pose, DOWN, 128)
    origins, _ = lcam.rays()
    x, y = origins[..., 0], origins[..., 1]  # orthographic: each pixel's ray starts above its point
    fx, fy = (x + 0.5) * CELLS, (0.5 - y) * CELLS
    on_card = (np.abs(x) < 0.5) & (np.abs(y) < 0.5)
    exact = on_card & (np.minimum(np.abs(fx - np.rint(fx)), np.abs(fy - np.rint(fy))) * TEXELS > 1.0)
    opaque = (np.floor(fx).astype(int) + np.floor(fy).astype(int)) % 2 == 0
    assert exact.sum() > 5000
    np.testing.assert_array_equal(np.isfinite(depth[exact]), opaque[exact])
    assert 0.3 < np.isfinite(depth[on_card]).mean() < 0.7


def test_leaf_edge_from_the_depth_map_agrees_with_the_ray_cast_to_a_texel(renderer):
    """A horizontal leaf card (64^2 texels) under a slanted sun, its map at about 2 pixels per
    texel: every ground point where the map's shadow and the ray-cast shadow differ lies within
    one texel of the ray-cast shadow's edge (measured 0.56; 0.19 is one ground pixel)."""
    tex = 64
    card = alpha_card(leaf_texture(tex)[..., 3])
    pose = translation(0.05, -0.03, 0.5)
    n, half = 512, 0.75
    grid = receiver_grid(half, (n, n)).reshape(-1, 3)
    truth = (hard_visibility(grid, SUN, SceneObject(card, pose)) < 0.5).reshape(n, n)
    depth, lcam = _card_map(renderer, card, pose, SUN, 128)
    est = (shadow_visibility(grid, depth, lcam) < 0.5).reshape(n, n)
    inside = cv2.distanceTransform(truth.astype(np.uint8), cv2.DIST_L2, 5)
    outside = cv2.distanceTransform((~truth).astype(np.uint8), cv2.DIST_L2, 5)
    texels = np.where(truth, inside, outside)[est != truth] * (2 * half / n) * tex
    assert truth.sum() > 20000 and shadow_iou(est, truth) > 0.98
    assert texels.max() <= 1.0


def _ious(renderer, mesh: trimesh.Trimesh, truth_mesh: trimesh.Trimesh, xys: np.ndarray
          ) -> dict[str, float]:
    """Mean shadow IoU on the ground of the 3 x 3 atlas (warped, baked by ``bake_atlas``) and of
    a re-rendered map (direct), both 256^2, against the ray cast of ``truth_mesh``
    (``morphkit bench shadows``' directional scene and ground grid)."""
    grid = receiver_grid(1.7, (256, 256)).reshape(-1, 3)
    atlas = bake_atlas(mesh, np.eye(4), MOTION, SUN, (256, 256), renderer=renderer, progress=False)
    methods = {"warp": atlas.method(), "direct": DirectShadow(atlas.rig, mesh, renderer)}
    ious: dict[str, list[float]] = {k: [] for k in methods}
    for xy in xys:
        truth = hard_visibility(grid, SUN, SceneObject(truth_mesh, translation(*xy, 0.0))) < 0.5
        for k, m in methods.items():
            d, cam = m.shadow_map(xy)
            ious[k].append(shadow_iou(shadow_visibility(grid, d, cam) < 0.5, truth))
    return {k: float(np.mean(v)) for k, v in ious.items()}


def test_leaf_plant_atlas_and_direct_shadows_match_the_cut_out_ray_cast(renderer, plant):
    """The leaf plant's baked atlas (warped) and re-rendered (direct) shadows, both from
    ``Renderer.depth`` with its cut-outs, against the cut-out-aware ray cast: within 0.02 IoU of
    a sample mesh's direct shadow (chair, the lowest of teapot/chair/cow in ``bench shadows``'
    directional scene: 0.986) and far above the IoU against the bare card squares (a
    cut-out-blind truth). Measured: plant 0.977 (both), chair 0.986, solid 0.66."""
    xys = np.random.default_rng(2026).uniform(MOTION.lo, MOTION.hi, (3, 2))
    solid = trimesh.Trimesh(plant.vertices, plant.faces, process=False)
    plant_iou = _ious(renderer, plant, plant, xys)
    chair = sample_mesh("chair")
    chair_iou = _ious(renderer, chair, chair, xys)["direct"]
    solid_iou = _ious(renderer, plant, solid, xys)["direct"]  # the holed maps, a solid truth
    for k in ("warp", "direct"):
        assert plant_iou[k] >= chair_iou - 0.02, k
    assert solid_iou < 0.8 and plant_iou["direct"] > solid_iou + 0.15


def test_frames_draw_the_objects_own_look(renderer, plant):
    """A frame of the plant draws its leaves' texture (green, where a flat draw in the scene
    object's colour would be red-brown); a sample mesh keeps the scene object's colour (its
    frames are those of earlier versions: the demo's references)."""
    cow_scene = demo_scene(sample_mesh("cow"), 96)
    items = frame_items(cow_scene)
    assert items[-1].color == cow_scene.obj.color and items[-1].mesh is cow_scene.obj.mesh
    base = demo_scene(plant, 128)
    scene = Scene(SceneObject(plant, translation(0.0, 0.0, 0.0)), DOWN, base.camera, base.receiver,
                  ambient=base.ambient)
    assert frame_items(scene)[-1].color is None
    frame = render_frame(renderer, scene, lambda p, _n: hard_visibility(p, scene.light, scene.obj))
    obj_depth = renderer.depth(scene.camera, [Item(plant, scene.obj.pose)])
    with np.errstate(invalid="ignore"):  # inf - inf on the background
        on_obj = np.isfinite(obj_depth) & (np.abs(obj_depth - frame["depth"]) < 1e-4 * frame["depth"])
    rgb = frame["unlit"][on_obj].astype(float).mean(0)
    assert on_obj.sum() > 200 and rgb[1] > rgb[0] + 20  # green leaves, not (0.75, 0.35, 0.25)
