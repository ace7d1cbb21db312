"""Billboards seen from any height: the viewpoint facing, the fly-over and top-down paths, the sun."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard.frames.facing import AxialFacing, ViewpointFacing, view_directions
from morphkit.billboard.frames.paths import (
    PATHS,
    FlyoverPath,
    FlyPath,
    OrbitPath,
    PanPath,
    TopDownPan,
    make_path,
)
from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.sunpath import TEST_SUNS, SunPath, sun, sun_directions_8
from morphkit.views.domecameras import direction, quad_axes

CAM = perspective(np.radians(50), (48, 64), look_at([0, -10, 1], [0, 0, 1]))


def _field(rng, n=12):
    pivots = np.column_stack([rng.uniform(-4, 4, n), rng.uniform(-4, 4, n), rng.uniform(0.3, 1.0, n)])
    return pivots, rng.uniform(-180, 180, n)


# ------------------------------------------------------------------ facing


def test_viewpoint_facing_is_axial_facing_at_elevation_zero(rng):
    pivots, yaw = _field(rng)
    pivots[:, 2] = 0.5
    views = view_directions(np.array([1.0, -9.0, 0.5]), pivots, yaw)
    np.testing.assert_allclose(views.elevation_deg, 0.0, atol=1e-12)
    for got, want in zip(ViewpointFacing().axes(CAM, views), AxialFacing().axes(CAM, views), strict=True):
        np.testing.assert_allclose(got, want, atol=1e-12)


@pytest.mark.parametrize("eye", [(2.0, -6.0, 3.0), (0.5, 0.2, 9.0), (-3.0, 1.0, -2.0)])
def test_right_up_and_the_direction_to_the_eye_are_orthonormal(rng, eye):
    pivots, yaw = _field(rng)
    pivots[0] = [eye[0], eye[1], 0.5]  # one pivot straight below (or above) the eye
    views = view_directions(np.array(eye), pivots, yaw)
    right, up = ViewpointFacing().axes(CAM, views)
    d = np.array(eye)[None, :] - pivots
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    for a, b in ((right, up), (right, d), (up, d)):
        np.testing.assert_allclose(np.einsum("ij,ij->i", a, b), 0.0, atol=1e-9)
    for v in (right, up):
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.cross(up, d), right, atol=1e-9)  # the dome rule's handedness


def test_viewpoint_facing_is_the_dome_rule_turned_by_the_yaw(rng):
    """Each instance's quad is the :mod:`domecameras` quad of its viewing azimuth and
    elevation (object frame), turned by its yaw into the world."""
    pivots, yaw = _field(rng)
    views = view_directions(np.array([3.0, -7.0, 4.0]), pivots, yaw)
    right, up = ViewpointFacing().axes(CAM, views)
    r_obj, u_obj = quad_axes(views.azimuth_deg, views.elevation_deg)
    d_obj = direction(views.azimuth_deg, views.elevation_deg)
    for k, y in enumerate(np.radians(yaw)):
        Rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
        np.testing.assert_allclose(Rz @ r_obj[k], right[k], atol=1e-9)
        np.testing.assert_allclose(Rz @ u_obj[k], up[k], atol=1e-9)
        to_eye = np.array([3.0, -7.0, 4.0]) - pivots[k]
        np.testing.assert_allclose(Rz @ d_obj[k], to_eye / np.linalg.norm(to_eye), atol=1e-9)


def test_straight_above_the_quad_lies_flat_with_the_instances_front_down_the_image():
    yaw = 30.0
    views = view_directions(np.array([1.0, 2.0, 8.0]), np.array([[1.0, 2.0, 0.5]]), np.array([yaw]))
    assert views.above[0] and views.azimuth_deg[0] == 0.0
    right, up = ViewpointFacing().axes(CAM, views)
    assert np.isfinite(right).all() and np.isfinite(up).all()
    front = np.array([np.cos(np.radians(yaw)), np.sin(np.radians(yaw)), 0.0])
    np.testing.assert_allclose(up[0], -front, atol=1e-12)  # the quad of (azimuth 0, elevation 90)
    np.testing.assert_allclose(right[0], [-front[1], front[0], 0.0], atol=1e-12)


# ------------------------------------------------------------------ paths


def test_flyover_rises_from_5_to_85_degrees_looking_at_the_centre():
    path = FlyoverPath(centre=(1.0, -1.0, 0.5), distance=9.0)
    cams = path.cameras(9, shape=(30, 40))
    c = np.array([1.0, -1.0, 0.5])
    elev = [np.degrees(np.arcsin((cm.position - c)[2] / np.linalg.norm(cm.position - c))) for cm in cams]
    np.testing.assert_allclose(elev, np.linspace(5.0, 85.0, 9), atol=1e-9)
    for cm in cams:
        assert np.linalg.norm(cm.position - c) == pytest.approx(9.0)
        px, _ = cm.project(c[None])
        np.testing.assert_allclose(px[0], [cm.cx, cm.cy], atol=1e-9)
    # the field centre is seen at those elevations by the billboards' own rule
    views = view_directions(cams[-1].position, c[None], np.zeros(1))
    assert views.elevation_deg[0] == pytest.approx(85.0)
    with pytest.raises(ValidationError, match=r"end_elevation_deg: expected degrees in \[-89, 89\]"):
        FlyoverPath(end_elevation_deg=90.0).camera_at(1.0)


def test_top_down_pan_looks_straight_down_and_pans_across():
    path = TopDownPan(start=(-3.0, 0.0), end=(3.0, 0.0), height=7.0, heading_deg=90.0)
    cams = path.cameras(4, shape=(30, 40))
    np.testing.assert_allclose([cm.position[0] for cm in cams], [-3, -1, 1, 3], atol=1e-12)
    for cm in cams:
        np.testing.assert_allclose(cm.axis, [0.0, 0.0, -1.0], atol=1e-12)
        assert cm.position[2] == pytest.approx(7.0)
        np.testing.assert_allclose(-cm.cam2world[:3, 1], [0.0, 1.0, 0.0], atol=1e-12)  # image up: +y
        ground = np.array([cm.position[0], cm.position[1], 0.5])
        views = view_directions(cm.position, ground[None], np.zeros(1))
        assert views.above[0] and views.elevation_deg[0] == pytest.approx(90.0)


def test_make_path_knows_the_new_and_the_old_paths():
    assert set(PATHS) == {"pan", "orbit", "fly", "flyover", "topdown"}
    for name, cls in (("pan", PanPath), ("orbit", OrbitPath), ("fly", FlyPath), ("flyover", FlyoverPath),
                      ("topdown", TopDownPan)):
        path = make_path(name, 5.0)
        assert isinstance(path, cls)
        assert len(path.cameras(3, shape=(12, 16))) == 3
    top = make_path("topdown", 5.0)
    assert top.camera_at(0.0).position[1] == pytest.approx(-5.0)
    assert top.camera_at(1.0).position[1] == pytest.approx(5.0)


# ------------------------------------------------------------------ the sun


def test_a_day_rises_below_the_horizon_peaks_at_noon_and_sets():
    path = SunPath(azimuth_range=(-90.0, 90.0), max_elevation=60.0, rise_deg=-5.0)
    suns = path.suns(11)
    up = np.array([-s.direction[2] for s in suns])  # sin(elevation) of the way to the sun
    elev = np.degrees(np.arcsin(up))
    assert elev[0] == pytest.approx(-5.0) and elev[-1] == pytest.approx(-5.0)
    assert elev[5] == pytest.approx(60.0) and elev.argmax() == 5
    np.testing.assert_allclose(elev, elev[::-1], atol=1e-9)  # symmetric about noon
    assert (np.diff(elev[:6]) > 0).all()
    az = np.degrees(np.arctan2(-np.array([s.direction[1] for s in suns]),
                               -np.array([s.direction[0] for s in suns])))
    np.testing.assert_allclose(az, np.linspace(-90, 90, 11), atol=1e-9)
    # on the horizon exactly at both ends with rise_deg = 0
    edge = SunPath.day(3, rise_deg=0.0)
    assert edge[0].direction[2] == 0.0 and edge[-1].direction[2] == 0.0
    with pytest.raises(ValidationError, match=r"max_elevation: expected degrees in \(0, 90\]"):
        SunPath(max_elevation=95.0)
    with pytest.raises(ValidationError, match=r"rise_deg: expected degrees in \(-90, max_elevation = 60\]"):
        SunPath(rise_deg=70.0)
    with pytest.raises(ValidationError, match=r"t: expected a number in \[0, 1\]"):
        path.sun_at(1.5)


@pytest.mark.parametrize("frames", [1, 2, 3, 4, 5, 8, 48])
def test_every_frame_of_the_default_day_has_a_sun(frames):
    elev = np.degrees(np.arcsin(np.array([-s.direction[2] for s in SunPath.day(frames)])))
    assert len(elev) == frames and (elev > 0.0).all()
    assert elev.min() == pytest.approx(SunPath().rise_deg)  # sunrise is the lowest


def test_the_eight_test_suns():
    suns = sun_directions_8()
    assert list(suns) == list(TEST_SUNS) and len(suns) == 8
    towards = {k: -v.direction for k, v in suns.items()}
    assert np.degrees(np.arcsin(towards["low"][2])) == pytest.approx(5.0)
    np.testing.assert_allclose(towards["above"], [0, 0, 1], atol=1e-12)
    assert towards["horizon"][2] == 0.0  # on the horizon: no light by the shading rule
    assert towards["behind"][0] < -0.8  # the viewer is along +x (azimuth 0): the sun is behind
    assert towards["front"][0] > 0.8
    turned = sun_directions_8(view_azimuth_deg=90.0)
    assert turned["behind"].direction[1] > 0.8  # viewer along +y: light travels towards +y
    np.testing.assert_allclose(sun(0.0, 90.0).direction, [0, 0, -1], atol=1e-12)


def test_from_85_degrees_viewpoint_quads_are_drawn_where_axial_ones_are_edge_on():
    """The issue's failure: at 85 degrees of elevation an axial quad is nearly edge-on; the
    viewpoint quad faces the camera and covers about its full area."""
    from billboard_fakes import FakeAsset

    from morphkit.billboard import BillboardScene, Instances, MorphMode

    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1)
    inst = Instances.from_records([("solid", 0.0, 0.0)])
    cam = FlyoverPath(centre=(0.0, 0.0, 0.4), distance=6.0).camera_at(1.0, (60, 80))
    cover = {}
    for name, facing in (("axial", AxialFacing()), ("viewpoint", ViewpointFacing())):
        scene = BillboardScene({"solid": asset}, inst, facing=facing)
        cover[name] = float(scene.render(cam, MorphMode()).layer[..., 3].sum())
    # the quad (0.6 x 0.8 at distance 6, focal 60 / (2 tan 25) = 64 px) covers ~ 0.6 * 0.8 * (64/6)^2 = 55 px
    assert cover["viewpoint"] > 40.0
    assert cover["axial"] < 0.2 * cover["viewpoint"]  # sin(5 deg) of it, about
    top = TopDownPan(start=(0.0, 0.0), end=(0.0, 1.0), height=5.0).camera_at(0.0, (60, 80))
    scene = BillboardScene({"solid": asset}, inst, facing=ViewpointFacing())
    frame = scene.render(top, MorphMode())
    assert frame.stats.n_drawn == 1 and frame.layer[..., 3].sum() > 40.0
