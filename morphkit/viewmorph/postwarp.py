"""Post-warp: homographies from the rectified-interpolated frame to output pixels.

A post-warp ``H_out_rect`` maps the rectified-interpolated frame (where the
morph at ``s`` puts a pair at ``q(s) = (1 - s) H_rect_0 p0 + s H_rect_1 p1``; see
:mod:`morphkit.viewmorph.morph`) to output pixels (pixel-centre origin):
``out = H_out_rect q``. It comes from the two views' image planes
(:func:`interpolated_post_homography`), from points or a camera
(:func:`fit_post_homography`, :class:`PostWarpPoints`), or is given; a crop/size
policy then scales and shifts it in the output (:func:`frame_post_homography`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from .. import tol
from ..errors import GeometryError, ValidationError, expected_got
from .fundamental import check_spread
from .images import image_corners
from .rectify import apply_h

__all__ = ["PostWarpPoints", "FRAMES", "homography_4pt", "interpolated_post_homography",
           "fit_post_homography", "overshoot", "frame_post_homography"]

#: Crop/size policies of :func:`frame_post_homography`.
FRAMES = ("contain", "fixed", "fit")


@dataclass(frozen=True)
class PostWarpPoints:
    """Post-warp given by image points: correspondences ``index`` (into
    :attr:`ViewMorpher.correspondences`) must land on ``points`` (``(k, 2)``
    output pixels, ``k >= 4``); the homography is their least-squares fit.

    Parameters
    ----------
    index : (k,) int
        Indices into :attr:`~morphkit.viewmorph.morph.ViewMorpher.correspondences`.
    points : (k, 2) float
        Where those pairs must land, in output pixels (pixel-centre origin).
    """

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


def interpolated_post_homography(H_rect_0: np.ndarray, H_rect_1: np.ndarray, shape0: tuple[int, int],
                                 shape1: tuple[int, int], s: float) -> np.ndarray:
    """The default post-warp: image planes interpolated between the two views.

    The homography taking the interpolated rectified image corners
    ``(1 - s) H_rect_0 c0 + s H_rect_1 c1`` to the interpolated output corners
    ``(1 - s) c0 + s c1`` (so it is ``H_rect_0^-1`` at ``s = 0`` and
    ``H_rect_1^-1`` at ``s = 1``).

    Parameters
    ----------
    H_rect_0, H_rect_1 : (3, 3) float
        The pre-warps (image-``i`` pixels to the rectified frame).
    shape0, shape1 : (H, W)
        The images' shapes.
    s : float
        Position between the views, in ``[0, 1]``.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 ``H_out_rect`` (rectified-interpolated frame to output pixels).
    """
    c0 = apply_h(H_rect_0, image_corners(shape0))
    c1 = apply_h(H_rect_1, image_corners(shape1))
    src = (1 - s) * c0 + s * c1
    dst = (1 - s) * image_corners(shape0) + s * image_corners(shape1)
    return homography_4pt(src, dst)


def fit_post_homography(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Least-squares homography taking ``src`` to ``dst`` (``cv2.findHomography``, all points).

    Parameters
    ----------
    src : (k, 2) float
        Points in the rectified-interpolated frame, ``k >= 4``, spread in 2-D.
    dst : (k, 2) float
        Where they must land, in output pixels.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 ``H_out_rect`` with ``H[2, 2] = 1``.

    Raises
    ------
    ValidationError
        Fewer than 4 points.
    GeometryError
        Points without 2-D spread, or no finite fit.
    """
    if len(src) < 4:
        raise ValidationError(expected_got("post-warp points", "at least 4", f"{len(src)}"))
    check_spread(src, "post-warp source points")
    check_spread(dst, "post-warp target points")
    H_out_rect, _ = cv2.findHomography(src, dst, 0)
    if H_out_rect is None or not np.all(np.isfinite(H_out_rect)):
        raise GeometryError(expected_got("post-warp homography fit", "a solution", "none"))
    return H_out_rect / H_out_rect[2, 2]


def overshoot(points: np.ndarray, shape: tuple[int, int]) -> float:
    """How far (pixels) ``points`` reach outside an image of ``shape`` (0 when all lie inside).

    Parameters
    ----------
    points : (N, 2) float
        Pixel positions (pixel-centre origin), ``N >= 1``.
    shape : (H, W)

    Returns
    -------
    float
        The largest distance, along ``x`` or ``y``, from the image's outer edges
        to a point beyond them.
    """
    c = image_corners(shape)
    return float(max(0.0, np.max(c[0] - points.min(axis=0)), np.max(points.max(axis=0) - c[2])))


def frame_post_homography(H_out_rect: np.ndarray, object_rect: np.ndarray, shape: tuple[int, int], frame: str,
                          slack: float = 0.0) -> np.ndarray:
    """Apply a crop/size policy to a post-warp: a similarity left-multiplied onto it.

    Parameters
    ----------
    H_out_rect : (3, 3) float
        The post-warp (rectified-interpolated frame to output pixels).
    object_rect : (N, 2) float
        The object's points (the pairs) in the rectified-interpolated frame.
    shape : (H, W)
        The output shape.
    frame : {"contain", "fixed", "fit"}
        ``"contain"``: scale down (about the frame centre) and shift only when
        the object's bounding box leaves the frame by more than ``slack``;
        ``"fit"``: always scale the object to fill the frame with a 5% margin;
        ``"fixed"``: ``H_out_rect`` unchanged.
    slack : float
        Pixels the object may leave the frame by under ``"contain"`` (how far it
        leaves the input images).

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 ``H_framed_out @ H_out_rect`` (``H_framed_out`` a
        scale and shift of output pixels), or ``H_out_rect`` itself when nothing
        changes.
    """
    if frame == "fixed":
        return H_out_rect
    obj = apply_h(H_out_rect, object_rect)
    blo, bhi = obj.min(axis=0), obj.max(axis=0)
    h, w = shape
    flo, fhi = np.array([-0.5, -0.5]), np.array([w - 0.5, h - 0.5])
    if frame == "contain":
        if np.all(blo >= flo - slack - tol.PX_EQUAL) and np.all(bhi <= fhi + slack + tol.PX_EQUAL):
            return H_out_rect
        margin = 0.02
    else:
        margin = 0.05
    size = fhi - flo
    inner_lo, inner_hi = flo + margin * size, fhi - margin * size
    k = float(np.min((inner_hi - inner_lo) / np.maximum(bhi - blo, tol.PX_EQUAL)))
    if frame == "contain":
        k = min(k, 1.0)
    cb, cf = 0.5 * (blo + bhi), 0.5 * (flo + fhi)
    H_framed_out = np.array([[k, 0.0, cf[0] - k * cb[0]], [0.0, k, cf[1] - k * cb[1]], [0.0, 0.0, 1.0]])
    return H_framed_out @ H_out_rect
