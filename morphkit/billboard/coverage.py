"""Coverage of an in-between view from the reference views' depth: where the object is.

A view morph moves the pixels both references see along their correspondences,
but a part that only one reference sees (a flank that turns away, a leg that
passes behind the body) has no partner: its pixels move by the morph mesh's
interpolation and are cross-dissolved with the other view's background, so the
morph shows half-transparent lobes where the object is not, and thins it where
it is (Seitz & Dyer's morph assumes no occlusion changes). The asset has both
references' depth maps, so the object's outline in the in-between view is known
exactly up to sampling: every object pixel of either reference is a surface
point, and the in-between camera projects it.

:func:`splat_coverage` projects such points into a camera on a grid
``supersample`` times finer than its image (a sample sets the fine cell it
falls in), closes the gaps between the splats (a morphological closing, :func:`cv2.morphologyEx`, of
``close_px`` finer pixels: a surface seen at a grazing angle by a reference is
sampled sparsely in the in-between view) and area-averages back to the image:
coverage in ``[0, 1]``, with anti-aliased edges. Gaps narrower than
``close_px / supersample`` pixels between two parts are closed too; a surface
neither reference sees is missing (rare between neighbours of a ring 30-60
degrees apart). :meth:`~morphkit.billboard.BillboardAsset.morph` uses it as the
morph's alpha (``coverage=True``; ``docs/RESULTS.md`` has the gain).
"""

from __future__ import annotations

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array

__all__ = ["splat_coverage", "object_points"]


def object_points(camera: CameraModel, depth: np.ndarray) -> np.ndarray:
    """The surface points of a view's object pixels (finite, positive depth), ``(N, 3)`` float32.

    Parameters
    ----------
    camera : CameraModel
        The view's camera.
    depth : (H, W) float
        Its linear depth, background non-finite (``Renderer.depth``).

    Returns
    -------
    (N, 3) float32
        World (object-frame) points, one per object pixel, row-major order.
    """
    d = np.asarray(depth, dtype=np.float64)
    if d.shape != camera.shape:
        raise ValidationError(expected_got("depth", f"shape {camera.shape} (the camera's)",
                                           f"shape {d.shape}"))
    pts, valid = camera.unproject(np.where(np.isfinite(d) & (d > 0), d, np.inf))
    return np.ascontiguousarray(pts[valid], dtype=np.float32)


def splat_coverage(points: np.ndarray, camera: CameraModel, *, supersample: int = tol.BB_COVERAGE_SUPERSAMPLE,
                   close_px: int = tol.BB_COVERAGE_CLOSE_PX) -> np.ndarray:
    """Coverage ``(H, W)`` float32 in ``[0, 1]`` of ``points`` seen by ``camera`` (module notes).

    Parameters
    ----------
    points : (N, 3) float
        Surface samples, world frame, in front of the camera (``N`` may be 0).
    camera : CameraModel
        The view, images of ``camera.shape``.
    supersample : int
        Splat grid per image pixel and axis (>= 1; :data:`tol.BB_COVERAGE_SUPERSAMPLE`).
    close_px : int
        Side of the elliptic closing on the fine grid (>= 1; 1: no closing;
        :data:`tol.BB_COVERAGE_CLOSE_PX`).

    Returns
    -------
    (H, W) float32
        Fraction of each pixel covered, pixel-centre convention (:mod:`morphkit.conventions`).

    Examples
    --------
    A 2 x 2 square sampled densely, 5 units in front of a camera of focal length 40 px:
    1 unit is 8 px, so 16 x 16 pixels are covered, the rest is clear.

    >>> import numpy as np
    >>> from morphkit.camera import CameraModel, look_at
    >>> cam = CameraModel("perspective", (40, 40), 40.0, 40.0, 19.5, 19.5, 0.1, 10.0,
    ...                   look_at(np.array([0.0, 0, 5]), np.zeros(3), np.array([0.0, 1, 0])))
    >>> g = np.arange(-0.975, 1.0, 0.05)
    >>> x, y = np.meshgrid(g, g)
    >>> cov = splat_coverage(np.c_[x.ravel(), y.ravel(), np.zeros(x.size)], cam)
    >>> int((cov > 0.5).sum()), float(cov.max()), float(cov[:10].max())
    (256, 1.0, 0.0)
    """
    ss = int(supersample)
    k = int(close_px)
    if ss < 1:
        raise ValidationError(expected_got("supersample", "an int >= 1", supersample))
    if k < 1:
        raise ValidationError(expected_got("close_px", "an int >= 1", close_px))
    pts = as_finite_array(points, "points", shape=(None, 3))
    h, w = camera.shape
    fine = np.zeros((h * ss, w * ss), np.uint8)
    if len(pts):
        px, z = camera.project(pts[np.isfinite(pts).all(axis=1)])
        # pixel x covers [x - 0.5, x + 0.5) (pixel-centre origin): fine cell floor((x + 0.5) ss)
        q = np.floor((px + 0.5) * ss).astype(np.int64)
        ok = (z > 0) & (q[:, 0] >= 0) & (q[:, 0] < w * ss) & (q[:, 1] >= 0) & (q[:, 1] < h * ss)
        fine[q[ok, 1], q[ok, 0]] = 255
    if k > 1:
        fine = cv2.morphologyEx(fine, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
    cov = fine.astype(np.float32) * np.float32(1.0 / 255.0)
    return cov if ss == 1 else cv2.resize(cov, (w, h), interpolation=cv2.INTER_AREA)
