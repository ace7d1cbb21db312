"""`morphkit demo` and the CLI end to end (small images)."""

from __future__ import annotations

import json

import cv2
import pytest

from morphkit.cli import main


def test_help_lists_subcommands(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "demo" in out and "bench" in out


@pytest.mark.gl
def test_demo_quick_writes_indexed_files(tmp_path, capsys):
    # a previous demo: replaced only with --overwrite; its files that the new demo
    # does not write again go, files it did not list stay
    (tmp_path / "index.json").write_text(json.dumps({"morphkit_demo": 1, "files": [
        {"path": "old_extra.png"}, {"path": "teapot_scene.png"}]}))
    (tmp_path / "old_extra.png").write_bytes(b"old")
    (tmp_path / "notes.txt").write_text("mine")
    assert main(["demo", "--quick", "-o", str(tmp_path)]) == 2
    assert "pass --overwrite" in capsys.readouterr().err
    assert main(["demo", "--quick", "--overwrite", "-o", str(tmp_path)]) == 0
    assert not (tmp_path / "old_extra.png").exists() and (tmp_path / "notes.txt").read_text() == "mine"
    assert not list(tmp_path.glob(".*.part"))  # no temporary left
    index = json.loads((tmp_path / "index.json").read_text())
    names = {f["path"] for f in index["files"]}
    for mesh in ("teapot", "chair", "cow"):
        assert f"{mesh}_scene.png" in names and f"{mesh}_light_depth.png" in names
        assert f"{mesh}_warped_direct_raycast.png" in names and f"{mesh}_viewmorph.png" in names
        # view morph at s = 0.5, 20 deg baseline, 128^2 (quick): measured 0.959 (teapot),
        # 0.965 (chair), 0.976 (cow); 256^2 in docs/results/view_morphing.md: 0.965-0.985. 0.93 leaves
        # 0.029 for rasterisation at 128^2 and stays above the nearest reference view
        # (0.907 teapot, 0.562 chair, 0.776 cow at 256^2): a morph that fails falls below.
        assert index["view_morphing"][mesh]["silhouette_iou"] > 0.93
        assert f"{mesh}_reprojected_direct_raycast.png" in names
        # the reprojected map is exact for what a map saw: about as close to the
        # ray cast as the re-rendered map, up to its holes
        hard = index["warped_shadows"][mesh]
        assert (hard["iou_reprojected_vs_raycast_lightfacing_pixels"]
                >= hard["iou_direct_vs_raycast_lightfacing_pixels"] - 0.03)
        assert f"{mesh}_soft_warped_direct_raycast.png" in names
        # Warped and re-rendered soft shadows use the same 9 light samples, so they
        # differ from the ray cast alike, up to outline bands: within 0.03 of each
        # other (measured at 128^2: <= 0.016) and well under a wrong shadow's ~0.2.
        soft = index["soft_shadows"][mesh]
        warped = soft["mae_warped_vs_raycast_lightfacing_pixels"]
        assert warped <= soft["mae_direct_vs_raycast_lightfacing_pixels"] + 0.03 and warped < 0.1
    assert {"billboards_compare.png", "billboards_error.png", "billboards_textured.png",
            "billboards_relit.png"} <= names
    # the preview page: one self-contained file, within the 20 MB a page may take
    page = tmp_path / "tree_preview.html"
    assert "tree_preview.html" in names and page.stat().st_size == index["billboards"]["preview"]["bytes"]
    assert page.read_text().startswith("<!DOCTYPE html>") and page.stat().st_size <= 20_000_000
    # the textured asset's billboard beside its real mesh, in its own look, turned +z up
    tex = index["billboards"]["textured"]
    assert (tex["asset"], tex["appearance"], tex["source_up"]) == ("photo_crate.glb", "own", "y")
    assert all(v["iou"] > 0.9 for v in tex["morph_vs_mesh"].values())
    # relit from three heights: the view morph beside the impostor at equal bytes, both close to
    # the mesh in outline (IoU > 0.9, measured >= 0.95 at 64 px) and the morph the sharper (PSNR)
    relit = index["billboards"]["relit"]
    assert relit["impostor_bytes"] <= relit["bytes"]
    for row in relit["vs_mesh"].values():
        assert row["morph"]["iou"] > 0.9 and row["impostor"]["iou"] > 0.9
        assert row["morph"]["psnr"] > row["impostor"]["psnr"]
    # a field of trees and cows under a sun: atlas-shadowed billboards beside ray-cast meshes; the
    # ground's shadow matches (quick demo: measured IoU 0.92 with 64-texel atlases, 0.96 at 128)
    assert "billboards_shadowed.png" in names
    assert index["billboards"]["shadowed"]["shadow_iou_ground"] > 0.85
    # the first picture is morphkit's output: four rows (warped, soft, view morph, billboards),
    # each a captioned pair of OVERVIEW_TILE-high images; the ray-cast scenes have their own file
    from morphkit.programs.demo import OVERVIEW_TILE

    assert {"overview.png", "groundtruth_overview.png", "shadow_path_strip.png",
            "billboards_pan_strip.png"} <= names
    overview = cv2.imread(str(tmp_path / "overview.png"))
    assert overview.shape[0] == 4 * (OVERVIEW_TILE + 44 + 4)
    # view-morphed billboards outline the meshes better than classic ones (quick demo, 128 px wide:
    # measured IoU 0.93 vs 0.79 over 11 billboards); 0.05 leaves room for the tiny sizes
    bb = index["billboards"]["per_billboard_vs_mesh"]
    assert bb["morph"]["n"] >= 5 and bb["morph"]["iou"] > bb["classic"]["iou"] + 0.05
    for f in index["files"]:
        assert (tmp_path / f["path"]).stat().st_size > 0
    assert str(tmp_path) in capsys.readouterr().out
