"""Where a relightable asset's reference views are: rings at several elevations and a top view.

A :class:`ViewDome` is a set of view directions over the upper hemisphere
(:mod:`.domecameras` for directions and cameras): rings of ``K_i`` views at
elevations ``e_i`` (ring ``i``'s azimuths ``(k + o_i) 360 / K_i``; odd rings are
offset by half a step when both rings have the same ``K`` so the triangles are not
slivers) and, optionally, one view straight above (azimuth 0, elevation 90). The
views' unit directions are triangulated on the sphere (their convex hull, closed
below by the nadir, whose triangles are dropped), and a viewing direction is
served by the **three views of the triangle around it** with barycentric weights
(:meth:`ViewDome.weights`): exactly one view with weight 1 at a view, weights
that change continuously across triangle edges.

Clamps: a direction below the lowest ring (the camera under the asset's horizon)
is treated as at the lowest ring's elevation; above the highest ring without a
top view, as at the highest ring's. :meth:`ViewDome.clamp` says which elevation
was used. A one-ring dome (the ring of :mod:`morphkit.billboard.ring`) has no triangles: its
directions are served by the two ring views around the azimuth (weights along the
chord, the third weight 0).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_int
from .domecameras import direction

__all__ = ["ViewDome", "DEFAULT_RINGS", "MAX_RINGS"]

#: Most rings a dome may have (with at most :data:`morphkit.tol.MAX_BILLBOARD_VIEWS` views each):
#: a file's ring list is read before its arrays are checked against it, so it is capped.
MAX_RINGS = 16

#: The default view set, chosen on ``morphkit bench billboards`` (dome rows): rings of
#: (elevation degrees, views) plus a top view.
DEFAULT_RINGS: tuple[tuple[float, int], ...] = ((0.0, 10), (30.0, 10), (60.0, 6))


@dataclass(frozen=True, eq=False)
class ViewDome:
    """Reference view directions over the upper hemisphere (module docstring).

    Parameters
    ----------
    rings : sequence of (elevation_deg, views)
        Elevations strictly increasing in ``[0, 90)``, ``views >= 3`` each (one ring:
        ``>= 2``).
    top : bool
        Add a view straight above.

    Raises
    ------
    ValidationError
        No rings or more than :data:`MAX_RINGS`, elevations out of range or not increasing,
        too few views or more than :data:`morphkit.tol.MAX_BILLBOARD_VIEWS` in a ring.
    """

    rings: tuple[tuple[float, int], ...] = DEFAULT_RINGS
    top: bool = True
    _az: np.ndarray = field(init=False, repr=False)
    _el: np.ndarray = field(init=False, repr=False)
    _tris: np.ndarray = field(init=False, repr=False)
    _inv: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        rings = tuple(self.rings) if isinstance(self.rings, Sequence) else ()
        if not 1 <= len(rings) <= MAX_RINGS:
            raise ValidationError(expected_got("rings", f"1 to {MAX_RINGS} (elevation_deg, views)",
                                               repr(self.rings)[:200]))
        clean: list[tuple[float, int]] = []
        for i, ring in enumerate(rings):
            try:
                e, k = ring
                e = float(e)
            except (TypeError, ValueError) as exc:
                raise ValidationError(expected_got(f"rings[{i}]", "(elevation_deg, views)",
                                                   repr(ring))) from exc
            k = as_int(k, f"rings[{i}] views", lo=2 if len(rings) == 1 and not self.top else 3,
                       hi=tol.MAX_BILLBOARD_VIEWS)
            if not 0.0 <= e < 90.0:
                raise ValidationError(expected_got(f"rings[{i}] elevation", "degrees in [0, 90)", e))
            if clean and e <= clean[-1][0]:
                raise ValidationError(expected_got("rings", "strictly increasing elevations", repr(rings)))
            clean.append((e, k))
        object.__setattr__(self, "rings", tuple(clean))
        object.__setattr__(self, "top", bool(self.top))
        az, el = [], []
        for i, (e, k) in enumerate(clean):
            offset = 0.5 if i > 0 and clean[i - 1][1] == k and i % 2 == 1 else 0.0
            for j in range(k):
                az.append(((j + offset) * 360.0 / k + 180.0) % 360.0 - 180.0)
                el.append(e)
        if self.top:
            az.append(0.0)
            el.append(90.0)
        object.__setattr__(self, "_az", np.array(az))
        object.__setattr__(self, "_el", np.array(el))
        tris = np.zeros((0, 3), np.int64)
        inv = np.zeros((0, 3, 3))
        if len(clean) > 1 or self.top:
            dirs = direction(self._az, self._el)
            pts = np.vstack([dirs, [[0.0, 0.0, -1.0]]])
            try:
                hull = ConvexHull(pts)
                nadir = len(dirs)
                tris = np.array([s for s in hull.simplices if nadir not in s], dtype=np.int64)
                inv = np.linalg.inv(np.transpose(dirs[tris], (0, 2, 1)))  # columns: the three directions
            except (QhullError, np.linalg.LinAlgError, ValueError) as exc:
                raise ValidationError(expected_got("rings", "views that span the upper hemisphere "
                                                   "(their triangles not flat)", repr(clean))) from exc
        object.__setattr__(self, "_tris", tris)
        object.__setattr__(self, "_inv", inv)

    @property
    def views(self) -> int:
        """Number of reference views."""
        return len(self._az)

    def azimuths_deg(self) -> np.ndarray:
        """``(V,)`` view azimuths, degrees in ``[-180, 180)``.

        Returns
        -------
        (V,) float64
            A copy.
        """
        return self._az.copy()

    def elevations_deg(self) -> np.ndarray:
        """``(V,)`` view elevations, degrees.

        Returns
        -------
        (V,) float64
            A copy.
        """
        return self._el.copy()

    def triangles(self) -> np.ndarray:
        """``(T, 3)`` view indices of the triangles on the sphere (empty for one ring).

        Returns
        -------
        (T, 3) int64
            A copy.
        """
        return self._tris.copy()

    def barycentric_inverses(self) -> np.ndarray:
        """``(T, 3, 3)``: per triangle, the inverse of the matrix whose columns are its three view
        directions, so that ``inverse @ d`` is a direction's barycentric coordinates (:meth:`weights`).

        Returns
        -------
        (T, 3, 3) float64
            A copy (empty for one ring).
        """
        return self._inv.copy()

    def clamp(self, elevation_deg: float) -> float:
        """The elevation a direction is served at (module docstring: the clamps).

        Parameters
        ----------
        elevation_deg : float
            Degrees.

        Returns
        -------
        float
            ``elevation_deg`` clamped to the dome's range.
        """
        e = float(elevation_deg)
        if not np.isfinite(e):
            raise ValidationError(expected_got("elevation_deg", "a finite angle", e))
        hi = 90.0 if self.top else self.rings[-1][0]
        return min(max(e, self.rings[0][0]), hi)

    def weights(self, azimuth_deg: float, elevation_deg: float) -> tuple[np.ndarray, np.ndarray]:
        """The views serving a direction and their weights (module docstring).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame (the elevation is clamped).

        Returns
        -------
        views : (3,) int64
            View indices (a one-ring dome repeats one view with weight 0).
        weights : (3,) float64
            Non-negative, summing to 1, in the order of ``views``.
        """
        a = float(azimuth_deg)
        if not np.isfinite(a):
            raise ValidationError(expected_got("azimuth_deg", "a finite angle", a))
        e = self.clamp(elevation_deg)
        if len(self._tris) == 0:
            return self._ring_weights(a)
        d = direction(a, e)
        lam = self._inv @ d  # (T, 3)
        worst = lam.min(axis=1)
        t = int(np.argmax(worst))
        w = np.clip(lam[t], 0.0, None)
        w = w / w.sum()
        w[w < tol.REL_EQUAL] = 0.0
        return self._tris[t].copy(), w / w.sum()

    def weights_many(self, azimuths_deg: np.ndarray, elevation_deg: float) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`weights` for many azimuths at one elevation, at once (a field's instances
        under one sun: their object-frame suns differ by their yaws only).

        Parameters
        ----------
        azimuths_deg : (M,) float
            Azimuths, degrees (finite).
        elevation_deg : float
            The elevation shared by all (clamped as :meth:`weights` does).

        Returns
        -------
        views : (M, 3) int64
            Each direction's views, as :meth:`weights` returns them.
        weights : (M, 3) float64
            Their weights (rows sum to 1).

        Raises
        ------
        ValidationError
            A non-finite azimuth.
        """
        a = np.asarray(azimuths_deg, dtype=np.float64).reshape(-1)
        if not np.all(np.isfinite(a)):
            raise ValidationError(expected_got("azimuths_deg", "finite angles", "NaN or inf"))
        if len(self._tris) == 0 or len(a) == 0:
            got = [self.weights(float(x), elevation_deg) for x in a]
            return (np.array([g[0] for g in got], np.int64).reshape(-1, 3),
                    np.array([g[1] for g in got], np.float64).reshape(-1, 3))
        d = direction(a, self.clamp(elevation_deg))
        lam = np.einsum("tij,mj->mti", self._inv, d)  # (M, T, 3)
        t = np.argmax(lam.min(axis=2), axis=1)
        w = np.clip(lam[np.arange(len(a)), t], 0.0, None)
        w /= w.sum(axis=1, keepdims=True)
        w[w < tol.REL_EQUAL] = 0.0
        return self._tris[t].astype(np.int64), w / w.sum(axis=1, keepdims=True)

    def _ring_weights(self, a: float) -> tuple[np.ndarray, np.ndarray]:
        k = len(self._az)
        step = 360.0 / k
        rel = (a - self._az[0]) % 360.0
        i = int(rel // step) % k
        j = (i + 1) % k
        b = np.radians(step / 2.0)
        t = np.radians(rel - i * step - step / 2.0)
        s = float(np.clip((np.tan(t) / np.tan(b) + 1.0) / 2.0, 0.0, 1.0))  # the chord fraction (.ring)
        return np.array([i, j, j], np.int64), np.array([1.0 - s, s, 0.0])
