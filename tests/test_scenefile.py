"""JSON scene files (morphkit.scenes): what they say, read back as written, and refused clearly.

Pure data: nothing here renders (the rendering of scenes is in tests/test_render_scene.py).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from morphkit import tol
from morphkit.billboard import Instances
from morphkit.errors import FileFormatError, OutputExistsError, ValidationError
from morphkit.scenes import (
    SCHEMA_PATH,
    BakeLight,
    DaySun,
    FixedSun,
    Keyframes,
    Listed,
    NamedPath,
    Scatter,
    SceneAsset,
    SceneDescription,
    SceneShadows,
    load_scene,
    read_scene_file,
    write_scene_file,
)
from morphkit.scenes.jsonfile import scene_from_json, scene_to_json
from morphkit.scenes.placing import overlapping
from morphkit.scenes.suns import sun_from_light
from morphkit.sunpath import SunPath, sun


def _scene(**kw):
    base = dict(assets=(SceneAsset("tree", "tree"), SceneAsset("person", "person", scale=1.8)),
                instances=Scatter(30, seed=4), camera=NamedPath("flyover"), sun=DaySun(),
                shadows=SceneShadows("pcss", 256), shape=(120, 160), frames=5)
    base.update(kw)
    return SceneDescription(**base)


def test_the_schema_is_a_valid_json_schema():
    from jsonschema import Draft202012Validator

    Draft202012Validator.check_schema(json.loads(SCHEMA_PATH.read_text()))


@pytest.mark.parametrize("kw", [
    {},
    {"instances": Listed(Instances.from_records([("tree", 0, 0, 30, 1.2), ("person", 2.5, -1, 90)])),
     "camera": Keyframes([[0, -8, 1.7], [8, 0, 1.7]], [[0, 0, 1], [0, 0, 1]], yfov_deg=40.0),
     "sun": FixedSun(135.0, 35.0), "shadows": None, "views": "dome", "fog": False},
    {"sun": BakeLight(), "shadows": None, "views": 8},
    {"sun": BakeLight(), "shadows": SceneShadows(4), "views": "dome"},
    {"sun": DaySun(SunPath(azimuth_range=(-60.0, 60.0), max_elevation=45.0, rise_deg=-5.0))},
], ids=["scatter-day", "listed-keyframes-fixed", "ring-bake-light", "shadows-no-sun", "day-of-its-own"])
def test_a_scene_file_reads_back_as_written(tmp_path, kw):
    scene = _scene(**kw)
    path = write_scene_file(scene, tmp_path / "s.json")
    back = read_scene_file(path)
    assert scene_to_json(back, folder=tmp_path) == scene_to_json(scene, folder=tmp_path)
    assert json.loads(path.read_text())["morphkit_scene"] == 1
    # and what it says is what it does: the same cameras and suns
    a, b = scene.camera.cameras(3, (48, 64), 5.0), back.camera.cameras(3, (48, 64), 5.0)
    assert all(np.array_equal(x.cam2world, y.cam2world) for x, y in zip(a, b, strict=True))
    sa, sb = scene.sun.suns(3), back.sun.suns(3)
    assert (sa is None and sb is None) or all(np.array_equal(x.direction, y.direction)
                                              for x, y in zip(sa, sb, strict=True))


def test_asset_paths_inside_the_scene_folder_are_written_relative_to_it(tmp_path):
    # inside the scene file's folder: relative (the folder moves as a whole); elsewhere: absolute
    (tmp_path / "scenes" / "models").mkdir(parents=True)
    inside, outside = tmp_path / "scenes" / "models" / "crate.glb", tmp_path / "oak.glb"
    scene = _scene(assets=(SceneAsset("crate", str(inside)), SceneAsset("oak", str(outside)),
                           SceneAsset("tree", "tree")))
    path = write_scene_file(scene, tmp_path / "scenes" / "s.json")
    written = json.loads(path.read_text())["assets"]
    assert [a["source"] for a in written] == ["models/crate.glb", str(outside), "tree"]  # a sample: its name
    moved = tmp_path / "elsewhere"
    (tmp_path / "scenes").rename(moved)
    back = read_scene_file(moved / "s.json").assets
    assert [a.source for a in back] == [str(moved / "models" / "crate.glb"), str(outside), "tree"]


def test_an_existing_file_is_replaced_only_when_asked(tmp_path):
    path = tmp_path / "s.json"
    path.write_text("mine")
    with pytest.raises(OutputExistsError, match="already there"):
        write_scene_file(_scene(), path)
    assert path.read_text() == "mine"
    write_scene_file(_scene(), path, overwrite=True)
    assert read_scene_file(path).frames == 5


def _doc(**changes):
    doc = scene_to_json(_scene())
    doc.update(changes)
    return doc


@pytest.mark.parametrize(("doc", "match"), [
    (_doc(morphkit_scene=2), r"expected version 1, got version 2"),
    ({"assets": []}, r'a JSON object with "morphkit_scene"'),
    ([1, 2], r'a JSON object with "morphkit_scene", got list'),
    (_doc(frames=0), r"at \$\.frames: 0 is less than the minimum of 1"),
    (_doc(instances={"scatter": {"count": -1}}), r"at \$\.instances\.scatter\.count: -1 is less than"),
    (_doc(instances={"scatter": {"count": 3}, "listed": []}), r"at \$\.instances"),
    (_doc(sun={"azimuth_deg": 0, "elevation_deg": -3}), r"at \$\.sun\.elevation_deg: -3"),
    (_doc(camera={"path": "spiral"}), r"at \$\.camera\.path: 'spiral' is not one of"),
    (_doc(colour="red"), r"at \$: Additional properties are not allowed \('colour' was unexpected\)"),
    (_doc(assets=[{"name": "tree"}]), r"at \$\.assets\[0\]: 'source' is a required property"),
    (_doc(image={"width": 16, "height": 9000}), r"at \$\.image\.height: 9000 is greater than the maximum"),
], ids=["version", "no-version", "not-an-object", "frames", "count", "two-placements", "sun-below",
        "camera-path", "unknown-key", "asset-source", "image-height"])
def test_a_file_failing_the_schema_is_refused_naming_the_path(doc, match):
    with pytest.raises(FileFormatError, match=match):
        scene_from_json(doc, where="s.json")


@pytest.mark.parametrize(("doc", "match"), [
    (_doc(assets=[{"name": "tree", "source": "tree"}, {"name": "tree", "source": "person"}]),
     r"distinct names, got \['tree'\] more than once"),
    (_doc(instances={"listed": [{"asset": "oak", "x": 0, "y": 0}]}),
     r"the scene's assets \['tree', 'person'\], got \['oak'\]"),
    (_doc(instances={"scatter": {"count": tol.MAX_INSTANCES + 1}}), r"scatter count"),
    (_doc(frames=tol.MAX_FRAMES + 1), r"scene frames"),
    (_doc(image={"width": 8192, "height": 8192}, frames=1), None),
    (_doc(camera={"keyframes": [{"eye": [0, 0, 1], "target": [0, 0, 1]}]}), r"eye"),
    (_doc(views=8), r"scene views with a sun or shadows: expected \"dome\" or null"),
    (_doc(views=8, sun=None), r"a ring of 8 views baked under the bake light"),
], ids=["two-assets-one-name", "instance-of-no-asset", "too-many-instances", "too-many-frames",
        "largest-image", "eye-is-target", "ring-under-a-sun", "ring-with-shadows"])
def test_values_the_scene_cannot_be_are_refused_before_any_work(doc, match):
    if match is None:
        assert scene_from_json(doc).shape == (8192, 8192)  # the limit itself is a scene
        return
    with pytest.raises(ValidationError, match=match):
        scene_from_json(doc, where="s.json")


def test_a_listed_scene_too_large_is_refused_before_its_instances_are_built():
    doc = _doc(instances={"listed": [{"asset": "tree", "x": 0, "y": 0}] * (tol.MAX_INSTANCES + 1)})
    with pytest.raises(ValidationError, match=rf"listed instances.*<= {tol.MAX_INSTANCES}"):
        scene_from_json(doc)


@pytest.mark.parametrize(("content", "match"), [
    (b"{not json", r"expected JSON, got JSONDecodeError"),
    (b"\xff\xfe", r"expected JSON, got UnicodeDecodeError"),
])
def test_a_file_that_is_not_json_is_refused(tmp_path, content, match):
    path = tmp_path / "s.json"
    path.write_bytes(content)
    with pytest.raises(FileFormatError, match=match):
        load_scene(path)


def test_load_scene_tells_files_by_suffix(tmp_path):
    with pytest.raises(FileFormatError, match=r"a file ending in \.json, \.glb, \.gltf, got '\.obj'"):
        load_scene(tmp_path / "scene.obj")
    with pytest.raises(FileFormatError, match="scene file"):
        load_scene(tmp_path / "missing.json")


def test_an_empty_scene_is_a_scene():
    scene = scene_from_json(_doc(assets=[], instances={"listed": []}))
    assert scene.assets == () and len(scene.instances.first(scene.names)) == 0


def test_scatter_moves_apart_what_would_interpenetrate():
    # 200 instances of footprint 0.5 on the default field: the scatter alone overlaps some (the
    # count is what placing without moving apart says); moved apart, none stands inside another
    loose = Scatter(200, seed=0, apart=False).place(["tree"], {"tree": 0.5})
    tight = Scatter(200, seed=0).place(["tree"], {"tree": 0.5})
    assert loose.overlapping > 0 and loose.moved == 0
    assert tight.moved > 0 and tight.overlapping == 0
    assert overlapping(tight.instances, {"tree": 0.5}) == 0


def test_listed_instances_at_one_spot_are_counted_not_moved():
    inst = Instances.from_records([("tree", 1.0, 1.0), ("tree", 1.0, 1.0), ("tree", 9.0, 1.0)])
    placed = Listed(inst).place(["tree"], {"tree": 0.4})
    assert placed.moved == 0 and placed.overlapping == 2
    assert np.array_equal(placed.instances.xy, inst.xy)


def test_keyframes_pass_through_their_keys():
    cam = Keyframes([[0.0, -10.0, 2.0], [10.0, 0.0, 2.0], [0.0, 10.0, 6.0]],
                    [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    cams = cam.cameras(5, (48, 64), half_size=1.0)  # t = 0, 1/4, 1/2, 3/4, 1: keys at 0, 1/2, 1
    for k, key in ((0, 0), (2, 1), (4, 2)):
        assert np.allclose(cams[k].cam2world[:3, 3], cam.eyes[key], atol=1e-12)
    assert np.allclose(cams[1].cam2world[:3, 3], (cam.eyes[0] + cam.eyes[1]) / 2, atol=1e-12)


def test_a_light_is_the_sun_it_shines_from():
    for az, el in ((30.0, 40.0), (-120.0, 5.0), (0.0, 90.0)):
        got = sun_from_light(sun(az, el))
        assert got.elevation_deg == pytest.approx(el, abs=1e-9)
        if el < 90.0:
            assert got.azimuth_deg == pytest.approx(az, abs=1e-9)
    with pytest.raises(ValidationError, match="a sun above the horizon"):
        sun_from_light(sun(0.0, 90.0).__class__(np.array([0.0, 0.0, 1.0]), 1.0))  # shining upwards
