"""Where a billboard asset's reference views are: a ring of directions about the up axis.

Azimuths are in degrees, counter-clockwise about ``+z`` (:mod:`morphkit.conventions`),
measured from the asset's front: the object frame's ``+x`` axis is azimuth 0 (the
sample meshes face ``+x``, :mod:`morphkit.meshes`). A view "at azimuth ``a``"
looks at the asset from the direction ``(cos a, sin a)``.

Two layouts:

* ``K = 2`` -- the paper's pair: a left and a right view at ``-arc/2`` and
  ``+arc/2`` (default ``arc = 60``: +-30 degrees about the front). Azimuths
  inside the arc are morphed between them; outside it the view is **clamped**
  to the nearer reference (``s = 0`` or ``1``) and ``outside_deg > 0`` says by
  how many degrees the viewing direction left the arc.
* ``K >= 3`` -- a full ring: views every ``360 / K`` degrees starting at
  azimuth 0, so every azimuth lies between two neighbouring references.

``K = 1`` is refused: one image for every direction is the classic billboard
(:meth:`morphkit.billboard.BillboardAsset.classic`), not a morph.

The fraction ``s`` is along the chord
-------------------------------------
A view morph (Seitz & Dyer) interpolating two views by ``s`` is the view from
the camera centre ``(1 - s) C_i + s C_j``: on the straight line between the
two reference cameras, not on the circle through them. So ``s`` is the
fraction along that chord whose point lies in the viewing direction: for a
pair ``2 b`` degrees apart whose bisector is at azimuth ``m``, the direction
``m + t`` (``|t| <= b``) meets the chord at

    ``s = (tan(t) / tan(b) + 1) / 2``,   and back:  ``t = atan((2 s - 1) tan(b))``,

exactly 0 and 1 at the references and exactly 1/2 on the bisector. (The
in-between camera is closer to the asset than the references by the factor
``|(1 - s) u_i + s u_j|``, at least ``cos(b)``; the quad rule keeps the pivot
plane's scale, so only the perspective changes, slightly:
:meth:`morphkit.billboard.QuadCameras.chord_camera`.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_int

__all__ = ["ViewRing", "wrap_deg"]

#: The paper's pair: +-30 degrees about the front.
DEFAULT_ARC_DEG = 60.0
#: Elevation of the reference cameras above the ground plane (degrees).
DEFAULT_ELEVATION_DEG = 10.0


def wrap_deg(angle_deg: float) -> float:
    """``angle_deg`` wrapped into ``[-180, 180)`` degrees.

    Parameters
    ----------
    angle_deg : float
        Angle, degrees.

    Returns
    -------
    float
        The wrapped angle, degrees.
    """
    a = float(angle_deg)
    if not math.isfinite(a):
        raise ValidationError(expected_got("azimuth", "a finite angle in degrees", a))
    return (a + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class ViewRing:
    """The reference directions of an asset (see the module docstring).

    Parameters
    ----------
    views : int
        ``K >= 2`` reference views.
    arc_deg : float, optional
        ``K = 2``: the angle between the two views, in ``(0, 180)``; default 60.
        ``K >= 3``: must be 360 (or left out).
    elevation_deg : float
        Camera elevation above the ground plane, in ``[0, 60]`` degrees (the
        reference cameras keep a vertical image plane, :mod:`.cameras`; steeper
        views would put the asset's near side behind them).

    Raises
    ------
    ValidationError
        ``views`` not an int >= 2 (``K = 1`` is the classic billboard), or an
        arc/elevation out of range.
    """

    views: int
    arc_deg: float = None  # type: ignore[assignment]  # set in __post_init__
    elevation_deg: float = DEFAULT_ELEVATION_DEG

    def __post_init__(self) -> None:
        k = as_int(self.views, "views")
        if k < 2:
            raise ValidationError(expected_got(
                "views", "K >= 2 reference views (K = 1 is the classic billboard: one image for every "
                "direction; use BillboardAsset.classic)", k))
        k = int(k)
        arc = self.arc_deg
        if arc is None:
            arc = DEFAULT_ARC_DEG if k == 2 else 360.0
        arc = float(arc)
        if k == 2 and not 0.0 < arc < 180.0:
            raise ValidationError(expected_got("arc_deg", "an angle in (0, 180) for K = 2", arc))
        if k >= 3 and arc != 360.0:
            raise ValidationError(expected_got("arc_deg", f"360 for K = {k} (a full ring)", arc))
        e = float(self.elevation_deg)
        if not 0.0 <= e <= 60.0:
            raise ValidationError(expected_got("elevation_deg", "an angle in [0, 60]", e))
        object.__setattr__(self, "views", k)
        object.__setattr__(self, "arc_deg", arc)
        object.__setattr__(self, "elevation_deg", e)

    @property
    def band_deg(self) -> tuple[float, float]:
        """The eye elevations (degrees) the ring's views serve: its elevation up to
        :data:`morphkit.tol.BB_RING_BAND_DEG` above it, from the horizon (0).

        Examples
        --------
        >>> from morphkit.billboard.ring import ViewRing
        >>> ViewRing(8).band_deg
        (0.0, 30.0)
        """
        return (0.0, self.elevation_deg + tol.BB_RING_BAND_DEG)

    @property
    def spacing_deg(self) -> float:
        """Angle between neighbouring references (the arc for ``K = 2``)."""
        return self.arc_deg if self.views == 2 else 360.0 / self.views

    def azimuths_deg(self) -> np.ndarray:
        """``(K,)`` float64 view azimuths in degrees, in ``[-180, 180)``.

        ``K = 2``: ``(-arc/2, +arc/2)``; ``K >= 3``: ``k * 360 / K`` (wrapped).

        Returns
        -------
        (K,) float64
            The azimuths, degrees, object frame.
        """
        if self.views == 2:
            return np.array([-0.5 * self.arc_deg, 0.5 * self.arc_deg])
        return np.array([wrap_deg(k * 360.0 / self.views) for k in range(self.views)])

    def pairs(self) -> list[tuple[int, int]]:
        """The neighbouring pairs ``(i, j)`` that are morphed, ``j`` counter-clockwise of ``i``:
        ``[(0, 1)]`` for ``K = 2``; ``(k, (k + 1) % K)`` for a full ring.

        Returns
        -------
        list of (int, int)
            The pairs.
        """
        if self.views == 2:
            return [(0, 1)]
        return [(k, (k + 1) % self.views) for k in range(self.views)]

    def pair_azimuth_deg(self, i: int, j: int, s: float) -> float:
        """Azimuth (degrees, wrapped) of the view at chord fraction ``s`` from reference ``i`` to ``j``.

        ``(i, j)`` is one of :meth:`pairs` or its reverse; the azimuth moves along the
        short way between the two (through the arc for ``K = 2``); see the module
        docstring for the chord fraction.

        Parameters
        ----------
        i, j : int
            Neighbouring reference indices.
        s : float
            Chord fraction in ``[0, 1]`` from ``i`` to ``j``.

        Returns
        -------
        float
            Azimuth in ``[-180, 180)`` degrees, object frame.
        """
        i, j = self.check_pair(i, j)
        s = float(s)
        if not 0.0 <= s <= 1.0:
            raise ValidationError(expected_got("s", "a number in [0, 1]", s))
        az = self.azimuths_deg()
        sign = 1.0 if (i, j) in self.pairs() else -1.0
        return wrap_deg(az[i] + sign * self.spacing_deg * _arc_fraction(s, 0.5 * self.spacing_deg))

    def check_pair(self, i: int, j: int) -> tuple[int, int]:
        """``(i, j)`` as ints if they are neighbouring references (one of :meth:`pairs`, or reversed).

        Parameters
        ----------
        i, j : int
            Reference indices.

        Returns
        -------
        (int, int)
            ``(i, j)`` as Python ints.

        Raises
        ------
        ValidationError
            An index out of range or two references that are not neighbours.
        """
        i = as_int(i, "view index i", lo=0, hi=self.views - 1)
        j = as_int(j, "view index j", lo=0, hi=self.views - 1)
        pairs = self.pairs()
        if (i, j) not in pairs and (j, i) not in pairs:
            raise ValidationError(expected_got("view pair", f"neighbouring references (one of {pairs} or "
                                               "reversed)", (i, j)))
        return i, j

    def pair(self, azimuth_deg: float) -> tuple[int, int, float, float]:
        """The two references bracketing ``azimuth_deg`` and the fraction between them.

        Parameters
        ----------
        azimuth_deg : float
            Viewing azimuth relative to the asset's front (any finite angle; wrapped).

        Returns
        -------
        i, j : int
            A pair of :meth:`pairs` (``j`` counter-clockwise of ``i``).
        s : float
            In ``[0, 1]``: 0 is view ``i``, 1 is view ``j``; the fraction along the
            chord between the two cameras (module docstring); exactly 0 (or, for
            ``K = 2`` at view 1, exactly 1) at a reference azimuth, exactly 1/2 half way.
        outside_deg : float
            ``K = 2`` outside the arc: the angle (degrees, > 0) from the azimuth
            to the nearer end of the arc, where the view is clamped (``s = 0``
            at view 0, ``s = 1`` at view 1); 0 otherwise.

        Examples
        --------
        The paper's pair (views at -30 and +30 degrees): the front is half way, 40 degrees
        is 10 degrees beyond view 1; a ring of 8 views (every 45 degrees) at 90 is view 2.

        >>> ring = ViewRing(2)
        >>> ring.pair(0.0)
        (0, 1, 0.5, 0.0)
        >>> ring.pair(40.0)
        (0, 1, 1.0, 10.0)
        >>> ViewRing(8).pair(90.0)
        (2, 3, 0.0, 0.0)
        """
        a = wrap_deg(azimuth_deg)
        if self.views == 2:
            half = 0.5 * self.arc_deg
            if -half <= a <= half:
                return 0, 1, _chord_fraction((a + half) / self.arc_deg, half), 0.0
            d0 = abs(wrap_deg(a + half))  # to view 0 at -half
            d1 = abs(wrap_deg(a - half))
            return (0, 1, 0.0, d0) if d0 <= d1 else (0, 1, 1.0, d1)
        t = (a % 360.0) / self.spacing_deg
        k = math.floor(t)
        s = t - k
        i = k % self.views
        return i, (i + 1) % self.views, _chord_fraction(float(s), 0.5 * self.spacing_deg), 0.0


def _chord_fraction(u: float, half_deg: float) -> float:
    """Chord fraction ``s`` of the direction a fraction ``u`` of the way along an arc of
    ``2 half_deg`` degrees: ``(tan((2u - 1) b) / tan(b) + 1) / 2``, exact at 0, 1/2 and 1."""
    if u <= 0.0 or u >= 1.0 or u == 0.5:
        return min(max(u, 0.0), 1.0)
    b = math.radians(half_deg)
    return min(max(0.5 * (math.tan((2.0 * u - 1.0) * b) / math.tan(b) + 1.0), 0.0), 1.0)


def _arc_fraction(s: float, half_deg: float) -> float:
    """Inverse of :func:`_chord_fraction`: ``(atan((2s - 1) tan(b)) / b + 1) / 2``."""
    if s <= 0.0 or s >= 1.0 or s == 0.5:
        return min(max(s, 0.0), 1.0)
    b = math.radians(half_deg)
    return 0.5 * (math.atan((2.0 * s - 1.0) * math.tan(b)) / b + 1.0)
