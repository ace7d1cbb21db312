"""What a camera sees of a billboard quad: frustum culling, near-plane clipping, the quad's homography.

* :func:`sphere_in_frustum` culls ``N`` bounding spheres against the six planes
  of a perspective camera in one numpy pass (conservative: a sphere touching the
  frustum is kept; the exact test is the clipped quad's screen box).
* :func:`clip_near` clips a convex polygon (camera frame) against the near plane
  ``Z = znear`` (Sutherland-Hodgman), so a quad cut by the near plane is drawn
  only where it lies in front of the camera -- projecting its corners behind the
  camera would flip them through the centre and draw it inverted.
* :func:`quad_homographies` gives ``H_screen_unit`` of many quads at once, the
  projective map from the unit square of a quad to the screen, exact for the
  part in front of the camera (the camera's projection of the quad's plane);
  :func:`unit_from_image` completes it to ``H_screen_img`` for an image shape.

Perspective cameras only (:class:`~morphkit.camera.CameraModel`); frames and
pixel conventions of :mod:`morphkit.conventions`.
"""

from __future__ import annotations

import numpy as np

from ...camera import CameraModel
from ...errors import ValidationError, expected_got

__all__ = ["require_perspective", "sphere_in_frustum", "clip_near", "quad_homographies", "unit_from_image",
           "screen_box"]


def require_perspective(camera: CameraModel) -> CameraModel:
    """Return ``camera`` if it is a perspective :class:`CameraModel`, else raise ValidationError.

    Parameters
    ----------
    camera : CameraModel
        Camera to check.

    Returns
    -------
    CameraModel
        ``camera``.

    Raises
    ------
    ValidationError
        If ``camera`` is not a perspective ``CameraModel``.
    """
    if not isinstance(camera, CameraModel) or camera.projection != "perspective":
        got = camera.projection if isinstance(camera, CameraModel) else type(camera).__name__
        raise ValidationError(expected_got("billboard camera", "a perspective CameraModel", got))
    return camera


def sphere_in_frustum(camera: CameraModel, world2cam: np.ndarray, centres: np.ndarray,
                      radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which spheres can be seen by ``camera``, and the depth of their centres.

    Parameters
    ----------
    camera : CameraModel
        Perspective camera.
    world2cam : (4, 4) float
        ``camera.world2cam`` (passed in so a frame inverts it once).
    centres : (N, 3) float
        Sphere centres, world frame.
    radii : (N,) float
        Sphere radii, scene units.

    Returns
    -------
    inside : (N,) bool
        The sphere meets the frustum (between the near and far planes, within the
        four side planes through the image's outer pixel edges).
    depth : (N,) float64
        ``Z`` of each centre in the camera frame.
    """
    h, w = camera.shape
    p = centres @ world2cam[:3, :3].T + world2cam[:3, 3]
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    r = np.asarray(radii, dtype=np.float64)
    inside = (z + r > camera.znear) & (z - r < camera.zfar)
    # side planes through the camera centre and the image's outer edges x = -0.5, w - 0.5
    for coord, lo_px, hi_px, c, f in ((x, -0.5, w - 0.5, camera.cx, camera.fx),
                                      (y, -0.5, h - 0.5, camera.cy, camera.fy)):
        a_lo, a_hi = (lo_px - c) / f, (hi_px - c) / f
        inside &= (coord - a_lo * z) / np.hypot(1.0, a_lo) >= -r
        inside &= (a_hi * z - coord) / np.hypot(1.0, a_hi) >= -r
    return inside, z


def clip_near(poly_cam: np.ndarray, znear: float) -> np.ndarray:
    """Clip a convex polygon (camera frame) to the half space ``Z >= znear``.

    Parameters
    ----------
    poly_cam : (M, 3) float
        Vertices in order (camera frame).
    znear : float
        The near plane's depth.

    Returns
    -------
    (K, 3) float64
        The clipped polygon's vertices in the same order; ``K = 0`` when the
        whole polygon lies behind the near plane, ``K <= M + 1``.

    References
    ----------
    .. [1] I. E. Sutherland and G. W. Hodgman, "Reentrant Polygon Clipping", Communications of the ACM,
       17(1), pp. 32-42, 1974.

    Examples
    --------
    A square tilted through the near plane ``Z = 1`` (its lower edge at
    ``Z = -1``, its upper at ``Z = 3``) is cut halfway up, at ``Y = 0``:

    >>> import numpy as np
    >>> from morphkit.billboard.frames.frustum import clip_near
    >>> square = np.array([[-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, 3.0], [-1.0, 1.0, 3.0]])
    >>> clip_near(square, 1.0)
    array([[ 1.,  0.,  1.],
           [ 1.,  1.,  3.],
           [-1.,  1.,  3.],
           [-1.,  0.,  1.]])
    """
    pts = np.asarray(poly_cam, dtype=np.float64)
    out: list[np.ndarray] = []
    m = len(pts)
    for k in range(m):
        a, b = pts[k], pts[(k + 1) % m]
        ina, inb = a[2] >= znear, b[2] >= znear
        if ina:
            out.append(a)
        if ina != inb:
            t = (znear - a[2]) / (b[2] - a[2])
            q = a + t * (b - a)
            q[2] = znear  # exactly on the plane despite rounding
            out.append(q)
    return np.array(out, dtype=np.float64).reshape(-1, 3)


def quad_homographies(camera: CameraModel, world2cam: np.ndarray, corner_tl: np.ndarray,
                      right: np.ndarray, up: np.ndarray, half_w: np.ndarray, half_h: np.ndarray
                      ) -> np.ndarray:
    """``H_screen_unit`` of ``M`` quads: the unit square to homogeneous screen pixels.

    The quad's point at ``(a, b)`` in ``[0, 1]^2`` is ``corner_tl + 2 a half_w right
    - 2 b half_h up`` (``a`` along the image's ``+x``, ``b`` along its ``+y``, from the
    top-left outer corner). :func:`unit_from_image` turns it into ``H_screen_img``.

    Parameters
    ----------
    camera : CameraModel
        Perspective camera.
    world2cam : (4, 4) float
        ``camera.world2cam``.
    corner_tl : (M, 3) float
        World position of each quad's top-left corner.
    right, up : (M, 3) float
        Unit quad axes, world frame.
    half_w, half_h : (M,) float
        Quad half sizes, scene units.

    Returns
    -------
    (M, 3, 3) float64
        ``H_screen_unit``; exact (the camera's projection of the quad's plane)
        where the quad is in front of the camera.
    """
    A = np.empty((len(corner_tl), 3, 3))
    A[:, :, 0] = (2.0 * np.asarray(half_w))[:, None] * right
    A[:, :, 1] = (-2.0 * np.asarray(half_h))[:, None] * up
    A[:, :, 2] = corner_tl
    cam = np.einsum("ij,mjk->mik", world2cam[:3, :3], A)
    cam[:, :, 2] += world2cam[:3, 3]
    return np.einsum("ij,mjk->mik", camera.K, cam)


def unit_from_image(shape: tuple[int, int]) -> np.ndarray:
    """``H_unit_img`` (3, 3): an image of ``shape (h, w)`` onto the unit square, its outer
    edges ``[-0.5, w - 0.5] x [-0.5, h - 0.5]`` (pixel-centre convention) to ``[0, 1]^2``.

    Parameters
    ----------
    shape : (h, w)
        Image shape in pixels.

    Returns
    -------
    (3, 3) float64
        ``H_unit_img``.
    """
    h, w = shape
    return np.array([[1.0 / w, 0.0, 0.5 / w], [0.0, 1.0 / h, 0.5 / h], [0.0, 0.0, 1.0]])


def screen_box(points_px: np.ndarray, shape: tuple[int, int]) -> tuple[int, int, int, int] | None:
    """Rows ``r0:r1`` and columns ``c0:c1`` of the pixels whose centres may lie in a
    polygon with vertices ``points_px (K, 2)`` (its bounding box, grown to whole pixels and
    cut to the image ``shape``); None when it misses the image.

    Parameters
    ----------
    points_px : (K, 2) float
        Polygon vertices ``(x, y)``, screen pixels.
    shape : (H, W)
        Screen shape in pixels.

    Returns
    -------
    (r0, r1, c0, c1) or None
        The box, or None when it misses the image.
    """
    h, w = shape
    lo = np.floor(points_px.min(axis=0))
    hi = np.ceil(points_px.max(axis=0)) + 1
    c0, r0 = int(max(lo[0], 0)), int(max(lo[1], 0))
    c1, r1 = int(min(hi[0], w)), int(min(hi[1], h))
    if c1 <= c0 or r1 <= r0:
        return None
    return r0, r1, c0, c1
