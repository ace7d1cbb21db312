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
