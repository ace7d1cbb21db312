"""morphkit.bake and the ``bake`` command: a library baked on Dask, incremental, nothing lost.

The GL tests share one local Dask cluster of 2 worker processes (module-scoped,
passed as ``scheduler=``, so they also exercise the ``--scheduler`` path); one
test starts the default local cluster (``workers=1``). Meshes are tiny
(trimesh primitives) and atlases 32 x 32 with a 3 x 3 grid.

Non-writable output: the tests run as root, where ``chmod`` does not stop a
write, so a folder that cannot be created is a path under a regular *file*,
and a permission error is simulated by making the probe file's creation fail.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
import trimesh

from morphkit.bake import (
    MANIFEST_NAME,
    BakeOptions,
    Manifest,
    ShadowAtlasKind,
    bake_library,
    check_writable,
    find_inputs,
)
from morphkit.bake import cluster as bake_cluster
from morphkit.bake import pipeline as bake_pipeline
from morphkit.bake.manifest import JOURNAL_NAME
from morphkit.cli import main
from morphkit.errors import ClusterError, MeshError, ValidationError
from morphkit.files import fileio
from morphkit.shadow import ATLAS_VERSION

TINY = ShadowAtlasKind(atlas_size=32, grid=3)
OPTS = BakeOptions((TINY,))
MESHES = {  # name -> (builder, suffix); the tests' library
    "box": (lambda: trimesh.creation.box([1.0, 0.6, 0.8]), ".ply"),
    "ball": (lambda: trimesh.creation.icosphere(subdivisions=1), ".obj"),
    "can": (lambda: trimesh.creation.cylinder(radius=0.3, height=1.0, sections=8), ".stl"),
    "sub/cone": (lambda: trimesh.creation.cone(radius=0.4, height=0.9, sections=8), ".ply"),
}


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def make_library(folder: Path, extra: dict[str, bytes] | None = None) -> Path:
    for name, (build, suffix) in MESHES.items():
        p = folder / f"{name}{suffix}"
        p.parent.mkdir(parents=True, exist_ok=True)
        build().export(p)
    for name, data in (extra or {}).items():
        (folder / name).write_bytes(data)
    return folder


def outputs(out: Path) -> dict[str, str]:
    """``{relative output file: sha256}`` of every atlas under ``out``."""
    return {p.relative_to(out).as_posix(): sha(p) for p in sorted(out.rglob("*.atlas.npz"))}


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                      silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address


@pytest.fixture(scope="module")
def clean(tmp_path_factory, scheduler) -> dict[str, str]:
    """The output hashes of a clean bake of the library (the reference of the fault tests)."""
    root = tmp_path_factory.mktemp("clean")
    m = bake_library([make_library(root / "lib")], root / "out", options=OPTS, scheduler=scheduler,
                     progress=False)
    assert m.run["baked"] == len(MESHES) and m.run["failed"] == 0
    return outputs(root / "out")


# ------------------------------------------------------------------ no GL
def test_find_inputs_names_assets_by_relative_path(tmp_path):
    lib = make_library(tmp_path / "lib", {"notes.txt": b"x", ".hidden.obj": b"x"})
    single = tmp_path / "extra.off"
    trimesh.creation.box().export(single)
    found = find_inputs([lib, single, lib / "box.ply"])  # a file named twice is baked once
    assert [a.name for a in found] == ["ball", "box", "can", "extra", "sub/cone"]
    assert all(a.path.is_absolute() and a.path.is_file() for a in found)


def test_find_inputs_refuses_missing_empty_and_clashing(tmp_path):
    with pytest.raises(MeshError, match="expected an existing mesh file or folder, got .*nope.*not found"):
        find_inputs([tmp_path / "nope"])
    (tmp_path / "empty").mkdir()
    with pytest.raises(MeshError, match="expected mesh files .*, got none"):
        find_inputs([tmp_path / "empty"])
    for sub in ("a", "b"):
        (tmp_path / sub).mkdir()
        trimesh.creation.box().export(tmp_path / sub / "tree.obj")
    with pytest.raises(ValidationError, match="asset name 'tree': expected one mesh file per name"):
        find_inputs([tmp_path / "a" / "tree.obj", tmp_path / "b" / "tree.obj"])


def test_output_folder_not_writable_is_refused(tmp_path, monkeypatch):
    blocker = tmp_path / "file.txt"
    blocker.write_text("a regular file")
    with pytest.raises(ValidationError, match="output folder: expected a folder morphkit can create "
                       "and write, got .*file.txt/sub"):
        check_writable(blocker / "sub")

    def denied(*_a, **_k):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(fileio.tempfile, "mkstemp", denied)
    with pytest.raises(ValidationError, match="PermissionError: Permission denied"):
        check_writable(tmp_path / "ok")


def test_not_writable_output_fails_before_any_work(tmp_path, monkeypatch):
    lib = make_library(tmp_path / "lib")
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")

    def no_cluster(**_kw):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(bake_pipeline, "open_client", no_cluster)
    with pytest.raises(ValidationError, match="output folder"):
        bake_library([lib], blocker / "sub", options=OPTS, progress=False)


def test_bake_options_and_kind_validation():
    with pytest.raises(ValidationError, match="bake kinds: expected at least one, got none"):
        BakeOptions(())
    with pytest.raises(ValidationError, match="bake kind names: expected distinct"):
        BakeOptions((TINY, ShadowAtlasKind(atlas_size=64)))
    with pytest.raises(ValidationError, match="bake kind: expected an AssetKind"):
        BakeOptions(("atlas",))  # type: ignore[arg-type]
    with pytest.raises(ValidationError, match=r"atlas size: expected an integer in \[8, 8192\], got 0"):
        ShadowAtlasKind(atlas_size=0)
    with pytest.raises(ValidationError, match="grid: expected an integer in"):
        ShadowAtlasKind(grid=1)
    with pytest.raises(ValidationError, match="motion range: expected hi > lo"):
        ShadowAtlasKind(range=(0.5, 0.0, -0.5, 1.0))
    with pytest.raises(ValidationError, match="light: expected finite values"):
        ShadowAtlasKind(light=(0.0, float("nan"), 2.0))
    assert BakeOptions().as_dict() == {"shadow-atlas": ShadowAtlasKind().options()}


def test_cli_help_states_the_kind_defaults(capsys):
    """The CLI does not import the kind (fast --help); its stated defaults must be the kind's."""
    with pytest.raises(SystemExit):
        main(["bake", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    k = ShadowAtlasKind()
    assert f"(default: {k.atlas_size})" in text and f"(default: {k.grid})" in text
    assert "(default: " + " ".join(f"{v:g}" for v in k.range) + ")" in text
    assert "(default: " + " ".join(f"{v:g}" for v in k.light) + ")" in text


def test_journal_is_replayed_and_a_truncated_line_skipped(tmp_path):
    from morphkit.bake import AssetRecord

    m = Manifest.open(tmp_path)
    m.record(AssetRecord("a", "/x/a.obj", "0" * 64, 3, "failed", error="MeshError: x"))
    m.record(AssetRecord("b", "/x/b.obj", "1" * 64, 3, "failed", error="MeshError: y"))
    with open(tmp_path / JOURNAL_NAME, "a") as f:
        f.write('{"name": "c", "inp')  # a crash in the middle of a line
    assert not (tmp_path / MANIFEST_NAME).exists()
    back = Manifest.open(tmp_path)
    assert sorted(back.assets) == ["a", "b"] and back.assets["b"].error == "MeshError: y"
    back.commit()
    assert not (tmp_path / JOURNAL_NAME).exists()
    assert sorted(Manifest.open(tmp_path).assets) == ["a", "b"]


def test_corrupt_manifest_is_a_file_format_error(tmp_path):
    from morphkit.errors import FileFormatError

    (tmp_path / MANIFEST_NAME).write_text("{not json")
    with pytest.raises(FileFormatError, match="manifest .*: expected a morphkit-bake-manifest JSON file"):
        Manifest.open(tmp_path)
    (tmp_path / MANIFEST_NAME).write_text(json.dumps({"format": "other"}))
    with pytest.raises(FileFormatError, match="expected morphkit-bake-manifest, got other"):
        Manifest.open(tmp_path)


def test_unreachable_scheduler_is_a_cluster_error_within_the_timeout(tmp_path, monkeypatch):
    monkeypatch.setattr(bake_cluster, "CONNECT_TIMEOUT_S", 1.0)  # default 5 s; the same code path
    lib = make_library(tmp_path / "lib")
    t0 = time.perf_counter()
    with pytest.raises(ClusterError, match=r"Dask scheduler: expected one answering at 'tcp://127.0.0.1:9' "
                       r"within 1 s, got (OSError: Timed out|no answer)"):
        bake_library([lib], tmp_path / "out", options=OPTS, scheduler="tcp://127.0.0.1:9", progress=False)
    # a hang guard, not a speed test: Dask would otherwise retry for its own 30 s connect timeout
    assert time.perf_counter() - t0 < bake_cluster.CONNECT_TIMEOUT_S + 10
    assert not (tmp_path / "out" / MANIFEST_NAME).exists()


def test_scheduler_without_workers_is_a_cluster_error(tmp_path, monkeypatch):
    from distributed import LocalCluster

    monkeypatch.setattr(bake_cluster, "CONNECT_TIMEOUT_S", 1.0)
    lib = make_library(tmp_path / "lib")
    with LocalCluster(n_workers=0, processes=False, dashboard_address="127.0.0.1:0",
                      silence_logs=logging.ERROR) as empty:
        with pytest.raises(ClusterError, match="expected at least one worker within 1 s, got none"):
            bake_library([lib], tmp_path / "out", options=OPTS, scheduler=empty.scheduler_address,
                         progress=False)


def test_workers_and_scheduler_together_are_refused(tmp_path):
    with pytest.raises(ValidationError, match="workers and scheduler: expected one of them, got both"):
        bake_library([tmp_path], tmp_path / "out", workers=2, scheduler="tcp://127.0.0.1:9")
    with pytest.raises(ValidationError, match="workers: expected an integer >= 1, got 0"):
        bake_library([tmp_path], tmp_path / "out", workers=0)
    for bad in (2.5, True, "2"):  # validate.as_int's rule: an integral value, not a bool or a string
        with pytest.raises(ValidationError, match=r"workers: expected an integer >= 1, got"):
            bake_library([tmp_path], tmp_path / "out", workers=bad)


# -------------------------------------------------------------------- GL
@pytest.mark.gl
def test_manifest_records_hashes_options_outputs_and_timings(tmp_path, scheduler, clean):
    import morphkit

    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    m = bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    d = json.loads((out / MANIFEST_NAME).read_text())
    assert d["format"] == "morphkit-bake-manifest" and d["version"] == 1
    assert d["morphkit_version"] == morphkit.__version__
    assert d["options"] == {"shadow-atlas": TINY.options()}
    assert d["run"]["baked"] == len(MESHES) and d["run"]["skipped"] == d["run"]["failed"] == 0
    assert d["run"]["workers"] == 2 and d["run"]["scheduler"] == scheduler
    assert sorted(d["assets"]) == sorted(MESHES)
    for name, (_build, suffix) in MESHES.items():
        rec = d["assets"][name]
        src = lib / f"{name}{suffix}"
        assert rec["input"] == str(src.resolve()) and rec["status"] == "baked" and rec["error"] is None
        assert rec["input_sha256"] == sha(src) and rec["input_bytes"] == src.stat().st_size
        o = rec["outputs"]["shadow-atlas"]
        assert o["file"] == f"{name}.atlas.npz" and o["version"] == ATLAS_VERSION
        assert o["options"] == TINY.options()
        assert o["sha256"] == sha(out / o["file"]) and o["bytes"] == (out / o["file"]).stat().st_size
        assert 0 < rec["timings_s"]["load"] < rec["timings_s"]["total"]
        assert rec["timings_s"]["shadow-atlas"] > 0
    assert outputs(out) == clean  # deterministic: the same bytes as another run
    assert not (out / JOURNAL_NAME).exists()
    assert m.to_dict() == d


@pytest.mark.gl
def test_baked_atlas_loads_and_matches_its_options(tmp_path, scheduler):
    from morphkit.scene import PointLight
    from morphkit.shadow import ShadowAtlas

    lib = make_library(tmp_path / "lib")
    bake_library([lib / "box.ply"], tmp_path / "out", options=OPTS, scheduler=scheduler, progress=False)
    atlas = ShadowAtlas.load(tmp_path / "out" / "box.atlas.npz", light=PointLight(TINY.light))
    assert atlas.grid == (3, 3) and atlas.shape == (32, 32)
    np.testing.assert_array_equal(atlas.rig.motion.lo, TINY.range[:2])
    np.testing.assert_array_equal(atlas.rig.motion.hi, TINY.range[2:])


@pytest.mark.gl
def test_billboard_kind_bakes_an_asset_beside_the_atlas(tmp_path, scheduler):
    from morphkit.bake import BillboardKind
    from morphkit.billboard import BillboardAsset
    from morphkit.billboard.asset import mesh_hash
    from morphkit.billboard.cameras import DISTANCE_FACTOR
    from morphkit.meshes import load_mesh

    lib = make_library(tmp_path / "lib")
    kind = BillboardKind(views=2, size=64)
    m = bake_library([lib / "box.ply"], tmp_path / "out", options=BakeOptions((TINY, kind)),
                     scheduler=scheduler, progress=False)
    assert m.run["baked"] == 1 and not m.failed()
    rec = m.assets["box"].outputs["billboard"]
    assert rec.file == "box.billboard.npz"
    assert rec.options == {"views": 2, "size": 64, "distance_factor": DISTANCE_FACTOR}
    asset = BillboardAsset.load(tmp_path / "out" / rec.file, mesh=load_mesh(lib / "box.ply"))
    assert asset.ring.views == 2 and asset.mesh_hash == mesh_hash(load_mesh(lib / "box.ply"))
    assert (tmp_path / "out" / "box.atlas.npz").is_file()
    with pytest.raises(ValidationError, match=r"billboard size: expected an integer in \[16, 2048\]"):
        BillboardKind(size=8)
    with pytest.raises(ValidationError, match=r"billboard distance_factor: expected a number in \[3, 100\]"):
        BillboardKind(distance_factor=1.0)


@pytest.mark.gl
def test_sun_atlas_kind_is_baked_once_and_read_by_billboards(tmp_path, scheduler, capfd, renderer):
    """bake --dome --sun-atlas writes the asset's sun atlas beside its dome asset; billboards
    --shadows given the dome asset reads it (said on stderr) and draws the frames a run that
    bakes the atlas itself draws (the bake is deterministic: the worker's atlas is the one baked
    here, bit for bit), and those frames are drawn from the atlas read (one without a caster,
    of the same mesh, draws other frames)."""
    import cv2

    from morphkit.bake import DomeKind, SunAtlasKind
    from morphkit.cli import main
    from morphkit.meshes import load_mesh, normalize
    from morphkit.sunlit.receivers import SCENE_ATLAS_DOME
    from morphkit.sunlit.sunatlas import SunAtlas, bake_sun_atlas
    from morphkit.sunlit.sunatlasfile import read_sun_atlas, write_sun_atlas

    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    kinds = (TINY, DomeKind(size=32), SunAtlasKind(size=16))
    m = bake_library([lib / "box.ply"], out, options=BakeOptions(kinds),
                     scheduler=scheduler, progress=False)
    rec = m.assets["box"].outputs["sun_atlas"]
    assert rec.file == "box.sunatlas.npz" and rec.options["size"] == 16
    baked_there = read_sun_atlas(out / rec.file)
    here = bake_sun_atlas(normalize(load_mesh(lib / "box.ply")), renderer, dome=SCENE_ATLAS_DOME, size=16)
    assert baked_there.size == 16 and baked_there.mesh_hash == here.mesh_hash
    assert baked_there.depth.tobytes() == here.depth.tobytes() and np.isfinite(here.depth).any()
    with pytest.raises(ValidationError, match=r"sun atlas size: expected an integer in \[16, 1024\]"):
        SunAtlasKind(size=8)
    argv = ["billboards", "--asset", str(out / "box.dome.npz"), "--shadows", "--sun-atlas-size", "16",
            "--n", "3", "--frames", "1", "--size", "64x48"]
    capfd.readouterr()
    assert main([*argv, "-o", str(tmp_path / "read")]) == 0
    assert "box's from the bake (box.sunatlas.npz, 16 texels)" in capfd.readouterr().err
    good = (out / rec.file).read_bytes()
    empty = SunAtlas(here.dome, here.cameras, np.full_like(here.depth, np.inf), np.zeros_like(here.coverage),
                     here.mesh_hash)  # the box's, casting nothing
    write_sun_atlas(out / rec.file, empty)
    assert main([*argv, "-o", str(tmp_path / "empty")]) == 0
    assert "box's from the bake (box.sunatlas.npz, 16 texels)" in capfd.readouterr().err
    (out / rec.file).write_bytes(good[: len(good) // 2])  # a damaged atlas: refused, not baked over
    assert main([*argv, "-o", str(tmp_path / "damaged")]) == 1
    line = one_line_error(capfd.readouterr().err)
    assert line.startswith("morphkit: error: the bake's sun atlas of asset 'box': sun atlas file ")
    assert "box.sunatlas.npz" in line and line.endswith("or remove the file to bake one at the run)")
    (out / rec.file).unlink()
    assert main([*argv, "-o", str(tmp_path / "baked")]) == 0
    assert "baking those of box (16 texels)" in capfd.readouterr().err
    read, baked, unshadowed = (cv2.imread(str(tmp_path / d / "frames" / "frame_0000.png"))
                               for d in ("read", "baked", "empty"))
    assert read is not None and np.array_equal(read, baked)
    lit = unshadowed.astype(int) - read  # the read atlas's shadow, gone without a caster: only lighter
    assert lit.min() >= 0 and np.count_nonzero(lit > 5) > 100


@pytest.mark.gl
def test_dome_kind_bakes_a_relightable_asset_beside_the_atlas(tmp_path, scheduler, renderer):
    from morphkit.bake import DomeKind
    from morphkit.billboard.asset import mesh_hash
    from morphkit.billboard.domeasset import DomeAsset
    from morphkit.billboard.formats.domefile import DOME_VERSION
    from morphkit.meshes import load_mesh

    lib = make_library(tmp_path / "lib")
    m = bake_library([lib / "box.ply"], tmp_path / "out", options=BakeOptions((TINY, DomeKind(size=32))),
                     scheduler=scheduler, progress=False)
    assert m.run["baked"] == 1 and not m.failed()
    rec = m.assets["box"].outputs["dome"]
    assert rec.file == "box.dome.npz" and rec.version == DOME_VERSION and rec.options["size"] == 32
    asset = DomeAsset.load(tmp_path / "out" / rec.file)
    assert asset.size == (32, 32) and asset.mesh_hash == mesh_hash(load_mesh(lib / "box.ply"))
    with pytest.raises(ValidationError, match=r"dome size: expected an integer in \[16, 2048\]"):
        DomeKind(size=8)
    # a billboard scene finds the baked asset's mesh through the manifest (shadows and the
    # mesh comparison need it), not only beside the file; a changed input is said, not used
    from morphkit.bake.manifest import ManifestRecords
    from morphkit.programs.sources import resolve_assets
    from morphkit.views.dome import ViewDome

    dome = tmp_path / "out" / rec.file
    res = resolve_assets([str(dome)], renderer, dome=ViewDome(), records=ManifestRecords())
    assert "box" in res.items and not res.skipped
    trimesh.creation.icosphere(subdivisions=1).export(lib / "box.ply")
    res = resolve_assets([str(dome)], renderer, dome=ViewDome(), records=ManifestRecords())
    assert not res.items and "is missing or changed since the bake" in res.skipped["box"]
    # a folder's manifest.json that is not a bake's is passed over
    alone = tmp_path / "app" / "box.dome.npz"
    alone.parent.mkdir()
    (alone.parent / "manifest.json").write_text('{"name": "a web app", "icons": []}')
    dome.replace(alone)
    res = resolve_assets([str(alone)], renderer, dome=ViewDome(), records=ManifestRecords())
    assert "no mesh file box{.obj," in res.skipped["box"]


@pytest.mark.gl
def test_rerun_skips_what_is_up_to_date_and_rebakes_what_changed(tmp_path, scheduler):
    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    first = {p: (out / p).stat().st_mtime_ns for p in outputs(out)}

    m = bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    assert (m.run["baked"], m.run["skipped"], m.run["failed"]) == (0, len(MESHES), 0)
    assert m.run["workers"] == 0  # nothing to do: no cluster contacted
    assert {p: (out / p).stat().st_mtime_ns for p in outputs(out)} == first

    trimesh.creation.box([0.4, 0.4, 1.0]).export(lib / "box.ply")  # input changed
    (out / "ball.atlas.npz").unlink()  # output lost
    (out / "can.atlas.npz").write_bytes(b"tampered")  # output damaged
    m = bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    status = {k: r.status for k, r in m.assets.items()}
    assert status == {"box": "baked", "ball": "baked", "can": "baked", "sub/cone": "skipped"}
    assert m.assets["box"].input_sha256 == sha(lib / "box.ply")

    m = bake_library([lib], out, options=BakeOptions((ShadowAtlasKind(atlas_size=40, grid=3),)),
                     scheduler=scheduler, progress=False)  # options changed: everything again
    assert m.run["baked"] == len(MESHES)


@pytest.mark.gl
def test_corrupt_mesh_is_recorded_and_the_others_baked(tmp_path, scheduler, clean, capsys):
    lib = make_library(tmp_path / "lib", {"broken.obj": b"v 0 0 0\nf 1 2 3\n", "empty.ply": b""})
    out = tmp_path / "out"
    rc = main(["bake", str(lib), "-o", str(out), "--atlas-size", "32", "--grid", "3",
               "--scheduler", scheduler, "-q"])
    err = capsys.readouterr().err
    assert rc == 1
    m = Manifest.open(out)
    assert {k for k, r in m.assets.items() if r.status == "failed"} == {"broken", "empty"}
    assert m.assets["empty"].error.startswith("MeshError: mesh file ")
    assert m.assets["broken"].outputs == {}
    assert outputs(out) == clean  # every good mesh baked, byte-identical to a clean run
    assert "failed: broken: MeshError" in err and "failed: empty: MeshError" in err
    assert "Traceback" not in err


@dataclass(frozen=True)
class DieOnceKind:
    """The tiny atlas kind, except that the first process to bake the mesh with ``victim_faces``
    faces dies on the spot (``os._exit``), as a worker killed mid-run."""

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
            Path(self.marker).write_text(str(os.getpid()))
            os._exit(1)
        return self.inner.bake(mesh, renderer, source_up)


@pytest.mark.gl
def test_killed_worker_loses_nothing(tmp_path, scheduler, clean):
    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    marker = tmp_path / "killed"
    victim = len(MESHES["can"][0]().faces)
    m = bake_library([lib], out, options=BakeOptions((DieOnceKind(str(marker), victim),)),
                     scheduler=scheduler, progress=False)
    assert marker.exists()  # a worker process did die mid-task
    # Dask re-ran the task on a live worker: the run finished, every asset intact
    assert m.run["failed"] == 0 and m.run["baked"] == len(MESHES), m.failed()
    assert outputs(out) == clean
    assert not list(out.rglob("*.part")) and not list(out.rglob(".*.npz.*"))  # no half files


@pytest.mark.gl
def test_driver_crash_mid_run_loses_no_finished_asset(tmp_path, scheduler, clean, monkeypatch):
    lib = make_library(tmp_path / "lib")
    out = tmp_path / "out"
    real_record = Manifest.record
    done: list[str] = []

    def record_then_crash(self, *recs):  # the first results are journaled, then the driver dies
        real_record(self, *recs)
        done.extend(r.name for r in recs)
        raise RuntimeError("simulated crash of the driver")

    monkeypatch.setattr(Manifest, "record", record_then_crash)
    with pytest.raises(RuntimeError, match="simulated crash"):
        bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    monkeypatch.undo()
    kept = {f"{n}.atlas.npz": (out / f"{n}.atlas.npz").stat().st_mtime_ns for n in done}

    m = bake_library([lib], out, options=OPTS, scheduler=scheduler, progress=False)
    assert {k for k, r in m.assets.items() if r.status == "skipped"} == set(done)
    # 2 workers, 4 tasks: the first results to arrive are at most 2 (the rest is still to bake)
    assert 1 <= len(done) <= 2
    assert m.run["baked"] == len(MESHES) - len(done) and m.run["failed"] == 0
    assert {p: (out / p).stat().st_mtime_ns for p in kept} == kept  # not baked again
    assert outputs(out) == clean


@pytest.mark.gl
def test_default_local_cluster_bakes(tmp_path, clean):
    lib = make_library(tmp_path / "lib")
    m = bake_library([lib / "box.ply", lib / "sub"], tmp_path / "out", options=OPTS, workers=1,
                     progress=False)
    assert m.run["scheduler"] == "local" and m.run["workers"] == 1
    # a folder's assets are named relative to it: sub/cone.ply -> cone
    assert outputs(tmp_path / "out") == {"box.atlas.npz": clean["box.atlas.npz"],
                                         "cone.atlas.npz": clean["sub/cone.atlas.npz"]}


# ------------------------------------------------------- command line mistakes
def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    try:
        rc = main(list(argv))
    except SystemExit as exc:  # argparse
        rc = int(exc.code)
    out, err = capsys.readouterr()
    return rc, out, err


def one_line_error(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# exit 2: a usage mistake (a bad option value or combination); 1: a run that failed on its inputs
@pytest.mark.parametrize(("args", "message", "code"), [
    (["bake", "{tmp}/missing.obj", "-o", "{tmp}/out"],
     r"input: expected an existing mesh file or folder, got '.*missing.obj' \(not found\)", 1),
    (["bake", "{lib}", "-o", "{tmp}/file.txt/sub"],
     "output folder: expected a folder morphkit can create and write, got '.*file.txt/sub' "
     r"\(NotADirectoryError", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--atlas-size", "0"],
     r"atlas size: expected an integer in \[8, 8192\], got 0", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--grid", "1"],
     r"grid: expected an integer in \[2, 64\], got 1", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--range", "1", "0", "0", "1"],
     "motion range: expected hi > lo", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--light", "0", "nan", "2"], "light: expected finite values", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--directional", "--light", "0", "0", "0"],
     "direction", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--workers", "0"],
     r"workers: expected an integer in \[1, 256\], got 0", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--scheduler", "tcp://127.0.0.1:9"],
     "Dask scheduler: expected one answering at 'tcp://127.0.0.1:9' within 1 s", 1),
    (["bake", "{lib}", "-o", "{tmp}/out", "--views", "4"], "--views: expected together with --billboard", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--billboard", "--views", "1"],
     r"billboard views: expected an integer in \[2, 64\], got 1", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--sun-atlas-size", "64"],
     "--sun-atlas-size: expected together with --sun-atlas", 2),
    (["bake", "{lib}", "-o", "{tmp}/out", "--sun-atlas", "--sun-atlas-size", "8"],
     r"sun atlas size: expected an integer in \[16, 1024\], got 8", 2),
    (["shadows", "{tmp}/missing.atlas.npz", "-o", "{tmp}/frames"],
     "atlas file: expected an existing file", 1),
    (["shadows", "{tmp}/a.atlas.npz", "-o", "{tmp}/frames", "--samples", "2"],
     "--samples: expected together with --area-light", 2),
    (["shadows", "{tmp}/a.atlas.npz", "-o", "{tmp}/frames", "--path", "{tmp}/p.csv", "--frames", "3"],
     "--frames: expected with --path line or circle", 2),
    (["shadows", "{tmp}/a.atlas.npz", "-o", "{tmp}/frames", "--path", "{tmp}/nope.csv"],
     "path file: expected an existing CSV file", 1),
    (["shadows", "{tmp}/a.atlas.npz", "-o", "{tmp}/frames", "--path", "zigzag"],
     r"--path: expected line, circle or a CSV file of x,y rows \(FILE.csv\), got 'zigzag'", 2),
])
def test_cli_user_mistakes_are_one_line_errors(tmp_path, capsys, monkeypatch, args, message, code):
    monkeypatch.setattr(bake_cluster, "CONNECT_TIMEOUT_S", 1.0)
    lib = make_library(tmp_path / "lib")
    (tmp_path / "file.txt").write_text("x")
    (tmp_path / "p.csv").write_text("x,y\n0,0\n")
    argv = [a.format(tmp=tmp_path, lib=lib) for a in args]
    rc, _out, err = run_cli(capsys, *argv)
    assert rc == code
    line = one_line_error(err)
    assert line.startswith("morphkit: error: ")
    assert re.search(message, line), line
    assert not (tmp_path / "out" / MANIFEST_NAME).exists()


def test_cli_unparsable_number_is_an_argparse_error(tmp_path, capsys):
    rc, _out, err = run_cli(capsys, "bake", str(tmp_path), "-o", str(tmp_path / "o"), "--atlas-size", "big")
    assert rc == 2 and "argument --atlas-size: invalid int value: 'big'" in err and "Traceback" not in err


def test_points_path_reads_csv_and_checks_the_range(tmp_path):
    from morphkit.errors import OutOfRangeError
    from morphkit.programs.playback import CirclePath, LinePath, PointsPath
    from morphkit.shadow import MotionRange

    motion = MotionRange([-1.0, -0.5], [1.0, 0.5])
    csv = tmp_path / "p.csv"
    csv.write_text("x, y\n# a comment\n0.1, -0.2\n\n-1.0,0.5\n")
    np.testing.assert_array_equal(PointsPath.from_csv(csv).positions(motion), [[0.1, -0.2], [-1.0, 0.5]])
    csv.write_text("0,0\n2.0,0\n")
    with pytest.raises(OutOfRangeError, match=r"object position: expected inside the baked range"):
        PointsPath.from_csv(csv).positions(motion)
    csv.write_text("0,0\n1,2,3\n")
    with pytest.raises(ValidationError, match="line 2: expected two finite numbers x,y, got '1,2,3'"):
        PointsPath.from_csv(csv)
    line = LinePath(5).positions(motion)
    np.testing.assert_allclose(line[[0, -1]], [motion.lo, motion.hi])
    np.testing.assert_allclose(np.diff(line, axis=0), 0.25 * (motion.hi - motion.lo)[None].repeat(4, 0))
    circle = CirclePath(8).positions(motion)
    np.testing.assert_allclose(((circle - motion.center) / (0.45 * (motion.hi - motion.lo))) ** 2 @ [1, 1],
                               np.ones(8))
    with pytest.raises(ValidationError, match=r"frames: expected an integer in \[1, 100000\], got 0"):
        LinePath(0).positions(motion)


# ---------------------------------------------------------------- shadows
@pytest.fixture(scope="module")
def baked(tmp_path_factory, scheduler) -> tuple[Path, Path]:
    """A library of one mesh (the box) baked at 32 x 32: ``(library, output folder)``."""
    root = tmp_path_factory.mktemp("baked")
    lib = root / "lib"
    lib.mkdir()
    MESHES["box"][0]().export(lib / "box.ply")
    bake_library([lib], root / "out", options=OPTS, scheduler=scheduler, progress=False)
    return lib, root / "out"


@pytest.mark.gl
def test_shadows_renders_frames_and_a_video_with_the_warped_shadow(tmp_path, baked, capsys, renderer):
    import cv2

    from morphkit.programs.playback import LinePath, baked_mesh, playback_scene
    from morphkit.shadow import ShadowAtlas
    from morphkit.shadow.frame import render_frame

    _lib, out = baked
    rc, stdout, _err = run_cli(capsys, "shadows", str(out / "box.atlas.npz"), "-o", str(tmp_path / "f"),
                               "--frames", "3", "--size", "48", "-q")
    assert rc == 0 and "3 frames (hard)" in stdout
    assert re.search(r"shadow vs ray cast on the ground: IoU min 0\.\d{3} mean 0\.\d{3}", stdout)
    names = sorted(p.relative_to(tmp_path / "f").as_posix() for p in (tmp_path / "f").rglob("*"))
    assert names == [".morphkit-output.json",  # morphkit.files.outfolder's marker, its one file of its own
                     "frames", "frames/frame_0000.png", "frames/frame_0001.png", "frames/frame_0002.png",
                     "shadows.webm"]
    video = cv2.VideoCapture(str(tmp_path / "f" / "shadows.webm"))
    assert video.get(cv2.CAP_PROP_FRAME_COUNT) == 3 and video.get(cv2.CAP_PROP_FRAME_WIDTH) == 48
    video.release()
    frames = [fileio.read_image(tmp_path / "f" / "frames" / f"frame_000{i}.png") for i in range(3)]
    assert not np.array_equal(frames[0], frames[2])  # the object moved
    # the light is exposed for the frame: no pixel clipped to white (the ground was, 39 % of it)
    assert all(np.count_nonzero(f.min(axis=2) >= 250) == 0 for f in frames)
    # the same frame without a shadow is nowhere darker and somewhere brighter: a shadow was drawn
    atlas = ShadowAtlas.load(out / "box.atlas.npz")
    xy = LinePath(3).positions(atlas.rig.motion)[1]
    scene = playback_scene(baked_mesh(out / "box.atlas.npz"), atlas, 48)
    scene = scene.with_object_pose(atlas.rig.object_pose(xy))
    unshadowed = render_frame(renderer, scene, lambda p, _n: np.ones(len(p)))["shaded"].astype(int)
    assert np.all(frames[1] <= unshadowed) and np.count_nonzero(frames[1] < unshadowed) > 20


@pytest.mark.gl
def test_shadows_soft_with_an_area_light(tmp_path, baked, capsys):
    _lib, out = baked
    rc, stdout, err = run_cli(capsys, "shadows", str(out / "box.atlas.npz"), "-o", str(tmp_path / "s"),
                              "--path", "circle", "--frames", "2", "--size", "32", "--area-light", "0.2",
                              "0.2", "--samples", "2", "-q")
    assert rc == 0, err
    assert "2 frames (soft, 0.2 x 0.2 area light)" in stdout
    assert re.search(r"visibility error \(mean abs\) max 0\.\d{3} mean 0\.\d{3}", stdout)
    rc, _out, err = run_cli(capsys, "shadows", str(out / "box.atlas.npz"), "-o", str(tmp_path / "s2"),
                            "--area-light", "1.5", "0.2", "-q")
    assert rc == 1 and "area light: expected smaller than the baked range" in one_line_error(err)


@pytest.mark.gl
def test_shadows_finds_the_mesh_through_the_manifest_and_checks_its_hash(tmp_path, baked, capsys):
    import shutil

    from morphkit.errors import FileFormatError
    from morphkit.meshes import load_mesh, shape_hash
    from morphkit.programs.playback import baked_mesh
    from morphkit.shadow import ShadowAtlas

    lib, out = baked
    np.testing.assert_array_equal(baked_mesh(out / "box.atlas.npz").vertices,
                                  load_mesh(lib / "box.ply").vertices)
    alone = tmp_path / "alone.atlas.npz"  # copied away from its manifest
    shutil.copy(out / "box.atlas.npz", alone)
    with pytest.raises(ValidationError, match="expected a bake manifest listing the atlas .*, or --mesh"):
        baked_mesh(alone)
    assert len(baked_mesh(alone, lib / "box.ply").faces) == 12
    other = tmp_path / "other.ply"
    trimesh.creation.icosphere(subdivisions=1).export(other)
    with pytest.raises(FileFormatError, match="expected the file the atlas was baked from"):
        baked_mesh(out / "box.atlas.npz", other)
    rc, _o, err = run_cli(capsys, "shadows", str(out / "box.atlas.npz"), "--mesh", str(other),
                          "-o", str(tmp_path / "x"), "-q")
    assert rc == 1 and "expected the file the atlas was baked from" in one_line_error(err)
    # away from its manifest the atlas still knows its mesh: another mesh is refused there too
    assert ShadowAtlas.load(alone).baked.mesh_sha256 == shape_hash(load_mesh(lib / "box.ply"))
    with pytest.raises(FileFormatError, match=r"mesh '.*other.ply': expected the mesh alone.atlas.npz was "
                                              r"baked from \(shape sha256 [0-9a-f]{12}\), got another shape"):
        baked_mesh(alone, other, mesh_sha256=ShadowAtlas.load(alone).baked.mesh_sha256)
    rc, _o, err = run_cli(capsys, "shadows", str(alone), "--mesh", str(other), "-o", str(tmp_path / "y"),
                          "-q")
    assert rc == 1 and "expected the mesh alone.atlas.npz was baked from" in one_line_error(err)
    assert not (tmp_path / "y").exists() or not any((tmp_path / "y").glob("*.png"))
