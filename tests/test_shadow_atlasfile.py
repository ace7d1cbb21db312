"""The shadow atlas file: checksums, value checks, typed metadata (no GL: a synthetic atlas).

Every corruption here used to load silently (NaN in a map, two map rows swapped,
surface and plane anchors swapped) or raise a raw KeyError/TypeError/ValueError
(a missing key, a wrongly typed field); each is now a FileFormatError that says
what was expected and what the file holds.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit.errors import FileFormatError
from morphkit.scene import PointLight
from morphkit.shadow import ATLAS_VERSION, BakedAtlas, LightRig, MotionRange
from morphkit.shadow.formats.atlasfile import load_atlas, save_atlas
from morphkit.shadow.rig import sample_axis

LIGHT = PointLight([0.2, -0.1, 2.6])


@pytest.fixture(scope="module")
def atlas() -> BakedAtlas:
    """A 3 x 3 atlas of 24 x 32 maps with made-up depths (finite on a blob, +inf
    elsewhere) and distinct surface and plane anchors: enough for the file format."""
    box = trimesh.creation.box((0.4, 0.3, 0.5))
    box.apply_translation([0, 0, 0.25])
    motion = MotionRange([-0.5, -0.4], [0.5, 0.4])
    rig = LightRig(LIGHT, box, np.eye(4), motion, (24, 32))
    rng = np.random.default_rng(7)
    xs, ys = sample_axis(-0.5, 0.5, 3), sample_axis(-0.4, 0.4, 3)
    maps = np.full((3, 3, 24, 32), np.inf, np.float32)
    maps[:, :, 6:18, 8:24] = rng.uniform(2.0, 2.5, (3, 3, 12, 16))
    plane = np.zeros((3, 3, 9, 3))
    plane[..., :2] = rng.uniform(-0.2, 0.2, (3, 3, 9, 2))
    plane[..., 2] = 0.25
    surf = plane + rng.uniform(-0.05, 0.05, plane.shape)
    return BakedAtlas(rig, xs, ys, maps, surf, plane, (3, 3), "sample")


def _arrays(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    return json.loads(bytes(arrays["meta"]).decode()), arrays


def _write(path: Path, meta: dict, arrays: dict[str, np.ndarray], *, rehash: tuple[str, ...] = ()) -> Path:
    """Write ``arrays`` with ``meta``; ``rehash`` names arrays whose checksum is
    recomputed (a writer with a bug, not a damaged file: the values must be checked too)."""
    meta = json.loads(json.dumps(meta))
    for k in rehash:
        meta["arrays"][k]["sha256"] = hashlib.sha256(np.ascontiguousarray(arrays[k]).tobytes()).hexdigest()
    out = dict(arrays, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8))
    np.savez(path, **out)
    return path


def test_round_trip_stores_a_checksum_per_array(tmp_path, atlas):
    path = save_atlas(atlas, tmp_path / "a.npz")
    meta, arrays = _arrays(path)
    assert meta["version"] == ATLAS_VERSION == 3
    names = {"xs", "ys", "maps", "anchors", "plane_anchors", "control", "triangles"}
    assert set(meta["arrays"]) == names
    for k in names:
        assert meta["arrays"][k]["sha256"] == hashlib.sha256(arrays[k].tobytes()).hexdigest()
    b = load_atlas(path, light=LIGHT)
    for k in ("xs", "ys", "maps", "anchors", "plane_anchors", "control"):
        np.testing.assert_array_equal(getattr(b, k), getattr(atlas, k))
    assert b.control_grid == atlas.control_grid and b.anchor_kind == atlas.anchor_kind
    assert b.mesh_sha256 is None and meta["mesh_sha256"] is None  # made-up maps: no mesh known
    digest = "ab" * 32
    c = load_atlas(save_atlas(dataclasses.replace(atlas, mesh_sha256=digest), tmp_path / "m.npz"))
    assert c.mesh_sha256 == digest


@pytest.mark.parametrize("value, match", [
    ("ab" * 31, r"atlas mesh_sha256: expected 64 hex digits or null, got 'abab"),
    (5, r"atlas mesh_sha256: expected 64 hex digits or null, got 5"),
])
def test_a_bad_mesh_record_is_refused(tmp_path, atlas, value, match):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    meta["mesh_sha256"] = value
    with pytest.raises(FileFormatError, match=match):
        load_atlas(_write(tmp_path / "bad.npz", meta, arrays))
    del meta["mesh_sha256"]  # a version-2 writer's metadata under version 3
    with pytest.raises(FileFormatError, match=r"atlas metadata: expected a key 'mesh_sha256'"):
        load_atlas(_write(tmp_path / "old.npz", meta, arrays))


def test_nan_in_a_map_is_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    arrays["maps"] = arrays["maps"].copy()
    arrays["maps"][1, 2, 10, 12] = np.nan
    with pytest.raises(FileFormatError, match=r"atlas array 'maps': expected sha256 [0-9a-f]{12}.*, got "
                       r"[0-9a-f]{12}.* \(corrupt file\)"):
        load_atlas(_write(tmp_path / "nan.npz", meta, arrays))
    # even with a matching checksum (a writer's bug), NaN depths are refused
    with pytest.raises(FileFormatError, match=r"atlas maps: expected finite or \+inf depths, "
                       r"got 1 NaN/-inf values"):
        load_atlas(_write(tmp_path / "nan2.npz", meta, arrays, rehash=("maps",)))
    arrays["maps"][1, 2, 10, 12] = -np.inf
    with pytest.raises(FileFormatError, match=r"expected finite or \+inf depths, got 1 NaN/-inf"):
        load_atlas(_write(tmp_path / "neginf.npz", meta, arrays, rehash=("maps",)))


def test_two_map_rows_swapped_are_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    m = arrays["maps"].copy()
    m[1, 1, [8, 9]] = m[1, 1, [9, 8]]
    assert not np.array_equal(m, arrays["maps"], equal_nan=True)  # the rows differ
    arrays["maps"] = m
    with pytest.raises(FileFormatError, match=r"atlas array 'maps': expected sha256 .*\(corrupt file\)"):
        load_atlas(_write(tmp_path / "rows.npz", meta, arrays))


def test_surface_and_plane_anchors_swapped_are_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    arrays["anchors"], arrays["plane_anchors"] = arrays["plane_anchors"], arrays["anchors"]
    with pytest.raises(FileFormatError, match=r"atlas array 'anchors': expected sha256"):
        load_atlas(_write(tmp_path / "swap.npz", meta, arrays))
    # checksums swapped too: the stored control points no longer follow from the anchors
    meta["arrays"]["anchors"], meta["arrays"]["plane_anchors"] = (meta["arrays"]["plane_anchors"],
                                                                  meta["arrays"]["anchors"])
    with pytest.raises(FileFormatError, match="atlas control points: expected consistent with its anchors"):
        load_atlas(_write(tmp_path / "swap2.npz", meta, arrays))


def test_non_finite_anchors_and_positions_are_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    for k, idx in [("anchors", (0, 0, 3, 1)), ("plane_anchors", (2, 1, 0, 2)), ("xs", (1,))]:
        bad = dict(arrays)
        bad[k] = arrays[k].copy()
        bad[k][idx] = np.inf
        with pytest.raises(FileFormatError, match=rf"atlas {k}: expected finite values, got 1 NaN/inf"):
            load_atlas(_write(tmp_path / f"{k}.npz", meta, bad, rehash=(k,)))
    bad = dict(arrays, ys=arrays["ys"][::-1].copy())
    with pytest.raises(FileFormatError, match=r"atlas ys: expected increasing sample positions"):
        load_atlas(_write(tmp_path / "ys.npz", meta, bad, rehash=("ys",)))


def test_inconsistent_shapes_are_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    bad = dict(arrays, xs=arrays["xs"][:2].copy())
    meta2 = json.loads(json.dumps(meta))
    meta2["arrays"]["xs"]["shape"] = [2]
    with pytest.raises(FileFormatError, match=r"atlas maps: expected shape \(3, 2, 24, 32\)"):
        load_atlas(_write(tmp_path / "xs.npz", meta2, bad, rehash=("xs",)))
    bad = dict(arrays, maps=arrays["maps"][:, :, :20].copy())
    meta2 = json.loads(json.dumps(meta))
    meta2["arrays"]["maps"]["shape"] = [3, 3, 20, 32]
    with pytest.raises(FileFormatError, match=r"atlas maps: expected shape \(3, 3, 24, 32\)"):
        load_atlas(_write(tmp_path / "maps.npz", meta2, bad, rehash=("maps",)))
    # an array whose shape or dtype differs from what the metadata declares
    bad = dict(arrays, maps=arrays["maps"].astype(np.float64))
    with pytest.raises(FileFormatError, match=r"atlas array 'maps': expected float32 of shape "
                       r"\[3, 3, 24, 32\], got float64"):
        load_atlas(_write(tmp_path / "dtype.npz", meta, bad))


@pytest.mark.parametrize("drop", ["meta:light", "meta:rig", "meta:control_grid", "meta:arrays",
                                  "meta:rig.fx", "meta:light.position", "meta:arrays.maps",
                                  "array:maps", "array:triangles"])
def test_missing_keys_are_file_format_errors(tmp_path, atlas, drop):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    where, key = drop.split(":")
    if where == "array":
        del arrays[key]
        match = rf"atlas file: expected a complete .* with the arrays .*, got no '{key}'"
    else:
        d, *rest = key.split(".")
        if rest:
            del meta[d][rest[0]]
            match = rf"atlas {d}: expected a key '{rest[0]}'"
        else:
            del meta[d]
            match = rf"atlas metadata: expected a key '{d}'"
    with pytest.raises(FileFormatError, match=match):
        load_atlas(_write(tmp_path / "missing.npz", meta, arrays))


@pytest.mark.parametrize("path, value, match", [
    (("control_grid",), "17x17", r"atlas control_grid: expected \[rows, cols\], integers >= 2, got '17x17'"),
    (("control_grid",), [3.5, 3], r"atlas control_grid: expected \[rows, cols\], integers >= 2"),
    (("anchor_kind",), 3, r"atlas anchor_kind: expected 'sample', 'shared' or 'plane', got 3"),
    (("version",), "3", r"atlas version: expected 3 .*, got '3'"),
    (("light",), "point", r"atlas light: expected an object, got 'point'"),
    (("light", "type"), "spot", r"atlas light type: expected 'directional' or 'point', got 'spot'"),
    (("light", "position"), [0, "a", 1], r"atlas light position: expected 3 finite numbers"),
    (("rig", "fx"), "abc", r"atlas rig fx: expected a finite number > 0, got 'abc'"),
    (("rig", "fx"), True, r"atlas rig fx: expected a finite number > 0, got True"),
    (("rig", "R"), [[1, 0], [0, 1]], r"atlas rig R: expected 3 x 3 finite numbers"),
    (("rig", "shape"), [24.5, 32], r"atlas rig shape: expected \[H, W\], integers >= 1"),
    (("rig", "lo"), [0.5, 0.4], r"atlas rig range: expected a valid motion range"),
    (("rig", "back"), None, r"atlas rig back: expected a number for a directional light"),
    (("arrays", "maps"), [1, 2], r"atlas arrays maps: expected an object with dtype, shape, sha256"),
    (("arrays", "maps", "sha256"), 5, r"atlas arrays maps: expected an object with dtype, shape, sha256"),
], ids=lambda v: str(v)[:20])
def test_wrongly_typed_fields_are_file_format_errors(tmp_path, atlas, path, value, match):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    if path == ("rig", "back"):  # only a directional light's rig has a 'back'
        meta["light"] = {"type": "directional", "direction": [0.0, 0.0, -1.0]}
    d = meta
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value
    with pytest.raises(FileFormatError, match=match):
        load_atlas(_write(tmp_path / "typed.npz", meta, arrays))


def test_metadata_that_is_not_an_object_is_refused(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    arrays["meta"] = np.frombuffer(b"[1, 2, 3]", np.uint8)
    np.savez(tmp_path / "list.npz", **arrays)
    with pytest.raises(FileFormatError, match=r"atlas metadata: expected a JSON object, got list"):
        load_atlas(tmp_path / "list.npz")


def test_version_one_files_are_refused_with_how_to_get_a_new_one(tmp_path, atlas):
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    meta["version"] = 1
    del meta["arrays"]
    with pytest.raises(FileFormatError, match=r"atlas version: expected 3 .*re-bake .*, got 1"):
        load_atlas(_write(tmp_path / "v1.npz", meta, arrays))


def test_pickled_object_arrays_are_never_loaded(tmp_path, atlas):
    """A file holding an object array would run code when unpickled: refused unread."""
    meta, arrays = _arrays(save_atlas(atlas, tmp_path / "a.npz"))
    arrays["xs"] = np.array([{"x": 1}, None, "a"], dtype=object)
    _write(tmp_path / "pickle.npz", meta, arrays)
    with pytest.raises(FileFormatError, match=r"atlas array 'xs': expected a numeric array "
                       r"\(pickled objects are never loaded\), got an object array"):
        load_atlas(tmp_path / "pickle.npz")


def test_save_is_atomic(tmp_path, atlas, monkeypatch):
    """A save that fails before it is complete (the disk fills up while the file
    is flushed) keeps the good atlas already at the path, and leaves no temporary."""
    import os

    path = save_atlas(atlas, tmp_path / "a.npz")
    good = path.read_bytes()

    def full(_fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    with pytest.raises(OSError, match="No space left"):
        save_atlas(atlas, path)
    monkeypatch.undo()
    assert path.read_bytes() == good
    assert [p.name for p in tmp_path.iterdir()] == ["a.npz"]
    load_atlas(path)


def test_non_npz_and_foreign_zip_files(tmp_path):
    (tmp_path / "x.npz").write_bytes(b"not a zip")
    with pytest.raises(FileFormatError, match="expected a complete morphkit-shadow-atlas .npz file"):
        load_atlas(tmp_path / "x.npz")
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("x.npy", b"nope")
    (tmp_path / "y.npz").write_bytes(buf.getvalue())
    with pytest.raises(FileFormatError, match="atlas file: expected"):
        load_atlas(tmp_path / "y.npz")
    with pytest.raises(FileFormatError, match="atlas file: expected an existing file"):
        load_atlas(tmp_path / "missing.npz")
