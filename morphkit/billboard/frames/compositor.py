"""The compositor: billboard images onto a frame, back to front, premultiplied "over".

Each billboard's image (premultiplied RGBA float32 in ``[0, 1]``) is warped by
its quad's homography with ``cv2.warpPerspective`` into its screen box only
(:func:`morphkit.imaging.composite.over_warped`) and composited over what is already
there, in the back-to-front order of the :class:`~.frametypes.FramePlan`; a quad cut
by the near plane is masked by its clipped polygon; distance fog blends its
colour towards the fog colour. The billboards accumulate in a transparent
*layer* (so its alpha is their coverage, used by the silhouette measures), and
:func:`finish` puts the layer over the backdrop: the same result as drawing
straight onto the backdrop (``over`` is associative), with the coverage kept.

**Depth.** A billboard whose asset carries depth (a relightable dome or impostor
surface) is composited per pixel: the frame keeps a depth buffer (:func:`new_depth`,
the camera depth ``Z`` of the nearest billboard pixel drawn so far whose alpha
reaches :data:`~morphkit.tol.BB_DEPTH_OPAQUE_ALPHA`), each of its pixels has its own
camera depth (:func:`surface_depth`, from its surface's depth and the instance's
pose), and a pixel behind what the buffer holds goes *under* it (Porter & Duff's
"under", ``dst + (1 - dst_alpha) src``) instead of over. Billboards still come back
to front, so an image without depth (a ring morph) lies in its quad's plane at its
pivot's depth and keeps the plain "over" of the back-to-front order; where two
overlapping objects interpenetrate or their pivots' order is not their pixels', the
nearer surface wins pixel by pixel.

Why OpenCV warps and not textured quads in pyrender: the OpenCV path touches
only each billboard's screen box, needs no GL context or texture upload per
changed image (a morphed image changes with the view), and keeps pyrender
behind :mod:`morphkit.render`.
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np

from ... import tol
from ...camera import CameraModel
from ...imaging.composite import box_from, over_warped, warped_part
from .frametypes import Placement
from .frustum import unit_from_image

__all__ = ["new_layer", "new_depth", "surface_depth", "entangled", "polygon_mask", "draw", "finish"]


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


def new_depth(shape: tuple[int, int]) -> np.ndarray:
    """An empty depth buffer (module docstring, "Depth"): float32 ``(H, W)`` of ``+inf``.

    Parameters
    ----------
    shape : (H, W)
        Frame shape in pixels.

    Returns
    -------
    (H, W) float32
        ``+inf`` everywhere (nothing drawn).
    """
    return np.full((int(shape[0]), int(shape[1])), np.inf, np.float32)


def surface_depth(view: CameraModel, depth: np.ndarray, object2world: np.ndarray,
                  camera: CameraModel) -> np.ndarray:
    """The frame camera's depth ``Z`` of each pixel of a billboard's surface.

    Each pixel's point (as ``view.unproject(depth)``, object frame) is carried to the world by
    the instance's pose and into ``camera``; pixels with nothing drawn take the least depth
    of their 3 x 3 neighbours (so that the warp's anti-aliased rim has its surface's depth),
    ``+inf`` further out.

    Parameters
    ----------
    view : CameraModel
        The surface's camera, object frame (:meth:`SurfaceSource.camera
        <morphkit.billboard.protocols.SurfaceSource.camera>`).
    depth : (h, w) float
        The surface's depth along ``view``'s axis, ``+inf`` where nothing is drawn.
    object2world : (4, 4) float
        The instance's pose.
    camera : CameraModel
        The frame's camera, world frame.

    Returns
    -------
    (h, w) float32
        Camera depth of each pixel, scene units.

    Examples
    --------
    A surface seen head-on at depth 2 by its own camera, the instance and the frame camera
    at the origin of the world: every drawn pixel is at depth 2, its rim too.

    >>> import numpy as np
    >>> from morphkit.camera import look_at, perspective
    >>> from morphkit.billboard.frames.compositor import surface_depth
    >>> cam = perspective(np.pi / 2, (5, 5), look_at(np.zeros(3), np.array([0.0, 0.0, -1.0]),
    ...                                              up=np.array([0.0, 1.0, 0.0])))
    >>> d = np.full((5, 5), np.inf)
    >>> d[2, 2] = 2.0
    >>> z = surface_depth(cam, d, np.eye(4), cam)
    >>> float(z[2, 2]), float(z[1, 1]), float(z[0, 0])
    (2.0, 2.0, inf)
    """
    d = np.asarray(depth, np.float32)
    h, w = d.shape
    valid = np.isfinite(d) & (d > 0)
    # a pixel's point in the view's frame is (X d, Y d, d) (perspective) or (X, Y, d); the frame
    # camera's depth is one row of world2cam @ object2world @ view.cam2world applied to it
    row = (np.asarray(camera.world2cam, np.float64) @ np.asarray(object2world, np.float64)
           @ np.asarray(view.cam2world, np.float64))[2]
    X = ((np.arange(w) - view.cx) / view.fx)[None, :]
    Y = ((np.arange(h) - view.cy) / view.fy)[:, None]
    dd = np.where(valid, d, 0.0)
    if view.projection == "perspective":
        z = dd * (row[0] * X + row[1] * Y + row[2]) + row[3]
    else:
        z = row[0] * X + row[1] * Y + row[2] * dd + row[3]
    z = np.where(valid, z, np.inf).astype(np.float32)
    rim = cv2.erode(z, np.ones((3, 3), np.uint8), borderType=cv2.BORDER_CONSTANT, borderValue=np.inf)
    return np.where(valid, z, rim)


def entangled(placements: Sequence[Placement], radii: np.ndarray) -> np.ndarray:
    """Which billboards need the depth test: those whose screen box meets another's while
    their depth ranges (the pivot's depth ``+-`` the object's radius) overlap. For any other
    pair the back-to-front order is already each pixel's order, so the plain "over" is exact
    (module docstring, "Depth").

    Parameters
    ----------
    placements : sequence of Placement
        The frame's billboards.
    radii : (N,) float
        Each one's object radius about its pivot, scene units (a bound: the quad's half size).

    Returns
    -------
    (N,) bool
        True for the billboards to composite by depth.
    """
    n = len(placements)
    out = np.zeros(n, bool)
    if n < 2:
        return out
    z = np.array([p.depth for p in placements], np.float64)
    r = np.asarray(radii, np.float64).reshape(n)
    box = np.array([p.roi for p in placements], np.int64)  # r0, r1, c0, c1
    order = np.argsort(z - r, kind="stable")
    lo = (z - r)[order]
    for a, i in enumerate(order):  # the ranges starting before i's ends
        top = int(np.searchsorted(lo, z[i] + r[i], side="left"))
        js = order[a + 1:top]
        if len(js) == 0:
            continue
        meet = ((box[js, 0] < box[i, 1]) & (box[i, 0] < box[js, 1]) & (box[js, 2] < box[i, 3])
                & (box[i, 2] < box[js, 3]))
        if meet.any():
            out[i] = True
            out[js[meet]] = True
    return out


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
         fog_color: tuple[float, float, float] = (0.0, 0.0, 0.0), *, zbuf: np.ndarray | None = None,
         depth: np.ndarray | None = None) -> None:
    """Composite one billboard's ``image`` into ``layer`` (in place) where ``placement`` puts it.

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
    zbuf : (H, W) float32, optional
        The frame's depth buffer (:func:`new_depth`; module docstring, "Depth"), updated in
        place. Without it the image goes over the layer.
    depth : (h, w) float32, optional
        With ``zbuf``: the camera depth of each pixel of ``image`` (:func:`surface_depth`);
        default the pivot's depth (``placement.depth``) everywhere.
    """
    H_screen_img = placement.H_screen_unit @ unit_from_image(image.shape[:2])
    mask = None if placement.clip_px is None else polygon_mask(placement.clip_px, placement.roi)
    if zbuf is None:
        over_warped(layer, image, H_screen_img, placement.roi, mask=mask, fade=placement.fog,
                    fade_color=fog_color)
        return
    r0, r1, c0, c1 = placement.roi
    part = warped_part(image, H_screen_img, placement.roi, mask=mask, fade=placement.fog,
                       fade_color=fog_color)
    if depth is None:
        d = np.full((r1 - r0, c1 - c0), placement.depth, np.float32)
        farthest = placement.depth
    else:
        src = np.asarray(depth, np.float32)
        d = cv2.warpPerspective(src, box_from(placement.roi) @ H_screen_img, (c1 - c0, r1 - r0),
                                flags=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=np.inf)
        drawn = src[src < np.inf]
        farthest = float(drawn.max()) if drawn.size else -np.inf
    view, zv = layer[r0:r1, c0:c1], zbuf[r0:r1, c0:c1]
    k = np.float32(1.0 + tol.BB_DEPTH_REL)
    behind = None
    if farthest > float(zv.min()) * k:  # some pixel may lie behind: a drawn one (finite depth) beyond
        behind = (d > zv * k) & (d < np.inf)
    if behind is not None and behind.any():  # "under" there (the layer's alpha on the part), "over" elsewhere
        b = behind[:, :, None]
        one = np.float32(1.0)
        view *= np.where(b, one, one - part[:, :, 3:])
        part *= np.where(b, one - view[:, :, 3:], one)
    else:
        view *= 1.0 - part[:, :, 3:]
    view += part
    near = part[:, :, 3] >= tol.BB_DEPTH_OPAQUE_ALPHA
    near &= d < zv
    np.copyto(zv, d, where=near)


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
