"""Motion range, sample placement and the light rig (no GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.errors import DegenerateViewError, OutOfRangeError, ValidationError
from morphkit.scene import DirectionalLight, PointLight
from morphkit.shadow.rig import LightRig, MotionRange, RangeClampWarning, sample_axis

BOX = trimesh.creation.box((0.4, 0.3, 0.5))
BASE = np.eye(4)
BASE[2, 3] = 0.25  # resting on the ground


def test_sample_axis_puts_the_middle_in_line_with_the_light():
    np.testing.assert_allclose(sample_axis(-1, 1, 3, 0.3), [-1, 0.3, 1])
    np.testing.assert_allclose(sample_axis(-1, 1, 5, 0.0), [-1, -0.5, 0, 0.5, 1])
    np.testing.assert_allclose(sample_axis(-1, 1, 3, 5.0), [-1, 0.8, 1])  # clamped to middle 80%
    np.testing.assert_allclose(sample_axis(-1, 1, 4, 0.3), np.linspace(-1, 1, 4))  # even: uniform
    with pytest.raises(ValidationError, match="grid: expected k >= 2 samples per axis, got 1"):
        sample_axis(0, 1, 1)
    with pytest.raises(ValidationError, match="grid: expected k >= 2 samples per axis, got 2.5"):
        sample_axis(0, 1, 2.5)  # refused, not truncated to 2
    np.testing.assert_allclose(sample_axis(0, 1, 3.0), [0, 0.5, 1])  # an integral float is an integer


def test_motion_range_checks():
    m = MotionRange([-1, -0.5], [1, 0.5])
    np.testing.assert_allclose(m.check(np.array([1.0, 0.5])), [1.0, 0.5])  # the edge is inside
    with pytest.raises(OutOfRangeError, match=r"object position: expected inside the baked range"):
        m.check(np.array([1.2, 0.0]))
    np.testing.assert_allclose(m.check(np.array([1.2, -0.9]), clamp=True), [1.0, -0.5])
    with pytest.raises(ValidationError, match="motion range: expected hi > lo on both axes"):
        MotionRange([0, 0], [1, 0])
    with pytest.raises(ValidationError, match="range lo: expected finite values"):
        MotionRange([np.nan, 0], [1, 1])


@pytest.mark.parametrize("light", [DirectionalLight([0.3, -0.4, -1]), PointLight([0.2, 0.1, 2.5])],
                         ids=["directional", "point"])
def test_rig_sees_the_object_everywhere_in_the_range(light):
    motion = MotionRange([-0.6, -0.4], [0.6, 0.4])
    rig = LightRig(light, BOX, BASE, motion, (96, 128))
    for xy in [*motion.corners(), motion.center, np.array([0.1, -0.3])]:
        cam = rig.camera_at(xy)
        pts = BOX.vertices @ rig.object_pose(xy)[:3, :3].T + rig.object_pose(xy)[:3, 3]
        px, z = cam.project(pts)
        assert px[:, 0].min() > -0.5 and px[:, 0].max() < 127.5
        assert px[:, 1].min() > -0.5 and px[:, 1].max() < 95.5
        assert z.min() > cam.znear and z.max() < cam.zfar
        # the anchor (bounding-box centre) projects to the image centre: the window follows
        a, _ = cam.project(rig.anchor0[None] + np.r_[xy, 0.0])
        np.testing.assert_allclose(a[0], [63.5, 47.5], atol=1e-9)


def test_directional_rig_moves_with_the_object():
    """Object and camera translate together: every object point keeps its pixel and depth."""
    rig = LightRig(DirectionalLight([0.3, -0.4, -1]), BOX, BASE, MotionRange([-1, -1], [1, 1]), (64, 64))
    a, b = np.array([-0.7, 0.2]), np.array([0.5, 0.9])
    pa, za = rig.camera_at(a).project(BOX.vertices + np.r_[a, 0.25])
    pb, zb = rig.camera_at(b).project(BOX.vertices + np.r_[b, 0.25])
    np.testing.assert_allclose(pa, pb, atol=1e-9)
    np.testing.assert_allclose(za, zb, atol=1e-12)


def test_point_rig_depth_model_is_exact():
    """Fixed orientation: moving the object by d moves every depth by axis . d."""
    rig = LightRig(PointLight([0.2, 0.1, 2.5]), BOX, BASE, MotionRange([-1, -1], [1, 1]), (64, 64))
    a, b = np.array([-0.7, 0.2]), np.array([0.5, 0.9])
    _, za = rig.camera_at(a).project(BOX.vertices + np.r_[a, 0.25])
    _, zb = rig.camera_at(b).project(BOX.vertices + np.r_[b, 0.25])
    np.testing.assert_allclose(zb - za, rig.axis[:2] @ (b - a), atol=1e-12)


def test_moving_light_is_object_moving_the_other_way():
    rig = LightRig(PointLight([0.2, 0.1, 2.5]), BOX, BASE, MotionRange([-1, -1], [1, 1]), (64, 64))
    xy, D = np.array([0.3, -0.2]), np.array([0.25, 0.4])
    pts = BOX.vertices + np.r_[xy, 0.25]
    moved_light = rig.camera_at(xy, light_offset=D)
    np.testing.assert_allclose(moved_light.position, rig.light.position + np.r_[D, 0.0])
    p1, z1 = moved_light.project(pts)
    p2, z2 = rig.camera_at(xy - D).project(pts - np.r_[D, 0.0])
    np.testing.assert_allclose(p1, p2, atol=1e-9)
    np.testing.assert_allclose(z1, z2, atol=1e-12)
    np.testing.assert_allclose(rig.equivalent_position(xy, D), xy - D)
    with pytest.warns(RangeClampWarning, match="outside the baked range; clamped"):
        rig.equivalent_position(np.array([0.9, 0.0]), np.array([-0.5, 0.0]), clamp=True)
    with pytest.raises(OutOfRangeError, match="expected inside the baked range"):
        rig.equivalent_position(np.array([0.9, 0.0]), np.array([-0.5, 0.0]))


def test_directional_light_cannot_be_translated():
    rig = LightRig(DirectionalLight([0, 0, -1]), BOX, BASE, MotionRange([-1, -1], [1, 1]), (32, 32))
    with pytest.raises(ValidationError, match="light_offset: expected none for a directional light"):
        rig.equivalent_position(np.zeros(2), np.array([0.1, 0.0]))


def test_point_light_inside_the_range_is_refused():
    """The object passes under/around a low light: no frustum < 180 deg holds it."""
    with pytest.raises(DegenerateViewError, match="point light: expected the object in front of the light"):
        LightRig(PointLight([0.0, 0.0, 0.3]), BOX, BASE, MotionRange([-1, -1], [1, 1]), (32, 32))
    with pytest.raises(ValidationError, match="light: expected a DirectionalLight or PointLight"):
        LightRig("sun", BOX, BASE, MotionRange([-1, -1], [1, 1]), (32, 32))


@pytest.mark.parametrize("light", [PointLight([0.2, 0.1, 2.5]), DirectionalLight([0.3, -0.4, -1])])
def test_principal_point_is_the_cameras_bit_for_bit(light, rng):
    """A reprojection's destination takes only the principal point: the same numbers as the camera."""
    rig = LightRig(light, BOX, BASE, MotionRange([-1, -1], [1, 1]), (64, 80))
    for xy in rng.uniform(-1, 1, (8, 2)):
        cam = rig.camera_at(xy)
        assert rig.principal_point(xy) == (cam.cx, cam.cy)
