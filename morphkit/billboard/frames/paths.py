"""Camera paths through a billboard scene: the paper's pan, an orbit, a fly-through.

A path is an object (:class:`CameraPath`) giving a perspective
:class:`~morphkit.camera.CameraModel` for a parameter ``t`` in ``[0, 1]``, and
:meth:`CameraPath.cameras` samples it at ``frames`` evenly spaced ``t``
(``t = k / (frames - 1)``). Default image: 640 x 480 (``shape=(480, 640)``).
World frame of :mod:`morphkit.conventions` (``+z`` up, ground ``z = 0``);
headings are degrees counter-clockwise from ``+x``.

* :class:`PanPath` -- the paper's Fig. 6: the eye stays, the view of interest
  pans from left to right (heading from ``heading_deg + pan_deg / 2`` down to
  ``heading_deg - pan_deg / 2``).
* :class:`OrbitPath` -- the eye circles a centre at a fixed radius and height,
  looking at the centre (the temporal-stability measure steps it by 0.5 deg).
* :class:`FlyPath` -- the eye flies low along a line across the field, swaying
  sideways, looking ahead and a little down: billboards pass close by and
  through the near plane.
* :class:`FlyoverPath` -- the eye rises over the field: its elevation above the
  centre's horizontal plane goes evenly from ``start_elevation_deg`` (5) to
  ``end_elevation_deg`` (85) at a fixed distance from the centre, while it circles it
  (azimuth ``start_deg`` to ``end_deg``), looking at the centre.
* :class:`TopDownPan` -- the eye straight above the field at ``height``, looking straight
  down (optical axis ``-z``, image up along ``heading_deg``), moving from ``start`` to
  ``end``: the ground point under the eye is seen at 90 degrees of elevation.

:data:`PATHS` builds each with defaults fitted to a field of instances of half
size ``half_size`` (:func:`~.instances.place_random`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ...camera import CameraModel, look_at, perspective
from ...errors import ValidationError, expected_got
from ...validate import as_finite_array, as_int, as_positive, as_shape

__all__ = ["CameraPath", "PanPath", "OrbitPath", "FlyPath", "FlyoverPath", "TopDownPan", "PATHS", "make_path",
           "look_down_deg"]

DEFAULT_SHAPE = (480, 640)


@runtime_checkable
class CameraPath(Protocol):
    """A camera moving with a parameter ``t`` in ``[0, 1]``.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """The camera at ``t`` with images of ``shape (H, W)``.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        ...

    def cameras(self, frames: int, shape: tuple[int, int] = DEFAULT_SHAPE) -> list[CameraModel]:
        """``frames`` cameras at ``t = k / (frames - 1)``.

        Parameters
        ----------
        frames : int
            Number of cameras, >= 1.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        list of CameraModel
            Perspective cameras, world frame.
        """
        ...


def _check_frames(frames: int) -> int:
    return as_int(frames, "frames", lo=1)


def _ts(frames: int) -> np.ndarray:
    n = _check_frames(frames)
    return np.linspace(0.0, 1.0, n) if n > 1 else np.zeros(1)


@dataclass(frozen=True)
class _Lens:
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def camera(self, eye: np.ndarray, target: np.ndarray, shape: tuple[int, int]) -> CameraModel:
        return perspective(np.radians(self.yfov_deg), as_shape(shape, "shape"), look_at(eye, target),
                           znear=self.znear, zfar=self.zfar)


def _heading(deg: float, pitch_deg: float) -> np.ndarray:
    a, p = np.radians(deg), np.radians(pitch_deg)
    return np.array([np.cos(a) * np.cos(p), np.sin(a) * np.cos(p), -np.sin(p)])


class _SampledPath:
    """What the paths share: :meth:`cameras` samples :meth:`camera_at` evenly."""

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:  # pragma: no cover
        raise NotImplementedError

    def cameras(self, frames: int, shape: tuple[int, int] = DEFAULT_SHAPE) -> list[CameraModel]:
        """See :class:`CameraPath`.

        Parameters
        ----------
        frames : int
            Number of cameras, >= 1.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        list of CameraModel
            Perspective cameras, world frame.
        """
        return [self.camera_at(t, shape) for t in _ts(frames)]


@dataclass(frozen=True)
class PanPath(_SampledPath):
    """The eye at ``eye``; the heading pans from left to right across ``pan_deg``.

    Parameters
    ----------
    eye : (3,) float
        Eye position, world frame.
    heading_deg : float
        Heading of the middle of the pan.
    pan_deg : float
        Total sweep (left to right).
    pitch_deg : float
        Downward tilt of the view.
    yfov_deg, znear, zfar : float
        The lens.

    Examples
    --------
    Three frames of the default pan: the eye stays, the middle frame looks
    along the heading (90 degrees: world ``+y``) tilted 8 degrees down, the
    first 30 degrees to its left.

    >>> import numpy as np
    >>> from morphkit.billboard import PanPath
    >>> cams = PanPath().cameras(3, shape=(48, 64))
    >>> len(cams), cams[0].shape, cams[2].position
    (3, (48, 64), array([  0. , -12. ,   1.6]))
    >>> np.round(cams[1].axis, 3) + 0.0
    array([ 0.   ,  0.99 , -0.139])
    >>> round(float(np.degrees(np.arctan2(cams[0].axis[1], cams[0].axis[0]))), 6)
    120.0
    """

    eye: tuple[float, float, float] = (0.0, -12.0, 1.6)
    heading_deg: float = 90.0
    pan_deg: float = 60.0
    pitch_deg: float = 8.0
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """See :class:`CameraPath`.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        eye = as_finite_array(self.eye, "eye", shape=(3,))
        h = self.heading_deg + self.pan_deg * (0.5 - float(t))
        return _Lens(self.yfov_deg, self.znear, self.zfar).camera(eye, eye + _heading(h, self.pitch_deg),
                                                                  shape)

    @classmethod
    def over(cls, half_size: float) -> PanPath:
        """A pan from just outside the field's ``-y`` edge, at eye height, over the field.

        Parameters
        ----------
        half_size : float
            Half side of the square field, scene units.

        Returns
        -------
        PanPath
            The path.
        """
        hs = as_positive(half_size, "half_size")
        return cls(eye=(0.0, -hs - 2.0, 1.6))


@dataclass(frozen=True)
class OrbitPath(_SampledPath):
    """The eye on a circle of ``radius`` about ``centre``, at ``height``, looking at ``centre``.

    Parameters
    ----------
    centre : (3,) float
        What the camera looks at; the circle is about its vertical axis.
    radius, height : float
        Of the circle (height above the ground).
    start_deg, end_deg : float
        Azimuths of the eye at ``t = 0`` and ``t = 1`` (counter-clockwise from ``+x``).
    yfov_deg, znear, zfar : float
        The lens.
    """

    centre: tuple[float, float, float] = (0.0, 0.0, 0.5)
    radius: float = 10.0
    height: float = 2.0
    start_deg: float = -90.0
    end_deg: float = 90.0
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def camera_at_deg(self, azimuth_deg: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """The camera with its eye at ``azimuth_deg`` on the circle.

        Parameters
        ----------
        azimuth_deg : float
            Eye azimuth on the circle, degrees, world frame.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        c = as_finite_array(self.centre, "centre", shape=(3,))
        r = as_positive(self.radius, "radius")
        a = np.radians(azimuth_deg)
        eye = np.array([c[0] + r * np.cos(a), c[1] + r * np.sin(a), float(self.height)])
        return _Lens(self.yfov_deg, self.znear, self.zfar).camera(eye, c, shape)

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """See :class:`CameraPath`.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        return self.camera_at_deg(self.start_deg + float(t) * (self.end_deg - self.start_deg), shape)

    @classmethod
    def around(cls, half_size: float) -> OrbitPath:
        """Half a circle about the field's centre, just outside it.

        Parameters
        ----------
        half_size : float
            Half side of the square field, scene units.

        Returns
        -------
        OrbitPath
            The path.
        """
        hs = as_positive(half_size, "half_size")
        return cls(radius=hs * 1.25 + 3.0, height=1.5 + 0.15 * hs)


@dataclass(frozen=True)
class FlyPath(_SampledPath):
    """The eye flies from ``start`` to ``end`` (ground positions) at ``height``, swaying sideways.

    Parameters
    ----------
    start, end : (2,) float
        Ground positions at ``t = 0`` and ``t = 1``.
    height : float
        Eye height.
    sway : float
        Amplitude of a sideways sine (one period over the path), scene units.
    pitch_deg : float
        Downward tilt of the view.
    yfov_deg, znear, zfar : float
        The lens.
    """

    start: tuple[float, float] = (0.0, -12.0)
    end: tuple[float, float] = (0.0, 12.0)
    height: float = 0.9
    sway: float = 1.0
    pitch_deg: float = 5.0
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def _position(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        a = as_finite_array(self.start, "start", shape=(2,))
        b = as_finite_array(self.end, "end", shape=(2,))
        d = b - a
        n = float(np.linalg.norm(d))
        if n == 0:
            raise ValidationError(expected_got("fly path", "start != end", f"both at {a.tolist()}"))
        side = np.array([-d[1], d[0]]) / n
        w = 2 * np.pi * t
        pos = a + t * d + self.sway * np.sin(w) * side
        vel = d + self.sway * 2 * np.pi * np.cos(w) * side
        return pos, vel

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """See :class:`CameraPath`.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        pos, vel = self._position(float(t))
        eye = np.array([pos[0], pos[1], float(self.height)])
        heading = np.degrees(np.arctan2(vel[1], vel[0]))
        return _Lens(self.yfov_deg, self.znear, self.zfar).camera(
            eye, eye + _heading(heading, self.pitch_deg), shape)

    @classmethod
    def across(cls, half_size: float) -> FlyPath:
        """Across the field along ``+y``, from outside one edge to outside the other.

        Parameters
        ----------
        half_size : float
            Half side of the square field, scene units.

        Returns
        -------
        FlyPath
            The path.
        """
        hs = as_positive(half_size, "half_size")
        return cls(start=(0.3, -hs - 2.0), end=(0.3, hs + 2.0))


@dataclass(frozen=True)
class FlyoverPath(_SampledPath):
    """The eye rises from low to high over the field while circling its centre, looking at it.

    At ``t`` the eye is at ``centre + distance (cos e cos a, cos e sin a, sin e)`` with the
    elevation ``e`` and azimuth ``a`` linear in ``t`` from their start to their end values.

    Parameters
    ----------
    centre : (3,) float
        What the camera looks at.
    distance : float
        Eye distance from ``centre``.
    start_elevation_deg, end_elevation_deg : float
        Elevations of the eye above the centre's horizontal plane at ``t = 0`` and ``1``,
        degrees in ``[-89, 89]`` (straight above, the look-at is the top-down path's).
    start_deg, end_deg : float
        Azimuths of the eye at ``t = 0`` and ``1`` (counter-clockwise from ``+x``).
    yfov_deg, znear, zfar : float
        The lens.

    Examples
    --------
    The eye starts 5 degrees above the centre and ends 85 degrees above it.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.paths import FlyoverPath
    >>> cams = FlyoverPath(centre=(0.0, 0.0, 0.0)).cameras(2, shape=(48, 64))
    >>> [round(float(np.degrees(np.arcsin(c.position[2] / np.linalg.norm(c.position)))), 6)
    ...  for c in cams]
    [5.0, 85.0]
    """

    centre: tuple[float, float, float] = (0.0, 0.0, 0.5)
    distance: float = 12.0
    start_elevation_deg: float = 5.0
    end_elevation_deg: float = 85.0
    start_deg: float = -90.0
    end_deg: float = 0.0
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def elevation_at(self, t: float) -> float:
        """Elevation of the eye above the centre at ``t``, degrees.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.

        Returns
        -------
        float
            Degrees.
        """
        e0, e1 = float(self.start_elevation_deg), float(self.end_elevation_deg)
        for name, e in (("start_elevation_deg", e0), ("end_elevation_deg", e1)):
            if not -89.0 <= e <= 89.0:
                raise ValidationError(expected_got(name, "degrees in [-89, 89]", e))
        return e0 + float(t) * (e1 - e0)

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """See :class:`CameraPath`.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        c = as_finite_array(self.centre, "centre", shape=(3,))
        r = as_positive(self.distance, "distance")
        e = np.radians(self.elevation_at(t))
        a = np.radians(self.start_deg + float(t) * (self.end_deg - self.start_deg))
        eye = c + r * np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
        return _Lens(self.yfov_deg, self.znear, self.zfar).camera(eye, c, shape)

    @classmethod
    def around(cls, half_size: float) -> FlyoverPath:
        """A quarter circle about the field's centre, rising from 5 to 85 degrees, at the
        orbit's distance (:meth:`OrbitPath.around`).

        Parameters
        ----------
        half_size : float
            Half side of the square field, scene units.

        Returns
        -------
        FlyoverPath
            The path.
        """
        hs = as_positive(half_size, "half_size")
        return cls(distance=hs * 1.25 + 3.0)


@dataclass(frozen=True)
class TopDownPan(_SampledPath):
    """The eye straight above the ground at ``height``, looking straight down, moving from
    ``start`` to ``end``.

    Parameters
    ----------
    start, end : (2,) float
        Ground positions under the eye at ``t = 0`` and ``t = 1``.
    height : float
        Eye height above the ground.
    heading_deg : float
        World heading of the image's up direction (image ``-y``), degrees
        counter-clockwise from ``+x``.
    yfov_deg, znear, zfar : float
        The lens.

    Examples
    --------
    Half way, the eye is above the middle and looks straight down.

    >>> from morphkit.billboard.frames.paths import TopDownPan
    >>> cam = TopDownPan(start=(-4.0, 0.0), end=(4.0, 0.0), height=10.0).camera_at(0.5, (48, 64))
    >>> cam.position + 0.0, cam.axis.round(12) + 0.0
    (array([ 0.,  0., 10.]), array([ 0.,  0., -1.]))
    """

    start: tuple[float, float] = (0.0, -6.0)
    end: tuple[float, float] = (0.0, 6.0)
    height: float = 10.0
    heading_deg: float = 90.0
    yfov_deg: float = 50.0
    znear: float = 0.1
    zfar: float = 500.0

    def camera_at(self, t: float, shape: tuple[int, int] = DEFAULT_SHAPE) -> CameraModel:
        """See :class:`CameraPath`.

        Parameters
        ----------
        t : float
            Path parameter in ``[0, 1]``.
        shape : (H, W), optional
            Image shape in pixels.

        Returns
        -------
        CameraModel
            Perspective camera, world frame.
        """
        a = as_finite_array(self.start, "start", shape=(2,))
        b = as_finite_array(self.end, "end", shape=(2,))
        pos = a + float(t) * (b - a)
        eye = np.array([pos[0], pos[1], as_positive(self.height, "height")])
        h = np.radians(self.heading_deg)
        up = np.array([np.cos(h), np.sin(h), 0.0])
        return perspective(np.radians(self.yfov_deg), as_shape(shape, "shape"),
                           look_at(eye, eye - np.array([0.0, 0.0, 1.0]), up=up),
                           znear=self.znear, zfar=self.zfar)

    @classmethod
    def over(cls, half_size: float) -> TopDownPan:
        """Across the field along ``+y`` (image up along ``+y``), from above one edge to above
        the other, high enough that the view spans about the field's width.

        Parameters
        ----------
        half_size : float
            Half side of the square field, scene units.

        Returns
        -------
        TopDownPan
            The path.
        """
        hs = as_positive(half_size, "half_size")
        return cls(start=(0.0, -hs), end=(0.0, hs), height=max(4.0, 1.5 * hs))


#: Path builders by name, each taking the half size of the field of instances.
PATHS: dict[str, Callable[[float], CameraPath]] = {
    "pan": PanPath.over,
    "orbit": OrbitPath.around,
    "fly": FlyPath.across,
    "flyover": FlyoverPath.around,
    "topdown": TopDownPan.over,
}


def make_path(name: str, half_size: float) -> CameraPath:
    """The path ``name`` (a key of :data:`PATHS`) fitted to a field of half size ``half_size``.

    Parameters
    ----------
    name : str
        A key of ``PATHS``.
    half_size : float
        Half side of the square field, scene units.

    Returns
    -------
    CameraPath
        The path.

    Raises
    ------
    ValidationError
        An unknown name.
    """
    if name not in PATHS:
        raise ValidationError(expected_got("camera path", f"one of {sorted(PATHS)}", repr(name)))
    return PATHS[name](half_size)


def look_down_deg(cameras: Sequence[CameraModel]) -> np.ndarray:
    """How far each camera looks down: its optical axis's angle below the horizontal, degrees
    (0: level, 90: straight down; negative: looking up).

    Parameters
    ----------
    cameras : sequence of CameraModel
        World frame (``+z`` up).

    Returns
    -------
    (len(cameras),) float64
        Degrees in ``[-90, 90]``.

    Examples
    --------
    >>> from morphkit.billboard.frames.paths import look_down_deg, make_path
    >>> look_down_deg(make_path("topdown", 5.0).cameras(2)).round(6) + 0.0
    array([90., 90.])
    """
    axes = np.array([np.asarray(c.cam2world, np.float64)[:3, 2] for c in cameras]).reshape(-1, 3)
    return np.degrees(np.arcsin(np.clip(-axes[:, 2], -1.0, 1.0)))
