"""Inputs that hung, ran out of memory or drew nothing: each is refused (or ignored) up front.

Counts of ``morphkit bench`` against their caps, hostile glTF node graphs, dome files of
negative depths, lights that cannot reach the ground, and files of other programs that
carry morphkit's names. The CLI cases run the real entry point in a subprocess under a
timeout and an address-space limit, so that code which would work on the input instead of
refusing it fails the test rather than the machine.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
from pathlib import Path

import pytest

from morphkit import tol

ROOT = Path(__file__).resolve().parents[1]
ENV = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "OMP_NUM_THREADS": "1",
       "OPENBLAS_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1", "HOME": os.environ.get("HOME", "/tmp")}
#: Address space a refused command runs in: the imports take well under it; a command that
#: allocates for a count of 10^9 does not.
MEMORY_LIMIT = 4 * 2**30


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def morphkit_cli(*argv: str | Path, timeout: float = 120) -> tuple[int, str]:
    """Run ``python -m morphkit ARGV``; return its exit code and its one stderr line."""
    r = subprocess.run([sys.executable, "-m", "morphkit", *map(str, argv)], capture_output=True, text=True,
                       env=ENV, timeout=timeout, preexec_fn=_limit_memory, cwd=ROOT)
    lines = r.stderr.strip().splitlines()
    assert "Traceback" not in r.stderr, r.stderr[-2000:]
    assert len(lines) == 1 and lines[0].startswith("morphkit: error: "), lines[-5:]
    return r.returncode, lines[0]


# ------------------------------------------------------------ bench counts


def _want(what: str, cap: int, got: int) -> str:
    return rf"{what}: expected an integer in \[1, {cap}\], got {got}"


@pytest.mark.parametrize("argv, match", [
    (("scene", "--instances", "1000000000"), _want("--instances", tol.MAX_BENCH_INSTANCES, 1000000000)),
    (("scene", "--instances", "10", "0"), _want("--instances", tol.MAX_BENCH_INSTANCES, 0)),
    (("bake", "--workers", "1", "100000"), _want("--workers", tol.MAX_LOCAL_WORKERS, 100000)),
    (("bake", "--workers", "-2"), _want("--workers", tol.MAX_LOCAL_WORKERS, -2)),
    (("bake", "--assets", "1000000000"), _want("--assets", tol.MAX_BENCH_ASSETS, 1000000000)),
], ids=["instances-1e9", "instances-0", "workers-1e5", "workers-negative", "assets-1e9"])
def test_bench_counts_are_capped_before_any_work(argv, match):
    import re

    rc, line = morphkit_cli("bench", *argv)
    assert rc == 1
    assert re.search(match, line), line


@pytest.mark.parametrize("call, match", [
    ("scene_suite.run(instances=[10**9])", _want("instances", tol.MAX_BENCH_INSTANCES, 1000000000)),
    ("bake_suite.run(workers=[10**6])", _want("workers", tol.MAX_LOCAL_WORKERS, 1000000)),
    ("bake_suite.run(assets=10**9)", _want("library assets", tol.MAX_BENCH_ASSETS, 1000000000)),
], ids=["scene-instances", "bake-workers", "bake-assets"])
def test_bench_suites_check_their_counts_too(call, match):
    """The API refuses the same counts (in a subprocess: code that took them would run the suite)."""
    import re

    r = subprocess.run([sys.executable, "-c", f"from morphkit.bench import bake_suite, scene_suite; {call}"],
                       capture_output=True, text=True, env=ENV, timeout=120, preexec_fn=_limit_memory,
                       cwd=ROOT)
    assert r.returncode == 1
    assert re.search("ValidationError: " + match, r.stderr.strip().splitlines()[-1]), r.stderr[-2000:]
