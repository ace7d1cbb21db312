"""View morphing (Seitz & Dyer 1996): pre-warp, morph, post-warp, for one reference pair.

:class:`ViewMorpher` does everything that depends on the reference pair once
(correspondence cleaning, F, the pre-warps, the morph mesh, premultiplied
images, warpers); each :meth:`ViewMorpher.morph` call for a new ``s`` then costs
the interpolation of the mesh, one mesh-map computation and two ``cv2.remap``.

Convention
----------
* Pixels: ``(x, y)``, origin at the centre of the top-left pixel
  (:mod:`morphkit.conventions`); shapes are ``(H, W)``.
* ``H0 = H_rect_0`` and ``H1 = H_rect_1`` map image pixels to the shared
  rectified frame (:mod:`morphkit.viewmorph.rectify`). The rectified positions of
  a pair, ``r0 = H0 p0`` and ``r1 = H1 p1``, share their ``y``; the morph at ``s``
  puts the pair at ``q(s) = (1 - s) r0 + s r1`` (rectified-interpolated frame).
* The post-warp ``P = H_out_rect`` maps that frame to output pixels. Default
  (``post="interpolate"``): the homography taking the interpolated rectified
  image corners ``(1 - s) H0 c0 + s H1 c1`` to the interpolated output corners
  ``(1 - s) c0 + s c1`` (so ``P = H0^-1`` at ``s = 0`` and ``H1^-1`` at ``s = 1``;
  in between it interpolates the two views' image planes).
* Warps are backward (``cv2.remap``): each output pixel samples image ``i`` at
  the position the mesh gives it.

The morph mesh
--------------
Vertices are the (inlier, de-duplicated) correspondences plus *frame points*: a
``frame_grid x frame_grid`` lattice over the rectified canvas (the bounding box
of both rectified images, grown by a margin), whose outer ring always stays and
whose inner points are dropped near the correspondences. Frame points move by
the median disparity of the correspondences (the background behaves like a
fronto-parallel plane at the object's median depth). Triangles: Delaunay of the
vertices at ``s = 1/2``. **Fold-overs**: a triangle whose signed area reaches
:data:`tol.VM_MIN_TRIANGLE_AREA_PX2` for some ``s`` in ``[0, 1]`` (checked
exactly: the area is quadratic in ``s``) loses a vertex -- an inner frame point
if it has one, else the correspondence whose disparity deviates most from its
neighbours' median -- and the mesh is re-triangulated, until none folds (the
number dropped is reported in :attr:`ViewMorpher.report`).

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

**Occluded is not empty** (``fill_occluded=True``, layered morphs only): a
layer's pixels that a *nearer* layer hides in one image (their depth key lies
in front of the layer) say nothing about the layer there; by default they are
transparent, so where the near part moves away between the views the far part
shows a half-transparent hole (alpha ``1 - s`` or ``s``). With
``fill_occluded``, each layer carries a *known* mask per image (1 except where
a nearer layer hides it), warped with the image, and the two warped images are
mixed with weights ``(1 - s) k0`` and ``s k1`` normalised by their sum: where
one image does not see the layer, the other fills it at full weight. Pixels
known empty (background, or a farther surface) still count, so silhouettes
blend as before.

Rendering paths
---------------
``path="direct"`` (default): the pre-warp, the interpolation and the post-warp
are applied *exactly to the mesh vertices*; each output triangle then samples
the original images affinely (one resampling per image, no rectified images).
Inside a triangle this replaces the composed projective map by its affine
interpolant: exact at vertices and measured (tests) to stay within a fraction
of a pixel for the sample meshes. ``path="rectified"``: Seitz & Dyer literally --
the cached rectified images are mesh-warped to ``q(s)`` in the rectified frame,
cross-dissolved and post-warped with ``cv2.warpPerspective`` (three resamplings:
blurrier, slower; kept as the reference).

Blending is premultiplied (alpha-aware): each image carries an alpha channel
(RGBA's own; 1 inside the image for grey/RGB, 0 outside), colours are
multiplied by it, the two warped images are mixed with weights ``(1 - s, s)``,
and colour is divided by the mixed alpha. Grey/RGB outputs drop alpha (pixels
seen by neither image are 0); RGBA outputs keep straight alpha.

Fallbacks and refusals (``fallback="raise"`` refuses, ``"morph"`` degrades)
--------------------------------------------------------------------------
======================================  ============================================================
case                                    policy
======================================  ============================================================
fewer than 8 pairs (after cleaning)     ValidationError
NaN/inf coordinates                     ValidationError
duplicated pairs                        dropped (kept the first), counted in ``report``
collinear points                        GeometryError
one homography explains the pairs       mode ``"homography"``: ``H0 = I``, ``H1 = H_0_1``; morph of
(planar scene, pure rotation, zero      aligned images, post-warp interpolating ``I .. H_1_0``
baseline, identical images)             (identical images give the input at every s)
outliers                                robust F (USAC-MAGSAC); only inliers are used
views already parallel                  mode ``"parallel"``: no pre-warp
epipole in/near an image, or pre-warps  DegenerateViewError; ``fallback="morph"``: mode ``"morph"``
too distorting                          (plain mesh morph, no pre-/post-warp), reason in ``report``
fold-overs                              vertices dropped (see above); FoldOverError if that fails
images of different sizes               supported: output size interpolates between them
grey / RGB / RGBA, mixed                promoted to the richer layout (grey < RGB < RGBA)
different dtypes                        ValidationError
s outside [0, 1]                        ValidationError
layers > 1/auto without depths or keys  ValidationError (pairs need ``depth``, ``layer_depth`` keys)
a layer with < VM_MIN_LAYER_PAIRS pairs fewer layers (``report["layers"]``)
======================================  ============================================================
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from .. import tol
from .. import warp as _warp
from ..camera import CameraModel
from ..composite import from_premultiplied, over, to_premultiplied
from ..errors import (
    DegenerateViewError,
    FoldOverError,
    GeometryError,
    ValidationError,
    expected_got,
)
from ..validate import as_finite_array, as_image, as_points, as_shape, as_unit_interval
from ..warp import MeshWarper, delaunay_triangles
from .correspondences import Correspondences, _spread_subset
from .fundamental import (
    FundamentalFit,
    check_spread,
    epipolar_distance,
    estimate_fundamental,
    homography_degeneracy,
    normalize_f,
    sampson_distance,
)
from .rectify import Rectification, apply_h, rectify

__all__ = ["ViewMorpher", "PostWarpPoints", "crossfade", "nearest",
           "PREWARPS", "FALLBACKS", "FRAMES"]

PREWARPS = ("auto", "opencv", "seitz-dyer", "none")
FALLBACKS = ("raise", "morph")
FRAMES = ("contain", "fixed", "fit")
PATHS = ("direct", "rectified")

#: Far-outside sampling position (pixels) for uncovered output pixels.
_FAR = -1.0e5


@dataclass(frozen=True)
class PostWarpPoints:
    """Post-warp given by image points: correspondences ``index`` (into
    :attr:`ViewMorpher.correspondences`) must land on ``points`` (``(k, 2)``
    output pixels, ``k >= 4``); the homography is their least-squares fit."""

    index: Any
    points: Any


# --------------------------------------------------------------------------- image helpers


def _layout(img: np.ndarray) -> int:
    return 1 if img.ndim == 2 else int(img.shape[2])


def _prepare_pair(image0: Any, image1: Any) -> tuple[np.ndarray, np.ndarray, int, np.dtype]:
    a = as_image(image0, "image0", channels=(1, 3, 4))
    b = as_image(image1, "image1", channels=(1, 3, 4))
    if a.dtype != b.dtype:
        raise ValidationError(expected_got("image1 dtype", f"{a.dtype} (as image0)", f"{b.dtype}"))
    if a.dtype == np.bool_:
        raise ValidationError(expected_got("image dtype", "a numeric dtype", "bool"))
    ch = max(_layout(a), _layout(b))
    return a, b, ch, a.dtype


def crossfade(image0: Any, image1: Any, s: float) -> np.ndarray:
    """Premultiplied cross-dissolve ``(1 - s) I0 + s I1`` (images of the same shape).

    Layouts are promoted like :class:`ViewMorpher`; the output has the richer layout.
    """
    s = as_unit_interval(s, "s")
    a, b, ch, dt = _prepare_pair(image0, image1)
    if a.shape[:2] != b.shape[:2]:
        raise ValidationError(expected_got("image1 shape", f"{a.shape[:2]} (as image0)", f"{b.shape[:2]}"))
    acc = cv2.addWeighted(to_premultiplied(a, ch), 1.0 - s, to_premultiplied(b, ch), s, 0.0)
    return from_premultiplied(acc, ch, dt)


def nearest(image0: Any, image1: Any, s: float) -> np.ndarray:
    """The reference image nearer to ``s`` (image 0 for ``s <= 1/2``): a classic billboard."""
    s = as_unit_interval(s, "s")
    return np.array(image0 if s <= 0.5 else image1, copy=True)


def _remap_args(wm: Any) -> tuple[np.ndarray, np.ndarray | None]:
    """``(map1, map2)`` for ``cv2.remap`` from a :class:`morphkit.warp.WarpMaps`."""
    m1 = getattr(wm, "map1", None)
    if m1 is None and hasattr(wm, "map_xy"):
        return wm.map_xy, None
    return m1, getattr(wm, "map2", None)


def _xy_of(wm: Any) -> np.ndarray:
    m1, m2 = _remap_args(wm)
    return np.ascontiguousarray(m1 if m2 is None else np.stack([m1, m2], axis=2))


def _corners(shape: tuple[int, int]) -> np.ndarray:
    h, w = shape
    return np.array([[-0.5, -0.5], [w - 0.5, -0.5], [w - 0.5, h - 0.5], [-0.5, h - 0.5]])


def _homography_4pt(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """``H_dst_src`` from four point pairs, solved in float64 (cv2's version is float32)."""
    A = np.zeros((8, 8))
    b = np.zeros(8)
    for i, ((x, y), (u, v)) in enumerate(zip(src, dst, strict=True)):
        A[2 * i] = [x, y, 1, 0, 0, 0, -u * x, -u * y]
        A[2 * i + 1] = [0, 0, 0, x, y, 1, -v * x, -v * y]
        b[2 * i], b[2 * i + 1] = u, v
    try:
        h = np.linalg.solve(A, b)
    except np.linalg.LinAlgError as exc:
        raise GeometryError(expected_got("post-warp corners", "a non-degenerate quadrilateral",
                                         "three collinear corners")) from exc
    return np.r_[h, 1.0].reshape(3, 3)


def _known_mix(a0: np.ndarray, a1: np.ndarray, s: float) -> np.ndarray:
    """Mix two warped premultiplied images whose last channel is a "known" weight
    (``fill_occluded``): ``(k0 (1 - s) a0 + k1 s a1) / (k0 (1 - s) + k1 s)``, 0 where
    neither is known; the known channel is dropped."""
    w0 = a0[..., -1:] * np.float32(1.0 - s)
    w1 = a1[..., -1:] * np.float32(s)
    wsum = w0 + w1
    num = a0[..., :-1] * w0 + a1[..., :-1] * w1
    return np.where(wsum > 1e-6, num / np.maximum(wsum, np.float32(1e-6)), np.float32(0.0)).astype(np.float32)


# --------------------------------------------------------------------------- mesh


def _signed_area2(v: np.ndarray) -> np.ndarray:
    d1 = v[:, 1] - v[:, 0]
    d2 = v[:, 2] - v[:, 0]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


def _min_area_over_s(r0: np.ndarray, r1: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Minimum over s in [0, 1] of the signed area of each triangle of ``(1 - s) r0 + s r1``,
    signed so that positive means "oriented as at s = 1/2"."""
    a = r0[tris]
    b = r1[tris] - r0[tris]
    u0, w0 = a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]
    u1, w1 = b[:, 1] - b[:, 0], b[:, 2] - b[:, 0]

    def cr(p: np.ndarray, q: np.ndarray) -> np.ndarray:
        return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]

    c0 = cr(u0, w0)
    c1 = cr(u0, w1) + cr(u1, w0)
    c2 = cr(u1, w1)
    sign = np.sign(c0 + 0.5 * c1 + 0.25 * c2)
    sign[sign == 0] = 1.0
    c0, c1, c2 = c0 * sign, c1 * sign, c2 * sign
    vals = [c0, c0 + c1 + c2]
    with np.errstate(divide="ignore", invalid="ignore"):
        sv = np.where(c2 > 0, -c1 / (2 * c2), -1.0)
    inside = (sv > 0) & (sv < 1)
    vals.append(np.where(inside, c0 + c1 * sv + c2 * sv * sv, np.inf))
    return 0.5 * np.min(np.stack(vals), axis=0)


@dataclass
class _Layer:
    """One depth layer: its premultiplied images, its morph mesh and the look-ups built from it."""

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
    known: bool = False  # prem carries a last "known" channel (fill_occluded)


def _concat(parts: list[Correspondences]) -> Correspondences:
    """The pairs of several :class:`Correspondences` in order (3-D points/depths kept if all have them)."""
    p3 = None if any(c.points3d is None for c in parts) else np.concatenate([c.points3d for c in parts])
    dep = None if any(c.depth is None for c in parts) else np.concatenate([c.depth for c in parts])
    return Correspondences(np.concatenate([c.pts0 for c in parts]), np.concatenate([c.pts1 for c in parts]),
                           parts[0].source, p3, dep)


def _mask_bbox(mask: np.ndarray) -> np.ndarray | None:
    """Corners (pixel edges) of the bounding box of ``mask``'s True pixels, or None."""
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return None
    x0, x1, y0, y1 = cols[0] - 0.5, cols[-1] + 0.5, rows[0] - 0.5, rows[-1] + 0.5
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)


def _depth_edges(z: np.ndarray, n: int) -> np.ndarray:
    """Limits ``[min, e_1, ..., e_{n-1}, max]`` of ``n`` depth slices of ``z``: 1-D k-means
    (Lloyd's iterations from the quantiles; the edges are the midpoints between centres),
    so that slices part at the gaps between separate parts and evenly through a continuum."""
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


def _build_mesh(r0c: np.ndarray, r1c: np.ndarray, bbox: tuple[np.ndarray, np.ndarray], grid: int,
                depth: np.ndarray | None = None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """Frame points + correspondences, Delaunay at s = 1/2, fold-over cleanup.

    Returns ``(r0, r1, tris, corr_index, n_dropped)``: rectified vertex positions
    in both images, triangles, for each vertex the index of its correspondence
    (``-1`` for frame points), and how many correspondences were dropped.
    """
    lo, hi = bbox
    disp = r1c - r0c
    dmed = np.median(disp, axis=0)
    n = max(int(grid), 2)
    xs = np.linspace(lo[0], hi[0], n)
    ys = np.linspace(lo[1], hi[1], n)
    gx, gy = np.meshgrid(xs, ys)
    g = np.stack([gx.ravel(), gy.ravel()], axis=1)
    ring = (gx == xs[0]) | (gx == xs[-1]) | (gy == ys[0]) | (gy == ys[-1])
    ring = ring.ravel()
    cell = float(max(xs[1] - xs[0], ys[1] - ys[0]))
    dev = float(np.max(np.linalg.norm(disp - dmed, axis=1))) if len(disp) else 0.0
    radius = 0.75 * cell + dev
    if len(r0c):
        from scipy.spatial import cKDTree

        tree = cKDTree(np.r_[r0c, r1c])
        dist, _ = tree.query(g)
        keep_g = ring | (dist > radius)
    else:
        keep_g = np.ones(len(g), bool)
    g, ring = g[keep_g], ring[keep_g]
    r0 = np.r_[g, r0c]
    r1 = np.r_[g + dmed, r1c]
    idx = np.r_[np.full(len(g), -1), np.arange(len(r0c))]
    is_ring = np.r_[ring, np.zeros(len(r0c), bool)]
    dropped = 0
    for _ in range(200):
        mid = 0.5 * (r0 + r1)
        tris = delaunay_triangles(mid)
        amin = _min_area_over_s(r0, r1, tris)
        bad = np.flatnonzero(amin < tol.VM_MIN_TRIANGLE_AREA_PX2)
        if bad.size == 0:
            return r0, r1, tris, idx, dropped
        d = r1 - r0
        # neighbours' median disparity, per vertex
        nb: list[list[int]] = [[] for _ in range(len(r0))]
        for t in tris:
            for a in range(3):
                nb[t[a]].extend((int(t[(a + 1) % 3]), int(t[(a + 2) % 3])))
        drop: set[int] = set()
        for t in tris[bad]:
            inner = [v for v in t if idx[v] < 0 and not is_ring[v]]
            if inner:
                drop.add(int(inner[0]))
                continue
            cands = [v for v in t if idx[v] >= 0]
            if not cands:
                continue
            if depth is not None:
                # the farthest point: the occluder's outline stays, the occluded side gives way
                drop.add(int(cands[int(np.argmax(depth[idx[cands]]))]))
                continue
            devs = [np.linalg.norm(d[v] - np.median(d[nb[v]], axis=0)) if nb[v] else 0.0 for v in cands]
            drop.add(int(cands[int(np.argmax(devs))]))
        if not drop:
            break
        keep = np.ones(len(r0), bool)
        keep[list(drop)] = False
        dropped += int(np.count_nonzero(idx[~keep] >= 0))
        r0, r1, idx, is_ring = r0[keep], r1[keep], idx[keep], is_ring[keep]
        if np.count_nonzero(idx >= 0) < 3:
            break
    raise FoldOverError(expected_got("morph mesh", "no triangle folding over for s in [0, 1]",
                                     "fold-overs left after dropping vertices"))


# --------------------------------------------------------------------------- morpher


class ViewMorpher:
    """View morphing between two reference images; build once, call :meth:`morph` per ``s``.

    Parameters
    ----------
    image0, image1 : numpy.ndarray
        ``(H, W)``, ``(H, W, 3)`` or ``(H, W, 4)`` (straight alpha), same dtype
        (uint8, uint16 or float in [0, 1]); sizes may differ.
    correspondences : Correspondences or (pts0, pts1)
        Pixel pairs (pixel-centre origin), at least 8 after cleaning.
    prewarp : {"auto", "opencv", "seitz-dyer", "none"}
        Rectification (see :func:`morphkit.viewmorph.rectify.rectify`); ``"none"``
        is a plain mesh morph (no F, no pre- or post-warp: the ``morph`` baseline).
    intrinsics : (K0, K1), optional
        For the Seitz & Dyer construction (true rotations when known).
    fundamental : (3, 3), optional
        A known F (``x1^T F x0 = 0``), e.g. from the cameras; else estimated.
    threshold : float
        Inlier threshold (pixels) for F and the homography test.
    fallback : {"raise", "morph"}
        What to do when rectification is impossible (see the module table).
    frame_grid : int
        Side of the frame-point lattice.
    seed : int
        Seed of the robust estimators (and of the spread subset a camera post-warp is fitted on).
    layers : int or "auto"
        Depth layers (see the module docstring); 1 is Seitz & Dyer's single
        mesh. ``"auto"``: one mesh, unless it had to drop more than
        :data:`tol.VM_AUTO_LAYER_DROP` of the pairs to fold-overs (parts cross
        between the views); then :data:`tol.VM_AUTO_LAYERS` layers.
    layer_depth : (key0, key1), optional
        Per-pixel depth keys of the two images (``+inf`` for background), in the
        measure of :attr:`Correspondences.depth` (:func:`~morphkit.viewmorph.pair_depth`);
        required for ``layers > 1``.
    layer_overlap : float
        Overlap of neighbouring layers, a fraction of the pairs' depth range.
    fill_occluded : bool
        Layered morphs: where a nearer layer hides a layer in one image, fill it
        from the other image instead of blending with transparency (see
        "Occluded is not empty" in the module docstring). No effect with one layer.

    Attributes
    ----------
    mode : str
        ``"viewmorph"``, ``"parallel"``, ``"homography"`` or ``"morph"``.
    fit : FundamentalFit or None
    rectification : Rectification
    correspondences : Correspondences
        The pairs kept in the mesh (inliers, de-duplicated, not dropped for
        fold-overs); with layers, each layer's in turn (pairs in an overlap repeat).
    triangles : (M, 3) int
        The mesh triangles (all layers'), indexing :meth:`vertices`.
    report : dict
        What happened: counts of input/duplicate/outlier/dropped pairs, F quality,
        rectification quality, fallback reasons.
    """

    def __init__(self, image0: Any, image1: Any, correspondences: Any, *, prewarp: str = "auto",
                 intrinsics: tuple[Any, Any] | None = None, fundamental: Any = None,
                 threshold: float = tol.VM_THRESHOLD_PX, fallback: str = "raise",
                 frame_grid: int = 9, seed: int = 0, layers: int | str = 1, layer_depth: Any = None,
                 layer_overlap: float = tol.VM_LAYER_OVERLAP, fill_occluded: bool = False) -> None:
        if prewarp not in PREWARPS:
            raise ValidationError(expected_got("prewarp", f"one of {PREWARPS}", repr(prewarp)))
        if fallback not in FALLBACKS:
            raise ValidationError(expected_got("fallback", f"one of {FALLBACKS}", repr(fallback)))
        if not (isinstance(layers, str) and layers == "auto") and (
                isinstance(layers, (bool, str)) or not isinstance(layers, (int, np.integer)) or layers < 1):
            raise ValidationError(expected_got("layers", "an int >= 1 or 'auto'", repr(layers)))
        n_layers: int | str = layers if isinstance(layers, str) else int(layers)
        overlap = float(layer_overlap)
        if not 0.0 <= overlap < 0.5:
            raise ValidationError(expected_got("layer_overlap", "a fraction in [0, 0.5)",
                                               repr(layer_overlap)))
        if not isinstance(fill_occluded, (bool, np.bool_)):
            raise ValidationError(expected_got("fill_occluded", "a bool", repr(fill_occluded)))
        self._fill_occluded = bool(fill_occluded)
        a, b, ch, dt = _prepare_pair(image0, image1)
        self.shape0: tuple[int, int] = a.shape[:2]
        self.shape1: tuple[int, int] = b.shape[:2]
        self.channels, self.dtype = ch, dt
        self._prem = (to_premultiplied(a, ch), to_premultiplied(b, ch))
        corr = correspondences if isinstance(correspondences, Correspondences) else \
            Correspondences(*correspondences)
        report: dict[str, Any] = {"n_input": len(corr)}
        corr, ndup = corr.cleaned()
        report["n_duplicates"] = ndup
        if len(corr) < 8:
            raise ValidationError(expected_got(
                "correspondences", "at least 8 distinct pairs (F has 7 degrees of freedom)",
                f"{len(corr)} after dropping {ndup} duplicates"))
        check_spread(corr.pts0, "pts0")
        check_spread(corr.pts1, "pts1")
        K0, K1 = (None, None) if intrinsics is None else intrinsics

        self.fit: FundamentalFit | None = None
        mode = "viewmorph"
        rect: Rectification | None = None
        if prewarp == "none":
            mode = "morph"
        else:
            Hh, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
            if Hh is None:
                try:
                    self.fit = self._fit_f(corr, fundamental, threshold, seed)
                except GeometryError as exc:
                    if fallback == "raise":
                        raise
                    mode, report["fallback"] = "morph", str(exc)
            if self.fit is not None:
                inl = self.fit.inliers
                report["n_outliers"] = int(np.count_nonzero(~inl))
                corr = corr.subset(inl)
                Hh, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
            report["homography_inlier_fraction"] = float(frac)
            if Hh is not None:
                mode = "homography"
                self.fit = None
                inv = np.linalg.inv(Hh)
                rect = Rectification(np.eye(3), inv / inv[2, 2], "homography",
                                     float(np.sqrt(np.mean((apply_h(inv, corr.pts1) - corr.pts0) ** 2))),
                                     1.0, 1.0, {})
            elif mode == "viewmorph":
                try:
                    rect = rectify(self.fit.F, corr.pts0, corr.pts1, self.shape0, self.shape1,
                                   method=prewarp, K0=K0, K1=K1)
                    if rect.method == "parallel":
                        mode = "parallel"
                except DegenerateViewError as exc:
                    if fallback == "raise":
                        raise
                    mode, report["fallback"] = "morph", str(exc)
        if rect is None:
            rect = Rectification(np.eye(3), np.eye(3), "none", float("nan"), 1.0, 1.0, {})
        self.mode = mode
        self.rectification = rect
        self.H0, self.H1 = rect.H0, rect.H1
        self._H0inv, self._H1inv = np.linalg.inv(self.H0), np.linalg.inv(self.H1)
        if self.fit is not None:
            report["fundamental"] = self.fit.report()
        report["rectification"] = rect.report()
        report["mode"] = mode

        # ---- depth layers, each with its own mesh in the shared rectified frame
        self._layers = self._build_layers(corr, n_layers, layer_depth, overlap, frame_grid, report)
        self._canvas = self._layers[-1].canvas  # the farthest (or only) layer covers the whole images
        offs = np.cumsum([0] + [len(L.r0) for L in self._layers])
        self._r0 = np.concatenate([L.r0 for L in self._layers])
        self._r1 = np.concatenate([L.r1 for L in self._layers])
        self.triangles = np.concatenate([L.tris + o for L, o in zip(self._layers, offs, strict=False)])
        self._is_corr = np.concatenate([L.is_corr for L in self._layers])
        self.correspondences = _concat([L.corr for L in self._layers])
        report["n_dropped_foldover"] = sum(L.n_dropped for L in self._layers)
        report["n_frame_points"] = int(np.count_nonzero(~self._is_corr))
        report["n_used"] = len(self.correspondences)
        # the pairs a post-warp to a camera is fitted on: at most VM_POST_FIT_PAIRS, spread over image 0
        self._post_fit_index = _spread_subset(self.correspondences.pts0, tol.VM_POST_FIT_PAIRS,
                                              np.random.default_rng(seed))
        self._rectified: tuple[np.ndarray, np.ndarray] | None = None
        self.report = report

    # ---------------------------------------------------------------- construction helpers
    def _canvas_for(self, corr: Correspondences, box0: np.ndarray | None, box1: np.ndarray | None
                    ) -> tuple[np.ndarray, np.ndarray]:
        """The rectified region a mesh must cover: the pairs and the given image-space
        quadrilaterals (``None``: the whole image), grown by a margin, capped, kept in front."""
        r0c, r1c = apply_h(self.H0, corr.pts0), apply_h(self.H1, corr.pts1)
        parts = [r0c, r1c]
        for box, shape, H in ((box0, self.shape0, self.H0), (box1, self.shape1, self.H1)):
            if box is None:
                box = _corners(shape)
            if len(box):
                parts.append(apply_h(H, box))
        allp = np.concatenate(parts)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        size = float(max(max(self.shape0), max(self.shape1)))
        centre = 0.5 * (r0c.mean(axis=0) + r1c.mean(axis=0))
        lim = 0.5 * tol.VM_MAX_CANVAS_FACTOR * size
        lo, hi = np.maximum(lo, centre - lim), np.minimum(hi, centre + lim)
        margin = 0.05 * float(np.max(hi - lo)) + 4.0
        return self._safe_bbox(lo - margin, hi + margin, centre)

    def _make_layer(self, prem: tuple[np.ndarray, np.ndarray], corr: Correspondences,
                    bbox: tuple[np.ndarray, np.ndarray], frame_grid: int) -> _Layer:
        """Mesh (frame points + pairs, fold-overs resolved), warpers and the C1 look-up of one layer."""
        r0c, r1c = apply_h(self.H0, corr.pts0), apply_h(self.H1, corr.pts1)
        r0, r1, tris, idx, ndrop = _build_mesh(r0c, r1c, bbox, frame_grid, corr.depth)
        used = idx[idx >= 0]
        is_corr = idx >= 0
        # vertex positions in the original images (correspondences exactly, frame points by H^-1)
        p0 = apply_h(self._H0inv, r0)
        p1 = apply_h(self._H1inv, r1)
        p0[is_corr] = corr.pts0[used]
        p1[is_corr] = corr.pts1[used]
        w0, w1 = MeshWarper(p0, tris), MeshWarper(p1, tris)
        # C1: for each image-0 pixel of the mesh's footprint, its image-1 position (s-independent)
        lo0 = np.floor(p0.min(axis=0)) - 1
        hi0 = np.ceil(p0.max(axis=0)) + 1
        c1_shape = (int(hi0[1] - lo0[1]) + 1, int(hi0[0] - lo0[0]) + 1)
        wm = w1.maps(p0 - lo0, c1_shape)
        c1 = np.full(c1_shape + (2,), _FAR, np.float32)
        r_0, r_1, c_0, c_1 = wm.roi
        c1[r_0:r_1, c_0:c_1] = np.where(wm.mask[r_0:r_1, c_0:c_1, None], _xy_of(wm), np.float32(_FAR))
        # Does the warp's position for uncovered pixels fall >= 2 px off the C1 canvas?
        far = getattr(_warp, "_OUTSIDE", None)
        c1_far = far is not None and float(far) - float(lo0.max()) <= -2.0
        lo, hi = bbox
        return _Layer(prem, (np.floor(lo), np.ceil(hi)), r0, r1, tris, is_corr, corr.subset(used), ndrop,
                      w0, w1, lo0, c1, c1_far)

    def _build_layers(self, corr: Correspondences, layers: int | str, layer_depth: Any, overlap: float,
                      frame_grid: int, report: dict[str, Any]) -> list[_Layer]:
        """Split pairs and pixels into depth layers (1-D k-means of the depths) and build each layer."""
        full = self._canvas_for(corr, None, None)
        if layers == 1:
            report["layers"] = 1
            return [self._make_layer(self._prem, corr, full, frame_grid)]
        if corr.depth is None:
            raise ValidationError(expected_got(
                "correspondences", "pairs with depths for layers > 1 or 'auto' (from_geometry or from_depth)",
                "pairs without depth"))
        if layer_depth is None or len(layer_depth) != 2:
            raise ValidationError(expected_got(
                "layer_depth", "(key0, key1) per-pixel depth keys for layers > 1 or 'auto' "
                "(viewmorph.pair_depth)", type(layer_depth).__name__))
        keys = self._check_keys(layer_depth)
        if layers == "auto":
            one = self._make_layer(self._prem, corr, full, frame_grid)
            frac = one.n_dropped / max(len(corr), 1)
            report["auto_dropped_fraction"] = float(frac)
            if frac <= tol.VM_AUTO_LAYER_DROP:
                report["layers"] = 1
                return [one]
            layers = tol.VM_AUTO_LAYERS
        assert isinstance(layers, int)
        z = corr.depth
        n = min(int(layers), max(1, len(corr) // tol.VM_MIN_LAYER_PAIRS))
        while True:
            edges = _depth_edges(z, n)
            m = float(overlap) * float(edges[-1] - edges[0])
            lims = [(-np.inf if i == 0 else edges[i] - m, np.inf if i == n - 1 else edges[i + 1] + m)
                    for i in range(n)]
            sels = [(z >= a) & (z <= b) for a, b in lims]
            if n == 1 or min(int(c.sum()) for c in sels) >= tol.VM_MIN_LAYER_PAIRS:
                break
            n -= 1
        report["layers"] = n
        report["layer_edges"] = [float(e) for e in edges[1:-1]]
        out = []
        report["fill_occluded"] = self._fill_occluded and n > 1
        for i, ((a, b), sel) in enumerate(zip(lims, sels, strict=True)):
            masks = [(k >= a) & (k <= b) for k in keys]
            prem = (self._prem[0] * masks[0][..., None], self._prem[1] * masks[1][..., None])
            if self._fill_occluded and n > 1:
                # last channel: "known" = not hidden by a nearer layer (key in front of this layer's range)
                prem = (np.concatenate([prem[0], (keys[0] >= a)[..., None].astype(np.float32)], axis=2),
                        np.concatenate([prem[1], (keys[1] >= a)[..., None].astype(np.float32)], axis=2))
            sub = corr.subset(sel)
            if i == n - 1:
                bbox = full  # the farthest layer holds the background: the whole images
            else:
                boxes = [_mask_bbox(mk) for mk in masks]
                bbox = self._canvas_for(sub, *(np.zeros((0, 2)) if b_ is None else b_ for b_ in boxes))
            layer = self._make_layer(prem, sub, bbox, frame_grid)
            layer.known = prem[0].shape[2] > self._prem[0].shape[2]
            out.append(layer)
        return out

    def _check_keys(self, layer_depth: Any) -> list[np.ndarray]:
        """The two per-pixel depth-key images, validated (float64, image shapes, no NaN)."""
        keys = []
        for key, shape, name in ((layer_depth[0], self.shape0, "layer_depth[0]"),
                                 (layer_depth[1], self.shape1, "layer_depth[1]")):
            k = as_image(key, name, channels=(1,), allow_nonfinite=True).astype(np.float64)
            if k.shape != shape:
                raise ValidationError(expected_got(name, f"shape {shape} (its image's)", f"shape {k.shape}"))
            if np.isnan(k).any():
                raise ValidationError(expected_got(name, "depths, +inf for background", "NaN values"))
            keys.append(k)
        return keys

    @staticmethod
    def _fit_f(corr: Correspondences, fundamental: Any, threshold: float, seed: int) -> FundamentalFit:
        if fundamental is None:
            return estimate_fundamental(corr.pts0, corr.pts1, threshold=threshold, seed=seed,
                                        check_degenerate=False)
        F = normalize_f(fundamental)
        d = sampson_distance(F, corr.pts0, corr.pts1)
        inl = d <= threshold
        if inl.sum() < 8:
            raise GeometryError(expected_got("given F", "at least 8 pairs within the threshold",
                                             f"{int(inl.sum())}"))
        e = epipolar_distance(F, corr.pts0[inl], corr.pts1[inl])
        return FundamentalFit(F, inl, "given", threshold, float(np.sqrt(np.mean(d[inl] ** 2))),
                              float(d[inl].max()), float(np.sqrt(np.mean(e**2))))

    def _safe_bbox(self, lo: np.ndarray, hi: np.ndarray, centre: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
        """Shrink the rectified canvas until both inverse pre-warps keep its corners in front."""
        for _ in range(40):
            c = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
            ok = True
            for Hinv in (self._H0inv, self._H1inv):
                w = np.c_[c, np.ones(4)] @ Hinv[2]
                wc = np.r_[centre, 1.0] @ Hinv[2]
                if np.any(w * np.sign(wc) <= 0.05 * abs(wc)):
                    ok = False
            if ok:
                return lo, hi
            lo = centre + 0.85 * (lo - centre)
            hi = centre + 0.85 * (hi - centre)
        raise DegenerateViewError(expected_got("rectified canvas", "a region in front of both views",
                                               "none found"))

    # ---------------------------------------------------------------- geometry per s
    def vertices(self, s: float) -> np.ndarray:
        """Mesh vertices ``q(s) = (1 - s) r0 + s r1`` in the rectified-interpolated frame."""
        s = as_unit_interval(s, "s")
        return self._r0 + s * (self._r1 - self._r0)

    def out_shape(self, s: float) -> tuple[int, int]:
        """Default output shape: the input shapes interpolated by ``s`` (rounded)."""
        s = as_unit_interval(s, "s")
        return (int(round((1 - s) * self.shape0[0] + s * self.shape1[0])),
                int(round((1 - s) * self.shape0[1] + s * self.shape1[1])))

    def post_homography(self, s: float, post: Any = "interpolate") -> tuple[np.ndarray, tuple[int, int]]:
        """The post-warp ``P = H_out_rect`` for ``s`` and its default output shape.

        Parameters
        ----------
        post : "interpolate", "rectified", (3, 3) array, CameraModel or PostWarpPoints
            ``"interpolate"``: corners interpolated between the two views (module
            convention). ``"rectified"``: no post-warp (a translation to the
            rectified canvas, whose size is returned). A (3, 3) array: ``P``
            itself. A :class:`~morphkit.camera.CameraModel`: the least-squares
            homography taking ``q(s)`` of the correspondences (at most
            :data:`tol.VM_POST_FIT_PAIRS` of them, spread over image 0) to their
            projections in that camera (needs ``points3d``, i.e. correspondences
            from geometry); the camera's shape. :class:`PostWarpPoints`:
            least squares on the given points.

        Convention
        ----------
        ``P`` maps rectified-interpolated coordinates (pixel-centre origin) to
        output pixels: ``out = P q``.
        """
        s = as_unit_interval(s, "s")
        q = self.vertices(s)
        if isinstance(post, str) and post == "interpolate":
            c0 = apply_h(self.H0, _corners(self.shape0))
            c1 = apply_h(self.H1, _corners(self.shape1))
            shape = self.out_shape(s)
            src = (1 - s) * c0 + s * c1
            dst = (1 - s) * _corners(self.shape0) + s * _corners(self.shape1)
            return _homography_4pt(src, dst), shape
        if isinstance(post, str) and post == "rectified":
            lo, hi = self._canvas
            P = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
            return P, (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
        if isinstance(post, CameraModel):
            if self.correspondences.points3d is None:
                raise ValidationError(expected_got("post", "a camera only with correspondences from geometry "
                                                   "(points3d)", "correspondences without 3-D points"))
            idx = self._post_fit_index
            tgt, _ = post.project(self.correspondences.points3d[idx])
            P = self._fit_h(q[self._is_corr][idx], tgt)
            return P, post.shape
        if isinstance(post, PostWarpPoints):
            index = np.asarray(post.index, dtype=np.int64).ravel()
            pts = as_points(post.points, "post points", min_count=4)
            if index.size != len(pts) or np.any(index < 0) or np.any(index >= len(self.correspondences)):
                raise ValidationError(expected_got("post index", f"{len(pts)} indices in "
                                                   f"[0, {len(self.correspondences)})", index.tolist()[:8]))
            P = self._fit_h(q[self._is_corr][index], pts)
            return P, self.out_shape(s)
        if isinstance(post, str):
            raise ValidationError(expected_got("post", "'interpolate', 'rectified', a 3x3 array, a "
                                               "CameraModel or PostWarpPoints", repr(post)))
        P = as_finite_array(post, "post", shape=(3, 3))
        if abs(np.linalg.det(P)) < 1e-300:
            raise ValidationError(expected_got("post", "a regular homography", "a singular matrix"))
        return P, self.out_shape(s)

    @staticmethod
    def _fit_h(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
        if len(src) < 4:
            raise ValidationError(expected_got("post-warp points", "at least 4", f"{len(src)}"))
        check_spread(src, "post-warp source points")
        check_spread(dst, "post-warp target points")
        H, _ = cv2.findHomography(src, dst, 0)
        if H is None or not np.all(np.isfinite(H)):
            raise GeometryError(expected_got("post-warp homography fit", "a solution", "none"))
        return H / H[2, 2]

    def _frame(self, P: np.ndarray, s: float, shape: tuple[int, int], frame: str) -> np.ndarray:
        """Apply the crop/size policy: a similarity left-multiplied onto ``P``."""
        if frame == "fixed":
            return P
        obj = apply_h(P, self.vertices(s)[self._is_corr])
        blo, bhi = obj.min(axis=0), obj.max(axis=0)
        h, w = shape
        flo, fhi = np.array([-0.5, -0.5]), np.array([w - 0.5, h - 0.5])
        if frame == "contain":
            def over(p: np.ndarray, sh: tuple[int, int]) -> float:
                c = _corners(sh)
                return float(max(0.0, np.max(c[0] - p.min(axis=0)), np.max(p.max(axis=0) - c[2])))
            slack = (1 - s) * over(self.correspondences.pts0, self.shape0) + \
                s * over(self.correspondences.pts1, self.shape1)
            if np.all(blo >= flo - slack - 1e-9) and np.all(bhi <= fhi + slack + 1e-9):
                return P
            margin = 0.02
        else:
            margin = 0.05
        size = fhi - flo
        inner_lo, inner_hi = flo + margin * size, fhi - margin * size
        k = float(np.min((inner_hi - inner_lo) / np.maximum(bhi - blo, 1e-9)))
        if frame == "contain":
            k = min(k, 1.0)
        cb, cf = 0.5 * (blo + bhi), 0.5 * (flo + fhi)
        S = np.array([[k, 0.0, cf[0] - k * cb[0]], [0.0, k, cf[1] - k * cb[1]], [0.0, 0.0, 1.0]])
        return S @ P

    # ---------------------------------------------------------------- rendering
    def morph(self, s: float, *, post: Any = "interpolate", out_shape: Any = None, frame: str = "contain",
              path: str = "direct") -> np.ndarray:
        """The in-between view at ``s`` (0: image 0, 1: image 1).

        Parameters
        ----------
        s : float in [0, 1]
        post : see :meth:`post_homography`
        out_shape : (H, W), optional
            Default: from ``post`` (interpolated input shapes, the camera's shape,
            or the rectified canvas).
        frame : {"contain", "fixed", "fit"}
            Crop/size policy: ``"contain"`` scales down (about the frame centre)
            and shifts only when the object (the correspondences' bounding box)
            would leave the frame further than it leaves the inputs;
            ``"fit"`` always scales the object to fill the frame with a 5%
            margin; ``"fixed"`` keeps ``P`` as is.
        path : {"direct", "rectified"}
            See the module docstring.

        Returns
        -------
        numpy.ndarray
            The layout (grey/RGB/RGBA, promoted) and dtype of the inputs.

        Convention
        ----------
        Output pixel ``p`` shows the mesh point ``P^-1 p`` of the
        rectified-interpolated frame; pixel-centre origin throughout.

        Raises
        ------
        ValidationError
            ``s`` outside [0, 1], bad ``post``/``frame``/``path``/``out_shape``.
        DegenerateViewError
            The post-warp sends part of the mesh through infinity.
        """
        s = as_unit_interval(s, "s")
        if frame not in FRAMES:
            raise ValidationError(expected_got("frame", f"one of {FRAMES}", repr(frame)))
        if path not in PATHS:
            raise ValidationError(expected_got("path", f"one of {PATHS}", repr(path)))
        P, shape = self.post_homography(s, post)
        if out_shape is not None:
            shape = as_shape(out_shape, "out_shape")
        P = self._frame(P, s, shape, frame)
        acc = self._render_direct(s, P, shape) if path == "direct" else self._render_rectified(s, P, shape)
        return from_premultiplied(acc, self.channels, self.dtype)

    def frames(self, n: int, **kw: Any) -> list[np.ndarray]:
        """``n >= 2`` views at ``s = 0, 1/(n-1), ..., 1`` (keyword arguments go to :meth:`morph`)."""
        n = int(n)
        if n < 2:
            raise ValidationError(expected_got("n", "an int >= 2", n))
        return [self.morph(float(s), **kw) for s in np.linspace(0.0, 1.0, n)]

    @staticmethod
    def _dst(layer: _Layer, s: float, P: np.ndarray) -> np.ndarray:
        q = np.c_[layer.r0 + s * (layer.r1 - layer.r0), np.ones(len(layer.r0))] @ P.T
        w = q[:, 2]
        wc = np.median(w)
        if np.any(w * np.sign(wc) <= 1e-9 * abs(wc)):
            raise DegenerateViewError(expected_got(
                "post-warp", "a homography keeping the morph mesh in front (w > 0)",
                "one sending part of it through infinity"))
        return q[:, :2] / w[:, None]

    def _render_direct(self, s: float, P: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        h, w = shape
        nch = self._prem[0].shape[2]
        out: np.ndarray | None = None
        for layer in reversed(self._layers):  # far to near, premultiplied "over"
            got = self._render_layer(layer, s, P, shape)
            if got is not None:
                out = over(out, got[1], got[0], shape)
        return np.zeros((h, w, nch), np.float32) if out is None else out

    def _render_layer(self, layer: _Layer, s: float, P: np.ndarray, shape: tuple[int, int]
                      ) -> tuple[tuple[int, int, int, int], np.ndarray] | None:
        """One layer's premultiplied morph over its region of interest (None if it covers nothing)."""
        dst = self._dst(layer, s, P)
        prem0, prem1 = layer.prem
        if s >= 1.0:
            wm1 = self._maps(layer.w1, dst, shape)
            m1, m2 = _remap_args(wm1)
            if m1 is None:
                return None
            a1 = cv2.remap(prem1, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            return wm1.roi, (a1[..., :-1] if layer.known else a1)
        wm0 = self._maps(layer.w0, dst, shape)
        m1, m2 = _remap_args(wm0)
        if m1 is None:
            return None
        r_0, r_1, c_0, c_1 = wm0.roi
        a0 = cv2.remap(prem0, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        if s <= 0.0:
            return wm0.roi, (a0[..., :-1] if layer.known else a0)
        # image-1 positions: look the image-0 positions up in C1 (piecewise affine, s-independent)
        ox, oy = layer.c1_origin
        if m2 is None:
            mx, my = m1 - np.float32([ox, oy]), None
        else:
            mx, my = m1 - np.float32(ox), m2 - np.float32(oy)
        pos1 = cv2.remap(layer.c1, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                         borderValue=(_FAR, _FAR, 0, 0))
        a1 = cv2.remap(prem1, pos1, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        mix = _known_mix(a0, a1, s) if layer.known else cv2.addWeighted(a0, 1.0 - s, a1, s, 0.0)
        if not layer.c1_far:
            # outside the mesh the C1 look-up of the warp's far position could land on the canvas
            np.copyto(mix, 0.0, where=~wm0.mask[r_0:r_1, c_0:c_1, None])
        return wm0.roi, mix

    @staticmethod
    def _maps(warper: MeshWarper, dst: np.ndarray, shape: tuple[int, int]) -> Any:
        try:
            return warper.maps(dst, shape)
        except FoldOverError as exc:
            raise FoldOverError(f"the post-warp mirrors or folds the morph mesh: {exc}") from exc

    # ---------------------------------------------------------------- Seitz & Dyer literally
    @staticmethod
    def _prewarp_images(prem: tuple[np.ndarray, np.ndarray], Hs: tuple[np.ndarray, np.ndarray],
                        canvas: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = canvas
        shape = (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
        T = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
        ims = tuple(cv2.warpPerspective(p, T @ H, (shape[1], shape[0]), flags=cv2.INTER_LINEAR,
                                        borderMode=cv2.BORDER_CONSTANT, borderValue=0)
                    for p, H in zip(prem, Hs, strict=True))
        return ims[0], ims[1]

    def rectified_images(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The two pre-warped (premultiplied float32) images on the rectified canvas, and its origin.

        Convention: canvas pixel ``(x, y)`` is rectified-frame point ``(x, y) + origin``.
        """
        if self._rectified is None:
            self._rectified = self._prewarp_images(self._prem, (self.H0, self.H1), self._canvas)
        return self._rectified[0], self._rectified[1], self._canvas[0].copy()

    def _render_rectified(self, s: float, P: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        out: np.ndarray | None = None
        for layer in reversed(self._layers):  # far to near, premultiplied "over"
            if layer.rectified is None:
                layer.rectified = (self.rectified_images()[:2] if len(self._layers) == 1 else
                                   self._prewarp_images(layer.prem, (self.H0, self.H1), layer.canvas))
            rect0, rect1 = layer.rectified
            lo = layer.canvas[0]
            cshape = rect0.shape[:2]
            q = layer.r0 + s * (layer.r1 - layer.r0) - lo
            parts = [(MeshWarper(r - lo, layer.tris).maps(q, cshape).apply(img, fill=0.0), wgt)
                     for img, r, wgt in ((rect0, layer.r0, 1.0 - s), (rect1, layer.r1, s)) if wgt > 0.0]
            if layer.known and len(parts) == 2:
                acc = _known_mix(parts[0][0], parts[1][0], s)
            elif layer.known:
                acc = np.ascontiguousarray(parts[0][0][..., :-1])
            else:
                acc = parts[0][0] * np.float32(parts[0][1])
                if len(parts) == 2:
                    acc = cv2.addWeighted(acc, 1.0, parts[1][0], parts[1][1], 0.0)
            T = np.array([[1.0, 0.0, lo[0]], [0.0, 1.0, lo[1]], [0.0, 0.0, 1.0]])
            img = cv2.warpPerspective(acc, P @ T, (shape[1], shape[0]), flags=cv2.INTER_LINEAR,
                                      borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            out = over(out, img.reshape(shape + (acc.shape[2],)), (0, shape[0], 0, shape[1]), shape)
        assert out is not None
        return out
