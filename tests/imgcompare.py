"""Image-regression harness.

``check_image(name, image, ...)`` compares ``image`` against the stored
reference ``tests/reference/<name>.png`` with a stated metric and tolerance.

Regenerate references (after an intended change; review the diff images!) with::

    MORPHKIT_REGEN_REFERENCES=1 python -m pytest tests/test_regression.py

A regenerating run compares nothing: each check writes its reference and is
reported as *skipped* ("reference regenerated"), never as passed.

On a mismatch, the actual image and an amplified difference image are written
next to pytest's tmp dir and their paths are in the assertion message.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

from morphkit.errors import FileFormatError
from morphkit.files.fileio import read_image, write_image

REFERENCE_DIR = Path(__file__).parent / "reference"


def _read(path: Path) -> np.ndarray:
    try:
        return read_image(path)
    except FileFormatError as exc:
        raise FileNotFoundError(f"reference image {path} is missing or unreadable ({exc}); regenerate "
                                "with MORPHKIT_REGEN_REFERENCES=1") from exc


def check_image(name: str, image: np.ndarray, *, max_mean_abs: float, max_bad_fraction: float,
                bad_level: int) -> dict[str, float]:
    """Compare a uint8 grey, RGB or RGBA image with ``reference/<name>.png``.

    Metric: mean absolute difference over all pixels and channels (grey levels),
    and the fraction of pixels whose largest channel difference exceeds
    ``bad_level``. Both must be within tolerance. Returns the measured values.

    With ``MORPHKIT_REGEN_REFERENCES`` set, writes ``image`` as the reference and
    skips the test (comparing the reference with itself would prove nothing).
    """
    assert image.dtype == np.uint8
    path = REFERENCE_DIR / f"{name}.png"
    if os.environ.get("MORPHKIT_REGEN_REFERENCES"):
        REFERENCE_DIR.mkdir(exist_ok=True)
        write_image(path, image)
        pytest.skip(f"{name}: reference regenerated ({path}); not compared (MORPHKIT_REGEN_REFERENCES)")
    ref = _read(path)
    assert ref.shape == image.shape, f"{name}: reference shape {ref.shape}, got {image.shape}"
    diff = np.abs(ref.astype(np.int16) - image.astype(np.int16))
    per_px = diff if diff.ndim == 2 else diff.max(axis=2)
    measured = {"mean_abs": float(diff.mean()), "bad_fraction": float((per_px > bad_level).mean())}
    if measured["mean_abs"] > max_mean_abs or measured["bad_fraction"] > max_bad_fraction:
        d = Path(tempfile.mkdtemp(prefix=f"morphkit-{name}-"))
        write_image(d / "actual.png", image)
        write_image(d / "diff_x8.png", np.clip(diff * 8, 0, 255).astype(np.uint8))
        raise AssertionError(f"{name}: {measured} exceeds mean_abs <= {max_mean_abs}, "
                             f"bad_fraction <= {max_bad_fraction} (> {bad_level} levels); see {d}")
    return measured
