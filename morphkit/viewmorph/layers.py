"""Depth layers of a view morph: depth slices and the per-layer data.

Depth layers
------------
One mesh cannot show parts that pass behind each other between the views (a
chair's back leg crossing behind a front leg: Seitz & Dyer's monotonicity
assumption fails, the crossing triangles fold and their points are dropped, so
the hidden part is smeared). ``layers=k`` (with ``layer_depth``, per-pixel
depth keys of both images from :func:`~morphkit.viewmorph.pair_depth`, and
pairs carrying depths, from :func:`~morphkit.viewmorph.from_geometry` or
:func:`~morphkit.viewmorph.from_depth`) splits the pairs into ``k`` depth
slices by 1-D k-means of their depths (cuts fall in the gaps between separate
parts, and evenly through a continuous range; overlapping by :data:`tol.VM_LAYER_OVERLAP` of the
depth range) and the pixels of each image by the same limits (background goes
to the farthest layer). Each layer has its own mesh in the *shared* rectified
frame (one F, one pre-warp, one post-warp for all), its own premultiplied
images, and a canvas fitted to its pixels (the farthest layer: the whole
images); the layers are morphed separately and composited far to near with the
premultiplied "over". Layers with fewer than :data:`tol.VM_MIN_LAYER_PAIRS`
pairs are merged (the count used is ``report["layers"]``). ``layers="auto"``
builds one mesh first and uses :data:`tol.VM_AUTO_LAYERS` layers only when
more than :data:`tol.VM_AUTO_LAYER_DROP` of the pairs were dropped to
fold-overs (``report["auto_dropped_fraction"]``): a mesh that had to give up
that many points cannot follow the motion, a sign of parts crossing. Inside a slice,
points can only swap order over distances below the slice's disparity range,
so its fold-overs are small. Costs one morph per layer (the near layers over
their own region only). Pixels in an overlap band are drawn by both layers:
exact where opaque; a semi-transparent (anti-aliased) pixel there gets alpha
``a (2 - a)`` instead of ``a`` (disjoint pixel sets, measured on the chair at
20 degrees, cost 0.7 dB PSNR through cracks at the cut; ``layer_overlap=0``
gives them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..warp import MeshWarper
from .correspondences import Correspondences

__all__ = ["MorphLayer", "concat_correspondences", "mask_bbox", "depth_edges"]


@dataclass
class MorphLayer:
    """One depth layer: its premultiplied images, its morph mesh and the look-ups built from it.

    Attributes
    ----------
    prem : (prem0, prem1)
        float32 ``(H_i, W_i, C + 1)`` premultiplied images of the layer
        (:func:`morphkit.composite.to_premultiplied`; alpha 0 outside the slice).
    canvas : (lo, hi)
        ``(2,)`` float64 integer-valued corners of the layer's canvas in the
        rectified frame.
    r0, r1 : numpy.ndarray
        ``(V, 2)`` float64 vertex positions in the rectified frame at ``s = 0``
        and ``s = 1``.
    tris : numpy.ndarray
        ``(M, 3)`` int32 triangles indexing the vertices.
    is_corr : numpy.ndarray
        ``(V,)`` bool: True for the vertices that are pairs (in the order of
        ``corr``), False for frame points.
    corr : Correspondences
        The layer's pairs kept in the mesh.
    n_dropped : int
        Pairs dropped to fold-overs.
    w0, w1 : MeshWarper
        The mesh with its vertices in image-0 / image-1 pixels (source meshes
        of the backward warps).
    c1_origin : numpy.ndarray
        ``(2,)`` float64: the image-0 pixel at ``c1[0, 0]``.
    c1 : numpy.ndarray
        ``(h, w, 2)`` float32: for image-0 pixel ``c1_origin + (x, y)``, its
        image-1 position through the mesh (piecewise affine, independent of
        ``s``); far outside where the mesh does not cover.
    c1_far : bool
        The warp's position for output pixels outside the mesh falls at least
        2 px off ``c1``: a look-up there reads "far outside" without a mask.
    rectified : (rect0, rect1) or None
        The pre-warped images on ``canvas`` (cached for ``path="rectified"``).
    """

    prem: tuple[np.ndarray, np.ndarray]
    canvas: tuple[np.ndarray, np.ndarray]
    r0: np.ndarray
    r1: np.ndarray
    tris: np.ndarray
    is_corr: np.ndarray
    corr: Correspondences
    n_dropped: int
    w0: MeshWarper
    w1: MeshWarper
    c1_origin: np.ndarray
    c1: np.ndarray
    c1_far: bool
    rectified: tuple[np.ndarray, np.ndarray] | None = None


def concat_correspondences(parts: list[Correspondences]) -> Correspondences:
    """The pairs of several :class:`Correspondences` in order (3-D points/depths kept if all have them).

    Parameters
    ----------
    parts : list of Correspondences
        At least one; the source of the first is kept.

    Returns
    -------
    Correspondences
        ``sum(len(p))`` pairs; ``points3d``/``depth`` None unless every part has them.
    """
    p3 = None if any(c.points3d is None for c in parts) else np.concatenate([c.points3d for c in parts])
    dep = None if any(c.depth is None for c in parts) else np.concatenate([c.depth for c in parts])
    return Correspondences(np.concatenate([c.pts0 for c in parts]), np.concatenate([c.pts1 for c in parts]),
                           parts[0].source, p3, dep)


def mask_bbox(mask: np.ndarray) -> np.ndarray | None:
    """Corners (pixel edges) of the bounding box of ``mask``'s True pixels, or None.

    Parameters
    ----------
    mask : (H, W) bool

    Returns
    -------
    numpy.ndarray or None
        ``(4, 2)`` float64 pixel positions (outer pixel edges, pixel-centre
        origin), clockwise from the top left; None when no pixel is True.
    """
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return None
    x0, x1, y0, y1 = cols[0] - 0.5, cols[-1] + 0.5, rows[0] - 0.5, rows[-1] + 0.5
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)


def depth_edges(z: np.ndarray, n: int) -> np.ndarray:
    """Limits ``[min, e_1, ..., e_{n-1}, max]`` of ``n`` depth slices of ``z``: 1-D k-means
    (Lloyd's iterations from the quantiles; the edges are the midpoints between centres),
    so that slices part at the gaps between separate parts and evenly through a continuum.

    Parameters
    ----------
    z : (N,) float
        Depths (finite, ``N >= 1``).
    n : int
        Number of slices, ``>= 1``.

    Returns
    -------
    numpy.ndarray
        ``(n + 1,)`` float64 increasing limits, ``min(z)`` first and ``max(z)`` last.
    """
    zs = np.sort(np.asarray(z, dtype=np.float64))
    centres = np.quantile(zs, (np.arange(n) + 0.5) / n)
    for _ in range(100):
        mids = 0.5 * (centres[1:] + centres[:-1])
        lab = np.searchsorted(mids, zs)
        new = np.array([zs[lab == i].mean() if np.any(lab == i) else centres[i] for i in range(n)])
        if np.allclose(new, centres, rtol=0.0, atol=1e-12 * max(1.0, float(np.abs(zs).max()))):
            break
        centres = new
    return np.r_[zs[0], 0.5 * (centres[1:] + centres[:-1]), zs[-1]]
