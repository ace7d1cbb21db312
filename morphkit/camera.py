"""Camera and light-view math: poses, intrinsics, projection, unprojection.

Pure numpy; no GL. Frames and pixel conventions are those of
:mod:`morphkit.conventions` (OpenCV camera frame, pixel-centre origin); the
OpenGL projection matrices here are the ones pyrender uses, so an image
rendered through :mod:`morphkit.render` with a :class:`CameraModel` has its
pixel ``(x, y)`` exactly where :meth:`CameraModel.project` puts it.

A light's view is a :class:`CameraModel` too: orthographic for a directional
light, perspective for a point/spot light.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from . import tol
from .conventions import BACKGROUND_DEPTH, CV_FROM_GL
from .errors import DegenerateViewError, ValidationError, expected_got
from .validate import as_finite_array, as_pose, as_positive, as_shape

__all__ = ["CameraModel", "look_at", "perspective", "orthographic"]

Projection = Literal["perspective", "orthographic"]


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray | None = None) -> np.ndarray:
    """Return ``cam_cv2world`` for a camera at ``eye`` looking at ``target``.

    The OpenCV camera frame is used: ``+z`` towards ``target``, ``+y`` (image
    down) is as close as possible to ``-up``. ``up`` defaults to world ``+z``,
    or ``+y`` when the view is (anti)parallel to ``+z``.

    Parameters
    ----------
    eye : (3,) float
        Camera centre, world frame.
    target : (3,) float
        Point looked at, world frame; must differ from ``eye``.
    up : (3,) float, optional
        World-frame up hint; see above for the default.

    Returns
    -------
    (4, 4) float64
        ``cam_cv2world`` pose (OpenCV camera frame, see :mod:`morphkit.conventions`).

    Raises
    ------
    ValidationError
        If ``eye`` equals ``target`` or a vector is not finite.

    Examples
    --------
    A camera at height 5 looking straight down: its optical axis (third
    column) is world ``-z`` and its centre (fourth column) is the eye.

    >>> import numpy as np
    >>> from morphkit.camera import look_at
    >>> pose = look_at(np.array([0.0, 0.0, 5.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
    >>> pose[:3, 2], pose[:3, 3]
    (array([ 0.,  0., -1.]), array([0., 0., 5.]))
    """
    eye = as_finite_array(eye, "eye", shape=(3,))
    target = as_finite_array(target, "target", shape=(3,))
    fwd = target - eye
    n = np.linalg.norm(fwd)
    if n < tol.MIN_EXTENT:
        raise ValidationError(expected_got("look_at", "eye != target", f"both at {eye.tolist()}"))
    fwd = fwd / n
    if up is None:
        up = np.array([0.0, 0.0, 1.0])
        if abs(fwd @ up) > 1 - tol.PARALLEL_DOT:
            up = np.array([0.0, 1.0, 0.0])
    up = as_finite_array(up, "up", shape=(3,))
    right = np.cross(fwd, up)
    if np.linalg.norm(right) < tol.REL_EQUAL:  # fwd is unit: |right| = |up| sin(angle)
        raise ValidationError(expected_got("up", "a vector not parallel to the view direction",
                                           up.tolist()))
    right /= np.linalg.norm(right)
    down = np.cross(fwd, right)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = right, down, fwd, eye
    return T


@dataclass(frozen=True)
class CameraModel:
    """A pinhole (perspective) or orthographic camera; also a light's view.

    Parameters
    ----------
    projection : {"perspective", "orthographic"}
    shape : (H, W)
        Image shape in pixels.
    fx, fy : float
        Perspective: focal lengths in pixels. Orthographic: pixels per scene
        unit along ``x`` and ``y``.
    cx, cy : float
        Principal point in pixels, pixel-centre convention (the image centre
        is ``((W - 1) / 2, (H - 1) / 2)``).
    znear, zfar : float
        Depth range along the viewing axis, ``0 < znear < zfar`` for both
        projections (to see closer, move the camera back).
    cam2world : (4, 4)
        ``cam_cv2world`` pose (OpenCV camera frame; see conventions).

    Notes
    -----
    Convention. Perspective: ``x = fx X / Z + cx``, ``y = fy Y / Z + cy``.
    Orthographic: ``x = fx X + cx``, ``y = fy Y + cy``.
    ``(X, Y, Z) = world2cam @ p`` and ``depth = Z``.
    """

    projection: Projection
    shape: tuple[int, int]
    fx: float
    fy: float
    cx: float
    cy: float
    znear: float
    zfar: float
    cam2world: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        if self.projection not in ("perspective", "orthographic"):
            raise ValidationError(expected_got("projection", "'perspective' or 'orthographic'",
                                               repr(self.projection)))
        object.__setattr__(self, "shape", as_shape(self.shape, "shape"))
        for name in ("fx", "fy"):
            object.__setattr__(self, name, as_positive(getattr(self, name), name))
        for name in ("cx", "cy"):
            v = float(getattr(self, name))
            if not np.isfinite(v):
                raise ValidationError(expected_got(name, "a finite number", v))
            object.__setattr__(self, name, v)
        zn = as_positive(self.znear, "znear")
        zf = as_positive(self.zfar, "zfar")
        if not zf > zn * (1 + tol.REL_EQUAL):
            raise ValidationError(expected_got("zfar", f"> znear ({zn})", zf))
        object.__setattr__(self, "znear", zn)
        object.__setattr__(self, "zfar", zf)
        pose = as_pose(self.cam2world, "cam2world")
        pose.setflags(write=False)
        object.__setattr__(self, "cam2world", pose)

    @classmethod
    def unchecked(cls, projection: Projection, shape: tuple[int, int], fx: float, fy: float,
                  cx: float, cy: float, znear: float, zfar: float, cam2world: np.ndarray
                  ) -> CameraModel:
        """A camera from values the caller has already validated, without checking them again.

        Same fields and types as the checked constructor leaves. For per-frame
        cameras derived from a validated one, such as
        :meth:`morphkit.shadow.rig.LightRig.camera_at`, which varies a validated
        camera's principal point and position every frame; anything else should
        use the constructor (or :func:`perspective`/:func:`orthographic`).

        Parameters
        ----------
        projection : {"perspective", "orthographic"}
            As in the class.
        shape : (H, W)
            Image shape in pixels.
        fx, fy : float
            Focal lengths (perspective) or pixels per scene unit (orthographic).
        cx, cy : float
            Principal point in pixels, pixel-centre convention.
        znear, zfar : float
            Depth range, ``0 < znear < zfar``.
        cam2world : (4, 4) float64
            ``cam_cv2world`` pose, world frame.

        Returns
        -------
        CameraModel
            The camera, built without validation.
        """
        cam = object.__new__(cls)
        pose = np.array(cam2world, dtype=np.float64)
        pose.setflags(write=False)
        for name, value in (("projection", projection), ("shape", (int(shape[0]), int(shape[1]))),
                            ("fx", float(fx)), ("fy", float(fy)), ("cx", float(cx)),
                            ("cy", float(cy)), ("znear", float(znear)), ("zfar", float(zfar)),
                            ("cam2world", pose)):
            object.__setattr__(cam, name, value)
        return cam

    # ------------------------------------------------------------------ frames
    @property
    def world2cam(self) -> np.ndarray:
        """``world2cam`` (OpenCV camera frame)."""
        return np.linalg.inv(self.cam2world)

    @property
    def position(self) -> np.ndarray:
        """Camera centre in world coordinates."""
        return self.cam2world[:3, 3].copy()

    @property
    def axis(self) -> np.ndarray:
        """Unit viewing direction (camera ``+z``) in world coordinates."""
        return self.cam2world[:3, 2].copy()

    @property
    def K(self) -> np.ndarray:
        """3x3 intrinsic matrix (for orthographic: the affine pixel scale)."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def with_pose(self, cam2world: np.ndarray) -> CameraModel:
        """The same intrinsics at another pose.

        Parameters
        ----------
        cam2world : (4, 4) float64
            New ``cam_cv2world`` pose, world frame.

        Returns
        -------
        CameraModel
            A copy with the same projection and intrinsics at ``cam2world``.
        """
        return CameraModel(self.projection, self.shape, self.fx, self.fy, self.cx, self.cy,
                           self.znear, self.zfar, cam2world)

    # -------------------------------------------------------------- projection
    def texture_matrix(self) -> np.ndarray:
        """4x4 projective-texture matrix ``T_pix_world``.

        For a homogeneous world point ``p``, ``q = T @ p`` gives pixel
        ``x = q[0] / q[3]``, ``y = q[1] / q[3]`` and linear depth ``q[2]``
        (not divided; for orthographic ``q[3] = 1``). This is the
        Segal et al. texture matrix with the NDC-to-texture step replaced by
        morphkit's pixel-centre pixel coordinates and linear depth.

        Returns
        -------
        (4, 4) float64
            ``T_pix_world``: world homogeneous points to (pixel x, pixel y, linear depth, w).

        References
        ----------
        .. [1] M. Segal, C. Korobkin, R. van Widenfelt, J. Foran and P. Haeberli, "Fast Shadows and
           Lighting Effects Using Texture Mapping", Computer Graphics (Proc. SIGGRAPH 92), 26(2), pp.
           249-252, 1992.
        """
        w2c = self.world2cam
        T = np.zeros((4, 4))
        if self.projection == "perspective":
            T[:2] = (self.K @ w2c[:3])[:2]
            T[2] = w2c[2]
            T[3] = w2c[2]
        else:
            T[:2] = (self.K @ np.vstack([w2c[:2], [0, 0, 0, 1]]))[:2]
            T[2] = w2c[2]
            T[3] = [0, 0, 0, 1]
        return T

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Project world points ``(N, 3)`` to pixels ``(N, 2)`` and depths ``(N,)``.


        Parameters
        ----------
        points : (N, 3) float
            Points, world frame.

        Returns
        -------
        pixels : (N, 2) float64
            Pixel coordinates ``(x, y)``, pixel-centre convention.
        depth : (N,) float64
            Linear depth ``Z`` in the camera frame.

        Raises
        ------
        DegenerateViewError
            If a perspective projection is asked for a point with ``Z <= 0``.

        Examples
        --------
        A 90-degree camera with a 5 x 5 image (``fx = 5 / (2 tan 45) = 2.5``,
        centre pixel ``(2, 2)``) at height 5 looking down: the origin lands on
        the centre pixel, and the point 1 unit along ``+x`` half a pixel to its
        right (``fx X / Z = 2.5 * 1 / 5``), both at depth 5.

        >>> import numpy as np
        >>> from morphkit.camera import look_at, perspective
        >>> pose = look_at(np.array([0.0, 0.0, 5.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
        >>> cam = perspective(np.pi / 2, (5, 5), pose)
        >>> cam.project(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
        (array([[2. , 2. ],
               [2.5, 2. ]]), array([5., 5.]))
        """
        pts = as_finite_array(points, "points", shape=(None, 3))
        q = self.texture_matrix() @ np.c_[pts, np.ones(len(pts))].T
        if self.projection == "perspective" and np.any(q[3] <= 0):
            n = int(np.count_nonzero(q[3] <= 0))
            raise DegenerateViewError(expected_got("points", "points in front of the camera (Z > 0)",
                                                   f"{n} at or behind it"))
        return (q[:2] / q[3]).T, q[2].copy()

    def pixel_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """Pixel-centre coordinates ``(x, y)``, each ``(H, W)`` float64.

        Returns
        -------
        x, y : (H, W) float64
            Column and row coordinates of each pixel centre.
        """
        h, w = self.shape
        return np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))

    def unproject(self, depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World points of a depth image.

        Parameters
        ----------
        depth : (H, W) float
            Linear depth; background pixels hold ``+inf`` (or any non-finite).

        Returns
        -------
        points : (H, W, 3) float64
            World positions; background pixels hold 0 (never NaN).
        valid : (H, W) bool
            True where ``depth`` is finite and positive.

        Examples
        --------
        The inverse of :meth:`project`: the same camera seeing the ground
        plane at depth 5 everywhere puts its centre pixel at the origin and
        the pixel 2 columns right of it at ``x = 2 * 5 / 2.5 = 4``; a pixel of
        infinite depth (background) is not valid.

        >>> import numpy as np
        >>> from morphkit.camera import look_at, perspective
        >>> pose = look_at(np.array([0.0, 0.0, 5.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
        >>> cam = perspective(np.pi / 2, (5, 5), pose)
        >>> depth = np.full((5, 5), 5.0)
        >>> depth[0, 0] = np.inf
        >>> points, valid = cam.unproject(depth)
        >>> points[2, 2], points[2, 4]
        (array([0., 0., 0.]), array([4., 0., 0.]))
        >>> int(valid.sum())
        24
        """
        depth = np.asarray(depth, dtype=np.float64)
        if depth.shape != self.shape:
            raise ValidationError(expected_got("depth", f"shape {self.shape}", f"shape {depth.shape}"))
        valid = np.isfinite(depth) & (depth > 0)
        z = np.where(valid, depth, 0.0)
        x, y = self.pixel_grid()
        X = (x - self.cx) / self.fx
        Y = (y - self.cy) / self.fy
        if self.projection == "perspective":
            X, Y = X * z, Y * z
        cam = np.stack([X, Y, z], axis=-1)
        world = cam @ self.cam2world[:3, :3].T + self.cam2world[:3, 3]
        world[~valid] = 0.0
        return world, valid

    def rays(self) -> tuple[np.ndarray, np.ndarray]:
        """Per-pixel ray origins and unit directions in world, each ``(H, W, 3)``.

        Returns
        -------
        origins : (H, W, 3) float64
            Ray origins, world frame (the camera centre for perspective; points on
            the image plane for orthographic).
        directions : (H, W, 3) float64
            Unit ray directions, world frame.
        """
        x, y = self.pixel_grid()
        X = (x - self.cx) / self.fx
        Y = (y - self.cy) / self.fy
        R, t = self.cam2world[:3, :3], self.cam2world[:3, 3]
        if self.projection == "perspective":
            d = np.stack([X, Y, np.ones_like(X)], -1) @ R.T
            d /= np.linalg.norm(d, axis=-1, keepdims=True)
            o = np.broadcast_to(t, d.shape).copy()
        else:
            o = np.stack([X, Y, np.zeros_like(X)], -1) @ R.T + t
            d = np.broadcast_to(R[:, 2], o.shape).copy()
        return o, d

    # ------------------------------------------------------------------- GL side
    def gl_projection(self) -> np.ndarray:
        """The 4x4 OpenGL projection matrix pyrender uses for this camera.

        Perspective equals ``pyrender.IntrinsicsCamera(fx, fy, cx + 0.5,
        cy + 0.5, znear, zfar)`` (pyrender's principal point is measured from the
        image *edge*); orthographic is the standard ``glOrtho`` matrix with
        half-extents ``W / (2 fx)`` and ``H / (2 fy)`` and a centred principal
        point (pyrender's OrthographicCamera cannot express ``fx != fy``, so
        :mod:`morphkit.render` passes this matrix to pyrender directly).

        Returns
        -------
        (4, 4) float64
            OpenGL projection matrix (GL camera frame to clip space).
        """
        h, w = self.shape
        n, f = self.znear, self.zfar
        P = np.zeros((4, 4))
        if self.projection == "perspective":
            P[0, 0] = 2 * self.fx / w
            P[1, 1] = 2 * self.fy / h
            P[0, 2] = 1 - 2 * (self.cx + 0.5) / w
            P[1, 2] = 2 * (self.cy + 0.5) / h - 1
            P[2, 2] = (f + n) / (n - f)
            P[2, 3] = 2 * f * n / (n - f)
            P[3, 2] = -1
        else:
            self._require_centred()
            P[0, 0] = 2 * self.fx / w
            P[1, 1] = 2 * self.fy / h
            P[2, 2] = 2 / (n - f)
            P[2, 3] = (f + n) / (n - f)
            P[3, 3] = 1
        return P

    def _require_centred(self) -> None:
        h, w = self.shape
        # the centre is computed, not measured: equal up to float64 rounding (REL_EQUAL of 1 px)
        if abs(self.cx - (w - 1) / 2) > tol.REL_EQUAL or abs(self.cy - (h - 1) / 2) > tol.REL_EQUAL:
            raise ValidationError(expected_got(
                "orthographic principal point", f"the image centre ({(w - 1) / 2}, {(h - 1) / 2})",
                f"({self.cx}, {self.cy}); shift the camera instead"))

    def linearize_window_depth(self, window: np.ndarray) -> np.ndarray:
        """Linear depth from OpenGL window depth ``w`` in ``[0, 1]``.

        Perspective: ``Z = 2 n f / (f + n - (2w - 1)(f - n))``.
        Orthographic: ``Z = n + w (f - n)``. Pixels with ``w >= 1`` (the far
        plane, i.e. nothing drawn) become :data:`BACKGROUND_DEPTH`.

        Parameters
        ----------
        window : (H, W) float
            OpenGL window depth in ``[0, 1]``.

        Returns
        -------
        (H, W) float64
            Linear depth ``Z`` along the viewing axis, ``BACKGROUND_DEPTH`` where nothing was drawn.
        """
        wd = np.asarray(window, dtype=np.float64)
        n, f = self.znear, self.zfar
        if self.projection == "perspective":
            z = 2 * n * f / (f + n - (2 * wd - 1) * (f - n))
        else:
            z = n + wd * (f - n)
        return np.where(wd >= 1.0, BACKGROUND_DEPTH, z).astype(np.float32)

    def gl_pose(self) -> np.ndarray:
        """``cam_gl2world``: the pose of this camera as a pyrender node.

        Returns
        -------
        (4, 4) float64
            ``cam_gl2world`` pose (OpenGL camera frame: ``+y`` up, looking down ``-z``), world frame.
        """
        return self.cam2world @ CV_FROM_GL

    def assert_outside(self, lo: np.ndarray, hi: np.ndarray, what: str = "object") -> None:
        """Raise :class:`DegenerateViewError` if the camera centre is inside an AABB.

        Parameters
        ----------
        lo, hi : (3,) float
            AABB corners, world frame.
        what : str, optional
            Name of the box used in the error message.

        Raises
        ------
        DegenerateViewError
            If the camera centre lies inside ``[lo, hi]``.
        """
        p = self.position
        margin = tol.CAMERA_CLEARANCE * float(np.max(hi - lo))
        if np.all(p > lo - margin) and np.all(p < hi + margin):
            raise DegenerateViewError(expected_got(
                "camera position", f"outside the {what}'s bounds {np.round(lo, 4).tolist()}.."
                f"{np.round(hi, 4).tolist()}", np.round(p, 4).tolist()))


def perspective(yfov: float, shape: tuple[int, int], cam2world: np.ndarray, *,
                znear: float = 0.05, zfar: float = 100.0) -> CameraModel:
    """A square-pixel pinhole camera with vertical field of view ``yfov`` (radians)
    and the principal point at the image centre.

    Parameters
    ----------
    yfov : float
        Vertical field of view in radians, in ``(0, pi)``.
    shape : (H, W)
        Image shape in pixels.
    cam2world : (4, 4) float64
        ``cam_cv2world`` pose, world frame.
    znear, zfar : float, optional
        Depth range, ``0 < znear < zfar``.

    Returns
    -------
    CameraModel
        A perspective camera.

    Examples
    --------
    The focal length is ``H / (2 tan(yfov / 2))``: 90 degrees over 480 rows
    gives 240 pixels; the principal point is the image centre.

    >>> import numpy as np
    >>> from morphkit.camera import perspective
    >>> cam = perspective(np.pi / 2, (480, 640), np.eye(4))
    >>> round(cam.fx, 9), cam.cx, cam.cy
    (240.0, 319.5, 239.5)
    """
    h, w = as_shape(shape, "shape")
    yfov = as_positive(yfov, "yfov")
    if yfov >= np.pi:
        raise ValidationError(expected_got("yfov", "an angle in (0, pi) radians", yfov))
    f = h / (2 * np.tan(yfov / 2))
    return CameraModel("perspective", (h, w), f, f, (w - 1) / 2, (h - 1) / 2, znear, zfar, cam2world)


def orthographic(half_width: float, half_height: float, shape: tuple[int, int],
                 cam2world: np.ndarray, *, znear: float, zfar: float) -> CameraModel:
    """An orthographic camera seeing ``[-half_width, half_width] x
    [-half_height, half_height]`` (scene units) of its image plane.

    Parameters
    ----------
    half_width, half_height : float
        Half extents of the visible image-plane window, scene units.
    shape : (H, W)
        Image shape in pixels.
    cam2world : (4, 4) float64
        ``cam_cv2world`` pose, world frame.
    znear, zfar : float
        Depth range along the viewing axis, ``0 < znear < zfar``.

    Returns
    -------
    CameraModel
        An orthographic camera.

    Examples
    --------
    A 4 x 4 light view of the square ``[-1, 1]^2`` from height 3: 2 pixels per
    unit (``fx = W / (2 half_width)``); a point is at ``fx X + cx`` whatever
    its depth.

    >>> import numpy as np
    >>> from morphkit.camera import look_at, orthographic
    >>> pose = look_at(np.array([0.0, 0.0, 3.0]), np.zeros(3), up=np.array([0.0, 1.0, 0.0]))
    >>> cam = orthographic(1.0, 1.0, (4, 4), pose, znear=1.0, zfar=5.0)
    >>> cam.fx
    2.0
    >>> cam.project(np.array([[0.5, 0.0, 0.0], [0.5, 0.0, 2.0]]))
    (array([[2.5, 1.5],
           [2.5, 1.5]]), array([3., 1.]))
    """
    h, w = as_shape(shape, "shape")
    hw = as_positive(half_width, "half_width")
    hh = as_positive(half_height, "half_height")
    return CameraModel("orthographic", (h, w), w / (2 * hw), h / (2 * hh), (w - 1) / 2, (h - 1) / 2,
                       znear, zfar, cam2world)
