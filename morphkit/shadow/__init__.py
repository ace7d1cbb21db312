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
* :mod:`.filtered` -- the filtered lookup: the fraction of a light cell one map says a point sees;
* :mod:`.depthtables` -- :class:`~.depthtables.DepthTables`: the filtered lookup's per-map
  summed-area tables and max-depth pyramid;
* :mod:`.penumbra` -- smooth penumbrae from few samples: :class:`PcfSoftShadow`, :class:`PcssSoftShadow`;
* :mod:`.frame` -- a whole frame: camera render + shadow map + composite.

The program ``morphkit shadows`` (a baked atlas's scene along an object path, to frames and a video)
is :mod:`morphkit.programs.playback`, above this package and the bake pipeline. The shadows of a field of
billboards under the sun (one atlas per asset over the sun's direction) are
:mod:`morphkit.sunlit`, the junction of both papers, above this package and the billboards.

Papers: the warped shadow maps of Kang & Ihm [1]_, built on shadow mapping [2]_ and projective
texture mapping [3]_; the image-based baseline of Lee & Ihm [4]_.

References
----------
.. [1] B. Kang and I. Ihm, "Real-Time Shadow Generation using Image Warping", Journal of KIISE, 2002
   (digest: ``docs/papers.md``).
.. [2] L. Williams, "Casting Curved Shadows on Curved Surfaces", Computer Graphics (Proc. SIGGRAPH 78),
   12(3), pp. 270-274, 1978.
.. [3] M. Segal, C. Korobkin, R. van Widenfelt, J. Foran and P. Haeberli, "Fast Shadows and Lighting
   Effects Using Texture Mapping", Computer Graphics (Proc. SIGGRAPH 92), 26(2), pp. 249-252, 1992.
.. [4] J. Lee and I. Ihm, "Real-Time Shadow Generation using Image-Based Wavelet Techniques"
   (in Korean; title translated), Journal of the Korea Computer Graphics Society, 7(1),
   pp. 27-35, 2001; reference 4 of Kang & Ihm.
"""

from __future__ import annotations

from .atlas import ShadowAtlas, bake_atlas
from .atlasfile import ATLAS_VERSION, load_atlas, save_atlas
from .baked import BakedAtlas
from .baselines import DirectShadow, ImageBasedShadow
from .lookup import ShadowBias, normals_from_points, shadow_visibility
from .method import ShadowMethod, bilinear_weights
from .methods import build_method
from .penumbra import PcfSoftShadow, PcssSoftShadow, default_soft_shadow
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
    "PcfSoftShadow",
    "PcssSoftShadow",
    "default_soft_shadow",
]
