"""Images for people to look at: colour maps of data that is not an image."""

from __future__ import annotations

import cv2
import numpy as np

from .. import tol

__all__ = ["colorize_depth"]


def colorize_depth(depth: np.ndarray) -> np.ndarray:
    """An RGB colour-mapped depth image (viridis, near bright), background black.

    Parameters
    ----------
    depth : (H, W) float
        Linear depth, ``+inf`` (non-finite) background.

    Returns
    -------
    (H, W, 3) uint8
        RGB image (:mod:`morphkit.conventions`).
    """
    fg = np.isfinite(depth)
    out = np.zeros((*depth.shape, 3), np.uint8)
    if fg.any():
        d = depth[fg]
        t = (d - d.min()) / max(float(d.max() - d.min()), tol.ZERO)
        g = np.zeros(depth.shape, np.uint8)
        g[fg] = np.clip(255 - 200 * t, 0, 255).astype(np.uint8)
        out = cv2.cvtColor(cv2.applyColorMap(g, cv2.COLORMAP_VIRIDIS), cv2.COLOR_BGR2RGB)  # OpenCV's is BGR
        out[~fg] = 0
    return out
