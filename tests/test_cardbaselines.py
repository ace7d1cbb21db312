"""The impostor-card baselines of a field's shadow: light-facing alpha-tested cards in the light view."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from morphkit.billboard.frames.instances import Instances
from morphkit.errors import ValidationError
from morphkit.imaging.metrics import shadow_iou
from morphkit.sunlit.cardbaselines import card_field_map, nearest_frame
from morphkit.sunlit.fieldbaselines import ray_cast_field
from morphkit.sunlit.fieldshadow import FieldShadow
from morphkit.sunlit.sunatlas import bake_sun_atlas, sun_direction

pytestmark = pytest.mark.gl

RECT = (-3.0, -3.0, 3.0, 3.0)
#: A wall: wide along object x, thin along y; its face is seen from azimuth +-90.
WALL = trimesh.creation.box(extents=(1.0, 0.08, 0.6))


@pytest.fixture(scope="module")
def kit(renderer):
    from morphkit.billboard.impostor import bake_impostor

    imp = bake_impostor(WALL, renderer, name="wall", frames=9, frame_size=48, levels=1, supersample=1)
    atlas = bake_sun_atlas(WALL, renderer, size=48)
    tpu = 48 / (2.0 * atlas.cameras.half_extent[0])
    return {"wall": imp}, FieldShadow({"wall": atlas}), tpu


def _grid(n: int = 160) -> np.ndarray:
    X, Y = np.meshgrid(np.linspace(RECT[0], RECT[2], n), np.linspace(RECT[1], RECT[3], n))
    return np.stack([X, Y, np.zeros_like(X)], -1).reshape(-1, 3)


def _shadow(kit, sun, image, eye=None, inst=None):
    imps, fs, tpu = kit
    inst = Instances.from_records([("wall", 0.0, 0.0, 0.0)]) if inst is None else inst
    fm = card_field_map(fs, imps, inst, sun, tpu, RECT, image=image, camera_position=eye)
    return fm.visibility(_grid()) < 0.5


def test_the_nearest_frame_of_a_frame_direction_is_that_frame(kit):
    imp = kit[0]["wall"]
    for k in (0, 17, 40, 80):
        assert nearest_frame(imp, 3.0 * imp.frame_dirs[k]) == k
    with pytest.raises(ValidationError, match="non-zero direction"):
        nearest_frame(imp, np.zeros(3))


def test_the_light_card_casts_about_the_true_shadow(kit):
    sun = sun_direction(-60.0, 50.0)
    inst = Instances.from_records([("wall", 0.0, 0.0, 20.0), ("wall", 1.5, -1.0, 110.0, 0.8)])
    truth = ray_cast_field({"wall": WALL}, inst, sun, _grid()) < 0.5
    got = _shadow(kit, sun, "light", inst=inst)
    assert truth.sum() > 300
    assert shadow_iou(got, truth) > 0.8


def test_the_camera_card_turns_with_the_camera_the_light_card_does_not(kit):
    sun = sun_direction(0.0, 45.0)  # the light along the wall's length: a thin true shadow
    truth = ray_cast_field({"wall": WALL}, Instances.from_records([("wall", 0.0, 0.0)]), sun, _grid()) < 0.5
    face = _shadow(kit, sun, "camera", eye=np.array([0.0, -20.0, 3.0]))   # the camera sees the face
    edge = _shadow(kit, sun, "camera", eye=np.array([-20.0, 0.0, 3.0]))   # and the edge
    assert face.sum() > 4 * edge.sum()  # the card-shaped shadow follows the camera's silhouette
    assert face.sum() > 4 * truth.sum()
    light_a = _shadow(kit, sun, "light", eye=np.array([0.0, -20.0, 3.0]))
    light_b = _shadow(kit, sun, "light", eye=np.array([-20.0, 0.0, 3.0]))
    np.testing.assert_array_equal(light_a, light_b)
    assert shadow_iou(light_a, truth) > shadow_iou(face, truth) + 0.3


def test_no_card_casts_with_the_sun_below_the_horizon_or_without_instances(kit):
    imps, fs, tpu = kit
    below = card_field_map(fs, imps, Instances.from_records([("wall", 0.0, 0.0)]), sun_direction(30.0, -2.0),
                           tpu, RECT)
    assert below.camera is None and (below.visibility(_grid(8)) == 1.0).all()
    empty = Instances(("wall",), np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0), np.ones(0))
    assert card_field_map(fs, imps, empty, sun_direction(0.0, 40.0), tpu, RECT).camera is None


def test_bad_arguments_raise(kit):
    imps, fs, tpu = kit
    inst = Instances.from_records([("wall", 0.0, 0.0)])
    sun = sun_direction(0.0, 40.0)
    with pytest.raises(ValidationError, match="image"):
        card_field_map(fs, imps, inst, sun, tpu, RECT, image="top")
    with pytest.raises(ValidationError, match="camera_position"):
        card_field_map(fs, imps, inst, sun, tpu, RECT, image="camera")
    with pytest.raises(ValidationError, match="none for"):
        card_field_map(fs, {}, inst, sun, tpu, RECT)
