"""The scene rows of ``morphkit bench billboards``: structure on tiny cases (speed is never asserted)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from billboard_fakes import FakeAsset

from morphkit.bench import SUITES
from morphkit.bench.billboard_scenes import (
    hit_rate_rows,
    scene_accuracy_rows,
    speed_rows,
    step_changes,
    temporal_rows,
)
from morphkit.scene import DirectionalLight, Item

REQUIRED = {"suite", "method", "params", "ms_median", "ms_min", "ms_max", "repeats", "metrics"}


def test_step_changes():
    a = np.zeros((2, 2, 4), np.float32)
    b = a.copy()
    b[0, 0] = (0.4, 0.0, 0.0, 0.4)  # one covered pixel changes by 0.4 in two of four channels
    assert step_changes([a, a, b]).tolist() == pytest.approx([0.0, 0.2])


def test_temporal_rows_show_the_nearest_view_popping():
    rows = temporal_rows(FakeAsset("fake", views=8, size=(32, 24), levels=1), start_deg=10.0, end_deg=35.0,
                         shape=(36, 48))
    by = {r["method"]: r["metrics"] for r in rows}
    assert set(by) == {"morph", "morph-paper", "classic", "nearest", "crossfade"}
    assert all(REQUIRED <= set(r) for r in rows)
    assert by["classic"]["step_max"] == 0.0  # one image whatever the view
    # nearest: nothing changes except where it switches views (at 22.5 deg): a spike over a zero median
    assert by["nearest"]["step_median"] == 0.0 and by["nearest"]["step_max"] > 0.0
    assert by["nearest"]["max_over_median"] == 1e9
    assert 0.0 < by["morph"]["step_median"] and by["morph"]["max_over_median"] < 1e9


def test_hit_rate_rows():
    (row,) = hit_rate_rows(FakeAsset("fake", views=8, size=(32, 24), levels=2), n=60, frames=4, step_deg=1.0,
                           shape=(48, 64), capacity=32)
    m = row["metrics"]
    assert row["method"] == "morph-path" and 0.0 <= m["hit_rate"] <= 1.0 and m["cache_entries"] <= 32
    assert row["params"]["billboards"] == 60 and row["repeats"] == 3


def test_suite_is_registered():
    assert "billboards" in SUITES


def _box_items():
    box = trimesh.creation.box((0.3, 0.3, 0.8))
    box.apply_translation([0, 0, 0.4])
    return [Item(box)]


@pytest.mark.gl
def test_speed_and_accuracy_rows(renderer):
    asset = FakeAsset("fake", views=2, size=(32, 24), levels=1)
    light = [DirectionalLight([0, 0, -1])]
    rows = speed_rows(asset, _box_items(), renderer, light, 0.35, counts=(4,), shape=(36, 48), repeats=2,
                      mesh_repeats=1)
    assert {r["method"] for r in rows} == {"morph-cold", "morph-warm", "crossfade-cold", "crossfade-warm",
                                           "classic", "mesh", "gl-quads"}
    warm = next(r for r in rows if r["method"] == "morph-warm")
    assert warm["metrics"]["hit_rate"] == 1.0 and warm["params"]["billboards"] == 4
    assert warm["metrics"]["x_classic"] == pytest.approx(
        warm["ms_median"] / next(r["ms_median"] for r in rows if r["method"] == "classic"))
    acc = scene_accuracy_rows([asset], {"fake": _box_items()}, renderer, light, 0.35, frames=2,
                              shape=(36, 48))
    groups = {(r["method"], r["params"]["azimuths"]) for r in acc}
    assert ("morph", "inside") in groups or ("morph", "outside<=30") in groups
    for r in acc:
        assert 0.0 <= r["metrics"]["iou"] <= 1.0 and r["metrics"]["n"] >= 1
