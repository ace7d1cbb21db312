"""View morphing (Seitz & Dyer 1996) for view-dependent billboards (Paper 2).

One concept per module:

* :mod:`~morphkit.viewmorph.correspondences` -- point pairs from geometry
  (mesh points or dense depth-map samples) or from a user file; per-pixel
  depth keys for layered morphs;
* :mod:`~morphkit.viewmorph.matching` -- point pairs from the images alone
  (feature matching);
* :mod:`~morphkit.viewmorph.fundamental` -- F (``x1^T F x0 = 0``), its quality,
  epipoles (SVD null vectors), geometric F from cameras, degeneracy tests;
* :mod:`~morphkit.viewmorph.rectify` -- the pre-warp ``H_rect_0``/``H_rect_1``
  (OpenCV/Hartley and Seitz & Dyer's rotations), normalised and checked;
* :mod:`~morphkit.viewmorph.images` -- the reference pair: validation, layout
  promotion (grey < RGB < RGBA), image corners;
* :mod:`~morphkit.viewmorph.mesh` -- the morph mesh in the rectified frame
  (frame points, Delaunay at ``s = 1/2``, exact fold-over test and repair) and
  the rectified canvas it covers;
* :mod:`~morphkit.viewmorph.layers` -- depth layers: depth slices of pairs and
  pixels, and each layer's mesh, warpers and image-1 look-up
  (:class:`~morphkit.viewmorph.layers.MorphLayer`);
* :mod:`~morphkit.viewmorph.postwarp` -- the post-warp ``H_out_rect`` (image
  planes interpolated between the views, fitted to points or a camera) and the
  output crop/size policy;
* :mod:`~morphkit.viewmorph.plan` -- :func:`plan_view_morph`: estimates all of
  the above once per pair (F, pre-warps, fallbacks, layers, meshes) into a
  frozen :class:`MorphPlan` with a typed :class:`MorphReport`;
* :mod:`~morphkit.viewmorph.morph` -- :class:`ViewMorpher`: applies a plan,
  rendering the view at each ``s`` (direct or rectified path, layers
  composited with the premultiplied "over" of :mod:`morphkit.imaging.composite`);
* :mod:`~morphkit.viewmorph.baselines` -- the image-only baselines
  :func:`crossfade` and :func:`nearest`.

The method: Seitz & Dyer [1]_.

References
----------
.. [1] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.

Examples
--------
Two photos of one scene -- here two windows of one textured image, 16 pixels apart -- and
the view half-way between them: the points are matched in the images, the pair is planned
once, and the morph at ``s = 0.5`` shows the scene shifted by 8 pixels.

>>> import numpy as np
>>> from morphkit.viewmorph import ViewMorpher, from_images, plan_view_morph
>>> rng = np.random.default_rng(0)
>>> scene = np.kron(rng.integers(0, 256, (24, 32), dtype=np.uint8), np.ones((4, 4), np.uint8))
>>> left, right = scene[:, :112], scene[:, 16:]
>>> plan = plan_view_morph(left, right, from_images(left, right))
>>> middle = ViewMorpher(plan).morph(0.5)
>>> middle.shape, bool(np.abs(middle[:, 8:-8] - scene[:, 16:112].astype(float)).mean() < 2.0)
((96, 112), True)

The same in one line (without correspondences, :meth:`ViewMorpher.from_estimate` matches
the images itself):

>>> ViewMorpher.from_estimate(left, right).morph(0.5).shape
(96, 112)
"""

from __future__ import annotations

from .baselines import crossfade, nearest
from .correspondences import (
    Correspondences,
    HasVertices,
    from_depth,
    from_geometry,
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
from .matching import (
    DEFAULT_MATCHER,
    CombinedMatcher,
    FlowMatcher,
    ImageMatcher,
    SiftMatcher,
    from_images,
)
from .morph import ViewMorpher
from .plan import AffineReport, MorphPlan, MorphReport, plan_view_morph
from .postwarp import PostWarpPoints
from .rectify import F0, Rectification, rectify

__all__ = [
    "Correspondences",
    "HasVertices",
    "from_geometry",
    "from_depth",
    "pair_depth",
    "from_images",
    "ImageMatcher",
    "SiftMatcher",
    "FlowMatcher",
    "CombinedMatcher",
    "DEFAULT_MATCHER",
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
    "plan_view_morph",
    "MorphPlan",
    "MorphReport",
    "AffineReport",
    "ViewMorpher",
    "PostWarpPoints",
    "crossfade",
    "nearest",
]
