"""Scene description and tight light-view fitting (no GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.camera import look_at, perspective
from morphkit.errors import DegenerateViewError, MeshError, ValidationError
from morphkit.scene import (
    AreaLight,
    DirectionalLight,
    PointLight,
    Scene,
    SceneObject,
    light_view,
    translation,
)


@pytest.mark.parametrize("light", [DirectionalLight([0.4, -0.3, -1.0]), PointLight([1.0, -2.0, 3.0])],
                         ids=["directional", "point"])
def test_light_view_is_tight(light, rng):
    pts = rng.uniform([-0.5, -0.3, 0.0], [0.7, 0.4, 0.9], (500, 3))
    margin = 0.02
    cam = light_view(light, pts, (64, 96), margin=margin)
    px, depth = cam.project(pts)
    h, w = cam.shape
    # every point inside the image, and the points span the image up to the margin
    assert px[:, 0].min() >= -0.5 and px[:, 0].max() <= w - 0.5
    assert px[:, 1].min() >= -0.5 and px[:, 1].max() <= h - 0.5
    span_x = (px[:, 0].max() - px[:, 0].min()) / w
    span_y = (px[:, 1].max() - px[:, 1].min()) / h
    assert span_x == pytest.approx(1 / (1 + 2 * margin), rel=1e-6)
    assert span_y == pytest.approx(1 / (1 + 2 * margin), rel=1e-6)
    assert depth.min() > cam.znear and depth.max() < cam.zfar
    if isinstance(light, DirectionalLight):
        np.testing.assert_allclose(cam.axis, light.direction, atol=1e-12)
    else:
        np.testing.assert_allclose(cam.position, light.position, atol=1e-12)


def test_point_light_inside_occluder_bounds_is_refused(rng):
    pts = rng.uniform(-1, 1, (100, 3))
    with pytest.raises(DegenerateViewError, match="point light: expected all occluder points in front"):
        light_view(PointLight([0.3, 0.2, 0.1]), pts, (32, 32))
    with pytest.raises(ValidationError, match="sample an AreaLight first"):
        light_view(AreaLight([0, 0, 3], [1, 0, 0], [0, 1, 0]), pts, (32, 32))


def test_scene_refuses_camera_inside_object():
    obj = SceneObject(trimesh.creation.box((1, 1, 1)), translation(0, 0, 0.5))
    inside = perspective(1.0, (16, 16), look_at([0.1, 0.0, 0.5], [2.0, 0.0, 0.5]))
    with pytest.raises(DegenerateViewError, match="camera position: expected outside the object"):
        Scene(obj, DirectionalLight([0, 0, -1]), inside)
    outside = perspective(1.0, (16, 16), look_at([3.0, 0.0, 1.0], [0.0, 0.0, 0.5]))
    s = Scene(obj, DirectionalLight([0, 0, -1]), outside)
    moved = s.with_object_pose(translation(1, 0, 0.5))
    assert moved.obj.mesh is s.obj.mesh and moved.obj.pose[0, 3] == 1.0


def test_scene_object_bad_input():
    with pytest.raises(MeshError, match="mesh: expected at least one face, got an empty mesh"):
        SceneObject(trimesh.Trimesh())
    with pytest.raises(MeshError, match="mesh: expected a trimesh.Trimesh"):
        SceneObject("teapot.obj")
    pose = np.eye(4)
    pose[1, 3] = np.inf
    with pytest.raises(ValidationError, match="object pose: expected finite values, got 1 NaN/inf"):
        SceneObject(trimesh.creation.box(), pose)


def test_area_light_samples_are_stratified(rng):
    light = AreaLight([0, 0, 2], [0.5, 0, 0], [0, 0.25, 0])
    s = light.samples(4, 2)
    assert s.shape == (8, 3)
    np.testing.assert_allclose(s.mean(0), [0, 0, 2], atol=1e-12)
    j = light.samples(4, 2, rng=rng)
    assert np.all(np.abs(j[:, 0]) <= 0.5) and np.all(np.abs(j[:, 1]) <= 0.25)
    assert np.all(np.abs(j - s)[:, 0] <= 0.125 + 1e-12)  # stays in its cell
    with pytest.raises(ValidationError, match="light samples: expected n_u, n_v >= 1"):
        light.samples(0)


@pytest.mark.parametrize("n_u, n_v, match", [
    (2.5, 2, r"n_u: expected an integer, got 2.5"),
    (10**4, 10**4, r"light samples: expected at most 4096 \(morphkit.tol.MAX_LIGHT_SAMPLES\), "
                   r"got 10000 x 10000"),
])
def test_area_light_sample_counts_are_integral_and_bounded(n_u, n_v, match):
    with pytest.raises(ValidationError, match=match):
        AreaLight([0, 0, 2], [0.5, 0, 0], [0, 0.25, 0]).samples(n_u, n_v)
