"""Estimation of a view morph (Seitz & Dyer 1996), apart from its application: :func:`plan_view_morph`.

Everything that depends on the reference pair alone is estimated once, by
:func:`plan_view_morph`, into a frozen :class:`MorphPlan`: the cleaned pairs,
the fundamental matrix, the pre-warps (or the fallback chosen instead), the
depth layers with their morph meshes and warpers, the rectified canvas, and a
typed :class:`MorphReport` of what happened. :class:`~morphkit.viewmorph.morph.ViewMorpher`
then only applies a plan (one mesh interpolation, one mesh-map computation and two
``cv2.remap`` per ``s``). In the style of scikit-image's ``from_estimate``: the
estimate is a value of its own; a pair that cannot be planned raises one of
the morphkit errors below (no partially built plan exists).

Convention
----------
* Pixels: ``(x, y)``, origin at the centre of the top-left pixel
  (:mod:`morphkit.conventions`); shapes are ``(H, W)``.
* The pre-warps ``H_rect_0`` and ``H_rect_1`` map image-0 and image-1 pixels to
  the shared rectified frame (:mod:`morphkit.viewmorph.rectify`). The rectified
  positions of a pair, ``r0 = H_rect_0 p0`` and ``r1 = H_rect_1 p1``, share their
  ``y``; the morph at ``s`` puts the pair at ``q(s) = (1 - s) r0 + s r1``.

Fallbacks and refusals (``fallback="raise"`` refuses, ``"morph"`` degrades)
---------------------------------------------------------------------------
======================================  ============================================================
case                                    policy
======================================  ============================================================
fewer than 8 pairs (after cleaning)     ValidationError
NaN/inf coordinates                     ValidationError
duplicated pairs                        dropped (kept the first), counted in ``report.n_duplicates``
collinear points                        GeometryError
one homography explains the pairs       mode ``"homography"``: ``H_rect_0 = I``, ``H_rect_1 = H_0_1``;
(planar scene, pure rotation, zero      morph of aligned images, post-warp interpolating ``I .. H_1_0``
baseline, identical images)             (identical images give the input at every s)
outliers                                robust F (USAC-MAGSAC); only inliers are used
views already parallel                  mode ``"parallel"``: no pre-warp
epipole in/near an image, or pre-warps  an estimated F is replaced by the affine F (both epipoles at
too distorting                          infinity) when that keeps >= tol.VM_AFFINE_INLIER_RATIO of its
                                        inliers, fits them about as well (tol.VM_AFFINE_RMS_RATIO) and
                                        passes the checks (``report.affine``); else
                                        DegenerateViewError; ``fallback="morph"``: mode ``"morph"``
                                        (plain mesh morph, no pre-/post-warp), reason in
                                        ``report.fallback``
fold-overs                              vertices dropped (viewmorph.mesh); FoldOverError if that fails
images of different sizes               supported: output size interpolates between them
grey / RGB / RGBA, mixed                promoted to the richer layout (grey < RGB < RGBA)
different dtypes                        ValidationError
layers > 1/auto without depths or keys  ValidationError (pairs need ``depth``, ``layer_depth`` keys)
a layer below VM_MIN_LAYER_PAIRS pairs  fewer layers (``report.layers``)
======================================  ============================================================
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import tol
from ..errors import DegenerateViewError, GeometryError, ValidationError, expected_got
from ..imaging.composite import to_premultiplied
from ..validate import as_flag, as_int
from .correspondences import Correspondences, spread_subset
from .fundamental import (
    FundamentalFit,
    check_spread,
    epipolar_distance,
    estimate_affine_fundamental,
    estimate_fundamental,
    homography_degeneracy,
    normalize_f,
    sampson_distance,
)
from .images import prepare_pair
from .layers import MorphLayer, build_layers, concat_correspondences
from .rectify import Rectification, apply_h, rectify

__all__ = ["plan_view_morph", "MorphPlan", "MorphReport", "AffineReport", "PREWARPS", "FALLBACKS", "MODES"]

#: The values of ``plan_view_morph(prewarp=...)`` (and ``morphkit viewmorph --prewarp``).
PREWARPS = ("auto", "opencv", "seitz-dyer", "none")
#: The values of ``plan_view_morph(fallback=...)``: refuse a degenerate pair, or plain mesh morph.
FALLBACKS = ("raise", "morph")
#: The modes a plan can end in (:attr:`MorphPlan.mode`).
MODES = ("viewmorph", "parallel", "homography", "morph")


@dataclass(frozen=True)
class AffineReport:
    """Why the affine F was (or was not) used in place of a refused general F.

    Parameters
    ----------
    f_refused : str
        Why the general F's pre-warps were refused.
    f_inliers : int
        The general F's inliers.
    used : bool
        The affine F and its pre-warps replaced the general F.
    refused : str or None
        Why the affine F was not used (None when it was).
    affine_inliers : int or None
        The affine F's inliers (None: no affine F could be fitted).
    inlier_ratio : float or None
        ``affine_inliers / f_inliers``.
    f_rms_px, affine_rms_px : float or None
        RMS Sampson distances of both Fs on the pairs both explain (None when
        the inlier ratio already refused the affine F).
    """

    f_refused: str
    f_inliers: int
    used: bool = False
    refused: str | None = None
    affine_inliers: int | None = None
    inlier_ratio: float | None = None
    f_rms_px: float | None = None
    affine_rms_px: float | None = None


@dataclass(frozen=True)
class MorphReport:
    """What :func:`plan_view_morph` did with the pairs, in typed fields.

    Parameters
    ----------
    mode : str
        One of :data:`MODES`.
    n_input : int
        Pairs given.
    n_duplicates : int
        Pairs dropped as duplicates of earlier ones.
    n_used : int
        Pairs in the mesh (all layers'; pairs in a layer overlap count twice).
    n_dropped_foldover : int
        Pairs dropped to fold-overs (all layers).
    n_frame_points : int
        Frame-point vertices of the meshes.
    layers : int
        Depth layers used.
    n_outliers : int or None
        Pairs outside the fundamental matrix's inliers (None: no F was fitted).
    homography_inlier_fraction : float or None
        The homography test's inlier fraction (None with ``prewarp="none"``).
    fallback : str or None
        Why the plan fell back to a plain morph (``fallback="morph"``), else None.
    affine : AffineReport or None
        The affine-F attempt after a refused general F, else None.
    layer_edges : tuple of float
        Inner depth cuts of the layers (empty with one layer).
    auto_dropped_fraction : float or None
        ``layers="auto"``: the fraction of the pairs one mesh dropped to fold-overs.
    fill_occluded : bool
        The layers fill what one image hides from the other.
    """

    mode: str
    n_input: int
    n_duplicates: int
    n_used: int
    n_dropped_foldover: int
    n_frame_points: int
    layers: int
    n_outliers: int | None = None
    homography_inlier_fraction: float | None = None
    fallback: str | None = None
    affine: AffineReport | None = None
    layer_edges: tuple[float, ...] = ()
    auto_dropped_fraction: float | None = None
    fill_occluded: bool = False


@dataclass(frozen=True, eq=False)
class MorphPlan:
    """Everything a view morph of one reference pair estimates, once (see :func:`plan_view_morph`).

    Parameters
    ----------
    shape0, shape1 : (H, W)
        The reference images' shapes.
    channels : int
        The output layout (1 grey, 3 RGB, 4 RGBA: the richer input's).
    dtype : numpy.dtype
        The inputs' (and outputs') dtype.
    prem : (prem0, prem1)
        float32 ``(H_i, W_i, C + 1)`` premultiplied images
        (:func:`morphkit.imaging.composite.to_premultiplied`).
    mode : str
        One of :data:`MODES`.
    fit : FundamentalFit or None
        The fundamental matrix used (None in modes ``"homography"`` and ``"morph"``).
    rectification : Rectification
        The pre-warps and their quality (identities without a pre-warp).
    layers : tuple of MorphLayer
        Near to far; the last covers the whole images.
    canvas : (lo, hi)
        ``(2,)`` float64 integer-valued corners of the rectified canvas (the farthest layer's).
    correspondences : Correspondences
        The pairs kept in the mesh, each layer's in turn.
    r0, r1 : numpy.ndarray
        ``(V, 2)`` float64 positions of all layers' vertices in the rectified
        frame at ``s = 0`` and ``s = 1``.
    triangles : numpy.ndarray
        ``(M, 3)`` int triangles (all layers'), indexing the vertices.
    is_correspondence : numpy.ndarray
        ``(V,)`` bool: True for the pairs (in the order of ``correspondences``),
        False for frame points.
    post_fit_index : numpy.ndarray
        Indices of at most :data:`tol.VM_POST_FIT_PAIRS` pairs, spread over
        image 0, that a post-warp to a camera is fitted on.
    report : MorphReport
        What happened.

    Notes
    -----
    Frozen: a plan is not changed after :func:`plan_view_morph`; its arrays are
    shared with every :class:`~morphkit.viewmorph.morph.ViewMorpher` applying it
    (do not modify them).
    """

    shape0: tuple[int, int]
    shape1: tuple[int, int]
    channels: int
    dtype: np.dtype
    prem: tuple[np.ndarray, np.ndarray]
    mode: str
    fit: FundamentalFit | None
    rectification: Rectification
    layers: tuple[MorphLayer, ...]
    canvas: tuple[np.ndarray, np.ndarray]
    correspondences: Correspondences
    r0: np.ndarray
    r1: np.ndarray
    triangles: np.ndarray
    is_correspondence: np.ndarray
    post_fit_index: np.ndarray
    report: MorphReport

    @property
    def H_rect_0(self) -> np.ndarray:
        """The pre-warp of image 0 (``(3, 3)`` float64; identity without one)."""
        return self.rectification.H_rect_0

    @property
    def H_rect_1(self) -> np.ndarray:
        """The pre-warp of image 1 (``(3, 3)`` float64; identity without one)."""
        return self.rectification.H_rect_1


def check_layers(layers: Any) -> int | str:
    """``layers`` as an int ``>= 1`` or the string ``"auto"``.

    Parameters
    ----------
    layers : int or "auto"
        The depth layers asked for.

    Returns
    -------
    int or str
        ``layers`` as an int, or ``"auto"``.
    """
    if isinstance(layers, str):
        if layers == "auto":
            return layers
        raise ValidationError(expected_got("layers", "an integer >= 1 or 'auto'", repr(layers)))
    return as_int(layers, "layers", lo=1)


def plan_view_morph(image0: Any, image1: Any, correspondences: Any, *, prewarp: str = "auto",
                    intrinsics: tuple[Any, Any] | None = None, fundamental: Any = None,
                    threshold: float = tol.VM_THRESHOLD_PX, fallback: str = "raise",
                    frame_grid: int = 9, seed: int = 0, layers: int | str = 1, layer_depth: Any = None,
                    layer_overlap: float = tol.VM_LAYER_OVERLAP, fill_occluded: bool = False) -> MorphPlan:
    """Estimate a view morph of two reference images: F, pre-warps, fallbacks, layers, meshes.

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
        Side of the frame-point lattice (``>= 2``).
    seed : int
        Seed of the robust estimators (and of the spread subset a camera post-warp is fitted on).
    layers : int or "auto"
        Depth layers (:mod:`morphkit.viewmorph.layers`); 1 is Seitz & Dyer's
        single mesh. ``"auto"``: one mesh, unless it had to drop more than
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
        from the other image instead of blending with transparency
        (:func:`~morphkit.viewmorph.layers.known_mix`). No effect with one layer.

    Returns
    -------
    MorphPlan
        The estimate; apply it with :class:`~morphkit.viewmorph.morph.ViewMorpher`.

    Raises
    ------
    ValidationError
        Bad arguments or images, fewer than 8 distinct pairs, layers without depths.
    GeometryError
        Collinear points; no F (``fallback="raise"``).
    DegenerateViewError
        The pair cannot be rectified (``fallback="raise"``).
    FoldOverError
        A morph mesh cannot be repaired.

    See Also
    --------
    morphkit.viewmorph.morph.ViewMorpher.from_estimate : plan and apply in one call.

    References
    ----------
    .. [1] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.

    Examples
    --------
    Points of a scene seen by a camera that moved sideways (disparity ``20 / depth``,
    no vertical motion): the views are already parallel, so no pre-warp is needed.

    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> p0 = rng.uniform(8.0, 56.0, (40, 2))
    >>> p1 = p0 - np.c_[20.0 / rng.uniform(2.0, 4.0, 40), np.zeros(40)]
    >>> image = np.zeros((64, 64), np.uint8)
    >>> plan = plan_view_morph(image, image, (p0, p1))
    >>> plan.mode, plan.report.n_used, plan.report.fallback
    ('parallel', 40, None)

    Points of one plane (here a shift): one homography explains them.

    >>> plan_view_morph(image, image, (p0, p0 + [3.0, 1.0])).mode
    'homography'
    """
    if prewarp not in PREWARPS:
        raise ValidationError(expected_got("prewarp", f"one of {PREWARPS}", repr(prewarp)))
    if fallback not in FALLBACKS:
        raise ValidationError(expected_got("fallback", f"one of {FALLBACKS}", repr(fallback)))
    n_layers = check_layers(layers)
    overlap = float(layer_overlap)
    if not 0.0 <= overlap < 0.5:
        raise ValidationError(expected_got("layer_overlap", "a fraction in [0, 0.5)", repr(layer_overlap)))
    fill = as_flag(fill_occluded, "fill_occluded")
    frame_grid = as_int(frame_grid, "frame_grid", lo=2)
    seed = as_int(seed, "seed", lo=0)
    a, b, ch, dt = prepare_pair(image0, image1)
    shape0: tuple[int, int] = a.shape[:2]
    shape1: tuple[int, int] = b.shape[:2]
    prem = (to_premultiplied(a, ch), to_premultiplied(b, ch))
    corr = correspondences if isinstance(correspondences, Correspondences) else \
        Correspondences(*correspondences)
    n_input = len(corr)
    corr, ndup = corr.cleaned()
    if len(corr) < 8:
        raise ValidationError(expected_got(
            "correspondences", "at least 8 distinct pairs (F has 7 degrees of freedom)",
            f"{len(corr)} after dropping {ndup} duplicates"))
    check_spread(corr.pts0, "pts0")
    check_spread(corr.pts1, "pts1")
    K0, K1 = (None, None) if intrinsics is None else intrinsics
    cleaned = corr

    fit: FundamentalFit | None = None
    mode = "viewmorph"
    rect: Rectification | None = None
    reason: str | None = None
    n_outliers: int | None = None
    frac: float | None = None
    affine: AffineReport | None = None
    if prewarp == "none":
        mode = "morph"
    else:
        H_1_0, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
        if H_1_0 is None:
            try:
                fit = _fit_f(corr, fundamental, threshold, seed)
            except GeometryError as exc:
                if fallback == "raise":
                    raise
                mode, reason = "morph", str(exc)
        if fit is not None:
            n_outliers = int(np.count_nonzero(~fit.inliers))
            corr = corr.subset(fit.inliers)
            H_1_0, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
        frac = float(frac)
        if H_1_0 is not None:
            mode = "homography"
            fit = None
            H_0_1 = np.linalg.inv(H_1_0)
            rect = Rectification(np.eye(3), H_0_1 / H_0_1[2, 2], "homography",
                                 float(np.sqrt(np.mean((apply_h(H_0_1, corr.pts1) - corr.pts0) ** 2))),
                                 1.0, 1.0, {})
        elif mode == "viewmorph":
            assert fit is not None
            try:
                rect = rectify(fit.F, corr.pts0, corr.pts1, shape0, shape1, method=prewarp, K0=K0, K1=K1)
            except DegenerateViewError as exc:
                if fundamental is not None:  # a given F is not replaced
                    if fallback == "raise":
                        raise
                    alt, mode, reason = None, "morph", str(exc)
                else:  # an estimated F refused: replace it by the affine F when that explains the pairs
                    alt, affine = _affine_instead(cleaned, fit, exc, threshold, seed, prewarp, (K0, K1),
                                                  (shape0, shape1))
                    if alt is None:
                        if fallback == "raise":
                            raise DegenerateViewError(f"{exc}; {affine.refused}") from exc
                        mode, reason = "morph", f"{exc}; {affine.refused}"
                if alt is not None:
                    fit, rect = alt
                    corr = cleaned.subset(fit.inliers)
                    n_outliers = int(np.count_nonzero(~fit.inliers))
            if rect is not None and rect.method == "parallel":
                mode = "parallel"
    if rect is None:
        rect = Rectification(np.eye(3), np.eye(3), "none", float("nan"), 1.0, 1.0, {})

    # ---- depth layers, each with its own mesh in the shared rectified frame
    built, layer_report = build_layers(
        prem, corr, n_layers, layer_depth, overlap, frame_grid,
        H_rect_0=rect.H_rect_0, H_rect_1=rect.H_rect_1, shape0=shape0, shape1=shape1, fill_occluded=fill)
    offs = np.cumsum([0] + [len(L.r0) for L in built])
    is_corr = np.concatenate([L.is_corr for L in built])
    used = concat_correspondences([L.corr for L in built])
    report = MorphReport(
        mode=mode, n_input=n_input, n_duplicates=ndup, n_used=len(used),
        n_dropped_foldover=sum(L.n_dropped for L in built), n_frame_points=int(np.count_nonzero(~is_corr)),
        layers=layer_report.layers, n_outliers=n_outliers, homography_inlier_fraction=frac,
        fallback=reason, affine=affine, layer_edges=layer_report.layer_edges,
        auto_dropped_fraction=layer_report.auto_dropped_fraction, fill_occluded=layer_report.fill_occluded)
    return MorphPlan(
        shape0=shape0, shape1=shape1, channels=ch, dtype=dt, prem=prem, mode=mode, fit=fit,
        rectification=rect, layers=tuple(built),
        canvas=built[-1].canvas,  # the farthest (or only) layer covers the whole images
        correspondences=used,
        r0=np.concatenate([L.r0 for L in built]), r1=np.concatenate([L.r1 for L in built]),
        triangles=np.concatenate([L.tris + o for L, o in zip(built, offs, strict=False)]),
        is_correspondence=is_corr,
        # the pairs a post-warp to a camera is fitted on: at most VM_POST_FIT_PAIRS, spread over image 0
        post_fit_index=spread_subset(used.pts0, tol.VM_POST_FIT_PAIRS, np.random.default_rng(seed)),
        report=report)


# --------------------------------------------------------------------------- estimation helpers


def _fit_f(corr: Correspondences, fundamental: Any, threshold: float, seed: int) -> FundamentalFit:
    """The robust F of the pairs, or the given F with its inliers."""
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


def _affine_instead(corr: Correspondences, fit: FundamentalFit, refused: DegenerateViewError,
                    threshold: float, seed: int, prewarp: str, intrinsics: tuple[Any, Any],
                    shapes: tuple[tuple[int, int], tuple[int, int]]
                    ) -> tuple[tuple[FundamentalFit, Rectification] | None, AffineReport]:
    """The affine F and its pre-warps in place of a refused F, or None; and why (an :class:`AffineReport`).

    Used when the affine F keeps at least :data:`tol.VM_AFFINE_INLIER_RATIO`
    of the general F's inliers, fits the pairs both explain nearly as well
    (RMS within :data:`tol.VM_AFFINE_RMS_RATIO` times the general F's: the
    pair is nearly affine and the general F's epipole is not determined by
    the matches), and its pre-warps pass
    :func:`~morphkit.viewmorph.rectify.rectify`'s checks.
    """
    base = {"f_refused": str(refused), "f_inliers": fit.n_inliers}
    try:
        fa = estimate_affine_fundamental(corr.pts0, corr.pts1, threshold=threshold, seed=seed)
    except GeometryError as exc:
        return None, AffineReport(**base, refused=f"no affine F either: {exc}")
    ratio = fa.n_inliers / max(fit.n_inliers, 1)
    base.update(affine_inliers=fa.n_inliers, inlier_ratio=ratio)
    if ratio < tol.VM_AFFINE_INLIER_RATIO:
        return None, AffineReport(**base, refused=expected_got(
            "affine F (nearly affine views)", f">= {tol.VM_AFFINE_INLIER_RATIO:.0%} of the general F's "
            f"{fit.n_inliers} inliers", f"{fa.n_inliers} ({ratio:.0%})"))
    both = fit.inliers & fa.inliers
    rms = [float(np.sqrt(np.mean(sampson_distance(F, corr.pts0[both], corr.pts1[both]) ** 2)))
           for F in (fit.F, fa.F)]
    base.update(f_rms_px=rms[0], affine_rms_px=rms[1])
    if not rms[1] <= tol.VM_AFFINE_RMS_RATIO * rms[0]:
        return None, AffineReport(**base, refused=expected_got(
            "affine F (nearly affine views)",
            f"an RMS Sampson distance <= {tol.VM_AFFINE_RMS_RATIO} x the general F's ({rms[0]:.2e} px) "
            "on the pairs both explain", f"{rms[1]:.2e} px: the general F is determined"))
    inl = fa.inliers
    K0, K1 = intrinsics
    try:
        rect = rectify(fa.F, corr.pts0[inl], corr.pts1[inl], shapes[0], shapes[1], method=prewarp,
                       K0=K0, K1=K1)
    except DegenerateViewError as exc:
        return None, AffineReport(**base, refused=f"the affine F's pre-warps refused too: {exc}")
    return (fa, rect), AffineReport(**base, used=True)
