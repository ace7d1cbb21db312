"""Billboard outputs without GL: the frame sequence, the video file, the comparison helpers."""

from __future__ import annotations

import json
import sys

import cv2
import numpy as np
import pytest
from billboard_fakes import FakeAsset

from morphkit.billboard import BillboardScene, ClassicMode, MorphMode, OrbitPath, place_random
from morphkit.billboard.compare import box_errors, compare_modes, mean_errors
from morphkit.errors import ValidationError
from morphkit.files.fileio import read_image
from morphkit.programs.sequence import compare_indices, write_sequence
from morphkit.programs.video import VideoFile


def _scene():
    asset = FakeAsset("fake", views=8)
    inst = place_random(["fake"], 20, np.random.default_rng(2), half_size=3.0)
    return BillboardScene({"fake": asset}, inst)


def test_write_sequence_writes_frames_video_and_summary(tmp_path):
    scene = _scene()
    cams = OrbitPath(radius=6.0, height=1.5).cameras(4, shape=(48, 64))
    summary = write_sequence(scene, cams, tmp_path / "out", fps=10)
    out = tmp_path / "out"
    assert sorted(p.name for p in (out / "frames").iterdir()) == [f"frame_{k:04d}.png" for k in range(4)]
    first = read_image(out / "frames" / "frame_0000.png")
    expect = scene.render(cams[0], MorphMode()).rgb
    np.testing.assert_array_equal(first, expect)
    cap = cv2.VideoCapture(str(out / "billboards.webm"))
    n = 0
    while cap.read()[0]:
        n += 1
    assert n == 4
    data = json.loads((out / "billboards.json").read_text())
    assert data["frames"] == 4 and len(data["per_frame"]) == 4 and data["mode"] == "morph"
    assert data == json.loads(json.dumps(summary))
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary file left


def test_video_file_is_atomic_and_validated(tmp_path):
    target = tmp_path / "v.mp4"
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError, match="boom"), VideoFile(target, 10, (16, 16)) as v:
        v.write(np.zeros((16, 16, 3), np.uint8))
        raise RuntimeError("boom")
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["v.mp4"]
    with pytest.raises(ValidationError, match="video file: expected a name ending in one of"):
        VideoFile(tmp_path / "v.gif", 10, (16, 16))
    with VideoFile(target, 10, (16, 16)) as v, pytest.raises(ValidationError, match="video frame: expected"):
        v.write(np.zeros((8, 8, 3), np.uint8))


def test_the_commands_videos_are_vp9_webm_and_odd_frames_keep_every_pixel(tmp_path):
    from morphkit.programs.video import VIDEO_SUFFIX

    assert VIDEO_SUFFIX == ".webm"  # browsers play VP9 in WebM, not MPEG-4 Part 2
    rng = np.random.default_rng(3)
    frames = [cv2.GaussianBlur(rng.integers(0, 256, (33, 47, 3), dtype=np.uint8), (9, 9), 3)
              for _ in range(3)]
    with VideoFile(tmp_path / "odd.webm", 10, (33, 47)) as v:
        for f in frames:
            v.write(f)
    cap = cv2.VideoCapture(str(tmp_path / "odd.webm"))
    assert int(cap.get(cv2.CAP_PROP_FOURCC)).to_bytes(4, "little") == b"VP90"
    ok, first = cap.read()
    cap.release()
    # padded to 34 x 48 with the edge repeated, not cropped to 32 x 46: the last column is there
    assert ok and first.shape == (34, 48, 3)
    # lossy, but the decoded frame follows the written one: its mean error is under half the
    # frame's own spread (a flat grey or a shifted frame would be at or over it)
    err = np.abs(cv2.cvtColor(first, cv2.COLOR_BGR2RGB)[:33, :47].astype(int) - frames[0]).mean()
    assert err < 0.5 * frames[0].std()


def test_opening_a_webm_writer_prints_nothing(tmp_path, capfd):
    # FFmpeg's "tag ... is not supported ... fallback" line (WebM has no codec tags) is held back
    with VideoFile(tmp_path / "q.webm", 10, (16, 16)) as v:
        v.write(np.zeros((16, 16, 3), np.uint8))
    out, err = capfd.readouterr()
    assert (out, err) == ("", "") and (tmp_path / "q.webm").stat().st_size > 0
    print("after", file=sys.stderr)  # stderr is back
    assert capfd.readouterr().err == "after\n"


def test_compare_helpers():
    assert compare_indices(10, 3) == [0, 4, 9]  # round(4.5) = 4
    assert compare_indices(1, 3) == [0] and compare_indices(0, 3) == []
    scene = _scene()
    cam = OrbitPath(radius=6.0, height=1.5).camera_at(0.3, (48, 64))
    morph = MorphMode()
    cmp = compare_modes(scene, cam, {"classic": ClassicMode()}, morph)  # the "truth" here is the morph
    assert list(cmp.frames) == ["classic", "mesh"] and cmp.strip.shape == (48, 128, 3)
    same = box_errors(cmp.frames["mesh"], cmp.frames["mesh"])
    assert same and all(e["iou"] == 1.0 and e["psnr"] == 100.0 for e in same)
    m = mean_errors(box_errors(cmp.frames["classic"], cmp.frames["mesh"]))
    assert m["n"] == len(cmp.frames["classic"].placements) and m["iou"] < 1.0
    assert cmp.errors["classic"] == m
    assert np.isnan(mean_errors([])["iou"])
