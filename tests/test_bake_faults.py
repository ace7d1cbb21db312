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

import contextlib
import hashlib
import logging
import os
import re
import signal
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import pytest
import trimesh

from morphkit.bake import BakeOptions, Manifest, ShadowAtlasKind, bake_library
from morphkit.bake.manifest import JOURNAL_NAME
from morphkit.cli import main
from morphkit.files import fileio
from morphkit.shadow import ShadowAtlas

ROOT = Path(__file__).resolve().parents[1]
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


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


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


# ------------------------------------------------------------------ the output's file system
@contextlib.contextmanager
def tmpfs(path: Path, size: str):
    """A tmpfs of ``size`` mounted at ``path`` (unmounted at the end); skips where mounting is not
    permitted (not root, no mount command, a container without CAP_SYS_ADMIN)."""
    path.mkdir(parents=True)
    try:
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(path)],
                           capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError) as exc:
        pytest.skip(f"cannot mount a tmpfs here ({exc})")
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here (root with mount permission needed): {r.stderr.strip()}")
    try:
        yield path
    finally:
        if subprocess.run(["umount", str(path)], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", str(path)], capture_output=True)  # busy: detach it


def remount(path: Path, options: str) -> None:
    """``mount -o remount,OPTIONS path``, retried while a writer keeps it busy (a worker mid-save)."""
    deadline = time.monotonic() + 30
    while True:
        r = subprocess.run(["mount", "-o", f"remount,{options}", str(path)], capture_output=True, text=True)
        if r.returncode == 0:
            return
        assert "busy" in r.stderr and time.monotonic() < deadline, r.stderr
        time.sleep(0.01)


def cli_bake(capfd, lib: Path, out: Path, scheduler: str) -> tuple[int, str]:
    rc = main(["bake", str(lib), "-o", str(out), "--atlas-size", "32", "--grid", "3", "--scheduler",
               scheduler, "-q"])
    return rc, capfd.readouterr().err


def assert_intact(out: Path, clean: dict[str, str]) -> Manifest:
    """Every atlas in ``out`` is whole (loads, the bytes of a clean bake), the manifest is valid and
    names only files that are there with its hash, and no temporary file is left."""
    for name, digest in outputs(out).items():
        ShadowAtlas.load(out / name)
        assert digest == clean[name], name
    m = Manifest.open(out)
    for rec in m.assets.values():
        for o in rec.outputs.values():
            assert sha(out / o.file) == o.sha256
    assert not [p.name for p in out.rglob("*") if ".part" in p.name]
    return m


def stopped(out: Path, disk: Path, code: str, text: str) -> str:
    """The pattern of the one line of a bake stopped by a write its file system refused."""
    return (rf"morphkit: error: bake output folder '{re.escape(str(out))}': expected a file system that "
            rf"takes every output, got {code} \({text}\) writing (the output of '\w+'|the manifest), on the "
            rf"file system mounted at {re.escape(str(disk))} \(\d+ bytes free\); the bake stopped: "
            r"\d+ assets? baked and kept, \d+ not baked \(free space or make the folder writable, then run "
            r"the bake again\)")


@pytest.mark.gl
def test_a_full_disk_stops_the_bake_with_one_line_and_a_rerun_after_freeing_space_finishes(
        tmp_path, cluster, clean, capfd, monkeypatch):
    lib = make_library(tmp_path / "lib")
    with tmpfs(tmp_path / "disk", "300k") as disk:  # room for two of the four atlases (~120 kB each)
        out = disk / "out"
        journal = Journaled(monkeypatch)
        rc, err = cli_bake(capfd, lib, out, cluster.scheduler_address)
        assert rc == 1
        line = one_line(err)
        assert re.fullmatch(stopped(out, disk, "ENOSPC", "No space left on device"), line), line
        m = assert_intact(out, clean)
        kept = journal.baked()
        assert 1 <= len(kept) < len(MESHES) and all(m.assets[k].status == "baked" for k in kept)
        assert f"{len(kept)} asset" in line

        remount(disk, "size=4m")  # space freed
        rc, err = cli_bake(capfd, lib, out, cluster.scheduler_address)
        assert rc == 0, err
        m = assert_intact(out, clean)
        assert outputs(out) == clean and leftovers(out) == []
        assert {k for k, r in m.assets.items() if r.status == "skipped"} == set(kept)  # not baked again
        assert journal.baked() == dict.fromkeys(MESHES, 1)  # every asset baked once over both runs


@pytest.mark.gl
def test_an_output_folder_made_read_only_half_way_stops_the_bake_and_a_rerun_finishes(
        tmp_path, cluster, clean, capfd, monkeypatch):
    lib = make_library(tmp_path / "lib")
    with tmpfs(tmp_path / "disk", "4m") as disk:
        out = disk / "out"

        def read_only_after_the_first(j: Journaled) -> None:  # called after each journaled batch
            if not getattr(j, "ro", False):
                remount(disk, "ro")  # as root chmod would not stop a write; a read-only mount does
                j.ro = True

        journal = Journaled(monkeypatch, after=read_only_after_the_first)
        rc, err = cli_bake(capfd, lib, out, cluster.scheduler_address)
        assert rc == 1
        line = one_line(err)
        assert re.fullmatch(stopped(out, disk, "EROFS", "Read-only file system"), line), line
        kept = journal.baked()
        assert 1 <= len(kept) < len(MESHES)
        remount(disk, "rw")  # writable again
        m = assert_intact(out, clean)
        assert all(m.assets[k].status == "baked" for k in kept)

        monkeypatch.undo()
        journal = Journaled(monkeypatch)
        rc, err = cli_bake(capfd, lib, out, cluster.scheduler_address)
        assert rc == 0, err
        m = assert_intact(out, clean)
        assert outputs(out) == clean and leftovers(out) == []
        assert {k for k, r in m.assets.items() if r.status == "skipped"} == set(kept)  # not baked again
        assert sorted([*kept, *journal.baked()]) == sorted(MESHES)  # every asset baked once in all


# ------------------------------------------------------------------ the driver SIGKILLed, in a loop
@pytest.mark.gl
@pytest.mark.slow  # ~20-30 s on 2 busy cores: each run is a new `python -m morphkit bake` whose
# interpreter and local Dask cluster take ~4-6 s to start (the full loop: scripts/bake_kill_loop.py)
def test_a_reduced_kill_loop_loses_nothing_and_bakes_nothing_twice(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("bake_kill_loop", ROOT / "scripts" / "bake_kill_loop.py")
    loop = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loop)
    # 3 runs, each SIGKILLed (driver and worker) 0-0.3 s after it wrote its first atlas: mid-bake
    r = loop.kill_loop(3, 28, inputs=4, changed=3, atlas_size=64, workers=1, kill_s=(0.0, 0.3),
                       after_first=True, root=tmp_path)
    print(r["outcomes"], r["last_stdout"])
    assert r["killed"] >= 1, r["outcomes"]
    assert r["last_rc"] == 0, r["last_stdout"]
    assert r["assets"] == 4 and r["counts"]["failed"] == 0 and r["atlases"] == 4
    assert r["baked_twice"] == 0  # no (asset, input version) recorded as baked twice
    assert r["bad_hashes"] == [] and r["temporary"] == [] and not r["journal_left"]
