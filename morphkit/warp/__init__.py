"""Piecewise-affine mesh warping: fast, exact at pixel centres, and reusable.

Convention
----------
* **Direction.** A warp is given by a *source* mesh ``src_pts`` (in the input
  image) and a *destination* mesh ``dst_pts`` (in the output image) with the same
  triangles. Each output pixel ``p`` inside destination triangle ``t`` is filled by
  sampling the input image at ``A_src_dst[t] @ (x, y, 1)``, the affine map taking
  the destination triangle onto the source triangle (a *backward* warp, like
  ``cv2.remap``/``skimage.transform.warp``). Points move *from* ``src_pts`` *to*
  ``dst_pts``.
* **Pixels.** ``(x, y)`` order, ``x`` = column, ``y`` = row, origin at the
  **centre** of the top-left pixel (see :mod:`morphkit.conventions`): the same
  convention as ``cv2.warpAffine`` and ``skimage.transform.warp``.
* **Coverage.** Output pixel centres are assigned to triangles exactly, with a
  top-left fill rule: a pixel centre ``(x, y)`` belongs to the triangle whose
  row section ``[x_left(y), x_right(y))`` contains ``x`` and whose rows
  ``[y_min, y_max)`` contain ``y``. Each covered centre belongs to exactly one
  triangle of a mesh without fold-overs; shared edges give both sides the same,
  bit-identical crossing. The mesh as a whole is *closed*: for coverage its
  boundary is pushed outwards by :data:`morphkit.tol.MESH_BOUNDARY_PX`, so
  centres on the boundary (e.g. the last row and column of an identity warp)
  are covered. Pixels outside every destination triangle get ``fill`` and
  ``mask == False``.
* **Sampling.** ``cv2.remap`` with ``BORDER_CONSTANT``: source positions outside
  the input image read ``fill`` (linearly blended at the image border). Like
  ``cv2.warpAffine``, OpenCV quantises sub-pixel positions to 1/32 px for
  ``"linear"``; the maps themselves are exact (float32).
* **Non-finite pixels** (e.g. depth maps whose background is ``+inf``) are safe
  with ``"linear"``: an output pixel whose bilinear footprint touches a non-finite
  source value (or a non-finite ``fill`` at the image border) takes the
  ``"nearest"`` value instead, so ``inf * 0`` never produces NaN. ``"nearest"``
  never mixes values and is the right choice for depth at silhouettes. NaN
  pixels are refused (:class:`~morphkit.errors.ValidationError` naming their
  count): they would spread through the output without a word.

Fold-over policy
----------------
morphkit refuses degenerate warps rather than repairing them:
:class:`~morphkit.errors.FoldOverError` (naming the triangle indices) is raised
when a destination triangle's orientation differs from its source triangle's,
when its ``|area|`` is below :data:`morphkit.tol.TRIANGLE_AREA_PX2`, or when two
destination triangles cover the same output pixel centre (a mesh that folds over
while each triangle keeps its orientation). A source triangle of ~zero area is
refused the same way when the :class:`MeshWarper` is built. Bad arguments
(mismatched counts, NaN/inf points, points farther than
:data:`morphkit.tol.MAX_COORD_PX` from the origin in x or y, triangle indices out
of range, unknown interpolation, NaN pixels) raise
:class:`~morphkit.errors.ValidationError`.

Reuse
-----
:class:`MeshWarper` keeps what depends on the source mesh only (validated points,
triangles, source orientation, boundary edges). :meth:`MeshWarper.maps` turns
destination points into :class:`WarpMaps` (per-pixel sampling maps of the mesh's
bounding box plus the coverage mask), which :meth:`WarpMaps.apply` applies to any
number of images or channels at the cost of one ``cv2.remap`` each.

How the maps are built (per call, :mod:`.build`): per-triangle affines
``A_src_dst``, then by default one compiled pass (:mod:`.scanline`, numba) that
walks every destination triangle's pixel rows and writes each covered pixel's source
position, counting coverage to detect overlaps unless the mesh is a disk whose
boundary stays simple (it then cannot overlap: no count needed, and
:attr:`WarpMaps.mask` is counted only when asked for). The numpy path is the
reference (same coverage rule and edge arithmetic; ``tests/test_warp.py`` checks the
two agree) and runs when numba is missing or ``MORPHKIT_WARP_NUMPY=1``
(:func:`morphkit.settings.use_compiled`): exact scanline runs ``[x_left, x_right)``
for every (triangle, pixel row) pair; one integer sort of the runs along the image;
then either (<= 255 triangles) a uint8 triangle-label image expanded from the runs
and per-pixel affines by ``cv2.LUT`` + ``cv2.multiply``/``cv2.add``, or (more
triangles) the runs' slopes and offsets expanded with ``np.repeat``. Coordinate
planes and scratch buffers are kept per thread and output shape (:mod:`.pool`), and
the map buffers of a dropped :class:`WarpMaps` are recycled (only if nothing else
refers to them): fresh page-faulted memory costs as much as the arithmetic.
``MeshWarper`` and ``WarpMaps`` are safe to use from several threads only if each
thread has its own objects.

Fused accumulation (:mod:`.accumulate`, for callers that blend several warped
sources, e.g. the shadow atlas): :func:`accumulate_warps` adds
``weight * warp(src)`` of two-plane float32 sources straight into an accumulator,
sampling each pixel's source position bilinearly in the same compiled pass that finds it
(:func:`morphkit.warp.scanline.accumulate`): no map images, no remap, only the
triangles :meth:`MeshWarper.triangles_touching` says can read nonzero source pixels,
and bands of rows on :data:`WARP_THREADS` threads. Source positions are exact there
(OpenCV quantises them to 1/32 px); meshes that might overlap themselves, and the
numpy reference mode, go through :meth:`MeshWarper.maps`
(:meth:`MeshWarper.accumulation` chooses the :class:`Accumulation` plan).

Modules
-------
This package re-exports its public API; the modules hold one concept each:

* :mod:`.mesh` -- topology and its checks: :func:`grid_triangles`,
  :func:`delaunay_triangles`, :func:`grid_shape`, triangle validation,
  boundary edges, the topological-disk test.
* :mod:`.warper` -- :class:`MeshWarper` (the plan of a fixed source mesh) and
  :func:`warp_mesh`.
* :mod:`.build` -- building :class:`WarpMaps`: fold test, per-triangle
  affines, the compiled fill and the numpy reference path.
* :mod:`.maps` -- :class:`WarpMaps` and applying them: ``cv2.remap`` with
  constant borders, channel grouping (never two channels at once), dtype
  conversion, the non-finite guard; :data:`OUTSIDE`.
* :mod:`.accumulate` -- the fused accumulation: :func:`accumulate_warps`,
  :class:`Accumulation`, :func:`band_pool`, :func:`in_bands`, :func:`roi_union`,
  :data:`PARALLEL_MIN_PIXELS`.
* :mod:`.pool` -- per-thread coordinate planes and recycled map buffers.
* :mod:`.scanline` -- the compiled (numba) kernels: map fill, fused
  accumulation, per-call set-up, injectivity test.

:data:`WARP_THREADS` is :data:`morphkit.settings.WARP_THREADS` (environment
switches are read there only).

The piecewise-affine (piecewise linear) mapping is Goshtasby's [1]_; Wolberg [2]_ surveys
mesh warping.

References
----------
.. [1] A. Goshtasby, "Piecewise linear mapping functions for image registration", Pattern Recognition,
   19(6), pp. 459-466, 1986.
.. [2] G. Wolberg, *Digital Image Warping*, IEEE Computer Society Press, 1990.
"""

from __future__ import annotations

from ..settings import WARP_THREADS
from .accumulate import PARALLEL_MIN_PIXELS, Accumulation, accumulate_warps, band_pool, in_bands, roi_union
from .maps import OUTSIDE, WarpMaps
from .mesh import delaunay_triangles, grid_shape, grid_triangles
from .warper import MeshWarper, warp_mesh

__all__ = ["warp_mesh", "MeshWarper", "WarpMaps", "grid_triangles", "delaunay_triangles", "grid_shape",
           "OUTSIDE", "accumulate_warps", "Accumulation", "roi_union", "band_pool", "in_bands",
           "PARALLEL_MIN_PIXELS", "WARP_THREADS"]
