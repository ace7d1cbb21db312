"""Error budgets (morphkit.plan.budget): parsed from KEY=VALUE, nonsense refused naming the key."""

from __future__ import annotations

import pytest

from morphkit.errors import UsageError
from morphkit.plan.budget import DEFAULT_FRAMES, Budget


def test_a_budget_reads_its_keys_and_keeps_the_frames_default():
    b = Budget.parse(["billboard-psnr=28", "billboard-iou=0.9", "shadow-iou=0.75", "time-ms=40"])
    assert (b.billboard_psnr, b.billboard_iou, b.shadow_iou, b.time_ms, b.frames) == (28.0, 0.9, 0.75, 40.0,
                                                                                      DEFAULT_FRAMES)
    assert Budget.parse(["shadow-iou=0.8", "frames=0.5"]).to_json() == {"shadow-iou": 0.8, "frames": 0.5}
    assert Budget.parse([" Billboard-PSNR = 30 "]).billboard_psnr == 30.0  # spaces and case


@pytest.mark.parametrize(("items", "match"), [
    (["psnr=30"], r"--budget key: expected one of billboard-psnr, .*, got 'psnr'"),
    (["billboard-psnr=nan"], r"--budget billboard-psnr: expected dB > 0, got 'nan'"),
    (["billboard-psnr=inf"], r"expected dB > 0, got 'inf'"),
    (["billboard-psnr=0"], r"expected dB > 0, got '0'"),
    (["billboard-psnr=-3"], r"expected dB > 0"),
    (["billboard-iou=1.2"], r"--budget billboard-iou: expected a number in \(0, 1\], got '1.2'"),
    (["shadow-iou=0"], r"--budget shadow-iou: expected a number in \(0, 1\]"),
    (["shadow-iou=high"], r"got 'high'"),
    (["billboard-psnr=30", "frames=1.5"], r"--budget frames: expected a fraction in \(0, 1\]"),
    (["time-ms=-1"], r"--budget time-ms: expected milliseconds > 0"),
    (["billboard-psnr"], r"--budget: expected KEY=VALUE, got 'billboard-psnr'"),
    (["billboard-psnr=30", "billboard-psnr=31"], r"--budget billboard-psnr: expected once, got twice"),
    (["frames=0.9"], r"--budget: expected at least one of billboard-psnr, billboard-iou, shadow-iou, time"),
    ([], r"at least one of"),
], ids=["unknown", "nan", "inf", "psnr-0", "psnr-negative", "iou-above-1", "iou-0", "not-a-number",
        "frames-above-1", "time-negative", "no-value", "twice", "frames-alone", "empty"])
def test_nonsense_budgets_are_usage_errors(items, match):
    with pytest.raises(UsageError, match=match):
        Budget.parse(items)


def test_a_frame_meets_every_key_or_not():
    b = Budget(billboard_psnr=28.0, shadow_iou=0.8)
    assert b.meets({"billboard-psnr": 28.0, "shadow-iou": 0.8})  # at least: the bound itself meets
    assert not b.meets({"billboard-psnr": 27.99, "shadow-iou": 0.9})
    assert not b.meets({"billboard-psnr": 30.0, "shadow-iou": 0.79})
    assert b.meets({"billboard-psnr": None, "shadow-iou": 0.85})  # no billboard on screen
    assert not b.meets({"billboard-psnr": float("nan"), "shadow-iou": 0.85})  # NaN never meets


def test_the_verdict_counts_frames_against_the_fraction():
    b = Budget(billboard_iou=0.9, frames=0.75)
    frames = [{"billboard-iou": v} for v in (0.95, 0.91, 0.89, 0.93)]
    assert b.verdict(frames) == {"frames": 4, "within": 3, "fraction": 0.75, "met": True}
    assert Budget(billboard_iou=0.9).verdict(frames)["met"] is False  # 0.75 < 0.95
    assert b.verdict([])["met"] is False
