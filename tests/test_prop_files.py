"""Property-based tests: every file format morphkit reads, damaged or foreign (issue 28).

For each format a valid file is made once (no GL); Hypothesis then feeds the
loader random bytes, truncations, bit flips and overwritten runs of that file,
and -- to get past the zip/JSON layer into the value checks -- files whose
metadata fields are deleted or replaced by random JSON values and whose arrays
hold NaN/inf/huge values or another dtype or shape, with the checksums
recomputed (a writer with a bug, not a damaged disk). The property: the loader
returns a valid object or raises a MorphkitError subclass (props.outcome);
never a raw exception, a hang or a NaN in what it returns.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import given
from hypothesis import strategies as st
from props import (
    damaged,
    meta_array,
    mutated_array,
    mutated_json,
    npz_bytes,
    outcome,
    read_npz,
)
from test_billboard_asset import synthetic_record

from morphkit.bake.kinds import ShadowAtlasKind
from morphkit.bake.manifest import AssetRecord as ManifestRecord
from morphkit.bake.manifest import Manifest, OutputRecord
from morphkit.billboard import BillboardAsset
from morphkit.billboard.domeasset import DomeAsset
from morphkit.billboard.formats.assetfile import read_record
from morphkit.billboard.formats.domefile import read_dome
from morphkit.files.fileio import array_digest, read_image, write_image
from morphkit.meshes import load_mesh
from morphkit.scene import PointLight
from morphkit.shadow import BakedAtlas, LightRig, MotionRange, ShadowAtlas
from morphkit.shadow.formats.atlasfile import load_atlas, save_atlas
from morphkit.shadow.rig import sample_axis
from morphkit.sunlit.sunatlas import SunAtlas
from morphkit.sunlit.sunatlasfile import read_sun_atlas, write_sun_atlas
from morphkit.viewmorph import Correspondences
from morphkit.viewmorph.correspondences import load_points, save_points

LIGHT = PointLight([0.2, -0.1, 2.6])


def _write(tmp: Path, name: str, data: bytes) -> Path:
    p = tmp / name
    p.write_bytes(data)
    return p


# =================================================================== shadow atlas
@pytest.fixture(scope="module")
def atlas_bytes(tmp_path_factory) -> bytes:
    box = trimesh.creation.box((0.4, 0.3, 0.5))
    box.apply_translation([0, 0, 0.25])
    rig = LightRig(LIGHT, box, np.eye(4), MotionRange([-0.5, -0.4], [0.5, 0.4]), (12, 16))
    rng = np.random.default_rng(7)
    maps = np.full((2, 2, 12, 16), np.inf, np.float32)
    maps[:, :, 3:9, 4:12] = rng.uniform(2.0, 2.5, (2, 2, 6, 8))
    plane = np.zeros((2, 2, 4, 3))
    plane[..., :2] = rng.uniform(-0.2, 0.2, (2, 2, 4, 2))
    plane[..., 2] = 0.25
    surf = plane + rng.uniform(-0.05, 0.05, plane.shape)
    atlas = BakedAtlas(rig, sample_axis(-0.5, 0.5, 2), sample_axis(-0.4, 0.4, 2), maps, surf, plane,
                       (2, 2), "sample")
    return save_atlas(atlas, tmp_path_factory.mktemp("atlas") / "a.npz").read_bytes()


def _check_atlas(atlas: ShadowAtlas) -> None:
    maps = atlas.baked.maps
    assert not np.isnan(maps).any() and not (maps == -np.inf).any()
    assert np.isfinite(atlas.baked.anchors).all()


@given(data=st.data())
def test_atlas_damaged_bytes(atlas_bytes, tmp_path, data):
    path = _write(tmp_path, "a.npz", data.draw(damaged(atlas_bytes)))
    ok, atlas = outcome(ShadowAtlas.load, path)
    if ok:
        _check_atlas(atlas)


def _rehash_atlas(meta: dict, arrays: dict[str, np.ndarray]) -> dict:
    decl = meta.get("arrays")
    if isinstance(decl, dict):
        for k, a in arrays.items():
            if k != "meta" and isinstance(decl.get(k), dict):
                decl[k].update(dtype=str(a.dtype), shape=list(a.shape), sha256=array_digest(a))
    return meta


@given(data=st.data())
def test_atlas_bad_metadata_and_values(atlas_bytes, tmp_path, data):
    arrays = read_npz(atlas_bytes)
    meta = json.loads(bytes(arrays["meta"]).decode())
    if data.draw(st.booleans(), label="mutate metadata"):
        meta = data.draw(mutated_json(meta, keep=("arrays",)))
    if data.draw(st.booleans(), label="mutate an array"):
        k = data.draw(st.sampled_from(["xs", "ys", "maps", "anchors", "plane_anchors", "control",
                                       "triangles"]))
        arrays[k] = data.draw(mutated_array(arrays[k]))
    meta = _rehash_atlas(meta, arrays)
    arrays["meta"] = meta_array(meta)
    path = _write(tmp_path, "a.npz", npz_bytes(arrays))
    ok, atlas = outcome(ShadowAtlas.load, path)
    if ok:
        _check_atlas(atlas)
    ok, baked = outcome(load_atlas, path, light=LIGHT)
    if ok:
        assert not np.isnan(baked.maps).any()


# =================================================================== billboard asset
@pytest.fixture(scope="module")
def asset_bytes(tmp_path_factory) -> bytes:
    path = tmp_path_factory.mktemp("asset") / "b.npz"
    return BillboardAsset(synthetic_record(shape=(16, 12), levels=1)).save(path).read_bytes()


def _check_asset(asset: BillboardAsset) -> None:
    rec = asset.record()
    assert rec.images.dtype == np.uint8
    assert not np.isnan(rec.depth).any() and not (rec.depth == -np.inf).any()
    assert np.isfinite(rec.points3d).all()


@given(data=st.data())
def test_asset_damaged_bytes(asset_bytes, tmp_path, data):
    path = _write(tmp_path, "b.npz", data.draw(damaged(asset_bytes)))
    ok, asset = outcome(BillboardAsset.load, path)
    if ok:
        _check_asset(asset)


def _rehash_asset(meta: dict, arrays: dict[str, np.ndarray]) -> dict:
    sums = meta.get("sha256")
    if isinstance(sums, dict):
        for k, a in arrays.items():
            if k != "meta":
                sums[k] = array_digest(a)
    return meta


@given(data=st.data())
def test_asset_bad_metadata_and_values(asset_bytes, tmp_path, data):
    arrays = read_npz(asset_bytes)
    meta = json.loads(bytes(arrays["meta"]).decode())
    if data.draw(st.booleans(), label="mutate metadata"):
        meta = data.draw(mutated_json(meta, keep=("sha256", "format", "version")))
    if data.draw(st.booleans(), label="mutate an array"):
        k = data.draw(st.sampled_from([k for k in arrays if k != "meta"]))
        arrays[k] = data.draw(mutated_array(arrays[k]))
    arrays["meta"] = meta_array(_rehash_asset(meta, arrays))
    path = _write(tmp_path, "b.npz", npz_bytes(arrays))
    ok, asset = outcome(BillboardAsset.load, path)
    if ok:
        _check_asset(asset)
        # a loaded asset serves its views: a reference and the classic billboard
        ok, img = outcome(asset.reference, 0)
        if ok:
            assert img.dtype == np.float32 and img.shape[-1] == 4
            assert np.isfinite(img).all() and img.min() >= 0 and img.max() <= 1
    outcome(read_record, path)


# =================================================================== dome (relightable) asset
@pytest.fixture(scope="module")
def dome_bytes(tmp_path_factory) -> bytes:
    from morphkit.billboard.analytic import sphere_dome_asset

    path = tmp_path_factory.mktemp("dome") / "d.npz"
    return sphere_dome_asset(size=16, levels=1).save(path).read_bytes()


def _check_dome(asset: DomeAsset) -> None:
    rec = asset.record()
    assert rec.rgba.dtype == np.uint8 and rec.normal.dtype == np.int8
    assert not np.isnan(rec.depth).any() and not (rec.depth == -np.inf).any()
    # a loaded asset serves a surface between its views: finite, alpha in [0, 1]
    ok, surf = outcome(asset.surface, 17.0, 33.0)
    if ok:
        assert np.isfinite(surf.albedo).all() and 0.0 <= surf.alpha.min() <= surf.alpha.max() <= 1.0


@given(data=st.data())
def test_dome_damaged_bytes(dome_bytes, tmp_path, data):
    path = _write(tmp_path, "d.npz", data.draw(damaged(dome_bytes)))
    ok, asset = outcome(DomeAsset.load, path)
    if ok:
        _check_dome(asset)


@given(data=st.data())
def test_dome_bad_metadata_and_values(dome_bytes, tmp_path, data):
    arrays = read_npz(dome_bytes)
    meta = json.loads(bytes(arrays["meta"]).decode())
    if data.draw(st.booleans(), label="mutate metadata"):
        meta = data.draw(mutated_json(meta, keep=("sha256", "format", "version", "kind")))
    if data.draw(st.booleans(), label="mutate an array"):
        k = data.draw(st.sampled_from([k for k in arrays if k != "meta"]))
        arrays[k] = data.draw(mutated_array(arrays[k]))
    arrays["meta"] = meta_array(_rehash_asset(meta, arrays))
    path = _write(tmp_path, "d.npz", npz_bytes(arrays))
    ok, asset = outcome(DomeAsset.load, path)
    if ok:
        _check_dome(asset)
    outcome(read_dome, path)


# =================================================================== sun atlas
@pytest.fixture(scope="module")
def sun_atlas_bytes(tmp_path_factory) -> bytes:
    from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_view
    from morphkit.views.dome import ViewDome
    from morphkit.views.domecameras import DomeCameras

    dome = ViewDome(((10.0, 4), (50.0, 4)), top=True)
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (8, 8))
    depths = [sphere_view(cams.ortho_camera(a, e, (8, 8)))[2]
              for a, e in zip(dome.azimuths_deg(), dome.elevations_deg(), strict=True)]
    atlas = SunAtlas.from_depths(dome, cams, np.stack(depths), "1" * 64)
    return write_sun_atlas(tmp_path_factory.mktemp("sunatlas") / "s.sunatlas.npz", atlas).read_bytes()


def _check_sun_atlas(atlas: SunAtlas) -> None:
    assert not np.isnan(atlas.depth).any() and not (atlas.depth == -np.inf).any()
    # a loaded atlas serves a light view between its directions: depths finite or +inf
    ok, view = outcome(atlas.light_view, np.array([0.3, 0.2, 0.7]))
    if ok and view is not None:
        assert not np.isnan(view[1]).any()


@given(data=st.data())
def test_sun_atlas_damaged_bytes(sun_atlas_bytes, tmp_path, data):
    path = _write(tmp_path, "s.npz", data.draw(damaged(sun_atlas_bytes)))
    ok, atlas = outcome(read_sun_atlas, path)
    if ok:
        _check_sun_atlas(atlas)


@given(data=st.data())
def test_sun_atlas_bad_metadata_and_values(sun_atlas_bytes, tmp_path, data):
    arrays = read_npz(sun_atlas_bytes)
    meta = json.loads(bytes(arrays["meta"]).decode())
    if data.draw(st.booleans(), label="mutate metadata"):
        meta = data.draw(mutated_json(meta, keep=("sha256", "format", "version")))
    if data.draw(st.booleans(), label="mutate an array"):
        k = data.draw(st.sampled_from(["depth", "coverage"]))
        arrays[k] = data.draw(mutated_array(arrays[k]))
    arrays["meta"] = meta_array(_rehash_asset(meta, arrays))
    path = _write(tmp_path, "s.npz", npz_bytes(arrays))
    ok, atlas = outcome(read_sun_atlas, path)
    if ok:
        _check_sun_atlas(atlas)


# =================================================================== bake manifest and journal
def _manifest_record(name: str = "a/b") -> ManifestRecord:
    kind = ShadowAtlasKind()
    return ManifestRecord(name=name, input=f"/in/{name}.obj", input_sha256="0" * 64, input_bytes=10,
                          status="baked", outputs={kind.name: OutputRecord(
                              f"{name}.atlas.npz", "1" * 64, 100, kind.version, kind.options(), 0.5)},
                          timings_s={"load": 0.1, "total": 0.6}, worker="host:1")


@pytest.fixture(scope="module")
def manifest_bytes(tmp_path_factory) -> tuple[bytes, bytes]:
    folder = tmp_path_factory.mktemp("manifest")
    m = Manifest(folder, run={"started": "now", "wall_s": 1.5, "baked": 1, "skipped": 0, "failed": 0})
    m.record(_manifest_record())
    m.commit()
    m.record(_manifest_record("c"))
    journal = m.journal.read_bytes()
    return m.path.read_bytes(), journal


def _use_manifest(m: Manifest) -> None:
    """What a bake does with an opened manifest: counts, failures, the summary, up-to-date checks."""
    counts = m.counts()
    assert sum(counts.values()) == len(m.assets)
    assert all(isinstance(v, str) for v in m.failed().values())
    assert isinstance(m.summary(), str) and "\n" not in m.summary()
    kind = ShadowAtlasKind()
    for name in list(m.assets):
        assert m.up_to_date(name, "0" * 64, kind, up_axis="z") in (True, False)
    json.dumps(m.to_dict(), allow_nan=False)


def _open_manifest(tmp_path: Path, manifest: bytes | None, journal: bytes | None) -> None:
    for name, data in (("manifest.json", manifest), ("manifest.journal", journal)):
        if data is not None:
            (tmp_path / name).write_bytes(data)
    ok, m = outcome(Manifest.open, tmp_path)
    if ok:
        ok, _ = outcome(_use_manifest, m)


@given(data=st.data())
def test_manifest_damaged_bytes(manifest_bytes, tmp_path, data):
    manifest, journal = manifest_bytes
    which = data.draw(st.sampled_from(["manifest", "journal", "both"]))
    m = data.draw(damaged(manifest)) if which != "journal" else manifest
    j = data.draw(damaged(journal)) if which != "manifest" else journal
    _open_manifest(tmp_path, m, j)


@given(data=st.data())
def test_manifest_and_journal_bad_fields(manifest_bytes, tmp_path, data):
    manifest, journal = manifest_bytes
    d = json.loads(manifest)
    if data.draw(st.booleans(), label="mutate the manifest"):
        d = data.draw(mutated_json(d, keep=("format", "version")))
    j = journal
    if data.draw(st.booleans(), label="mutate the journal"):
        lines = [data.draw(mutated_json(json.loads(line))) for line in journal.decode().splitlines()]
        j = "".join(json.dumps(x) + "\n" for x in lines).encode()
    _open_manifest(tmp_path, json.dumps(d).encode(), j)


# =================================================================== view-morph points
POINTS = Correspondences(np.array([[1.5, 2.0], [10.0, 3.25], [4.0, 8.0]]),
                         np.array([[2.5, 2.0], [11.0, 3.5], [5.0, 8.5]]), "user")


def _check_points(c: Correspondences) -> None:
    assert c.pts0.shape == c.pts1.shape and c.pts0.ndim == 2 and c.pts0.shape[1] == 2
    assert np.isfinite(c.pts0).all() and np.isfinite(c.pts1).all()


@pytest.mark.parametrize("suffix", [".json", ".csv"])
@given(data=st.data())
def test_points_damaged_bytes(tmp_path, suffix, data):
    valid = save_points(tmp_path / f"valid{suffix}", POINTS).read_bytes()
    path = _write(tmp_path, f"p{suffix}", data.draw(damaged(valid)))
    ok, c = outcome(load_points, path)
    if ok:
        _check_points(c)


_cell = st.one_of(st.floats(), st.integers(-2**70, 2**70), st.text(max_size=5),
                  st.sampled_from(["nan", "inf", "-inf", "1e999", "", " 1", "\ufeffx0", "x0"]))


@given(rows=st.lists(st.lists(_cell, max_size=6), max_size=6))
def test_points_csv_generated_rows(tmp_path, rows):
    text = "\n".join(",".join(str(c) for c in r) for r in rows)
    path = _write(tmp_path, "p.csv", text.encode("utf-8", "surrogatepass"))
    ok, c = outcome(load_points, path)
    if ok:
        _check_points(c)


@given(doc=st.one_of(
    mutated_json({"pts0": POINTS.pts0.tolist(), "pts1": POINTS.pts1.tolist()}),
    mutated_json([[1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 7.0, 8.0]]),
    mutated_json([{"x0": 1, "y0": 2, "x1": 3, "y1": 4}]),
    st.builds(lambda v: v, st.recursive(st.none() | st.floats() | st.text(max_size=3),
                                        lambda c: st.lists(c, max_size=4)
                                        | st.dictionaries(st.sampled_from(["pts0", "pts1", "x0"]), c),
                                        max_leaves=8))))
def test_points_json_generated_documents(tmp_path, doc):
    path = _write(tmp_path, "p.json", json.dumps(doc).encode())
    ok, c = outcome(load_points, path)
    if ok:
        _check_points(c)


# =================================================================== meshes
@pytest.fixture(scope="module")
def mesh_bytes(tmp_path_factory) -> dict[str, bytes]:
    box = trimesh.creation.box((1.0, 0.5, 0.25))
    return {s: box.export(file_type=s[1:]) if s != ".obj" else box.export(file_type="obj").encode()
            for s in (".obj", ".ply", ".glb")}


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".glb"])
@given(data=st.data())
def test_mesh_damaged_bytes(mesh_bytes, tmp_path, suffix, data):
    path = _write(tmp_path, f"m{suffix}", data.draw(damaged(mesh_bytes[suffix])))
    ok, mesh = outcome(load_mesh, path)
    if ok:
        assert len(mesh.faces) > 0 and np.isfinite(mesh.vertices).all()


# =================================================================== images
@pytest.fixture(scope="module")
def image_bytes(tmp_path_factory) -> dict[str, bytes]:
    folder = tmp_path_factory.mktemp("img")
    img = np.random.default_rng(3).integers(0, 256, (6, 5, 4), dtype=np.uint8)
    return {s: write_image(folder / f"i{s}", img if s == ".png" else img[..., :3]).read_bytes()
            for s in (".png", ".jpg", ".bmp", ".tif")}


@pytest.mark.parametrize("suffix", [".png", ".jpg", ".bmp", ".tif"])
@given(data=st.data())
def test_image_damaged_bytes(image_bytes, tmp_path, suffix, data):
    path = _write(tmp_path, f"i{suffix}", data.draw(damaged(image_bytes[suffix])))
    ok, img = outcome(read_image, path)
    if ok:
        assert img.ndim in (2, 3) and img.dtype in (np.uint8, np.uint16, np.float32)
        assert img.size > 0
