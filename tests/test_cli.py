"""CLI error paths: every command catches morphkit and OS errors at its edge and
prints one line ``morphkit: error: ...`` (exit 1; usage errors, bad option values included, exit 2),
no traceback."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from morphkit.cli import main


@pytest.fixture(scope="module")
def pair(tmp_path_factory) -> dict[str, Path]:
    """Two small images and correspondences that morph without rectification."""
    d = tmp_path_factory.mktemp("vm")
    img = (np.random.default_rng(0).random((40, 48, 3)) * 255).astype(np.uint8)
    cv2.imwrite(str(d / "l.png"), img)
    cv2.imwrite(str(d / "r.png"), img)
    (d / "p.json").write_text(json.dumps([[x, y, x + 1, y] for x in (2, 20, 45) for y in (2, 20, 37)]))
    (d / "syntax.json").write_text("{not json")
    (d / "layout.json").write_text('{"pts0": [[1, 2, 3]], "pts1": [[1, 2]]}')
    (d / "afile").write_text("x")
    names = ("l.png", "r.png", "p.json", "syntax.json", "layout.json", "afile")
    return {k: d / k for k in names} | {"dir": d}


def _vm(pair, out, points="p.json"):
    return ["viewmorph", str(pair["l.png"]), str(pair["r.png"]), "--points", str(pair[points]),
            "--prewarp", "none", "-o", str(out)]


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("morphkit: error: ") and "Traceback" not in err[0]
    return err[0]


def test_viewmorph_writes_its_output(pair, capsys):
    out = pair["dir"] / "out.png"
    assert main(_vm(pair, out)) == 0
    assert cv2.imread(str(out)).shape == (40, 48, 3)
    assert [p.name for p in pair["dir"].iterdir() if p.name.endswith(".part")] == []


@pytest.mark.parametrize("case, match", [
    ("parent-is-a-file", r"output: expected a path whose parents are folders, got .*afile/o.png.*is a file"),
    ("unknown-extension", r"image for .xyz: expected an image OpenCV can encode in that format"),
    ("output-is-a-folder", r"output: expected an image file path .*, got the folder"),
    ("system-path", r"cannot write /proc/morphkit-test.png"),
    ("points-not-json", r"points file: expected valid JSON"),
    ("points-bad-layout", r"points file pts0: expected a list of \[x, y\] numbers, got shape .*layout.json"),
    ("missing-input", r"image .*missing.png.*: expected an existing file, got nothing there"),
])
def test_viewmorph_errors_are_one_line(pair, capsys, case, match):
    d = pair["dir"]
    argv = {
        "parent-is-a-file": _vm(pair, pair["afile"] / "o.png"),
        "unknown-extension": _vm(pair, d / "o.xyz"),
        "output-is-a-folder": _vm(pair, d),
        "system-path": _vm(pair, "/proc/morphkit-test.png"),
        "points-not-json": _vm(pair, d / "o.png", "syntax.json"),
        "points-bad-layout": _vm(pair, d / "o.png", "layout.json"),
        "missing-input": ["viewmorph", str(d / "missing.png"), str(pair["r.png"]), "-o", str(d / "o.png")],
    }[case]
    if case == "system-path" and not Path("/proc/self").exists():
        pytest.skip("needs Linux /proc (a folder nobody can create files in)")
    # a bad -o is a usage error (exit 2); an input or a write that fails, a failed run (exit 1)
    usage = case in ("parent-is-a-file", "unknown-extension", "output-is-a-folder")
    assert main(argv) == (2 if usage else 1)
    line = _one_error_line(capsys)
    assert __import__("re").search(match, line), line


def test_usage_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as e:
        main(["viewmorph", "only-one.png"])
    assert e.value.code == 2
    assert "the following arguments are required" in capsys.readouterr().err  # argparse's own
    assert main(["bench", "nope"]) == 2
    assert _one_error_line(capsys).endswith("available: " + ", ".join(sorted(
        __import__("morphkit.bench", fromlist=["SUITES"]).SUITES)))


@pytest.mark.parametrize("flag", ["--json", "--plot"])
def test_bench_refuses_bad_output_paths_before_running(tmp_path, capsys, flag):
    """A folder, or a path under a file, is refused before the (long) suite runs."""
    (tmp_path / "f").write_text("x")
    assert main(["bench", "nope-never-run", flag, str(tmp_path)]) == 2
    assert "expected a file path, got the folder" in _one_error_line(capsys)
    assert main(["bench", "warp", flag, str(tmp_path / "f" / "x.json")]) == 2
    assert "expected a path under a folder" in _one_error_line(capsys)


@pytest.mark.gl
def test_demo_into_a_file_is_one_line(tmp_path, capsys):
    f = tmp_path / "not-a-folder"
    f.write_text("keep")
    assert main(["demo", "--quick", "-o", str(f)]) == 2  # -o used wrongly: a usage error
    assert "demo output folder: expected a folder, got the file" in _one_error_line(capsys)
    assert f.read_text() == "keep"
    assert main(["demo", "--quick", "-o", str(f / "sub")]) == 2  # a file on the path
    _one_error_line(capsys)


@pytest.mark.gl
def test_demo_keeps_a_previous_demo_unless_overwrite(tmp_path, capsys):
    index = tmp_path / "index.json"
    index.write_text('{"morphkit_demo": 1, "files": [{"path": "teapot_scene.png"}]}')
    assert main(["demo", "--quick", "-o", str(tmp_path)]) == 2
    line = _one_error_line(capsys)
    assert "already holds a demo (index.json); pass --overwrite" in line
    assert [p.name for p in tmp_path.iterdir()] == ["index.json"]  # nothing written
    from morphkit.errors import ValidationError
    from morphkit.programs.demo import run_demo

    with pytest.raises(ValidationError, match=r"demo output folder: expected one without a previous demo "
                       r"\(--overwrite / overwrite=True replaces it\), got .* holding index.json"):
        run_demo(tmp_path, quick=True)


def test_errors_print_no_traceback_in_a_subprocess(tmp_path):
    """The real entry point (python -m morphkit), as a user runs it."""
    root = Path(__file__).resolve().parents[1]
    env = {"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin"}
    r = subprocess.run([sys.executable, "-m", "morphkit", "viewmorph", str(tmp_path / "a.png"),
                        str(tmp_path / "b.png"), "-o", str(tmp_path / "o.png")],
                       capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 1
    assert "Traceback" not in r.stderr
    assert r.stderr.strip().startswith("morphkit: error: image") and len(r.stderr.strip().splitlines()) == 1
