"""``morphkit render SCENE`` and ``billboards --save-scene``: a scene file draws what it says.

Small scenes (ring views of 32 px, frames of 64 x 48) so that each run bakes in a second or two.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from morphkit.cli import main
from morphkit.files.fileio import read_image
from morphkit.files.outfolder import RENDER_OUTPUT, claim_output
from morphkit.programs.scenerender import render_scene
from morphkit.scenes import SceneShadows, load_scene
from morphkit.scenes.gltfscene import read_gltf_scene

pytestmark = pytest.mark.gl

SMALL = ["--n", "6", "--frames", "2", "--size", "64x48", "--views", "2", "--asset-size", "32"]


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("morphkit: error: "), err
    return err[0]


def _frames(folder):
    return [read_image(p) for p in sorted((folder / "frames").glob("frame_*.png"))]


def _scene_doc(**kw):
    doc = {
        "morphkit_scene": 1,
        "assets": [{"name": "tree", "source": "tree"}],
        "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 0.0}]},
        "camera": {"keyframes": [{"eye": [0.0, -6.0, 0.6], "target": [0.0, 0.0, 0.5]}]},
        "image": {"width": 64, "height": 48},
        "frames": 1,
        "views": 2,
        "asset_size": 32,
        "fog": False,
    }
    doc.update(kw)
    return doc


def _write(tmp_path, doc, name="s.json"):
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize(
    "extra", [[], ["--views", "dome", "--shadows", "--sun-atlas-size", "32"]], ids=["ring", "dome-shadows"]
)
def test_a_saved_scene_renders_as_the_command_did(tmp_path, capsys, extra):
    args = ["billboards", "--asset", "tree", *SMALL, *extra]
    if "--views" in extra:  # the second --views wins: dome
        args = ["billboards", "--asset", "tree", *SMALL[:6], "--asset-size", "32", *extra]
    scene = tmp_path / "scene.json"
    assert main([*args, "--save-scene", str(scene)]) == 0
    assert "nothing rendered" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.json"]  # no folder, no frame
    assert main([*args, "-o", str(tmp_path / "bb")]) == 0
    assert main(["render", str(scene), "-o", str(tmp_path / "r")]) == 0
    a, b = _frames(tmp_path / "bb"), _frames(tmp_path / "r")
    assert len(a) == len(b) == 2 and all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    bb = json.loads((tmp_path / "bb" / "billboards.json").read_text())
    rs = json.loads((tmp_path / "r" / "render.json").read_text())
    assert [c["errors"] for c in bb["compared"]] == [c["errors"] for c in rs["compared"]]
    assert rs["morphkit_render"] == 1 and rs["assets"] == [
        {"name": "tree", "source": "tree", "instances": 6, "scale": 1.0}
    ]
    assert sorted(p.name for p in (tmp_path / "r").iterdir()) == sorted(
        [
            "frames",
            "render.webm",
            "render.json",
            "compare_0000.png",
            "compare_0001.png",
            ".morphkit-output.json",
        ]
    )


def test_save_scene_replaces_a_file_only_when_asked(tmp_path, capsys):
    scene = tmp_path / "scene.json"
    scene.write_text("mine")
    assert main(["billboards", *SMALL, "--save-scene", str(scene)]) == 2
    assert "already there" in _one_error_line(capsys) and scene.read_text() == "mine"
    assert main(["billboards", *SMALL, "--save-scene", str(scene), "--overwrite"]) == 0
    assert load_scene(scene).frames == 2


def test_billboards_without_an_output_says_what_it_needs(capsys):
    assert main(["billboards", *SMALL]) == 2
    assert "-o/--out" in _one_error_line(capsys)


def _height_px(frame, backdrop):
    rows = np.flatnonzero(np.any(np.abs(frame.astype(int) - backdrop.astype(int)).sum(axis=2) > 30, axis=1))
    return int(rows.max() - rows.min() + 1) if len(rows) else 0


def test_an_assets_scale_is_its_size_in_the_frame(tmp_path):
    # one tree 3 units in front of a still camera: twice the asset's scale, twice its image height
    # (a pinhole's image size is proportional to the object's, at one distance; the camera at about
    # mid-height of both sees the top and the foot at about the same distance)
    backdrop = None
    heights = {}
    big = {"width": 128, "height": 96}
    near = {"keyframes": [{"eye": [0.0, -3.0, 0.4], "target": [0.0, 0.0, 0.4]}]}
    for scale in (0.5, 1.0):
        doc = _scene_doc(assets=[{"name": "tree", "source": "tree", "scale": scale}], image=big, camera=near)
        assert (
            main(["render", str(_write(tmp_path, doc, f"{scale}.json")), "-o", str(tmp_path / f"r{scale}")])
            == 0
        )
        if backdrop is None:
            empty = _scene_doc(instances={"listed": []}, image=big, camera=near)
            assert (
                main(["render", str(_write(tmp_path, empty, "empty.json")), "-o", str(tmp_path / "e")]) == 0
            )
            (backdrop,) = _frames(tmp_path / "e")
        (frame,) = _frames(tmp_path / f"r{scale}")
        heights[scale] = _height_px(frame, backdrop)
    assert heights[0.5] > 10  # 0.5 units 3 away under a focal length of 103 px: about 17 px
    assert heights[1.0] / heights[0.5] == pytest.approx(2.0, rel=0.15)  # a pixel's rounding at either end


def test_the_village_renders_as_its_assets_at_their_sizes_lit_by_its_light_seen_by_its_camera(tmp_path):
    from pathlib import Path

    from morphkit.meshes import sample_file  # noqa: F401 -- the village is a sample of the repo

    village = Path(__file__).resolve().parent.parent / "samples" / "scenes" / "village.glb"
    g = read_gltf_scene(village)
    scene = load_scene(village)
    # the file's own sizes: each instance's scale times its asset's is the node's size in the file
    inst = scene.instances.instances
    size = np.array([scene.asset(nm).scale for nm in inst.names])[inst.asset]
    assert np.allclose(inst.scale * size, g.instances.scale, rtol=1e-12)
    assert {a.name: a.scale for a in scene.assets} == {a.name: a.scale for a in g.assets}
    # its light is the sun: the direction towards the sun is the light's reversed
    assert np.allclose(scene.sun.suns(1)[0].direction, g.sun.direction, atol=1e-9)
    small = dataclasses.replace(
        scene, shape=(96, 160), asset_size=32, shadows=SceneShadows(sun_atlas_size=32)
    )
    summary = render_scene(small, claim_output(tmp_path / "v", RENDER_OUTPUT))
    assert [(a["name"], a["instances"], a["scale"]) for a in summary["assets"]] == [
        (a.name, int(np.count_nonzero(g.instances.asset == k)), a.scale) for k, a in enumerate(g.assets)
    ]
    # seen by its camera: the frame's camera is the file's (its pose, its field of view)
    cam = small.camera.cameras(1, small.shape, 1.0)[0]
    want = g.camera.model(small.shape)
    assert np.allclose(cam.cam2world[:3, 3], want.cam2world[:3, 3]) and np.isclose(cam.fy, want.fy)
    assert np.allclose(cam.cam2world[:3, 2], want.cam2world[:3, 2], atol=1e-9)
    (frame,) = _frames(tmp_path / "v")
    assert frame.shape == (96, 160, 3)
    # every instance in front of the camera is drawn where its base projects (not the backdrop)
    drawn = summary["per_frame"][0]["drawn"]
    assert drawn >= 8, summary["per_frame"]


def test_every_instance_off_screen_gives_the_backdrop(tmp_path):
    behind = _scene_doc(instances={"listed": [{"asset": "tree", "x": 0.0, "y": -20.0}]})
    assert main(["render", str(_write(tmp_path, behind)), "-o", str(tmp_path / "r")]) == 0
    empty = _scene_doc(instances={"listed": []})
    assert main(["render", str(_write(tmp_path, empty, "e.json")), "-o", str(tmp_path / "e")]) == 0
    (a,), (b,) = _frames(tmp_path / "r"), _frames(tmp_path / "e")
    assert np.array_equal(a, b)
    rs = json.loads((tmp_path / "r" / "render.json").read_text())
    assert rs["per_frame"][0]["drawn"] == 0 and rs["per_frame"][0]["culled"] == 1


def test_the_camera_inside_an_asset_draws_a_finite_frame(tmp_path):
    inside = _scene_doc(
        camera={"keyframes": [{"eye": [0.0, 0.0, 0.4], "target": [0.0, 5.0, 0.4]}]},
        instances={"listed": [{"asset": "tree", "x": 0.0, "y": 0.0}, {"asset": "tree", "x": 0.0, "y": 3.0}]},
    )
    assert main(["render", str(_write(tmp_path, inside)), "-o", str(tmp_path / "r")]) == 0
    (frame,) = _frames(tmp_path / "r")
    rs = json.loads((tmp_path / "r" / "render.json").read_text())
    assert frame.shape == (48, 64, 3) and rs["per_frame"][0]["drawn"] >= 1  # the one ahead


def test_two_instances_at_one_spot_are_drawn_and_said(tmp_path, capsys):
    two = _scene_doc(
        instances={"listed": [{"asset": "tree", "x": 0.0, "y": 0.0}, {"asset": "tree", "x": 0.0, "y": 0.0}]}
    )
    assert main(["render", str(_write(tmp_path, two)), "-o", str(tmp_path / "r")]) == 0
    err = capsys.readouterr().err
    assert "morphkit: warning: 2 of 2 instances still overlap another: drawn where the scene puts them" in err


@pytest.mark.parametrize(
    ("doc", "code", "match"),
    [
        (_scene_doc(assets=[], instances={"listed": []}), 1, r"expected at least one asset, got none"),
        ({"morphkit_scene": 7}, 1, r"expected version 1, got version 7"),
        (_scene_doc(frames=-1), 1, r"at \$\.frames"),
        (_scene_doc(assets=[{"name": "tree", "source": "nope.obj"}]), 1, r"nope\.obj"),
    ],
    ids=["no-assets", "other-version", "schema", "missing-asset-file"],
)
def test_a_scene_that_cannot_be_drawn_is_one_line(tmp_path, capsys, doc, code, match):
    assert main(["render", str(_write(tmp_path, doc)), "-o", str(tmp_path / "r")]) == code
    assert __import__("re").search(match, _one_error_line(capsys))
    assert not (tmp_path / "r").exists()  # nothing half-written


def test_render_refuses_another_commands_folder(tmp_path, capsys):
    assert main(["billboards", *SMALL, "-o", str(tmp_path / "bb")]) == 0
    capsys.readouterr()
    assert main(["render", str(_write(tmp_path, _scene_doc())), "-o", str(tmp_path / "bb")]) == 2
    assert "render output" in _one_error_line(capsys)


@pytest.mark.parametrize("name", ["forest.json", "flyover.json", "village.glb"])
def test_the_example_scenes_render(tmp_path, name):
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "samples" / "scenes" / name
    scene = load_scene(path)
    shadows = None if scene.shadows is None else dataclasses.replace(scene.shadows, sun_atlas_size=32)
    small = dataclasses.replace(
        scene, shape=(72, 96), frames=min(scene.frames, 2), asset_size=32, shadows=shadows
    )
    summary = render_scene(small, claim_output(tmp_path / "r", RENDER_OUTPUT))
    assert sum(a["instances"] for a in summary["assets"]) == len(scene.instances.first(scene.names))
    assert summary["compared"] and all(f["drawn"] > 0 for f in summary["per_frame"])


def test_compare_says_how_many_frames_are_measured_against_the_truth(tmp_path, capsys):
    path = _write(tmp_path, _scene_doc(frames=3, camera={"path": "orbit"}))
    assert main(["render", str(path), "--compare", "all", "-o", str(tmp_path / "all")]) == 0
    rs = json.loads((tmp_path / "all" / "render.json").read_text())
    assert [c["frame"] for c in rs["compared"]] == [0, 1, 2]
    assert main(["render", str(path), "--compare", "0", "-o", str(tmp_path / "none")]) == 0
    assert not list((tmp_path / "none").glob("compare_*.png"))
    capsys.readouterr()
    with pytest.raises(SystemExit) as e:
        main(["render", str(path), "--compare", "-2", "-o", str(tmp_path / "bad")])
    assert e.value.code == 2 and "a number of frames >= 0 or 'all'" in capsys.readouterr().err


def test_a_gltf_without_meshes_says_so_and_draws_nothing(tmp_path, capsys):
    path = tmp_path / "empty.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
                                "nodes": [{"name": "group"}]}))
    assert main(["render", str(path), "-o", str(tmp_path / "r")]) == 1
    out = capsys.readouterr()
    assert "morphkit render: no meshes: the scene is empty" in out.out
    assert out.err.strip() == "morphkit: error: scene: expected at least one asset, got none"
    assert not (tmp_path / "r").exists()
