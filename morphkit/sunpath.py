"""The sun of a billboard scene: a day's path across the sky, and the bench's fixed test suns.

A sun is a :class:`~morphkit.scene.DirectionalLight` (world frame) whose direction
towards the light is ``d(a, e) = (cos e cos a, cos e sin a, sin e)`` -- the rule of
:func:`~morphkit.views.domecameras.direction`, with the sun's azimuth ``a``
(degrees counter-clockwise from world ``+x``) and elevation ``e`` above the horizon --
so the light travels along ``-d(a, e)``. A sun at or below the horizon (``e <= 0``)
adds no light, by the shading model (:mod:`morphkit.imaging.shading`, "Horizon"): such
frames show ambient light only.

* :class:`SunPath` -- a day: the azimuth sweeps evenly across ``azimuth_range``, the
  elevation rises as ``e(t) = r + (e_max - r) sin(pi t)`` (``r`` = ``rise_deg``)
  from ``r`` at sunrise (``t = 0``) to ``e_max`` at noon (``t = 1/2``) and back at
  sunset (``t = 1``). By default ``r > 0``: every frame of the day has a sun. With
  ``r < 0`` the first and last frames are below the horizon (no light) and the
  horizon is crossed at ``t = asin(-r / (e_max - r)) / pi`` and its mirror; with
  ``r = 0`` the end frames lie exactly on it (also no light).
* :func:`sun_directions_8` -- eight fixed suns for the relit bench, named, each
  relative to the viewer's azimuth so that "behind the billboard" means what it says.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import ValidationError, expected_got
from .scene import DirectionalLight
from .validate import as_finite_array, as_int, as_positive
from .views.domecameras import direction

__all__ = ["SunPath", "sun", "sun_directions_8", "SUN_INTENSITY", "TEST_SUNS", "DEFAULT_RISE_DEG"]

#: Default sun intensity (the :class:`~morphkit.scene.DirectionalLight` default).
SUN_INTENSITY = 3.0
#: The default day's elevation at sunrise and sunset, degrees: above the horizon, so every
#: frame of a day has a sun (and above the sun atlases' grazing cut-off,
#: :data:`morphkit.tol.SUN_MIN_ELEVATION_DEG`, so every frame's shadow is looked up as it is).
DEFAULT_RISE_DEG = 10.0


def sun(azimuth_deg: float, elevation_deg: float, intensity: float = SUN_INTENSITY) -> DirectionalLight:
    """The sun at ``(azimuth, elevation)`` (module docstring): the light travels along ``-d(a, e)``.

    Parameters
    ----------
    azimuth_deg : float
        Degrees counter-clockwise from world ``+x``, of the direction towards the sun.
    elevation_deg : float
        Degrees above the horizon (``<= 0``: below it, no light).
    intensity : float, optional
        Light intensity.

    Returns
    -------
    DirectionalLight
        World frame.

    Examples
    --------
    Straight above, the light travels straight down.

    >>> from morphkit.sunpath import sun
    >>> sun(0.0, 90.0).direction.round(12) + 0.0
    array([ 0.,  0., -1.])
    """
    a = as_finite_array([azimuth_deg, elevation_deg], "sun azimuth, elevation", shape=(2,))
    return DirectionalLight(-direction(a[0], a[1]), as_positive(intensity, "intensity"))


@dataclass(frozen=True)
class SunPath:
    """A day's sun (module docstring).

    Parameters
    ----------
    azimuth_range : (2,) float
        Sun azimuths at sunrise (``t = 0``) and sunset (``t = 1``), degrees (world).
    max_elevation : float
        Elevation at noon, degrees in ``(0, 90]``.
    rise_deg : float
        Elevation at sunrise and sunset, degrees in ``(-90, max_elevation]`` (default
        :data:`DEFAULT_RISE_DEG`, above the horizon; ``< 0``: the day starts and ends in
        the night, those frames unlit).
    intensity : float
        Light intensity.

    Examples
    --------
    The default day: 10 degrees up at both ends, 60 degrees at noon,
    ``10 + 50 sin(pi / 4)`` at ``t = 1/4``; a day from 5 degrees below the horizon:

    >>> from morphkit.sunpath import SunPath
    >>> path = SunPath()
    >>> [round(path.elevation_at(t), 6) for t in (0.0, 0.25, 0.5, 1.0)]
    [10.0, 45.355339, 60.0, 10.0]
    >>> [round(SunPath(rise_deg=-5.0).elevation_at(t), 6) for t in (0.0, 0.25, 0.5)]
    [-5.0, 40.961941, 60.0]
    >>> len(SunPath.day(5))
    5
    """

    azimuth_range: tuple[float, float] = (-90.0, 90.0)
    max_elevation: float = 60.0
    rise_deg: float = DEFAULT_RISE_DEG
    intensity: float = SUN_INTENSITY

    def __post_init__(self) -> None:
        az = as_finite_array(self.azimuth_range, "azimuth_range", shape=(2,))
        e = float(self.max_elevation)
        if not 0.0 < e <= 90.0:
            raise ValidationError(expected_got("max_elevation", "degrees in (0, 90]", self.max_elevation))
        r = float(self.rise_deg)
        if not -90.0 < r <= e:
            raise ValidationError(expected_got("rise_deg", f"degrees in (-90, max_elevation = {e:g}]",
                                               self.rise_deg))
        object.__setattr__(self, "azimuth_range", (float(az[0]), float(az[1])))
        object.__setattr__(self, "max_elevation", e)
        object.__setattr__(self, "rise_deg", r)
        object.__setattr__(self, "intensity", as_positive(self.intensity, "intensity"))

    @staticmethod
    def _t(t: float) -> float:
        tt = float(t)
        if not 0.0 <= tt <= 1.0:
            raise ValidationError(expected_got("t", "a number in [0, 1]", t))
        return tt

    def azimuth_at(self, t: float) -> float:
        """Sun azimuth at ``t``, degrees (linear across ``azimuth_range``).

        Parameters
        ----------
        t : float
            Time of day in ``[0, 1]``.

        Returns
        -------
        float
            Degrees, world frame.
        """
        a0, a1 = self.azimuth_range
        return a0 + self._t(t) * (a1 - a0)

    def elevation_at(self, t: float) -> float:
        """Sun elevation at ``t``, degrees: ``r + (e_max - r) sin(pi t)``, symmetric about noon
        (exactly ``r`` at both ends).

        Parameters
        ----------
        t : float
            Time of day in ``[0, 1]``.

        Returns
        -------
        float
            Degrees above the horizon.
        """
        tt = self._t(t)
        s = math.sin(math.pi * min(tt, 1.0 - tt))  # exactly 0 at both ends (sin(pi) is not)
        return self.rise_deg + (self.max_elevation - self.rise_deg) * s

    def sun_at(self, t: float) -> DirectionalLight:
        """The sun at ``t``.

        Parameters
        ----------
        t : float
            Time of day in ``[0, 1]``.

        Returns
        -------
        DirectionalLight
            World frame (below the horizon it lights nothing, :mod:`morphkit.imaging.shading`).
        """
        return sun(self.azimuth_at(t), self.elevation_at(t), self.intensity)

    def suns(self, frames: int) -> list[DirectionalLight]:
        """``frames`` suns at ``t = k / (frames - 1)`` (one frame: sunrise).

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.

        Returns
        -------
        list of DirectionalLight
            One per frame.
        """
        n = as_int(frames, "frames", lo=1)
        ts = np.linspace(0.0, 1.0, n) if n > 1 else np.zeros(1)
        return [self.sun_at(float(t)) for t in ts]

    @classmethod
    def day(cls, frames: int, *, azimuth_range: tuple[float, float] = (-90.0, 90.0),
            max_elevation: float = 60.0, rise_deg: float = DEFAULT_RISE_DEG,
            intensity: float = SUN_INTENSITY) -> list[DirectionalLight]:
        """The suns of ``frames`` frames of a day: ``SunPath(...).suns(frames)``.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.
        azimuth_range : (2,) float
            Sun azimuths at sunrise and sunset, degrees.
        max_elevation : float
            Elevation at noon, degrees.
        rise_deg : float
            Elevation at sunrise and sunset, degrees.
        intensity : float
            Light intensity.

        Returns
        -------
        list of DirectionalLight
            One per frame, world frame.
        """
        return cls(azimuth_range, max_elevation, rise_deg, intensity).suns(frames)


#: The eight test suns of :func:`sun_directions_8`: name -> (azimuth relative to the
#: viewer's, elevation), degrees.
TEST_SUNS: dict[str, tuple[float, float]] = {
    "front": (0.0, 35.0),        # behind the camera: the lit side faces the viewer
    "front_left": (60.0, 45.0),  # a three-quarter light
    "side": (90.0, 20.0),        # from the viewer's left, grazing the front
    "low": (-45.0, 5.0),         # a low sun, 5 degrees up, front right
    "behind": (180.0, 30.0),     # behind the billboard: the viewer sees the unlit side
    "behind_high": (150.0, 70.0),  # high and behind: mostly the tops lit
    "above": (0.0, 90.0),        # straight above (noon at the equator)
    "horizon": (-120.0, 0.0),    # exactly on the horizon: below it by the rule, ambient only
}


def sun_directions_8(view_azimuth_deg: float = 0.0, intensity: float = SUN_INTENSITY
                     ) -> dict[str, DirectionalLight]:
    """The relit bench's eight suns, by name (:data:`TEST_SUNS`).

    ``front`` is behind the camera (sun and eye on the same side, azimuth of the
    viewer); ``front_left`` a three-quarter light 60 degrees to the viewer's left;
    ``side`` from the left at 20 degrees; ``low`` 5 degrees above the horizon,
    45 degrees to the right; ``behind`` behind the billboard (the viewer's azimuth
    + 180) at 30 degrees; ``behind_high`` behind and 70 degrees up; ``above``
    straight above; ``horizon`` exactly on the horizon (elevation 0: counted below it,
    so it lights nothing and the frame is ambient only).

    Parameters
    ----------
    view_azimuth_deg : float, optional
        World azimuth from the billboards towards the viewer (e.g. a fixed bench
        camera's), degrees; the suns' azimuths are relative to it.
    intensity : float, optional
        Light intensity of every sun.

    Returns
    -------
    dict of str to DirectionalLight
        Eight suns, world frame, in the order of :data:`TEST_SUNS`.

    Examples
    --------
    >>> from morphkit.sunpath import sun_directions_8
    >>> suns = sun_directions_8()
    >>> list(suns)[:3], suns["behind"].direction.round(3) + 0.0
    (['front', 'front_left', 'side'], array([ 0.866,  0.   , -0.5  ]))
    """
    v = float(as_finite_array([view_azimuth_deg], "view_azimuth_deg", shape=(1,))[0])
    return {name: sun(v + a, e, intensity) for name, (a, e) in TEST_SUNS.items()}
