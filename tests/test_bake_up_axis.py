"""``morphkit bake --up-axis``: Y-up files baked standing, the axis in the manifest and the resume key.

The library: a tall box (0.2 x 1.0 x 0.2, its long side along the file's +y) as
OBJ and GLB (Y-up by default: ``morphkit.meshes.UP_AXIS_BY_FORMAT``), and the
same box stored +z up as PLY (Z-up by default). Normalised, the standing box
is 1.0 high and the lying one 0.2: the baked shadow atlas's depth maps,
lifted to world points through the rig's light camera, show which.
"""

from __future__ import annotations

import json
import logging
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit.bake import MANIFEST_NAME, BakeOptions, Manifest, ShadowAtlasKind, bake_library
from morphkit.bake.manifest import LEGACY_UP_AXIS, AssetRecord, OutputRecord, file_digest
from morphkit.cli import main
from morphkit.errors import ValidationError
from morphkit.meshes import UP_AXIS_BY_FORMAT

TINY = ShadowAtlasKind(atlas_size=32, grid=3)
TALL = 1.0  # the box's long side: normalised height when standing
THIN = 0.2  # its short sides: normalised height when lying


def tall_library(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box([THIN, TALL, THIN]).export(folder / "tall_obj.obj")  # +y up, as exporters write
    trimesh.creation.box([THIN, TALL, THIN]).export(folder / "tall_glb.glb")  # +y up by the glTF spec
    trimesh.creation.box([THIN, THIN, TALL]).export(folder / "tall_ply.ply")  # +z up
    return folder


def atlas_top(path: Path) -> tuple[float, float]:
    """(highest world z, widest horizontal extent) of the object in every map of a baked atlas."""
    from morphkit.scene import PointLight
    from morphkit.shadow import ShadowAtlas

    atlas = ShadowAtlas.load(path, light=PointLight(TINY.light))
    top, width = [], []
    ky, kx = atlas.grid
    for j in range(ky):
        for i in range(kx):
            xy = atlas.baked.sample_xy(j, i)
            pts, valid = atlas.rig.camera_at(xy).unproject(atlas.maps[j, i])
            p = pts[valid] - np.r_[xy, 0.0]  # object frame
            top.append(p[:, 2].max())
            width.append(np.ptp(p[:, :2], axis=0).max())
    return float(np.max(top)), float(np.max(width))


def sha(path: Path) -> str:
    return file_digest(path)[0]


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                      silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address


# ------------------------------------------------------------------ no GL
def test_bake_options_refuse_another_up_axis():
    assert BakeOptions().up == "auto" and BakeOptions(up="Y").up == "y"
    for bad in ("x", "", None, 1):
        with pytest.raises(ValidationError, match="bake up axis: expected 'auto', 'z' or 'y'"):
            BakeOptions(up=bad)  # type: ignore[arg-type]


def test_cli_refuses_up_axis_x_at_parse_time(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["bake", str(tmp_path), "-o", str(tmp_path / "out"), "--up-axis", "x"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    errors = [ln for ln in err.splitlines() if "error" in ln]
    assert errors == ["morphkit bake: error: argument --up-axis: invalid choice: 'x' "
                      "(choose from 'auto', 'y', 'z')"], err
    assert "Traceback" not in err and not (tmp_path / "out").exists()


def test_cli_help_states_the_up_axis_table(capsys):
    """The CLI's help (no import of morphkit.meshes) states UP_AXIS_BY_FORMAT."""
    with pytest.raises(SystemExit):
        main(["bake", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert UP_AXIS_BY_FORMAT == {"gltf": "y", "glb": "y", "obj": "y"}
    assert "auto is each format's default (glTF/GLB and OBJ y, every other format z)" in text


def test_a_record_without_up_axis_counts_as_z(tmp_path):
    """A manifest written before the up axis existed: its files were loaded as stored (+z)."""
    out = tmp_path / "a.atlas.npz"
    out.write_bytes(b"an output")
    digest, size = file_digest(out)
    m = Manifest.open(tmp_path)
    m.record(AssetRecord("a", "/lib/a.obj", "0" * 64, 3, "baked",
                         outputs={TINY.name: OutputRecord(out.name, digest, size, TINY.version,
                                                          TINY.options(), 0.1)}))
    m.commit()
    d = json.loads((tmp_path / MANIFEST_NAME).read_text())
    del d["assets"]["a"]["up_axis"]  # as an older morphkit wrote it
    (tmp_path / MANIFEST_NAME).write_text(json.dumps(d))
    old = Manifest.open(tmp_path)
    assert old.assets["a"].up_axis is None and LEGACY_UP_AXIS == "z"
    assert old.up_to_date("a", "0" * 64, TINY, up_axis="z")
    assert not old.up_to_date("a", "0" * 64, TINY, up_axis="y")
    old.mark_skipped("a", "/lib/a.obj", up_axis="z")
    assert old.assets["a"].up_axis == "z"


# -------------------------------------------------------------------- GL
@pytest.mark.gl
def test_y_up_files_bake_standing_and_z_differs(tmp_path, scheduler):
    lib = tall_library(tmp_path / "lib")
    m = bake_library([lib], tmp_path / "auto", options=BakeOptions((TINY,)), scheduler=scheduler,
                     progress=False)
    assert m.run["baked"] == 3 and not m.failed() and m.run["up"] == "auto"
    assert {k: r.up_axis for k, r in m.assets.items()} == {"tall_obj": "y", "tall_glb": "y", "tall_ply": "z"}
    d = json.loads((tmp_path / "auto" / MANIFEST_NAME).read_text())
    assert {k: r["up_axis"] for k, r in d["assets"].items()} == {"tall_obj": "y", "tall_glb": "y",
                                                                  "tall_ply": "z"}
    for name in ("tall_obj", "tall_glb", "tall_ply"):  # standing: 1.0 high, 0.2 wide (+ diagonal)
        top, width = atlas_top(tmp_path / "auto" / f"{name}.atlas.npz")
        assert top == pytest.approx(TALL, abs=0.02), name
        assert width < THIN * np.sqrt(2) + 0.05, name

    m = bake_library([lib], tmp_path / "z", options=BakeOptions((TINY,), up="z"), scheduler=scheduler,
                     progress=False)
    assert {k: r.up_axis for k, r in m.assets.items()} == {"tall_obj": "z", "tall_glb": "z", "tall_ply": "z"}
    for name in ("tall_obj", "tall_glb"):  # taken as stored: lying, 0.2 high and 1.0 long
        top, width = atlas_top(tmp_path / "z" / f"{name}.atlas.npz")
        assert top == pytest.approx(THIN, abs=0.02), name
        assert width > 0.9 * TALL, name
    # the PLY is +z up either way: the same bytes
    assert sha(tmp_path / "z" / "tall_ply.atlas.npz") == sha(tmp_path / "auto" / "tall_ply.atlas.npz")


@pytest.mark.gl
def test_up_axis_is_part_of_the_resume_key(tmp_path, scheduler):
    lib = tall_library(tmp_path / "lib")
    out = tmp_path / "out"
    bake_library([lib], out, options=BakeOptions((TINY,), up="z"), scheduler=scheduler, progress=False)
    lying = sha(out / "tall_obj.atlas.npz")
    # a manifest from before the up axis: the same records without it (every file was taken +z up)
    d = json.loads((out / MANIFEST_NAME).read_text())
    for rec in d["assets"].values():
        del rec["up_axis"]
    (out / MANIFEST_NAME).write_text(json.dumps(d))

    m = bake_library([lib], out, options=BakeOptions((TINY,)), scheduler=scheduler, progress=False)
    status = {k: r.status for k, r in m.assets.items()}
    assert status == {"tall_obj": "baked", "tall_glb": "baked", "tall_ply": "skipped"}  # same hashes
    assert {k: r.up_axis for k, r in m.assets.items()} == {"tall_obj": "y", "tall_glb": "y", "tall_ply": "z"}
    assert sha(out / "tall_obj.atlas.npz") != lying
    assert atlas_top(out / "tall_obj.atlas.npz")[0] == pytest.approx(TALL, abs=0.02)

    m = bake_library([lib], out, options=BakeOptions((TINY,)), scheduler=scheduler, progress=False)
    assert m.run["baked"] == 0 and m.run["skipped"] == 3  # now up to date
    m = bake_library([lib], out, options=BakeOptions((TINY,), up="y"), scheduler=scheduler, progress=False)
    assert {k: r.status for k, r in m.assets.items()} == {"tall_obj": "skipped", "tall_glb": "skipped",
                                                           "tall_ply": "baked"}  # only the PLY turns


@pytest.mark.gl
def test_cli_up_axis_reaches_the_manifest(tmp_path, scheduler, capsys):
    lib = tall_library(tmp_path / "lib")
    rc = main(["bake", str(lib / "tall_obj.obj"), "-o", str(tmp_path / "out"), "--up-axis", "z",
               "--atlas-size", "32", "--scheduler", scheduler, "-q"])
    assert rc == 0, capsys.readouterr().err
    assert re.search(r"1 baked, 0 skipped, 0 failed", capsys.readouterr().out)
    d = json.loads((tmp_path / "out" / MANIFEST_NAME).read_text())
    assert d["run"]["up"] == "z" and d["assets"]["tall_obj"]["up_axis"] == "z"


@pytest.mark.gl
def test_billboard_kind_bakes_the_mesh_turned_upright(tmp_path, scheduler):
    from morphkit.bake import BillboardKind
    from morphkit.billboard import BillboardAsset
    from morphkit.billboard.asset import mesh_hash
    from morphkit.meshes import load_mesh

    lib = tall_library(tmp_path / "lib")
    src = lib / "tall_glb.glb"
    m = bake_library([src], tmp_path / "out", options=BakeOptions((TINY, BillboardKind(views=2, size=32))),
                     scheduler=scheduler, progress=False)
    assert not m.failed() and m.assets["tall_glb"].up_axis == "y"
    standing = load_mesh(src, up="y")
    asset = BillboardAsset.load(tmp_path / "out" / "tall_glb.billboard.npz", mesh=standing)
    assert asset.mesh_hash == mesh_hash(standing) != mesh_hash(load_mesh(src, up="z"))
    for k in range(asset.ring.views):  # a standing object in every reference view: taller than wide
        rows, cols = np.nonzero(asset.reference(k)[..., 3] > 0.5)
        assert np.ptp(rows) > 2 * np.ptp(cols), k
    assert asset.source_up == "y"  # the resolved axis kept in the asset file too


@pytest.mark.gl
def test_shadow_playback_reloads_the_mesh_with_the_baked_axis(tmp_path, scheduler):
    from morphkit.programs.playback import baked_mesh

    lib = tall_library(tmp_path / "lib")
    src = lib / "tall_obj.obj"
    for up, height in (("z", THIN), ("auto", TALL)):  # taken as stored, and turned +y -> +z
        out = tmp_path / f"out_{up}"
        bake_library([src], out, options=BakeOptions((TINY,), up=up), scheduler=scheduler, progress=False)
        mesh = baked_mesh(out / "tall_obj.atlas.npz")
        assert np.ptp(mesh.vertices[:, 2]) == pytest.approx(height, abs=1e-6), up
