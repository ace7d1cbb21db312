"""Smoke tests of the bench harness and the warp suite (structure only: speed is never asserted)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from morphkit import bench
from morphkit.bench.fronts import error_figure, is_default, method_family, pareto_front
from morphkit.bench.harness import (
    Timing,
    format_table,
    make_row,
    time_call,
    time_calls,
    time_cycling,
    write_json,
    write_plots,
)
from morphkit.cli import main

REQUIRED = {"suite", "method", "params", "ms_median", "ms_min", "ms_max", "repeats", "metrics"}


def test_time_call_and_time_calls_count_calls():
    calls = {"a": 0, "b": 0}

    def fa():
        calls["a"] += 1

    def fb():
        calls["b"] += 1

    t = time_call(fa, repeats=4, warmup=2)
    assert isinstance(t, Timing) and t.repeats == 4 and calls["a"] == 6
    assert 0 <= t.ms_min <= t.ms_median <= t.ms_max
    ts = time_calls({"a": fa, "b": fb}, repeats=3, warmup=1)
    assert set(ts) == {"a", "b"} and ts["b"].repeats == 3
    assert calls == {"a": 10, "b": 4}


def test_time_cycling_feeds_each_method_the_inputs_in_turn():
    seen = {"a": [], "b": []}
    ts = time_cycling({"a": seen["a"].append, "b": seen["b"].append}, [1, 2, 3],
                      repeats=4, warmup=1)
    assert set(ts) == {"a", "b"} and ts["a"].repeats == 4
    assert seen["a"] == seen["b"] == [1, 2, 3, 1, 2]  # 1 warm-up + 4 repeats, cycling
    with pytest.raises(ValueError, match="no inputs"):
        time_cycling({"a": seen["a"].append}, [])


def _rows():
    rows = []
    for size in (8, 16):
        for method, ms in (("remap", 1.0), ("fast", 2.0)):
            rows.append(make_row("toy", method, {"size": size, "dtype": "float32"},
                                 Timing(ms * size, ms * size * 0.9, ms * size * 1.2, 3),
                                 metrics={"mean_abs_err": 1e-4 * ms} if method == "fast" else {},
                                 note="n" if method == "fast" else ""))
    return rows


def test_rows_table_json_and_plots(tmp_path):
    rows = _rows()
    assert REQUIRED <= set(rows[0])
    table = format_table(rows, floor_method="remap")
    assert "x_remap" in table and "2.00" in table and "fast" in table
    path = write_json(rows, tmp_path / "sub" / "rows.json")
    assert json.loads(path.read_text()) == rows
    written = write_plots(rows, tmp_path / "p.png", error_key="mean_abs_err", panel_keys=("dtype",),
                          defaults=[{"method": "fast", "size": 16}])
    assert [p.name for p in written] == ["p_time_vs_size.png", "p_time_vs_error.png"]
    assert all(p.stat().st_size > 1000 for p in written)


def test_pareto_front_by_hand():
    nan = float("nan")
    pts = [(0.10, 5.0),  # 0: on the front
           (0.20, 1.0),  # 1: on
           (0.30, 2.0),  # 2: worse than 1 in both: off
           (0.05, 9.0),  # 3: the most accurate: on
           (0.20, 1.0),  # 4: equal to 1: the first of equal points is kept, so off
           (0.10, 6.0),  # 5: as accurate as 0 and slower: off
           (nan, 0.1),   # 6: not finite: never on
           (0.50, 0.5),  # 7: the fastest: on
           (0.40, 1.0)]  # 8: as fast as 1 and less accurate: off
    assert pareto_front(pts) == [3, 0, 1, 7]  # by increasing error
    assert pareto_front([]) == [] and pareto_front([(1.0, 2.0)]) == [0]
    assert pareto_front([(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]) == [0]  # one point beats all


def test_method_family_and_default_rows():
    assert method_family("warp_9", r"_\d+") == "warp"
    assert method_family("pcss-reproject_16", r"_\d+") == "pcss-reproject"
    assert method_family("warp_17x17", r"_\d+(?:x\d+)?") == "warp"
    assert method_family("warp_nearest", r"_\d+") == "warp_nearest"  # only the end is cut
    assert method_family("warp_9", None) == "warp_9"
    row = {"method": "warp", "params": {"size": 512, "mesh": "cow"}}
    assert is_default(row, [{"method": "warp", "size": 512}])
    assert not is_default(row, [{"method": "warp", "size": 256}])
    assert not is_default(row, [{"method": "reproject", "size": 512}])
    assert is_default(row, [{"method": "warp", "texels": 128}])  # a key the row lacks: not compared
    assert not is_default(row, [])


def test_error_figure_draws_each_method_front_and_stars_the_default():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def row(method, scene, err, ms):
        return make_row("toy", method, {"scene": scene, "size": 8}, Timing(ms, ms, ms, 1),
                        metrics={"err": err})

    rows = [row("fast_1", "a", 0.3, 1.0), row("fast_2", "a", 0.2, 2.0), row("fast_3", "a", 0.25, 3.0),
            row("slow", "a", 0.01, 50.0), row("slow", "b", 0.02, 40.0),
            make_row("toy", "floor", {"scene": "a"}, Timing(1, 1, 1, 1))]  # no error: left out
    fig = error_figure(rows, "err", scene_keys=("scene",), family=r"_\d+",
                       defaults=[{"method": "fast_2"}])
    try:
        panels = [ax for ax in fig.axes if ax.get_visible()]
        assert [ax.get_title() for ax in panels] == ["scene=a", "scene=b"]
        fronts = {ln.get_color(): list(ln.get_xdata()) for ln in panels[0].get_lines()}
        assert sorted(fronts.values()) == [[0.01], [0.2, 0.3]]  # fast_3 is dominated by fast_2
        stars = [c.get_offsets().tolist() for c in panels[0].collections
                 if len(c.get_offsets()) and c.get_sizes()[0] > 100]
        assert stars == [[[0.2, 2.0]]]
        assert [t.get_text() for t in panels[0].texts] == ["default"]
        assert not panels[1].texts  # the default's method has no row in scene b
    finally:
        plt.close(fig)
    assert error_figure(rows, "missing") is None


def test_run_suite_with_registered_toy_suite(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(bench.SUITES, "toy", lambda *, quick=False: _rows()[: 2 if quick else 4])
    rows = bench.run_suite("toy", quick=True, json_path=tmp_path / "t.json", plot_path=tmp_path / "t.png")
    assert len(rows) == 2
    out = capsys.readouterr().out
    assert "ms_median" in out and "t.json" in out
    assert (tmp_path / "t_time_vs_size.png").exists()
    from morphkit.errors import ValidationError

    with pytest.raises(ValidationError,
                       match="bench suite: expected one of .*warp.*, got unknown suite 'nope'"):
        bench.run_suite("nope")
    assert main(["bench", "nope"]) == 2


def test_warp_suite_tiny_run():
    from morphkit.bench.warp_suite import run

    rows = run(sizes=(24,), grids=((3, 4),), dtypes=("float32", "uint8"), budget_s=0.0)
    methods = {r["method"] for r in rows}
    assert {"morphkit", "morphkit_apply", "remap", "per_triangle"} <= methods
    for r in rows:
        assert REQUIRED <= set(r)
        assert r["suite"] == "warp" and r["params"]["size"] == 24 and r["repeats"] >= 3
        assert r["ms_min"] <= r["ms_median"] <= r["ms_max"]
    json.dumps(rows, allow_nan=False)
    try:
        import skimage  # noqa: F401
    except ImportError:
        return
    assert "skimage" in methods
    for r in rows:
        if r["method"] in ("morphkit", "remap"):
            assert r["metrics"]["mean_abs_err"] < 1e-3


def test_per_triangle_baseline_is_close_to_identity():
    from morphkit.bench.warp_suite import make_case, per_triangle_warp

    rng = np.random.default_rng(0)
    src, _, tris = make_case(32, 3, 3, rng)
    img = rng.uniform(0, 1, (32, 32)).astype(np.float32)
    out = per_triangle_warp(img, src, src, tris, (32, 32))
    assert np.abs(out - img)[1:-1, 1:-1].max() < 1e-5


def test_billboards_suite_is_registered_with_open_sections():
    from morphkit.bench import billboard_suite

    assert "billboards" in bench.SUITES
    assert billboard_suite.SECTIONS[:4] == [billboard_suite.pair_rows, billboard_suite.ring_rows,
                                           billboard_suite.equal_memory_rows, billboard_suite.bake_rows]
    a = np.zeros((8, 8, 4), np.float32)
    a[2:6, 2:6] = 1.0
    iou, p = billboard_suite.quality(a, a)
    assert iou == 1.0 and p == billboard_suite.PSNR_CAP  # identical: capped, JSON-safe
    b = a.copy()
    b[2:6, 2:4] = 0.0
    iou, p = billboard_suite.quality(b, a)
    assert iou == 0.5 and p == pytest.approx(10 * np.log10(1 / (3 * 8 / (8 * 8 * 3))))


@pytest.mark.gl
def test_billboards_pair_section_tiny_run(renderer, monkeypatch):
    from morphkit.bench import billboard_suite as bs

    monkeypatch.setattr(bs, "_meshes", lambda quick: ("person",))
    monkeypatch.setattr(bs, "_size", lambda quick: 64)
    rows = bs.pair_rows(bs.AssetCache(renderer), True)
    by = {(r["params"]["section"], r["params"]["mesh"], r["method"]): r for r in rows}
    assert len(rows) == 20  # 2 sections x (person + all) x 5 methods
    inside = {m: by[("pair-inside", "person", m)]["metrics"]
              for m in ("morph", "morph-paper", "classic", "crossfade")}
    assert inside["morph"]["iou"] > inside["crossfade"]["iou"]
    assert inside["morph"]["iou"] >= inside["morph-paper"]["iou"]  # the alpha from depth fixes outlines
    outside = {m: by[("pair-outside", "person", m)]["metrics"] for m in ("morph", "nearest")}
    assert outside["morph"] == outside["nearest"]  # clamped: the morph is the nearer reference
    assert by[("pair-inside", "all", "morph")]["metrics"] == inside["morph"]


@pytest.mark.gl
def test_plan_suite_rows_predict_beside_measure():
    from morphkit.bench import plan_suite

    rows = plan_suite.run(quick=True)
    methods = [r["method"] for r in rows]
    assert methods[:2] == ["table_classic", "table_morph"]
    for nm in ("classic", "morph"):
        pred = [r for r in rows if r["method"] == f"predict_{nm}"]
        meas = [r for r in rows if r["method"] == f"measure_{nm}"]
        assert len(pred) == len(meas) == 1
        for p, m in zip(pred, meas, strict=True):  # the gap is the predicted against the measured
            assert p["metrics"]["gap_db"] == pytest.approx(abs(p["metrics"]["psnr"] - m["metrics"]["psnr"]))
            assert p["metrics"]["gap_iou"] == pytest.approx(abs(p["metrics"]["iou"] - m["metrics"]["iou"]))
    (plan,) = [r for r in rows if r["params"].get("what") == "planning"]
    # 10,000 instances over the sample size: predicted from tol.PLAN_MAX_INSTANCES of them
    assert plan["method"] == "plan_10000" and plan["params"]["frames"] == 36 and plan["metrics"]["drawn"] > 0
