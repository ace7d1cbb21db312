"""``morphkit billboards``: user errors as one line and a non-zero exit; a tiny run end to end."""

from __future__ import annotations

import json
import re

import cv2
import numpy as np
import pytest

from morphkit.cli import main
from morphkit.errors import ValidationError
from morphkit.programs.cliargs import parse_size


def _one_line_error(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err
    assert code != 0
    assert err.startswith("morphkit: error: ") and err.count("\n") == 1 and "Traceback" not in err
    return err


@pytest.mark.parametrize("size", ["640", "640x", "0x480", "axb", "640x480x3", "-640x480", "99999x10"])
def test_bad_size(capsys, tmp_path, size):
    err = _one_line_error(capsys, ["billboards", f"--size={size}", "-o", str(tmp_path / "o")])
    assert "--size: expected WIDTHxHEIGHT" in err
    assert not (tmp_path / "o").exists()  # refused before anything was written


def test_parse_size():
    assert parse_size("640x480") == (480, 640) and parse_size("64X48") == (48, 64)
    with pytest.raises(ValidationError, match="--size: expected"):
        parse_size("64*48")


def test_bad_asset_name(capsys, tmp_path):
    err = _one_line_error(capsys, ["billboards", "--asset", "tree", "--asset", "unicorn",
                                   "-o", str(tmp_path / "o")])
    assert "asset: expected a sample mesh name" in err and "'unicorn'" in err
    assert not (tmp_path / "o").exists()
    err = _one_line_error(capsys, ["billboards", "--asset", str(tmp_path / "missing.npz"),
                                   "-o", str(tmp_path / "o")])
    assert "missing.npz" in err


def test_unwritable_output(capsys, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    err = _one_line_error(capsys, ["billboards", "-o", str(blocker / "out")])
    assert "output folder: expected a folder morphkit can create and write" in err
    err = _one_line_error(capsys, ["billboards", "-o", str(blocker)])
    assert "output folder" in err


def test_bad_counts(capsys, tmp_path):
    err = _one_line_error(capsys, ["billboards", "--n", "-3", "-o", str(tmp_path)])
    assert "--n: expected an integer in [0, 100000]" in err
    assert "--views: expected an integer in [2, 64]" in _one_line_error(
        capsys, ["billboards", "--views", "1", "-o", str(tmp_path)])


@pytest.mark.gl
def test_tiny_run_writes_frames_video_and_comparisons(capsys, tmp_path):
    out = tmp_path / "bb"
    assert main(["billboards", "--asset", "tree", "--n", "6", "--frames", "3", "--size", "96x72",
                 "--views", "2", "--asset-size", "64", "--path", "orbit", "-o", str(out)]) == 0
    summary = json.loads((out / "billboards.json").read_text())
    assert summary["frames"] == 3 and summary["instances"] == 6
    for f in summary["files"]:
        assert (out / f).stat().st_size > 0
    assert sorted(p.name for p in (out / "frames").iterdir()) == ["frame_0000.png", "frame_0001.png",
                                                                  "frame_0002.png"]
    strip = cv2.imread(str(out / "compare_0000.png"))
    assert strip.shape == (72, 3 * 96, 3)  # classic | morph | mesh
    assert [c["frame"] for c in summary["compared"]] == [0, 1, 2]
    printed = capsys.readouterr().out
    assert "cache hit rate" in printed and str(out.resolve()) in printed


@pytest.mark.gl
def test_instances_that_would_stand_inside_each_other_are_moved_apart(capsys, tmp_path):
    """The seed's uniform scatter of 80 trees puts some inside others: the run moves them (the
    footprint test itself: test_instances_spacing.py) and says so on stdout."""
    assert main(["billboards", "--asset", "tree", "--n", "80", "--frames", "1", "--size", "64x48",
                 "--views", "2", "--asset-size", "32", "-o", str(tmp_path / "bb")]) == 0
    printed = capsys.readouterr().out
    assert re.search(r"\b[1-9]\d* of 80 instances moved apart", printed), printed


@pytest.mark.gl
def test_mesh_file_asset_is_baked_in_its_own_look_and_compared(capsys, tmp_path):
    from morphkit.programs.fixtures import photo_texture, write_photo_glb

    glb = write_photo_glb(tmp_path, photo_texture(32), name="crate")
    out = tmp_path / "bb"
    assert main(["billboards", "--asset", str(glb), "--up-axis", "auto", "--n", "4", "--frames", "2",
                 "--size", "96x72", "--views", "2", "--asset-size", "48", "--path", "orbit",
                 "-o", str(out)]) == 0
    summary = json.loads((out / "billboards.json").read_text())
    assert [c["frame"] for c in summary["compared"]] == [0, 1]  # compared with the real mesh
    captured = capsys.readouterr()
    assert "billboards of crate," in captured.out and "skipped" not in captured.err
    # a baked asset with no mesh beside it: its own name, and why the comparison is skipped
    from morphkit.billboard import bake_asset
    from morphkit.meshes import load_mesh
    from morphkit.render import Renderer

    with Renderer() as r:
        bake_asset(load_mesh(glb), r, views=2, size=48, levels=1).save(tmp_path / "lonely.npz")
    assert main(["billboards", "--asset", str(tmp_path / "lonely.npz"), "--n", "2", "--frames", "1",
                 "--size", "64x48", "-o", str(tmp_path / "bb2")]) == 0
    captured = capsys.readouterr()
    assert "billboards of lonely," in captured.out
    assert "skipped: lonely: no mesh file lonely{.obj," in captured.err


def test_bad_up_axis(capsys, tmp_path):
    with pytest.raises(SystemExit):
        main(["billboards", "--up-axis", "x", "-o", str(tmp_path / "o")])
    assert "--up-axis" in capsys.readouterr().err


def test_views_must_be_a_ring_or_dome_and_relighting_needs_a_dome(capsys, tmp_path):
    err = _one_line_error(capsys, ["billboards", "--views", "many", "-o", str(tmp_path / "o")])
    assert "--views: expected an integer in [2, 64] (a ring) or 'dome'" in err
    err = _one_line_error(capsys, ["billboards", "--views", "8", "--sun-path", "day",
                                   "-o", str(tmp_path / "o")])
    assert "--views with --sun-path: expected dome" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.gl
def test_fly_over_under_a_moving_sun_with_dome_assets(capsys, tmp_path):
    out = tmp_path / "bb"
    assert main(["billboards", "--asset", "tree", "--n", "6", "--frames", "3", "--size", "96x72",
                 "--asset-size", "32", "--path", "flyover", "--sun-path", "day", "-o", str(out)]) == 0
    summary = json.loads((out / "billboards.json").read_text())
    assert summary["mode"] == "morph" and summary["frames"] == 3
    printed = capsys.readouterr().out
    assert "relit dome assets" in printed and "sun: day" in printed
    frames = [cv2.imread(str(out / "frames" / f"frame_{k:04d}.png")) for k in range(3)]
    assert all(f is not None and f.shape == (72, 96, 3) for f in frames)
    # a ring asset file given where a dome is asked for: one line, re-bake
    from morphkit.billboard import bake_asset
    from morphkit.meshes import sample_mesh
    from morphkit.render import Renderer

    with Renderer() as r:
        bake_asset(sample_mesh("tree"), r, views=2, size=32, levels=1).save(tmp_path / "ring.npz")
    err = _one_line_error(capsys, ["billboards", "--asset", str(tmp_path / "ring.npz"), "--views", "dome",
                                   "--frames", "1", "-o", str(tmp_path / "bb3")])
    assert "re-bake" in err


@pytest.mark.parametrize("path, argv, chosen", [
    ("pan", [], "a ring of 8 views (the pan path's eye looks down by at most 8 degrees"),
    ("orbit", [], "a ring of 8 views (the orbit path"),
    ("fly", [], "a ring of 8 views (the fly path"),
    ("flyover", [], "dome views (the flyover path's eye looks down by up to 85 degrees, above the ring's "
                    "band of 0-30"),
    ("topdown", [], "dome views (the topdown path's eye looks down by up to 90 degrees"),
    ("pan", ["--sun-path", "day"], "dome views (--sun-path relights them"),
])
def test_the_default_views_follow_the_camera_path_and_say_so(capsys, tmp_path, path, argv, chosen):
    broken = tmp_path / "broken.ply"  # the run stops at loading it: after the choice, before any bake
    broken.write_text("not a mesh")
    run = ["billboards", "--asset", str(broken), "--path", path, "--frames", "5"]
    assert main([*run, *argv, "-o", str(tmp_path / "a")]) == 1
    out, err = capsys.readouterr()
    # said on stdout; the error alone, one line, on stderr
    assert f"morphkit billboards: {chosen}" in out
    assert len(err.strip().splitlines()) == 1 and "broken.ply" in err
    assert main([*run, "--views", "4", "-o", str(tmp_path / "b")]) == 1
    assert "morphkit billboards:" not in capsys.readouterr().out  # given: nothing to choose or say


def _dome_like(path):
    """An .npz whose metadata says dome asset (of a version no reader takes: the run stops at
    loading it, after the choice of views)."""
    import json

    meta = {"format": "morphkit-billboard", "version": 999, "kind": "dome", "name": "thing"}
    np.savez(path, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8))
    return path


def test_dome_asset_files_take_dome_views_and_one_kind_is_asked_for(capsys, tmp_path):
    from morphkit.billboard.formats.domefile import is_dome_file

    dome = _dome_like(tmp_path / "thing.npz")  # a dome file by its metadata, not by its name
    assert is_dome_file(dome) and not is_dome_file(tmp_path / "missing.npz") and not is_dome_file(tmp_path)
    run = ["billboards", "--asset", str(dome), "--frames", "2"]
    assert main([*run, "-o", str(tmp_path / "a")]) == 1  # the made-up version: refused at loading
    assert "morphkit billboards: dome views (the --asset files are dome assets)" in capsys.readouterr().out
    assert main([*run, "--views", "4", "-o", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err
    assert "--asset files: expected assets of one kind" in err and "with --views 4" in err
    ring = tmp_path / "ring.npz"
    np.savez(ring, meta=np.frombuffer(b'{"format": "morphkit-billboard", "version": 2}', np.uint8))
    assert main(["billboards", "--asset", str(dome), "--asset", str(ring), "-o", str(tmp_path / "c")]) == 2
    assert f"with ring {ring}" in capsys.readouterr().err
