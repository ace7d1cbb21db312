"""The object's range of motion and the light camera that follows it.

"Model only what a scene needs": a shadow map only has to see the occluder, so
its resolution is spent on the object, not on the whole range it moves over.
A :class:`LightRig` is a light camera of fixed orientation and fixed focal
length whose *window* follows the object:

* **Directional light** (orthographic): the camera translates with the object.
  The object's light-view image and depths are then *identical* at every
  position of the range (translation in any plane): one rendering is exact
  everywhere, and warping between samples is the identity.
* **Point light** (perspective, camera at the light): the camera stays at the
  light and keeps its orientation; its principal point shifts so that the
  object's anchor (its bounding-box centre) always projects to the image centre.
  The object's image changes shape with position (the light sees it from
  another side): that is what warping has to reproduce.

Depth model. Depth is the light camera's ``Z`` (OpenCV frame, see
:mod:`morphkit.conventions`). With a fixed camera orientation, translating the
object by ``d`` changes the depth of *every* one of its points by exactly
``axis . d`` (``axis`` = the camera's viewing direction): for a point light a
warped map's depth values are shifted by that amount; for a directional light
the camera moves with the object and depths do not change at all.

Moving light (Kang & Ihm 2.3.1). A point light moved by ``D`` (parallel to the
motion plane) casts the shadow of the object moved by ``-D``: the light map is
the map for object position ``t - D`` seen from a camera translated by ``D``
(:meth:`LightRig.camera_at` with ``light_offset``).

The sample grid and the moving light: Kang & Ihm [1]_.

References
----------
.. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
   (digest: ``docs/papers.md``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel, look_at
from ..errors import DegenerateViewError, OutOfRangeError, ValidationError, expected_got
from ..meshes import check_mesh
from ..scene import DirectionalLight, PointLight, translation
from ..validate import as_finite_array, as_int, as_pose, as_shape

__all__ = ["MotionRange", "LightRig", "sample_axis", "RangeClampWarning"]


class RangeClampWarning(UserWarning):
    """A position outside the baked range was clamped into it."""


@dataclass(frozen=True)
class MotionRange:
    """Object translations ``(x, y)`` in ``[lo, hi]`` (world units) on the plane
    ``z = const``; the object pose at ``(x, y)`` is ``translation(x, y, 0) @ base_pose``.

    Parameters
    ----------
    lo, hi : (2,) float
        Lower and upper corners ``(x, y)`` (world units); ``hi > lo`` on both axes.

    Examples
    --------
    >>> from morphkit.shadow import MotionRange
    >>> rng = MotionRange([-1.0, -1.0], [1.0, 2.0])
    >>> rng.center
    array([0. , 0.5])
    >>> rng.check([0.5, 3.0], clamp=True)
    array([0.5, 2. ])
    >>> rng.check([0.5, 3.0])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    morphkit.errors.OutOfRangeError: object position: expected inside the baked range ..., got [0.5, 3.0]
    """

    lo: np.ndarray
    hi: np.ndarray

    def __post_init__(self) -> None:
        lo = as_finite_array(self.lo, "range lo", shape=(2,))
        hi = as_finite_array(self.hi, "range hi", shape=(2,))
        if np.any(hi - lo <= tol.MIN_EXTENT):
            raise ValidationError(expected_got("motion range", "hi > lo on both axes",
                                               f"lo={lo.tolist()}, hi={hi.tolist()}"))
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)

    @property
    def center(self) -> np.ndarray:
        """The range's centre ``(x, y)``, float64 ``(2,)`` (world units, on the motion plane)."""
        return (self.lo + self.hi) / 2

    def check(self, xy: np.ndarray, *, clamp: bool = False) -> np.ndarray:
        """Return ``xy`` if it lies in the range (within a relative :data:`morphkit.tol.REL_EQUAL`), else
        clamp it (``clamp=True``) or raise :class:`OutOfRangeError`.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        clamp : bool
            Clamp instead of raising.

        Returns
        -------
        (2,) float64
            ``xy``, inside the range.
        """
        xy = as_finite_array(xy, "position", shape=(2,))
        eps = tol.REL_EQUAL * (self.hi - self.lo)
        if np.all(xy >= self.lo - eps) and np.all(xy <= self.hi + eps):
            return np.clip(xy, self.lo, self.hi)
        if clamp:
            return np.clip(xy, self.lo, self.hi)
        raise OutOfRangeError(expected_got(
            "object position", f"inside the baked range x in [{self.lo[0]:g}, {self.hi[0]:g}], "
            f"y in [{self.lo[1]:g}, {self.hi[1]:g}]", np.round(xy, 6).tolist()))

    def corners(self) -> np.ndarray:
        """The range's corners, float64 ``(4, 2)``: lower-left, lower-right, upper-left, upper-right.

        Returns
        -------
        (4, 2) float64
            The corners, world units.
        """
        return np.array([[self.lo[0], self.lo[1]], [self.hi[0], self.lo[1]],
                         [self.lo[0], self.hi[1]], [self.hi[0], self.hi[1]]])


def sample_axis(lo: float, hi: float, k: int, mid: float | None = None) -> np.ndarray:
    """``k`` sample coordinates on ``[lo, hi]``, ends included.

    For odd ``k >= 3`` the middle sample sits at ``mid`` (Kang & Ihm: "the
    position in line with the light"), clamped to the middle 80% of the range so
    no cell is degenerate; the others are spaced evenly on each side. Otherwise
    (even ``k``, or ``mid`` None) the samples are evenly spaced.

    Parameters
    ----------
    lo, hi : float
        The axis's ends (world units).
    k : int
        Number of samples (>= 2).
    mid : float, optional
        Where the middle sample should sit (odd ``k`` only).

    Returns
    -------
    (k,) float64
        Ascending sample coordinates.

    References
    ----------
    .. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
       (digest: ``docs/papers.md``).

    Examples
    --------
    Three samples on ``[0, 4]`` with the middle one in line with the light at
    1: the middle sample moves there; with ``mid`` at 0 it is clamped to the
    middle 80% of the range (0.4).

    >>> from morphkit.shadow.rig import sample_axis
    >>> sample_axis(0.0, 4.0, 3, mid=1.0)
    array([0., 1., 4.])
    >>> sample_axis(0.0, 4.0, 3, mid=0.0)
    array([0. , 0.4, 4. ])
    """
    try:
        k = as_int(k, "grid", lo=2)
    except ValidationError as exc:
        raise ValidationError(expected_got("grid", "k >= 2 samples per axis", repr(k)[:120])) from exc
    if mid is None or k % 2 == 0:
        return np.linspace(lo, hi, k)
    m = float(np.clip(mid, lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo)))
    h = (k - 1) // 2
    return np.concatenate([np.linspace(lo, m, h + 1)[:-1], np.linspace(m, hi, h + 1)])


class LightRig:
    """A light camera that follows an object over its :class:`MotionRange`.

    Parameters
    ----------
    light : DirectionalLight or PointLight
    mesh : trimesh.Trimesh
        The occluder, in its own frame.
    base_pose : (4, 4)
        ``object2world`` at translation ``(0, 0)``.
    motion : MotionRange
    shape : (H, W)
        Shadow-map shape.
    margin : float
        Relative margin around the object's image (fraction of the half size).
    """

    def __init__(self, light: DirectionalLight | PointLight, mesh: trimesh.Trimesh,
                 base_pose: np.ndarray, motion: MotionRange, shape: tuple[int, int], *,
                 margin: float = 0.04) -> None:
        if not isinstance(light, DirectionalLight | PointLight):
            raise ValidationError(expected_got("light", "a DirectionalLight or PointLight (sample an "
                                               "AreaLight into point lights)", type(light).__name__))
        mesh = check_mesh(mesh, "mesh")
        if not isinstance(motion, MotionRange):
            raise ValidationError(expected_got("motion", "a MotionRange", type(motion).__name__))
        self.light = light
        self.motion = motion
        self.shape = as_shape(shape, "shadow map shape")
        self.base_pose = as_pose(base_pose, "base_pose")
        hull = mesh.convex_hull.vertices if len(mesh.vertices) > 64 else mesh.vertices
        # object points in world at translation 0 (hull: the silhouette's extremes)
        self._pts0 = np.asarray(hull) @ self.base_pose[:3, :3].T + self.base_pose[:3, 3]
        lo, hi = mesh.bounds
        self.anchor0 = self.base_pose[:3, :3] @ ((lo + hi) / 2) + self.base_pose[:3, 3]
        h, w = self.shape
        if isinstance(light, DirectionalLight):
            self._fit_directional(margin)
        else:
            self._fit_point(margin)
        self.axis = self.R[:, 2].copy()

    # ------------------------------------------------------------------ fitting
    def _fit_directional(self, margin: float) -> None:
        h, w = self.shape
        self.R = look_at(np.zeros(3), self.light.direction)[:3, :3]
        rel = (self._pts0 - self.anchor0) @ self.R  # camera-frame offsets from the anchor
        half = np.maximum(np.abs(rel[:, :2]).max(0), tol.MIN_EXTENT) * (1 + margin)
        self.fx, self.fy = w / (2 * half[0]), h / (2 * half[1])
        radius = float(np.linalg.norm(rel, axis=1).max())
        self.back = 2 * radius + 1.0  # camera distance behind the anchor
        zs = rel[:, 2] + self.back
        pad = margin * (zs.max() - zs.min()) + tol.LIGHT_DEPTH_PAD
        self.znear, self.zfar = float(zs.min() - pad), float(zs.max() + pad)

    def _fit_point(self, margin: float) -> None:
        h, w = self.shape
        L = self.light.position
        c = self.anchor0 + np.r_[self.motion.center, 0.0]
        if np.linalg.norm(c - L) < tol.MIN_EXTENT:
            raise DegenerateViewError(expected_got("point light", "away from the object",
                                                   f"at the object's centre {L.tolist()}"))
        self.R = look_at(L, c)[:3, :3]
        # sample positions over the range: the image extents are extreme at the edges
        g = np.linspace(0, 1, 5)
        U, V = np.meshgrid(g, g)
        ts = self.motion.lo + np.c_[U.ravel(), V.ravel()] * (self.motion.hi - self.motion.lo)
        us, zs = [], []
        for t in ts:
            off = np.r_[t, 0.0]
            cam = (self._pts0 + off - L) @ self.R
            a = (self.anchor0 + off - L) @ self.R
            if np.any(cam[:, 2] <= tol.MIN_EXTENT) or a[2] <= tol.MIN_EXTENT:
                raise DegenerateViewError(expected_got(
                    "point light", "the object in front of the light over its whole range "
                    "(a light frustum < 180 deg)", f"object beside or behind the light at {t.tolist()}"))
            us.append(cam[:, :2] / cam[:, 2:] - a[:2] / a[2])
            zs.append(cam[:, 2])
        half = np.abs(np.concatenate(us)).max(0) * (1 + margin)
        if np.any(half > np.tan(np.deg2rad(80))):
            raise DegenerateViewError(expected_got(
                "point light", "the object within an 80 deg half-angle of its centre as seen "
                "from the light", f"half-angles {np.rad2deg(np.arctan(half)).round(1).tolist()} deg"))
        self.fx, self.fy = w / (2 * half[0]), h / (2 * half[1])
        self.back = None
        z = np.concatenate(zs)
        pad = margin * (z.max() - z.min()) + tol.LIGHT_DEPTH_PAD
        self.znear, self.zfar = float(max(z.min() - pad, 0.5 * z.min())), float(z.max() + pad)

    # ---------------------------------------------------------- persistence
    _PARAMS = ("R", "fx", "fy", "znear", "zfar", "anchor0", "base_pose", "back")

    def params(self) -> dict[str, object]:
        """JSON-able parameters that rebuild this rig with :meth:`from_params`.

        Returns
        -------
        dict
            ``shape``, ``lo``, ``hi`` and the fitted camera values (lists and floats).
        """
        out: dict[str, object] = {"shape": list(self.shape), "lo": self.motion.lo.tolist(),
                                  "hi": self.motion.hi.tolist()}
        for k in self._PARAMS:
            v = getattr(self, k, None)
            out[k] = np.asarray(v).tolist() if v is not None else None
        return out

    @classmethod
    def from_params(cls, light: DirectionalLight | PointLight, p: dict[str, object]) -> LightRig:
        """Rebuild a rig saved with :meth:`params` (no mesh needed).

        Parameters
        ----------
        light : DirectionalLight or PointLight
            The rig's light.
        p : dict
            What :meth:`params` returned.

        Returns
        -------
        LightRig
            The rig.
        """
        rig = cls.__new__(cls)
        rig.light = light
        rig.motion = MotionRange(np.array(p["lo"]), np.array(p["hi"]))
        rig.shape = as_shape(p["shape"], "shape")
        for k in cls._PARAMS:
            v = p.get(k)
            setattr(rig, k, None if v is None else (np.array(v) if isinstance(v, list) else float(v)))
        rig.axis = rig.R[:, 2].copy()
        return rig

    # --------------------------------------------------------------- cameras
    def object_pose(self, xy: np.ndarray) -> np.ndarray:
        """``object2world`` at translation ``xy``.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).

        Returns
        -------
        (4, 4) float64
            ``object2world``.
        """
        return translation(float(xy[0]), float(xy[1])) @ self.base_pose

    def camera_at(self, xy: np.ndarray, light_offset: np.ndarray | None = None) -> CameraModel:
        """The light camera for the object at ``xy`` (and, for a point light, the
        light moved by ``light_offset``, a 2-vector parallel to the motion plane).

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane (world units).

        Returns
        -------
        morphkit.camera.CameraModel
            Orthographic (directional light) or perspective (point light) camera of
            the rig's ``shape``.
        """
        xy = np.asarray(xy, dtype=np.float64)
        h, w = self.shape
        anchor = self.anchor0 + np.array([xy[0], xy[1], 0.0])
        pose = np.eye(4)
        pose[:3, :3] = self.R
        if isinstance(self.light, DirectionalLight):
            if light_offset is not None and np.any(np.asarray(light_offset) != 0):
                raise ValidationError(expected_got("light_offset", "none for a directional light "
                                                   "(translating it changes nothing)", light_offset))
            pose[:3, 3] = anchor - self.axis * self.back
            # the rig's own validated values (checked when it was fitted), per frame
            return CameraModel.unchecked("orthographic", (h, w), self.fx, self.fy, (w - 1) / 2,
                                        (h - 1) / 2, self.znear, self.zfar, pose)
        L = self.light.position.copy()
        if light_offset is not None:
            L[:2] += as_finite_array(light_offset, "light_offset", shape=(2,))
        pose[:3, 3] = L
        cx, cy = self._point_light_centre(anchor, L)
        return CameraModel.unchecked("perspective", (h, w), self.fx, self.fy, cx, cy, self.znear,
                                    self.zfar, pose)

    def principal_point(self, xy: np.ndarray) -> tuple[float, float]:
        """The principal point ``(cx, cy)`` of :meth:`camera_at` ``(xy)`` (the light
        unmoved), the same numbers, without building the camera (a reprojection's
        destination needs only these).

        Parameters
        ----------
        xy : (2,) float64
            Object translation (world units), already checked (e.g. by :meth:`resolve`).

        Returns
        -------
        (float, float)
            ``(cx, cy)``, pixels.
        """
        h, w = self.shape
        if isinstance(self.light, DirectionalLight):
            return (w - 1) / 2, (h - 1) / 2
        return self._point_light_centre(self.anchor0 + np.array([xy[0], xy[1], 0.0]),
                                        self.light.position)

    def _point_light_centre(self, anchor: np.ndarray, L: np.ndarray) -> tuple[float, float]:
        """The principal point of the light at ``L`` looking along the rig's axis with the
        object's anchor at ``anchor`` (world), checked to be in front of it."""
        h, w = self.shape
        a = (anchor - L) @ self.R
        cx = (w - 1) / 2 - self.fx * a[0] / a[2]
        cy = (h - 1) / 2 - self.fy * a[1] / a[2]
        # The object at xy seen from L + D is the object at xy - D seen from L, so
        # the depth range fitted over the motion range still holds (the caller
        # checks that xy - D lies in the range).
        if not (np.isfinite(cx) and np.isfinite(cy)):
            raise ValidationError(expected_got("object anchor", "in front of the point light",
                                               f"depth {a[2]:.3g} along its axis"))
        return float(cx), float(cy)

    def equivalent_position(self, xy: np.ndarray, light_offset: np.ndarray | None = None, *,
                            clamp: bool = False) -> np.ndarray:
        """The object position that, with the light unmoved, casts the same shadow:
        ``xy - light_offset`` (Kang & Ihm 2.3.1), checked against the range.

        Outside the range: :class:`~morphkit.errors.OutOfRangeError`, or with
        ``clamp=True`` the nearest position inside and a :class:`RangeClampWarning`.
        A light offset is only meaningful for a point light (a 2-vector parallel to
        the motion plane).

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane (world units).
        clamp : bool
            Clamp into the range instead of raising.

        Returns
        -------
        (2,) float64
            The equivalent position, inside the range.
        """
        xy = as_finite_array(xy, "position", shape=(2,))
        if light_offset is not None:
            off = as_finite_array(light_offset, "light_offset", shape=(2,))
            if isinstance(self.light, DirectionalLight) and np.any(off != 0):
                raise ValidationError(expected_got("light_offset", "none for a directional light "
                                                   "(translating it changes nothing)", off.tolist()))
            xy = xy - off
        inside = self.motion.check(xy, clamp=True)
        if not np.all(np.abs(inside - xy) <= tol.POSITION_EQUAL):  # np.allclose(rtol=0), without its overhead
            if not clamp:
                self.motion.check(xy)  # raises OutOfRangeError with the message
            warnings.warn(f"position {xy.tolist()} is outside the baked range; clamped to "
                          f"{inside.tolist()}", RangeClampWarning, stacklevel=3)
        return inside

    def resolve(self, xy: np.ndarray, light_offset: np.ndarray | None = None, *,
                clamp: bool = False) -> tuple[np.ndarray, np.ndarray, CameraModel]:
        """What every shadow method needs for one frame: the equivalent position
        (:meth:`equivalent_position`), the object's own position (``eq`` plus the
        light offset; differs from ``xy`` only when clamped) and the light camera.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        light_offset : (2,) float, optional
            Point-light displacement in the motion plane (world units).
        clamp : bool
            Clamp into the range instead of raising.

        Returns
        -------
        eq : (2,) float64
            The equivalent position.
        pos : (2,) float64
            The object's position.
        camera : morphkit.camera.CameraModel
            The light camera for ``pos`` and the moved light.
        """
        off = None if light_offset is None else np.asarray(light_offset, dtype=np.float64)
        eq = self.equivalent_position(xy, off, clamp=clamp)  # validates the offset
        pos = eq if off is None else eq + off
        return eq, pos, self.camera_at(pos, off)
