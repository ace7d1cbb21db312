"""Per-pixel 3-D reprojection of light depth maps (forward, z-buffered): the kernels
behind :class:`~morphkit.shadow.reprojection.method.ReprojectedMaps` (``warps="reproject"``).

A piecewise-affine mesh warp (:mod:`morphkit.shadow.warped`, the paper's) moves
every pixel of a triangle with one affine motion, so it cannot follow parallax
*inside* a triangle: where a triangle straddles surfaces at different depths
(the chair's back slats in front of its seat) the warped silhouette is wrong by
up to the parallax difference. A depth map, though, holds the 3-D position of
every pixel: with the object translated by ``d`` and a light camera of fixed
orientation, each pixel can be moved exactly. This package does that for the
atlas's maps ("3-D image warping", McMillan & Bishop 1995; the mesh
reconstruction of Mark, McMillan & Bishop 1997):

1. **Move each pixel.** Source pixel ``(x, y)`` of depth ``z`` is the camera
   point ``P = (z (x - cx_s) / fx, z (y - cy_s) / fy, z)`` (perspective; for
   orthographic ``((x - cx_s) / fx, (y - cy_s) / fy, z)``); the object moved by
   ``d`` puts it at ``P + e`` with ``e = R^T d`` (``R`` the light camera's
   rotation, the same for every map of a :class:`~morphkit.shadow.rig.LightRig`),
   which projects with the destination camera's principal point to
   ``(x', y')`` at depth ``z + e_z``. Exact for every surface point a map saw.
2. **Reconnect the pixels.** Neighbouring pixel centres form quads, split into
   two triangles (along the ``(x+1, y)``-``(x, y+1)`` diagonal; a quad with
   only 3 object pixels gives their triangle), each rasterised at the
   destination pixel centres it covers, depth interpolated linearly. A triangle
   with a bounding box wider or taller than :data:`STRETCH_PX` pixels is not
   drawn: its vertices moved apart by parallax, so it spans a depth jump (a
   disocclusion), not a surface. Pixels that belong to no triangle of three
   object pixels (one-pixel-wide features) are drawn as points, at the nearest
   pixel centre.
3. **Several sources, one z-buffer.** A surface hidden in one map (disoccluded
   by the motion) is usually seen by another: the cell's maps are all
   reprojected into one z-buffer, which keeps the nearest depth. What none of
   them saw stays a hole (the method's error).
4. **Only what is new.** Most of a neighbour map repeats what the primary map
   (the largest weight) holds. :func:`hidden_layer` keeps, once per pair of
   neighbouring samples, only the neighbour's pixels that the primary's map
   does not explain (hidden from its position, or at its silhouette): a layered
   depth image (Shade, Gortler, He & Szeliski 1998). A frame then reprojects
   the primary whole and its neighbours' layers: the same shadow as the whole
   maps from a fraction of their pixels (docs/RESULTS.md, "Warped shadow maps"),
   and a layer costs only a list of runs of quads (:class:`Layer`).

At a sample position the reprojection is the identity and reproduces the baked
map exactly (every object pixel is a vertex of a drawn triangle or a point).

Threads and determinism: :func:`reproject_maps` splits the *output* rows into
bands, one per thread; a band draws, in the single-threaded order, every quad
that can reach its rows (found from bounds on each source row's destination
``y``: :meth:`Reprojection.row_y_range`) and writes only its own rows. Every
output pixel then sees the same sequence of writes and early-z tests whatever
the thread count: the z-buffer is bit-identical for 1, 2 or 4 threads.

Convention: pixel centres at integer ``(x, y)``, origin at the top-left pixel
centre (:mod:`morphkit.conventions`); a triangle covers the centres inside or
on its edges. Depths are linear light-camera ``Z``; ``+inf`` is background.

The kernel is compiled (numba); :func:`reproject_numpy` is an independent
vectorised reference used by the tests (``MORPHKIT_WARP_NUMPY=1`` selects it).

Modules:

* :mod:`.motion` -- :class:`Reprojection` (how one map's pixels move), the
  measured constants and the per-row analysis of a map;
* :mod:`.kernels` -- the compiled rasterising kernels and the numpy reference
  :func:`reproject_numpy`;
* :mod:`.maps` -- :class:`Source`, :class:`Layer`, :func:`hidden_layer` and
  :func:`reproject_maps` (bands of output rows over threads).
"""

from __future__ import annotations

from .kernels import reproject_numpy
from .maps import Layer, Source, hidden_layer, reproject_maps
from .motion import (
    EARLY_Z_TEXELS,
    LAYER_TEXELS,
    PARALLEL_MIN_SOURCE_PIXELS,
    STRETCH_PX,
    Reprojection,
    orphans,
    row_depth_range,
    row_spans,
    support_box,
)

__all__ = ["EARLY_Z_TEXELS", "LAYER_TEXELS", "PARALLEL_MIN_SOURCE_PIXELS", "STRETCH_PX",
           "Layer", "Reprojection", "Source", "hidden_layer", "orphans", "reproject_maps",
           "reproject_numpy", "row_depth_range", "row_spans", "support_box"]
