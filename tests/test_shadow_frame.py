"""The frame compositor: self-shadowing vs the paper's receiver-only mode (GL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.camera import look_at, perspective
from morphkit.errors import ValidationError
from morphkit.scene import DirectionalLight, Receiver, Scene, SceneObject, translation
from morphkit.shadow import MotionRange, bake_atlas, shadow_visibility
from morphkit.shadow.frame import render_frame

pytestmark = pytest.mark.gl


@pytest.fixture(scope="module")
def setup(renderer):
    """An L-shaped object: a tall block whose top overhangs a step, lit from above
    so the overhang shadows the object's own lower step (self-shadowing)."""
    step = trimesh.creation.box((0.6, 0.4, 0.2))
    step.apply_translation([0.0, 0.0, 0.1])
    tower = trimesh.creation.box((0.2, 0.4, 0.8))
    tower.apply_translation([-0.2, 0.0, 0.4])
    roof = trimesh.creation.box((0.6, 0.4, 0.1))
    roof.apply_translation([0.0, 0.0, 0.85])
    mesh = trimesh.util.concatenate([step, tower, roof])
    light = DirectionalLight([0.4, 0.2, -1.0])
    atlas = bake_atlas(mesh, np.eye(4), MotionRange([-0.2, -0.2], [0.2, 0.2]), light, (192, 192),
                       renderer=renderer, progress=False)
    cam = perspective(np.deg2rad(40), (96, 96), look_at([1.6, -1.8, 1.2], [0.0, 0.0, 0.4]),
                      znear=0.1, zfar=10)
    scene = Scene(SceneObject(mesh, translation(0.0, 0.0)), light, cam, Receiver(1.5))
    depth, lcam = atlas.shadow_map(np.zeros(2))
    return scene, depth, lcam


def _vis(depth, lcam):
    return lambda p, n: shadow_visibility(p, depth, lcam, normals=n)


def test_self_shadowing_darkens_the_object(renderer, setup):
    from morphkit.scene import Item

    scene, depth, lcam = setup
    full = render_frame(renderer, scene, _vis(depth, lcam))
    recv = render_frame(renderer, scene, _vis(depth, lcam), receiver_only=True)
    obj = np.isfinite(renderer.depth(scene.camera, [Item(scene.obj.mesh, scene.obj.pose)]))
    on_object = obj  # the object is in front of the receivers everywhere it is seen
    # self-shadow: the roof shadows the step's top, seen by the camera
    assert (full["visibility"][on_object] == 0).sum() > 20
    # receiver-only (the paper's mode): the object is never shadowed ...
    assert np.all(recv["visibility"][on_object] == 1)
    # ... and the ground shadow is the same in both modes
    ground = ~obj & np.isfinite(full["depth"])
    np.testing.assert_array_equal(full["visibility"][ground], recv["visibility"][ground])
    assert (full["visibility"][ground] == 0).sum() > 50
    # shaded = unlit where visibility is 0, lit where 1
    z = full["visibility"] == 0
    np.testing.assert_array_equal(full["shaded"][z], full["unlit"][z])


@pytest.mark.parametrize("visibility, match", [
    (lambda p, n: np.ones(len(p) - 1, np.float32),
     r"visibility\(points, normals\): expected \(\d+,\) values in \[0, 1\], got shape \(\d+,\)"),
    (lambda p, n: np.ones((len(p), 1), np.float32),
     r"visibility\(points, normals\): expected \(\d+,\) values in \[0, 1\], got shape \(\d+, 1\)"),
    (lambda p, n: np.full(len(p), np.nan), r"visibility\(points, normals\): expected .*values in \[0, 1\], "
                                          r"got \d+ values outside \[0, 1\] or NaN"),
    (lambda p, n: np.full(len(p), 2.0), r"got \d+ values outside \[0, 1\] or NaN"),
    (lambda p, n: None, r"visibility\(points, normals\): expected .*got NoneType"),
    ("not callable", r"visibility: expected a callable \(points, normals\) -> \(N,\) values, got str"),
], ids=["short", "2-d", "nan", "above-one", "none", "str"])
def test_render_frame_refuses_a_bad_visibility(renderer, setup, visibility, match):
    scene, _depth, _lcam = setup
    with pytest.raises(ValidationError, match=match):
        render_frame(renderer, scene, visibility)


def test_render_frame_refuses_what_is_not_a_scene_or_renderer(renderer, setup):
    scene, depth, lcam = setup
    with pytest.raises(ValidationError, match="scene: expected a morphkit.scene.Scene, got dict"):
        render_frame(renderer, {"camera": scene.camera}, _vis(depth, lcam))
    with pytest.raises(ValidationError, match="renderer: expected a SceneRenderer .*got str"):
        render_frame("pyrender", scene, _vis(depth, lcam))
