"""The frame that draws its camera once (issue #26): the same image as the two-render frame (GL).

``render_frame`` draws lit and unlit from one pass where the renderer is a ``FrameRenderer``
(``Renderer.frame_pass``); ``one_pass=False`` is the frame as before (lit, then unlit). The
two must agree within ``tol.FRAME_ONCE_MEAN_LEVELS`` (mean |difference| of ``shaded``, levels
of 255; why not exactly: ``morphkit.tol``), on the demo scene's meshes, a photo-textured crate,
a cut-out plant and a vertex-coloured mesh, with and without ``receiver_only``.
"""

from __future__ import annotations

import numpy as np
import pytest

from morphkit import tol
from morphkit.errors import RenderError, ValidationError
from morphkit.imaging.groundtruth import hard_visibility
from morphkit.meshes import load_mesh, sample_mesh
from morphkit.programs.fixtures import (
    DEMO_MESHES,
    demo_scene,
    write_color_ply,
    write_leaf_plant,
    write_photo_glb,
)
from morphkit.protocols import FrameRenderer, SceneRenderer
from morphkit.shadow.frame import SKY, frame_items, render_frame

pytestmark = pytest.mark.gl

SIZE = 96  # small frames: the whole module runs in a few seconds


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("frame_once")
    out = {name: sample_mesh(name) for name in DEMO_MESHES}
    out["photo_crate"] = load_mesh(write_photo_glb(folder))  # textured (its own look)
    out["leaf_plant"] = load_mesh(write_leaf_plant(folder))  # alpha-masked cards (cut-outs)
    out["color_ply"] = load_mesh(write_color_ply(folder))  # vertex colours
    return out


def _frames(renderer, scene, receiver_only=False):
    vis = lambda p, _n: hard_visibility(p, scene.light, scene.obj)  # noqa: E731 - the ray cast
    return (render_frame(renderer, scene, vis, receiver_only=receiver_only),
            render_frame(renderer, scene, vis, receiver_only=receiver_only, one_pass=False))


def _levels(a, b):
    return np.abs(a.astype(np.int16) - b.astype(np.int16))


@pytest.mark.parametrize("receiver_only", [False, True], ids=["self-shadowed", "receiver-only"])
@pytest.mark.parametrize("name", [*DEMO_MESHES, "photo_crate", "leaf_plant", "color_ply"])
def test_one_pass_frame_equals_the_two_render_frame(renderer, meshes, name, receiver_only):
    scene = demo_scene(meshes[name], SIZE)
    once, twice = _frames(renderer, scene, receiver_only)
    assert (twice["visibility"] == 0).sum() > 10  # the frame has a shadow to get right
    mean = _levels(once["shaded"], twice["shaded"]).mean()
    assert mean <= tol.FRAME_ONCE_MEAN_LEVELS, f"{name}: mean |one pass - two renders| {mean:.3f} levels"
    for key in ("lit", "unlit"):
        assert _levels(once[key], twice[key]).max() <= tol.FRAME_ONCE_COLOR_LEVELS, key
    if name in DEMO_MESHES:  # one colour: the same fragments, bit for bit
        np.testing.assert_array_equal(once["lit"], twice["lit"])
        np.testing.assert_array_equal(once["unlit"], twice["unlit"])
    drawn = np.isfinite(twice["depth"])
    np.testing.assert_array_equal(np.isfinite(once["depth"]), drawn)
    np.testing.assert_allclose(once["depth"][drawn], twice["depth"][drawn], rtol=tol.DEPTH_SAME_SURFACE_REL)
    assert (once["facing"] != twice["facing"]).mean() < 0.01


def test_receiver_only_leaves_the_object_lit_in_one_pass(renderer, meshes):
    scene = demo_scene(meshes["cow"], SIZE)
    full, _ = _frames(renderer, scene)
    recv, recv_twice = _frames(renderer, scene, receiver_only=True)
    obj_depth = renderer.depth(scene.camera, frame_items(scene)[-1:])  # the object alone
    with np.errstate(invalid="ignore"):
        obj = np.abs(obj_depth - full["depth"]) <= tol.DEPTH_SAME_SURFACE_REL * full["depth"]
    assert (full["visibility"][obj] < 1).sum() > 20  # the cow shadows itself ...
    assert np.all(recv["visibility"][obj] == 1)  # ... not in receiver-only mode
    np.testing.assert_array_equal(recv["visibility"] == 1, recv_twice["visibility"] == 1)
    ground = ~obj & np.isfinite(full["depth"])
    np.testing.assert_array_equal(recv["visibility"][ground], full["visibility"][ground])


def test_background_pixels_are_the_sky_lit_and_unshadowed(renderer, meshes):
    scene = demo_scene(meshes["chair"], SIZE)
    once, _ = _frames(renderer, scene)
    sky = ~np.isfinite(once["depth"])
    assert sky.sum() > 100  # the demo view sees the sky above the ground square
    want = np.rint(np.asarray(SKY) * 255).astype(np.uint8)
    for key in ("lit", "unlit", "shaded"):
        assert np.all(once[key][sky] == want), key
    assert np.all(once["visibility"][sky] == 1) and not once["facing"][sky].any()


def test_frame_pass_leaves_the_renderer_as_it_was(renderer, meshes):
    """Culling, draw buffers and shader choice are restored: colour and depth draws after a
    one-pass draw are those before it."""
    scene = demo_scene(meshes["photo_crate"], SIZE)
    items, cam = frame_items(scene), scene.camera
    before = renderer.color_depth(cam, items, [scene.light], ambient=scene.ambient)
    depth = renderer.depth(cam, items)
    drawn = renderer.frame_pass(cam, items, [scene.light], ambient=scene.ambient, marked=[len(items) - 1])
    assert drawn.marked.sum() > 100 and not drawn.marked[~np.isfinite(drawn.depth)].any()
    after = renderer.color_depth(cam, items, [scene.light], ambient=scene.ambient)
    np.testing.assert_array_equal(after[0], before[0])
    np.testing.assert_array_equal(after[1], before[1])
    np.testing.assert_array_equal(renderer.depth(cam, items), depth)


def test_frame_pass_refuses_a_mark_that_is_not_an_item(renderer, meshes):
    scene = demo_scene(meshes["cow"], SIZE)
    items = frame_items(scene)
    with pytest.raises(ValidationError, match=r"marked index: expected .*got 2"):
        renderer.frame_pass(scene.camera, items, [scene.light], marked=[len(items)])


def test_a_frame_pass_without_memory_for_its_framebuffers_is_a_render_error():
    from morphkit.glplatform import check_gl_memory

    check_gl_memory((SIZE, SIZE), tol.GL_FRAME_PASS_BYTES_PER_PIXEL)  # fits
    with pytest.raises(RenderError, match=r"memory for an offscreen GL context of shape \(1024, 1024\): "
                                          r"expected about 16777216 MiB"):
        check_gl_memory((1024, 1024), 1 << 24)  # 16 TiB: more than any machine here lets a process map


class _TwoDrawRenderer:
    """A SceneRenderer without frame_pass (the real renderer's three draws only)."""

    def __init__(self, inner):
        self.inner = inner

    def depth(self, camera, items):
        return self.inner.depth(camera, items)

    def color_depth(self, camera, items, lights, **kw):
        return self.inner.color_depth(camera, items, lights, **kw)

    def source_view(self, camera, items, lights, **kw):
        return self.inner.source_view(camera, items, lights, **kw)


def test_a_renderer_without_frame_pass_gets_the_two_render_frame(renderer, meshes):
    assert isinstance(renderer, FrameRenderer)
    plain = _TwoDrawRenderer(renderer)
    assert isinstance(plain, SceneRenderer) and not isinstance(plain, FrameRenderer)
    scene = demo_scene(meshes["teapot"], SIZE)
    vis = lambda p, _n: hard_visibility(p, scene.light, scene.obj)  # noqa: E731
    got = render_frame(plain, scene, vis, receiver_only=True)
    want = render_frame(renderer, scene, vis, receiver_only=True, one_pass=False)
    for key in want:
        np.testing.assert_array_equal(got[key], want[key], err_msg=key)


def test_bench_rows_time_every_frame_and_state_the_image_difference(renderer):
    from morphkit.bench.shadow_suite import frame_once_rows

    rows = frame_once_rows(renderer, faces=(6000,), size=48, repeats=1)
    assert [r["method"] for r in rows] == ["two_warp", "once_warp", "once_reproject", "once_direct",
                                           "camera_once", "camera_two"]
    assert all(r["params"]["what"] == "frame_once" and r["ms_median"] > 0 for r in rows)
    by = {r["method"]: r["metrics"] for r in rows}
    assert by["once_direct"]["vs_direct"] == 1.0
    for name in ("once_warp", "once_reproject", "once_direct"):
        assert 0 <= by[name]["mean_levels"] <= tol.FRAME_ONCE_MEAN_LEVELS
