"""The reference pair of images: validation, layout promotion (grey < RGB < RGBA), corners."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ValidationError, expected_got
from ..validate import as_image

__all__: list[str] = []


def _layout(img: np.ndarray) -> int:
    return 1 if img.ndim == 2 else int(img.shape[2])


def _prepare_pair(image0: Any, image1: Any) -> tuple[np.ndarray, np.ndarray, int, np.dtype]:
    a = as_image(image0, "image0", channels=(1, 3, 4))
    b = as_image(image1, "image1", channels=(1, 3, 4))
    if a.dtype != b.dtype:
        raise ValidationError(expected_got("image1 dtype", f"{a.dtype} (as image0)", f"{b.dtype}"))
    if a.dtype == np.bool_:
        raise ValidationError(expected_got("image dtype", "a numeric dtype", "bool"))
    ch = max(_layout(a), _layout(b))
    return a, b, ch, a.dtype


def _corners(shape: tuple[int, int]) -> np.ndarray:
    h, w = shape
    return np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5], [-0.5, h - 0.5]])
