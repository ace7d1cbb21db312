"""Correspondences from the images alone: feature matching.

:func:`from_images` matches SIFT features with Lowe's ratio test and a mutual
(cross-check) test; outliers that survive are removed later by the robust
fundamental-matrix fit (:func:`morphkit.viewmorph.fundamental.estimate_fundamental`).
Pixels follow :mod:`morphkit.conventions` (origin at the centre of the top-left pixel).
"""

from __future__ import annotations

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..validate import as_image
from .correspondences import Correspondences

__all__ = ["from_images"]



def _gray_u8(img: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """8-bit grey version of ``img`` and, for RGBA, the alpha > 0 mask (dilated 2 px)."""
    a = as_image(img, "image", channels=(1, 3, 4))
    if a.dtype == np.uint8:
        f = a
    elif a.dtype.kind == "f":
        f = np.clip(np.rint(a * 255.0), 0, 255).astype(np.uint8)
    else:
        top = float(np.iinfo(a.dtype).max)
        f = np.clip(np.rint(a.astype(np.float64) * (255.0 / top)), 0, 255).astype(np.uint8)
    mask = None
    if f.ndim == 3 and f.shape[2] == 4:
        alpha = f[..., 3]
        mask = cv2.dilate((alpha > 0).astype(np.uint8) * 255, np.ones((5, 5), np.uint8))
        rgb = (f[..., :3].astype(np.float32) * (alpha[..., None] / 255.0)).astype(np.uint8)
        gray = cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY)
    elif f.ndim == 3:
        gray = cv2.cvtColor(np.ascontiguousarray(f), cv2.COLOR_RGB2GRAY)
    else:
        gray = f
    return np.ascontiguousarray(gray), mask


def from_images(image0: np.ndarray, image1: np.ndarray, *, ratio: float = 0.75,
                max_features: int = 4000, cross_check: bool = True,
                contrast_threshold: float = 0.02) -> Correspondences:
    """Correspondences from the images alone: SIFT + Lowe's ratio test + mutual check.

    Grey, RGB and RGBA images of any of uint8/uint16/float (in [0, 1]) are
    accepted; RGBA images are matched on their premultiplied colour, with
    features only where alpha > 0 (dilated by 2 px). The result still contains
    outliers: fit F robustly (``estimate_fundamental(method="auto")`` does).

    Parameters
    ----------
    ratio : float
        Lowe's ratio: keep a match whose best distance is below ``ratio`` times
        the second best.
    max_features : int
        SIFT ``nfeatures`` per image.
    cross_check : bool
        Keep only mutual best matches (image 0 -> 1 and 1 -> 0 agree).
    contrast_threshold : float
        SIFT's ``contrastThreshold``; lower than OpenCV's default (0.04) to find
        more matches on the flat-shaded renders of the bench.

    Returns
    -------
    Correspondences
        ``source="features"``; possibly fewer than 8 pairs (then the view
        morpher refuses it with a ValidationError).
    """
    if not 0.0 < float(ratio) <= 1.0:
        raise ValidationError(expected_got("ratio", "a number in (0, 1]", ratio))
    g0, m0 = _gray_u8(image0)
    g1, m1 = _gray_u8(image1)
    sift = cv2.SIFT_create(nfeatures=int(max_features), contrastThreshold=float(contrast_threshold))
    k0, d0 = sift.detectAndCompute(g0, m0)
    k1, d1 = sift.detectAndCompute(g1, m1)
    empty = Correspondences(np.zeros((0, 2)), np.zeros((0, 2)), "features")
    if d0 is None or d1 is None or len(k0) < 2 or len(k1) < 2:
        return empty
    bf = cv2.BFMatcher(cv2.NORM_L2)
    fwd = bf.knnMatch(d0, d1, k=2)
    good = {m.queryIdx: m.trainIdx for m, n in (p for p in fwd if len(p) == 2)
            if m.distance < ratio * n.distance}
    if cross_check and good:
        back = bf.match(d1, d0)
        best_back = {m.queryIdx: m.trainIdx for m in back}
        good = {q: t for q, t in good.items() if best_back.get(t) == q}
    if not good:
        return empty
    q = np.array(list(good.keys()))
    t = np.array(list(good.values()))
    p0 = np.array([k0[i].pt for i in q], dtype=np.float64)
    p1 = np.array([k1[i].pt for i in t], dtype=np.float64)
    # cv2 keypoints use the pixel-centre origin already (pixel (c, r) centred at (c, r)).
    return Correspondences(p0, p1, "features")
