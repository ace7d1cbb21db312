"""The dome sections of ``morphkit bench billboards`` (#25): their direction sampler, the
section filter, and a tiny run of the per-band and relit sections."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.bench import billboard_suite as bs
from morphkit.bench import dome_suite as ds
from morphkit.errors import ValidationError
from morphkit.views.domecameras import direction


def test_band_directions_stay_in_their_band_and_away_from_the_views():
    views = direction(np.array([0.0, 36.0, 72.0, 0.0]), np.array([30.0, 30.0, 30.0, 90.0]))
    dirs = ds.band_directions((20.0, 40.0), 12, np.random.default_rng(0), views)
    assert len(dirs) == 12
    el = np.array([e for _, e in dirs])
    assert (el >= 20.0).all() and (el < 40.0).all()
    assert np.all(np.diff(el) > 0)  # stratified: one per equal part of the band
    d = direction(np.array([a for a, _ in dirs]), el)
    sep = np.degrees(np.arccos(np.clip(d @ views.T, -1.0, 1.0)))
    assert sep.min() >= ds.MIN_VIEW_SEP_DEG
    again = ds.band_directions((20.0, 40.0), 12, np.random.default_rng(0), views)
    assert again == dirs  # seeded


def test_band_directions_refuse_a_band_outside_the_hemisphere():
    with pytest.raises(ValidationError, match="0 <= lo < hi <= 90"):
        ds.band_directions((80.0, 95.0), 3, np.random.default_rng(0))


def test_dome_sections_are_appended_and_selectable_by_name():
    names = [bs.section_name(s) for s in bs.SECTIONS]
    assert names[-5:] == ["dome-bands", "dome-relit", "dome-temporal", "dome-speed", "dome-bake"]
    assert names[:3] == ["pair", "ring", "equal-memory"]
    assert bs.selected_sections("dome-bake, pair") == [bs.pair_rows, ds.dome_bake_rows]
    assert bs.selected_sections("") == bs.SECTIONS == bs.selected_sections(None)
    with pytest.raises(ValidationError, match="no-such-section"):
        bs.selected_sections("dome-bands,no-such-section")


def test_bench_sections_flag_is_for_the_sectioned_suites_only(capsys):
    from morphkit.cli import main

    assert main(["bench", "warp", "--quick", "--sections", "pair"]) == 2
    err = capsys.readouterr().err
    assert "--sections is an option of `bench billboards|scene|shadows|render` only" in err


def test_shadows_and_render_suites_name_their_sections():
    from morphkit.bench import render_suite, shadow_suite
    from morphkit.bench.harness import pick_sections, section_name

    assert [section_name(s) for s in shadow_suite.SECTIONS] == [
        "accuracy", "cutout", "control-grid", "complexity", "frame", "frame-once"]
    assert [section_name(s) for s in render_suite.SECTIONS] == ["depth", "accuracy", "fidelity", "pass"]
    with pytest.raises(ValidationError, match="no-such"):
        pick_sections("complexity,no-such", shadow_suite.SECTIONS)
    with pytest.raises(ValidationError, match="no-such"):
        shadow_suite.run(sections="no-such")


@pytest.mark.gl
def test_dome_bands_and_relit_tiny_run(renderer, monkeypatch):
    monkeypatch.setattr(ds, "_size", lambda quick: 48)
    cache = bs.AssetCache(renderer)
    rows = ds.dome_bands_rows(cache, True)
    by = {(r["params"]["band"], r["method"]): r["metrics"] for r in rows}
    assert len(rows) == 6 * 5  # 5 bands + all, 5 methods
    for band in [ds.band_label(b) for b in ds.BANDS] + ["all"]:
        assert by[(band, "morph")]["n"] == (20 if band == "all" else 4)
    assert by[("all", "impostor")]["bytes"] <= by[("all", "morph")]["bytes"]  # equal bytes, at most
    assert by[("all", "morph")]["iou"] > by[("all", "classic")]["iou"]
    relit = {r["method"]: r["metrics"] for r in ds.dome_relit_rows(cache, True)}
    assert set(relit) == {"morph", "impostor", "nearest", "crossfade"}
    m = relit["morph"]
    assert len([k for k in m if k.startswith("psnr_") and k not in ("psnr_bake", "psnr_relit")]) == 8
    assert m["relit_delta"] == pytest.approx(m["psnr_bake"] - m["psnr_relit"])
