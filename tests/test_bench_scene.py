"""``morphkit bench scene`` (issue #26): its sections, its scene's pieces and its quick run (structure and
sane values only: speed is never asserted)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from morphkit import bench
from morphkit.cli import main
from morphkit.errors import ValidationError

SECTIONS = {"accuracy", "per-asset", "receivers", "sun-change", "atlas-grid", "temporal", "sun-disc",
            "levels", "receivers-resolution"}


def test_suite_is_registered_with_its_sections():
    from morphkit.bench import scene_suite as ss

    assert "scene" in bench.SUITES
    assert {ss.section_name(s) for s in ss.SECTIONS} == SECTIONS
    assert [ss.section_name(s) for s in ss.selected_sections("temporal,accuracy")] == ["accuracy", "temporal"]
    with pytest.raises(ValidationError, match="no-such"):
        ss.selected_sections("accuracy,no-such")


def test_instances_is_an_option_of_bench_scene_only(capsys):
    assert main(["bench", "warp", "--quick", "--instances", "10"]) == 2
    assert "--instances is an option of `bench scene` only" in capsys.readouterr().err


def test_the_suns_rise_from_the_morning_to_noon_and_the_path_crosses_the_horizon():
    from morphkit.bench.fieldshadows.fields import day_suns, path_suns

    el = [math.degrees(math.asin(s[2])) for s in day_suns(4)]
    assert el == sorted(el) and 14.0 < el[0] < 16.0 and abs(el[-1] - 60.0) < 1e-9
    suns, elev = path_suns(24)
    assert len(suns) == 24 and elev[0] < 0 and elev[-1] < 0 and (elev[1:-1] > 0).all()


def test_subdivided_meshes_reach_the_face_count_and_keep_the_cutout(tmp_path):
    from morphkit.bench.fieldshadows.fields import subdivided, textured_meshes
    from morphkit.imaging.cutout import mesh_cutout

    meshes = textured_meshes(tmp_path)
    for target in (600, 6000):
        for name, m in meshes.items():
            s = subdivided(m, target)
            assert target <= len(s.faces) <= target + 2
            np.testing.assert_allclose(s.bounds, m.bounds, atol=1e-9)
            assert (mesh_cutout(s) is not None) == (name == "leaf-plant")


@pytest.mark.gl
@pytest.mark.slow  # ~10 s on an idle core (every section's quick case, bakes included), ~25 s on 2 busy ones
def test_the_quick_run_gives_every_section_with_sane_values(tmp_path, capsys):
    out = tmp_path / "scene.json"
    assert main(["bench", "scene", "--quick", "--json", str(out)]) == 0
    rows = json.loads(out.read_text())
    assert {r["params"]["section"] for r in rows} == SECTIONS
    printed = capsys.readouterr().out
    assert "atlas-cold" in printed  # the harness's table
    titles = ("accuracy (", "per asset (", "receivers (", "sun change (", "atlas grid vs", "temporal (",
              "sun disc (", "levels (", "receivers by resolution (")
    for title in titles:  # markdown
        assert title in printed
    for r in rows:
        assert r["suite"] == "scene" and r["ms_median"] > 0
        assert all(math.isfinite(v) for v in r["metrics"].values()), r
    acc = {r["method"]: r["metrics"] for r in rows if r["params"]["section"] == "accuracy"}
    assert set(acc) == {"atlas", "direct", "card-camera", "card-light", "ray-cast"}
    for m in ("atlas", "direct", "card-camera", "card-light"):
        assert 0.3 < acc[m]["iou_min"] <= acc[m]["iou"] <= 1.0 and 0.0 <= acc[m]["mae"] < 0.2
    # the camera's card casts the camera's silhouette: worse than the light's own
    assert acc["card-camera"]["iou"] < acc["card-light"]["iou"]
    per = {(r["params"]["asset"], r["method"]) for r in rows if r["params"]["section"] == "per-asset"}
    assert per == {(a, m) for a in ("photo-crate", "leaf-plant") for m in acc}
    rec = {r["method"]: r for r in rows if r["params"]["section"] == "receivers"}
    assert set(rec) == {"atlas", "direct", "card-camera", "card-light"}
    assert all(r["params"]["points"] > 500 for r in rec.values())
    for r in rec.values():
        m = r["metrics"]
        assert 0.0 <= m["iou_min"] <= m["iou"] <= 1.0 and 0.0 <= m["mae"] < 0.5
    # a flat card through the pivot cannot shadow the instances' own surfaces as their depth does
    assert rec["atlas"]["metrics"]["iou"] > rec["card-light"]["metrics"]["iou"]
    disc = {r["method"]: r for r in rows if r["params"]["section"] == "sun-disc"}
    assert set(disc) == {"avg-4", "pcss", "ray-cast"}
    for name in ("avg-4", "pcss"):
        m = disc[name]["metrics"]
        assert 0.0 < m["mae"] < 0.5 and 0.0 < m["banding"] < 1.0
    change = [r for r in rows if r["params"]["section"] == "sun-change"]
    assert {(r["method"], r["params"]["faces"]) for r in change} == {
        (m, f) for m in ("atlas-cold", "atlas-warm", "direct") for f in (6000, 50000)}
    for r in change:
        assert r["metrics"]["flat"] >= 1.0 and r["metrics"]["faces_min"] >= r["params"]["faces"]
    grid = [r for r in rows if r["params"]["section"] == "atlas-grid" and r["method"] == "atlas"]
    assert [r["metrics"]["views"] for r in grid] == [21.0, 27.0]
    assert grid[1]["metrics"]["kib"] > grid[0]["metrics"]["kib"] > 0
    temporal = {r["method"]: r["metrics"] for r in rows if r["params"]["section"] == "temporal"}
    assert set(temporal) == {"atlas", "direct", "card-camera", "card-light", "ray-cast"}
    for m in temporal.values():
        assert 0.0 < m["step_median"] <= m["step_max"] < 1.0 and m["spike"] >= 1.0
    lv = {(r["params"]["resolution"], r["method"]): r["metrics"]
          for r in rows if r["params"]["section"] == "levels"}
    assert set(lv) == {(res, m) for res in ("suite", "frame", "suite/4")
                       for m in ("splat-l0", "splat-levels")}
    for (_, m), x in lv.items():
        assert 0.3 < x["iou_min"] <= x["iou"] <= 1.0 and x["vs_l0"] > 0.0
        assert m == "splat-levels" or x["coarse"] == x["level_mean"] == 0.0
    assert lv[("suite/4", "splat-levels")]["coarse"] == 1.0  # a field 4x coarser than every atlas
    res = {(r["params"]["texels"], r["method"]): r["metrics"]
           for r in rows if r["params"]["section"] == "receivers-resolution"}
    assert set(res) == {(t, m) for t in (64, 128) for m in ("atlas", "atlas-squares", "direct")}
    for x in res.values():
        assert 0.0 <= x["iou_min"] <= x["iou"] <= 1.0 and 0.0 <= x["mae"] < 0.5
    # the map's resolution follows the atlas's texels (twice the texels, twice the texels a unit)
    assert res[(128, "direct")]["tpu"] == pytest.approx(2.0 * res[(64, "direct")]["tpu"], rel=1e-6)
    assert res[(128, "atlas")]["kib"] == pytest.approx(4.0 * res[(64, "atlas")]["kib"], rel=0.05)


def test_the_bench_help_names_every_scene_section(capsys):
    from morphkit.bench import scene_suite as ss

    with pytest.raises(SystemExit, match="0"):
        main(["bench", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    listed = text.split("scene: ", 1)[1].split(";", 1)[0].replace("- ", "-").replace(" ", "")
    assert listed.split(",") == [ss.section_name(s) for s in ss.SECTIONS]
