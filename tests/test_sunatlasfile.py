"""The sun atlas file (shadow.sunatlasfile): round trip and refusals, no GL (depths made by hand)."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from morphkit.errors import FileFormatError
from morphkit.sunlit.receivers import SCENE_ATLAS_DOME
from morphkit.sunlit.sunatlas import SunAtlas
from morphkit.sunlit.sunatlasfile import SavableSunAtlas, read_sun_atlas, write_sun_atlas
from morphkit.views.domecameras import DomeCameras


def _atlas(seed: int = 0) -> SunAtlas:
    cams = DomeCameras(np.array([0.0, 0.0, 0.5]), 12.0, 0.7, 16)
    rng = np.random.default_rng(seed)
    depths = 12.0 + rng.uniform(-0.5, 0.5, (SCENE_ATLAS_DOME.views, 16, 16))
    depths[:, :3] = np.inf  # nothing drawn on some rows
    return SunAtlas.from_depths(SCENE_ATLAS_DOME, cams, depths, "ab" * 32)


def test_round_trip_is_bit_identical(tmp_path):
    atlas = _atlas()
    path = SavableSunAtlas(atlas).save(tmp_path / "duck.sunatlas.npz")
    back = read_sun_atlas(path)
    assert (back.dome.rings, back.dome.top) == (atlas.dome.rings, atlas.dome.top)
    assert back.mesh_hash == atlas.mesh_hash and back.size == 16
    np.testing.assert_array_equal(back.depth.view(np.uint16), atlas.depth.view(np.uint16))
    np.testing.assert_array_equal(back.coverage, atlas.coverage)
    a, b = back.cameras, atlas.cameras
    assert (a.distance, a.radius, a.shape) == (b.distance, b.radius, b.shape)
    np.testing.assert_array_equal(a.pivot, b.pivot)


def _rewrite(path, **meta_changes):
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(bytes(arrays.pop("meta")).decode())
    meta.update(meta_changes)
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
    path.write_bytes(buf.getvalue())


def test_damaged_or_foreign_files_are_refused(tmp_path):
    path = write_sun_atlas(tmp_path / "a.sunatlas.npz", _atlas())
    good = path.read_bytes()
    _rewrite(path, version=99)
    with pytest.raises(FileFormatError, match=r"version: expected 1, got 99 \(re-bake it\)"):
        read_sun_atlas(path)
    path.write_bytes(good)
    _rewrite(path, format="morphkit-billboard")
    with pytest.raises(FileFormatError, match="format: expected morphkit-sun-atlas"):
        read_sun_atlas(path)
    path.write_bytes(good)
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["coverage"][0, 5, 5] ^= 255
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    path.write_bytes(buf.getvalue())
    with pytest.raises(FileFormatError, match="checksum recorded in meta"):
        read_sun_atlas(path)
    path.write_bytes(good[: len(good) // 2])
    with pytest.raises(FileFormatError, match="a complete morphkit-sun-atlas .npz file"):
        read_sun_atlas(path)
    with pytest.raises(FileFormatError, match="nothing at"):
        read_sun_atlas(tmp_path / "none.npz")
    with pytest.raises(FileFormatError, match="a regular file"):
        read_sun_atlas(tmp_path)


def _parts(path):
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    return json.loads(bytes(arrays.pop("meta")).decode()), arrays


def _rehashed(path, meta, arrays):
    """``path`` rewritten with ``meta`` and ``arrays``, the checksums recomputed: a writer's bug, not
    a damaged disk (the checks past the checksums)."""
    from morphkit.files.fileio import array_digest

    meta["sha256"] = {k: array_digest(a) for k, a in arrays.items()}
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
    path.write_bytes(buf.getvalue())
    return path


def _set(key, value):
    def change(meta, arrays):
        meta[key] = value
    return change


def _drop(key):
    def change(meta, arrays):
        del meta[key]
    return change


def _behind_the_camera(meta, arrays):
    arrays["depth"] = np.where(np.isfinite(arrays["depth"]), np.float16(-13.0), arrays["depth"])


def _fewer_views(meta, arrays):
    meta["rings"] = meta["rings"][:2]


@pytest.mark.parametrize(("change", "message"), [
    (_set("top", "false"), r"top: expected true or false, got 'false'"),
    (_set("size", 16.5), "size: expected an integer, got 16.5"),
    (_set("rings", [[10.0, 8.9], [40.0, 8], [70.0, 4]]), r"rings: expected 1 to 16 \[elevation_deg, views\]"),
    (_set("version", True), r"version: expected 1, got True \(re-bake it\)"),
    (_set("mesh_hash", "abc"), "mesh_hash: expected 64 hex digits, got 'abc'"),
    (_set("pivot", [0.0, 0.0]), "pivot: expected 3 finite numbers"),
    (_drop("radius"), "meta: expected a 'radius' entry"),
    (_set("radius", 20.0), "meta: expected a dome, cameras and arrays that fit them, got ValidationError: "
     "radius: expected < the camera distance"),
    (_fewer_views, r"meta: expected a dome, cameras and arrays that fit them, got ValidationError: depth, "
     r"coverage: expected float16 and uint8 arrays of \(17, 16, 16\)"),
    (_behind_the_camera, r"depth: expected drawn depths within the light views' near and far planes "
     r"\(offsets within \+-1.05 of the distance 12\), or \+inf, got offsets -13 to -13"),
])
def test_metadata_of_another_type_or_values_that_cannot_be_are_refused_naming_the_file(tmp_path, change,
                                                                                      message):
    path = write_sun_atlas(tmp_path / "a.sunatlas.npz", _atlas())
    meta, arrays = _parts(path)
    change(meta, arrays)
    with pytest.raises(FileFormatError, match=r"^sun atlas file '.*a\.sunatlas\.npz': " + message):
        read_sun_atlas(_rehashed(path, meta, arrays))
