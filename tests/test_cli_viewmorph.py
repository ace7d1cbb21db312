"""``morphkit viewmorph`` on the command line: a run that works, and each bad input refused in
one line on stderr with a non-zero exit code and no traceback."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from morphkit.cli import main


@pytest.fixture
def pair(tmp_path):
    """Two 64^2 RGB images of a smooth texture, the second moved 3 px right and 1 down, and a
    points file of that motion (a 4 x 4 grid)."""
    rng = np.random.default_rng(5)
    small = rng.uniform(0, 255, (14, 14, 3))
    tex = np.clip(cv2.resize(small, (64, 64), interpolation=cv2.INTER_CUBIC), 0, 255).astype(np.uint8)
    moved = cv2.warpAffine(tex, np.float64([[1, 0, 3], [0, 1, 1]]), (64, 64), borderMode=cv2.BORDER_REFLECT)
    cv2.imwrite(str(tmp_path / "left.png"), tex)
    cv2.imwrite(str(tmp_path / "right.png"), moved)
    g = np.linspace(4, 56, 4)
    p0 = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    (tmp_path / "points.json").write_text(json.dumps({"pts0": p0.tolist(), "pts1": (p0 + [3, 1]).tolist()}))
    return tmp_path


def run_cli(capsys, *args):
    code = main(["viewmorph", *map(str, args)])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_a_plain_morph_from_a_points_file_is_written(pair, capsys):
    out = pair / "sub" / "mid.png"
    code, stdout, err = run_cli(capsys, pair / "left.png", pair / "right.png", "--points",
                                pair / "points.json", "--prewarp", "none", "-o", out)
    assert code == 0 and err == "" and "wrote" in stdout
    img = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert img.shape == (64, 64, 3) and img.dtype == np.uint8
    # the morph at s = 1/2 of a 3 px, 1 px translation: the texture moved half way (inside the grid)
    left = cv2.imread(str(pair / "left.png"))
    half = cv2.warpAffine(left, np.float64([[1, 0, 1.5], [0, 1, 0.5]]), (64, 64), flags=cv2.INTER_LINEAR)
    inner = (slice(8, 54), slice(8, 54))
    assert np.abs(img[inner].astype(int) - half[inner].astype(int)).mean() < 3.0
    assert sorted(p.name for p in out.parent.iterdir()) == ["mid.png"]  # no temporary file left


def _one_line_error(code, stdout, err, *needles):
    assert code != 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("morphkit: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], lines[0]


def test_output_whose_parent_is_a_file(pair, capsys):
    (pair / "afile").write_text("x")
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "-o", pair / "afile" / "out.png"),
                    "output: expected a path whose parents are folders", "is a file")
    assert (pair / "afile").read_text() == "x"
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "--frames", 3,
                             "-o", pair / "afile"), "output with --frames: expected a folder path")


def test_output_that_is_a_folder(pair, capsys):
    (pair / "adir").mkdir()
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "-o", pair / "adir"),
                    "output: expected an image file path", "the folder")


def test_unknown_output_extension(pair, capsys):
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "-o", pair / "out.xyz"),
                    "image for .xyz: expected an image OpenCV can encode")
    assert not (pair / "out.xyz").exists()


def test_malformed_points_json(pair, capsys):
    (pair / "bad.json").write_text('{"pts0": [[1, 2],')
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "--points", pair / "bad.json",
                             "-o", pair / "o.png"), "points file: expected valid JSON")
    (pair / "short.json").write_text(json.dumps([[1, 2, 3]]))
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "--points", pair / "short.json",
                             "-o", pair / "o.png"), "points file: expected rows of 4 numbers")


def test_missing_or_unreadable_input_image(pair, capsys):
    _one_line_error(*run_cli(capsys, pair / "missing.png", pair / "right.png", "-o", pair / "o.png"),
                    "missing.png", "expected an existing file, got nothing there")
    (pair / "text.png").write_text("not an image")
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "text.png", "-o", pair / "o.png"),
                    "text.png", "expected an image file OpenCV can decode")
    _one_line_error(*run_cli(capsys, pair, pair / "right.png", "-o", pair / "o.png"),
                    "expected an existing file, got a folder")
    assert not (pair / "o.png").exists()


def test_bad_s_is_one_line_too(pair, capsys):
    _one_line_error(*run_cli(capsys, pair / "left.png", pair / "right.png", "--points", pair / "points.json",
                             "--s", 1.5, "-o", pair / "o.png"), "s: expected")


def test_a_real_process_prints_no_traceback(pair):
    (pair / "afile").write_text("x")
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
    cases = [["-o", str(pair / "afile" / "o.png")], ["-o", str(pair / "o.xyz")],
             ["--points", str(pair / "missing.json"), "-o", str(pair / "o.png")],
             ["--points", str(pair / "points.json"), "-o", str(pair / "afile" / "deeper" / "o.png")]]
    for extra in cases:
        proc = subprocess.run([sys.executable, "-m", "morphkit", "viewmorph", str(pair / "left.png"),
                               str(pair / "right.png"), *extra], capture_output=True, text=True, env=env,
                              timeout=120)
        assert proc.returncode != 0
        assert "Traceback" not in proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1 and proc.stderr.startswith("morphkit: error: ")
