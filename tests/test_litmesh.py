"""The relit ground truth (LitMeshMode): GL renders, tiny sizes."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from billboard_fakes import FakeAsset

from morphkit.billboard import Backdrop, BillboardScene, Fog, Ground, Instances, MeshMode, Sky
from morphkit.billboard.frames.compositor import finish
from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.imaging.shading import Lighting, shade_passes
from morphkit.scene import Item, PointLight
from morphkit.sunlit.litmesh import LitMeshMode
from morphkit.sunpath import sun

pytestmark = pytest.mark.gl

FLAT = Backdrop(Ground(cell=None), Sky((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))
COLOR = (0.2, 0.4, 0.8)


def _srgb(x: float) -> float:
    return min(x, 1.0) ** (1 / 2.2)  # the model's output encoding (morphkit.imaging.shading)


def _panel():
    """A thin 0.6 x 0.8 panel standing on the ground facing +x (the fake asset's quad)."""
    m = trimesh.creation.box((0.002, 0.6, 0.8))
    m.apply_translation([0, 0, 0.4])
    return m


def _scene(backdrop=FLAT):
    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1)
    inst = Instances.from_records([("solid", 0.0, 0.0), ("solid", 0.0, 1.5, 0.0, 0.7)])
    scene = BillboardScene({"solid": asset}, inst, backdrop=backdrop)
    cam = perspective(np.radians(40), (60, 80), look_at([3.5, 0.75, 0.4], [0, 0.75, 0.4]), znear=0.1)
    return scene, cam


def test_lit_mesh_mode_is_the_shading_of_the_renderers_passes(renderer):
    scene, cam = _scene()
    meshes = {"solid": [Item(_panel(), color=COLOR)]}
    lighting = Lighting(0.3, (sun(0.0, 40.0, 2.0), PointLight([2.0, 0.0, 1.0], 5.0)))
    mode = LitMeshMode(renderer, meshes, lighting)
    frame = scene.render(cam, mode)
    assert frame.stats.mode == "litmesh" and frame.stats.n_drawn == 2
    items = MeshMode(renderer, meshes).items(scene, scene.plan(cam).visible)
    want = shade_passes(renderer.passes(cam, items, ()), lighting, cam)
    np.testing.assert_array_equal(frame.layer, want)
    np.testing.assert_array_equal(frame.rgb, finish(want, FLAT.draw(cam)))
    assert (frame.layer[..., 3] > 0).sum() > 300


def test_a_sun_in_front_lights_the_panel_as_the_equation_says(renderer):
    scene, cam = _scene()
    mode = LitMeshMode(renderer, {"solid": [Item(_panel(), color=COLOR)]}, Lighting(0.3, (sun(0.0, 40.0),)))
    px, _ = cam.project(np.array([[0.001, 0.0, 0.4]]))  # the centre of the first panel's front
    x, y = np.rint(px[0]).astype(int)
    lit = scene.render(cam, mode).layer[y, x]
    # normal +x, sun from +x at 40 degrees: n . l = cos 40; albedo through an 8-bit sRGB pass (~1/255)
    want = [_srgb(c * (0.3 + 3.0 * np.cos(np.radians(40)) / np.pi)) for c in COLOR]
    np.testing.assert_allclose(lit[:3], want, atol=2.5 / 255)
    assert lit[3] == 1.0
    # the sun replaced per frame: below the horizon, ambient only
    mode.lighting = Lighting(0.3, (sun(0.0, -3.0),))
    dark = scene.render(cam, mode).layer[y, x]
    np.testing.assert_allclose(dark[:3], [_srgb(c * 0.3) for c in COLOR], atol=2.5 / 255)
    # behind the panel: ambient only on the side facing the camera
    mode.lighting = Lighting(0.3, (sun(180.0, 20.0),))
    np.testing.assert_allclose(scene.render(cam, mode).layer[y, x], dark, atol=1e-6)


def test_supersampled_passes_give_coverage_alpha_and_fog_applies(renderer):
    scene, cam = _scene(Backdrop(Ground(cell=None), Sky((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)),
                                 Fog(color=(1.0, 0.0, 0.0), density=0.3)))
    meshes = {"solid": [Item(_panel(), color=COLOR)]}
    fogged = scene.render(cam, LitMeshMode(renderer, meshes, Lighting(0.3, (sun(0.0, 40.0),)), supersample=2))
    a = fogged.layer[..., 3]
    assert ((a > 0) & (a < 1)).any()  # edge pixels partly covered
    clear_scene, _ = _scene()
    clear = clear_scene.render(cam, LitMeshMode(renderer, meshes, Lighting(0.3, (sun(0.0, 40.0),)),
                                                supersample=2))
    inside = a == 1.0
    assert inside.sum() > 100
    # red fog: more red, less blue where the panel is drawn
    assert (fogged.layer[..., 0][inside] > clear.layer[..., 0][inside] + 0.05).all()
    assert (fogged.layer[..., 2][inside] < clear.layer[..., 2][inside]).all()


def test_lit_mesh_mode_refuses_what_it_cannot_use(renderer):
    scene, cam = _scene()
    meshes = {"solid": [Item(_panel())]}
    with pytest.raises(ValidationError, match="renderer: expected a renderer with passes and source_passes"):
        LitMeshMode(object(), meshes, Lighting(0.3))
    with pytest.raises(ValidationError, match="supersample: expected an integer >= 1"):
        LitMeshMode(renderer, meshes, Lighting(0.3), supersample=0)
    mode = LitMeshMode(renderer, meshes, Lighting(0.3))
    mode.lighting = [sun(0.0, 30.0)]
    with pytest.raises(ValidationError, match="lighting: expected a morphkit.imaging.shading.Lighting"):
        scene.render(cam, mode)
