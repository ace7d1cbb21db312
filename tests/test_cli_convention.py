"""One command-line convention: exit 2 for a usage error (argparse's, a bad option value, an output
refused without --overwrite, a bad environment variable), 1 for a run that failed on its inputs;
one line per error and per warning; ``viewmorph -o`` never replaces an input, nor a file unasked."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import cv2
import numpy as np
import pytest
from clirun import one_line, run

from morphkit import tol
from morphkit.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def images(tmp_path_factory) -> dict[str, Path]:
    """A textured image and a shifted view of it (with its points), and an unrelated image."""
    d = tmp_path_factory.mktemp("conv")
    rng = np.random.default_rng(0)
    big = cv2.GaussianBlur(rng.integers(0, 255, (80, 120, 3), dtype=np.uint8), (0, 0), 1.0)
    cv2.imwrite(str(d / "l.png"), big[10:70, 10:100])
    cv2.imwrite(str(d / "r.png"), big[10:70, 14:104])
    other = np.full((60, 90, 3), 90, np.uint8)
    for _ in range(12):
        c = tuple(int(v) for v in rng.integers(0, 255, 3))
        centre = (int(rng.integers(0, 90)), int(rng.integers(0, 60)))
        cv2.circle(other, centre, int(rng.integers(4, 20)), c, -1)
    cv2.imwrite(str(d / "unrelated.png"), cv2.GaussianBlur(other, (0, 0), 2.0))
    pts = [[x, y, x - 4, y] for x in (10, 30, 50, 70) for y in (8, 25, 40, 52)]
    (d / "p.csv").write_text("\n".join(",".join(map(str, p)) for p in pts) + "\n")
    for h, w in ((1, 1), (5, 5), (11, 11), (12, 40)):
        cv2.imwrite(str(d / f"tiny{h}x{w}.png"), rng.integers(0, 255, (h, w, 3), dtype=np.uint8))
    return {p.name: p for p in d.iterdir()} | {"dir": d}


# ------------------------------------------------------------------ viewmorph -o (a single file)
def test_an_existing_output_file_is_kept_without_overwrite(images, tmp_path, capsys):
    out = tmp_path / "o.png"
    out.write_bytes(b"mine")
    argv = ("viewmorph", images["l.png"], images["r.png"], "--points", images["p.csv"], "-o", out)
    rc, _o, err = run(capsys, *argv)
    assert rc == 2 and re.search(r"output: expected a new file, or --overwrite to replace it, got the "
                                 r"existing file .*o\.png", one_line(err)), err
    assert out.read_bytes() == b"mine"
    rc, _o, _e = run(capsys, *argv, "--overwrite")
    assert rc == 0 and cv2.imread(str(out)) is not None


@pytest.mark.parametrize("which", ["l.png", "r.png", "p.csv"])
def test_the_output_is_never_an_input(images, capsys, which):
    before = images[which].read_bytes()
    same = images["dir"] / "." / which  # another spelling of the same path
    rc, _o, err = run(capsys, "viewmorph", images["l.png"], images["r.png"], "--points", images["p.csv"],
                      "-o", same, "--overwrite")
    assert rc == 2 and re.search(r"-o: expected a path other than the inputs' .*which is "
                                 r"(LEFT|RIGHT|--points)", one_line(err)), err
    assert images[which].read_bytes() == before


# ------------------------------------------------------------------ viewmorph: too few matches
@pytest.mark.parametrize("fallback", ["raise", "morph"])
def test_unrelated_images_are_refused_with_or_without_fallback(images, tmp_path, capsys, fallback):
    rc, _o, err = run(capsys, "viewmorph", images["l.png"], images["unrelated.png"], "--fallback", fallback,
                      "-o", tmp_path / "o.png")
    line = one_line(err)
    assert rc == 1 and f"at least {tol.VM_MIN_SCENE_MATCHES} distinctive (SIFT) matches" in line, err
    assert "do not seem to show one scene" in line and "--points" in line and "epipole" not in line
    assert not (tmp_path / "o.png").exists()


def test_views_of_one_scene_still_morph_from_the_images(images, tmp_path, capsys):
    rc, out, err = run(capsys, "viewmorph", images["l.png"], images["r.png"], "-o", tmp_path / "o.png")
    assert rc == 0, err
    assert cv2.imread(str(tmp_path / "o.png")).shape == (60, 90, 3)


# ------------------------------------------------------------------ viewmorph: images below a matcher's size
@pytest.mark.parametrize("name", ["tiny1x1.png", "tiny5x5.png", "tiny11x11.png", "tiny12x40.png"])
def test_tiny_images_are_one_line_or_a_morph(images, tmp_path, name):
    """DIS flow refuses images under 12 px a side and crashed the process on 12 x 40: in a
    subprocess, the command either morphs or prints one error line; never a traceback or a signal."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    r = subprocess.run([sys.executable, "-m", "morphkit", "viewmorph", str(images[name]), str(images[name]),
                        "-o", str(tmp_path / "o.png")], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode in (0, 1), (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr and "cv2.error" not in r.stderr, r.stderr
    if r.returncode == 1:
        one_line(r.stderr)


def test_the_flow_matcher_takes_images_smaller_than_dis_does():
    from morphkit.viewmorph.matching import FlowMatcher

    img = np.random.default_rng(1).integers(0, 255, (5, 5), dtype=np.uint8)
    got = FlowMatcher(step=1).match(img, img)
    assert len(got) > 0 and got.pts0.max() <= 4 and got.pts1.min() >= -0.5


# ------------------------------------------------------------------ exit codes
@pytest.mark.parametrize("args, message", [
    (["billboards", "--frames", "0"], r"--frames: expected an integer in \[1, 100000\], got 0"),
    (["viewmorph", "{l}", "{r}", "--frames", "1"], r"--frames: expected an integer in \[2, "),
    (["viewmorph", "{l}", "{r}", "--s", "1.5"], r"--s: expected a position in \[0, 1\], got 1.5"),
    (["billboards", "--size", "320"], r"--size: expected WIDTHxHEIGHT"),
    (["demo", "--size", "3"], r"--size: expected an integer in \[16, "),
    (["bench", "warp", "--json", "{dir}"], r"--json: expected a file path, got the folder"),
    (["bench", "scene", "--sections", ""], r"--sections: expected section names"),
    (["bench", "scene", "--sections", "accuracy,,levels"], r"--sections: expected section names"),
    (["bench", "scene", "--instances", "0"], r"--instances: expected an integer in \[1, 2000\], got 0"),
    (["bench", "scene", "--instances", "10", "10000000000"], r"--instances: expected an integer in \[1, "),
    (["bench", "bake", "--assets", "1000000000"], r"--assets: expected an integer in \[1, 4096\]"),
    (["bench", "bake", "--workers", "0"], r"--workers: expected an integer in \[1, 256\]"),
])
def test_bad_option_values_exit_2(images, capsys, monkeypatch, args, message):
    import morphkit.bench

    def never(*_a, **_k):
        raise AssertionError("the suite ran")

    monkeypatch.setattr(morphkit.bench, "run_suite", never)
    argv = [a.format(l=images["l.png"], r=images["r.png"], dir=images["dir"]) for a in args]
    rc, _o, err = run(capsys, *argv, *(["-o", images["dir"] / "never.png"] if argv[0] != "bench" else []))
    assert rc == 2 and re.search(message, one_line(err)), err


NOT_SAMPLE = (r"--asset: expected a sample mesh name \(teapot, chair, cow, tree, person\) or a mesh or asset "
              r"file \(\.obj, .*\.npz\), got 'unicorn', no sample of that name")
AN_O_FILE = r"output folder: expected a folder, got the file .*a-file"


@pytest.mark.parametrize("args, message", [
    (["billboards", "--asset", "unicorn", "-o", "{dir}/o"], NOT_SAMPLE),
    (["billboards", "--asset", "tree", "--asset", "{file}", "-o", "{dir}/o"],
     r"--asset: .*got '.*a-file', a file of another kind"),
    (["billboards", "-o", "{file}"], "billboards " + AN_O_FILE),
    (["billboards", "-o", "{file}/sub"], r"billboards output folder: .*a-file is a file"),
    (["demo", "-o", "{file}"], "demo " + AN_O_FILE),
    (["shadows", "{dir}/none.atlas.npz", "-o", "{file}"], "shadows " + AN_O_FILE),
    (["shadows", "{dir}/none.atlas.npz", "--path", "circel", "-o", "{dir}/o"],
     r"--path: expected line, circle or a CSV file of x,y rows \(FILE\.csv\), got 'circel'"),
    (["bake", "{dir}/none.obj", "-o", "{file}"], "bake " + AN_O_FILE),
    (["bake", "{dir}/none.obj", "-o", "{file}/sub"], r"bake output folder: .*a-file is a file"),
    (["bake", "{dir}/none.obj", "--scheduler", "nonsense", "-o", "{dir}/o"],
     r"Dask scheduler address: expected"),
    (["bench", "scene", "--sections", "accuracy,nosuch"],
     r"sections: expected names among \[.*'accuracy'.*\], got \['nosuch'\]"),
])
def test_usage_errors_of_names_and_output_folders_exit_2(tmp_path, capsys, monkeypatch, args, message):
    """A value that names nothing (a sample, a path, a section) or an -o that cannot be the command's
    folder is the command line used wrongly: exit 2, before any work (these exited 1)."""
    import morphkit.bench

    def never(*_a, **_k):
        raise AssertionError("the suite ran")

    monkeypatch.setattr(morphkit.bench, "run_suite", never)
    file = tmp_path / "a-file"
    file.write_text("mine")
    rc, _o, err = run(capsys, *[a.format(file=file, dir=tmp_path) for a in args])
    assert rc == 2 and re.search(message, one_line(err)), err
    assert file.read_text() == "mine" and sorted(p.name for p in tmp_path.iterdir()) == ["a-file"]


@pytest.mark.parametrize("args, message", [
    (["billboards", "--asset", "{dir}/missing.obj"], r"asset: expected .* got '.*missing\.obj'"),
    (["shadows", "{dir}/none.atlas.npz", "--path", "{dir}/missing.csv"],
     r"path file: expected an existing CSV"),
    (["bake", "{dir}/missing.obj"], r"input: expected an existing mesh file or folder, got '.*missing\.obj'"),
])
def test_a_missing_input_file_is_still_the_run_failing(tmp_path, capsys, args, message):
    rc, _o, err = run(capsys, *[a.format(dir=tmp_path) for a in args], "-o", tmp_path / "o")
    assert rc == 1 and re.search(message, one_line(err)), err


def test_a_failed_run_exits_1_and_argparse_2(images, tmp_path, capsys):
    missing = images["dir"] / "missing.png"
    rc, _o, err = run(capsys, "viewmorph", missing, images["r.png"], "-o", tmp_path / "o.png")
    assert rc == 1 and "expected an existing file" in one_line(err)
    rc, _o, err = run(capsys, "viewmorph", images["l.png"], images["r.png"], "--frames", "x", "-o", tmp_path)
    assert rc == 2 and "invalid int value" in err


# ------------------------------------------------------------------ environment variables
@pytest.mark.parametrize("name, value, message", [
    ("MORPHKIT_WARP_THREADS", "abc", r"MORPHKIT_WARP_THREADS: expected an integer in \[1, 256\].*got 'abc'"),
    ("MORPHKIT_WARP_THREADS", "-2", r"MORPHKIT_WARP_THREADS: expected an integer in \[1, 256\]"),
    ("MORPHKIT_EGL_DEVICE", "gpu0", r"MORPHKIT_EGL_DEVICE: expected an integer in \[0, 1023\].*got 'gpu0'"),
    ("MORPHKIT_GL", "vulkan", r"MORPHKIT_GL: expected one of osmesa, egl \(or unset\), got 'vulkan'"),
])
def test_a_bad_environment_variable_is_one_line_even_for_help(name, value, message):
    env = {k: v for k, v in os.environ.items() if not k.startswith("MORPHKIT_")}
    env.update({"PYTHONPATH": str(ROOT), name: value})
    r = subprocess.run([sys.executable, "-m", "morphkit", "--help"], capture_output=True, text=True, env=env,
                       timeout=300)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout)
    assert re.search(message, one_line(r.stderr)), r.stderr


def test_the_environment_is_checked_in_process_too(monkeypatch, capsys):
    monkeypatch.setenv("MORPHKIT_EGL_DEVICE", "-1")
    rc, _o, err = run(capsys, "viewmorph", "l.png", "r.png", "-o", "o.png")
    assert rc == 2 and "MORPHKIT_EGL_DEVICE: expected an integer in [0, 1023]" in one_line(err)


# ------------------------------------------------------------------ warnings
def test_a_warning_is_one_line(monkeypatch, capsys):
    from morphkit.programs import cliargs

    def warn(_args):
        warnings.warn("the texture of 'box' could not\nbe read; drawn grey", UserWarning, stacklevel=1)

    monkeypatch.setattr(cliargs, "_CHECKS", {"viewmorph": warn})
    monkeypatch.setattr("morphkit.cli._cmd_viewmorph", lambda _a: 0)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        rc = main(["viewmorph", "l.png", "r.png", "-o", "o.png"])
    err = capsys.readouterr().err
    assert rc == 0 and err == "morphkit: warning: the texture of 'box' could not be read; drawn grey\n", err
    assert warnings.showwarning.__module__ == "warnings"  # Python's own printer is back
