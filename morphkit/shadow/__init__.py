"""Warped shadow maps (Kang & Ihm 2002) and their baselines.

The method (paper 1):

* :mod:`.method` -- :class:`ShadowMethod`, the interface every hard-shadow method implements;
* :mod:`.rig` -- the object's range of motion and the light camera that follows it;
* :mod:`.atlas` -- the k x k shadow atlas: :func:`bake_atlas` and :class:`ShadowAtlas`;
* :mod:`.baked` -- :class:`BakedAtlas`, the baked data (frozen);
* :mod:`.runtime` -- :class:`AtlasRuntime`, the per-map building blocks (cached);
* :mod:`.methods` -- :func:`build_method`: an atlas's shadow method by option (cached);
* :mod:`.planes` -- depth maps as coverage-depth planes (warped and blended without background);
* :mod:`.warped` -- the mesh warps: :class:`ComposedWarp` (default), :class:`ThreeWarps` (the paper's);
* :mod:`.lookup` -- the projective depth comparison (bias documented there);
* :mod:`.soft` -- soft shadows of area lights: one warp per light sample, averaged;
* :mod:`.pixels`, :mod:`.frame` -- a frame's drawn pixels; a whole frame: camera render,
  shadow map, composite.

Extensions, baselines, files and bake time, one folder each:

* :mod:`.reprojection` -- :class:`ReprojectedMaps`: per-pixel 3-D reprojection of the maps;
* :mod:`.filtering` -- the filtered lookup (the fraction of a light cell a point sees) and the
  smooth penumbrae from few samples: :class:`PcfSoftShadow`, :class:`PcssSoftShadow`;
* :mod:`.baselines` -- ``direct`` re-rendering and the image-based ``ibr_*`` methods;
* :mod:`.formats` -- the atlas file (save/load of the baked data, checked);
* :mod:`.baking` -- automatic control points and the fold-over relaxation of their destinations.

The program ``morphkit shadows`` (a baked atlas's scene along an object path, to frames and a video)
is :mod:`morphkit.programs.playback`, above this package and the bake pipeline. The shadows
of a field of billboards under the sun (one atlas per asset over the sun's direction) are
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
from .baked import BakedAtlas
from .baselines import DirectShadow, ImageBasedShadow
from .filtering.penumbra import PcfSoftShadow, PcssSoftShadow, default_soft_shadow
from .formats.atlasfile import ATLAS_VERSION, load_atlas, save_atlas
from .lookup import ShadowBias, normals_from_points, shadow_visibility
from .method import ShadowMethod, bilinear_weights
from .methods import build_method
from .reprojection.method import ReprojectedMaps
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
