"""Post-warp: homographies from the rectified-interpolated frame to output pixels.

Convention: see :mod:`morphkit.viewmorph.morph` (``P = H_out_rect`` maps the
rectified-interpolated frame to output pixels).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import GeometryError, expected_got

__all__ = ["PostWarpPoints", "homography_4pt"]


@dataclass(frozen=True)
class PostWarpPoints:
    """Post-warp given by image points: correspondences ``index`` (into
    :attr:`ViewMorpher.correspondences`) must land on ``points`` (``(k, 2)``
    output pixels, ``k >= 4``); the homography is their least-squares fit."""

    index: Any
    points: Any


def homography_4pt(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """``H_dst_src`` from four point pairs, solved in float64 (cv2's version is float32).

    Parameters
    ----------
    src, dst : (4, 2) float
        Four points in the source frame and where they must land in the
        destination frame.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 ``H_dst_src`` with ``H[2, 2] = 1``: ``dst ~ H (src, 1)``.

    Raises
    ------
    GeometryError
        Degenerate quadrilaterals (three collinear points).
    """
    A = np.zeros((8, 8))
    b = np.zeros(8)
    for i, ((x, y), (u, v)) in enumerate(zip(src, dst, strict=True)):
        A[2 * i] = [x, y, 1, 0, 0, 0, -u * x, -u * y]
        A[2 * i + 1] = [0, 0, 0, x, y, 1, -v * x, -v * y]
        b[2 * i], b[2 * i + 1] = u, v
    try:
        h = np.linalg.solve(A, b)
    except np.linalg.LinAlgError as exc:
        raise GeometryError(expected_got("post-warp corners", "a non-degenerate quadrilateral",
                                         "three collinear corners")) from exc
    return np.r_[h, 1.0].reshape(3, 3)
