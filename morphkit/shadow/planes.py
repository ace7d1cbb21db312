"""Depth maps as premultiplied planes, so warps and blends never mix depth with background.

A depth map becomes two float32 planes ``[coverage, coverage * (depth - ref)]``
(:func:`depth_planes`); bilinear sampling and weighted sums of such planes blend
object depths only, and :func:`planes_to_depth` turns the result back into depth
(``+inf`` where the blended coverage is below 0.5).
"""

from __future__ import annotations

import cv2
import numpy as np

from ..settings import compile_kernel, use_compiled
from ..warp import MeshWarper, accumulate_warps

__all__ = ["depth_planes", "add_planes", "warp_planes", "planes_to_depth"]


def depth_planes(depth: np.ndarray, ref: float = 0.0) -> np.ndarray:
    """``(2, H, W)`` float32 planes, premultiplied: ``[coverage, coverage * (depth - ref)]``;
    coverage is 1 on the object and 0 on the background.

    Bilinear interpolation of premultiplied channels blends object depths only:
    ``channel1 / channel0`` is the mean depth of the covered part of a footprint,
    never mixed with the background. ``ref`` (the object's anchor depth) makes
    depth relative, so that the same source serves every position (the depth
    model shifts all of an object's depths by the same amount).

    Parameters
    ----------
    depth : (H, W) float32
        Linear depth, ``+inf`` background.
    ref : float
        Reference depth subtracted from the object's depths.

    Returns
    -------
    (2, H, W) float32
        Coverage, then coverage times relative depth.
    """
    cov = np.isfinite(depth)
    out = np.zeros((2, *depth.shape), np.float32)
    out[0] = cov
    out[1][cov] = depth[cov] - ref
    return out


def add_planes(acc: np.ndarray, warped: tuple[tuple[int, int, int, int], np.ndarray], weight: float
           ) -> None:
    """``acc[:, roi] += weight * pixels`` for a ``(roi, pixels)`` pair (planes ``(2, h, w)``).

    Parameters
    ----------
    acc : (2, H, W) float32
        Accumulator, updated in place.
    warped : tuple
        ``((r0, r1, c0, c1), pixels (2, r1 - r0, c1 - c0) float32)``.
    weight : float
        Weight of ``pixels``.
    """
    (r0, r1, c0, c1), px = warped
    if px.size == 0:
        return
    for k in range(2):
        view = acc[k, r0:r1, c0:c1]  # rows strided, each row contiguous: a valid cv::Mat
        cv2.scaleAdd(px[k], float(weight), view, dst=view)


def warp_planes(src: np.ndarray, src_pts: np.ndarray, dst_pts: np.ndarray,
                 triangles: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``(2, H, W)``: the premultiplied planes of ``src`` warped from ``src_pts`` to
    ``dst_pts`` (0 outside).

    Parameters
    ----------
    src : (2, h, w) float32
        Premultiplied planes (:func:`depth_planes`).
    src_pts : (N, 2) float
        Control points in ``src``, pixels.
    dst_pts : (N, 2) float
        Their destinations, pixels.
    triangles : (M, 3) int
        The control mesh's triangles.
    shape : (H, W)
        Output size.

    Returns
    -------
    (2, H, W) float32
        The warped planes.
    """
    warper = MeshWarper(src_pts, triangles)
    out = np.zeros((2, *shape), np.float32)
    accumulate_warps([(warper.accumulation(dst_pts, shape), src,
                        warper.triangles_touching(src[0]), 1.0)], out)
    return out


def _finish_numpy(acc: np.ndarray, ref: float, out: np.ndarray, r0: int, r1: int, c0: int,
                  c1: int, clear: bool) -> None:
    cov, num = acc[0, r0:r1, c0:c1], acc[1, r0:r1, c0:c1]
    with np.errstate(divide="ignore", invalid="ignore"):
        out[r0:r1, c0:c1] = np.where(cov >= 0.5, num / cov + np.float32(ref), np.inf)
    if clear:
        acc[:, r0:r1, c0:c1] = 0.0


def _finish_loop(acc: np.ndarray, ref: float, out: np.ndarray, r0: int, r1: int, c0: int,
                 c1: int, clear: bool) -> None:
    for i in range(r0, r1):
        den_row = acc[0, i]
        num_row = acc[1, i]
        out_row = out[i]
        for j in range(c0, c1):
            den = den_row[j]
            out_row[j] = num_row[j] / den + ref if den >= 0.5 else np.inf
        if clear:
            den_row[c0:c1] = 0.0
            num_row[c0:c1] = 0.0


_finish_compiled = compile_kernel(_finish_loop)


def planes_to_depth(acc: np.ndarray, ref: float, roi: tuple[int, int, int, int] | None = None, *,
            clear: bool = False) -> np.ndarray:
    """Depth from premultiplied blended channels: ``cov * depth / cov + ref``, and
    ``+inf`` where the blended coverage is below 0.5 (one compiled pass); only
    over ``roi = (r0, r1, c0, c1)`` when given (``acc`` must be 0 elsewhere).
    ``clear``: set the ``acc`` it read back to 0 in the same pass.

    Parameters
    ----------
    acc : (2, H, W) float32
        Blended premultiplied planes.
    ref : float
        Reference depth added back.
    roi : (r0, r1, c0, c1), optional
        Region to convert (None: all).
    clear : bool
        Zero ``acc`` where read.

    Returns
    -------
    (H, W) float32
        Linear depth, ``+inf`` background.
    """
    h, w = acc.shape[1:]
    r0, r1, c0, c1 = (0, h, 0, w) if roi is None else roi
    out = np.full((h, w), np.inf, np.float32)
    if r1 > r0 and c1 > c0:
        kernel = _finish_compiled if use_compiled(_finish_compiled) else _finish_numpy
        kernel(acc, np.float32(ref), out, r0, r1, c0, c1, clear)
    return out
