"""Warped shadow maps (Kang & Ihm 2002) and their baselines.

* :mod:`.rig` -- the object's range of motion and the light camera that follows it;
* :mod:`.atlas` -- the k x k shadow atlas: bake, control points, run-time warp, file I/O;
* :mod:`.reproject` -- per-pixel 3-D reprojection of the atlas's maps (``warps="reproject"``);
* :mod:`.baselines` -- ``direct`` re-rendering and the image-based ``ibr_*`` methods;
* :mod:`.lookup` -- the projective depth comparison (bias documented there);
* :mod:`.soft` -- soft shadows of area lights: one warp per light sample, averaged;
* :mod:`.frame` -- a whole frame: camera render + shadow map + composite.
"""

from __future__ import annotations

from .atlas import ATLAS_VERSION, AtlasMethod, ShadowAtlas, bake_atlas
from .baselines import DirectShadow, ImageBasedShadow
from .lookup import ShadowBias, normals_from_points, shadow_visibility
from .rig import LightRig, MotionRange, RangeClampWarning
from .soft import SoftShadow, bake_soft_atlas, light_offsets, soft_motion_range

__all__ = [
    "AtlasMethod",
    "ATLAS_VERSION",
    "ShadowAtlas",
    "bake_atlas",
    "DirectShadow",
    "ImageBasedShadow",
    "ShadowBias",
    "shadow_visibility",
    "normals_from_points",
    "LightRig",
    "MotionRange",
    "RangeClampWarning",
    "SoftShadow",
    "bake_soft_atlas",
    "light_offsets",
    "soft_motion_range",
]
