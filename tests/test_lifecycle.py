"""What a run leaves behind: a refused run, a terminated one (SIGTERM), an interrupted bake on Dask
workers, and a finished folder (one file of morphkit's own, one frame pattern)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import trimesh

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
    from morphkit.outfolder import TEMPORARY

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
    from clirun import run

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
