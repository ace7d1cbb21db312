"""Ray-cast shadows of cut-out (alpha-masked) occluders: derivable patterns, re-casting
through stacked holes, and meshes without cut-outs untouched (no GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from PIL import Image

import morphkit.imaging.cutout as cutout_module
from morphkit import tol
from morphkit.errors import ValidationError
from morphkit.imaging.cutout import Cutout, mesh_cutout, sample_texture
from morphkit.imaging.groundtruth import (
    CutoutLayersWarning,
    hard_visibility,
    receiver_grid,
    sampled_visibility,
)
from morphkit.meshes import sample_mesh
from morphkit.programs.fixtures import alpha_card, checker_alpha
from morphkit.scene import DirectionalLight, PointLight, SceneObject, translation

DOWN = DirectionalLight([0.0, 0.0, -1.0])
CELLS, TEXELS = 4, 8  # a 4 x 4 checkerboard of 8 x 8-texel squares on a unit card


def _checker_truth(pts: np.ndarray, centre: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Expected shadow (True) of a unit checker card centred over ``centre`` (light straight
    down), and the points more than one texel from every square edge (bilinear blur is half a
    texel wide), where it is exact."""
    x, y = pts[:, 0] - centre[0], pts[:, 1] - centre[1]
    fx, fy = (x + 0.5) * CELLS, (0.5 - y) * CELLS  # square column and row (row 0 at +y)
    on_card = (np.abs(x) < 0.5) & (np.abs(y) < 0.5)
    opaque = (np.floor(fx).astype(int) + np.floor(fy).astype(int)) % 2 == 0
    edge = np.minimum(np.abs(fx - np.rint(fx)), np.abs(fy - np.rint(fy))) * TEXELS
    return on_card & opaque, edge > 1.0


def _stack(*cards: tuple[trimesh.Trimesh, float, float]) -> trimesh.Trimesh:
    """Cards (mesh, x shift, height) of one material merged into one mesh, UVs kept."""
    verts = np.concatenate([c.vertices + [dx, 0.0, z] for c, dx, z in cards])
    faces = np.concatenate([c.faces + 4 * k for k, (c, _, _) in enumerate(cards)])
    uv = np.concatenate([c.visual.uv for c, _, _ in cards])
    return trimesh.Trimesh(verts, faces, process=False,
                           visual=trimesh.visual.TextureVisuals(uv=uv, material=cards[0][0].visual.material))


def test_checker_card_casts_its_mask_pattern():
    """A checker card 0.5 above the ground, light straight down: the ground shadow is the
    mask projected, exactly, at points a texel or more from the squares' edges."""
    centre = np.array([0.1, -0.05])
    pts = receiver_grid(0.75, (96, 96)).reshape(-1, 3)
    vis = hard_visibility(pts, DOWN, SceneObject(alpha_card(checker_alpha(CELLS, TEXELS)),
                                                 translation(*centre, 0.5)))
    shadow, exact = _checker_truth(pts, centre)
    assert exact.sum() > 3000 and shadow[exact].sum() > 500 and (~shadow[exact]).sum() > 500
    np.testing.assert_array_equal(vis[exact] < 0.5, shadow[exact])
    assert set(np.unique(vis)) <= {0.0, 1.0}


def test_checker_card_under_a_point_light_matches_the_projection():
    """Point light: ground point p shadows where the ray to the light crosses the card's plane
    (z = h) at an opaque square: crossing p + (L - p) h / L_z."""
    L, h = np.array([0.3, -0.2, 2.0]), 0.6
    pts = receiver_grid(1.0, (96, 96)).reshape(-1, 3)
    vis = hard_visibility(pts, PointLight(L), SceneObject(alpha_card(checker_alpha(CELLS, TEXELS)),
                                                          translation(0.0, 0.0, h)))
    cross = pts + (L - pts) * (h / L[2])
    shadow, exact = _checker_truth(cross, np.zeros(2))
    assert exact.sum() > 2000 and shadow[exact].sum() > 300
    np.testing.assert_array_equal(vis[exact] < 0.5, shadow[exact])


def test_treated_as_solid_the_card_would_shadow_its_whole_square():
    """Guard of the test above: the same card without its look is one solid square."""
    card = alpha_card(checker_alpha(CELLS, TEXELS))
    solid = trimesh.Trimesh(card.vertices, card.faces, process=False)
    pts = receiver_grid(0.75, (64, 64)).reshape(-1, 3)
    on_card = (np.abs(pts[:, 0]) < 0.49) & (np.abs(pts[:, 1]) < 0.49)
    assert np.all(hard_visibility(pts, DOWN, SceneObject(solid, translation(0, 0, 0.5)))[on_card] == 0)
    assert hard_visibility(pts, DOWN, SceneObject(card, translation(0, 0, 0.5)))[on_card].mean() == \
        pytest.approx(0.5, abs=0.05)


@pytest.mark.parametrize("shift, expect_all_shadowed", [(0, False), (1, True)])
def test_stacked_cards_recast_through_holes(shift, expect_all_shadowed):
    """Two checker cards stacked (z = 0.4 and 0.7): aligned, a ray through a hole of the lower
    one passes the upper one's hole too (lit: two re-casts, then it leaves); shifted by one
    square, the upper card's opaque squares fill the lower one's holes (all shadowed)."""
    card = alpha_card(checker_alpha(CELLS, TEXELS))
    dx = shift / CELLS
    stack = _stack((card, 0.0, 0.4), (card, dx, 0.7))
    pts = receiver_grid(0.75, (96, 96)).reshape(-1, 3)
    vis = hard_visibility(pts, DOWN, SceneObject(stack))
    lower, exact = _checker_truth(pts, np.zeros(2))
    upper, exact_up = _checker_truth(pts, np.array([dx, 0.0]))
    both = exact & exact_up & (np.abs(pts[:, 0]) < 0.5) & (np.abs(pts[:, 0] - dx) < 0.5) & \
        (np.abs(pts[:, 1]) < 0.5)  # under both cards
    assert both.sum() > 1000
    np.testing.assert_array_equal(vis[both] < 0.5, (lower | upper)[both])
    assert bool(np.all(vis[both] < 0.5)) is expect_all_shadowed


def test_too_many_holes_in_a_row_count_as_shadowed_with_a_warning(monkeypatch):
    """With the layer bound at 1, a ray through the lower card's hole has no casts left:
    counted as shadowed, with a warning naming the bound."""
    card = alpha_card(checker_alpha(CELLS, TEXELS))
    stack = _stack((card, 0.0, 0.4), (card, 0.0, 0.7))
    pts = receiver_grid(0.75, (64, 64)).reshape(-1, 3)
    lit_before = hard_visibility(pts, DOWN, SceneObject(stack)).mean()
    monkeypatch.setattr(tol, "CUTOUT_MAX_LAYERS", 1)
    with pytest.warns(CutoutLayersWarning, match="CUTOUT_MAX_LAYERS"):
        vis = hard_visibility(pts, DOWN, SceneObject(stack))
    on_card = (np.abs(pts[:, 0]) < 0.5) & (np.abs(pts[:, 1]) < 0.5)
    assert np.all(vis[on_card] == 0.0) and vis.mean() < lit_before


def _old_hard_visibility(points: np.ndarray, light, obj: SceneObject) -> np.ndarray:
    """The ray cast as it was before cut-outs (kept here as the reference)."""
    dirs, dist = light.to_light(points)
    origins = points + dirs * tol.RAY_OFFSET
    dist = dist - tol.RAY_OFFSET
    R, t = obj.pose[:3, :3], obj.pose[:3, 3]
    o, d = (origins - t) @ R, dirs @ R
    if np.all(np.isinf(dist)):
        return (~obj.mesh.ray.intersects_any(o, d)).astype(np.float32)
    out = np.zeros(len(o), bool)
    loc, idx, _ = obj.mesh.ray.intersects_location(o, d, multiple_hits=False)
    out[idx[np.einsum("ij,ij->i", loc - o[idx], d[idx]) < dist[idx]]] = True
    return (~out).astype(np.float32)


@pytest.mark.parametrize("light", [DirectionalLight([-0.5, 0.35, -1.0]), PointLight([0.25, -0.2, 2.4])])
def test_a_mesh_without_cut_outs_is_cast_as_before(light, monkeypatch):
    """The cow (no visuals): identical visibility to the old code path, and its look is never
    read (the cut-out path is skipped)."""
    cow = SceneObject(sample_mesh("cow"), translation(0.1, -0.2, 0.0))
    pts = receiver_grid(1.7, (128, 128)).reshape(-1, 3)
    old = _old_hard_visibility(pts, light, cow)

    def refuse(_mesh):
        raise AssertionError("the look of a mesh without TextureVisuals was read")

    monkeypatch.setattr(cutout_module, "mesh_look", refuse)
    new = hard_visibility(pts, light, cow)
    assert new.dtype == np.float32 and 0.01 < (new == 0).mean() < 0.5
    np.testing.assert_array_equal(new, old)


def test_an_opaque_textured_mesh_is_cast_as_its_bare_geometry():
    """The checker card with an OPAQUE material (its alpha ignored) shadows its whole square."""
    card = alpha_card(checker_alpha(CELLS, TEXELS))
    card.visual.material.alphaMode = "OPAQUE"
    assert mesh_cutout(card) is None
    obj = SceneObject(card, translation(0.0, 0.0, 0.5))
    pts = receiver_grid(0.75, (64, 64)).reshape(-1, 3)
    np.testing.assert_array_equal(hard_visibility(pts, DOWN, obj), _old_hard_visibility(pts, DOWN, obj))


def test_factor_and_vertex_alpha_multiply_the_texture_alpha():
    """glTF's rule: alpha = factor x texture x vertex colour; a hole where it is below the cutoff."""
    rgba = np.full((2, 2, 4), 255, np.uint8)
    rgba[..., 3] = 200  # 0.784
    mat = trimesh.visual.material.PBRMaterial(baseColorTexture=Image.fromarray(rgba), alphaMode="MASK",
                                              alphaCutoff=0.5, baseColorFactor=[1.0, 1.0, 1.0, 0.7])
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    quad = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]],
                           visual=trimesh.visual.TextureVisuals(uv=uv, material=mat), process=False)
    cut = mesh_cutout(quad)
    bary = np.array([[1 / 3, 1 / 3, 1 / 3]])
    f = cut.factor_alpha  # trimesh stores the factor in 8 bits
    assert f == pytest.approx(0.7, abs=1 / 255)
    assert cut.alpha(np.array([0]), bary)[0] == pytest.approx(f * 200 / 255)  # 0.547: opaque
    assert cut.opaque(np.array([0]), bary)[0]
    halved = Cutout(cut.faces, cut.cutoff, cut.factor_alpha, cut.texture_alpha, cut.uv,
                    vertex_alpha=np.array([1.0, 1.0, 0.5, 0.5]))
    # vertex alpha at the centroid of face 0 (vertices 0, 1, 2): (1 + 1 + 0.5) / 3
    assert halved.alpha(np.array([0]), bary)[0] == pytest.approx(f * 200 / 255 * 2.5 / 3)
    assert not halved.opaque(np.array([0]), bary)[0]


def test_sample_texture_is_bilinear_on_texel_centres_with_v_up_and_repeat():
    img = np.arange(12, dtype=np.float64).reshape(3, 4)  # rows top to bottom
    uv_centres = np.array([[(c + 0.5) / 4, 1 - (r + 0.5) / 3] for r in range(3) for c in range(4)])
    np.testing.assert_allclose(sample_texture(img, uv_centres), img.reshape(-1), atol=1e-12)
    # halfway between columns 1 and 2 of the top row; past the right edge wraps to column 0
    np.testing.assert_allclose(sample_texture(img, np.array([[0.5, 1 - 0.5 / 3], [1.0, 1 - 0.5 / 3]])),
                               [1.5, 1.5])
    rgb = np.stack([img, 2 * img], -1)
    assert sample_texture(rgb, uv_centres[:1]).shape == (1, 2)
    with pytest.raises(ValidationError, match="uv: expected an \\(N, 2\\) array"):
        sample_texture(img, np.zeros(3))
    with pytest.raises(ValidationError, match="image: expected an \\(H, W\\)"):
        sample_texture(np.zeros(3), np.zeros((1, 2)))


def test_sampled_visibility_honours_cut_outs():
    """An area light's samples each see the checker card's holes (every sample lit there)."""
    card = SceneObject(alpha_card(checker_alpha(CELLS, TEXELS)), translation(0.0, 0.0, 0.5))
    pts = receiver_grid(0.75, (64, 64)).reshape(-1, 3)
    lights = [PointLight([dx, 0.0, 50.0]) for dx in (-0.01, 0.01)]  # nearly straight down
    vis = sampled_visibility(pts, lights, card)
    shadow, exact = _checker_truth(pts, np.zeros(2))
    np.testing.assert_array_equal(vis[exact] < 0.5, shadow[exact])


def test_mesh_cutout_refuses_what_is_not_a_mesh():
    with pytest.raises(ValidationError, match="mesh: expected a trimesh.Trimesh"):
        mesh_cutout("leaf")


def test_a_replaced_visual_is_read_again():
    """Looks are cached per mesh and visual: giving the mesh new visuals is seen."""
    card = alpha_card(checker_alpha(CELLS, TEXELS))
    assert mesh_cutout(card) is not None
    opaque = trimesh.visual.material.PBRMaterial(baseColorTexture=card.visual.material.baseColorTexture)
    card.visual = trimesh.visual.TextureVisuals(uv=card.visual.uv, material=opaque)
    assert mesh_cutout(card) is None
