"""Tests of morphkit.imaging.metrics: values derivable by hand, scikit-image parity, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from morphkit.errors import ValidationError
from morphkit.imaging.metrics import SSIM_WINDOW, mean_abs_error, psnr, rmse, shadow_iou, ssim


def rect(shape: tuple[int, int], r0: int, r1: int, c0: int, c1: int) -> np.ndarray:
    m = np.zeros(shape, dtype=bool)
    m[r0:r1, c0:c1] = True
    return m


# --------------------------------------------------------------------------- IoU


def test_iou_of_two_overlapping_rectangles():
    a = rect((20, 20), 0, 10, 0, 10)  # 100 px
    b = rect((20, 20), 5, 15, 5, 15)  # 100 px, overlap 5x5 = 25
    assert shadow_iou(a, b) == pytest.approx(25 / 175)
    assert shadow_iou(b, a) == pytest.approx(25 / 175)
    assert shadow_iou(a, a) == 1.0
    assert shadow_iou(a, rect((20, 20), 12, 20, 12, 20)) == 0.0


def test_iou_both_empty_is_one():
    z = np.zeros((8, 8), dtype=bool)
    assert shadow_iou(z, z) == 1.0


def test_iou_with_mask():
    a = rect((20, 20), 0, 10, 0, 10)
    b = rect((20, 20), 5, 15, 5, 15)
    # Only the left half (columns < 10): a has 100 px, b has 10x5 = 50, overlap 25.
    left = rect((20, 20), 0, 20, 0, 10)
    assert shadow_iou(a, b, left) == pytest.approx(25 / 125)
    # A region holding neither shadow: empty union -> 1.0.
    assert shadow_iou(a, b, rect((20, 20), 16, 20, 16, 20)) == 1.0


def test_iou_rejects_non_boolean_and_bad_shapes():
    a = rect((4, 4), 0, 2, 0, 2)
    with pytest.raises(ValidationError, match="pred: expected a boolean numpy array"):
        shadow_iou(a.astype(np.uint8), a)
    with pytest.raises(ValidationError, match="truth: expected a boolean numpy array"):
        shadow_iou(a, [[True]])
    want = r"truth shape: expected the shape of pred \(4, 4\), got \(4, 5\)"
    with pytest.raises(ValidationError, match=want):
        shadow_iou(a, np.zeros((4, 5), dtype=bool))
    with pytest.raises(ValidationError, match="expected a non-empty array"):
        shadow_iou(np.zeros((0, 4), dtype=bool), np.zeros((0, 4), dtype=bool))


# --------------------------------------------------------------------------- MAE / RMSE / PSNR


def test_mae_and_rmse_of_constant_offset():
    a = np.full((6, 7), 0.25)
    b = a + 0.5
    assert mean_abs_error(a, b) == pytest.approx(0.5)
    assert rmse(a, b) == pytest.approx(0.5)
    assert mean_abs_error(a, a) == 0.0 and rmse(a, a) == 0.0


def test_mae_and_rmse_differ_for_uneven_errors():
    a = np.zeros(4)  # 1-D visibility fractions are fine
    b = np.array([0.0, 0.0, 0.0, 1.0])
    assert mean_abs_error(a, b) == pytest.approx(0.25)
    assert rmse(a, b) == pytest.approx(0.5)  # sqrt(1/4)


def test_mae_rmse_with_mask():
    a = np.zeros((4, 4))
    b = np.zeros((4, 4))
    b[0, :] = 1.0  # errors only in row 0
    row0 = rect((4, 4), 0, 1, 0, 4)
    assert mean_abs_error(a, b, row0) == pytest.approx(1.0)
    assert mean_abs_error(a, b, ~row0) == 0.0
    assert rmse(a, b, row0) == pytest.approx(1.0)
    assert mean_abs_error(a, b) == pytest.approx(0.25)


def test_per_pixel_mask_applies_to_all_channels():
    a = np.zeros((4, 4, 3))
    b = np.zeros((4, 4, 3))
    b[0, 0] = [1.0, 2.0, 3.0]
    px = rect((4, 4), 0, 1, 0, 1)
    assert mean_abs_error(a, b, px) == pytest.approx(2.0)
    full = np.zeros((4, 4, 3), dtype=bool)
    full[0, 0, 2] = True
    assert mean_abs_error(a, b, full) == pytest.approx(3.0)


def test_psnr_of_known_mse():
    a = np.zeros((10, 10))
    b = np.full((10, 10), 0.1)  # MSE = 0.01
    assert psnr(a, b, data_range=1.0) == pytest.approx(20.0)
    assert psnr(a, b * 255, data_range=255.0) == pytest.approx(10 * math.log10(255**2 / 25.5**2))
    assert psnr(a, a, data_range=1.0) == math.inf


def test_psnr_with_mask_and_uint8():
    a = np.zeros((4, 4), dtype=np.uint8)
    b = a.copy()
    b[0, 0] = 10  # no uint8 wrap-around: compared as float
    m = rect((4, 4), 0, 1, 0, 1)
    assert psnr(a, b, data_range=255, mask=m) == pytest.approx(10 * math.log10(255**2 / 100))
    assert psnr(a, b, data_range=255, mask=~m) == math.inf
    assert mean_abs_error(b, a) == pytest.approx(10 / 16)


def test_psnr_requires_positive_data_range():
    a = np.zeros((3, 3))
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValidationError, match="data_range"):
            psnr(a, a, data_range=bad)


# --------------------------------------------------------------------------- SSIM


def test_ssim_identical_is_one():
    rng = np.random.default_rng(1)
    a = rng.random((32, 24))
    assert ssim(a, a, data_range=1.0) == pytest.approx(1.0, abs=1e-12)
    c = rng.random((16, 16, 3))
    assert ssim(c, c, data_range=1.0) == pytest.approx(1.0, abs=1e-12)
    flat = np.full((16, 16), 0.3)
    assert ssim(flat, flat, data_range=1.0) == pytest.approx(1.0)


def test_ssim_of_constant_images_by_hand():
    # Constant images: variances vanish, SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1).
    a = np.full((16, 16), 0.2)
    b = np.full((16, 16), 0.6)
    c1 = (0.01 * 1.0) ** 2
    want = (2 * 0.2 * 0.6 + c1) / (0.2**2 + 0.6**2 + c1)
    assert ssim(a, b, data_range=1.0) == pytest.approx(want, rel=1e-9)


def test_ssim_degrades_with_noise():
    rng = np.random.default_rng(2)
    a = rng.random((40, 40))
    s_small = ssim(a, np.clip(a + 0.05 * rng.normal(size=a.shape), 0, 1), data_range=1.0)
    s_big = ssim(a, np.clip(a + 0.3 * rng.normal(size=a.shape), 0, 1), data_range=1.0)
    assert 1.0 > s_small > s_big


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("shape", [(32, 40), (11, 17), (48, 36, 3)])
def test_ssim_matches_skimage(seed, shape):
    metrics = pytest.importorskip("skimage.metrics")
    rng = np.random.default_rng(seed)
    a = rng.random(shape)
    b = np.clip(a + 0.2 * rng.normal(size=shape), 0.0, 1.0)
    kw = {"channel_axis": -1} if len(shape) == 3 else {}
    want = metrics.structural_similarity(
        a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1.0, **kw
    )
    assert ssim(a, b, data_range=1.0) == pytest.approx(want, abs=1e-3)


def test_ssim_matches_skimage_uint8():
    metrics = pytest.importorskip("skimage.metrics")
    rng = np.random.default_rng(3)
    a = rng.integers(0, 256, (30, 30), dtype=np.uint8)
    b = rng.integers(0, 256, (30, 30), dtype=np.uint8)
    want = metrics.structural_similarity(
        a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=255
    )
    assert ssim(a, b, data_range=255) == pytest.approx(want, abs=1e-3)


def test_ssim_with_mask():
    rng = np.random.default_rng(4)
    a = rng.random((40, 40))
    b = a.copy()
    b[:, 20:] = rng.random((40, 20))  # right half differs
    left = rect((40, 40), 0, 40, 0, 12)  # far enough from the changed half (window radius 5)
    right = rect((40, 40), 0, 40, 28, 40)
    assert ssim(a, b, data_range=1.0, mask=left) == pytest.approx(1.0, abs=1e-12)
    assert ssim(a, b, data_range=1.0, mask=right) < 0.5
    everything = np.ones((40, 40), dtype=bool)
    assert ssim(a, b, data_range=1.0, mask=everything) == ssim(a, b, data_range=1.0)
    c = np.dstack([a, b])
    assert ssim(c, c, data_range=1.0, mask=left) == pytest.approx(1.0)


def test_ssim_mask_only_on_border_is_refused():
    a = np.zeros((20, 20))
    border = rect((20, 20), 0, 2, 0, 20)
    with pytest.raises(ValidationError, match="at least one True pixel at least 5 pixels from the border"):
        ssim(a, a, data_range=1.0, mask=border)


def test_ssim_rejects_small_and_bad_images():
    small = np.zeros((SSIM_WINDOW - 1, 30))
    with pytest.raises(ValidationError, match="image size: expected H and W >= 11"):
        ssim(small, small, data_range=1.0)
    with pytest.raises(ValidationError, match="an \\(H, W\\) or \\(H, W, C\\) image"):
        ssim(np.zeros(30), np.zeros(30), data_range=1.0)
    with pytest.raises(ValidationError, match="data_range"):
        ssim(np.zeros((20, 20)), np.zeros((20, 20)), data_range=0)


# --------------------------------------------------------------------------- shared validation


@pytest.mark.parametrize(
    "fn",
    [
        mean_abs_error,
        rmse,
        lambda a, b, mask=None: psnr(a, b, data_range=1.0, mask=mask),
        lambda a, b, mask=None: ssim(a, b, data_range=1.0, mask=mask),
    ],
    ids=["mae", "rmse", "psnr", "ssim"],
)
def test_shared_validation(fn):
    a = np.zeros((16, 16))
    with pytest.raises(ValidationError, match=r"b shape: expected the shape of a \(16, 16\), got \(16, 15\)"):
        fn(a, np.zeros((16, 15)))
    bad = a.copy()
    bad[3, 3] = np.nan
    with pytest.raises(ValidationError, match="a: expected finite values, got 1 NaN/inf entries"):
        fn(bad, a)
    inf = a.copy()
    inf[0, 0] = np.inf
    with pytest.raises(ValidationError, match="b: expected finite values"):
        fn(a, inf)
    with pytest.raises(ValidationError, match="a: expected a non-empty array"):
        fn(np.zeros((0, 16)), np.zeros((0, 16)))
    with pytest.raises(ValidationError, match="a: expected a numpy array"):
        fn([[0.0]], a)
    with pytest.raises(ValidationError, match="expected a mask with at least one True pixel"):
        fn(a, a, mask=np.zeros((16, 16), dtype=bool))
    with pytest.raises(ValidationError, match=r"mask shape: expected \(16, 16\), got \(16, 8\)"):
        fn(a, a, mask=np.ones((16, 8), dtype=bool))
    with pytest.raises(ValidationError, match="mask: expected a boolean numpy array"):
        fn(a, a, mask=np.ones((16, 16), dtype=np.uint8))
