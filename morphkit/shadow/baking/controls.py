"""Automatic control points of a shadow atlas: silhouette boxes, anchor depths, lifting to 3-D."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ...camera import CameraModel

__all__ = ["silhouette_box", "anchor_depths", "lift"]


def silhouette_box(depth: np.ndarray, margin: float = 0.06) -> tuple[float, float, float, float]:
    """``(x0, y0, x1, y1)``: the bounding box of a map's covered pixels, grown by
    ``margin`` of the map size (at least 2 px) and clipped to the map; the whole
    map when nothing is covered. Control grids span it: the warp's work and its
    resolution go where the shadow is.

    Parameters
    ----------
    depth : (H, W) float32
        Light-view linear depth, ``+inf`` background.
    margin : float
        Growth, a fraction of the map's width (x) and height (y).

    Returns
    -------
    tuple of float
        ``(x0, y0, x1, y1)`` in pixels.
    """
    h, w = depth.shape
    rows = np.flatnonzero(np.isfinite(depth).any(1))
    cols = np.flatnonzero(np.isfinite(depth).any(0))
    if len(rows) == 0:
        return 0.0, 0.0, float(w - 1), float(h - 1)
    mx, my = max(2.0, margin * w), max(2.0, margin * h)
    return (max(0.0, cols[0] - mx), max(0.0, rows[0] - my), min(w - 1.0, cols[-1] + mx),
            min(h - 1.0, rows[-1] + my))


def anchor_depths(depth: np.ndarray, pts: np.ndarray, grid: tuple[int, int], fallback: float,
                   smooth: float) -> np.ndarray:
    """Depths for surface anchors at grid points ``pts``: the map's depth extended
    beyond the silhouette by the nearest object depth (so the depth field, and
    with it the parallax of the control points, is continuous across the
    silhouette), blurred with a Gaussian of ``smooth`` grid spacings (so depth
    jumps inside the object, e.g. seat/legs, do not fold the mesh).

    Parameters
    ----------
    depth : (H, W) float32
        Light-view linear depth, ``+inf`` background.
    pts : (N, 2) float
        Grid points ``(x, y)``, pixels inside the map.
    grid : (rows, cols)
        The grid's layout (``N = rows * cols``).
    fallback : float
        Depth of every anchor when nothing is covered.
    smooth : float
        Blur, in grid spacings (0: none).

    Returns
    -------
    (N,) float64
        Light-view depths.
    """
    cov = np.isfinite(depth)
    if not cov.any():
        return np.full(len(pts), fallback)
    idx = ndimage.distance_transform_edt(~cov, return_distances=False, return_indices=True)
    filled = depth[idx[0], idx[1]]
    if smooth > 0:
        sx = smooth * np.ptp(pts[:, 0]) / max(grid[1] - 1, 1)
        sy = smooth * np.ptp(pts[:, 1]) / max(grid[0] - 1, 1)
        filled = ndimage.gaussian_filter(filled, (sy, sx), mode="nearest")
    return filled[np.rint(pts[:, 1]).astype(int), np.rint(pts[:, 0]).astype(int)].astype(np.float64)


def lift(cam: CameraModel, pts: np.ndarray, z: np.ndarray) -> np.ndarray:
    """World points at pixel ``pts`` and depth ``z`` of ``cam``.

    Parameters
    ----------
    cam : morphkit.camera.CameraModel
        The camera (perspective or orthographic).
    pts : (N, 2) float
        Pixel positions ``(x, y)``.
    z : (N,) float
        Depths along the camera axis.

    Returns
    -------
    (N, 3) float64
        Points, world frame.
    """
    X = (pts[:, 0] - cam.cx) / cam.fx
    Y = (pts[:, 1] - cam.cy) / cam.fy
    if cam.projection == "perspective":
        X, Y = X * z, Y * z
    return np.c_[X, Y, z] @ cam.cam2world[:3, :3].T + cam.cam2world[:3, 3]
