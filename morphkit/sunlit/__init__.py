"""Billboards under the sun with the field's shadows: where the two papers meet.

Paper 2's billboards (:mod:`morphkit.billboard`) stand in a field; paper 1's idea, a few baked
light views warped to the light actually used (:mod:`morphkit.shadow`), gives them shadows:
one atlas per asset over the sun's direction in its own frame, reused by every instance, every
yaw and every sun. This package sits above both wings and imports them; neither imports it.

The sun's shadow casters (the sun itself, a day's path across the sky, is
:mod:`morphkit.sunpath`):

* :mod:`.sunatlas` -- :class:`SunAtlas`: an asset's light views over the sun's direction
  (every yaw, every sun), morphed per pixel; one instance's ground shadow;
* :mod:`.pointlevels` -- coarser levels of an atlas view's surface points;
* :mod:`.sunatlasfile` -- the sun atlas file (versioned, checksummed);
* :mod:`.sunbaselines` -- the sun atlas's baselines: the direct light render, the ray-cast truth.

The field's shadow, one light view along the sun:

* :mod:`.fieldshadow` -- :class:`FieldShadow`: the field's light view (culled to a receiver,
  reused while nothing moves), drawn by a ``FieldDrawer``;
* :mod:`.fieldsplat` -- the default drawer: the atlas views' points reprojected into that view;
* :mod:`.sundisc` -- a sun disc's soft shadow from that one view (percentage-closer soft shadows);
* :mod:`.fieldbaselines`, :mod:`.cardbaselines` -- the field's baselines: every posed mesh
  rendered into that view, the impostor cards drawn into it, the ray cast.

Relit billboard frames:

* :mod:`.receivers` -- :class:`SceneShadow`: the sun's visibility at a frame's receivers, from
  the atlases (:class:`AtlasShadow`); :mod:`.raycast` -- :class:`RayCastShadow`, the truth;
* :mod:`.shadowing` -- the ground's and the billboards' sun visibility per pixel of a frame;
* :mod:`.litmodes` -- :class:`LitMode`: relit billboards (each billboard's surface for its
  viewing direction, shaded by the scene's lights);
* :mod:`.litmesh` -- :class:`LitMeshMode`: the real meshes shaded the same way, the truth;
* :mod:`.sunlitfield` -- :class:`SunlitField`: all of it from a few meshes in a few lines (bake,
  scatter, render, and compare with the truth).
"""

from __future__ import annotations

from .fieldshadow import FieldMap, FieldShadow
from .fieldsplat import SplatDrawer
from .litmesh import LitMeshMode
from .litmodes import ClassicSurface, CrossfadeSurface, LitMode, MorphSurface, NearestSurface, Relit
from .raycast import RayCastShadow
from .receivers import AtlasShadow, FilteredAtlasShadow, FrameShadow, SceneShadow
from .sunatlas import SunAtlas, bake_sun_atlas, ground_shadow
from .sunatlasfile import read_sun_atlas, write_sun_atlas
from .sunlitfield import FieldComparison, SunlitField

__all__ = [
    "SunAtlas", "bake_sun_atlas", "ground_shadow", "read_sun_atlas", "write_sun_atlas",
    "FieldShadow", "FieldMap", "SplatDrawer",
    "SceneShadow", "FrameShadow", "AtlasShadow", "FilteredAtlasShadow", "RayCastShadow",
    "Relit", "LitMode", "MorphSurface", "NearestSurface", "CrossfadeSurface", "ClassicSurface",
    "LitMeshMode", "SunlitField", "FieldComparison",
]
