"""View morphing (Seitz & Dyer 1996) for view-dependent billboards (Paper 2).

One concept per module:

* :mod:`~morphkit.viewmorph.correspondences` -- point pairs from geometry
  (mesh points or dense depth-map samples), from image features, or from a
  user file; per-pixel depth keys for layered morphs;
* :mod:`~morphkit.viewmorph.fundamental` -- F (``x1^T F x0 = 0``), its quality,
  epipoles (SVD null vectors), geometric F from cameras, degeneracy tests;
* :mod:`~morphkit.viewmorph.rectify` -- the pre-warp (OpenCV/Hartley and
  Seitz & Dyer's rotations), normalised and checked;
* :mod:`~morphkit.viewmorph.morph` -- :class:`ViewMorpher` (mesh morph in the
  rectified frame, optionally in depth layers, post-warp, crop policy,
  premultiplied blending) and the
  ``crossfade``/``nearest`` baselines.

Typical use::

    from morphkit.viewmorph import ViewMorpher, from_images
    vm = ViewMorpher(left, right, from_images(left, right))
    middle = vm.morph(0.5)
"""

from __future__ import annotations

from .baselines import crossfade, nearest
from .correspondences import (
    Correspondences,
    from_depth,
    from_geometry,
    from_images,
    load_points,
    pair_depth,
    save_points,
)
from .fundamental import (
    FundamentalFit,
    epipoles,
    estimate_fundamental,
    fundamental_from_cameras,
    sampson_distance,
)
from .morph import ViewMorpher
from .postwarp import PostWarpPoints
from .rectify import F0, Rectification, rectify

__all__ = [
    "Correspondences",
    "from_geometry",
    "from_depth",
    "pair_depth",
    "from_images",
    "load_points",
    "save_points",
    "FundamentalFit",
    "estimate_fundamental",
    "fundamental_from_cameras",
    "epipoles",
    "sampson_distance",
    "F0",
    "Rectification",
    "rectify",
    "ViewMorpher",
    "PostWarpPoints",
    "crossfade",
    "nearest",
]
