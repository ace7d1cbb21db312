"""morphkit.export: an asset's views tiled into atlases, a dome asset with its mesh and sun atlas
as one GLB and back, checked by the Khronos glTF validator; ``morphkit export`` end to end (GL)."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh
from gltfcheck import validate

from morphkit.billboard.analytic import SPHERE_PIVOT, sphere_dome_asset, sphere_impostor, sphere_view
from morphkit.cli import main
from morphkit.errors import FileFormatError, ValidationError
from morphkit.export import read_dome_glb, write_dome_glb
from morphkit.export.glb import read_glb
from morphkit.export.tiles import TILE_PAD, TileLayout, tile_views, untile_views
from morphkit.meshes import load_mesh, normalize, sample_mesh
from morphkit.sunlit.sunatlas import SunAtlas
from morphkit.views.dome import ViewDome
from morphkit.views.domecameras import DomeCameras

ROOT = Path(__file__).resolve().parent.parent


def test_views_tile_with_their_edges_repeated_and_untile_bit_for_bit():
    rng = np.random.default_rng(5)
    for shape, dtype in (((27, 16, 16, 4), np.uint8), ((5, 9, 9), np.uint16), ((1, 8, 8, 3), np.uint8)):
        views = rng.integers(0, 256, shape).astype(dtype)
        atlas, layout = tile_views(views)
        assert atlas.shape[:2] == layout.shape and atlas.dtype == dtype
        assert np.array_equal(untile_views(atlas, layout), views)
        # the padding repeats each view's edge: the pixel left of the first column is the first column's
        x, y = layout.origin(0)
        assert np.array_equal(atlas[y : y + shape[1], x - TILE_PAD], views[0][:, 0])
        assert np.array_equal(atlas[y - TILE_PAD, x : x + shape[2]], views[0][0, :])
    layout = TileLayout(27, 128)
    assert TileLayout.from_json(layout.to_json()) == layout
    with pytest.raises(FileFormatError, match="tile layout columns: expected 6, got 7"):
        TileLayout.from_json({**layout.to_json(), "columns": 7})
    with pytest.raises(FileFormatError, match="atlas: expected"):
        untile_views(np.zeros((10, 10), np.uint8), layout)
    with pytest.raises(ValidationError, match=r"views: expected \(V, n, n\) or \(V, n, n, C\) square"):
        tile_views(np.zeros((2, 8, 9), np.uint8))


def _sun_atlas(dome: ViewDome, n: int = 24) -> SunAtlas:
    cams = DomeCameras(SPHERE_PIVOT, 12.0, 1.0, (n, n))
    depths = [sphere_view(cams.ortho_camera(a, e, (n, n)))[2]
              for a, e in zip(dome.azimuths_deg(), dome.elevations_deg(), strict=True)]
    return SunAtlas.from_depths(dome, cams, np.stack(depths))


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    asset = sphere_dome_asset(size=32, levels=2)
    atlas = _sun_atlas(ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True))
    path = tmp_path_factory.mktemp("glb") / "ball.glb"
    write_dome_glb(path, asset, sun_atlas=atlas, measured={"morph": {"psnr_db": 28.9}},
                   impostor=sphere_impostor(frames=6, size=24))
    return asset, atlas, path


def test_a_dome_asset_round_trips_through_its_glb_bit_for_bit(exported):
    asset, atlas, path = exported
    back = read_dome_glb(path)
    a, b = asset.record(), back.asset.record()
    for k in ("rgba", "normal"):
        assert getattr(b, k).dtype == getattr(a, k).dtype and np.array_equal(getattr(b, k), getattr(a, k))
    assert np.array_equal(b.depth.view(np.uint16), a.depth.view(np.uint16))  # +inf and every bit kept
    keys = ("name", "mesh_hash", "appearance", "rings", "top", "pivot", "distance", "radius", "size")
    for k in (*keys, "levels"):
        assert getattr(b, k) == getattr(a, k), k
    assert np.array_equal(back.sun_atlas.depth.view(np.uint16), atlas.depth.view(np.uint16))
    assert np.array_equal(back.sun_atlas.coverage, atlas.coverage)
    # the impostor's frames too, bit for bit, and it draws as the original does
    imp = sphere_impostor(frames=6, size=24)
    assert back.impostor is not None and back.impostor.frames == 6 and back.impostor.frame_side == 24
    for k in (0, 17, 35):
        a_f, b_f = imp.stored_frame(k), back.impostor.stored_frame(k)
        assert np.array_equal(a_f.rgba, b_f.rgba) and np.array_equal(a_f.normal, b_f.normal)
        assert np.array_equal(a_f.depth.view(np.uint16), b_f.depth.view(np.uint16))
    np.testing.assert_array_equal(back.impostor.surface(20.0, 45.0).albedo, imp.surface(20.0, 45.0).albedo)
    assert back.sidecar["impostor"]["grid"].startswith("hemi-octahedral")
    side = back.sidecar
    assert side["morphkit_export"] == 1 and side["kind"] == "dome"
    assert side["measured"] == {"morph": {"psnr_db": 28.9}}
    assert len(side["views"]) == asset.dome.views and side["bounds"] is None
    assert side["depth_range"] == list(asset.cameras.depth_range())
    # the views drawn from the file are the asset's
    np.testing.assert_array_equal(back.asset.surface(20.0, 45.0).albedo, asset.surface(20.0, 45.0).albedo)
    # the images are plain PNGs of the documented kinds
    glb = read_glb(path)
    assert glb.image("albedo").shape[2] == 4 and glb.image("depth").dtype == np.uint16
    assert glb.tree["asset"]["version"] == "2.0"


def test_a_glb_that_is_not_morphkits_or_is_damaged_is_refused_naming_what(exported, tmp_path):
    _, _, path = exported
    plain = tmp_path / "plain.glb"
    plain.write_bytes(trimesh.creation.box().export(file_type="glb"))
    with pytest.raises(FileFormatError, match="expected a morphkit sidecar"):
        read_dome_glb(plain)
    data = bytearray(path.read_bytes())
    cut = tmp_path / "cut.glb"
    cut.write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(FileFormatError, match="expected a glTF 2.0 binary"):
        read_dome_glb(cut)
    n = struct.unpack_from("<I", data, 12)[0]
    tree = json.loads(bytes(data[20 : 20 + n]))
    tree["extras"]["morphkit"]["morphkit_export"] = 99
    other = tmp_path / "other.glb"
    other.write_bytes(trimesh.exchange.gltf.export_glb(trimesh.Scene(), tree_postprocessor=lambda t: t.update(
        {"extras": tree["extras"]})))
    with pytest.raises(FileFormatError, match="sidecar: expected morphkit_export 1 of kind 'dome', got 99"):
        read_dome_glb(other)
    with pytest.raises(ValidationError, match="asset: expected a DomeAsset"):
        write_dome_glb(tmp_path / "x.glb", "ball")


def test_an_atlas_wider_than_engines_load_is_refused_naming_the_limit(tmp_path):
    from morphkit import tol

    side = tol.EXPORT_MAX_TEXTURE_SIDE // 6 + 1  # 27 views: 6 columns of it and its padding, too wide
    asset = sphere_dome_asset(size=side, levels=1)
    limit = tol.EXPORT_MAX_TEXTURE_SIDE
    want = rf"the views' atlases: expected at most {limit} px a side .*bake smaller views"
    with pytest.raises(ValidationError, match=want):
        write_dome_glb(tmp_path / "big.glb", asset)
    assert not (tmp_path / "big.glb").exists()


def test_the_khronos_validator_finds_no_error_in_an_exported_asset(exported):
    _, _, path = exported
    report = validate(path)
    assert report["errors"] == 0, report["messages"]
    assert report["warnings"] == 0, report["messages"]


@pytest.mark.gl
def test_export_bakes_a_mesh_into_a_glb_engines_and_trimesh_read(tmp_path, capsys):
    out = tmp_path / "tree.glb"
    assert main(["export", "tree", "-o", str(out), "--size", "32", "--sun-atlas-size", "32"]) == 0
    said = capsys.readouterr().out
    assert "tree, 27 views of 32 px" in said and "its mesh, its sun atlas of 32 texels" in said
    back = read_dome_glb(out)
    assert back.sun_atlas is not None and back.sun_atlas.size == 32
    # its impostor at equal bytes (12 x 12 frames, the largest whose bytes do not pass the views'), and
    # each one's error against the mesh measured into the sidecar
    assert back.impostor is not None and back.impostor.frames == 12 and "octahedral impostor" in said
    m = back.sidecar["measured"]
    side = back.impostor.frame_side  # the largest frames that fit the views' bytes
    assert m["impostor"]["bytes"] <= m["morph"]["bytes"] < 144 * (side + 1) ** 2 * 9
    # PSNR against the mesh at the preview's first view: the morph of the same bytes errs less (on the
    # tree at 128 px: 32.34 against 29.5 dB)
    assert m["morph"]["psnr_db"] > m["impostor"]["psnr_db"] > 15.0
    # the mesh as trimesh reads the file: +y up, glTF's frame, (x, y, z) of morphkit's at (x, z, -y)
    scene = trimesh.load(out)
    (lo_x, lo_y, lo_z), (hi_x, hi_y, hi_z) = back.sidecar["bounds"]
    np.testing.assert_allclose(scene.bounds, [[lo_x, lo_z, -hi_y], [hi_x, hi_z, -lo_y]], atol=1e-6)
    # and as morphkit reads it (turned +z up): the asset's own mesh, which the asset accepts
    mesh = load_mesh(out)
    want = normalize(sample_mesh("tree"))
    np.testing.assert_allclose(mesh.bounds, want.bounds, atol=1e-6)
    # the same points (the checker's colour groups split the vertices they share): float32 apart
    from scipy.spatial import cKDTree

    assert cKDTree(want.vertices).query(mesh.vertices)[0].max() < 1e-6
    assert cKDTree(mesh.vertices).query(want.vertices)[0].max() < 1e-6
    assert validate(out)["errors"] == 0
    # the usual rule: an existing file is replaced only with --overwrite
    assert main(["export", "tree", "-o", str(out), "--size", "32"]) == 2
    assert "expected a new file, or --overwrite to replace it" in capsys.readouterr().err
    assert main(["export", "tree", "-o", str(tmp_path / "tree.png")]) == 1
    assert "-o: expected a .glb file path" in capsys.readouterr().err


def _accessor(glb, index: int) -> np.ndarray:
    acc = glb.tree["accessors"][index]
    view = glb.tree["bufferViews"][acc["bufferView"]]
    width = {"VEC3": 3, "VEC4": 4}[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    return np.frombuffer(glb.binary, np.float32, acc["count"] * width, start).reshape(-1, width)


def test_a_scene_is_one_glb_whose_instances_stand_where_the_scene_puts_them(tmp_path):
    from morphkit.billboard import Instances
    from morphkit.export.assetglb import ExportedAsset, write_scene_glb
    from morphkit.export.glb import INSTANCING
    from morphkit.meshes import Y_UP_TO_Z_UP
    from morphkit.scene import Item

    ball = sphere_dome_asset(size=16, levels=1)
    box = sphere_dome_asset(size=16, levels=1, name="box")
    shape = trimesh.creation.box((0.5, 0.4, 1.0))
    inst = Instances(("ball", "box"), np.array([0, 1, 0, 0]), np.array([[0.0, 0.0], [2.0, 1.0], [-1.5, 3.0],
                                                                          [4.0, -2.0]]),
                     np.array([0.0, 30.0, 90.0, 200.0]), np.array([1.0, 2.0, 0.5, 1.5]))
    path = tmp_path / "scene.glb"
    write_scene_glb(path, {"ball": ExportedAsset(ball, [Item(trimesh.creation.icosphere())]),
                           "box": ExportedAsset(box, [Item(shape, color=(0.2, 0.5, 0.1))])}, inst)
    glb = read_glb(path)
    side = glb.sidecar
    assert side["kind"] == "scene" and side["assets"]["ball"]["instances"] == 3
    assert side["assets"]["box"]["instances"] == 1 and glb.tree["extensionsUsed"] == [INSTANCING]
    # every instance's vertex where the scene puts it: the node's turn +y up after the instance's
    nodes = {n["name"]: n for n in glb.tree["nodes"] if "name" in n}
    for a, name in enumerate(inst.names):
        (node,) = [nodes[nm] for nm in side["assets"][name]["nodes"]]
        attrs = node["extensions"][INSTANCING]["attributes"]
        t, q, s = (_accessor(glb, attrs[k]).astype(float) for k in ("TRANSLATION", "ROTATION", "SCALE"))
        matrix = np.array(node.get("matrix", np.eye(4).ravel()), float).reshape(4, 4).T  # column-major
        np.testing.assert_allclose(matrix, np.linalg.inv(Y_UP_TO_Z_UP), atol=1e-12)
        for j, k in enumerate(np.flatnonzero(inst.asset == a)):
            trs = trimesh.transformations.quaternion_matrix([q[j, 3], *q[j, :3]])  # (w, x, y, z)
            trs[:3, :3] *= s[j][None, :]
            trs[:3, 3] = t[j]
            np.testing.assert_allclose(trs, inst.object2world(k), atol=1e-6)
    # each asset's views read back from the scene's file, by name
    back = read_dome_glb(path, "box")
    assert back.asset.name == "box" and np.array_equal(back.asset.record().rgba, box.record().rgba)
    with pytest.raises(FileFormatError, match=r"expected one asset \(or a name\), got \['ball', 'box'\]"):
        read_dome_glb(path)
    assert validate(path)["errors"] == 0
    with pytest.raises(ValidationError, match="assets: expected one per asset of the instances"):
        write_scene_glb(tmp_path / "x.glb", {"ball": ExportedAsset(ball)}, inst)


@pytest.mark.gl
def test_export_writes_a_scene_file_as_one_glb(tmp_path, capsys):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({
        "morphkit_scene": 1, "assets": [{"name": "tree", "source": "tree", "scale": 2.0}],
        "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 0.0},
                                 {"asset": "tree", "x": 3.0, "y": 1.0}]},
        "camera": {"path": "orbit"}, "image": {"width": 96, "height": 72}, "frames": 2, "asset_size": 32,
    }))
    out = tmp_path / "scene.glb"
    assert main(["export", str(scene), "-o", str(out), "--sun-atlas-size", "16"]) == 0
    assert "tree: 2 instances, 27 views of 32 px" in capsys.readouterr().out
    back = read_dome_glb(out)  # its one asset
    assert back.sun_atlas is not None and back.sidecar["instances"] == 2
    assert validate(out)["errors"] == 0
