"""Warped shadow maps (Kang & Ihm 2002) and their baselines.

* :mod:`.method` -- :class:`ShadowMethod`, the interface every hard-shadow method implements;
* :mod:`.rig` -- the object's range of motion and the light camera that follows it;
* :mod:`.atlas` -- the k x k shadow atlas: bake and per-map building blocks;
* :mod:`.atlasfile` -- the atlas file (save/load, checked);
* :mod:`.controls` -- automatic control points (silhouette box, anchor depths, lifting);
* :mod:`.planes` -- depth maps as coverage-depth planes (warped and blended without mixing background);
* :mod:`.fold` -- fold-over relaxation of destination control points;
* :mod:`.warped` -- the mesh-warp methods: :class:`ComposedWarp` (default), :class:`ThreeWarps` (the paper's);
* :mod:`.reprojected` -- :class:`ReprojectedMaps`: per-pixel 3-D reprojection of the maps;
* :mod:`.reproject` -- the reprojection kernels and hidden layers;
* :mod:`.baselines` -- ``direct`` re-rendering and the image-based ``ibr_*`` methods;
* :mod:`.lookup` -- the projective depth comparison (bias documented there);
* :mod:`.soft` -- soft shadows of area lights: one warp per light sample, averaged;
* :mod:`.filtered` -- the filtered lookup: the fraction of a light cell one map says a point sees;
* :mod:`.penumbra` -- smooth penumbrae from few samples: :class:`PcfSoftShadow`, :class:`PcssSoftShadow`;
* :mod:`.frame` -- a whole frame: camera render + shadow map + composite.
"""

from __future__ import annotations

from .atlas import ShadowAtlas, bake_atlas
from .atlasfile import ATLAS_VERSION
from .baselines import DirectShadow, ImageBasedShadow
from .lookup import ShadowBias, normals_from_points, shadow_visibility
from .method import ShadowMethod, bilinear_weights
from .penumbra import PcfSoftShadow, PcssSoftShadow, default_soft_shadow
from .reprojected import ReprojectedMaps
from .rig import LightRig, MotionRange, RangeClampWarning
from .soft import SoftShadow, bake_soft_atlas, light_offsets, soft_motion_range
from .warped import ComposedWarp, ThreeWarps

__all__ = [
    "ShadowMethod",
    "bilinear_weights",
    "ComposedWarp",
    "ThreeWarps",
    "ReprojectedMaps",
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
    "PcfSoftShadow",
    "PcssSoftShadow",
    "default_soft_shadow",
]
