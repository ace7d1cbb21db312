"""Warped shadow maps (Kang & Ihm 2002) and their baselines.

* :mod:`.method` -- :class:`ShadowMethod`, the interface every hard-shadow method implements;
* :mod:`.rig` -- the object's range of motion and the light camera that follows it;
* :mod:`.atlas` -- the k x k shadow atlas: :func:`bake_atlas` and :class:`ShadowAtlas` (data + run time);
* :mod:`.baked` -- :class:`BakedAtlas`, the baked data (frozen);
* :mod:`.runtime` -- :class:`AtlasRuntime`, the per-map building blocks (cached) and run-time counts;
* :mod:`.methods` -- :func:`build_method`: an atlas's shadow method by option (cached per option set);
* :mod:`.atlasfile` -- the atlas file (save/load of the baked data, checked);
* :mod:`.controls` -- automatic control points (silhouette box, anchor depths, lifting);
* :mod:`.planes` -- depth maps as coverage-depth planes (warped and blended without mixing background);
* :mod:`.fold` -- fold-over relaxation of destination control points;
* :mod:`.warped` -- the mesh-warp methods: :class:`ComposedWarp` (default), :class:`ThreeWarps` (the paper's);
* :mod:`.reprojected` -- :class:`ReprojectedMaps`: per-pixel 3-D reprojection of the maps;
* :mod:`.reprojection` -- the per-pixel reprojection kernels and hidden layers (a package);
* :mod:`.baselines` -- ``direct`` re-rendering and the image-based ``ibr_*`` methods;
* :mod:`.lookup` -- the projective depth comparison (bias documented there);
* :mod:`.soft` -- soft shadows of area lights: one warp per light sample, averaged;
* :mod:`.frame` -- a whole frame: camera render + shadow map + composite;
* :mod:`.playback` -- ``morphkit shadows``: a baked atlas's scene along an object path, to frames and
  a video (imported by the CLI, not re-exported here).
"""

from __future__ import annotations

from .atlas import ShadowAtlas, bake_atlas
from .atlasfile import ATLAS_VERSION, load_atlas, save_atlas
from .baked import BakedAtlas
from .baselines import DirectShadow, ImageBasedShadow
from .lookup import ShadowBias, normals_from_points, shadow_visibility
from .method import ShadowMethod, bilinear_weights
from .methods import build_method
from .reprojected import ReprojectedMaps
from .rig import LightRig, MotionRange, RangeClampWarning
from .runtime import AtlasRuntime
from .soft import SoftShadow, bake_soft_atlas, light_offsets, soft_motion_range
from .warped import ComposedWarp, ThreeWarps

__all__ = [
    "ShadowMethod",
    "bilinear_weights",
    "ComposedWarp",
    "ThreeWarps",
    "ReprojectedMaps",
    "build_method",
    "ATLAS_VERSION",
    "ShadowAtlas",
    "BakedAtlas",
    "AtlasRuntime",
    "bake_atlas",
    "save_atlas",
    "load_atlas",
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
