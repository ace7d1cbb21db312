"""What a run leaves behind: a refused run, a terminated one (SIGTERM), an interrupted bake on Dask
workers, and a finished folder (one file of morphkit's own, one frame pattern)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import trimesh
from clirun import one_line, run

from morphkit.bake import cluster as bake_cluster

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT)}


def start(*argv: object) -> subprocess.Popen:
    """``python -m morphkit ARGV`` in its own process group (a terminal's Ctrl-C signals the whole
    group), SIGINT and SIGTERM at their defaults (a test started in the background by a
    non-interactive shell inherits SIGINT ignored, and Python then installs no handler for it)."""

    def defaults() -> None:
        os.setpgrp()
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)

    return subprocess.Popen([sys.executable, "-m", "morphkit", *map(str, argv)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=ENV, preexec_fn=defaults)


def wait_for(p: subprocess.Popen, ready: Callable[[], bool], timeout: float = 120.0) -> None:
    """Return once ``ready()``; fail if the process ended first."""
    deadline = time.monotonic() + timeout
    while not ready():
        assert p.poll() is None, p.communicate()
        assert time.monotonic() < deadline, "the run never got there"
        time.sleep(0.02)


def boxes(folder: Path, n: int) -> Path:
    """``n`` small meshes (different shapes) in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        trimesh.creation.box([1.0, 0.5 + 0.02 * i, 0.8]).export(folder / f"box{i:02d}.ply")
    return folder


# ------------------------------------------------------------------ Ctrl-C and Dask workers
def test_local_workers_never_take_sigint_and_the_callers_mask_is_restored():
    before = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    with bake_cluster.open_client(workers=1) as client:
        blocked = client.run(lambda: signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, []))
        assert signal.pthread_sigmask(signal.SIG_BLOCK, []) == before
    assert list(blocked.values()) == [True]
    assert signal.pthread_sigmask(signal.SIG_BLOCK, []) == before


@pytest.mark.gl
def test_ctrl_c_during_a_dome_bake_is_one_line_and_no_worker_traceback(tmp_path):
    lib = boxes(tmp_path / "lib", 16)  # more work than two workers finish before the interrupt
    out = tmp_path / "out"
    p = start("bake", lib, "-o", out, "--workers", "2", "--dome", "-q")
    # a worker has baked (or is writing) an asset: the workers are mid-task
    wait_for(p, lambda: out.is_dir() and any(f.name.endswith(".npz") for f in out.iterdir()))
    os.killpg(p.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the parent and every worker
    stdout, stderr = p.communicate(timeout=120)
    assert (p.returncode, stderr) == (130, "morphkit: interrupted\n"), stderr[-3000:]
    assert not [f.name for f in out.iterdir() if ".part" in f.name]


# ------------------------------------------------------------------ SIGTERM, and what a killed run left
def test_sigterm_unwinds_like_ctrl_c_one_line_exit_143_handlers_restored():
    # in a child: SIGTERM at its default would end the test process itself on a version without
    # the handler
    script = """if True:
        import os, signal, sys, time
        from morphkit import cli

        def command(args):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
            print("not reached")
            return 0

        cli._cmd_demo = command
        rc = cli.main(["demo", "-o", "unused"])
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL, signal.getsignal(signal.SIGTERM)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
        sys.exit(rc)
    """
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=ENV, timeout=60,
                       preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert (r.returncode, r.stdout, r.stderr) == (143, "", "morphkit: terminated\n")


def test_an_ignored_sigterm_stays_ignored():
    script = """if True:
        import signal, sys
        from morphkit import cli

        cli._cmd_demo = lambda args: int(signal.getsignal(signal.SIGTERM) is signal.SIG_IGN)
        sys.exit(cli.main(["demo", "-o", "unused"]))
    """
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=ENV, timeout=60,
                       preexec_fn=lambda: signal.signal(signal.SIGTERM, signal.SIG_IGN))
    assert (r.returncode, r.stderr) == (1, "")


def test_only_morphkits_own_temporary_names_are_taken_for_a_killed_runs():
    from morphkit.files.outfolder import TEMPORARY

    for name in (".frame_0003.k2x_9abc.part.png", ".billboards.b5jtfs0u.part.webm",
                 ".manifest.ab12cd34.part.json", ".morphkit-probe-ab12cd34", ".morphkit-probe-ab12cd34.webm",
                 ".billboards.ab12cd34.webm", ".shadows.ab12cd34.mp4"):
        assert TEMPORARY.match(name), name
    for name in (".billboards.webm", ".notes.ab12cd34.webm", "billboards.ab12cd34.webm", ".frame_0003.png",
                 ".billboards.ab12.part.webm", ".shadows.AB12CD34.webm", ".morphkit-output.json",
                 "notes.part.txt"):
        assert not TEMPORARY.match(name), name


def _dotfiles(folder: Path) -> list[str]:
    return sorted(f.relative_to(folder).as_posix() for f in folder.rglob(".*"))


BILLBOARDS = ("billboards", "--asset", "tree", "--n", "3", "--size", "64x48", "--asset-size", "32")


@pytest.mark.gl
def test_sigterm_mid_billboards_is_one_line_exit_143_and_leaves_no_temporary(tmp_path):
    out = tmp_path / "out"
    p = start(*BILLBOARDS, "--frames", "400", "-o", out)  # far more frames than it draws before the signal
    wait_for(p, lambda: (out / "frames" / "frame_0000.png").exists())  # mid-run: its video is half written
    p.send_signal(signal.SIGTERM)
    _stdout, stderr = p.communicate(timeout=120)
    assert (p.returncode, stderr) == (143, "morphkit: terminated\n")
    assert _dotfiles(out) == [".morphkit-output.json"]  # the marker only: no half video, no half frame


@pytest.mark.gl
def test_a_later_run_removes_what_a_killed_run_left_half_written_and_nothing_else(tmp_path, capfd):

    out = tmp_path / "out"
    p = start(*BILLBOARDS, "--frames", "400", "-o", out)
    wait_for(p, lambda: (out / "frames" / "frame_0000.png").exists())
    p.kill()  # SIGKILL: nothing of it can clean up
    p.communicate(timeout=60)
    left = [n for n in _dotfiles(out) if n != ".morphkit-output.json"]
    assert left and all(".part" in n for n in left), left  # its half-written video
    (out / ".billboards.ab12cd34.webm").write_bytes(b"an older version's half video")
    mine = [".billboards.webm", ".notes.ab12cd34.webm", "frames/.keep"]  # the user's
    for name in mine:
        (out / name).write_text("mine")
    rc, _out, err = run(capfd, *BILLBOARDS, "--frames", "2", "-o", out, "--overwrite")
    assert rc == 0, err
    assert _dotfiles(out) == sorted([".morphkit-output.json", *mine])


# ------------------------------------------------------------------ a run refused once it claimed its folder
def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every file (its bytes) and folder under ``folder``."""
    return {p.relative_to(folder).as_posix(): (p.read_bytes() if p.is_file() else None)
            for p in sorted(folder.rglob("*"))}


def no_video_writer(*_a: object, **_k: object) -> None:
    """What an OpenCV build without VP9 answers (morphkit.files.fileio.open_video_writer)."""
    from morphkit.errors import RenderError

    raise RenderError("video writer: expected OpenCV's VP90 writer for .webm files, got none in this "
                      "OpenCV build")


@pytest.mark.gl
def test_a_refused_billboards_run_leaves_the_folder_as_it_was_and_overwrite_works(tmp_path, capfd,
                                                                                  monkeypatch):
    import morphkit.programs.sequence as sequence

    out = tmp_path / "out"
    with monkeypatch.context() as m:
        m.setattr(sequence, "VideoFile", no_video_writer)  # refused after frames/ was made
        rc, _o, err = run(capfd, *BILLBOARDS, "--frames", "2", "-o", out)
        assert rc == 1 and "VP90 writer" in one_line(err)
        assert not out.exists()
        assert run(capfd, *BILLBOARDS, "--frames", "2", "-o", out)[0] == 1  # the same refusal again
        assert not out.exists()
    assert run(capfd, *BILLBOARDS, "--frames", "2", "-o", out)[0] == 0
    before = snapshot(out)
    with monkeypatch.context() as m:
        m.setattr(sequence, "VideoFile", no_video_writer)
        assert run(capfd, *BILLBOARDS, "--frames", "3", "-o", out, "--overwrite")[0] == 1
    assert snapshot(out) == before  # the previous run, its marker ("complete") included
    rc, _o, err = run(capfd, *BILLBOARDS, "--frames", "3", "-o", out, "--overwrite")
    assert rc == 0, err
    assert (out / "frames" / "frame_0002.png").is_file()
    # the empty frames/ an older version left is no obstacle, with or without --overwrite
    for extra in ((), ("--overwrite",)):
        old = tmp_path / f"old{len(extra)}"
        (old / "frames").mkdir(parents=True)
        rc, _o, err = run(capfd, *BILLBOARDS, "--frames", "2", "-o", old, *extra)
        assert rc == 0, err


@pytest.fixture(scope="module")
def atlas_file(tmp_path_factory) -> Path:
    """A small baked shadow atlas (its folder holds the bake's manifest, which names the mesh)."""
    from morphkit.cli import main

    root = tmp_path_factory.mktemp("bake")
    trimesh.creation.box([0.4, 0.4, 0.6]).export(root / "box.ply")
    assert main(["bake", str(root / "box.ply"), "-o", str(root / "out"), "--workers", "1",
                 "--atlas-size", "32", "--grid", "2", "-q"]) == 0
    return root / "out" / "box.atlas.npz"


@pytest.mark.gl
def test_a_refused_shadows_run_leaves_the_folder_as_it_was(tmp_path, capfd, atlas_file):

    out = tmp_path / "out"
    assert run(capfd, "shadows", atlas_file, "--frames", "2", "--size", "32", "-q", "-o", out)[0] == 0
    (out / "notes.txt").write_text("mine")
    before = snapshot(out)
    far = tmp_path / "far.csv"
    far.write_text("0,0\n50,50\n")  # found outside the atlas's range once the folder is claimed
    argv = ("shadows", atlas_file, "--path", far, "--size", "32", "-q")
    rc, _o, err = run(capfd, *argv, "-o", out, "--overwrite")
    assert rc == 1 and "range" in one_line(err)
    assert snapshot(out) == before
    assert run(capfd, *argv, "-o", tmp_path / "new")[0] == 1
    assert not (tmp_path / "new").exists()


def test_a_refused_demo_leaves_the_previous_demo_as_it_was(tmp_path, capfd, monkeypatch):
    import morphkit.programs.demo
    from morphkit.errors import RenderError
    from morphkit.files.outfolder import DEMO_OUTPUT, claim_output

    out = tmp_path / "out"
    with claim_output(out, DEMO_OUTPUT).writing():  # a finished demo, as run_demo leaves it
        (out / "cow_scene.png").write_bytes(b"png")
        (out / "index.json").write_text('{"morphkit_demo": 1, "files": [{"path": "cow_scene.png"}]}')
    before = snapshot(out)

    def no_gl() -> None:
        raise RenderError("GL context: expected one (OSMesa or EGL), got none")

    monkeypatch.setattr(morphkit.programs.demo, "Renderer", no_gl)
    rc, _o, err = run(capfd, "demo", "--quick", "-o", out, "--overwrite")
    assert rc == 1 and "GL context" in one_line(err)
    assert snapshot(out) == before


# ------------------------------------------------------------------ one frame pattern, one file of its own
def viewmorph_inputs(folder: Path) -> tuple[Path, Path, Path]:
    """Two images of one textured scene (the second shifted 4 px) and their correspondences."""
    import cv2
    import numpy as np

    from morphkit.files.fileio import write_image

    folder.mkdir(parents=True, exist_ok=True)
    img = cv2.GaussianBlur((np.random.default_rng(0).random((96, 128, 3)) * 255).astype(np.uint8), (0, 0), 3)
    left, right = write_image(folder / "l.png", img), write_image(folder / "r.png", np.roll(img, 4, axis=1))
    points = folder / "p.csv"
    rows = [f"{x},{y},{x + 4},{y}" for x in range(20, 100, 15) for y in range(20, 80, 15)]
    points.write_text("\n".join(rows))
    return left, right, points


def listing(folder: Path) -> list[str]:
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*"))


def test_viewmorph_frames_follow_the_one_pattern_and_overwrite_an_old_layout(tmp_path, capfd):
    from morphkit.files.outfolder import MARKER_NAME, frame_name

    left, right, points = viewmorph_inputs(tmp_path / "in")
    argv = ("viewmorph", left, right, "--points", points, "--prewarp", "none")
    out = tmp_path / "out"
    rc, _o, err = run(capfd, *argv, "--frames", "3", "-o", out)
    assert rc == 0, err
    assert listing(out) == [MARKER_NAME, "frames", "frames/frame_0000.png", "frames/frame_0001.png",
                            "frames/frame_0002.png"]
    assert frame_name(2) == "frames/frame_0002.png"
    # folders an older version left: frame_NNN.png in the folder itself, with its record or without
    for record in (True, False):
        old = tmp_path / f"old-{record}"
        old.mkdir()
        names = ["frame_000.png", "frame_001.png", "frame_002.png"]
        for name in names:
            (old / name).write_bytes(b"old frame")
        (old / "notes.txt").write_text("mine")
        marker = {"morphkit_output": 1, "command": "viewmorph", "status": "complete"}
        (old / MARKER_NAME).write_text(json.dumps({**marker, "files": names} if record else marker))
        assert run(capfd, *argv, "--frames", "2", "-o", old)[0] == 2  # a previous run: --overwrite
        rc, _o, err = run(capfd, *argv, "--frames", "2", "-o", old, "--overwrite")
        assert rc == 0, err
        assert listing(old) == [MARKER_NAME, "frames", "frames/frame_0000.png", "frames/frame_0001.png",
                                "notes.txt"]


@pytest.mark.gl
def test_every_command_names_its_frames_alike_and_keeps_one_file_of_its_own(tmp_path, capfd, atlas_file):
    from morphkit.files.outfolder import MARKER_NAME

    two = ["frames", "frames/frame_0000.png", "frames/frame_0001.png"]
    rc, _o, err = run(capfd, *BILLBOARDS, "--frames", "2", "-o", tmp_path / "bb")
    assert rc == 0, err
    assert listing(tmp_path / "bb") == sorted([MARKER_NAME, *two, "billboards.json", "billboards.webm",
                                               "compare_0000.png", "compare_0001.png"])
    rc, _o, err = run(capfd, "shadows", atlas_file, "--frames", "2", "--size", "32", "-q",
                      "-o", tmp_path / "sh")
    assert rc == 0, err
    assert listing(tmp_path / "sh") == sorted([MARKER_NAME, *two, "shadows.webm"])
    left, right, points = viewmorph_inputs(tmp_path / "in")
    rc, _o, err = run(capfd, "viewmorph", left, right, "--points", points, "--prewarp", "none",
                      "--frames", "2", "-o", tmp_path / "vm")
    assert rc == 0, err
    assert listing(tmp_path / "vm") == sorted([MARKER_NAME, *two])
    assert listing(atlas_file.parent) == sorted([MARKER_NAME, "box.atlas.npz", "manifest.json"])
