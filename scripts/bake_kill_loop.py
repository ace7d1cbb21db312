"""The bake's kill loop (issue 28): SIGKILL ``morphkit bake`` at random moments, then rerun.

Each of RUNS runs first gives 4 of the 12 inputs a new version (so every run has work), starts
``python -m morphkit bake`` (2 local workers) in its own process group and kills the whole group
(driver and workers) with SIGKILL after a random 0.5-9 s, unless it finished first. A last run
completes the bake. Printed: the runs (killed or finished), the final run's line, how many times
each (asset, input version) was recorded as baked over all runs (1 = no finished asset baked
again), the outputs whose hash differs from the manifest, temporary files left, and whether every
atlas loads.

Usage: python scripts/bake_kill_loop.py [RUNS] [SEED]   (default 20 runs, seed 28; ~4 min on 2 cores)

:func:`kill_loop` is the loop with its sizes as parameters (a reduced run is a test:
``tests/test_bake_faults.py``).
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import trimesh

from morphkit.bake import Manifest
from morphkit.shadow import ShadowAtlas


def _input(lib: Path, k: int, version: int) -> None:
    trimesh.creation.icosphere(subdivisions=2, radius=0.3 + 0.02 * k + 0.001 * version).export(
        lib / f"s{k:02d}.ply")


def _recorded(out: Path) -> set[tuple[str, str, str]]:
    """``(name, input sha, updated)`` of every baked record in the manifest and the journal."""
    recs = []
    if (out / "manifest.json").exists():
        recs += json.loads((out / "manifest.json").read_text())["assets"].values()
    if (out / "manifest.journal").exists():
        for line in (out / "manifest.journal").read_text().splitlines():
            try:
                recs.append(json.loads(line))
            except ValueError:  # a truncated last line
                pass
    return {(r["name"], r["input_sha256"], r["updated"]) for r in recs if r["status"] == "baked"}


def _wrote_since(out: Path, t: float) -> bool:
    """An atlas in ``out`` was written at or after ``t`` (seconds since the epoch)."""
    for f in out.glob("*.atlas.npz"):
        try:
            if f.stat().st_mtime >= t:
                return True
        except FileNotFoundError:
            pass
    return False


def kill_loop(runs: int = 20, seed: int = 28, *, inputs: int = 12, changed: int = 4, atlas_size: int = 128,
              workers: int = 2, kill_s: tuple[float, float] = (0.5, 9.0), after_first: bool = False,
              root: Path | None = None) -> dict[str, Any]:
    """Run the loop in ``root`` (default: a new temporary folder) and return its outcome.

    Parameters
    ----------
    runs : int
        Killed (or finished) runs before the last, complete one.
    seed : int
        Seed of the kill moments and of the inputs changed each run.
    inputs : int
        Meshes in the library.
    changed : int
        Inputs given a new version before each run.
    atlas_size : int
        ``--atlas-size`` of the bake.
    workers : int
        ``--workers`` of the bake.
    kill_s : (float, float)
        The kill moment is drawn uniformly in this range (seconds after the start).
    after_first : bool
        Count the kill moment from when the run has written its first atlas instead of from its
        start: every kill lands mid-bake, none in the start-up
        of Python and the Dask cluster (a short loop's runs would otherwise mostly die there).
    root : pathlib.Path, optional
        Where the library (``lib``) and the output (``out``) go.

    Returns
    -------
    dict
        ``outcomes`` (one line per run: killed at / finished), ``killed``, ``last_rc``,
        ``last_stdout``, ``counts`` (the final manifest's baked/skipped/failed), ``versions``
        (asset-version pairs baked), ``baked_twice`` (pairs recorded as baked more than once:
        a finished asset baked again), ``bad_hashes`` (outputs differing from the manifest),
        ``temporary`` (temporary files left), ``journal_left``, ``atlases`` (atlases that
        load), ``out``.
    """
    rng = random.Random(seed)
    root = Path(tempfile.mkdtemp(prefix="morphkit-kill-loop-")) if root is None else Path(root)
    lib, out = root / "lib", root / "out"
    lib.mkdir(parents=True)
    for k in range(inputs):
        _input(lib, k, 0)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    cmd = [sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(out), "--workers", str(workers),
           "--atlas-size", str(atlas_size), "-q"]
    seen: set[tuple[str, str, str]] = set()
    outcomes = []
    for run in range(runs):
        for k in rng.sample(range(inputs), changed):
            _input(lib, k, run + 1)
        started = time.time()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                             start_new_session=True)
        t = rng.uniform(*kill_s)
        if after_first:  # until this run wrote its first atlas
            deadline = time.monotonic() + 300
            while p.poll() is None and not _wrote_since(out, started) and time.monotonic() < deadline:
                time.sleep(0.01)
        try:
            p.wait(timeout=t)
            outcomes.append(f"finished (exit {p.returncode})")
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
            outcomes.append(f"killed at {t:.1f} s" + (" after its first atlas" if after_first else ""))
        try:
            os.killpg(p.pid, signal.SIGKILL)  # worker processes still alive
        except ProcessLookupError:
            pass
        seen |= _recorded(out)
    last = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
    seen |= _recorded(out)
    m = Manifest.open(out)
    times: dict[tuple[str, str], int] = {}
    for name, sha, _updated in seen:
        times[(name, sha)] = times.get((name, sha), 0) + 1
    bad = [o.file for r in m.assets.values() for o in r.outputs.values()
           if hashlib.sha256((out / o.file).read_bytes()).hexdigest() != o.sha256]
    atlases = 0
    for f in sorted(out.glob("*.atlas.npz")):
        ShadowAtlas.load(f)  # a corrupt file raises
        atlases += 1
    counts = {s: sum(r.status == s for r in m.assets.values()) for s in ("baked", "skipped", "failed")}
    return {"outcomes": outcomes, "killed": sum(o.startswith("killed") for o in outcomes),
            "last_rc": last.returncode, "last_stdout": last.stdout.strip(), "counts": counts,
            "assets": len(m.assets), "versions": len(times),
            "baked_twice": sum(v > 1 for v in times.values()),
            "bad_hashes": bad, "temporary": [str(f) for f in out.rglob("*") if ".part" in f.name],
            "journal_left": (out / "manifest.journal").exists(), "atlases": atlases, "out": out}


def main(runs: int = 20, seed: int = 28) -> None:
    """Run the loop (:func:`kill_loop`, the defaults above) in a temporary folder and print its outcome.

    Parameters
    ----------
    runs : int
        Killed (or finished) runs before the last, complete one.
    seed : int
        Seed of the kill moments and of the inputs changed each run.
    """
    r = kill_loop(runs, seed)
    outcomes = r["outcomes"]
    print(f"{runs} runs: {r['killed']} killed, {len(outcomes) - r['killed']} finished: {outcomes}")
    print(f"last run: exit {r['last_rc']}: {r['last_stdout']}")
    print(f"assets {r['assets']}: " + ", ".join(f"{s} {n}" for s, n in r["counts"].items()))
    print(f"(asset, input version) pairs baked: {r['versions']}; baked more than once: {r['baked_twice']}")
    print(f"outputs differing from the manifest: {r['bad_hashes']}; temporary files left: {r['temporary']}; "
          f"journal left: {r['journal_left']}; every atlas loads ({r['atlases']})")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
