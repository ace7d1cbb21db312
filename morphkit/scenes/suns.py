"""A scene's sun: the bake light, a fixed sun, or a day's sun.

Each is a :class:`SceneSun`: :meth:`SceneSun.suns` gives one sun per frame, or None for the
light the assets were baked under (ring assets can show only that one; relightable dome assets
any). A scene file writes the sun as (:func:`sun_from_json` reads it back):

* ``null`` -- the bake light;
* ``{"azimuth_deg": A, "elevation_deg": E}`` -- a sun standing still (a glTF scene's light);
* ``{"day": {"azimuth_range": [A0, A1], "max_elevation": E, "rise_deg": R}}`` -- a day's sun
  across the frames (:class:`morphkit.sunpath.SunPath`; every key optional).

Directions follow :func:`morphkit.sunpath.sun` (azimuth counter-clockwise from world ``+x``,
elevation above the horizon).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import ValidationError, expected_got
from ..scene import DirectionalLight
from ..sunpath import SunPath, sun
from ..validate import as_finite_array, as_int

__all__ = ["SceneSun", "BakeLight", "FixedSun", "DaySun", "sun_from_json", "sun_from_light"]


@runtime_checkable
class SceneSun(Protocol):
    """What a scene's sun gives: a sun per frame (or None: the bake light), and its JSON form.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def suns(self, frames: int) -> list[DirectionalLight] | None:
        """One sun per frame; None for the bake light.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.

        Returns
        -------
        list of DirectionalLight or None
        """
        ...

    def to_json(self) -> dict[str, Any] | None:
        """The sun as a scene file writes it.

        Returns
        -------
        dict or None
        """
        ...


@dataclass(frozen=True)
class BakeLight:
    """The light the assets were baked under (no sun of the scene's own)."""

    def suns(self, frames: int) -> list[DirectionalLight] | None:
        """See :class:`SceneSun`.

        Parameters
        ----------
        frames : int
            Not used.

        Returns
        -------
        None
        """
        return None

    def to_json(self) -> dict[str, Any] | None:
        """See :class:`SceneSun`.

        Returns
        -------
        None
        """
        return None


@dataclass(frozen=True)
class FixedSun:
    """A sun standing still at ``(azimuth_deg, elevation_deg)`` (:func:`morphkit.sunpath.sun`).

    Parameters
    ----------
    azimuth_deg : float
        Degrees counter-clockwise from world ``+x``, towards the sun.
    elevation_deg : float
        Degrees above the horizon, in ``(0, 90]``.

    Examples
    --------
    >>> from morphkit.scenes.suns import FixedSun
    >>> [s.direction.round(6) + 0.0 for s in FixedSun(0.0, 90.0).suns(2)]
    [array([ 0.,  0., -1.]), array([ 0.,  0., -1.])]
    """

    azimuth_deg: float
    elevation_deg: float

    def __post_init__(self) -> None:
        a, e = as_finite_array([self.azimuth_deg, self.elevation_deg], "sun azimuth, elevation", shape=(2,))
        if not 0.0 < e <= 90.0:
            raise ValidationError(
                expected_got(
                    "sun elevation_deg", "degrees in (0, 90] (above the horizon)", self.elevation_deg
                )
            )
        object.__setattr__(self, "azimuth_deg", float(a))
        object.__setattr__(self, "elevation_deg", float(e))

    def suns(self, frames: int) -> list[DirectionalLight] | None:
        """See :class:`SceneSun`.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.

        Returns
        -------
        list of DirectionalLight
            The same sun ``frames`` times.
        """
        return [sun(self.azimuth_deg, self.elevation_deg)] * as_int(frames, "frames", lo=1)

    def to_json(self) -> dict[str, Any] | None:
        """See :class:`SceneSun`.

        Returns
        -------
        dict
            ``{"azimuth_deg": ..., "elevation_deg": ...}``.
        """
        return {"azimuth_deg": self.azimuth_deg, "elevation_deg": self.elevation_deg}


@dataclass(frozen=True)
class DaySun:
    """A day's sun across the frames (:class:`morphkit.sunpath.SunPath`).

    Parameters
    ----------
    path : SunPath, optional
        The day (default: morphkit's, from 10 degrees up at both ends to 60 at noon).
    """

    path: SunPath = field(default_factory=SunPath)

    def suns(self, frames: int) -> list[DirectionalLight] | None:
        """See :class:`SceneSun`.

        Parameters
        ----------
        frames : int
            Number of frames, >= 1.

        Returns
        -------
        list of DirectionalLight
        """
        return self.path.suns(frames)

    def to_json(self) -> dict[str, Any] | None:
        """See :class:`SceneSun`.

        Returns
        -------
        dict
            ``{"day": {...}}`` with every field of the path but its intensity.
        """
        d = asdict(self.path)
        d.pop("intensity")
        d["azimuth_range"] = list(d["azimuth_range"])
        return {"day": d}


def sun_from_json(obj: Mapping[str, Any] | None) -> BakeLight | FixedSun | DaySun:
    """The sun a scene file's ``"sun"`` value describes (the module notes).

    Parameters
    ----------
    obj : mapping or None
        Checked by the scene schema first.

    Returns
    -------
    BakeLight, FixedSun or DaySun

    Raises
    ------
    ValidationError
        None of the forms, or bad values.
    """
    if obj is None:
        return BakeLight()
    if "day" in obj:
        day = dict(obj["day"])
        if "azimuth_range" in day:
            day["azimuth_range"] = tuple(day["azimuth_range"])
        return DaySun(SunPath(**day))
    if "azimuth_deg" in obj and "elevation_deg" in obj:
        return FixedSun(obj["azimuth_deg"], obj["elevation_deg"])
    raise ValidationError(
        expected_got("sun", 'null, {"azimuth_deg", "elevation_deg"} or {"day": {...}}', sorted(obj))
    )


def sun_from_light(light: DirectionalLight) -> FixedSun:
    """The fixed sun a directional light is (the direction towards the sun, in azimuth and elevation).

    Parameters
    ----------
    light : DirectionalLight
        World frame; it must shine downwards (from above the horizon).

    Returns
    -------
    FixedSun

    Raises
    ------
    ValidationError
        A light shining level or upwards: no sun above the horizon.

    Examples
    --------
    >>> from morphkit.scenes.suns import sun_from_light
    >>> from morphkit.sunpath import sun
    >>> s = sun_from_light(sun(30.0, 40.0))
    >>> round(s.azimuth_deg, 9), round(s.elevation_deg, 9)
    (30.0, 40.0)
    """
    to_sun = -np.asarray(light.direction, np.float64)
    elevation = float(np.degrees(np.arcsin(np.clip(to_sun[2], -1.0, 1.0))))
    if not elevation > 0.0:
        raise ValidationError(
            expected_got(
                "the scene's light",
                "a sun above the horizon (shining downwards)",
                f"elevation {elevation:.1f} degrees",
            )
        )
    azimuth = float(np.degrees(np.arctan2(to_sun[1], to_sun[0])))
    return FixedSun(azimuth, elevation)
