"""The sun atlases a bake made, found again by billboards --shadows (:mod:`morphkit.bake.reuse`),
without GL: a bake folder written by hand (a manifest listing a dome asset and its sun atlas; the
dome asset's bytes are not read here) and atlases of the analytic sphere's depths.

Taken when of the size, the sun directions and the mesh asked; else said why (and baked at the
run); a damaged atlas file refused in one error naming the asset, the file and what to do.
"""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit.bake.kinds import SunAtlasKind
from morphkit.bake.manifest import AssetRecord, Manifest, OutputRecord
from morphkit.bake.reuse import baked_sun_atlases
from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_view
from morphkit.billboard.baking.bakelook import mesh_hash
from morphkit.errors import FileFormatError
from morphkit.sunlit.receivers import SCENE_ATLAS_DOME
from morphkit.sunlit.sunatlas import SunAtlas
from morphkit.sunlit.sunatlasfile import write_sun_atlas
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras

BOX = trimesh.creation.box((0.4, 0.4, 1.0))
N = 16


def _atlas(dome: ViewDome = SCENE_ATLAS_DOME, mesh: trimesh.Trimesh = BOX) -> SunAtlas:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (N, N))
    depths = [sphere_view(cams.ortho_camera(a, e, (N, N)))[2]
              for a, e in zip(dome.azimuths_deg(), dome.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(dome, cams, np.stack(depths), mesh_hash(mesh))


def _bake_folder(folder: Path, atlas: SunAtlas | None) -> Path:
    """A bake folder with ``box.dome.npz`` and, when given, ``box.sunatlas.npz`` listed under one asset."""
    folder.mkdir()
    outputs = {"dome": OutputRecord("box.dome.npz", "1" * 64, 1, 3, {}, 0.1)}
    (folder / "box.dome.npz").write_bytes(b"not read here")
    if atlas is not None:
        write_sun_atlas(folder / "box.sunatlas.npz", atlas)
        outputs[SunAtlasKind.name] = OutputRecord("box.sunatlas.npz", "2" * 64, 1, SunAtlasKind.version,
                                                  SunAtlasKind(N).options(), 0.1)
    m = Manifest(folder)
    m.record(AssetRecord(name="box", input=str(folder / "box.ply"), input_sha256="0" * 64, input_bytes=1,
                         status="baked", outputs=outputs))
    m.commit()
    return folder / "box.dome.npz"


def test_an_atlas_of_the_mesh_size_and_sun_directions_asked_is_taken(tmp_path):
    dome = _bake_folder(tmp_path / "out", _atlas())
    got, said = baked_sun_atlases([str(dome)], ["box"], {"box": BOX}, N)
    assert list(got) == ["box"] and said == [f"box's from the bake (box.sunatlas.npz, {N} texels)"]
    assert got["box"].depth.tobytes() == _atlas().depth.tobytes()


@pytest.mark.parametrize(("atlas", "size", "mesh", "why"), [
    (_atlas(), 2 * N, BOX, f"box.sunatlas.npz: {N} texels, not {2 * N}: baked again"),
    (_atlas(ViewDome(((10.0, 8), (40.0, 8)), top=True)), N, BOX,
     "box.sunatlas.npz: 17 sun directions, not the scene's 21: baked again"),
    (_atlas(), N, trimesh.creation.cone(0.4, 0.9), "box.sunatlas.npz: baked from another mesh than box's: "
     "baked again"),
])
def test_an_atlas_that_does_not_serve_is_said_and_left(tmp_path, atlas, size, mesh, why):
    dome = _bake_folder(tmp_path / "out", atlas)
    assert baked_sun_atlases([str(dome)], ["box"], {"box": mesh}, size) == ({}, [why])


def test_a_bake_without_an_atlas_or_an_asset_of_no_bake_says_nothing(tmp_path):
    dome = _bake_folder(tmp_path / "out", None)
    alone = tmp_path / "alone.dome.npz"
    alone.write_bytes(b"x")
    assert baked_sun_atlases([str(dome), str(alone), "tree"], ["box", "alone", "tree"],
                             {"box": BOX, "alone": BOX, "tree": BOX}, N) == ({}, [])


def test_a_damaged_atlas_is_refused_naming_the_asset_the_file_and_what_to_do(tmp_path):
    dome = _bake_folder(tmp_path / "out", _atlas())
    path = tmp_path / "out" / "box.sunatlas.npz"
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["depth"][0, 8, 8] = np.float16(0.25)  # a byte gone wrong: the checksum no longer matches
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    path.write_bytes(buf.getvalue())
    assert json.loads(bytes(arrays["meta"]).decode())["format"] == "morphkit-sun-atlas"
    with pytest.raises(FileFormatError, match=r"^the bake's sun atlas of asset 'box': sun atlas file "
                       r"'.*box\.sunatlas\.npz': array 'depth': expected the checksum recorded in meta, got "
                       r"different bytes \(corrupt file\) \(bake it again with morphkit bake --sun-atlas, or "
                       r"remove the file to bake one at the run\)$"):
        baked_sun_atlases([str(dome)], ["box"], {"box": BOX}, N)
