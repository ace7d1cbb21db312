"""The image-regression harness itself: a regenerating run never reports a pass."""

from __future__ import annotations

import imgcompare
import numpy as np
import pytest


def test_regeneration_skips_instead_of_comparing_with_itself(tmp_path, monkeypatch):
    monkeypatch.setattr(imgcompare, "REFERENCE_DIR", tmp_path)
    monkeypatch.setenv("MORPHKIT_REGEN_REFERENCES", "1")
    img = np.arange(64, dtype=np.uint8).reshape(8, 8)
    with pytest.raises(pytest.skip.Exception, match=r"x: reference regenerated .*x.png.*not compared"):
        imgcompare.check_image("x", img, max_mean_abs=0.0, max_bad_fraction=0.0, bad_level=0)
    assert (tmp_path / "x.png").exists()
    monkeypatch.delenv("MORPHKIT_REGEN_REFERENCES")
    # a normal run compares: the same image passes, a changed one fails
    assert imgcompare.check_image("x", img, max_mean_abs=0.0, max_bad_fraction=0.0, bad_level=0) == {
        "mean_abs": 0.0, "bad_fraction": 0.0}
    with pytest.raises(AssertionError, match=r"x: .*exceeds mean_abs <= 0.0"):
        imgcompare.check_image("x", img[::-1].copy(), max_mean_abs=0.0, max_bad_fraction=0.0, bad_level=0)
