"""The reference pair of images: validation, layout promotion (grey < RGB < RGBA), corners."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import ValidationError, expected_got
from ..validate import as_image

__all__ = ["prepare_pair", "image_corners"]


def _layout(img: np.ndarray) -> int:
    return 1 if img.ndim == 2 else int(img.shape[2])


def prepare_pair(image0: Any, image1: Any) -> tuple[np.ndarray, np.ndarray, int, np.dtype]:
    """Validate two reference images and the layout they are promoted to.

    Parameters
    ----------
    image0, image1 : numpy.ndarray
        ``(H, W)`` grey, ``(H, W, 3)`` RGB or ``(H, W, 4)`` RGBA (straight
        alpha), one numeric (not bool) dtype; shapes may differ.

    Returns
    -------
    image0, image1 : numpy.ndarray
        The images as validated arrays (not copied, not promoted).
    channels : int
        The richer layout of the two (1 grey < 3 RGB < 4 RGBA), for
        :func:`morphkit.imaging.composite.to_premultiplied`.
    dtype : numpy.dtype
        Their common dtype.

    Raises
    ------
    ValidationError
        Not an image, an unsupported channel count, different dtypes, or bool.
    """
    a = as_image(image0, "image0", channels=(1, 3, 4))
    b = as_image(image1, "image1", channels=(1, 3, 4))
    if a.dtype != b.dtype:
        raise ValidationError(expected_got("image1 dtype", f"{a.dtype} (as image0)", f"{b.dtype}"))
    if a.dtype == np.bool_:
        raise ValidationError(expected_got("image dtype", "a numeric dtype", "bool"))
    ch = max(_layout(a), _layout(b))
    return a, b, ch, a.dtype


def image_corners(shape: tuple[int, int]) -> np.ndarray:
    """The outer corners of an image of ``shape``, clockwise on screen from the top left.

    Parameters
    ----------
    shape : (H, W)

    Returns
    -------
    numpy.ndarray
        ``(4, 2)`` float64 pixel positions (pixel-centre origin, so the image's
        outer edges are at ``-0.5`` and ``W - 0.5``, ``H - 0.5``).
    """
    h, w = shape
    return np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5], [-0.5, h - 0.5]])
