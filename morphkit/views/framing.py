"""How far a view's camera stands and how much room it leaves: the rule every baked view follows.

A baked view of an object (a billboard's ring, a dome, an impostor, a sun atlas) is taken from
:data:`DISTANCE_FACTOR` radii of the object's bounding sphere about its pivot (within
:data:`DISTANCE_FACTOR_RANGE`), and its image holds the object with a margin of
:data:`FRAME_MARGIN` on each side.
"""

from __future__ import annotations

import numpy as np

from ..errors import ValidationError, expected_got

__all__ = ["DISTANCE_FACTOR", "DISTANCE_FACTOR_RANGE", "FRAME_MARGIN", "check_distance_factor"]

#: Default camera distance from the pivot, in radii of the mesh's bounding sphere
#: about it (``bake_asset(distance_factor=...)``). A billboard stands in for an
#: object seen from afar, so its views are baked with the perspective a scene
#: camera has there: at 4 radii the near side of the object is 3/5 of the far
#: side's distance, and even a perfect view mapped on the quad misses the mesh
#: seen from 12 radii far more than at 12 (the "true-view" rows of
#: ``morphkit bench billboards``, docs/RESULTS.md). Bake nearer for scenes that
#: see the assets closer.
DISTANCE_FACTOR = 12.0

#: Allowed range of the distance factor: nearer than 3 radii the depth range of
#: :meth:`QuadCameras.camera_at` no longer holds the object between two ring cameras
#: 60 degrees apart, farther than 100 the views are orthographic for every purpose.
DISTANCE_FACTOR_RANGE = (3.0, 100.0)


def check_distance_factor(value: float, name: str = "distance_factor") -> float:
    """``value`` as a float, checked to lie in :data:`DISTANCE_FACTOR_RANGE`.

    Parameters
    ----------
    value : float
        A camera distance in bounding radii.
    name : str
        What the error message calls it.

    Returns
    -------
    float
        The distance factor.

    Raises
    ------
    ValidationError
        Not a number (bools refused), NaN, or outside the range.
    """
    lo, hi = DISTANCE_FACTOR_RANGE
    numeric = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
    factor = float(value) if numeric else float("nan")
    if not lo <= factor <= hi:
        raise ValidationError(expected_got(name, f"a number in [{lo:g}, {hi:g}] (radii)", repr(value)))
    return factor

#: Fraction by which the fitted quad is larger than the object's widest
#: projection (a margin of transparent pixels around every view).
FRAME_MARGIN = 0.04
