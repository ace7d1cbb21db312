"""The one shading model (morphkit.imaging.shading): analytic values, the horizon, frames, passes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.shading import Lighting, shade, shade_passes
from morphkit.passes import RenderPasses
from morphkit.scene import AreaLight, DirectionalLight, PointLight
from morphkit.views.gbuffer import ViewSurface


def _srgb(x: float) -> float:
    """The model's output encoding, written out: gamma 1/2.2 (the renderer's lit colour)."""
    return min(x, 1.0) ** (1 / 2.2)


# the encoding table (65536 steps) is within 0.01 / 255 of the curve above 0.01 (morphkit.imaging.shading)
ENC_ATOL = 0.25 / 255


def _flat(shape, rgb, alpha, normal) -> ViewSurface:
    """A one-colour surface: straight linear ``rgb``, coverage ``alpha``, one normal."""
    h, w = shape
    albedo = np.empty((h, w, 4), np.float32)
    albedo[..., :3] = np.asarray(rgb, np.float32) * alpha
    albedo[..., 3] = alpha
    n = np.asarray(normal, np.float64)
    n = np.broadcast_to((n / np.linalg.norm(n)).astype(np.float32), (h, w, 3)).copy()
    return ViewSurface(albedo, n, np.ones((h, w), np.float32))


def _random_surface(rng, shape) -> ViewSurface:
    h, w = shape
    a = rng.uniform(0.0, 1.0, (h, w)).astype(np.float32)
    a[0, :] = 0.0
    albedo = np.empty((h, w, 4), np.float32)
    albedo[..., :3] = rng.uniform(0.0, 1.0, (h, w, 3)) * a[..., None]
    albedo[..., 3] = a
    n = rng.normal(size=(h, w, 3))
    n = (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)
    return ViewSurface(albedo, n, np.ones((h, w), np.float32))


def _sun(az_deg: float, el_deg: float, intensity: float = 3.0) -> DirectionalLight:
    a, e = np.radians(az_deg), np.radians(el_deg)
    return DirectionalLight(-np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)]), intensity)


# ------------------------------------------------------------------ analytic values


def test_a_sun_along_the_normal_gives_the_equation_by_hand():
    rgb, alpha, amb, intensity = (0.2, 0.05, 0.4), 0.6, 0.25, 2.0
    sun = _sun(30.0, 40.0, intensity)
    out = shade(_flat((3, 4), rgb, alpha, -sun.direction), Lighting(amb, (sun,)))
    # n . l = 1: L = rho (a + I / pi)
    want = [_srgb(min(c * (amb + intensity / np.pi), 1.0)) * alpha for c in rgb]
    assert out.shape == (3, 4, 4) and out.dtype == np.float32
    np.testing.assert_allclose(out[..., :3], np.broadcast_to(want, (3, 4, 3)), atol=ENC_ATOL)
    np.testing.assert_array_equal(out[..., 3], np.float32(alpha))


def test_the_cosine_the_clamp_behind_and_the_sum_of_two_suns():
    rgb, amb = (0.3, 0.3, 0.3), 0.1
    top = _sun(0.0, 90.0, 1.5)  # straight down
    side = _sun(0.0, 30.0, 1.0)  # from +x, 30 degrees up: n . l = sin 30 = 0.5 on an up normal
    out = shade(_flat((2, 2), rgb, 1.0, (0, 0, 1)), Lighting(amb, (top, side)))
    want = _srgb(0.3 * (amb + 1.5 / np.pi + 1.0 * 0.5 / np.pi))
    np.testing.assert_allclose(out[..., :3], want, atol=ENC_ATOL)
    # a normal facing away from both lights: ambient only (max(0, n . l))
    away = shade(_flat((2, 2), rgb, 1.0, (-1, 0, -1)), Lighting(amb, (top, side)))
    np.testing.assert_allclose(away[..., :3], _srgb(0.3 * amb), atol=ENC_ATOL)


def test_a_point_light_falls_off_with_the_squared_distance():
    rgb, amb, intensity = (0.1, 0.2, 0.3), 0.05, 20.0
    surf = _flat((2, 3), rgb, 1.0, (0, 0, 1))
    pts = np.zeros((2, 3, 3), np.float32)
    pts[..., 0] = np.arange(3)  # points (0, 0, 0), (1, 0, 0), (2, 0, 0) on the ground
    lamp = PointLight([0.0, 0.0, 2.0], intensity)
    out = shade(surf, Lighting(amb, (lamp,)), pts)
    for x in range(3):
        d2 = x * x + 4.0
        cos = 2.0 / np.sqrt(d2)
        want = [_srgb(min(c * (amb + intensity * cos / (np.pi * d2)), 1.0)) for c in rgb]
        np.testing.assert_allclose(out[0, x, :3], want, atol=ENC_ATOL)


def test_zero_alpha_gives_zero_everywhere(rng):
    surf = _random_surface(rng, (8, 8))
    out = shade(surf, Lighting(0.5, (_sun(10.0, 45.0),)))
    assert (surf.alpha[0] == 0).all()
    np.testing.assert_array_equal(out[0], 0.0)
    # elsewhere: premultiplied (colour <= alpha) and alpha passed through
    assert (out[..., :3] <= out[..., 3:] + 1e-6).all()
    np.testing.assert_array_equal(out[..., 3], surf.alpha)


# ------------------------------------------------------------------ the horizon


@pytest.mark.parametrize("elevation", [0.0, -0.5, -45.0])
def test_a_sun_at_or_below_the_horizon_lights_nothing(rng, elevation):
    surf = _random_surface(rng, (6, 7))
    low = _sun(20.0, elevation, 5.0)
    ambient_only = shade(surf, Lighting(0.3))
    np.testing.assert_array_equal(shade(surf, Lighting(0.3, (low,))), ambient_only)
    # a normal pointing straight at that sun is still ambient only
    flat = _flat((2, 2), (0.5, 0.5, 0.5), 1.0, -low.direction)
    np.testing.assert_array_equal(shade(flat, Lighting(0.3, (low,))), shade(flat, Lighting(0.3)))
    assert Lighting(0.3, (low,)).above_horizon().lights == ()


def test_the_horizon_is_the_worlds_in_an_object_frame():
    """A rotation that would lift a world-frame sun below the horizon above the object's
    horizontal plane does not bring it back: the test is the world's (``up`` is carried)."""
    below = _sun(0.0, -20.0)
    T = np.eye(4)
    T[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]  # -90 degrees about y
    assert (T[:3, :3] @ -below.direction)[2] > 0.9  # above the object's horizontal plane
    lit = Lighting(0.2, (below, _sun(0.0, 30.0))).in_frame(T)
    assert len(lit.lights) == 1
    np.testing.assert_allclose(lit.up, [-1.0, 0.0, 0.0], atol=1e-12)
    # and a sun above the horizon stays above it in the new frame
    assert float(-lit.lights[0].direction @ np.asarray(lit.up)) > 0


# ------------------------------------------------------------------ frames


def test_shading_in_an_object_frame_equals_shading_in_the_world(rng):
    """An instance pose (translation, yaw, uniform scale): its object-frame normals and points
    under the lighting moved into its frame shade exactly as the world-frame ones."""
    yaw, s = np.radians(35.0), 1.7
    c, sn = np.cos(yaw), np.sin(yaw)
    obj2world = np.eye(4)
    obj2world[:3, :3] = s * np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1]])
    obj2world[:3, 3] = [3.0, -2.0, 0.0]
    surf = _random_surface(rng, (9, 11))
    pts_obj = rng.uniform(-0.5, 0.5, (9, 11, 3)).astype(np.float32)
    R = obj2world[:3, :3] / s
    n_world = (surf.normal.reshape(-1, 3) @ R.T).reshape(surf.normal.shape).astype(np.float32)
    pts_world = (pts_obj.reshape(-1, 3) @ obj2world[:3, :3].T + obj2world[:3, 3]).reshape(pts_obj.shape)
    world = Lighting(0.2, (_sun(-60.0, 25.0, 2.5), PointLight([4.0, -1.0, 2.0], 15.0), _sun(0.0, -5.0)))
    want = shade(ViewSurface(surf.albedo, n_world, surf.depth), world, pts_world.astype(np.float32))
    got = shade(surf, world.in_frame(np.linalg.inv(obj2world)), pts_obj)
    np.testing.assert_allclose(got, want, atol=2e-4)
    assert np.ptp(want[..., :3]) > 0.3  # lit, not all one value


def test_lighting_validation():
    with pytest.raises(ValidationError, match="ambient: expected a finite number >= 0"):
        Lighting(-0.1)
    area = AreaLight(np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))
    with pytest.raises(ValidationError, match=r"lights\[1\]: expected a DirectionalLight or a PointLight"):
        Lighting(0.1, (_sun(0, 30), area))
    shear = np.eye(4)
    shear[0, 0] = 2.0
    with pytest.raises(ValidationError, match="frame_from_world: expected rotation, uniform scale"):
        Lighting(0.1, (_sun(0, 30),)).in_frame(shear)
    assert Lighting(0.1, [_sun(0, 30)]).lights[0].intensity == 3.0  # a list becomes a tuple


def test_point_lights_need_points():
    surf = _flat((2, 2), (0.5, 0.5, 0.5), 1.0, (0, 0, 1))
    lamp = Lighting(0.1, (PointLight([0.0, 0.0, 1.0]),))
    with pytest.raises(ValidationError, match=r"points: expected \(h, w, 3\) surface positions"):
        shade(surf, lamp)
    with pytest.raises(ValidationError, match=r"points: expected \(2, 2, 3\)"):
        shade(surf, lamp, np.zeros((3, 2, 3)))
    # suns alone need no points
    assert shade(surf, Lighting(0.1, (_sun(0, 30),))).shape == (2, 2, 4)


# ------------------------------------------------------------------ passes (the truth)


def _plane_passes(shape=(9, 9), value=150):
    """A camera 4 units above the ground looking down; the ground covers the left 5 columns."""
    cam = perspective(np.radians(60.0), shape, look_at([0.0, 0.0, 4.0], [0.0, 0.0, 0.0],
                                                       up=np.array([0.0, 1.0, 0.0])))
    h, w = shape
    alpha = np.zeros((h, w), np.float32)
    alpha[:, :5] = 1.0
    x, y = cam.pixel_grid()
    ray_z = 1.0  # looking straight down at z = 0: depth 4 everywhere
    depth = np.where(alpha > 0, 4.0 / ray_z, np.inf).astype(np.float32)
    albedo = np.where(alpha[..., None] > 0, np.uint8(value), np.uint8(0)).repeat(3, axis=2).astype(np.uint8)
    normal = np.zeros((h, w, 3), np.float32)
    normal[alpha > 0] = [0.0, 0.0, 1.0]
    color = np.zeros((h, w, 3), np.uint8)
    return cam, RenderPasses(color, albedo, normal, depth, alpha)


def test_shade_passes_decodes_albedo_and_uses_the_depth_for_point_lights():
    cam, passes = _plane_passes()
    rho = ((150 / 255 + 0.055) / 1.055) ** 2.4  # sRGB 150 decoded
    sun = _sun(0.0, 60.0, 2.0)
    out = shade_passes(passes, Lighting(0.3, (sun,)), cam)
    np.testing.assert_allclose(out[:, :5, :3], _srgb(rho * (0.3 + 2.0 * np.sin(np.radians(60)) / np.pi)),
                               atol=ENC_ATOL)
    np.testing.assert_array_equal(out[:, 5:], 0.0)
    # a point light 1 above the ground point under the centre pixel (4, 4): d = 1, cos = 1
    lit = shade_passes(passes, Lighting(0.3, (PointLight([0.0, 0.0, 1.0], 2.0),)), cam)
    np.testing.assert_allclose(lit[4, 4, :3], _srgb(rho * (0.3 + 2.0 / np.pi)), atol=ENC_ATOL)
    assert (lit[4, 0, :3] < lit[4, 4, :3]).all()  # farther from the lamp: darker
    with pytest.raises(ValidationError, match="passes: expected images of the camera's shape"):
        shade_passes(passes, Lighting(0.3), perspective(np.radians(60.0), (5, 5), cam.cam2world))


def test_importing_shading_first_then_the_billboards_works():
    """shading imports the billboard package's colour tables lazily, so a billboard module
    may import shading whichever is imported first."""
    code = "import morphkit.imaging.shading, morphkit.billboard, morphkit.sunlit.litmesh; print('ok')"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
