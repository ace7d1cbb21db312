"""Billboard scene geometry without images: instances, facing, azimuths, frustum, clipping, levels, paths."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard import (
    AxialFacing,
    FlyPath,
    Instance,
    Instances,
    OrbitPath,
    PanPath,
    ScreenFacing,
    make_path,
    paper_angle,
    place_random,
    view_directions,
)
from morphkit.billboard.frames.frustum import (
    clip_near,
    quad_homographies,
    require_perspective,
    sphere_in_frustum,
    unit_from_image,
)
from morphkit.billboard.frames.lod import screen_height_px, select_levels
from morphkit.camera import look_at, orthographic, perspective
from morphkit.errors import ValidationError

# ------------------------------------------------------------------ instances


def test_instances_from_records_and_validation():
    inst = Instances.from_records([Instance("tree", 1, 2, 90, 2.0), ("person", -1, 0), ("tree", 0, 0, 10)])
    assert inst.names == ("tree", "person") and len(inst) == 3
    assert inst.asset.tolist() == [0, 1, 0]
    assert inst.record(1) == Instance("person", -1.0, 0.0, 0.0, 1.0)
    # a pivot (0.1, 0, 0.4) of the tree, turned 90 deg and doubled, at (1, 2)
    piv = inst.pivots([np.array([0.1, 0.0, 0.4]), np.array([0.0, 0.0, 0.5])])
    np.testing.assert_allclose(piv[0], [1.0, 2.2, 0.8], atol=1e-12)
    np.testing.assert_allclose(piv[1], [-1.0, 0.0, 0.5], atol=1e-12)
    T = inst.object2world(0)
    np.testing.assert_allclose(T @ [0.1, 0, 0.4, 1], [*piv[0], 1], atol=1e-12)
    with pytest.raises(ValidationError, match="instance scale: expected values > 0"):
        Instances.from_records([("tree", 0, 0, 0, -1.0)])
    with pytest.raises(ValidationError, match="instance positions: expected finite values"):
        Instances.from_records([("tree", np.nan, 0)])
    with pytest.raises(ValidationError, match="instance record: expected"):
        Instances.from_records([("tree",)])
    with pytest.raises(ValidationError, match="asset indices: expected in"):
        Instances(("a",), np.array([1]), np.zeros((1, 2)), np.zeros(1), np.ones(1))
    with pytest.raises(ValidationError, match="asset name: expected a non-empty string"):
        Instances.from_records([("", 0, 0)])


def test_place_random_is_reproducible_and_validated():
    a = place_random(["tree", "person"], 50, np.random.default_rng(3), half_size=4.0)
    b = place_random(["tree", "person"], 50, np.random.default_rng(3), half_size=4.0)
    c = place_random(["tree", "person"], 50, np.random.default_rng(4), half_size=4.0)
    np.testing.assert_array_equal(a.xy, b.xy)
    assert not np.array_equal(a.xy, c.xy)
    assert np.abs(a.xy).max() <= 4.0 and set(a.asset.tolist()) == {0, 1}
    assert len(place_random(["tree"], 0, np.random.default_rng(0))) == 0
    with pytest.raises(ValidationError, match="rng: expected a numpy Generator"):
        place_random(["tree"], 3, 7)
    with pytest.raises(ValidationError, match="instance count: expected an integer >= 0"):
        place_random(["tree"], -1, np.random.default_rng(0))


# -------------------------------------------------------------------- facing


def test_view_azimuth_in_the_object_frame():
    """Instance yawed 30 deg at the origin, eye at azimuth 100 deg: seen from 70 deg."""
    a = np.radians(100)
    eye = np.array([5 * np.cos(a), 5 * np.sin(a), 2.0])
    v = view_directions(eye, np.array([[0.0, 0.0, 0.5], [0.0, 0.0, 0.5]]), np.array([30.0, -150.0]))
    np.testing.assert_allclose(v.azimuth_deg, [70.0, -110.0], atol=1e-9)
    np.testing.assert_allclose(v.elevation_deg, np.degrees(np.arctan2(1.5, 5.0)), atol=1e-9)
    np.testing.assert_allclose(v.toward_eye[0], [np.cos(a), np.sin(a)], atol=1e-12)
    assert not v.above.any()


def test_axial_facing_equals_the_papers_angle():
    """The quad's normal (right x up) points horizontally at the eye, and its angle from
    the rest normal B_n is the paper's theta = pi - acos(L_os . B_n), L_os from the eye
    to the billboard. Derived case: B_n = -y, eye at (1, -1): theta = pi/4."""
    b_n = np.array([0.0, -1.0, 0.0])
    eye = np.array([1.0, -1.0, 1.7])
    piv = np.array([[0.0, 0.0, 0.5]])
    assert paper_angle(piv[0] - eye * [1, 1, 0] - [0, 0, 0.5], b_n) == pytest.approx(np.pi / 4)
    rng = np.random.default_rng(0)
    eyes = rng.uniform(-5, 5, size=(20, 3))
    eyes[:, 2] = np.abs(eyes[:, 2]) + 0.1
    cam = perspective(1.0, (8, 8), look_at([0, -5, 1], [0, 0, 0]))
    for e in eyes:
        v = view_directions(e, piv, np.zeros(1))
        right, up = AxialFacing().axes(cam, v)
        n = np.cross(right[0], up[0])
        np.testing.assert_allclose(up[0], [0, 0, 1])
        L = piv[0] - e
        L[2] = 0.0
        np.testing.assert_allclose(n, -L / np.linalg.norm(L), atol=1e-12)
        assert np.arccos(np.clip(n @ b_n, -1, 1)) == pytest.approx(paper_angle(L, b_n), abs=1e-9)


def test_directly_above_keeps_the_instance_yaw():
    """Eye straight above the pivot: azimuth 0 (the front) and the quad faces the
    instance's front direction (cos yaw, sin yaw); no NaN."""
    piv = np.array([[2.0, 1.0, 0.4], [0.0, 0.0, 0.4]])
    v = view_directions(np.array([2.0, 1.0, 6.0]), piv, np.array([40.0, 0.0]))
    assert v.above.tolist() == [True, False]
    assert v.azimuth_deg[0] == 0.0 and v.elevation_deg[0] == pytest.approx(90.0)
    np.testing.assert_allclose(v.toward_eye[0], [np.cos(np.radians(40)), np.sin(np.radians(40))])
    cam = perspective(1.0, (8, 8), look_at([2.0, 1.0, 6.0], [2.0, 1.0, 0.0]))
    right, up = AxialFacing().axes(cam, v)
    assert np.all(np.isfinite(right)) and np.all(np.isfinite(up))
    np.testing.assert_allclose(np.cross(right[0], up[0])[:2], v.toward_eye[0], atol=1e-12)


def test_screen_facing_uses_the_camera_axes():
    cam = perspective(1.0, (8, 8), look_at([3, -4, 2], [0, 0, 0.5]))
    v = view_directions(cam.position, np.array([[0, 0, 0.5], [1, 1, 0.5]]), np.zeros(2))
    right, up = ScreenFacing().axes(cam, v)
    np.testing.assert_allclose(right, np.repeat(cam.cam2world[None, :3, 0], 2, 0))
    np.testing.assert_allclose(up, np.repeat(-cam.cam2world[None, :3, 1], 2, 0))


# ------------------------------------------------------------------- frustum


def test_sphere_culling_against_the_frustum():
    cam = perspective(np.radians(60), (48, 64), look_at([0, 0, 1], [0, 10, 1]), znear=0.5, zfar=50)
    c = np.array([[0, 5, 1],      # straight ahead
                  [0, -5, 1],     # behind
                  [20, 5, 1],     # far to the right
                  [4.3, 5, 1],    # just outside the right edge, its sphere overlapping it
                  [0, 60, 1],     # beyond zfar
                  [0, 0.2, 1]])   # in front of znear, sphere reaching past it
    r = np.array([0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
    inside, z = sphere_in_frustum(cam, cam.world2cam, c.astype(float), r)
    # right edge: x/z = (63.5 - 31.5)/fx with fx = 24/tan(30deg) -> 4.157 at y = 5 (z = 5)
    assert inside.tolist() == [True, False, False, True, False, True]
    np.testing.assert_allclose(z, [5, -5, 5, 5, 60, 0.2])
    with pytest.raises(ValidationError, match="billboard camera: expected a perspective CameraModel"):
        require_perspective(orthographic(1, 1, (8, 8), np.eye(4), znear=0.1, zfar=5))


def test_clip_near_cuts_a_square_in_half():
    sq = np.array([[-1, -1, -1.0], [1, -1, -1.0], [1, 1, 1.0], [-1, 1, 1.0]])  # z from -1 to 1 along y
    out = clip_near(sq, 0.0)
    np.testing.assert_allclose(out, [[1, 0, 0], [1, 1, 1], [-1, 1, 1], [-1, 0, 0]], atol=1e-12)
    assert len(clip_near(sq, 2.0)) == 0
    np.testing.assert_allclose(clip_near(sq, -5.0), sq)


def test_quad_homography_maps_image_corners_onto_projected_quad_corners():
    cam = perspective(np.radians(50), (48, 64), look_at([1, -6, 1.5], [0, 0, 0.6]))
    tl = np.array([[-0.3, 0.1, 1.2]])
    right = np.array([[0.8, 0.6, 0.0]])
    up = np.array([[0.0, 0.0, 1.0]])
    H_unit = quad_homographies(cam, cam.world2cam, tl, right, up, np.array([0.3]), np.array([0.5]))[0]
    h, w = 20, 12
    H = H_unit @ unit_from_image((h, w))
    src = np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5], [-0.5, h - 0.5], [5.0, 7.0]])
    r, u = 0.6 * right[0], 1.0 * up[0]  # full width and height of the quad
    world = np.array([tl[0], tl[0] + r, tl[0] + r - u, tl[0] - u, tl[0] + (5.5 / w) * r - (7.5 / h) * u])
    q = (H @ np.c_[src, np.ones(5)].T).T
    expect, _ = cam.project(world)
    np.testing.assert_allclose(q[:, :2] / q[:, 2:], expect, atol=1e-9)


# ----------------------------------------------------------------------- lod


def test_levels_from_on_screen_height():
    h = screen_height_px(500.0, np.array([0.5, 0.5, 0.5, 0.5]), np.array([1.0, 4.0, 40.0, 0.05]), 0.1)
    np.testing.assert_allclose(h[:3], [500.0, 125.0, 12.5])
    assert h[3] == np.inf
    # base 256: 500 px -> 0 (never enlarged beyond level 0), 125 -> 1 (128 >= 125), 12.5 -> 4 clipped to 2
    assert select_levels(h, 256, 3).tolist() == [0, 1, 2, 0]
    assert select_levels(np.array([64.0, 65.0]), 256, 5).tolist() == [2, 1]


# --------------------------------------------------------------------- paths


def test_pan_keeps_the_eye_and_pans_left_to_right():
    cams = PanPath(eye=(0, -5, 1.6), pan_deg=40.0).cameras(5, shape=(24, 32))
    assert all(c.shape == (24, 32) for c in cams)
    for c in cams:
        np.testing.assert_allclose(c.position, [0, -5, 1.6])
    heads = [np.degrees(np.arctan2(c.axis[1], c.axis[0])) for c in cams]
    np.testing.assert_allclose(heads, [110, 100, 90, 80, 70], atol=1e-9)  # left (ccw) to right


def test_orbit_circles_the_centre_and_looks_at_it():
    path = OrbitPath(centre=(1, 2, 0.5), radius=6, height=2, start_deg=0, end_deg=90)
    cams = path.cameras(4)
    assert cams[0].shape == (480, 640)
    for c in cams:
        assert np.hypot(*(c.position[:2] - [1, 2])) == pytest.approx(6)
        px, _ = c.project(np.array([[1.0, 2.0, 0.5]]))
        np.testing.assert_allclose(px[0], [c.cx, c.cy], atol=1e-9)
    np.testing.assert_allclose(cams[-1].position, [1, 8, 2], atol=1e-12)
    np.testing.assert_allclose(path.camera_at_deg(45.0).position,
                               [1 + 6 * np.cos(np.pi / 4), 2 + 6 * np.sin(np.pi / 4), 2], atol=1e-12)


def test_fly_path_and_path_errors():
    cams = FlyPath(start=(0, -5), end=(0, 5), height=0.9).cameras(3)
    np.testing.assert_allclose([c.position[2] for c in cams], 0.9)
    np.testing.assert_allclose(cams[1].position[:2], [0, 0], atol=1e-12)  # sway is 0 half way
    # looking along the velocity: d + sway 2 pi cos(2 pi t) side, side = (-1, 0), 5 deg down
    for c, t in zip(cams, (0.0, 0.5, 1.0), strict=True):
        vel = np.array([0.0, 10.0]) + 2 * np.pi * np.cos(2 * np.pi * t) * np.array([-1.0, 0.0])
        np.testing.assert_allclose(c.axis[:2] / np.linalg.norm(c.axis[:2]), vel / np.linalg.norm(vel))
        assert c.axis[2] == pytest.approx(-np.sin(np.radians(5.0)))
    assert isinstance(make_path("orbit", 5.0), OrbitPath)
    with pytest.raises(ValidationError, match="camera path: expected one of"):
        make_path("spiral", 5.0)
    with pytest.raises(ValidationError, match="frames: expected an integer >= 1"):
        PanPath().cameras(0)
    with pytest.raises(ValidationError, match="fly path: expected start != end"):
        FlyPath(start=(1, 1), end=(1, 1)).cameras(2)
