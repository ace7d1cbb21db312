"""Level of detail: which pyramid level of an asset's images a billboard needs on screen.

Level ``l`` of an asset holds its images at ``2^-l`` of the full resolution.
A billboard that covers ``p`` pixels of height on screen takes the smallest
image that is still at least ``p`` pixels high, i.e. ``l = floor(log2(h0 / p))``
clamped to the asset's levels: the warp then shrinks the image by less than
2x (bilinear sampling stays nearly alias free) and never enlarges it unless
even level 0 is smaller than the billboard.

The levels are a mip-map pyramid [1]_, chosen per billboard rather than per pixel.

References
----------
.. [1] L. Williams, "Pyramidal Parametrics", Computer Graphics (Proc. SIGGRAPH 83), 17(3), pp. 1-11,
   1983.
"""

from __future__ import annotations

import numpy as np

from ... import tol

__all__ = ["screen_height_px", "select_levels"]


def screen_height_px(fy: float, half_height: np.ndarray, depth: np.ndarray, znear: float) -> np.ndarray:
    """On-screen height in pixels of quads of half height ``half_height (N,)`` (scene units)
    whose centres lie at camera depth ``depth (N,)``: ``2 fy half_height / depth``; ``inf`` at
    or in front of the near plane (such a quad fills the view).

    Parameters
    ----------
    fy : float
        Vertical focal length, pixels.
    half_height : (N,) float
        Quad half heights, scene units.
    depth : (N,) float
        Camera depth ``Z`` of the quad centres, scene units.
    znear : float
        Near-plane depth.

    Returns
    -------
    (N,) float64
        On-screen heights, pixels.

    Examples
    --------
    Quads 1 unit high under ``fy = 500``: 250 pixels at depth 2, 50 at depth 10,
    and ``inf`` in front of the near plane.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.lod import screen_height_px
    >>> screen_height_px(500.0, np.array([0.5, 0.5, 0.5]), np.array([2.0, 10.0, 0.05]), 0.1)
    array([250.,  50.,  inf])
    """
    z = np.asarray(depth, dtype=np.float64)
    with np.errstate(divide="ignore"):
        return np.where(z > znear, 2.0 * fy * np.asarray(half_height) / np.maximum(z, znear), np.inf)


def select_levels(height_px: np.ndarray, base_height: int | np.ndarray,
                  levels: int | np.ndarray) -> np.ndarray:
    """Pyramid level per billboard, ``(N,)`` int64 in ``[0, levels - 1]``.

    Parameters
    ----------
    height_px : (N,) float
        On-screen heights (pixels, > 0; ``inf`` allowed).
    base_height : int or (N,) int
        Image height at level 0 (per billboard, or one for all).
    levels : int or (N,) int
        Levels the asset holds (>= 1; per billboard, or one for all).

    Returns
    -------
    (N,) int64
        ``clip(floor(log2(base_height / height_px)), 0, levels - 1)``.

    Examples
    --------
    Level-0 images 256 pixels high, 4 levels (256, 128, 64, 32): a billboard
    250 pixels high takes level 0, one 50 pixels high level 2 (64 pixels, the
    smallest still >= 50), one 10 pixels high the last level, 3.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.lod import select_levels
    >>> select_levels(np.array([250.0, 50.0, 10.0, np.inf]), 256, 4)
    array([0, 2, 3, 0])
    """
    p = np.maximum(np.asarray(height_px, dtype=np.float64), tol.ZERO)
    with np.errstate(divide="ignore"):  # inf heights: log2(0) = -inf, clipped to level 0
        lv = np.floor(np.log2(np.asarray(base_height, dtype=np.float64) / p))
    return np.clip(lv, 0, np.maximum(np.asarray(levels) - 1, 0)).astype(np.int64)
