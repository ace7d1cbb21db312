"""Camera/light math: round trips and conventions, no GL."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.camera import CameraModel, look_at, orthographic, perspective
from morphkit.conventions import CV_FROM_GL, cv_pose_from_gl, gl_pose_from_cv
from morphkit.errors import DegenerateViewError, ValidationError


def _cams():
    pose = look_at([3.0, -2.0, 2.5], [0.1, 0.2, 0.3])
    return [
        perspective(np.deg2rad(45), (48, 64), pose, znear=0.1, zfar=20),
        orthographic(1.5, 1.0, (48, 64), pose, znear=0.1, zfar=20),
    ]


def test_look_at_frame_is_opencv():
    T = look_at([0, 0, 5], [0, 0, 0], up=[0, 1, 0])
    np.testing.assert_allclose(T[:3, 2], [0, 0, -1], atol=1e-12)  # +z forward
    np.testing.assert_allclose(T[:3, 1], [0, -1, 0], atol=1e-12)  # +y (image down) = -up
    np.testing.assert_allclose(T[:3, :3].T @ T[:3, :3], np.eye(3), atol=1e-12)
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)


def test_gl_cv_conversion_is_an_involution():
    T = look_at([1, 2, 3], [0, 0, 0])
    np.testing.assert_allclose(cv_pose_from_gl(gl_pose_from_cv(T)), T, atol=1e-12)
    np.testing.assert_allclose(CV_FROM_GL @ CV_FROM_GL, np.eye(4))
    # the GL camera looks along its -z: that is the cv +z
    np.testing.assert_allclose(-gl_pose_from_cv(T)[:3, 2], T[:3, 2], atol=1e-12)


@pytest.mark.parametrize("cam", _cams(), ids=["perspective", "orthographic"])
def test_project_unproject_round_trip(cam: CameraModel, rng):
    pts = rng.uniform(-0.5, 0.5, (200, 3)) + [0.1, 0.2, 0.3]
    px, depth = cam.project(pts)
    # unproject through a depth image holding the depths at the rounded pixels
    h, w = cam.shape
    inside = (px[:, 0] > 0) & (px[:, 0] < w - 1) & (px[:, 1] > 0) & (px[:, 1] < h - 1)
    assert inside.sum() > 50
    # exact inverse at sub-pixel positions: invert the model analytically
    x, y = px[inside, 0], px[inside, 1]
    X, Y = (x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy
    if cam.projection == "perspective":
        X, Y = X * depth[inside], Y * depth[inside]
    back = np.c_[X, Y, depth[inside]] @ cam.cam2world[:3, :3].T + cam.cam2world[:3, 3]
    np.testing.assert_allclose(back, pts[inside], atol=1e-10)


@pytest.mark.parametrize("cam", _cams(), ids=["perspective", "orthographic"])
def test_unproject_then_project_hits_pixel_centres(cam: CameraModel):
    depth = np.full(cam.shape, 4.0, np.float32)
    depth[0, 0] = np.inf  # background
    world, valid = cam.unproject(depth)
    assert not valid[0, 0] and valid.sum() == depth.size - 1
    assert np.all(np.isfinite(world))
    px, d = cam.project(world[valid])
    x, y = cam.pixel_grid()
    np.testing.assert_allclose(px[:, 0], x[valid], atol=1e-9)
    np.testing.assert_allclose(px[:, 1], y[valid], atol=1e-9)
    np.testing.assert_allclose(d, 4.0, atol=1e-9)


@pytest.mark.parametrize("cam", _cams(), ids=["perspective", "orthographic"])
def test_texture_matrix_matches_project(cam: CameraModel, rng):
    pts = rng.uniform(-0.5, 0.5, (50, 3))
    q = cam.texture_matrix() @ np.c_[pts, np.ones(50)].T
    px, depth = cam.project(pts)
    np.testing.assert_allclose((q[:2] / q[3]).T, px, atol=1e-9)
    np.testing.assert_allclose(q[2], depth, atol=1e-12)


@pytest.mark.parametrize("cam", _cams(), ids=["perspective", "orthographic"])
def test_gl_projection_maps_pixels_to_ndc(cam: CameraModel, rng):
    """The GL projection puts a point at NDC x = (2 (x_px + 0.5) / W) - 1 and
    y_ndc = 1 - 2 (y_px + 0.5) / H (pixel centres, y down)."""
    pts = rng.uniform(-0.5, 0.5, (50, 3))
    px, depth = cam.project(pts)
    world2gl = CV_FROM_GL @ cam.world2cam
    clip = cam.gl_projection() @ world2gl @ np.c_[pts, np.ones(50)].T
    ndc = clip[:3] / clip[3]
    h, w = cam.shape
    np.testing.assert_allclose(ndc[0], 2 * (px[:, 0] + 0.5) / w - 1, atol=1e-9)
    np.testing.assert_allclose(ndc[1], 1 - 2 * (px[:, 1] + 0.5) / h, atol=1e-9)
    # window depth -> linear depth round trip
    wd = (ndc[2] + 1) / 2
    np.testing.assert_allclose(cam.linearize_window_depth(wd), depth, rtol=1e-6)


def test_rays_pass_through_unprojected_points():
    for cam in _cams():
        o, d = cam.rays()
        world, _ = cam.unproject(np.full(cam.shape, 2.0))
        t = np.einsum("hwk,hwk->hw", world - o, d)
        np.testing.assert_allclose(o + t[..., None] * d, world, atol=1e-9)


def test_project_behind_camera_is_refused():
    cam = _cams()[0]
    behind = cam.position - 2 * cam.axis
    with pytest.raises(DegenerateViewError, match="in front of the camera"):
        cam.project(behind[None])


def test_bad_camera_parameters():
    pose = look_at([0, 0, 5], [0, 0, 0])
    with pytest.raises(ValidationError, match=r"shape: expected positive \(H, W\), got \(0, 10\)"):
        perspective(1.0, (0, 10), pose)
    with pytest.raises(ValidationError, match="zfar: expected > znear"):
        perspective(1.0, (10, 10), pose, znear=5, zfar=1)
    with pytest.raises(ValidationError, match="yfov: expected an angle in"):
        perspective(4.0, (10, 10), pose)
    bad = pose.copy()
    bad[0, 3] = np.nan
    with pytest.raises(ValidationError, match="cam2world: expected finite values"):
        perspective(1.0, (10, 10), bad)
    with pytest.raises(ValidationError, match="rigid 4x4"):
        perspective(1.0, (10, 10), np.diag([2.0, 1, 1, 1]))
    with pytest.raises(ValidationError, match="eye != target"):
        look_at([1, 1, 1], [1, 1, 1])
    with pytest.raises(ValidationError, match="half_width: expected a finite number > 0"):
        orthographic(0.0, 1.0, (8, 8), pose, znear=0.1, zfar=10)


def test_camera_inside_bounds_is_refused():
    cam = perspective(1.0, (8, 8), look_at([0, 0, 0.5], [1, 0, 0.5]))
    with pytest.raises(DegenerateViewError, match="camera position: expected outside the object"):
        cam.assert_outside(np.array([-1.0, -1, 0]), np.array([1.0, 1, 1]))
