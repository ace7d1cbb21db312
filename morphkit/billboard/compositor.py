"""The compositor: billboard images onto a frame, back to front, premultiplied "over".

Each billboard's image (premultiplied RGBA float32 in ``[0, 1]``) is warped by
its quad's homography with ``cv2.warpPerspective`` into its screen box only
(:func:`morphkit.composite.over_warped`) and composited over what is already
there, in the back-to-front order of the :class:`~.frame.FramePlan`; a quad cut
by the near plane is masked by its clipped polygon; distance fog blends its
colour towards the fog colour. The billboards accumulate in a transparent
*layer* (so its alpha is their coverage, used by the silhouette measures), and
:func:`finish` puts the layer over the backdrop: the same result as drawing
straight onto the backdrop (``over`` is associative), with the coverage kept.

Why OpenCV warps and not textured quads in pyrender: the OpenCV path touches
only each billboard's screen box, needs no GL context or texture upload per
changed image (a morphed image changes with the view), and keeps pyrender
behind :mod:`morphkit.render`.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..composite import over_warped
from .frame import Placement
from .frustum import unit_from_image

__all__ = ["new_layer", "polygon_mask", "draw", "finish"]


def new_layer(shape: tuple[int, int]) -> np.ndarray:
    """A transparent premultiplied RGBA layer, float32 ``(H, W, 4)`` of zeros.

    Parameters
    ----------
    shape : (H, W)
        Layer shape in pixels.

    Returns
    -------
    (H, W, 4) float32
        Zeros.
    """
    return np.zeros((int(shape[0]), int(shape[1]), 4), np.float32)


def polygon_mask(poly_px: np.ndarray, roi: tuple[int, int, int, int]) -> np.ndarray:
    """Float32 ``(r1 - r0, c1 - c0)`` mask: 1 at the pixel centres inside the convex polygon
    ``poly_px (K, 2)`` (screen pixels), 0 elsewhere (1/16-pixel vertex precision).

    Parameters
    ----------
    poly_px : (K, 2) float
        Convex polygon vertices ``(x, y)``, screen pixels.
    roi : (r0, r1, c0, c1)
        Screen box the mask covers (rows ``r0:r1``, columns ``c0:c1``).

    Returns
    -------
    (r1 - r0, c1 - c0) float32
        The mask, 0 or 1.
    """
    r0, r1, c0, c1 = roi
    mask = np.zeros((r1 - r0, c1 - c0), np.float32)
    pts = np.rint((np.asarray(poly_px, dtype=np.float64) - (c0, r0)) * 16).astype(np.int32)
    cv2.fillConvexPoly(mask, pts, 1.0, lineType=cv2.LINE_8, shift=4)
    return mask


def draw(layer: np.ndarray, placement: Placement, image: np.ndarray,
         fog_color: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
    """Composite one billboard's ``image`` over ``layer`` (in place) where ``placement`` puts it.

    Parameters
    ----------
    layer : (H, W, 4) float32
        Premultiplied frame layer.
    placement : Placement
        Where and how (homography, screen box, near-plane polygon, fog factor).
    image : (h, w, 4) float32
        The billboard's premultiplied image; any pyramid level (its shape fixes
        the homography).
    fog_color : RGB in [0, 1]
        The fog colour (used when ``placement.fog > 0``).
    """
    H_screen_img = placement.H_screen_unit @ unit_from_image(image.shape[:2])
    mask = None if placement.clip_px is None else polygon_mask(placement.clip_px, placement.roi)
    over_warped(layer, image, H_screen_img, placement.roi, mask=mask, fade=placement.fog,
                fade_color=fog_color)


def finish(layer: np.ndarray, backdrop: np.ndarray) -> np.ndarray:
    """The layer over an opaque backdrop, as uint8 RGB.

    Parameters
    ----------
    layer : (H, W, 4) float32
        Premultiplied RGB in ``[0, 1]`` and alpha.
    backdrop : (H, W, 3) float32
        RGB in ``[0, 1]``.

    Returns
    -------
    (H, W, 3) uint8
        ``round(255 (layer_rgb + (1 - alpha) backdrop))``, saturated.
    """
    out = backdrop * (1.0 - layer[:, :, 3:]) + layer[:, :, :3]
    return cv2.convertScaleAbs(out, alpha=255.0)
