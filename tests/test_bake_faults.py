"""A bake against the faults of a real machine (issue 28): a worker process SIGKILLed mid-task,
the output disk full, the output folder turned read-only half way, a memory cap, the driver
SIGKILLed in a loop.

After each: the run finishes, or stops (or records the asset as failed) with a one-line error
that names the cause; a rerun finishes; every asset is baked once (no finished asset baked
again), and no partial or corrupt file is left.

The library is the tiny one of ``tests/test_bake.py`` (4 trimesh primitives, 32 x 32 atlases
on a 3 x 3 grid). The disk tests mount a small tmpfs (root only; skipped where ``mount`` is not
permitted).
"""

from __future__ import annotations

import hashlib
import logging
import os
import re
import signal
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import pytest
import trimesh

from morphkit import fileio
from morphkit.bake import BakeOptions, Manifest, ShadowAtlasKind, bake_library
from morphkit.bake.manifest import JOURNAL_NAME

TINY = ShadowAtlasKind(atlas_size=32, grid=3)
OPTS = BakeOptions((TINY,))
MESHES = {  # name -> builder; 4 small meshes, ply (the bake's up axis is +z for all)
    "box": lambda: trimesh.creation.box([1.0, 0.6, 0.8]),
    "ball": lambda: trimesh.creation.icosphere(subdivisions=1),
    "can": lambda: trimesh.creation.cylinder(radius=0.3, height=1.0, sections=8),
    "cone": lambda: trimesh.creation.cone(radius=0.4, height=0.9, sections=8),
}


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def make_library(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for name, build in MESHES.items():
        build().export(folder / f"{name}.ply")
    return folder


def outputs(out: Path) -> dict[str, str]:
    """``{output file: sha256}`` of every atlas in ``out``."""
    return {p.name: sha(p) for p in sorted(out.glob("*.atlas.npz"))}


def leftovers(out: Path) -> list[str]:
    """Temporary files (half written) and a journal left in ``out``."""
    return sorted(p.name for p in out.rglob("*") if ".part" in p.name or p.name == JOURNAL_NAME)


class Journaled:
    """Counts the records the driver journals per asset and status (``Manifest.record`` wrapped)."""

    def __init__(self, monkeypatch, after=None):
        self.records: list[tuple[str, str]] = []
        real = Manifest.record

        def record(m, *recs):
            real(m, *recs)
            self.records += [(r.name, r.status) for r in recs]
            if after is not None:
                after(self)

        monkeypatch.setattr(Manifest, "record", record)

    def baked(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for name, status in self.records:
            if status == "baked":
                out[name] = out.get(name, 0) + 1
        return out


@pytest.fixture(scope="module")
def cluster():
    """A local cluster of 2 worker processes (each under a nanny, which restarts a killed one)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                      silence_logs=logging.CRITICAL) as c:
        yield c


@pytest.fixture(scope="module")
def clean(tmp_path_factory, cluster) -> dict[str, str]:
    """The output hashes of an undisturbed bake of the library."""
    root = tmp_path_factory.mktemp("clean")
    m = bake_library([make_library(root / "lib")], root / "out", options=OPTS,
                     scheduler=cluster.scheduler_address, progress=False)
    assert m.run["baked"] == len(MESHES) and m.run["failed"] == 0
    return outputs(root / "out")


# ------------------------------------------------------------------ a worker SIGKILLed mid-task
@dataclass(frozen=True)
class HangingSave:
    """An atlas whose save writes half a temporary file, says so in ``marker`` (the pid) and waits
    to be killed (a worker process killed in the middle of writing its output)."""

    marker: str

    def save(self, target):
        with fileio.atomic_output(target) as tmp:
            tmp.write_bytes(b"PK\x03\x04 half an atlas")
            Path(self.marker).write_text(str(os.getpid()))
            time.sleep(120)  # killed long before
        raise AssertionError("the worker was not killed")


@dataclass(frozen=True)
class KillableKind:
    """The tiny atlas kind, except that the mesh with ``victim_faces`` faces hangs in its save
    (:class:`HangingSave`) while ``marker`` does not exist: the test SIGKILLs that worker."""

    marker: str
    victim_faces: int
    inner: ShadowAtlasKind = TINY
    name: ClassVar[str] = ShadowAtlasKind.name
    suffix: ClassVar[str] = ShadowAtlasKind.suffix
    version: ClassVar[int] = ShadowAtlasKind.version

    def options(self):
        return self.inner.options()

    def bake(self, mesh, renderer, source_up):
        if len(mesh.faces) == self.victim_faces and not os.path.exists(self.marker):
            return HangingSave(self.marker)
        return self.inner.bake(mesh, renderer, source_up)


def kill_when_marked(marker: Path, timeout: float = 120.0) -> threading.Thread:
    """A thread that SIGKILLs the process whose pid appears in ``marker``."""

    def run():
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                pid = int(marker.read_text())
            except (OSError, ValueError):
                time.sleep(0.02)
                continue
            os.kill(pid, signal.SIGKILL)
            return

    t = threading.Thread(target=run, daemon=True)
    t.start()
    return t


@pytest.mark.gl
def test_a_worker_sigkilled_mid_save_is_replaced_and_its_asset_baked_once(tmp_path, cluster, clean,
                                                                          monkeypatch):
    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    marker = tmp_path / "killed"
    kind = KillableKind(str(marker), len(MESHES["can"]().faces))
    journal = Journaled(monkeypatch)
    killer = kill_when_marked(marker)
    m = bake_library([lib], out, options=BakeOptions((kind,)), scheduler=cluster.scheduler_address,
                     progress=False)
    killer.join()
    pid = int(marker.read_text())
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)  # the worker that was saving is gone
    # Dask ran the task again on a live worker: the run finished, every asset baked once
    assert m.run["baked"] == len(MESHES) and m.run["failed"] == 0, m.failed()
    assert journal.baked() == dict.fromkeys(MESHES, 1)
    assert outputs(out) == clean
    assert leftovers(out) == []  # the killed worker's half-written temporary file is gone too


@pytest.mark.gl
def test_a_worker_killed_more_often_than_dask_allows_fails_its_asset_and_a_rerun_bakes_it(
        tmp_path, cluster, clean, monkeypatch):
    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    marker = tmp_path / "killed"
    monkeypatch.setattr(cluster.scheduler, "allowed_failures", 0)  # default 3: the first death is final
    kind = KillableKind(str(marker), len(MESHES["can"]().faces))
    journal = Journaled(monkeypatch)
    killer = kill_when_marked(marker)
    m = bake_library([lib], out, options=BakeOptions((kind,)), scheduler=cluster.scheduler_address,
                     progress=False)
    killer.join()
    failed = m.failed()
    # the killed worker's task failed; so did any task queued on that worker (Dask blames them too)
    assert "can" in failed and m.run["failed"] == len(failed) and m.run["baked"] == len(MESHES) - len(failed)
    for error in failed.values():
        assert re.fullmatch(r"KilledWorker: the worker process holding this task \(baking it, or with it "
                            r"queued\) died 1 time, more than Dask allows \(distributed\.scheduler\."
                            r"allowed-failures = 0; last worker tcp://[0-9.:]+\); a rerun bakes it",
                            error), error
    assert all(m.assets[k].outputs == {} and f"{k}.atlas.npz" not in outputs(out) for k in failed)
    assert leftovers(out) == []  # no half-written atlas, no journal
    first = journal.baked()
    monkeypatch.undo()  # the scheduler allows failures again; the journal counter goes

    journal = Journaled(monkeypatch)
    m = bake_library([lib], out, options=OPTS, scheduler=cluster.scheduler_address, progress=False)
    assert (m.run["baked"], m.run["skipped"], m.run["failed"]) == (len(failed), len(MESHES) - len(failed), 0)
    assert journal.baked() == dict.fromkeys(failed, 1)  # only the failed ones: nothing baked again
    assert sorted([*first, *journal.baked()]) == sorted(MESHES)  # every asset baked once over both runs
    assert outputs(out) == clean and leftovers(out) == []
