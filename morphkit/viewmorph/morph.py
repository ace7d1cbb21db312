"""View morphing (Seitz & Dyer 1996): pre-warp, morph, post-warp, applied to one reference pair's plan.

:class:`ViewMorpher` applies a :class:`~morphkit.viewmorph.plan.MorphPlan`, the
estimate of everything that depends on the reference pair (correspondence
cleaning, F, the pre-warps, the morph mesh, premultiplied images, warpers;
:func:`~morphkit.viewmorph.plan.plan_view_morph`, or both in one line with
:meth:`ViewMorpher.from_estimate`); each :meth:`ViewMorpher.morph` call for a
new ``s`` then costs the interpolation of the mesh, one mesh-map computation
and two ``cv2.remap``.

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

Fallbacks and refusals
----------------------
What a pair that cannot be rectified becomes (or which error refuses it) is
decided by :func:`~morphkit.viewmorph.plan.plan_view_morph` (the table in
:mod:`morphkit.viewmorph.plan`). Here: ``s`` outside [0, 1] and bad
``post``/``frame``/``path``/``out_shape`` raise ValidationError; a post-warp
that sends the mesh through infinity raises DegenerateViewError.
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import DegenerateViewError, FoldOverError, ValidationError, expected_got
from ..imaging.composite import from_premultiplied, over
from ..memo import Memo
from ..validate import as_finite_array, as_int, as_points, as_shape, as_unit_interval
from ..warp import MeshWarper
from .fundamental import FundamentalFit
from .layers import FAR_POSITION, MorphLayer, known_mix
from .matching import from_images
from .plan import FALLBACKS, PREWARPS, MorphPlan, MorphReport, plan_view_morph
from .postwarp import (
    FRAMES,
    PostWarpPoints,
    fit_post_homography,
    frame_post_homography,
    interpolated_post_homography,
    overshoot,
)
from .rectify import Rectification

__all__ = ["ViewMorpher", "PREWARPS", "FALLBACKS", "FRAMES", "PATHS"]

#: The values of ``ViewMorpher.morph(path=...)``.
PATHS = ("direct", "rectified")
#: Key of the whole images' pre-warped pair in a ViewMorpher's cache (layers are keyed 0, 1, ...).
_IMAGES = -1


# --------------------------------------------------------------------------- morpher


class ViewMorpher:
    """View morphing between two reference images: applies a plan, one :meth:`ViewMorpher.morph` per ``s``.

    Parameters
    ----------
    plan : MorphPlan
        The estimate of the pair (:func:`~morphkit.viewmorph.plan.plan_view_morph`).
        To plan and apply in one line: :meth:`ViewMorpher.from_estimate`.

    Attributes
    ----------
    plan : MorphPlan
        The plan applied.
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
    report : MorphReport
        What happened: counts of input/duplicate/outlier/dropped pairs, the
        fallbacks and layers chosen (typed fields).

    References
    ----------
    .. [1] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.

    Examples
    --------
    A camera moved sideways over points at depths 2 to 4 (disparity ``20 / depth``):
    plan once, then render any in-between view.

    >>> import numpy as np
    >>> from morphkit.viewmorph.plan import plan_view_morph
    >>> rng = np.random.default_rng(0)
    >>> p0 = rng.uniform(8.0, 56.0, (40, 2))
    >>> p1 = p0 - np.c_[20.0 / rng.uniform(2.0, 4.0, 40), np.zeros(40)]
    >>> left = np.tile(np.arange(64, dtype=np.uint8) * 4, (64, 1))
    >>> vm = ViewMorpher(plan_view_morph(left, left, (p0, p1)))
    >>> vm.mode, vm.morph(0.5).shape
    ('parallel', (64, 64))

    The same in one line, with :func:`plan_view_morph`'s arguments:

    >>> ViewMorpher.from_estimate(left, left, (p0, p1)).report.layers
    1
    """

    def __init__(self, plan: MorphPlan) -> None:
        if not isinstance(plan, MorphPlan):
            raise ValidationError(expected_got(
                "plan", "a MorphPlan (plan_view_morph(...); or ViewMorpher.from_estimate(image0, image1, "
                "correspondences, ...))", type(plan).__name__))
        self.plan = plan
        self.mode: str = plan.mode
        self.fit: FundamentalFit | None = plan.fit
        self.rectification: Rectification = plan.rectification
        self.H_rect_0, self.H_rect_1 = plan.H_rect_0, plan.H_rect_1
        self.shape0, self.shape1 = plan.shape0, plan.shape1
        self.channels, self.dtype = plan.channels, plan.dtype
        self.correspondences = plan.correspondences
        self.triangles = plan.triangles
        self.is_correspondence = plan.is_correspondence
        self.report: MorphReport = plan.report
        self._prem = plan.prem
        self._layers: tuple[MorphLayer, ...] = plan.layers
        self._canvas = plan.canvas
        self._r0, self._r1 = plan.r0, plan.r1
        # pre-warped images of path="rectified", made on first use: the whole images', then each layer's
        self._rectified: Memo[int, tuple[np.ndarray, np.ndarray]] = Memo()

    @classmethod
    def from_estimate(cls, image0: Any, image1: Any, correspondences: Any = None, **options: Any
                      ) -> ViewMorpher:
        """Plan the pair (:func:`~morphkit.viewmorph.plan.plan_view_morph`) and apply the plan.

        Parameters
        ----------
        image0, image1 : numpy.ndarray
            The reference images (see :func:`~morphkit.viewmorph.plan.plan_view_morph`).
        correspondences : Correspondences or (pts0, pts1), optional
            Pixel pairs; default: matched in the images alone
            (:func:`~morphkit.viewmorph.matching.from_images`, which refuses two images that do
            not seem to show one scene).
        **options
            Keyword arguments of :func:`~morphkit.viewmorph.plan.plan_view_morph`
            (``prewarp``, ``fallback``, ``layers``, ...).

        Returns
        -------
        ViewMorpher
            The morpher of the plan.

        Raises
        ------
        ValidationError
            Bad images or options; without ``correspondences``, images with too few distinctive
            matches (:func:`~morphkit.viewmorph.matching.from_images`).
        """
        if correspondences is None:
            correspondences = from_images(image0, image1)
        return cls(plan_view_morph(image0, image1, correspondences, **options))

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
            idx = self.plan.post_fit_index
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
        if abs(np.linalg.det(H_out_rect)) < tol.ZERO:
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
        n = as_int(n, "n", lo=2)
        return [self.morph(float(s), **kw) for s in np.linspace(0.0, 1.0, n)]

    @staticmethod
    def _dst(layer: MorphLayer, s: float, H_out_rect: np.ndarray) -> np.ndarray:
        q = np.c_[layer.r0 + s * (layer.r1 - layer.r0), np.ones(len(layer.r0))] @ H_out_rect.T
        w = q[:, 2]
        wc = np.median(w)
        if np.any(w * np.sign(wc) <= tol.REL_EQUAL * abs(wc)):
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
            then alpha; :func:`morphkit.imaging.composite.to_premultiplied`), warped by
            ``H_rect_0`` / ``H_rect_1`` onto the canvas (cached; do not modify).
        origin : numpy.ndarray
            ``(2,)`` float64 rectified-frame position of canvas pixel ``(0, 0)``.

        Convention: canvas pixel ``(x, y)`` is rectified-frame point ``(x, y) + origin``.
        """
        rect0, rect1 = self._rectified.get(_IMAGES, lambda: self._prewarp_images(
            self._prem, (self.H_rect_0, self.H_rect_1), self._canvas))
        return rect0, rect1, self._canvas[0].copy()

    def _render_rectified(self, s: float, H_out_rect: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
        out: np.ndarray | None = None
        for i in reversed(range(len(self._layers))):  # far to near, premultiplied "over"
            layer = self._layers[i]
            if len(self._layers) == 1:
                rect0, rect1 = self.rectified_images()[:2]
            else:
                rect0, rect1 = self._rectified.get(i, lambda layer=layer: self._prewarp_images(
                    layer.prem, (self.H_rect_0, self.H_rect_1), layer.canvas))
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
