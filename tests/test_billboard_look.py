"""Billboards in a mesh's own look (issue #24): appearance, the hash of the look, cut-outs, files."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

from morphkit.billboard import (
    BAKE_AMBIENT,
    VERSION,
    BillboardAsset,
    bake_asset,
    bake_items,
    bake_lights,
    look_hash,
    mesh_hash,
)
from morphkit.billboard.baking.bakelook import sideways_colour
from morphkit.errors import FileFormatError, ValidationError
from morphkit.files.fileio import write_bytes
from morphkit.imaging.appearance import checker_items
from morphkit.meshes import load_mesh, normalize, sample_mesh
from morphkit.programs.fixtures import photo_texture, textured_demo_asset, write_leaf_plant, write_photo_glb
from morphkit.programs.sources import resolve_assets

SIZE = 48
#: The stored (sRGB) colour of the one-colour box.
RED = (220, 60, 40)


def coloured_box(color=RED) -> trimesh.Trimesh:
    box = trimesh.creation.box(extents=(0.6, 0.4, 1.0))
    box.apply_translation([0.0, 0.0, 0.5])
    box.visual.vertex_colors = np.tile([*color, 255], (len(box.vertices), 1)).astype(np.uint8)
    return box


def covered_mean(img: np.ndarray) -> np.ndarray:
    """Mean straight colour (0..255) of the fully covered pixels of a premultiplied image."""
    cov = img[..., 3] > 0.99
    assert cov.sum() > 100
    return 255.0 * (img[..., :3][cov] / img[..., 3:][cov]).mean(axis=0)


def test_sideways_colour_is_the_ambient_term_in_gamma():
    np.testing.assert_allclose(sideways_colour([255, 0, 0]), [255 * 0.35 ** (1 / 2.2), 0, 0], rtol=1e-12)
    assert sideways_colour([0, 0, 0]).tolist() == [0.0, 0.0, 0.0]


def test_bake_items_appearance():
    box = coloured_box()
    own = bake_items(box)
    assert len(own) == 1 and own[0].color is None and own[0].mesh is box
    chk = bake_items(box, "checker")
    assert [it.color for it in chk] == [it.color for it in checker_items(box)]
    with pytest.raises(ValidationError, match=r"appearance: expected one of \['own', 'checker'\], "
                                              r"got 'flat'"):
        bake_items(box, "flat")


def test_hash_covers_the_look():
    box, other = coloured_box(), coloured_box((40, 60, 220))
    assert look_hash(box) != look_hash(other) and mesh_hash(box) != mesh_hash(other)
    # the checker ignores the mesh's own colours; the shape still counts
    assert mesh_hash(box, "checker") == mesh_hash(other, "checker") != mesh_hash(box)
    assert mesh_hash(box, "checker") != mesh_hash(sample_mesh("teapot"), "checker")
    moved = box.copy()
    moved.apply_translation([3.0, 1.0, 0.0])
    assert mesh_hash(moved) == mesh_hash(box)
    # a re-textured photo asset: same shape, another image
    a, b = (normalize(m) for m in (load_mesh(textured_demo_asset()), load_mesh(textured_demo_asset())))
    assert mesh_hash(a) == mesh_hash(b)
    b.visual.material.baseColorTexture = photo_texture(32, "coffee")
    assert mesh_hash(a) != mesh_hash(b) and mesh_hash(a, "checker") == mesh_hash(b, "checker")


@pytest.mark.gl
def test_own_look_is_kept_one_colour_within_2_of_255(renderer):
    """A box of one vertex colour seen at elevation 0 shows only its vertical faces, at right angles
    to the bake light: each covered pixel is the ambient term, sideways_colour(RED)."""
    asset = bake_asset(coloured_box(), renderer, name="box", views=2, size=SIZE, levels=1, elevation_deg=0.0)
    assert asset.appearance == "own"
    want = sideways_colour(RED)
    for img in (asset.reference(0), asset.reference(1), asset.morph(0, 1, 0.5), asset.classic()):
        assert np.abs(covered_mean(img) - want).max() <= 2.0
    # the checker, asked for, recolours it
    chk = bake_asset(coloured_box(), renderer, name="box", views=2, size=SIZE, levels=1, elevation_deg=0.0,
                     appearance="checker")
    assert chk.appearance == "checker" and chk.mesh_hash != asset.mesh_hash
    assert np.abs(covered_mean(chk.reference(0)) - want).max() > 20.0


@pytest.mark.gl
def test_cut_outs_are_holes_in_colour_depth_and_coverage(renderer, tmp_path):
    plant = load_mesh(write_leaf_plant(tmp_path))
    opaque = load_mesh(write_leaf_plant(tmp_path, name="opaque", cutoff=0.0))
    a = bake_asset(plant, renderer, name="plant", views=2, size=SIZE, levels=1)
    b = bake_asset(opaque, renderer, name="opaque", views=2, size=SIZE, levels=1)
    rec, rec_b = a.record(), b.record()
    hole, solid = rec.images[..., 3] == 0, rec.images[..., 3] == 255
    # a hole in colour is a hole in depth, a fully covered pixel has depth (edges: the renders'
    # supersampled coverage against depth at the pixel centre)
    assert not np.isfinite(rec.depth[hole]).any() and np.isfinite(rec.depth[solid]).all()
    # the masked leaves cover far less than the same cards drawn opaque
    assert hole.sum() > (rec_b.images[..., 3] == 0).sum() + 0.1 * hole.size * 0.2
    # the morph's alpha (from depth) follows the real cut-out plant, not the cards (measured at
    # 48^2: IoU 0.88 against the real plant; the opaque cards' morph 0.62 since their depth seen
    # from behind is complete (render.py: open surfaces take depth from the two-sided flat draw;
    # 0.43 before, when the depth-only draw culled the cards' back faces), the nearest view 0.38):
    # the cut-out morph must beat both by more than 0.15
    gt = renderer.source_view(a.camera(0.0), a.items(plant), bake_lights(), ambient=BAKE_AMBIENT)
    t = gt[..., 3] > 127

    def iou(img: np.ndarray) -> float:
        m = img[..., 3] > 0.5
        return float((m & t).sum() / (m | t).sum())

    cut = iou(a.morph(0, 1, 0.5))
    assert cut > 0.8 and cut - max(iou(b.morph(0, 1, 0.5)), iou(a.nearest(0, 1, 0.5))) > 0.15
    with pytest.raises(ValidationError, match="another shape or look"):
        a.items(opaque)


@pytest.mark.gl
def test_saved_asset_records_appearance_and_up_and_refuses_another_texture(renderer, tmp_path):
    path = write_photo_glb(tmp_path, photo_texture(32))
    mesh = load_mesh(path)
    asset = bake_asset(mesh, renderer, name="crate", views=2, size=SIZE, levels=1, source_up="y")
    f = asset.save(tmp_path / "crate.npz")
    back = BillboardAsset.load(f, mesh=mesh)
    assert (back.appearance, back.source_up, back.mesh_hash) == ("own", "y", asset.mesh_hash)
    meta = json.loads(bytes(np.load(f)["meta"]).decode())
    assert meta["version"] == VERSION == 2 and meta["appearance"] == "own" and meta["source_up"] == "y"
    other = load_mesh(write_photo_glb(tmp_path, photo_texture(32, "coffee"), name="other"))
    want = mesh_hash(other)
    with pytest.raises(FileFormatError, match=rf"expected {want} \(the given mesh's, shape and 'own' "
                                              rf"look\), got {asset.mesh_hash} \(baked from another mesh "
                                              r"or another look"):
        BillboardAsset.load(f, mesh=other)
    with pytest.raises(ValidationError, match=r"source_up: expected None or one of \['z', 'y'\]"):
        bake_asset(mesh, renderer, views=2, size=SIZE, levels=1, source_up="auto")


def _rewrite_meta(src: Path, dst: Path, change) -> Path:
    with np.load(src, allow_pickle=False) as z:
        data = {k: z[k] for k in z.files}
    m = change(json.loads(bytes(data["meta"]).decode()))
    data["meta"] = np.frombuffer(json.dumps(m).encode(), np.uint8)
    buf = io.BytesIO()
    np.savez(buf, **data)
    return write_bytes(dst, buf.getvalue())


@pytest.mark.gl
def test_older_and_bad_records_are_refused(renderer, tmp_path):
    asset = bake_asset(coloured_box(), renderer, views=2, size=32, levels=1)
    f = asset.save(tmp_path / "a.npz")
    old = _rewrite_meta(f, tmp_path / "v1.npz", lambda m: {**m, "version": 1})
    with pytest.raises(FileFormatError, match=r"version: expected 2, got 1 \(an older asset file: "
                                              r"re-bake it"):
        BillboardAsset.load(old)
    bad = _rewrite_meta(f, tmp_path / "bad.npz", lambda m: {**m, "appearance": "flat"})
    with pytest.raises(FileFormatError, match=r"meta\['appearance'\]: expected one of \['own', 'checker'\]"):
        BillboardAsset.load(bad)
    up = _rewrite_meta(f, tmp_path / "up.npz", lambda m: {**m, "source_up": "x"})
    with pytest.raises(FileFormatError, match=r"meta\['source_up'\]: expected 'z', 'y' or null"):
        BillboardAsset.load(up)


@pytest.mark.gl
def test_resolve_assets_bakes_mesh_files_and_finds_an_npz_mesh(renderer, tmp_path):
    glb = write_photo_glb(tmp_path, photo_texture(32), name="crate")
    res = resolve_assets([str(glb)], renderer, views=2, size=32, levels=1)
    asset = res.assets["crate"]
    assert (asset.appearance, asset.source_up) == ("own", "y") and "crate" in res.items
    # a baked file beside its mesh file finds it; bake_asset's default name becomes the file's
    baked = bake_asset(load_mesh(glb), renderer, views=2, size=32, levels=1, source_up="y")
    baked.save(tmp_path / "crate.billboard.npz")
    res = resolve_assets([str(tmp_path / "crate.billboard.npz")], renderer)
    assert list(res.assets) == ["crate"] and "crate" in res.items and not res.skipped
    lone = tmp_path / "lone"
    lone.mkdir()
    baked.save(lone / "thing.npz")
    res = resolve_assets([str(lone / "thing.npz")], renderer)
    assert list(res.assets) == ["thing"] and not res.items
    assert "no mesh file thing{.obj," in res.skipped["thing"] and "pass the mesh file" in res.skipped["thing"]
    # a sample name bakes in the checker (the samples have no look of their own)
    res = resolve_assets(["teapot"], renderer, views=2, size=32, levels=1)
    assert res.assets["teapot"].appearance == "checker"
