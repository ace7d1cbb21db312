"""The bake's kill loop (issue 28): SIGKILL ``morphkit bake`` at random moments, then rerun.

Each of RUNS runs first gives 4 of the 12 inputs a new version (so every run has work), starts
``python -m morphkit bake`` (2 local workers) in its own process group and kills the whole group
(driver and workers) with SIGKILL after a random 0.5-9 s, unless it finished first. A last run
completes the bake. Printed: the runs (killed or finished), the final run's line, how many times
each (asset, input version) was recorded as baked over all runs (1 = no finished asset baked
again), the outputs whose hash differs from the manifest, temporary files left, and whether every
atlas loads.

Usage: python scripts/bake_kill_loop.py [RUNS] [SEED]   (default 20 runs, seed 28; ~4 min on 2 cores)
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
from pathlib import Path

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


def main(runs: int = 20, seed: int = 28) -> None:
    """Run the loop in a temporary folder and print its outcome.

    Parameters
    ----------
    runs : int
        Killed (or finished) runs before the last, complete one.
    seed : int
        Seed of the kill moments and of the inputs changed each run.
    """
    rng = random.Random(seed)
    root = Path(tempfile.mkdtemp(prefix="morphkit-kill-loop-"))
    lib, out = root / "lib", root / "out"
    lib.mkdir()
    for k in range(12):
        _input(lib, k, 0)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    cmd = [sys.executable, "-m", "morphkit", "bake", str(lib), "-o", str(out), "--workers", "2",
           "--atlas-size", "128", "-q"]
    seen: set[tuple[str, str, str]] = set()
    outcomes = []
    for run in range(runs):
        for k in rng.sample(range(12), 4):
            _input(lib, k, run + 1)
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                             start_new_session=True)
        t = rng.uniform(0.5, 9.0)
        try:
            p.wait(timeout=t)
            outcomes.append(f"finished (exit {p.returncode})")
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
            outcomes.append(f"killed at {t:.1f} s")
        try:
            os.killpg(p.pid, signal.SIGKILL)  # worker processes still alive
        except ProcessLookupError:
            pass
        seen |= _recorded(out)
    last = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
    seen |= _recorded(out)
    print(f"{runs} runs: {sum(o.startswith('killed') for o in outcomes)} killed, "
          f"{sum(o.startswith('finished') for o in outcomes)} finished: {outcomes}")
    print(f"last run: exit {last.returncode}: {last.stdout.strip()}")
    m = Manifest.open(out)
    times: dict[tuple[str, str], int] = {}
    for name, sha, _updated in seen:
        times[(name, sha)] = times.get((name, sha), 0) + 1
    print(f"assets {len(m.assets)}: " + ", ".join(
        f"{s} {sum(r.status == s for r in m.assets.values())}" for s in ("baked", "skipped", "failed")))
    print(f"(asset, input version) pairs baked: {len(times)}; baked more than once: "
          f"{sum(v > 1 for v in times.values())}")
    bad = [o.file for r in m.assets.values() for o in r.outputs.values()
           if hashlib.sha256((out / o.file).read_bytes()).hexdigest() != o.sha256]
    for f in sorted(out.glob("*.atlas.npz")):
        ShadowAtlas.load(f)  # a corrupt file raises
    temps = [str(f) for f in out.rglob("*") if ".part" in f.name]
    print(f"outputs differing from the manifest: {bad}; temporary files left: {temps}; "
          f"journal left: {(out / 'manifest.journal').exists()}; every atlas loads")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
