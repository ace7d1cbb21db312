"""The warp plan of a fixed source mesh (:class:`MeshWarper`) and the one-call
:func:`warp_mesh`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import cv2
import numpy as np

from .. import tol
from ..errors import FoldOverError, ValidationError, expected_got
from ..settings import use_compiled
from ..validate import as_shape
from . import scanline
from .accumulate import Accumulation
from .build import build_maps, prepare
from .maps import WarpMaps, interp_flag
from .mesh import (
    as_mesh_points,
    as_triangles,
    boundary_edges,
    default_triangles,
    disk_boundary,
    list_indices,
    signed_area,
)

__all__ = ["MeshWarper", "warp_mesh"]


class MeshWarper:
    """A reusable warp plan for a fixed source mesh (points + triangles).

    Parameters
    ----------
    src_pts : array_like
        ``(N, 2)`` source control points ``(x, y)`` in input-image pixels.
    triangles : array_like, optional
        ``(M, 3)`` vertex indices. Default: :func:`~morphkit.warp.grid_triangles`
        when ``src_pts`` is a row-major axis-aligned lattice
        (:func:`~morphkit.warp.grid_shape`), else
        :func:`~morphkit.warp.delaunay_triangles` of ``src_pts``.

    Raises
    ------
    ValidationError
        Non-finite or malformed points, a coordinate beyond
        :data:`tol.MAX_COORD_PX`, bad triangle indices.
    FoldOverError
        A source triangle has ``|area| < tol.TRIANGLE_AREA_PX2``.

    Notes
    -----
    Per call, :meth:`maps` costs O(M + covered rows) work for the per-triangle
    affines and the exact scanline runs, plus O(pixels in the mesh's bounding
    box) to expand the runs into float32 maps; applying them is one
    ``cv2.remap``. Measure with ``morphkit bench warp``.

    References
    ----------
    .. [1] A. Goshtasby, "Piecewise linear mapping functions for image registration", Pattern
       Recognition, 19(6), pp. 459-466, 1986.

    Examples
    --------
    One source mesh (a quad on the corner pixels' centres of a 5 x 5 image, two
    triangles), warped to several destinations: the triangulation and the
    source side are set up once. Shrinking the quad to half its size around
    pixel ``(0, 0)`` samples the source at twice the spacing: output pixel
    ``(x, y)`` reads source pixel ``(2x, 2y)``.

    >>> import numpy as np
    >>> from morphkit.warp import MeshWarper
    >>> img = np.arange(25, dtype=np.float32).reshape(5, 5)
    >>> src = np.array([[0, 0], [4, 0], [0, 4], [4, 4]], float)
    >>> warper = MeshWarper(src)
    >>> warper.triangles.shape
    (2, 3)
    >>> warper(img, src / 2, (3, 3))
    array([[ 0.,  2.,  4.],
           [10., 12., 14.],
           [20., 22., 24.]], dtype=float32)
    >>> bool(np.array_equal(warper(img, src, (5, 5)), img))
    True
    """

    def __init__(self, src_pts: Any, triangles: Any = None) -> None:
        self.src_pts = as_mesh_points(src_pts, "src_pts", min_count=3)
        self.src_pts.setflags(write=False)
        if triangles is None:
            tris = default_triangles(self.src_pts)
        else:
            tris = as_triangles(triangles, self.src_pts.shape[0])
        tris = np.ascontiguousarray(tris, dtype=np.int64)  # as the compiled kernels take them
        tris.setflags(write=False)
        self.triangles = tris
        self._src_v = self.src_pts[tris]  # (M, 3, 2)
        area = signed_area(self._src_v)
        small = np.flatnonzero(np.abs(area) < tol.TRIANGLE_AREA_PX2)
        if small.size:
            raise FoldOverError(
                expected_got("source triangles", f"|area| >= {tol.TRIANGLE_AREA_PX2} px^2",
                             f"degenerate triangles {list_indices(small)}")
            )
        self._src_sign = np.sign(area)
        self._boundary = boundary_edges(tris, self.n_points)
        self._loop = disk_boundary(tris, self._src_sign)

    @property
    def n_points(self) -> int:
        """Number of control points ``N``."""
        return int(self.src_pts.shape[0])

    def _check_dst(self, dst_pts: Any) -> np.ndarray:
        dst = as_mesh_points(dst_pts, "dst_pts")
        if dst.shape[0] != self.n_points:
            raise ValidationError(
                expected_got("dst_pts", f"{self.n_points} points (as many as src_pts)", f"{dst.shape[0]}")
            )
        return dst

    def maps(self, dst_pts: Any, out_shape: Sequence[int]) -> WarpMaps:
        """Compute the sampling maps (and coverage) for destination points ``dst_pts``.

        Parameters
        ----------
        dst_pts : array_like
            ``(N, 2)`` destination control points ``(x, y)`` in output pixels.
        out_shape : (int, int)
            ``(H, W)`` of the output.

        Returns
        -------
        WarpMaps

        Raises
        ------
        ValidationError
            Wrong point count, NaN/inf points or beyond :data:`tol.MAX_COORD_PX`, bad ``out_shape``.
        FoldOverError
            Flipped or ~zero-area destination triangles, or overlapping ones.
        """
        dst = self._check_dst(dst_pts)
        shape = as_shape(out_shape, "out_shape")
        return build_maps(dst, self.triangles, self._src_v, self._src_sign, self._boundary, shape,
                           self._loop)

    def triangles_touching(self, support: Any) -> np.ndarray:
        """``(M,)`` bool: the triangles whose source footprint can read a nonzero
        pixel of ``support`` (``(h, w)``, the input image's nonzero pixels) with
        ``"linear"`` sampling: its bounding box, grown by 2 px, holds one. A warp
        of the other triangles only reads zeros (see :func:`~morphkit.warp.accumulate_warps`).

        Parameters
        ----------
        support : (h, w) array
            The input image's support (nonzero where it holds something), input pixels.

        Returns
        -------
        (M,) bool
            True for the triangles whose warp can read a nonzero pixel.
        """
        sup = np.asarray(support)
        if sup.ndim != 2 or sup.size == 0:
            raise ValidationError(expected_got("support", "a non-empty (h, w) array", sup.shape))
        h, w = sup.shape
        ii = cv2.integral((sup != 0).view(np.uint8), sdepth=cv2.CV_32S)  # (h + 1, w + 1)
        lo = np.floor(self._src_v.min(axis=1)) - 2
        hi = np.ceil(self._src_v.max(axis=1)) + 3
        x0, x1 = (np.clip(v, 0, w).astype(np.intp) for v in (lo[:, 0], hi[:, 0]))
        y0, y1 = (np.clip(v, 0, h).astype(np.intp) for v in (lo[:, 1], hi[:, 1]))
        return (ii[y1, x1] - ii[y0, x1] - ii[y1, x0] + ii[y0, x0]) > 0

    def accumulation(self, dst_pts: Any, shape: tuple[int, int]) -> Accumulation | WarpMaps:
        """The plan of this mesh warped to ``dst_pts``, for :func:`~morphkit.warp.accumulate_warps`.

        Parameters
        ----------
        dst_pts : array_like
            ``(N, 2)`` destination control points ``(x, y)`` in output pixels.
        shape : tuple[int, int]
            ``(H, W)`` of the accumulator (not validated: a per-frame path).

        Returns
        -------
        Accumulation or WarpMaps
            An :class:`~morphkit.warp.Accumulation` (the compiled fused pass)
            when the mesh provably does not overlap itself; else :meth:`maps`
            (also without numba, or with ``MORPHKIT_WARP_NUMPY=1``).

        Raises
        ------
        ValidationError
            Wrong point count, NaN/inf points.
        FoldOverError
            As :meth:`maps`, before any pixel is touched.
        """
        dst = np.asarray(dst_pts, dtype=np.float64)
        if dst.shape != self.src_pts.shape or not (np.abs(dst) <= tol.MAX_COORD_PX).all():
            dst = self._check_dst(dst_pts)  # raises the full message (a per-frame path: checked lean)
        if use_compiled(scanline.accumulate) and self._loop is not None:
            cov, coef, roi = prepare(dst, self.triangles, self._src_v, self._src_sign,
                                      self._boundary, shape)
            r0, r1, c0, c1 = roi
            if r1 <= r0 or c1 <= c0:
                return WarpMaps(shape, roi, None, None, None)
            if scanline.mesh_injective(cov, self.triangles, self._src_sign, self._loop):
                return Accumulation(cov, coef, self.triangles, roi)
        return self.maps(dst, shape)

    def __call__(self, image: Any, dst_pts: Any, out_shape: Sequence[int], *,
                 interpolation: str = "linear", fill: Any = 0.0,
                 return_mask: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Warp ``image`` onto the destination mesh ``dst_pts``; see :func:`warp_mesh`."""
        interp_flag(interpolation)
        wm = self.maps(dst_pts, out_shape)
        out = wm.apply(image, interpolation=interpolation, fill=fill)
        return (out, wm.mask) if return_mask else out


def warp_mesh(image: Any, src_pts: Any, dst_pts: Any, out_shape: Sequence[int], *,
              triangles: Any = None, interpolation: str = "linear", fill: Any = 0.0,
              return_mask: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Piecewise-affine warp of ``image`` moving ``src_pts`` onto ``dst_pts``.

    Convention: each destination triangle ``dst_pts[tri]`` is filled by sampling
    ``image`` at the affinely corresponding point of the source triangle
    ``src_pts[tri]`` (a backward map, as ``cv2.remap``); points are ``(x, y)``
    with the origin at the centre of the top-left pixel. Details, fill rule and
    the fold-over/non-finite policy: see :mod:`morphkit.warp`.

    Parameters
    ----------
    image : numpy.ndarray
        ``(h, w)`` or ``(h, w, C)``, any numeric or bool dtype (uint8 RGB/RGBA,
        float32 depth with ``+inf`` background, ...); NaN pixels are refused.
    src_pts, dst_pts : array_like
        ``(N, 2)`` control points in the input and the output image.
    out_shape : (int, int)
        ``(H, W)`` of the output.
    triangles : array_like, optional
        ``(M, 3)`` vertex indices; default grid topology for lattice ``src_pts``,
        else Delaunay of ``src_pts``.
    interpolation : {"linear", "nearest"}
    fill : float or sequence of float
        Value outside the mesh (and for source positions outside ``image``).
    return_mask : bool
        Also return the ``(H, W)`` bool mask of pixels covered by the mesh.

    Returns
    -------
    numpy.ndarray or (numpy.ndarray, numpy.ndarray)
        The warped image (``out_shape`` + channels, dtype of ``image``), and the
        mask when ``return_mask``.

    Raises
    ------
    ValidationError
        Mismatched point counts, NaN/inf points or beyond :data:`tol.MAX_COORD_PX`, bad
        triangles, bad interpolation, NaN pixels in ``image``.
    FoldOverError
        Flipped, ~zero-area or overlapping destination triangles.

    Examples
    --------
    Move a 4 x 4 image one pixel to the right with one quad (two triangles) on the
    corner pixels' centres; column 0 is outside the moved mesh and gets ``fill``:

    >>> import numpy as np
    >>> from morphkit.warp import warp_mesh
    >>> img = np.arange(16, dtype=np.float32).reshape(4, 4)
    >>> src = np.array([[0, 0], [3, 0], [0, 3], [3, 3]], float)
    >>> out, mask = warp_mesh(img, src, src + [1, 0], (4, 4), return_mask=True)
    >>> out
    array([[ 0.,  0.,  1.,  2.],
           [ 0.,  4.,  5.,  6.],
           [ 0.,  8.,  9., 10.],
           [ 0., 12., 13., 14.]], dtype=float32)
    >>> mask[0]
    array([False,  True,  True,  True])
    """
    return MeshWarper(src_pts, triangles)(image, dst_pts, out_shape, interpolation=interpolation,
                                          fill=fill, return_mask=return_mask)
