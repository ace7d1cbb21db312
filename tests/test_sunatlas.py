"""The sun atlas (issue 26, first step): light views over the sun's direction, one instance's
ground shadow, the yaw rule, the horizon and the grazing clamp, bad arguments.

The analytic sphere (:mod:`morphkit.billboard.analytic`: radius 0.6 about ``(0, 0, 1)``) gives an
atlas without GL and a shadow known exactly: a ground point is shadowed when its ray towards the
sun passes within the radius of the centre (an ellipse, a disc under a sun straight above).
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit import tol
from morphkit.billboard.analytic import SPHERE_PIVOT, SPHERE_RADIUS, sphere_view
from morphkit.errors import ValidationError
from morphkit.imaging.metrics import shadow_iou
from morphkit.sunlit.sunatlas import (
    SunAtlas,
    bake_sun_atlas,
    ground_shadow,
    instance_frame,
    sun_direction,
    sun_in_object,
)
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras

DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
N = 64


@pytest.fixture(scope="module")
def sphere_atlas() -> SunAtlas:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (N, N))
    depths = [sphere_view(cams.ortho_camera(a, e, (N, N)))[2]
              for a, e in zip(DOME.azimuths_deg(), DOME.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(DOME, cams, np.stack(depths))


def _pose(yaw_deg: float = 0.0, xy: tuple[float, float] = (0.0, 0.0), scale: float = 1.0) -> np.ndarray:
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    pose = np.eye(4)
    pose[:2, :2] = scale * np.array([[c, -s], [s, c]])
    pose[2, 2] = scale
    pose[:2, 3] = xy
    return pose


def _grid(centre: np.ndarray, half: float, n: int = 160) -> np.ndarray:
    xs = np.linspace(-half, half, n)
    X, Y = np.meshgrid(xs + centre[0], xs + centre[1])
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def _sphere_truth(points: np.ndarray, centre: np.ndarray, radius: float, sun: np.ndarray) -> np.ndarray:
    """True where the ray from a point towards the sun passes within ``radius`` of ``centre``."""
    v = centre - points
    along = v @ sun
    miss = np.linalg.norm(v - along[:, None] * sun, axis=1)
    return (miss < radius) & (along > 0)


def test_between_atlas_directions_the_sphere_casts_its_ellipse(sphere_atlas):
    sun = sun_direction(17.0, 52.0)
    assert DOME.weights(17.0, 52.0)[1].max() < 0.9  # truly between three views
    centre = SPHERE_PIVOT - SPHERE_PIVOT[2] / sun[2] * sun  # the shadow's centre on the ground
    pts = _grid(centre, 1.2)
    shadow = ground_shadow(sphere_atlas, np.eye(4), sun, pts) < 0.5
    truth = _sphere_truth(pts, SPHERE_PIVOT, SPHERE_RADIUS, sun)
    assert shadow_iou(shadow, truth) > 0.95
    texel = 2.0 * sphere_atlas.cameras.half_extent[0] / N
    assert np.linalg.norm(pts[shadow, :2].mean(axis=0) - centre[:2]) < texel
    # across the sun's azimuth the ellipse is as wide as the sphere
    across = np.array([-sun[1], sun[0]]) / np.linalg.norm(sun[:2])
    width = np.ptp((pts[shadow, :2] - centre[:2]) @ across)
    assert abs(width - 2 * SPHERE_RADIUS) < 2 * texel


def test_sun_straight_above_casts_a_disc_of_the_sphere_radius(sphere_atlas):
    pts = _grid(np.zeros(3), 1.0)
    shadow = ground_shadow(sphere_atlas, np.eye(4), np.array([0.0, 0.0, 2.0]), pts) < 0.5
    r = np.linalg.norm(pts[:, :2], axis=1)
    texel = 2.0 * sphere_atlas.cameras.half_extent[0] / N
    assert shadow[r < SPHERE_RADIUS - texel].all() and not shadow[r > SPHERE_RADIUS + texel].any()


def test_at_an_atlas_direction_the_light_view_is_the_stored_view(sphere_atlas):
    k = 9  # a view of the 40-degree ring
    sun = sun_direction(DOME.azimuths_deg()[k], DOME.elevations_deg()[k])
    cam, depth = sphere_atlas.light_view(sun)
    assert np.array_equal(depth, sphere_atlas.view_depth(k))
    np.testing.assert_array_equal(cam.cam2world, sphere_atlas.view_camera(k).cam2world)
    # at another resolution it is that view resampled: the disc, off at its rim only
    cam2, depth2 = sphere_atlas.light_view(sun, (32, 32))
    exact = sphere_view(cam2)[2]
    assert shadow_iou(np.isfinite(depth2), np.isfinite(exact)) > 0.95


def test_a_yawed_instance_is_the_object_under_the_sun_turned_back(sphere_atlas):
    sun = sun_direction(-63.0, 33.0)
    yaw, xy = 71.0, (2.0, -1.0)
    pose = _pose(yaw, xy)
    turned = sun_in_object(pose, sun)
    np.testing.assert_allclose(turned, sun_direction(-63.0 - yaw, 33.0), atol=1e-12)
    centre = np.array([*xy, 0.0]) + SPHERE_PIVOT - SPHERE_PIVOT[2] / sun[2] * sun
    pts = _grid(centre, 1.8)
    seen = ground_shadow(sphere_atlas, pose, sun, pts)
    inv = np.linalg.inv(pose)
    local = pts @ inv[:3, :3].T + inv[:3, 3]
    alone = ground_shadow(sphere_atlas, np.eye(4), turned, local)
    assert (seen != alone).sum() <= 2  # float rounding at texel edges only
    assert (seen < 0.5).sum() > 500
    truth = _sphere_truth(pts, SPHERE_PIVOT + [*xy, 0.0], SPHERE_RADIUS, sun)
    assert shadow_iou(seen < 0.5, truth) > 0.95


def test_a_scaled_instance_casts_a_scaled_shadow(sphere_atlas):
    sun = sun_direction(100.0, 60.0)
    pose = _pose(20.0, (0.5, 0.5), scale=1.5)
    centre = 1.5 * SPHERE_PIVOT + [0.5, 0.5, 0.0]
    pts = _grid(centre - centre[2] / sun[2] * sun, 2.0)
    truth = _sphere_truth(pts, centre, 1.5 * SPHERE_RADIUS, sun)
    assert shadow_iou(ground_shadow(sphere_atlas, pose, sun, pts) < 0.5, truth) > 0.95
    assert instance_frame(pose)[0] == pytest.approx(1.5)


@pytest.mark.parametrize("elevation", [0.0, -10.0, -90.0])
def test_a_sun_at_or_below_the_horizon_casts_nothing_and_raises_nothing(sphere_atlas, elevation):
    sun = sun_direction(30.0, elevation)
    assert sphere_atlas.light_view(sun) is None
    vis = ground_shadow(sphere_atlas, _pose(40.0), sun, _grid(np.zeros(3), 3.0, 20))
    assert vis.dtype == np.float32 and (vis == 1.0).all()


def test_a_grazing_sun_is_served_at_the_cut_off(sphere_atlas):
    low = sphere_atlas.light_view(sun_direction(25.0, 1.0))
    cut = sphere_atlas.light_view(sun_direction(25.0, tol.SUN_MIN_ELEVATION_DEG))
    np.testing.assert_allclose(low[0].cam2world, cut[0].cam2world, atol=1e-12)
    np.testing.assert_array_equal(low[1], cut[1])
    assert np.isfinite(low[1]).any()


def test_bad_arguments_raise(sphere_atlas):
    pts = np.zeros((3, 3))
    tilted = np.eye(4)
    tilted[:3, :3] = trimesh.transformations.rotation_matrix(0.3, [1.0, 0.0, 0.0])[:3, :3]
    with pytest.raises(ValidationError, match="a yaw only"):
        ground_shadow(sphere_atlas, tilted, np.array([0.0, 0.0, 1.0]), pts)
    stretched = np.diag([1.0, 2.0, 1.0, 1.0])
    with pytest.raises(ValidationError, match="a yaw only"):
        ground_shadow(sphere_atlas, stretched, np.array([0.0, 0.0, 1.0]), pts)
    with pytest.raises(ValidationError, match="non-zero direction"):
        ground_shadow(sphere_atlas, np.eye(4), np.zeros(3), pts)
    with pytest.raises(ValidationError, match="non-zero direction"):
        sphere_atlas.light_view(np.zeros(3))
    with pytest.raises(ValidationError, match="a SunAtlas"):
        ground_shadow("atlas", np.eye(4), np.array([0.0, 0.0, 1.0]), pts)
    with pytest.raises(ValidationError, match="points"):
        ground_shadow(sphere_atlas, np.eye(4), np.array([0.0, 0.0, 1.0]), np.zeros((3, 2)))
    with pytest.raises(ValidationError, match="float16 and uint8"):
        SunAtlas(DOME, sphere_atlas.cameras, sphere_atlas.depth.astype(np.float32), sphere_atlas.coverage)
    with pytest.raises(ValidationError, match="float16 and uint8"):
        SunAtlas(ViewDome(), sphere_atlas.cameras, sphere_atlas.depth, sphere_atlas.coverage)
    with pytest.raises(ValidationError, match="a ViewDome"):
        bake_sun_atlas(trimesh.creation.box(), None, dome="dense")
    with pytest.raises(ValidationError, match="size"):
        bake_sun_atlas(trimesh.creation.box(), None, size=4)
    with pytest.raises(ValidationError, match="hash"):
        sphere_atlas.check_mesh(trimesh.creation.box())


@pytest.mark.gl
def test_a_baked_atlas_matches_its_direct_render_and_the_ray_cast(renderer):
    from morphkit.meshes import normalize
    from morphkit.sunlit.sunbaselines import direct_ground_shadow, direct_light_view, ray_cast_ground_shadow

    mesh = trimesh.creation.box(extents=(0.3, 0.6, 1.0))
    atlas = bake_sun_atlas(mesh, renderer, dome=DOME, size=48)
    assert atlas.nbytes == DOME.views * 48 * 48 * 3
    k = 12  # at an atlas direction: the light view is the baked one, the direct render too
    sun_k = sun_direction(DOME.azimuths_deg()[k], DOME.elevations_deg()[k])
    cam, depth = atlas.light_view(sun_k)
    dcam, ddepth = direct_light_view(atlas, normalize(mesh), renderer, sun_k)
    np.testing.assert_allclose(cam.cam2world, dcam.cam2world, atol=1e-12)
    both = np.isfinite(depth)
    assert np.array_equal(both, np.isfinite(ddepth))
    np.testing.assert_allclose(depth[both], ddepth[both], atol=2e-3)  # float16 storage
    sun, pose = sun_direction(-140.0, 38.0), _pose(25.0, (1.0, 2.0))
    pts = _grid(np.array([1.0, 2.0, 0.0]) - 0.5 / sun[2] * sun, 1.6, 96)
    truth = ray_cast_ground_shadow(mesh, pose, sun, pts) < 0.5
    assert truth.sum() > 300
    assert shadow_iou(ground_shadow(atlas, pose, sun, pts) < 0.5, truth) > 0.9
    assert shadow_iou(direct_ground_shadow(atlas, mesh, renderer, pose, sun, pts) < 0.5, truth) > 0.9
    with pytest.raises(ValidationError, match="hash"):
        direct_ground_shadow(atlas, trimesh.creation.icosphere(), renderer, pose, sun, pts)


def test_a_jump_to_a_nearer_surface_is_no_crossing_for_light_views():
    """A ray passing from in front of a far plate to behind a nearer one (a gap between parts
    the reference sees overlapping) lands far behind the near plate: occluded, not hit."""
    from morphkit.camera import orthographic
    from morphkit.views.depthmorph import HIT, OCCLUDED, march_view

    cam = orthographic(1.0, 1.0, (16, 16), np.eye(4), znear=0.1, zfar=10.0)  # camera frame = world
    depth = np.full((16, 16), 3.0, np.float32)
    depth[:, :8] = 1.0  # the near plate on the image's left (camera x < 0)
    d = np.array([-1.0, 0.0, 0.2]) / np.linalg.norm([-1.0, 0.0, 0.2])
    o = np.array([[0.5, 0.0, 1.5]], np.float32)
    dirs = d[None].astype(np.float32)
    t0, t1 = np.zeros(1, np.float32), np.ones(1, np.float32)
    assert march_view(o, dirs, t0, t1, cam, depth, 32).status[0] == OCCLUDED
    # a continuous crossing of the far plate stays a hit
    down = np.array([[-0.05, 0.0, 0.96]], np.float32)  # steep into the far plate at x > 0
    deep = np.array([[0.5, 0.0, 2.0]], np.float32)
    hit = march_view(deep, down / np.linalg.norm(down), t0, 2 * t1, cam, depth, 32)
    assert hit.status[0] == HIT and abs(2.0 + hit.t[0] * 0.96 / np.linalg.norm(down) - 3.0) < 0.05


def test_view_points_lie_on_the_sphere_with_its_normals(sphere_atlas):
    for k in (0, 9, 20):
        pts, nrm = sphere_atlas.view_points(k)
        assert pts.shape == nrm.shape and len(pts) == int((sphere_atlas.coverage[k] > 0).sum()) > 1000
        radial = pts - SPHERE_PIVOT
        # on the surface to float16 depth and the texel's half width
        assert np.abs(np.linalg.norm(radial, axis=1) - SPHERE_RADIUS).max() < 0.02
        known = np.linalg.norm(nrm, axis=1) > 0
        assert known.mean() > 0.99
        cos = np.sum(nrm[known] * radial[known], axis=1) / np.linalg.norm(radial[known], axis=1)
        # the depth's differences give the normal: within 5 degrees where the view is not grazing
        facing = radial[known] @ np.asarray(sphere_atlas.view_camera(k).cam2world)[:3, 2] < -0.3
        assert np.median(cos) > 0.999 and cos[facing].min() > np.cos(np.radians(5.0))
