"""The planner (morphkit.plan.representations, .planner, .planfile): bands, the banded modes, the
frame's prediction from the tables, the choice to a budget and the plan file. No GL: fake assets and
hand-made tables; the command end to end is in test_plan_command.py."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from billboard_fakes import FakeAsset

from morphkit import tol
from morphkit.billboard import BillboardScene, ClassicMode, Instances, MorphCache, MorphMode, NearestMode
from morphkit.billboard.compare import PSNR_CAP_DB
from morphkit.camera import look_at, perspective
from morphkit.errors import BudgetError, FileFormatError, ValidationError
from morphkit.plan import Budget
from morphkit.plan.calibration import band_offsets, calibration_offsets, path_offsets
from morphkit.plan.errortable import ErrorTable
from morphkit.plan.planfile import PLAN_VERSION, ScenePlan, read_plan
from morphkit.plan.planner import FramePredictions, choose, predict_frames, reached
from morphkit.plan.representations import (
    BILLBOARD_REPRESENTATIONS,
    REPRESENTATIONS,
    BandChoice,
    BandedRing,
    BillboardRepresentation,
    elevation_band,
    representation,
)

HASH = "cd" * 32
SHAPE = (240, 320)


def _camera(eye, target):
    return perspective(math.radians(50.0), SHAPE, look_at(np.asarray(eye, float), np.asarray(target, float)))


def _scene() -> BillboardScene:
    asset = FakeAsset("tree", views=8, half_extent=(0.3, 0.4), levels=3)
    inst = Instances.from_records([("tree", -1.0, 3.0), ("tree", 1.0, 9.0), ("tree", 0.5, 20.0)])
    return BillboardScene({"tree": asset}, inst)


# ---------------------------------------------------------------- representations and bands


def test_representations_are_ordered_by_cost_and_found_by_name():
    assert [r.name for r in REPRESENTATIONS] == ["cull", "classic", "nearest", "morph", "mesh"]
    assert [r.cost for r in REPRESENTATIONS] == sorted(r.cost for r in REPRESENTATIONS)
    assert representation("nearest") is REPRESENTATIONS[2]
    # culling and the real mesh are representations but draw no billboard image
    assert [r.name for r in BILLBOARD_REPRESENTATIONS] == ["classic", "nearest", "morph"]
    assert not isinstance(representation("mesh"), BillboardRepresentation)
    assert not isinstance(representation("cull"), BillboardRepresentation)
    with pytest.raises(
        ValidationError,
        match=r"representation: expected one of \['cull', 'classic', 'nearest', 'morph', 'mesh'\]",
    ):
        representation("impostor")


def test_elevation_bands_split_at_their_edges():
    assert elevation_band([-5.0, 0.0, 29.99, 30.0, 59.0, 60.0, 90.0]).tolist() == [0, 0, 0, 1, 1, 2, 2]


def test_a_band_choice_names_known_representations_and_defaults_the_rest():
    c = BandChoice({("tree", 1, 0): "classic"})
    assert c.of("tree", 1, 10.0) == "classic"
    assert c.of("tree", 1, 45.0) == "morph"  # another elevation band
    assert c.of("bush", 1, 10.0) == "morph"
    with pytest.raises(ValidationError, match="representation: expected one of"):
        BandChoice({("tree", 1, 0): "sprite"})
    with pytest.raises(
        ValidationError, match=r"band: expected \(asset name, level >= 0, elevation band >= 0\)"
    ):
        BandChoice({("tree", -1, 0): "classic"})


def test_a_banded_ring_draws_every_band_as_its_representation():
    scene = _scene()
    cam = _camera([0.0, 0.0, 0.6], [0.0, 8.0, 0.4])
    plain = {"classic": ClassicMode(), "nearest": NearestMode(), "morph": MorphMode(MorphCache())}
    for name, mode in plain.items():
        want = scene.render(cam, mode).rgb
        got = scene.render(cam, BandedRing(BandChoice(default=name))).rgb
        np.testing.assert_array_equal(got, want, err_msg=name)
    # one band classic, the others morphed: each billboard's image is its band's
    placements = scene.plan(cam).placements
    near = max(placements, key=lambda p: p.height_px)
    band = ("tree", near.level, int(elevation_band(near.elevation_deg)))
    mode = BandedRing(BandChoice({band: "classic"}))
    asset = scene.assets["tree"]
    for pl in placements:
        img, _ = mode.image(asset, pl)
        ref = ClassicMode() if (pl.level, int(elevation_band(pl.elevation_deg))) == band[1:] else MorphMode()
        np.testing.assert_array_equal(img, ref.image(asset, pl)[0])
    assert len({(p.level, int(elevation_band(p.elevation_deg))) for p in placements}) > 1  # the test can fail


# ---------------------------------------------------------------- predictions


def _pred(psnr, iou, pixels, bands=(("tree", 0, 0),)) -> FramePredictions:
    """One frame of billboards, each row a representation (classic, nearest, morph)."""
    psnr = np.asarray(psnr, float)
    n = psnr.shape[1]
    return FramePredictions(
        ("classic", "nearest", "morph"),
        list(bands),
        [np.zeros(n, np.int64)],
        [psnr],
        [np.asarray(iou, float)],
        [np.asarray(pixels, float)],
        {"tree": 64},
    )


def test_a_frames_prediction_weights_each_billboard_by_its_pixels():
    # two billboards of 100 and 300 pixels at 20 and 30 dB: MSE 0.25 10^-2 + 0.75 10^-3 = 3.25e-3
    pred = _pred([[20.0, 30.0]] * 3, [[0.6, 1.0]] * 3, [100.0, 300.0])
    (got,) = pred.frame_errors(np.array([2]))
    assert got["billboard-psnr"] == pytest.approx(-10.0 * math.log10(3.25e-3), abs=1e-12)
    assert got["billboard-iou"] == pytest.approx(0.25 * 0.6 + 0.75 * 1.0, abs=1e-12)
    # every billboard at the cap: the frame at the cap, not beyond it
    (capped,) = _pred([[PSNR_CAP_DB] * 2] * 3, [[1.0, 1.0]] * 3, [5.0, 5.0]).frame_errors(np.array([0]))
    assert capped["billboard-psnr"] == PSNR_CAP_DB


def test_predicting_a_path_sees_what_its_frames_draw(rng):
    scene = _scene()
    tables = {}
    for r, base in (("cull", 8.0), ("classic", 18.0), ("nearest", 22.0), ("morph", 26.0), ("mesh", 60.0)):
        h = np.array([4.0, 16.0, 64.0, 256.0])
        e = np.array([0.0, 40.0, 80.0])
        tables[("tree", r)] = ErrorTable(
            "tree", HASH, r, h, e, base + rng.uniform(0, 1, (4, 3)), rng.uniform(0.6, 1.0, (4, 3))
        )
    cams = [_camera([0.0, 0.0, 0.6], [0.0, 8.0, 0.4]), _camera([0.0, 40.0, 0.6], [0.0, 80.0, 0.4])]
    pred = predict_frames(tables, scene, cams)
    drawn = scene.plan(cams[0]).placements
    assert len(pred.band_index[0]) == len(drawn) and len(pred.band_index[1]) == 0
    for r, rep in enumerate(pred.representations):
        p, q = tables[("tree", rep)].lookup(
            [pl.height_px for pl in drawn], [pl.elevation_deg for pl in drawn]
        )
        np.testing.assert_allclose(pred.psnr_db[0][r], p)
        np.testing.assert_allclose(pred.iou[0][r], q)
    assert pred.frame_errors(pred.pick_of(BandChoice()))[1] == {"billboard-psnr": None, "billboard-iou": None}
    assert pred.counts().sum() == len(drawn)
    with pytest.raises(ValidationError, match="an ErrorTable of 'tree' as 'classic'"):
        predict_frames({k: v for k, v in tables.items() if k[1] != "classic"}, scene, cams)


def test_calibration_moves_each_representations_predictions_by_its_offset():
    pred = _pred([[20.0, 30.0], [21.0, 31.0], [25.0, 35.0]], [[0.5, 0.9]] * 3, [10.0, 10.0])
    moved = pred.shifted({"classic": (-2.0, 0.2), "morph": (1.0, -0.95)})
    np.testing.assert_allclose(moved.psnr_db[0], [[18.0, 28.0], [21.0, 31.0], [26.0, 36.0]])
    np.testing.assert_allclose(moved.iou[0], [[0.7, 1.0], [0.5, 0.9], [0.0, 0.0]])  # clipped to [0, 1]
    # a constant dB offset moves the frame's PSNR by exactly that constant
    before = pred.frame_errors(np.array([0]))[0]["billboard-psnr"]
    after = moved.frame_errors(np.array([0]))[0]["billboard-psnr"]
    assert after - before == pytest.approx(-2.0, abs=1e-9)
    c = calibration_offsets(
        [
            {"billboard-psnr": 25.0, "billboard-iou": 0.9},
            {"billboard-psnr": None},
            {"billboard-psnr": 27.0, "billboard-iou": 0.8},
        ],
        [
            {"billboard-psnr": 23.5, "billboard-iou": 0.95},
            {"billboard-psnr": 22.0},
            {"billboard-psnr": 26.5, "billboard-iou": 0.8},
        ],
    )
    # gaps -1.5 and -0.5 dB (the frame without a prediction left out): median -1.0, each 0.5 from it
    assert (c.db, c.frames, c.spread_db) == (-1.0, 2, 0.5) and c.iou == pytest.approx(0.025)


def test_a_prediction_at_the_cap_measured_below_it_is_calibrated_a_measure_at_the_cap_is_not():
    # the real mesh's table is the truth against itself (the cap); its frames, shadowed by the
    # frame's own sun atlases, measure 40 and 42 dB: the offset is theirs, the frame at the cap left out
    c = calibration_offsets(
        [{"billboard-psnr": PSNR_CAP_DB, "billboard-iou": 1.0}] * 3,
        [
            {"billboard-psnr": 40.0, "billboard-iou": 1.0},
            {"billboard-psnr": 42.0, "billboard-iou": 1.0},
            {"billboard-psnr": PSNR_CAP_DB, "billboard-iou": 1.0},
        ],
    )
    assert (c.db, c.frames, c.spread_db) == (41.0 - PSNR_CAP_DB, 2, 1.0) and c.iou == 0.0


def test_path_offsets_follow_the_calibration_frames_around_each_frame():
    # calibration frames 0, 10, 20 measured 2 dB under, 1 dB over, then at the cap (left out);
    # frame 30 has no prediction (nothing drawn): left out too
    p = [{"billboard-psnr": 30.0, "billboard-iou": 0.9}] * 3 + [{"billboard-psnr": None}]
    m = [
        {"billboard-psnr": 28.0, "billboard-iou": 0.8},
        {"billboard-psnr": 31.0, "billboard-iou": 0.9},
        {"billboard-psnr": PSNR_CAP_DB, "billboard-iou": 1.0},
        {"billboard-psnr": 20.0},
    ]
    got = path_offsets([0, 10, 20, 30], p, m, [-5, 0, 4, 10, 25])
    # linear in the frame's index between 0 and 10, the nearest's beyond them
    want = [(-2.0, -0.1), (-2.0, -0.1), (-0.8, -0.06), (1.0, 0.0), (1.0, 0.0)]
    np.testing.assert_allclose(got, want, atol=1e-12)
    # nothing serves: no offset
    assert path_offsets([0], [p[0]], [m[2]], [3]) == [(0.0, 0.0)]


def test_the_plan_along_the_path_takes_its_drawn_frames_as_measured_and_moves_the_others():
    from morphkit.plan.calibration import Calibration
    from morphkit.programs.planning.planown import PlanCalibration

    # drawn on frames 0 and 10: 2 dB and 0.1 IoU under, then 1 dB over and 0.1 IoU over
    own = PlanCalibration(
        Calibration(0.0, 0.0, 2, 0.0, 0.0),
        [0, 10],
        [{"billboard-psnr": 30.0, "billboard-iou": 0.8}] * 2,
        [{"billboard-psnr": 28.0, "billboard-iou": 0.7}, {"billboard-psnr": 31.0, "billboard-iou": 0.9}],
    )
    predicted = [
        {"billboard-psnr": 99.0, "billboard-iou": 0.1},  # frame 0: drawn, its measure whatever predicted
        {"billboard-psnr": 25.0, "billboard-iou": 0.95},  # frame 5: halfway, -0.5 dB, 0.0 IoU
        {"billboard-psnr": PSNR_CAP_DB, "billboard-iou": 0.95},  # frame 12: at the cap, kept; IoU +0.1
        {"billboard-psnr": None, "billboard-iou": None},  # frame 20: nothing drawn
    ]
    got = own.along(predicted, [0, 5, 12, 20])
    assert got[0] == {"billboard-psnr": 28.0, "billboard-iou": 0.7}
    assert got[1]["billboard-psnr"] == pytest.approx(24.5) and got[1]["billboard-iou"] == pytest.approx(0.95)
    # frame 12: beyond frame 10, its offset; the IoU clipped at 1
    assert got[2]["billboard-psnr"] == PSNR_CAP_DB and got[2]["billboard-iou"] == pytest.approx(1.0)
    assert got[3] == {"billboard-psnr": None, "billboard-iou": None}


def test_band_offsets_correct_each_band_apart_from_its_billboards_own_figures():
    pred = _two_bands()  # band 0 (eye level): 3 billboards a frame; band 1 (from above): 1
    # the card measured 2 dB under its table at eye level and 6 dB under from above; the IoU +0.01
    boxes = [
        [{"psnr": 27.0, "iou": 0.96}] * 3 + [{"psnr": 9.0, "iou": 0.51}],
        [{"psnr": 27.0, "iou": 0.96}] * 3 + [{"psnr": 9.0, "iou": 0.51}],
    ]
    got = band_offsets(pred, "classic", boxes)
    # band 1 has 2 billboards, fewer than PLAN_MIN_BAND_BILLBOARDS: only band 0 is calibrated apart
    assert tol.PLAN_MIN_BAND_BILLBOARDS > 2
    assert set(got) == {("classic", ("tree", 0, 0))}
    assert got[("classic", ("tree", 0, 0))] == pytest.approx((-2.0, 0.01))
    # a band's offset takes the place of the representation's, in that band only
    moved = pred.shifted({"classic": (-6.0, 0.0), **got})
    np.testing.assert_allclose(moved.psnr_db[0][0], [27.0, 27.0, 27.0, 9.0])
    np.testing.assert_allclose(moved.psnr_db[0][1:], pred.psnr_db[0][1:])  # other representations kept
    # a frame measured with another number of billboards than predicted is not used
    assert band_offsets(pred, "classic", [boxes[0][:3], None]) == {}


# ---------------------------------------------------------------- the choice


def _two_bands() -> FramePredictions:
    """Two frames; band 0 (eye level) draws 3 billboards, band 1 (from above) 1. The card holds at
    eye level (29 dB) and fails from above (15 dB); the nearest view is between; the morph best."""
    bands = [("tree", 0, 0), ("tree", 0, 2)]
    idx = np.array([0, 0, 0, 1])
    psnr = np.array([[29.0, 29.0, 29.0, 15.0], [29.5, 29.5, 29.5, 24.0], [31.0, 31.0, 31.0, 30.0]])
    iou = np.array([[0.95] * 3 + [0.5], [0.96] * 3 + [0.8], [0.97] * 3 + [0.95]])
    px = np.full(4, 100.0)
    return FramePredictions(
        ("classic", "nearest", "morph"), bands, [idx, idx], [psnr, psnr], [iou, iou], [px, px], {"tree": 64}
    )


def test_the_choice_is_the_cheapest_that_meets_the_budget():
    pred = _two_bands()
    got = choose(pred, Budget(billboard_psnr=25.0))
    assert got.choice.choices == {("tree", 0, 0): "classic", ("tree", 0, 2): "nearest"}
    for f in got.predicted:  # predicted within the budget by the margin
        assert f["billboard-psnr"] >= 25.0 + tol.PLAN_MARGIN_DB
    # a stricter budget keeps the morph from above
    got = choose(pred, Budget(billboard_psnr=28.0))
    assert got.choice.choices[("tree", 0, 2)] == "morph"
    # an IoU budget the card misses from above: with 0.93 the card's frame (0.8375) fails
    got = choose(pred, Budget(billboard_iou=0.93))
    assert got.choice.choices[("tree", 0, 2)] != "classic"


def test_measured_costs_steer_the_choice_and_it_is_never_dearer_than_one_representation_everywhere():
    pred = _two_bands()
    budget = Budget(billboard_psnr=25.0)
    # the card measured dearer than the nearest view (a card's big image): the nearest view everywhere
    got = choose(pred, budget, costs={"classic": 5.0, "nearest": 1.0, "morph": 10.0})
    assert set(got.choice.choices.values()) == {"nearest"}
    counts = pred.counts()
    for costs in (
        {"classic": 1.0, "nearest": 2.0, "morph": 9.0},
        {"classic": 3.0, "nearest": 2.0, "morph": 2.5},
    ):
        got = choose(pred, budget, costs=costs)
        cost = np.array([costs[r] for r in pred.representations])
        total = float(np.sum(counts * cost[pred.pick_of(got.choice)]))
        for r, name in enumerate(pred.representations):
            uniform = np.full(len(pred.bands), r)
            if all(f["billboard-psnr"] >= 25.0 + tol.PLAN_MARGIN_DB for f in pred.frame_errors(uniform)):
                assert total <= float(np.sum(counts * cost[uniform])), name
    # a wider margin keeps a dearer representation
    assert choose(pred, budget, margin=(3.0, 0.0)).choice.choices[("tree", 0, 2)] == "morph"


def test_each_representation_keeps_its_own_margin():
    pred = _two_bands()
    budget = Budget(billboard_psnr=25.0)
    assert "classic" in choose(pred, budget).choice.choices.values()
    # the card's calibration fell 6 dB short of its prediction: drawing 3 of 4 pixels of a frame (29 dB,
    # margin 4.6 dB) it falls below 25 dB, so it is trusted nowhere
    got = choose(pred, budget, margin={"classic": (6.0, 0.0), "nearest": (0.5, 0.0), "morph": (0.5, 0.0)})
    assert "classic" not in got.choice.choices.values()


def test_a_representation_measured_to_meet_the_budget_starts_a_descent_the_prediction_refuses():
    pred = _two_bands()
    budget = Budget(billboard_psnr=32.0)  # the morph everywhere is predicted 30.8 dB less the margin
    with pytest.raises(BudgetError, match="no representation meets the budget"):
        choose(pred, budget)
    # the nearest view everywhere measured within it: chosen, and no band is moved below what that
    # start is predicted (the card at eye level would lower the frames)
    got = choose(pred, budget, proven=["nearest"])
    assert set(got.choice.choices.values()) == {"nearest"}
    # the card everywhere proven too, and cheaper: it wins
    got = choose(pred, budget, proven=["nearest", "classic"])
    assert set(got.choice.choices.values()) == {"classic"}


def test_a_budget_nothing_meets_names_the_best_reachable_figure_and_its_bound():
    pred = _two_bands()
    with pytest.raises(
        BudgetError, match=r"billboard-psnr 30\.2 .* against 40; bounded by tree, >= 32 px, 60-90 deg"
    ):
        choose(pred, Budget(billboard_psnr=40.0))


def _with_mesh() -> FramePredictions:
    """:func:`_two_bands` with the real mesh as a fourth representation: 45 dB and IoU 1 everywhere
    (as calibrated: its frames' own shadows)."""
    two = _two_bands()
    psnr = np.vstack([two.psnr_db[0], np.full(4, 45.0)])
    iou = np.vstack([two.iou[0], np.ones(4)])
    return FramePredictions(
        (*two.representations, "mesh"),
        two.bands,
        two.band_index,
        [psnr, psnr],
        [iou, iou],
        two.pixels,
        {"tree": 64},
    )


def test_the_real_mesh_takes_only_the_bands_no_billboard_holds():
    pred = _with_mesh()
    costs = {"classic": 1.0, "nearest": 2.0, "morph": 9.0, "mesh": 12.0}
    # 31.5 dB (frames of 4 billboards of 100 px, PSNR of their pooled squared error, less the 0.5 dB
    # margin): the morph everywhere 30.2, the card or the nearest view at eye level with the mesh from
    # above 29.7 and 30.2; the morph at eye level with the mesh from above 31.7, the cheaper of the
    # two that meet it (costs 78 against the mesh everywhere's 96)
    got = choose(pred, Budget(billboard_psnr=31.5), costs=costs)
    assert got.choice.choices == {("tree", 0, 0): "morph", ("tree", 0, 2): "mesh"}
    assert all(f["billboard-psnr"] >= 31.5 + tol.PLAN_MARGIN_DB for f in got.predicted)
    # the mesh measured cheaper than the morph: it takes every band the card cannot
    got = choose(pred, Budget(billboard_psnr=31.5), costs={**costs, "mesh": 5.0})
    assert set(got.choice.choices.values()) == {"mesh"}
    # beyond the mesh's figure nothing meets it: the best reachable is the mesh everywhere
    with pytest.raises(BudgetError, match=r"billboard-psnr 44\.5 .* against 50; .*\(mesh everywhere\)$"):
        choose(pred, Budget(billboard_psnr=50.0), costs=costs)


def test_a_representations_cost_per_frame_counts_once_in_each_frame_that_draws_it():
    pred = _with_mesh()
    costs = {"classic": 1.0, "nearest": 2.0, "morph": 9.0, "mesh": 0.5}
    # the mesh cheapest per billboard: everywhere, it is the choice
    assert set(choose(pred, Budget(billboard_psnr=25.0), costs=costs).choice.choices.values()) == {"mesh"}
    # but a frame drawing any mesh pays 50 ms for its render: the card and the nearest view win
    got = choose(pred, Budget(billboard_psnr=25.0), costs=costs, fixed={"mesh": 50.0}, base_ms=3.0)
    assert got.choice.choices == {("tree", 0, 0): "classic", ("tree", 0, 2): "nearest"}
    assert got.predicted_ms == 3.0 + 3 * 1.0 + 2.0  # base, 3 cards and a nearest view a frame
    cost = np.array([costs[r] for r in pred.representations])
    fixed = np.array([0.0, 0.0, 0.0, 50.0])
    # a frame with the mesh in one band pays its 50 ms once
    np.testing.assert_allclose(pred.frame_times(np.array([0, 3]), cost, fixed), [53.5, 53.5])
    np.testing.assert_allclose(pred.frame_times(np.array([3, 3]), cost, fixed, 1.0), [53.0, 53.0])


def test_a_time_budget_takes_the_least_error_within_the_time():
    pred = _with_mesh()  # 2 frames of 4 billboards: 3 at eye level, 1 from above
    costs = {"classic": 1.0, "nearest": 2.0, "morph": 9.0, "mesh": 12.0}
    cost = np.array([costs[r] for r in pred.representations])
    np.testing.assert_allclose(pred.frame_times(np.zeros(2, np.int64), cost), [4.0, 4.0])
    np.testing.assert_allclose(pred.frame_times(np.array([3, 2]), cost), [45.0, 45.0])
    # 4 ms: only the card everywhere fits
    got = choose(pred, Budget(time_ms=4.0), costs=costs)
    assert set(got.choice.choices.values()) == {"classic"} and got.predicted_ms == 4.0
    # 48 ms: the mesh everywhere fits, and is the least error
    got = choose(pred, Budget(time_ms=48.0), costs=costs)
    assert set(got.choice.choices.values()) == {"mesh"} and got.predicted_ms == 48.0
    # between: within the time, and no worse than the card everywhere
    card = pred.frame_errors(np.zeros(2, np.int64))[0]["billboard-psnr"]
    for limit in (6.0, 13.0, 30.0):
        got = choose(pred, Budget(time_ms=limit), costs=costs)
        assert got.predicted_ms <= limit
        assert got.predicted[0]["billboard-psnr"] >= card
    # the error keys too: within 13 ms the frames cannot reach 40 dB; 3.9 ms not even the card
    with pytest.raises(BudgetError, match=r"no choice within 13 ms meets the budget: .*against 40"):
        choose(pred, Budget(billboard_psnr=40.0, time_ms=13.0), costs=costs)
    with pytest.raises(
        BudgetError, match=r"within 3\.9 ms: the cheapest, classic everywhere, is predicted 4 ms"
    ):
        choose(pred, Budget(time_ms=3.9), costs=costs)


def test_reached_is_the_figure_of_the_budgets_fraction_of_frames():
    frames = [{"billboard-psnr": float(v), "billboard-iou": None} for v in range(1, 21)]  # 1 .. 20 dB
    assert reached(Budget(billboard_psnr=10.0, frames=0.95), frames) == {"billboard-psnr": 2.0}
    assert reached(Budget(billboard_psnr=10.0, frames=0.5), frames) == {"billboard-psnr": 11.0}
    assert reached(Budget(billboard_iou=0.9), frames) == {"billboard-iou": None}


# ---------------------------------------------------------------- the plan file


def test_a_plan_file_round_trips_and_refuses_what_is_not_one(tmp_path):
    plan = ScenePlan(
        Budget(billboard_psnr=24.0, frames=0.9),
        BandChoice({("tree", 1, 0): "classic", ("tree", 0, 2): "nearest"}),
        True,
        ("tree",),
        {("tree", 1, 0): 12},
        {"tree": 128},
        {"verified": {"frames": 3}},
    )
    path = plan.save(tmp_path / "plan.json")
    obj = json.loads(path.read_text())
    assert obj["morphkit_plan"] == PLAN_VERSION and obj["verified"] == {"frames": 3}
    entry = next(c for c in obj["choices"] if c["level"] == 1)
    assert entry["height_px"] == [32.0, 64.0] and entry["elevation_deg"] == [0.0, 30.0]
    assert entry["billboards"] == 12 and entry["band"] == "tree, 32-64 px, 0-30 deg"
    back = read_plan(tmp_path)  # the folder names its plan.json
    assert (
        back.choice == plan.choice and back.budget == plan.budget and back.relit and back.assets == ("tree",)
    )
    back.check_kind(True)
    with pytest.raises(ValidationError, match=r"plan: expected a plan of ring assets \(no sun\)"):
        back.check_kind(False)
    with pytest.raises(ValidationError, match=r"plan: expected a plan of the scene's assets \['bush'\]"):
        back.check_assets(["bush"])
    obj["morphkit_plan"] = 2
    (tmp_path / "v2.json").write_text(json.dumps(obj))
    with pytest.raises(FileFormatError, match="expected morphkit_plan 1, got 2"):
        read_plan(tmp_path / "v2.json")
    obj["morphkit_plan"] = 1
    obj["choices"][0]["representation"] = "sprite"
    (tmp_path / "bad.json").write_text(json.dumps(obj))
    with pytest.raises(FileFormatError, match="relit, assets and choices of a plan"):
        read_plan(tmp_path / "bad.json")
    (tmp_path / "text.json").write_text("not json")
    with pytest.raises(FileFormatError, match="expected JSON"):
        read_plan(tmp_path / "text.json")


def test_a_large_scene_is_predicted_from_a_sample_of_its_instances():
    from morphkit.billboard import place_random
    from morphkit.plan.planner import sample_scene

    asset = FakeAsset("tree", views=8, half_extent=(0.3, 0.4), levels=3)
    scene = BillboardScene({"tree": asset}, place_random(["tree"], 3000, np.random.default_rng(5)))
    small = sample_scene(scene, 1000)
    again = sample_scene(scene, 1000)
    assert len(small) == 1000 and np.array_equal(small.instances.xy, again.instances.xy)  # the same sample
    rows = {tuple(r) for r in scene.instances.xy.round(12)}
    assert all(tuple(r) in rows for r in small.instances.xy.round(12))  # of the scene's own instances
    assert sample_scene(scene, 5000) is scene
    tables = {
        ("tree", r): ErrorTable(
            "tree",
            HASH,
            r,
            np.array([4.0, 256.0]),
            np.array([0.0, 80.0]),
            np.full((2, 2), 20.0),
            np.full((2, 2), 0.9),
        )
        for r in ("cull", "classic", "nearest", "morph", "mesh")
    }
    cams = [_camera([0.0, -60.0, 8.0], [0.0, 0.0, 0.0])]
    pred = predict_frames(tables, scene, cams, max_instances=1000)
    assert (pred.instances, pred.predicted_instances) == (3000, 1000)
    assert 0 < len(pred.band_index[0]) <= 1000


def test_a_table_of_a_scaled_instance_draws_its_billboard_the_cells_height():
    from morphkit.plan.errortable import measure_error_table

    asset = FakeAsset("fake", views=8, levels=1, solid=True)
    seen = []

    class Spy(ClassicMode):
        def render(self, scene, camera):
            frame = super().render(scene, camera)
            seen.append((scene.instances.scale[0], frame.placements[0].height_px))
            return frame

    t = measure_error_table(
        asset,
        None,
        None,
        Spy(),
        ClassicMode(),
        heights_px=(16.0, 40.0),
        elevations_deg=(0.0,),
        azimuths_deg=(10.0,),
        mesh_hash=HASH,
        scale=2.5,
    )
    assert t.params["scale"] == 2.5 and [s for s, _ in seen] == [2.5, 2.5]
    assert [h for _, h in seen] == [pytest.approx(16.0, rel=1e-9), pytest.approx(40.0, rel=1e-9)]
    with pytest.raises(ValidationError, match="scale: expected a scale > 0, got 0"):
        measure_error_table(asset, None, None, ClassicMode(), ClassicMode(), mesh_hash=HASH, scale=0.0)


def test_time_frames_draws_each_frame_in_every_mode_its_order_turned_and_times_each():
    from types import SimpleNamespace

    from morphkit.programs.planning.planverify import time_frames

    drawn: list[tuple[int, str]] = []

    class Scene:  # records what it is asked to draw
        def render(self, cam: int, mode: str) -> None:
            drawn.append((cam, mode))

    modes = {"a": "A", "b": "B", "c": "C"}
    got = time_frames(SimpleNamespace(lighting=None), [10, 11, 12], [0, 2], modes, Scene(), 1)
    assert got.keys() == set("abc") and all(len(t) == 2 and min(t) >= 0.0 for t in got.values())
    # the first frame's order turned one place on, the second's two
    assert drawn == [(10, "B"), (10, "C"), (10, "A"), (12, "C"), (12, "A"), (12, "B")]


@pytest.mark.parametrize(("frames", "again"), [(1, 4), (2, 2), (5, 0), (7, 0)])
def test_timed_again_draws_the_frames_again_by_new_modes_until_the_draws_and_takes_each_frames_median(
    monkeypatch, frames, again
):
    from morphkit.programs.planning import planverify

    calls: list[tuple[object, int]] = []

    def timed(prep, cameras, picks, modes, scene, turn=0):  # draw `turn` of each frame at `turn` ms
        calls.append((modes, turn))
        return {nm: [float(turn)] * len(picks) for nm in modes}

    monkeypatch.setattr(planverify, "time_frames", timed)
    made: list[dict[str, str]] = []

    def modes() -> dict[str, str]:
        made.append({"a": "A"})
        return made[-1]

    first = {"a": [10.0] * frames}  # each frame's first draw: 10 ms
    got = planverify.timed_again(None, [], list(range(frames)), modes, None, first, 5)
    # 5 draws in all at least: ceil(5 / frames) of each frame, each again by new modes, turned on
    assert [t for _, t in calls] == list(range(1, again + 1)) and len(made) == again
    assert all(m is made[i] for i, (m, _) in enumerate(calls))
    want = float(np.median([10.0, *range(1, again + 1)]))  # 1 frame: median(10, 1, 2, 3, 4) = 3
    assert got == {"a": [want] * frames}


def test_the_plans_rivals_are_timed_again_only_where_their_first_draws_tell_them_faster(monkeypatch):
    from types import SimpleNamespace

    from morphkit.programs.planning import planrun, planverify

    seen: list[list[str]] = []

    def timed(prep, cameras, picks, modes, scene, turn=0):  # every draw 10 ms
        seen.append(sorted(modes))
        return {nm: [10.0] * len(picks) for nm in modes}

    monkeypatch.setattr(planrun, "time_frames", timed)
    monkeypatch.setattr(planverify, "time_frames", timed)
    prep = SimpleNamespace(relit=False, base=None, shadow=None, meshes=lambda: None, scene=[1, 2, 3])
    plan = SimpleNamespace(mode=lambda *args: "the plan's mode")
    f = tol.PLAN_TIMED_FASTER
    first = {"classic": 100.0 / f - 1.0, "nearest": 100.0 / f + 1.0, "morph": 50.0}
    got = planrun._timed_rivals(prep, [0, 1], [0, 1], plan, 100.0, first)
    # faster than the plan's 100 ms by the tolerance: the card and the morph, not the nearest view; on
    # on 2 frames, PLAN_TIME_DRAWS in all at least (half of them each, rounded up), all three together
    assert seen == [["classic", "morph", "plan"]] * -(-planrun.PLAN_TIME_DRAWS // 2)
    assert got == {"plan": 10.0, "classic": 10.0, "morph": 10.0}
    seen.clear()
    assert planrun._timed_rivals(prep, [0], [0], plan, 100.0, {"nearest": 100.0 / f}) == {} and seen == []
