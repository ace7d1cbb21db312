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
pairs are merged (the count used is :attr:`LayerReport.layers`). ``layers="auto"``
builds one mesh first and uses :data:`tol.VM_AUTO_LAYERS` layers only when
more than :data:`tol.VM_AUTO_LAYER_DROP` of the pairs were dropped to
fold-overs (:attr:`LayerReport.auto_dropped_fraction`): a mesh that had to give up
that many points cannot follow the motion, a sign of parts crossing. Inside a slice,
points can only swap order over distances below the slice's disparity range,
so its fold-overs are small. Costs one morph per layer (the near layers over
their own region only). Pixels in an overlap band are drawn by both layers:
exact where opaque; a semi-transparent (anti-aliased) pixel there gets alpha
``a (2 - a)`` instead of ``a`` (disjoint pixel sets leave cracks at the cut;
``layer_overlap=0`` gives them).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..validate import as_image, as_int
from ..warp import OUTSIDE, MeshWarper
from .correspondences import Correspondences
from .mesh import build_morph_mesh, mesh_canvas
from .rectify import apply_h

__all__ = ["MorphLayer", "LayerReport", "known_mix", "FAR_POSITION", "build_layer", "build_layers",
           "check_depth_keys", "depth_slices", "concat_correspondences", "mask_bbox", "depth_edges"]

#: Sampling position (pixels, both coordinates) of the C1 look-up's cells the mesh
#: does not cover, and the border value read off the look-up: far outside any image.
FAR_POSITION = -1.0e5


@dataclass
class MorphLayer:
    """One depth layer: its premultiplied images, its morph mesh and the look-ups built from it.

    Parameters
    ----------
    prem : (prem0, prem1)
        float32 ``(H_i, W_i, C + 1)`` premultiplied images of the layer
        (:func:`morphkit.imaging.composite.to_premultiplied`; alpha 0 outside the slice).
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
    known : bool
        ``prem`` carries a last "known" channel (``fill_occluded``).
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
    #: ``prem`` carries a last "known" channel (``fill_occluded``; :func:`known_mix`).
    known: bool = False


@dataclass(frozen=True)
class LayerReport:
    """What :func:`build_layers` chose.

    Parameters
    ----------
    layers : int
        The number of layers used (fewer than asked when a slice had too few pairs).
    layer_edges : tuple of float
        The inner depth cuts (empty with one layer).
    auto_dropped_fraction : float or None
        For ``layers="auto"``: the fraction of the pairs one mesh dropped to
        fold-overs (None otherwise).
    fill_occluded : bool
        The layers carry a "known" channel (:func:`known_mix`): asked for and more than one layer.
    """

    layers: int
    layer_edges: tuple[float, ...] = ()
    auto_dropped_fraction: float | None = None
    fill_occluded: bool = False


def known_mix(a0: np.ndarray, a1: np.ndarray, s: float) -> np.ndarray:
    """Mix two warped premultiplied images whose last channel is a "known" weight.

    ``(k0 (1 - s) a0 + k1 s a1) / (k0 (1 - s) + k1 s)``, 0 where neither is known;
    the known channel is dropped (``fill_occluded``: where a nearer layer hides this
    one in one image, the other image fills it at full weight).

    Parameters
    ----------
    a0, a1 : numpy.ndarray
        float32 ``(h, w, C + 2)``: premultiplied colour, alpha, then the known weight.
    s : float
        The morph fraction in ``[0, 1]``.

    Returns
    -------
    numpy.ndarray
        float32 ``(h, w, C + 1)`` premultiplied colour and alpha.
    """
    w0 = a0[..., -1:] * np.float32(1.0 - s)
    w1 = a1[..., -1:] * np.float32(s)
    wsum = w0 + w1
    num = a0[..., :-1] * w0 + a1[..., :-1] * w1
    return np.where(wsum > tol.ALPHA_FLOOR, num / np.maximum(wsum, np.float32(tol.ALPHA_FLOOR)),
                    np.float32(0.0)).astype(np.float32)


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
    scale = max(1.0, float(np.abs(zs).max()))
    for _ in range(100):
        mids = 0.5 * (centres[1:] + centres[:-1])
        lab = np.searchsorted(mids, zs)
        new = np.array([zs[lab == i].mean() if np.any(lab == i) else centres[i] for i in range(n)])
        if np.allclose(new, centres, rtol=0.0, atol=tol.VM_KMEANS_CONVERGED_REL * scale):
            break
        centres = new
    return np.r_[zs[0], 0.5 * (centres[1:] + centres[:-1]), zs[-1]]


def depth_slices(z: np.ndarray, layers: int, overlap: float
                 ) -> tuple[np.ndarray, list[tuple[float, float]], list[np.ndarray]]:
    """Split the pairs' depths into at most ``layers`` overlapping slices.

    :func:`depth_edges` cuts the depths; neighbouring slices overlap by
    ``overlap`` times the depth range; the nearest slice reaches to ``-inf``
    and the farthest to ``+inf``. Fewer slices are used while one would hold
    fewer than :data:`tol.VM_MIN_LAYER_PAIRS` pairs.

    Parameters
    ----------
    z : (N,) float
        The pairs' depths (:attr:`Correspondences.depth`).
    layers : int
        Most slices wanted, ``>= 1``.
    overlap : float
        Overlap of neighbouring slices, a fraction of the depth range.

    Returns
    -------
    edges : numpy.ndarray
        ``(n + 1,)`` float64 cuts (:func:`depth_edges`), ``n`` the slices used.
    limits : list of (float, float)
        Each slice's inclusive depth range, near to far.
    selections : list of numpy.ndarray
        Each slice's ``(N,)`` bool selection of the pairs.
    """
    n = min(int(layers), max(1, len(z) // tol.VM_MIN_LAYER_PAIRS))
    while True:
        edges = depth_edges(z, n)
        m = float(overlap) * float(edges[-1] - edges[0])
        lims = [(-np.inf if i == 0 else edges[i] - m, np.inf if i == n - 1 else edges[i + 1] + m)
                for i in range(n)]
        sels = [(z >= a) & (z <= b) for a, b in lims]
        if n == 1 or min(int(c.sum()) for c in sels) >= tol.VM_MIN_LAYER_PAIRS:
            return edges, lims, sels
        n -= 1


def check_depth_keys(layer_depth: Any, shape0: tuple[int, int], shape1: tuple[int, int]) -> list[np.ndarray]:
    """The two per-pixel depth-key images, validated.

    Parameters
    ----------
    layer_depth : (key0, key1)
        ``(H_i, W_i)`` depth keys of the two images (``+inf`` for background;
        :func:`~morphkit.viewmorph.pair_depth`).
    shape0, shape1 : (H, W)
        The images' shapes.

    Returns
    -------
    list of numpy.ndarray
        ``[key0, key1]`` as float64 ``(H_i, W_i)``.

    Raises
    ------
    ValidationError
        Not two single-channel images of the images' shapes, or NaN values.
    """
    if layer_depth is None or len(layer_depth) != 2:
        raise ValidationError(expected_got(
            "layer_depth", "(key0, key1) per-pixel depth keys for layers > 1 or 'auto' "
            "(viewmorph.pair_depth)", type(layer_depth).__name__))
    keys = []
    for key, shape, name in ((layer_depth[0], shape0, "layer_depth[0]"),
                             (layer_depth[1], shape1, "layer_depth[1]")):
        k = as_image(key, name, channels=(1,), allow_nonfinite=True).astype(np.float64)
        if k.shape != shape:
            raise ValidationError(expected_got(name, f"shape {shape} (its image's)", f"shape {k.shape}"))
        if np.isnan(k).any():
            raise ValidationError(expected_got(name, "depths, +inf for background", "NaN values"))
        keys.append(k)
    return keys


def build_layer(prem: tuple[np.ndarray, np.ndarray], corr: Correspondences,
                bbox: tuple[np.ndarray, np.ndarray], frame_grid: int, H_rect_0: np.ndarray,
                H_rect_1: np.ndarray) -> MorphLayer:
    """Mesh (frame points + pairs, fold-overs resolved), warpers and the C1 look-up of one layer.

    Parameters
    ----------
    prem : (prem0, prem1)
        The layer's premultiplied images (float32 ``(H_i, W_i, C + 1)``).
    corr : Correspondences
        The layer's pairs.
    bbox : (lo, hi)
        ``(2,)`` float corners of the layer's canvas in the rectified frame
        (:func:`~morphkit.viewmorph.mesh.mesh_canvas`).
    frame_grid : int
        Side of the frame-point lattice.
    H_rect_0, H_rect_1 : (3, 3) float
        The pre-warps (image-``i`` pixels to the rectified frame).

    Returns
    -------
    MorphLayer

    Raises
    ------
    FoldOverError
        The mesh still folds after dropping vertices.
    """
    r0c, r1c = apply_h(H_rect_0, corr.pts0), apply_h(H_rect_1, corr.pts1)
    r0, r1, tris, idx, ndrop = build_morph_mesh(r0c, r1c, bbox, frame_grid, corr.depth)
    used = idx[idx >= 0]
    is_corr = idx >= 0
    # vertex positions in the original images (correspondences exactly, frame points by H^-1)
    p0 = apply_h(np.linalg.inv(H_rect_0), r0)
    p1 = apply_h(np.linalg.inv(H_rect_1), r1)
    p0[is_corr] = corr.pts0[used]
    p1[is_corr] = corr.pts1[used]
    w0, w1 = MeshWarper(p0, tris), MeshWarper(p1, tris)
    # C1: for each image-0 pixel of the mesh's footprint, its image-1 position (s-independent)
    lo0 = np.floor(p0.min(axis=0)) - 1
    hi0 = np.ceil(p0.max(axis=0)) + 1
    c1_shape = (int(hi0[1] - lo0[1]) + 1, int(hi0[0] - lo0[0]) + 1)
    wm = w1.maps(p0 - lo0, c1_shape)
    c1 = np.full(c1_shape + (2,), FAR_POSITION, np.float32)
    r_0, r_1, c_0, c_1 = wm.roi
    c1[r_0:r_1, c_0:c_1] = np.where(wm.mask[r_0:r_1, c_0:c_1, None], wm.map_xy, np.float32(FAR_POSITION))
    # Does the warp's position for uncovered pixels fall >= 2 px off the C1 canvas?
    c1_far = float(OUTSIDE) - float(lo0.max()) <= -2.0
    lo, hi = bbox
    return MorphLayer(prem, (np.floor(lo), np.ceil(hi)), r0, r1, tris, is_corr, corr.subset(used), ndrop,
                      w0, w1, lo0, c1, c1_far)


def build_layers(prem: tuple[np.ndarray, np.ndarray], corr: Correspondences, layers: int | str,
                 layer_depth: Any, overlap: float, frame_grid: int, *, H_rect_0: np.ndarray,
                 H_rect_1: np.ndarray, shape0: tuple[int, int], shape1: tuple[int, int],
                 fill_occluded: bool = False) -> tuple[list[MorphLayer], LayerReport]:
    """Split pairs and pixels into depth layers (module docstring) and build each layer.

    Parameters
    ----------
    prem : (prem0, prem1)
        The whole premultiplied images (float32 ``(H_i, W_i, C + 1)``).
    corr : Correspondences
        The cleaned inlier pairs; with ``depth`` unless ``layers == 1``.
    layers : int or "auto"
        Layers wanted (see :class:`~morphkit.viewmorph.morph.ViewMorpher`).
    layer_depth : (key0, key1) or None
        Per-pixel depth keys (:func:`check_depth_keys`); needed unless ``layers == 1``.
    overlap : float
        Overlap of neighbouring slices, a fraction of the pairs' depth range.
    frame_grid : int
        Side of each layer's frame-point lattice.
    H_rect_0, H_rect_1 : (3, 3) float
        The pre-warps (image-``i`` pixels to the rectified frame).
    shape0, shape1 : (H, W)
        The images' shapes.
    fill_occluded : bool
        Give each layer a "known" channel (not hidden by a nearer layer) so the
        other image fills what one image does not see (:func:`known_mix`).

    Returns
    -------
    layers : list of MorphLayer
        Near to far; the last covers the whole images.
    report : LayerReport
        The count used, and for ``"auto"`` the fraction one mesh dropped, for
        several layers the inner depth cuts.

    Raises
    ------
    ValidationError
        ``layers != 1`` without pair depths or valid depth keys.
    """
    full = mesh_canvas(H_rect_0, H_rect_1, corr.pts0, corr.pts1, shape0, shape1)
    if layers == 1:
        return [build_layer(prem, corr, full, frame_grid, H_rect_0, H_rect_1)], LayerReport(1)
    if corr.depth is None:
        raise ValidationError(expected_got(
            "correspondences", "pairs with depths for layers > 1 or 'auto' (from_geometry or from_depth)",
            "pairs without depth"))
    keys = check_depth_keys(layer_depth, shape0, shape1)
    if layers == "auto":
        one = build_layer(prem, corr, full, frame_grid, H_rect_0, H_rect_1)
        frac: float | None = float(one.n_dropped / max(len(corr), 1))
        if frac <= tol.VM_AUTO_LAYER_DROP:
            return [one], LayerReport(1, auto_dropped_fraction=frac)
        layers = tol.VM_AUTO_LAYERS
    else:
        frac = None
    layers = as_int(layers, "layers", lo=1)
    edges, lims, sels = depth_slices(corr.depth, layers, overlap)
    n = len(lims)
    report = LayerReport(n, tuple(float(e) for e in edges[1:-1]), frac, bool(fill_occluded) and n > 1)
    out = []
    for i, ((a, b), sel) in enumerate(zip(lims, sels, strict=True)):
        masks = [(k >= a) & (k <= b) for k in keys]
        prem_i = (prem[0] * masks[0][..., None], prem[1] * masks[1][..., None])
        if report.fill_occluded:
            # last channel: "known" = not hidden by a nearer layer (key in front of this layer's range)
            prem_i = (np.concatenate([prem_i[0], (keys[0] >= a)[..., None].astype(np.float32)], axis=2),
                      np.concatenate([prem_i[1], (keys[1] >= a)[..., None].astype(np.float32)], axis=2))
        sub = corr.subset(sel)
        if i == n - 1:
            bbox = full  # the farthest layer holds the background: the whole images
        else:
            boxes = [np.zeros((0, 2)) if b_ is None else b_ for b_ in (mask_bbox(mk) for mk in masks)]
            bbox = mesh_canvas(H_rect_0, H_rect_1, sub.pts0, sub.pts1, shape0, shape1, *boxes)
        layer = build_layer(prem_i, sub, bbox, frame_grid, H_rect_0, H_rect_1)
        layer.known = report.fill_occluded
        out.append(layer)
    return out, report
