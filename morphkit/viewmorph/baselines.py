"""Image-only baselines of view morphing: a premultiplied cross-dissolve and the nearer
reference image (what a classic billboard shows); both validate and promote the pair
like :class:`~morphkit.viewmorph.morph.ViewMorpher`.
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..imaging.composite import from_premultiplied, to_premultiplied
from ..validate import as_unit_interval
from .images import prepare_pair

__all__ = ["crossfade", "nearest"]


def crossfade(image0: Any, image1: Any, s: float) -> np.ndarray:
    """Premultiplied cross-dissolve ``(1 - s) I0 + s I1`` (images of the same shape).

    Layouts are promoted like :class:`~morphkit.viewmorph.morph.ViewMorpher`;
    the output has the richer layout.

    Parameters
    ----------
    image0, image1 : numpy.ndarray
        ``(H, W)``, ``(H, W, 3)`` or ``(H, W, 4)`` (straight alpha), one dtype,
        the same ``(H, W)``.
    s : float in [0, 1]

    Returns
    -------
    numpy.ndarray
        ``(H, W)`` / ``(H, W, 3)`` / ``(H, W, 4)`` in the inputs' dtype.

    Raises
    ------
    ValidationError
        ``s`` outside [0, 1], or images that differ in dtype or size.
    """
    s = as_unit_interval(s, "s")
    a, b, ch, dt = prepare_pair(image0, image1)
    if a.shape[:2] != b.shape[:2]:
        raise ValidationError(expected_got("image1 shape", f"{a.shape[:2]} (as image0)", f"{b.shape[:2]}"))
    acc = cv2.addWeighted(to_premultiplied(a, ch), 1.0 - s, to_premultiplied(b, ch), s, 0.0)
    return from_premultiplied(acc, ch, dt)


def nearest(image0: Any, image1: Any, s: float) -> np.ndarray:
    """The reference image nearer to ``s`` (image 0 for ``s <= 1/2``): a classic billboard.

    Parameters
    ----------
    image0, image1 : numpy.ndarray
        The two reference images (any shapes and layouts; not checked).
    s : float in [0, 1]

    Returns
    -------
    numpy.ndarray
        A copy of ``image0`` for ``s <= 1/2``, else of ``image1``.
    """
    s = as_unit_interval(s, "s")
    return np.array(image0 if s <= 0.5 else image1, copy=True)
