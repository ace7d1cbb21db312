"""Ray-cast ground truth against analytic shadows of a box on the ground plane."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import trimesh

from morphkit.errors import ValidationError
from morphkit.imaging.groundtruth import (
    area_visibility,
    ground_pixels,
    hard_visibility,
    receiver_grid,
)
from morphkit.scene import AreaLight, DirectionalLight, PointLight, SceneObject, translation

BOX = trimesh.creation.box((0.6, 0.4, 0.5))  # centred; lifted to rest on z=0 by its pose
BOX_POSE = translation(0.2, -0.1, 0.25)


def _box_corners() -> np.ndarray:
    return trimesh.bounds.corners(BOX.bounds) + BOX_POSE[:3, 3]


def _signed_dist(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    hull = cv2.convexHull(poly.astype(np.float32))
    return np.array([cv2.pointPolygonTest(hull, (float(x), float(y)), True) for x, y in pts])


def _check(vis: np.ndarray, pts: np.ndarray, shadow_poly: np.ndarray, band: float = 1e-3) -> None:
    d = _signed_dist(shadow_poly, pts[:, :2])
    assert np.all(vis[d > band] == 0.0), "points inside the analytic shadow must be shadowed"
    assert np.all(vis[d < -band] == 1.0), "points outside the analytic shadow must be lit"
    assert (d > band).sum() > 40 and (d < -band).sum() > 40


def test_box_shadow_directional():
    """Directional light d: the shadow is the hull of the box's corners moved
    along d down to z = 0: (x, y, z) -> (x, y) - z (dx, dy) / dz."""
    d = np.array([-0.5, 0.3, -1.0])
    light = DirectionalLight(d)
    pts = receiver_grid(2.0, (64, 64)).reshape(-1, 3)
    vis = hard_visibility(pts, light, SceneObject(BOX, BOX_POSE))
    c = _box_corners()
    dn = light.direction
    proj = c[:, :2] - c[:, 2:3] * dn[:2] / dn[2]
    _check(vis, pts, proj)


def test_box_shadow_point_light():
    """Point light L above the box: corner p projects to L + s (p - L), s = L_z / (L_z - p_z)."""
    L = np.array([-0.8, 0.5, 2.0])
    light = PointLight(L)
    pts = receiver_grid(2.0, (64, 64)).reshape(-1, 3)
    vis = hard_visibility(pts, light, SceneObject(BOX, BOX_POSE))
    c = _box_corners()
    s = L[2] / (L[2] - c[:, 2])
    proj = L[:2] + s[:, None] * (c[:, :2] - L[:2])
    _check(vis, pts, proj)


def test_point_light_between_occluder_and_point_does_not_shadow():
    """The occluder lies beyond the light: the segment to the light is clear."""
    light = PointLight([0.2, -0.1, 0.8])  # just above the box top (z = 0.5)
    pts = np.array([[0.2, -0.1, 1.5]])  # above the light
    assert hard_visibility(pts, light, SceneObject(BOX, BOX_POSE))[0] == 1.0
    below = np.array([[0.2, -0.1, -0.3]])  # under the box
    assert hard_visibility(below, light, SceneObject(BOX, BOX_POSE))[0] == 0.0


def test_area_light_fraction_matches_per_sample_analytic_shadows(rng):
    light = AreaLight([-0.5, 0.4, 2.2], [0.3, 0.0, 0.0], [0.0, 0.2, 0.0])
    pts = receiver_grid(2.0, (48, 48)).reshape(-1, 3)
    vis = area_visibility(pts, light, SceneObject(BOX, BOX_POSE), 3, 3, rng=np.random.default_rng(7))
    c = _box_corners()
    lit = np.zeros(len(pts))
    samples = light.samples(3, 3, rng=np.random.default_rng(7))
    band_ok = np.ones(len(pts), bool)
    for L in samples:
        s = L[2] / (L[2] - c[:, 2])
        proj = L[:2] + s[:, None] * (c[:, :2] - L[:2])
        d = _signed_dist(proj, pts[:, :2])
        lit += d < 0  # outside this sample's shadow polygon
        band_ok &= np.abs(d) > 1e-3
    expected = lit / len(samples)
    np.testing.assert_allclose(vis[band_ok], expected[band_ok], atol=1e-6)
    assert 0 < vis.min() < 1 or np.any((vis > 0) & (vis < 1))  # a penumbra exists


def test_pose_is_applied_rigidly():
    """The same box, rotated 90 deg about z and moved, shadows the rotated footprint."""
    R = trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1])
    pose = translation(-0.5, 0.6, 0.25) @ R
    pts = receiver_grid(2.0, (64, 64)).reshape(-1, 3)
    light = DirectionalLight([0, 0, -1])
    vis = hard_visibility(pts, light, SceneObject(BOX, pose))
    foot = np.array([[-0.7, 0.3], [-0.3, 0.3], [-0.3, 0.9], [-0.7, 0.9]])  # 0.4 x 0.6 now
    _check(vis, pts, foot)


def test_receiver_grid_round_trip():
    g = receiver_grid(1.5, (6, 8))
    px = ground_pixels(g.reshape(-1, 3), 1.5, (6, 8))
    x, y = np.meshgrid(np.arange(8), np.arange(6))
    np.testing.assert_allclose(px, np.c_[x.ravel(), y.ravel()], atol=1e-12)
    assert g[0, 0, 1] > g[-1, 0, 1] and g[0, 0, 0] < g[0, -1, 0]  # +y up, +x right


def test_bad_input():
    obj = SceneObject(BOX, BOX_POSE)
    with pytest.raises(ValidationError, match=r"points: expected shape \(N, 3\)"):
        hard_visibility(np.zeros((4, 2)), DirectionalLight([0, 0, -1]), obj)
    with pytest.raises(ValidationError, match="points: expected finite values"):
        hard_visibility(np.array([[0, 0, np.nan]]), DirectionalLight([0, 0, -1]), obj)
    with pytest.raises(ValidationError, match="use area_visibility"):
        hard_visibility(np.zeros((1, 3)), AreaLight([0, 0, 2], [1, 0, 0], [0, 1, 0]), obj)
    with pytest.raises(ValidationError, match="direction: expected a non-zero direction"):
        DirectionalLight([0, 0, 0])
    with pytest.raises(ValidationError, match="area light extent: expected non-zero"):
        AreaLight([0, 0, 2], [0, 0, 0], [0, 1, 0])


def test_sampled_visibility_needs_a_light():
    from morphkit.imaging.groundtruth import sampled_visibility

    obj = SceneObject(trimesh.creation.box((0.2, 0.2, 0.2)))
    with pytest.raises(ValidationError, match="at least one point light.*none"):
        sampled_visibility(np.zeros((1, 3)), [], obj)
