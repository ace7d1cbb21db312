"""Planning the frames' shadow to a ``shadow-iou`` budget (morphkit.plan.shadowchoice), its figure
(morphkit.sunlit.shadowing.darkened_iou) and its place in the plan file. No GL: measures made by
hand; the command end to end is in test_plan_command.py."""

from __future__ import annotations

import json

import numpy as np
import pytest

from morphkit import tol
from morphkit.billboard.frames.frametypes import Frame
from morphkit.errors import BudgetError, FileFormatError, ValidationError
from morphkit.plan import Budget
from morphkit.plan.planfile import ScenePlan, read_plan
from morphkit.plan.representations import BandChoice
from morphkit.plan.shadowchoice import (
    SHADOW_TEXELS,
    ShadowMeasure,
    choose_shadow,
    interpolate_frames,
    shadow_candidates,
    shadow_name,
)
from morphkit.scenes.description import SOFT_PCSS, SceneShadows
from morphkit.sunlit.shadowing import DARK_LEVELS, darkened_iou


def _frame(rgb: np.ndarray, alpha: np.ndarray) -> Frame:
    layer = np.zeros((*alpha.shape, 4), np.float32)
    layer[..., 3] = alpha
    return Frame(rgb, layer, [], None)


def test_the_shadow_figure_is_the_iou_of_the_darkened_pixels_where_both_frames_show_ground():
    rng = np.random.default_rng(4)
    plain = rng.integers(60, 256, (20, 30, 3), dtype=np.uint8)
    a = rng.random((20, 30)) < 0.3  # the method's shadow
    b = rng.random((20, 30)) < 0.3  # the truth's
    obj_a = np.zeros((20, 30), np.float32)
    obj_b = np.zeros((20, 30), np.float32)
    obj_a[:, :10] = 1.0  # the method draws an object over the first 10 columns, the truth over 12
    obj_b[:, :12] = 1.0
    dark = np.uint8(DARK_LEVELS)
    sa, sb = plain.copy(), plain.copy()
    sa[a] -= dark  # exactly the threshold: darkened
    sb[b] -= dark
    sb[~b & (rng.random((20, 30)) < 0.5)] -= np.uint8(DARK_LEVELS - 1)  # under it: not darkened
    ground = np.ones((20, 30), bool)
    ground[:, :12] = False  # an object in either frame: left out (objects in both, or in one only)
    want = np.count_nonzero(a & b & ground) / np.count_nonzero((a | b) & ground)
    got = darkened_iou(_frame(plain, obj_a), _frame(sa, obj_a), _frame(plain, obj_b), _frame(sb, obj_b))
    assert got == pytest.approx(want, abs=1e-12)
    # nothing darkened in either: nothing to measure
    lit_a, lit_b = _frame(plain, obj_a), _frame(plain, obj_b)
    assert darkened_iou(lit_a, lit_a, lit_b, lit_b) is None


def test_the_candidates_are_each_texel_size_under_the_scenes_softness_and_for_a_soft_sun_hard_and_pcss():
    hard = shadow_candidates(SceneShadows())
    assert [shadow_name(c) for c in hard] == ["hard-128", "hard-64", "hard-256", "hard-512"]
    soft = shadow_candidates(SceneShadows(soft=4, sun_atlas_size=96, sun_radius_deg=2.0))
    names = [shadow_name(c) for c in soft]
    assert names[0] == "disc4-96"  # the scene's own first
    assert len(names) == len(set(names)) == 3 * (len(SHADOW_TEXELS) + 1)
    assert {n.split("-")[0] for n in names} == {"disc4", "hard", "pcss"}
    assert all(c.sun_radius_deg == 2.0 for c in soft)  # the scene's disc kept
    pcss = shadow_candidates(SceneShadows(soft=SOFT_PCSS))
    assert {shadow_name(c).split("-")[0] for c in pcss} == {"pcss", "hard"}
    with pytest.raises(ValidationError, match="shadows: expected a SceneShadows, got dict"):
        shadow_candidates({"soft": None})


def _m(soft, size, iou, ms):
    return ShadowMeasure(SceneShadows(soft=soft, sun_atlas_size=size), (0, 10, 20, 30), tuple(iou), ms)


def test_the_least_work_shadow_meeting_the_budget_by_the_margin_is_chosen_whatever_its_time():
    own = _m(SOFT_PCSS, 128, [0.80, 0.82, 0.79, 0.81], 50.0)
    fine = _m(SOFT_PCSS, 512, [0.90, 0.91, 0.92, 0.90], 90.0)
    hard = _m(None, 256, [0.86, 0.87, 0.865, 0.88], 40.0)
    coarse = _m(None, 64, [0.70, 0.72, 0.71, 0.69], 20.0)
    measures = [own, fine, hard, coarse]
    assert [m.work for m in measures] == [128**2 * 2, 512**2 * 2, 256**2, 64**2]
    assert choose_shadow(measures, Budget(shadow_iou=0.85)) is hard  # 0.86 - 0.01 >= 0.85, the least work
    # 0.86 less the margin falls short of 0.855: only the finest atlases are left
    assert choose_shadow(measures, Budget(shadow_iou=0.855)) is fine
    # half of the frames: the fraction's figure is the second best of the four; the scene's own, 0.81,
    # would meet it with less work than hard-256 but for its margin (0.025: frame 20 fell that far
    # below what frames 10 and 30 predict of it)
    assert own.margin() == pytest.approx(0.025) and hard.margin() == pytest.approx(tol.PLAN_MARGIN_IOU)
    assert choose_shadow(measures, Budget(shadow_iou=0.795, frames=0.5)) is hard
    assert choose_shadow(measures, Budget(shadow_iou=0.78, frames=0.5)) is own  # less work, slower
    assert choose_shadow(measures, Budget(shadow_iou=0.68, frames=0.5)) is coarse
    # frames where nothing is shadowed meet it
    empty = _m(None, 64, [None, None, None, None], 1.0)
    assert choose_shadow([*measures, empty], Budget(shadow_iou=0.99)) is empty
    with pytest.raises(ValidationError, match="shadow candidates: expected at least one measured"):
        choose_shadow([], Budget(shadow_iou=0.5))


def test_a_shadow_budget_no_candidate_meets_names_the_best_reachable_and_its_bound():
    own = _m(SOFT_PCSS, 128, [0.80, 0.82, 0.79, 0.81], 50.0)
    fine = _m(SOFT_PCSS, 512, [0.90, 0.91, 0.92, 0.90], 90.0)
    want = (
        r"best reachable is shadow-iou 0\.88 \(with its margin of 0\.02\) in 95% of the 4 calibration "
        r"frames, against 0\.95, with pcss-512; bounded by the sun atlases' texels \(512, the finest "
        r"candidate's\)"
    )
    with pytest.raises(BudgetError, match=want):
        choose_shadow([own, fine], Budget(shadow_iou=0.95))
    # the finest atlases reach less than a coarser one: the texels do not bound it
    worse = _m(None, 1024, [0.5] * 4, 10.0)
    with pytest.raises(BudgetError, match="with pcss-512; bounded by the sun's softness"):
        choose_shadow([own, fine, worse], Budget(shadow_iou=0.95))


def test_a_shadow_whose_frames_dip_between_those_measured_keeps_a_margin_as_deep():
    # a sun low at both ends of the path: the ends' shadows fall short of the middle's
    m = _m(None, 64, [0.80, 0.92, 0.91, 0.78], 1.0)
    # frame 0 left out is predicted as frame 10 (0.92): 0.12 short; frame 30 as frame 20: 0.13 short
    assert m.margin() == pytest.approx(0.13)
    assert not m.meets(Budget(shadow_iou=0.70)) and m.meets(Budget(shadow_iou=0.65))
    one = ShadowMeasure(SceneShadows(), (5,), (0.9,), 1.0)  # one frame: nothing to leave out
    assert one.margin() == tol.PLAN_MARGIN_IOU


def test_a_held_out_frames_shadow_is_predicted_from_the_calibration_frames_around_it():
    got = interpolate_frames([0, 10, 20], [0.8, None, 0.6], [0, 5, 15, 25, -3])
    assert got == pytest.approx([0.8, 0.75, 0.65, 0.6, 0.8])
    assert interpolate_frames([0, 10], [None, None], [3]) == [None]


def test_a_measures_figure_is_its_budgets_fraction_of_the_frames():
    m = _m(None, 128, [0.9, 0.5, 0.7, None], 1.0)
    assert m.reached(Budget(shadow_iou=0.5)) == 0.5  # 95 % of 3 frames: all of them
    assert m.reached(Budget(shadow_iou=0.5, frames=0.6)) == 0.7
    assert m.name == "hard-128" and m.work == 128**2
    assert _m(4, 64, [0.5] * 4, 1.0).work == 4 * 64**2
    assert tol.PLAN_MARGIN_IOU > 0


def test_a_plans_shadow_round_trips_through_the_plan_file_and_a_bad_one_is_refused(tmp_path):
    shadows = SceneShadows(soft=SOFT_PCSS, sun_atlas_size=256)
    plan = ScenePlan(Budget(shadow_iou=0.8), BandChoice(), True, ("tree",), shadows=shadows,
                     report={"shadow": {"name": "pcss-256", "candidates": {}}})
    path = plan.save(tmp_path / "plan.json")
    obj = json.loads(path.read_text())
    assert obj["shadow"] == {"name": "pcss-256", "candidates": {}, "soft": "pcss", "sun_atlas_size": 256}
    back = read_plan(path)
    assert back.shadows == shadows and back.budget == Budget(shadow_iou=0.8)
    assert read_plan(ScenePlan(Budget(shadow_iou=0.8), BandChoice(), True, ("tree",)).save(
        tmp_path / "none.json")).shadows is None
    obj["shadow"] = {"soft": "blur", "sun_atlas_size": 256}
    (tmp_path / "bad.json").write_text(json.dumps(obj))
    with pytest.raises(FileFormatError, match="relit, assets and choices of a plan.*shadows soft"):
        read_plan(tmp_path / "bad.json")
    obj["shadow"] = [1]
    (tmp_path / "bad.json").write_text(json.dumps(obj))
    with pytest.raises(FileFormatError, match="shadow must be an object of soft and sun_atlas_size"):
        read_plan(tmp_path / "bad.json")


def test_render_refuses_a_plans_shadow_for_a_scene_without_shadows_before_any_work(tmp_path, capsys):
    from morphkit.cli import main

    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps({
        "morphkit_scene": 1, "assets": [{"name": "tree", "source": "tree"}],
        "instances": {"listed": [{"asset": "tree", "x": 0.0, "y": 0.0}]}, "camera": {"path": "orbit"},
        "sun": {"azimuth_deg": 120.0, "elevation_deg": 40.0}, "views": "dome", "frames": 2,
    }))
    plan = ScenePlan(Budget(shadow_iou=0.8), BandChoice(), True, ("tree",),
                     shadows=SceneShadows(sun_atlas_size=64)).save(tmp_path / "plan.json")
    out = tmp_path / "out"
    assert main(["render", str(scene), "--plan", str(plan), "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    want = "plan: expected a plan without a shadow for a scene without shadows, got one with"
    assert err == [f"morphkit: error: {want}"]
    assert not out.exists()
