"""View morphing (Seitz & Dyer 1996): pre-warp, morph, post-warp, for one reference pair.

:class:`ViewMorpher` does everything that depends on the reference pair once
(correspondence cleaning, F, the pre-warps, the morph mesh, premultiplied
images, warpers); each :meth:`ViewMorpher.morph` call for a new ``s`` then costs
the interpolation of the mesh, one mesh-map computation and two ``cv2.remap``.

Convention
----------
* Pixels: ``(x, y)``, origin at the centre of the top-left pixel
  (:mod:`morphkit.conventions`); shapes are ``(H, W)``.
* The pre-warps ``H_rect_0`` and ``H_rect_1`` map image-0 and image-1 pixels to
  the shared rectified frame (:mod:`morphkit.viewmorph.rectify`). The rectified
  positions of a pair, ``r0 = H_rect_0 p0`` and ``r1 = H_rect_1 p1``, share their
  ``y``; the morph at ``s`` puts the pair at ``q(s) = (1 - s) r0 + s r1`` (the
  rectified-interpolated frame).
* The post-warp ``H_out_rect`` maps that frame to output pixels
  (:mod:`morphkit.viewmorph.postwarp`). Default (``post="interpolate"``): the
  homography taking the interpolated rectified image corners
  ``(1 - s) H_rect_0 c0 + s H_rect_1 c1`` to the interpolated output corners
  ``(1 - s) c0 + s c1`` (so ``H_out_rect = H_rect_0^-1`` at ``s = 0`` and
  ``H_rect_1^-1`` at ``s = 1``; in between it interpolates the two views' image
  planes).
* Warps are backward (``cv2.remap``): each output pixel samples image ``i`` at
  the position the mesh gives it.

The morph mesh and depth layers
-------------------------------
See :mod:`morphkit.viewmorph.mesh` (frame points, fold-overs) and
:mod:`morphkit.viewmorph.layers` (``layers=k``, ``layers="auto"``).

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
---------------------------------------------------------------------------
======================================  ============================================================
case                                    policy
======================================  ============================================================
fewer than 8 pairs (after cleaning)     ValidationError
NaN/inf coordinates                     ValidationError
duplicated pairs                        dropped (kept the first), counted in ``report``
collinear points                        GeometryError
one homography explains the pairs       mode ``"homography"``: ``H_rect_0 = I``, ``H_rect_1 = H_0_1``;
(planar scene, pure rotation, zero      morph of aligned images, post-warp interpolating ``I .. H_1_0``
baseline, identical images)             (identical images give the input at every s)
outliers                                robust F (USAC-MAGSAC); only inliers are used
views already parallel                  mode ``"parallel"``: no pre-warp
epipole in/near an image, or pre-warps  an estimated F is replaced by the affine F (both epipoles at
too distorting                          infinity) when that keeps >= tol.VM_AFFINE_INLIER_RATIO of its
                                        inliers, fits them about as well (tol.VM_AFFINE_RMS_RATIO) and
                                        passes the checks (``report["affine"]``); else
                                        DegenerateViewError; ``fallback="morph"``: mode ``"morph"``
                                        (plain mesh morph, no pre-/post-warp), reason in ``report``
fold-overs                              vertices dropped (viewmorph.mesh); FoldOverError if that fails
images of different sizes               supported: output size interpolates between them
grey / RGB / RGBA, mixed                promoted to the richer layout (grey < RGB < RGBA)
different dtypes                        ValidationError
s outside [0, 1]                        ValidationError
layers > 1/auto without depths or keys  ValidationError (pairs need ``depth``, ``layer_depth`` keys)
a layer below VM_MIN_LAYER_PAIRS pairs  fewer layers (``report["layers"]``)
======================================  ============================================================
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..composite import from_premultiplied, over, to_premultiplied
from ..errors import (
    DegenerateViewError,
    FoldOverError,
    GeometryError,
    ValidationError,
    expected_got,
)
from ..validate import as_finite_array, as_points, as_shape, as_unit_interval
from ..warp import MeshWarper
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
from .layers import FAR_POSITION, MorphLayer, build_layers, concat_correspondences, known_mix
from .postwarp import (
    FRAMES,
    PostWarpPoints,
    fit_post_homography,
    frame_post_homography,
    interpolated_post_homography,
    overshoot,
)
from .rectify import Rectification, apply_h, rectify

__all__ = ["ViewMorpher", "PREWARPS", "FALLBACKS", "FRAMES"]

#: The values of ``ViewMorpher(prewarp=...)`` (and ``morphkit viewmorph --prewarp``).
PREWARPS = ("auto", "opencv", "seitz-dyer", "none")
#: The values of ``ViewMorpher(fallback=...)``: refuse a degenerate pair, or plain mesh morph.
FALLBACKS = ("raise", "morph")
PATHS = ("direct", "rectified")


# --------------------------------------------------------------------------- morpher


class ViewMorpher:
    """View morphing between two reference images; build once, call :meth:`ViewMorpher.morph` per ``s``.

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
        from the other image instead of blending with transparency
        (:func:`~morphkit.viewmorph.layers.known_mix`). No effect with one layer.

    Attributes
    ----------
    mode : str
        ``"viewmorph"``, ``"parallel"``, ``"homography"`` or ``"morph"``.
    fit : FundamentalFit or None
    rectification : Rectification
    H_rect_0, H_rect_1 : (3, 3) float64
        The pre-warps (image-``i`` pixels to the rectified frame; identities
        without a pre-warp).
    shape0, shape1 : (H, W)
        The reference images' shapes.
    channels : int
        The output layout (1 grey, 3 RGB, 4 RGBA: the richer input's).
    dtype : numpy.dtype
        The inputs' (and outputs') dtype.
    correspondences : Correspondences
        The pairs kept in the mesh (inliers, de-duplicated, not dropped for
        fold-overs); with layers, each layer's in turn (pairs in an overlap repeat).
    triangles : (M, 3) int
        The mesh triangles (all layers'), indexing :meth:`vertices`.
    is_correspondence : (V,) bool
        For each vertex of :meth:`vertices`: True for the pairs (in the order of
        :attr:`correspondences`), False for frame points.
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
        if not isinstance(fill_occluded, bool | np.bool_):
            raise ValidationError(expected_got("fill_occluded", "a bool", repr(fill_occluded)))
        a, b, ch, dt = prepare_pair(image0, image1)
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
        cleaned = corr

        self.fit: FundamentalFit | None = None
        mode = "viewmorph"
        rect: Rectification | None = None
        if prewarp == "none":
            mode = "morph"
        else:
            H_1_0, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
            if H_1_0 is None:
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
                H_1_0, frac = homography_degeneracy(corr.pts0, corr.pts1, threshold=threshold)
            report["homography_inlier_fraction"] = float(frac)
            if H_1_0 is not None:
                mode = "homography"
                self.fit = None
                H_0_1 = np.linalg.inv(H_1_0)
                rect = Rectification(np.eye(3), H_0_1 / H_0_1[2, 2], "homography",
                                     float(np.sqrt(np.mean((apply_h(H_0_1, corr.pts1) - corr.pts0) ** 2))),
                                     1.0, 1.0, {})
            elif mode == "viewmorph":
                try:
                    rect = rectify(self.fit.F, corr.pts0, corr.pts1, self.shape0, self.shape1,
                                   method=prewarp, K0=K0, K1=K1)
                except DegenerateViewError as exc:
                    # an estimated F refused: replace it by the affine F when that explains the pairs
                    alt = None if fundamental is not None else self._affine_instead(
                        cleaned, self.fit, exc, threshold, seed, prewarp, (K0, K1), report)
                    if alt is None:
                        if fallback == "raise":
                            raise DegenerateViewError(f"{exc}; {report['affine']['refused']}") from exc
                        mode, report["fallback"] = "morph", f"{exc}; {report['affine']['refused']}"
                    else:
                        self.fit, rect = alt
                        corr = cleaned.subset(self.fit.inliers)
                        report["n_outliers"] = int(np.count_nonzero(~self.fit.inliers))
                if rect is not None and rect.method == "parallel":
                    mode = "parallel"
        if rect is None:
            rect = Rectification(np.eye(3), np.eye(3), "none", float("nan"), 1.0, 1.0, {})
        self.mode = mode
        self.rectification = rect
        self.H_rect_0, self.H_rect_1 = rect.H_rect_0, rect.H_rect_1
        if self.fit is not None:
            report["fundamental"] = self.fit.report()
        report["rectification"] = rect.report()
        report["mode"] = mode

        # ---- depth layers, each with its own mesh in the shared rectified frame
        self._layers, layer_report = build_layers(
            self._prem, corr, n_layers, layer_depth, overlap, frame_grid,
            H_rect_0=self.H_rect_0, H_rect_1=self.H_rect_1, shape0=self.shape0, shape1=self.shape1,
            fill_occluded=bool(fill_occluded))
        report.update(layer_report)
        self._canvas = self._layers[-1].canvas  # the farthest (or only) layer covers the whole images
        offs = np.cumsum([0] + [len(L.r0) for L in self._layers])
        self._r0 = np.concatenate([L.r0 for L in self._layers])
        self._r1 = np.concatenate([L.r1 for L in self._layers])
        self.triangles = np.concatenate([L.tris + o for L, o in zip(self._layers, offs, strict=False)])
        self.is_correspondence = np.concatenate([L.is_corr for L in self._layers])
        self.correspondences = concat_correspondences([L.corr for L in self._layers])
        report["n_dropped_foldover"] = sum(L.n_dropped for L in self._layers)
        report["n_frame_points"] = int(np.count_nonzero(~self.is_correspondence))
        report["n_used"] = len(self.correspondences)
        # the pairs a post-warp to a camera is fitted on: at most VM_POST_FIT_PAIRS, spread over image 0
        self._post_fit_index = spread_subset(self.correspondences.pts0, tol.VM_POST_FIT_PAIRS,
                                              np.random.default_rng(seed))
        self._rectified: tuple[np.ndarray, np.ndarray] | None = None
        self.report = report

    # ---------------------------------------------------------------- construction helpers
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

    def _affine_instead(self, corr: Correspondences, fit: FundamentalFit, refused: DegenerateViewError,
                        threshold: float, seed: int, prewarp: str, intrinsics: tuple[Any, Any],
                        report: dict[str, Any]) -> tuple[FundamentalFit, Rectification] | None:
        """The affine F and its pre-warps in place of a refused F, or None (why: ``report["affine"]``).

        Used when the affine F keeps at least :data:`tol.VM_AFFINE_INLIER_RATIO`
        of the general F's inliers, fits the pairs both explain nearly as well
        (RMS within :data:`tol.VM_AFFINE_RMS_RATIO` times the general F's: the
        pair is nearly affine and the general F's epipole is not determined by
        the matches), and its pre-warps pass
        :func:`~morphkit.viewmorph.rectify.rectify`'s checks.
        """
        info: dict[str, Any] = {"f_refused": str(refused), "f_inliers": fit.n_inliers}
        report["affine"] = info
        try:
            fa = estimate_affine_fundamental(corr.pts0, corr.pts1, threshold=threshold, seed=seed)
        except GeometryError as exc:
            info["refused"] = f"no affine F either: {exc}"
            return None
        ratio = fa.n_inliers / max(fit.n_inliers, 1)
        info.update(affine_inliers=fa.n_inliers, inlier_ratio=ratio)
        if ratio < tol.VM_AFFINE_INLIER_RATIO:
            info["refused"] = expected_got(
                "affine F (nearly affine views)", f">= {tol.VM_AFFINE_INLIER_RATIO:.0%} of the general F's "
                f"{fit.n_inliers} inliers", f"{fa.n_inliers} ({ratio:.0%})")
            return None
        both = fit.inliers & fa.inliers
        rms = [float(np.sqrt(np.mean(sampson_distance(F, corr.pts0[both], corr.pts1[both]) ** 2)))
               for F in (fit.F, fa.F)]
        info.update(f_rms_px=rms[0], affine_rms_px=rms[1])
        if not rms[1] <= tol.VM_AFFINE_RMS_RATIO * rms[0]:
            info["refused"] = expected_got(
                "affine F (nearly affine views)",
                f"an RMS Sampson distance <= {tol.VM_AFFINE_RMS_RATIO} x the general F's ({rms[0]:.2e} px) "
                "on the pairs both explain", f"{rms[1]:.2e} px: the general F is determined")
            return None
        inl = fa.inliers
        K0, K1 = intrinsics
        try:
            rect = rectify(fa.F, corr.pts0[inl], corr.pts1[inl], self.shape0, self.shape1, method=prewarp,
                           K0=K0, K1=K1)
        except DegenerateViewError as exc:
            info["refused"] = f"the affine F's pre-warps refused too: {exc}"
            return None
        info["used"] = True
        return fa, rect

    # ---------------------------------------------------------------- geometry per s
    def vertices(self, s: float) -> np.ndarray:
        """Mesh vertices ``q(s) = (1 - s) r0 + s r1`` in the rectified-interpolated frame.

        Parameters
        ----------
        s : float in [0, 1]

        Returns
        -------
        numpy.ndarray
            ``(V, 2)`` float64 positions of all layers' vertices (frame points
            and pairs; :attr:`is_correspondence` tells them apart), indexed by
            :attr:`triangles`.
        """
        s = as_unit_interval(s, "s")
        return self._r0 + s * (self._r1 - self._r0)

    def out_shape(self, s: float) -> tuple[int, int]:
        """Default output shape: the input shapes interpolated by ``s`` (rounded).

        Parameters
        ----------
        s : float in [0, 1]

        Returns
        -------
        tuple of int
            ``(H, W)``.
        """
        s = as_unit_interval(s, "s")
        return (int(round((1 - s) * self.shape0[0] + s * self.shape1[0])),
                int(round((1 - s) * self.shape0[1] + s * self.shape1[1])))

    def post_homography(self, s: float, post: Any = "interpolate") -> tuple[np.ndarray, tuple[int, int]]:
        """The post-warp ``H_out_rect`` for ``s`` and its default output shape.

        Parameters
        ----------
        s : float
            Morph parameter in ``[0, 1]`` (0: view 0, 1: view 1).
        post : "interpolate", "rectified", (3, 3) array, CameraModel or PostWarpPoints
            ``"interpolate"``: corners interpolated between the two views (module
            convention). ``"rectified"``: no post-warp (a translation to the
            rectified canvas, whose size is returned). A (3, 3) array: ``H_out_rect``
            itself. A :class:`~morphkit.camera.CameraModel`: the least-squares
            homography taking ``q(s)`` of the correspondences (at most
            :data:`tol.VM_POST_FIT_PAIRS` of them, spread over image 0) to their
            projections in that camera (needs ``points3d``, i.e. correspondences
            from geometry); the camera's shape. :class:`PostWarpPoints`:
            least squares on the given points.

        Returns
        -------
        H_out_rect : numpy.ndarray
            ``(3, 3)`` float64 post-warp (before the crop/size policy of
            :meth:`apply_frame`).
        shape : tuple of int
            The default output ``(H, W)`` for it.

        Notes
        -----
        Convention: ``H_out_rect`` maps rectified-interpolated coordinates (pixel-centre origin) to
        output pixels: ``out = H_out_rect q``.
        """
        s = as_unit_interval(s, "s")
        q = self.vertices(s)
        if isinstance(post, str) and post == "interpolate":
            H_out_rect = interpolated_post_homography(self.H_rect_0, self.H_rect_1, self.shape0, self.shape1,
                                                      s)
            return H_out_rect, self.out_shape(s)
        if isinstance(post, str) and post == "rectified":
            lo, hi = self._canvas
            H_out_rect = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
            return H_out_rect, (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
        if isinstance(post, CameraModel):
            if self.correspondences.points3d is None:
                raise ValidationError(expected_got("post", "a camera only with correspondences from geometry "
                                                   "(points3d)", "correspondences without 3-D points"))
            idx = self._post_fit_index
            tgt, _ = post.project(self.correspondences.points3d[idx])
            H_out_rect = fit_post_homography(q[self.is_correspondence][idx], tgt)
            return H_out_rect, post.shape
        if isinstance(post, PostWarpPoints):
            index = np.asarray(post.index, dtype=np.int64).ravel()
            pts = as_points(post.points, "post points", min_count=4)
            if index.size != len(pts) or np.any(index < 0) or np.any(index >= len(self.correspondences)):
                raise ValidationError(expected_got("post index", f"{len(pts)} indices in "
                                                   f"[0, {len(self.correspondences)})", index.tolist()[:8]))
            H_out_rect = fit_post_homography(q[self.is_correspondence][index], pts)
            return H_out_rect, self.out_shape(s)
        if isinstance(post, str):
            raise ValidationError(expected_got("post", "'interpolate', 'rectified', a 3x3 array, a "
                                               "CameraModel or PostWarpPoints", repr(post)))
        H_out_rect = as_finite_array(post, "post", shape=(3, 3))
        if abs(np.linalg.det(H_out_rect)) < 1e-300:
            raise ValidationError(expected_got("post", "a regular homography", "a singular matrix"))
        return H_out_rect, self.out_shape(s)

    def apply_frame(self, H_out_rect: np.ndarray, s: float, shape: tuple[int, int], frame: str) -> np.ndarray:
        """A post-warp with the crop/size policy ``frame`` applied (see :meth:`ViewMorpher.morph`).

        Parameters
        ----------
        H_out_rect : (3, 3) float
            A post-warp (rectified-interpolated frame to output pixels).
        s : float in [0, 1]
        shape : (H, W)
            The output shape.
        frame : {"contain", "fixed", "fit"}
            See :func:`~morphkit.viewmorph.postwarp.frame_post_homography`; under
            ``"contain"`` the pairs may leave the frame as far as they leave
            the input images (interpolated by ``s``).

        Returns
        -------
        numpy.ndarray
            ``(3, 3)`` float64: ``H_framed_out @ H_out_rect`` (a scale and shift
            of output pixels), or ``H_out_rect`` itself.
        """
        if frame == "fixed":
            return H_out_rect
        slack = 0.0
        if frame == "contain":
            slack = (1 - s) * overshoot(self.correspondences.pts0, self.shape0) + \
                s * overshoot(self.correspondences.pts1, self.shape1)
        obj = self.vertices(s)[self.is_correspondence]
        return frame_post_homography(H_out_rect, obj, shape, frame, slack)

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
            margin; ``"fixed"`` keeps ``H_out_rect`` as is.
        path : {"direct", "rectified"}
            See the module docstring.

        Returns
        -------
        numpy.ndarray
            The layout (grey/RGB/RGBA, promoted) and dtype of the inputs.

        Notes
        -----
        Convention: Output pixel ``p`` shows the mesh point ``H_out_rect^-1 p`` of the
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
        H_out_rect, shape = self.post_homography(s, post)
        if out_shape is not None:
            shape = as_shape(out_shape, "out_shape")
        H_out_rect = self.apply_frame(H_out_rect, s, shape, frame)
        if path == "direct":
            acc = self._render_direct(s, H_out_rect, shape)
        else:
            acc = self._render_rectified(s, H_out_rect, shape)
        return from_premultiplied(acc, self.channels, self.dtype)

    def frames(self, n: int, **kw: Any) -> list[np.ndarray]:
        """``n >= 2`` views at ``s = 0, 1/(n-1), ..., 1``.

        Parameters
        ----------
        n : int
            Number of views, ``>= 2``.
        **kw
            Keyword arguments of :meth:`ViewMorpher.morph`.

        Returns
        -------
        list of numpy.ndarray
            The views, as :meth:`ViewMorpher.morph` returns them.
        """
        n = int(n)
        if n < 2:
            raise ValidationError(expected_got("n", "an int >= 2", n))
        return [self.morph(float(s), **kw) for s in np.linspace(0.0, 1.0, n)]

    @staticmethod
    def _dst(layer: MorphLayer, s: float, H_out_rect: np.ndarray) -> np.ndarray:
        q = np.c_[layer.r0 + s * (layer.r1 - layer.r0), np.ones(len(layer.r0))] @ H_out_rect.T
        w = q[:, 2]
        wc = np.median(w)
        if np.any(w * np.sign(wc) <= 1e-9 * abs(wc)):
            raise DegenerateViewError(expected_got(
                "post-warp", "a homography keeping the morph mesh in front (w > 0)",
                "one sending part of it through infinity"))
        return q[:, :2] / w[:, None]

    def _render_direct(self, s: float, H_out_rect: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        h, w = shape
        nch = self._prem[0].shape[2]
        out: np.ndarray | None = None
        for layer in reversed(self._layers):  # far to near, premultiplied "over"
            got = self._render_layer(layer, s, H_out_rect, shape)
            if got is not None:
                out = over(out, got[1], got[0], shape)
        return np.zeros((h, w, nch), np.float32) if out is None else out

    def _render_layer(self, layer: MorphLayer, s: float, H_out_rect: np.ndarray, shape: tuple[int, int]
                      ) -> tuple[tuple[int, int, int, int], np.ndarray] | None:
        """One layer's premultiplied morph over its region of interest (None if it covers nothing)."""
        dst = self._dst(layer, s, H_out_rect)
        prem0, prem1 = layer.prem
        if s >= 1.0:
            wm1 = self._maps(layer.w1, dst, shape)
            m1, m2 = wm1.map1, wm1.map2
            if m1 is None:
                return None
            a1 = cv2.remap(prem1, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            return wm1.roi, (a1[..., :-1] if layer.known else a1)
        wm0 = self._maps(layer.w0, dst, shape)
        m1, m2 = wm0.map1, wm0.map2
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
                         borderValue=(FAR_POSITION, FAR_POSITION, 0, 0))
        a1 = cv2.remap(prem1, pos1, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        mix = known_mix(a0, a1, s) if layer.known else cv2.addWeighted(a0, 1.0 - s, a1, s, 0.0)
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
    def _prewarp_images(prem: tuple[np.ndarray, np.ndarray], H_rect_img: tuple[np.ndarray, np.ndarray],
                        canvas: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = canvas
        shape = (int(hi[1] - lo[1]) + 1, int(hi[0] - lo[0]) + 1)
        H_canvas_rect = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
        ims = tuple(cv2.warpPerspective(p, H_canvas_rect @ H_rect_i, (shape[1], shape[0]),
                                        flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
                    for p, H_rect_i in zip(prem, H_rect_img, strict=True))
        return ims[0], ims[1]

    def rectified_images(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The two pre-warped (premultiplied float32) images on the rectified canvas, and its origin.

        Returns
        -------
        rect0, rect1 : numpy.ndarray
            float32 ``(h, w, C + 1)`` premultiplied images (colour times alpha,
            then alpha; :func:`morphkit.composite.to_premultiplied`), warped by
            ``H_rect_0`` / ``H_rect_1`` onto the canvas (cached; do not modify).
        origin : numpy.ndarray
            ``(2,)`` float64 rectified-frame position of canvas pixel ``(0, 0)``.

        Convention: canvas pixel ``(x, y)`` is rectified-frame point ``(x, y) + origin``.
        """
        if self._rectified is None:
            self._rectified = self._prewarp_images(self._prem, (self.H_rect_0, self.H_rect_1), self._canvas)
        return self._rectified[0], self._rectified[1], self._canvas[0].copy()

    def _render_rectified(self, s: float, H_out_rect: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        out: np.ndarray | None = None
        for layer in reversed(self._layers):  # far to near, premultiplied "over"
            if layer.rectified is None:
                layer.rectified = (self.rectified_images()[:2] if len(self._layers) == 1 else
                                   self._prewarp_images(layer.prem, (self.H_rect_0, self.H_rect_1),
                                                        layer.canvas))
            rect0, rect1 = layer.rectified
            lo = layer.canvas[0]
            cshape = rect0.shape[:2]
            q = layer.r0 + s * (layer.r1 - layer.r0) - lo
            parts = [(MeshWarper(r - lo, layer.tris).maps(q, cshape).apply(img, fill=0.0), wgt)
                     for img, r, wgt in ((rect0, layer.r0, 1.0 - s), (rect1, layer.r1, s)) if wgt > 0.0]
            if layer.known and len(parts) == 2:
                acc = known_mix(parts[0][0], parts[1][0], s)
            elif layer.known:
                acc = np.ascontiguousarray(parts[0][0][..., :-1])
            else:
                acc = parts[0][0] * np.float32(parts[0][1])
                if len(parts) == 2:
                    acc = cv2.addWeighted(acc, 1.0, parts[1][0], parts[1][1], 0.0)
            H_rect_canvas = np.array([[1.0, 0.0, lo[0]], [0.0, 1.0, lo[1]], [0.0, 0.0, 1.0]])
            img = cv2.warpPerspective(acc, H_out_rect @ H_rect_canvas, (shape[1], shape[0]),
                                      flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            out = over(out, img.reshape(shape + (acc.shape[2],)), (0, shape[0], 0, shape[1]), shape)
        assert out is not None
        return out
