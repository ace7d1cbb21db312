"""Relit billboards (#25): LitMode over dome assets, shaded by the scene's lights per frame.

The assets are the analytic sphere (:mod:`morphkit.billboard.analytic`): no GL.
"""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.billboard import Backdrop, BillboardScene, Instances
from morphkit.billboard.analytic import sphere_dome_asset
from morphkit.billboard.frames.facing import AxialFacing, ViewpointFacing
from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.shading import Lighting
from morphkit.scene import PointLight
from morphkit.sunlit.litmodes import (
    ClassicSurface,
    CrossfadeSurface,
    LitMode,
    MorphSurface,
    NearestSurface,
    pack_surface,
    unpack_surface,
)
from morphkit.sunpath import sun


@pytest.fixture(scope="module")
def ball():
    return sphere_dome_asset(size=32, levels=2)


def _scene(asset, yaw=0.0, facing=None):
    inst = Instances(("ball",), np.zeros(1, np.int64), np.zeros((1, 2)), np.array([yaw]), np.ones(1))
    return BillboardScene({"ball": asset}, inst, backdrop=Backdrop(), facing=facing or ViewpointFacing())


def _camera(azimuth_deg, elevation_deg, dist=9.0):
    a, e = np.radians(azimuth_deg), np.radians(elevation_deg)
    target = np.array([0.0, 0.0, 1.0])
    eye = target + dist * np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    up = np.array([0.0, 0.0, 1.0]) if elevation_deg < 89 else np.array([1.0, 0.0, 0.0])
    return perspective(np.radians(30.0), (64, 64), look_at(eye, target, up))


def test_relit_layer_turns_with_the_instance_and_its_lights(ball):
    """Turning the instance, the camera and the sun by the same yaw draws the same billboard."""
    mode = LitMode(MorphSurface(), Lighting(0.2, (sun(30.0, 40.0),)), quantum_deg=0.0)
    a = mode.render(_scene(ball, 0.0), _camera(10.0, 35.0)).layer
    mode.lighting = Lighting(0.2, (sun(30.0 + 90.0, 40.0),))
    b = mode.render(_scene(ball, 90.0), _camera(100.0, 35.0)).layer
    assert a[..., 3].sum() > 100
    assert np.abs(a - b).max() < 1e-4


def test_the_sun_moves_without_new_surfaces(ball):
    """The cache keys hold the direction only: a new sun re-shades the cached surface."""
    mode = LitMode(MorphSurface(), Lighting(0.2, (sun(0.0, 60.0),)))
    scene, cam = _scene(ball), _camera(20.0, 30.0)
    f1 = mode.render(scene, cam)
    mode.lighting = Lighting(0.2, (sun(180.0, 20.0),))
    f2 = mode.render(scene, cam)
    assert (f1.stats.misses, f2.stats.misses, f2.stats.hits) == (1, 0, 1)
    assert np.abs(f1.layer - f2.layer).max() > 0.05  # lit from the other side


def test_a_sun_below_the_horizon_lights_nothing(ball):
    scene, cam = _scene(ball), _camera(20.0, 30.0)
    dark = LitMode(MorphSurface(), Lighting(0.3, (sun(40.0, -5.0),))).render(scene, cam).layer
    ambient = LitMode(MorphSurface(), Lighting(0.3, ())).render(scene, cam).layer
    assert np.array_equal(dark, ambient)


def test_a_sun_behind_the_camera_lights_the_visible_side_most(ball):
    """Sun exactly behind the camera: the billboard's centre (normal towards the eye) gets
    the full sun, ambient + 3/pi of the albedo in linear light; it is brighter than with the
    sun behind the billboard."""
    scene, cam = _scene(ball), _camera(20.0, 30.0)
    front = LitMode(MorphSurface(), Lighting(0.2, (sun(20.0, 30.0),)), quantum_deg=0.0).render(scene, cam)
    back = LitMode(MorphSurface(), Lighting(0.2, (sun(200.0, -30.0 + 60.0),)), quantum_deg=0.0
                   ).render(scene, cam)
    c = front.layer[30:34, 30:34, :3].mean()
    assert c > back.layer[30:34, 30:34, :3].mean() + 0.1


def test_point_lights_use_the_surface_points(ball):
    scene, cam = _scene(ball), _camera(0.0, 10.0)
    near = LitMode(MorphSurface(), Lighting(0.0, (PointLight(np.array([2.0, 0.0, 1.0]), 30.0),)),
                   quantum_deg=0.0).render(scene, cam)
    assert near.layer[..., :3].max() > 0.2 and np.isfinite(near.layer).all()


def test_top_down_view_draws_the_top(ball):
    frame = LitMode(MorphSurface(), Lighting(0.5, ())).render(_scene(ball), _camera(0.0, 90.0))
    assert frame.stats.n_drawn == 1 and frame.layer[..., 3].sum() > 100


@pytest.mark.parametrize("choice", [MorphSurface(), NearestSurface(), CrossfadeSurface(), ClassicSurface()])
def test_every_choice_draws(ball, choice):
    frame = LitMode(choice, Lighting(0.4, (sun(10.0, 50.0),))).render(_scene(ball), _camera(33.0, 47.0))
    assert frame.stats.n_drawn == 1 and frame.layer[..., 3].sum() > 100
    assert frame.stats.mode == choice.name


def test_axial_scenes_and_bad_arguments_are_refused(ball):
    with pytest.raises(ValidationError, match="ViewpointFacing"):
        LitMode().render(_scene(ball, facing=AxialFacing()), _camera(0.0, 20.0))
    with pytest.raises(ValidationError, match="SurfaceChoice"):
        LitMode("morph")  # type: ignore[arg-type]
    with pytest.raises(ValidationError, match="Lighting"):
        LitMode(lighting=0.3)  # type: ignore[arg-type]
    with pytest.raises(ValidationError, match="quantum_deg"):
        LitMode(quantum_deg=-1.0)


def test_pack_round_trip(ball):
    s = ball.surface(12.0, 34.0)
    back = unpack_surface(pack_surface(s))
    assert np.array_equal(back.albedo, s.albedo) and np.array_equal(back.depth, s.depth)


def test_relit_billboards_take_the_fog_of_the_ground_and_the_meshes(ball):
    """One fog model (backdrop.Fog.blend, on the encoded colour): a relit billboard's fogged
    layer is its clear layer blended by its placement's fog factor, as the meshes are."""
    from morphkit.billboard import Fog

    fog = Fog(density=0.08)
    mode = LitMode(MorphSurface(), Lighting(0.2, (sun(30.0, 40.0),)), quantum_deg=0.0)
    cam = _camera(10.0, 35.0)
    clear = mode.render(_scene(ball), cam).layer
    foggy_scene = _scene(ball)
    foggy_scene.backdrop = Backdrop(fog=fog)
    foggy = mode.render(foggy_scene, cam)
    f = foggy.placements[0].fog
    assert 0.3 < f < 0.9 and clear[..., 3].sum() > 100
    want = fog.blend(clear[..., :3].copy(), clear[..., 3:], f)
    np.testing.assert_allclose(foggy.layer[..., :3], want, atol=1e-5)
    np.testing.assert_array_equal(foggy.layer[..., 3], clear[..., 3])


def _ray_sphere_depth(camera, centre, radius):
    """Camera depth of the sphere ``(centre, radius)`` (world frame) at each pixel, inf off it."""
    o, d = camera.rays()
    oc = o - centre
    b = np.einsum("ijk,ijk->ij", d, oc)
    disc = b * b - (np.einsum("ijk,ijk->ij", oc, oc) - radius**2)
    t = np.where(disc > 0, -b - np.sqrt(np.maximum(disc, 0.0)), np.inf)
    return t * (d @ camera.cam2world[:3, 2])


def test_interpenetrating_instances_are_composited_per_pixel(ball):
    """Two spheres that interpenetrate: A's pivot is nearer, so back to front draws A over B,
    but B (larger) reaches out in front of A over part of the overlap. Each instance is rendered alone
    (its layer) and the truth of the pair takes, per pixel, the layer of the sphere the
    pixel's ray meets first (analytic ray cast). The pair's frame must match it there."""
    from morphkit.billboard.analytic import SPHERE_PIVOT, SPHERE_RADIUS

    mode = LitMode(MorphSurface(), Lighting(0.3, (sun(30.0, 50.0),)), quantum_deg=0.0)
    cam = _camera(0.0, 10.0)  # looking along -x
    xy = np.array([[0.0, 0.0], [-0.3, 0.3]])  # B: 0.3 further along the view, 0.3 aside
    scale = np.array([1.0, 1.4])

    def scene(idx):
        inst = Instances(("ball",), np.zeros(len(idx), np.int64), xy[idx], np.zeros(len(idx)), scale[idx])
        return BillboardScene({"ball": ball}, inst, backdrop=Backdrop(), facing=ViewpointFacing())

    pair = mode.render(scene([0, 1]), cam)
    assert [p.index for p in pair.placements] == [1, 0]  # B first: its pivot is farther
    alone = [mode.render(scene([k]), cam).layer for k in (0, 1)]
    za, zb = (_ray_sphere_depth(cam, np.r_[xy[k], 0.0] + scale[k] * SPHERE_PIVOT, scale[k] * SPHERE_RADIUS)
              for k in (0, 1))
    both = (alone[0][..., 3] > 0.99) & (alone[1][..., 3] > 0.99)
    b_front = both & (zb < za - 0.05)  # B clearly nearer
    a_front = both & (za < zb - 0.05)
    assert b_front.sum() > 15 and a_front.sum() > 15
    # where B is in front the pair shows B's layer, where A is, A's (the morph's depth against
    # the analytic one: a pixel of 8-bit colour)
    np.testing.assert_allclose(pair.layer[b_front], alone[1][b_front], atol=1.5 / 255)
    np.testing.assert_allclose(pair.layer[a_front], alone[0][a_front], atol=1.5 / 255)
