"""The one-draw G-buffer (issue #26): ``Renderer.gbuffer_pass`` against the three-draw passes (GL).

``gbuffer_pass`` draws albedo, encoded normals and depth in one flat draw into two colour
attachments; ``passes`` draws the lit colour, then albedo, then normals. On a textured, a
vertex-coloured, a cut-out and a one-colour mesh: coverage identical, albedo within
``tol.GBUFFER_ALBEDO_LEVELS``, normals within twice ``conventions.NORMAL_ENCODING_DEG`` (each
encoding is within it of the true normal), depth within
``tol.DEPTH_SAME_SURFACE_REL`` (a framebuffer object's depth rounds differently from OSMesa's
buffer, by one or two steps of 24 bits: not bit-identical). ``LitMeshMode`` shades from either
within ``tol.GBUFFER_FRAME_MEAN_LEVELS`` (mean |difference| of the frame's ``rgb``, levels of 255).
"""

from __future__ import annotations

import numpy as np
import pytest
from billboard_fakes import FakeAsset

from morphkit import tol
from morphkit.billboard import Backdrop, BillboardScene, Ground, Instances, Sky
from morphkit.camera import look_at, perspective
from morphkit.conventions import NORMAL_ENCODING_DEG
from morphkit.errors import ValidationError
from morphkit.imaging.shading import Lighting
from morphkit.meshes import load_mesh, sample_mesh
from morphkit.programs.fixtures import demo_scene, write_color_ply, write_leaf_plant, write_photo_glb
from morphkit.protocols import GBufferRenderer, PassRenderer
from morphkit.scene import Item
from morphkit.shadow.frame import frame_items
from morphkit.sunlit.litmesh import LitMeshMode
from morphkit.sunlit.raycast import RayCastShadow
from morphkit.sunpath import sun

pytestmark = pytest.mark.gl

SIZE = 96
NAMES = ["photo_crate", "color_ply", "leaf_plant", "teapot"]  # textured, vertex colours, cut-out, one colour


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("gbuffer")
    return {"photo_crate": load_mesh(write_photo_glb(folder)),
            "color_ply": load_mesh(write_color_ply(folder)),
            "leaf_plant": load_mesh(write_leaf_plant(folder)), "teapot": sample_mesh("teapot")}


def _degrees(a, b):
    return np.degrees(np.arccos(np.clip(np.einsum("ijk,ijk->ij", a, b), -1.0, 1.0)))


@pytest.mark.parametrize("name", NAMES)
def test_the_one_draw_gbuffer_equals_the_three_draw_passes(renderer, meshes, name):
    scene = demo_scene(meshes[name], SIZE)
    items, cam = frame_items(scene), scene.camera
    three = renderer.passes(cam, items, [scene.light], ambient=scene.ambient)
    one = renderer.gbuffer_pass(cam, items)
    drawn = three.alpha > 0
    assert drawn.sum() > 1000 and (~drawn).sum() > 100  # the mesh and ground, and some sky
    np.testing.assert_array_equal(one.alpha, three.alpha)
    np.testing.assert_array_equal(np.isfinite(one.depth), drawn)
    np.testing.assert_allclose(one.depth[drawn], three.depth[drawn], rtol=tol.DEPTH_SAME_SURFACE_REL)
    levels = np.abs(one.albedo.astype(np.int16) - three.albedo.astype(np.int16))
    assert levels.max() <= tol.GBUFFER_ALBEDO_LEVELS, f"{name}: albedo {levels.max()} levels apart"
    assert not one.albedo[~drawn].any() and not one.normal[~drawn].any()
    # each encoding is within NORMAL_ENCODING_DEG of the true normal (and rounds alike but for one level)
    assert _degrees(one.normal, three.normal)[drawn].max() <= 2 * NORMAL_ENCODING_DEG
    np.testing.assert_allclose(np.linalg.norm(one.normal[drawn], axis=-1), 1.0, atol=1e-5)
    assert one.color is one.albedo  # no lit colour is drawn
    assert len(np.unique(one.albedo[drawn].reshape(-1, 3), axis=0)) > 1  # not one flat colour


def test_gbuffer_pass_leaves_the_renderer_as_it_was(renderer, meshes):
    """Shader choice and draw buffers are restored: the three draws after a G-buffer are those before."""
    scene = demo_scene(meshes["photo_crate"], SIZE)
    items, cam = frame_items(scene), scene.camera
    before = renderer.passes(cam, items, [scene.light], ambient=scene.ambient)
    renderer.gbuffer_pass(cam, items)
    after = renderer.passes(cam, items, [scene.light], ambient=scene.ambient)
    for key in ("color", "albedo", "normal", "depth", "alpha"):
        np.testing.assert_array_equal(getattr(after, key), getattr(before, key), err_msg=key)


class _Recorder:
    """A renderer that delegates to the real one and records which passes it was asked for;
    ``gbuffer`` False: without ``gbuffer_pass`` (a PassRenderer only)."""

    def __init__(self, inner, calls):
        self.inner, self.calls = inner, calls

    def depth(self, camera, items):
        return self.inner.depth(camera, items)

    def color_depth(self, camera, items, lights, **kw):
        return self.inner.color_depth(camera, items, lights, **kw)

    def source_view(self, camera, items, lights, **kw):
        return self.inner.source_view(camera, items, lights, **kw)

    def passes(self, camera, items, lights, **kw):
        self.calls.append("passes")
        return self.inner.passes(camera, items, lights, **kw)

    def source_passes(self, camera, items, lights, **kw):
        self.calls.append("source_passes")
        return self.inner.source_passes(camera, items, lights, **kw)


class _GBufferRecorder(_Recorder):
    def gbuffer_pass(self, camera, items):
        self.calls.append("gbuffer_pass")
        return self.inner.gbuffer_pass(camera, items)


def _fit(mesh, height=0.8):
    """A copy standing on the ground at the origin, ``height`` tall."""
    m = mesh.copy()
    lo, hi = m.bounds
    m.apply_translation([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
    m.apply_scale(height / (hi[2] - lo[2]))
    return m


def _billboard_scene():
    backdrop = Backdrop(Ground(cell=None), Sky((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))
    asset = FakeAsset("solid", solid=True, size=(64, 48), levels=1)
    inst = Instances.from_records([("solid", 0.0, 0.0), ("solid", 0.0, 1.5, 0.0, 0.7)])
    cam = perspective(np.radians(35), (90, 120), look_at([3.0, 0.75, 0.6], [0, 0.75, 0.3]), znear=0.1)
    return BillboardScene({"solid": asset}, inst, backdrop=backdrop), cam


@pytest.mark.parametrize("shadowed", [False, True], ids=["unshadowed", "ray-cast-shadow"])
@pytest.mark.parametrize("name", NAMES[:3])
def test_lit_mesh_mode_shades_the_one_draw_gbuffer_as_the_three_draw_passes(renderer, meshes, name, shadowed):
    scene, cam = _billboard_scene()
    mesh = _fit(meshes[name])
    lighting = Lighting(0.3, (sun(30.0, 40.0, 2.0),))
    shadow = RayCastShadow({"solid": mesh}) if shadowed else None
    calls: list[str] = []
    one, three = _GBufferRecorder(renderer, calls), _Recorder(renderer, calls)
    assert isinstance(one, GBufferRenderer) and isinstance(three, PassRenderer)
    assert not isinstance(three, GBufferRenderer)
    frames = [LitMeshMode(r, {"solid": [Item(mesh)]}, lighting, shadow=shadow, gbuffer=g).render(scene, cam)
              for r, g in ((one, True), (one, False), (three, True))]
    assert calls == ["gbuffer_pass", "passes", "passes"]  # one draw only where asked and possible
    np.testing.assert_array_equal(frames[2].rgb, frames[1].rgb)
    covered = frames[0].layer[..., 3] > 0
    assert covered.sum() > 500
    np.testing.assert_array_equal(covered, frames[1].layer[..., 3] > 0)
    diff = np.abs(frames[0].rgb.astype(np.int16) - frames[1].rgb.astype(np.int16))
    assert diff.mean() <= tol.GBUFFER_FRAME_MEAN_LEVELS, f"{name}: mean {diff.mean():.3f} levels"


def test_lit_mesh_mode_keeps_supersampled_passes_and_refuses_a_bad_gbuffer_flag(renderer, meshes):
    scene, cam = _billboard_scene()
    calls: list[str] = []
    mode = LitMeshMode(_GBufferRecorder(renderer, calls), {"solid": [Item(_fit(meshes["teapot"]))]},
                       Lighting(0.3, (sun(30.0, 40.0),)), supersample=2)
    mode.render(scene, cam)
    assert calls == ["source_passes"]
    with pytest.raises(ValidationError, match=r"gbuffer: expected"):
        LitMeshMode(renderer, {"solid": [Item(_fit(meshes["teapot"]))]}, Lighting(0.3, ()), gbuffer="yes")
