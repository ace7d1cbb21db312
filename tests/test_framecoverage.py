"""The coverage rule of a frame's IoU (morphkit.plan.framecoverage), against figures derived by hand."""

from __future__ import annotations

import numpy as np
import pytest

from morphkit.errors import ValidationError
from morphkit.plan.framecoverage import union_iou


def _iou(a: float, b: float, i: float) -> float:
    return i / (a + b - i)


def test_one_box_is_its_own_iou_whatever_its_size_and_the_grid():
    for roi, step in (([3, 17, 5, 40], 4), ([0, 1, 0, 1], 4), ([2, 30, 0, 64], 1)):
        got = union_iou(np.array([roi]), np.array([[0.6, 0.5, 0.4]]), (32, 64), step=step)
        assert got == pytest.approx(_iou(0.6, 0.5, 0.4), abs=1e-12)


def test_disjoint_boxes_weigh_by_the_pixels_of_their_silhouettes_union():
    rois = np.array([[0, 8, 0, 8], [8, 16, 0, 24]])  # 64 and 192 pixels, cells of 4
    f = np.array([[0.3, 0.4, 0.2], [0.7, 0.6, 0.55]])
    area = np.array([64.0, 192.0])
    inter = (area * f[:, 2]).sum()
    union = (area * (f[:, 0] + f[:, 1] - f[:, 2])).sum()
    assert union_iou(rois, f, (16, 32)) == pytest.approx(inter / union, abs=1e-12)
    # the boxes' mean weighted by their boxes (the plan's rule) is another figure: the test can fail
    assert union_iou(rois, f, (16, 32)) != pytest.approx((area * [_iou(*x) for x in f]).sum() / area.sum())


def test_two_boxes_on_one_another_cover_as_independent_silhouettes():
    a1, b1, i1, a2, b2, i2 = 0.5, 0.4, 0.3, 0.2, 0.6, 0.1
    pa = 1 - (1 - a1) * (1 - a2)
    pb = 1 - (1 - b1) * (1 - b2)
    pu = 1 - (1 - a1 - b1 + i1) * (1 - a2 - b2 + i2)
    got = union_iou(np.array([[0, 8, 0, 8]] * 2), np.array([[a1, b1, i1], [a2, b2, i2]]), (8, 8))
    assert got == pytest.approx((pa + pb - pu) / pu, abs=1e-12)
    # two silhouettes spread over one box overlap by chance: the IoU rises above either alone
    assert got > max(_iou(a1, b1, i1), _iou(a2, b2, i2))


def test_nothing_covered_is_an_iou_of_one_and_a_full_box_is_exact():
    assert union_iou(np.array([[0, 4, 0, 4]]), np.zeros((1, 3)), (4, 4)) == 1.0
    assert union_iou(np.zeros((0, 4), np.int64), np.zeros((0, 3)), (4, 4)) == 1.0
    assert union_iou(np.array([[0, 4, 0, 4]]), np.array([[1.0, 1.0, 1.0]]), (4, 4)) == 1.0
    # the truth covers the box wholly, the representation not at all
    assert union_iou(np.array([[0, 4, 0, 4]]), np.array([[0.0, 1.0, 0.0]]), (4, 4)) == 0.0


def test_fractions_no_silhouettes_could_cover_and_bad_boxes_are_refused():
    roi = np.array([[0, 4, 0, 4]])
    with pytest.raises(ValidationError, match=r"fractions\[0\]: expected 0 <= i <= min\(a, b\)"):
        union_iou(roi, np.array([[0.2, 0.5, 0.3]]), (8, 8))
    with pytest.raises(ValidationError, match=r"fractions\[0\]: expected .* and a \+ b - i <= 1"):
        union_iou(roi, np.array([[0.8, 0.9, 0.5]]), (8, 8))
    with pytest.raises(ValidationError, match=r"fractions"):
        union_iou(roi, np.array([[np.nan, 0.5, 0.3]]), (8, 8))
    with pytest.raises(ValidationError, match=r"rois\[0\]: expected a non-empty box inside the frame \(8"):
        union_iou(np.array([[0, 9, 0, 4]]), np.array([[0.5, 0.5, 0.5]]), (8, 8))
    with pytest.raises(ValidationError, match=r"rois: expected an \(N, 4\) integer array"):
        union_iou(np.array([[0.0, 4.0, 0.0, 4.0]]), np.array([[0.5, 0.5, 0.5]]), (8, 8))
    with pytest.raises(ValidationError, match=r"shape: expected positive \(H, W\), got \(0, 8\)"):
        union_iou(roi, np.array([[0.5, 0.5, 0.5]]), (0, 8))
    with pytest.raises(ValidationError, match=r"step: expected an integer >= 1"):
        union_iou(roi, np.array([[0.5, 0.5, 0.5]]), (8, 8), step=0)
