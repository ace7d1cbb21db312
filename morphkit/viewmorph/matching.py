"""Correspondences from the images alone: a family of matchers behind one protocol.

* :class:`SiftMatcher` -- SIFT features on the (upscaled) grey image, Lowe's
  ratio test and a mutual (cross-check) test: sparse, but robust to large
  motion;
* :class:`FlowMatcher` -- dense optical flow (OpenCV's DIS) both ways, sampled
  on a pixel grid and kept where the two flows agree (forward-backward check):
  hundreds of pairs spread over the object, where SIFT finds a few dozen on
  small renders;
* :class:`CombinedMatcher` -- the union of several matchers' pairs (duplicates
  dropped by :meth:`Correspondences.cleaned` later).

:func:`from_images` runs one (default :data:`DEFAULT_MATCHER`: SIFT and flow
combined) and refuses two images that share fewer distinctive (SIFT) matches than
:data:`morphkit.tol.VM_MIN_SCENE_MATCHES` (the command line and the library alike). Every
matcher's result still holds outliers: the view morpher fits F
robustly (:func:`morphkit.viewmorph.fundamental.estimate_fundamental`) and keeps
its inliers. Measured success rates of the image-only path are in
``docs/RESULTS.md`` (``morphkit bench viewmorph``, ``viewmorph-images`` rows).

Inputs: grey, RGB or RGBA of uint8/uint16/float in [0, 1]; RGBA images are
matched on their premultiplied colour and only where alpha > 0. Pixels follow
:mod:`morphkit.conventions` (origin at the centre of the top-left pixel).

SIFT [1]_ and DIS optical flow [2]_ are OpenCV's.

References
----------
.. [1] D. G. Lowe, "Distinctive Image Features from Scale-Invariant Keypoints", International Journal of
   Computer Vision, 60(2), pp. 91-110, 2004.
.. [2] T. Kroeger, R. Timofte, D. Dai and L. Van Gool, "Fast Optical Flow using Dense Inverse Search",
   Proc. ECCV, pp. 471-488, 2016.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import cv2
import numpy as np

from .. import tol
from ..conventions import SIFT_KEYPOINT_OFFSET_PX
from ..errors import ValidationError, expected_got
from ..validate import as_image, as_int
from .correspondences import Correspondences

__all__ = ["ImageMatcher", "SiftMatcher", "FlowMatcher", "CombinedMatcher", "DEFAULT_MATCHER", "from_images",
           "join_matches"]

DIS_PRESETS = {"ultrafast": cv2.DISOPTICAL_FLOW_PRESET_ULTRAFAST, "fast": cv2.DISOPTICAL_FLOW_PRESET_FAST,
               "medium": cv2.DISOPTICAL_FLOW_PRESET_MEDIUM}


@runtime_checkable
class ImageMatcher(Protocol):
    """Finds corresponding pixels of two images of the same object.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol describes objects, it is not instantiated.
    """

    def match(self, image0: np.ndarray, image1: np.ndarray) -> Correspondences:
        """Pairs ``pts0[i]`` (image 0) ~ ``pts1[i]`` (image 1), pixel-centre origin, ``source="features"``.

        Parameters
        ----------
        image0, image1 : (H, W) or (H, W, C) numpy.ndarray
            The two images (grey, RGB or RGBA; uint8, integer or float in ``[0, 1]``).

        Returns
        -------
        morphkit.viewmorph.correspondences.Correspondences
            The pairs.
        """
        ...


def _gray_u8(img: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """8-bit grey version of ``img`` and, for RGBA, the alpha > 0 mask (uint8 0/255) and that mask
    dilated by 2 px."""
    a = as_image(img, "image", channels=(1, 3, 4))
    if a.dtype == np.uint8:
        f = a
    elif a.dtype.kind == "f":
        f = np.clip(np.rint(a * 255.0), 0, 255).astype(np.uint8)
    else:
        top = float(np.iinfo(a.dtype).max)
        f = np.clip(np.rint(a.astype(np.float64) * (255.0 / top)), 0, 255).astype(np.uint8)
    mask = dilated = None
    if f.ndim == 3 and f.shape[2] == 4:
        alpha = f[..., 3]
        mask = (alpha > 0).astype(np.uint8) * 255
        dilated = cv2.dilate(mask, np.ones((5, 5), np.uint8))
        rgb = (f[..., :3].astype(np.float32) * (alpha[..., None] / 255.0)).astype(np.uint8)
        gray = cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY)
    elif f.ndim == 3:
        gray = cv2.cvtColor(np.ascontiguousarray(f), cv2.COLOR_RGB2GRAY)
    else:
        gray = f
    return np.ascontiguousarray(gray), mask, dilated


def _empty() -> Correspondences:
    return Correspondences(np.zeros((0, 2)), np.zeros((0, 2)), "features")


@dataclass(frozen=True)
class SiftMatcher:
    """SIFT features, Lowe's ratio test and a mutual (cross-check) test.

    Parameters
    ----------
    ratio : float
        Lowe's ratio: keep a match whose best distance is below ``ratio`` times
        the second best.
    max_features : int
        SIFT ``nfeatures`` per image.
    cross_check : bool
        Keep only mutual best matches (image 0 -> 1 and 1 -> 0 agree).
    contrast_threshold : float
        SIFT's ``contrastThreshold`` (OpenCV's default is 0.04); lower finds
        more features on flat-shaded renders.
    upscale : int
        Detect on the images enlarged this many times (bicubic); keypoints are
        mapped back to the original pixels. Small renders hold features of a
        pixel or two that SIFT's finest octave misses.
    """

    ratio: float = 0.8
    max_features: int = 4000
    cross_check: bool = True
    contrast_threshold: float = 0.01
    upscale: int = 2

    def __post_init__(self) -> None:
        if not 0.0 < float(self.ratio) <= 1.0:
            raise ValidationError(expected_got("ratio", "a number in (0, 1]", self.ratio))
        as_int(self.max_features, "max_features", lo=1)
        if not float(self.contrast_threshold) >= 0.0:
            raise ValidationError(expected_got("contrast_threshold", "a number >= 0",
                                               self.contrast_threshold))
        as_int(self.upscale, "upscale", lo=1)

    def match(self, image0: np.ndarray, image1: np.ndarray) -> Correspondences:
        """SIFT matches of the two images.

        Parameters
        ----------
        image0, image1 : numpy.ndarray
            ``(H, W[, C])`` grey/RGB/RGBA images (any sizes).

        Returns
        -------
        Correspondences
            ``source="features"``; possibly fewer than 8 pairs.
        """
        k = int(self.upscale)
        sift = cv2.SIFT_create(nfeatures=int(self.max_features),
                               contrastThreshold=float(self.contrast_threshold))
        found = []
        for img in (image0, image1):
            g, _, m = _gray_u8(img)
            if k > 1:
                g = cv2.resize(g, None, fx=k, fy=k, interpolation=cv2.INTER_CUBIC)
                m = None if m is None else cv2.resize(m, None, fx=k, fy=k, interpolation=cv2.INTER_NEAREST)
            # the robust fits depend on the order of the pairs (USAC's F from few matches does);
            # cv2.SIFT finds keypoints in parallel and does not promise an order: sort them
            kps = sorted(sift.detect(g, m), key=lambda k: (k.pt[1], k.pt[0], k.size, k.angle, k.response))
            found.append(sift.compute(g, kps) if kps else ((), None))
        (k0, d0), (k1, d1) = found
        if d0 is None or d1 is None or len(k0) < 2 or len(k1) < 2:
            return _empty()
        bf = cv2.BFMatcher(cv2.NORM_L2)
        fwd = bf.knnMatch(d0, d1, k=2)
        good = {m.queryIdx: m.trainIdx for m, n in (p for p in fwd if len(p) == 2)
                if m.distance < self.ratio * n.distance}
        if self.cross_check and good:
            best_back = {m.queryIdx: m.trainIdx for m in bf.match(d1, d0)}
            good = {q: t for q, t in good.items() if best_back.get(t) == q}
        if not good:
            return _empty()
        p0 = np.array([k0[i].pt for i in good], dtype=np.float64)
        p1 = np.array([k1[i].pt for i in good.values()], dtype=np.float64)
        # keypoints sit SIFT_KEYPOINT_OFFSET_PX off the pixel-centre convention (morphkit.conventions);
        # cv2.resize maps centre x to (x + 0.5) k - 0.5
        c = 0.5 - SIFT_KEYPOINT_OFFSET_PX
        return Correspondences((p0 + c) / k - 0.5, (p1 + c) / k - 0.5, "features")


@dataclass(frozen=True)
class FlowMatcher:
    """Dense optical flow (DIS) both ways, kept where forward and backward flow agree.

    Image 0's pixels on a ``step`` grid (object pixels only, for RGBA) are moved
    by the forward flow; a pair is kept when the backward flow at its end
    (bilinear) brings it back within ``max_fb_error`` pixels, the end lies inside
    image 1 (on its object, for RGBA). Images of different sizes are padded to a
    common size (coordinates are unchanged), and to at least
    :data:`morphkit.tol.VM_FLOW_MIN_SIDE` pixels a side (DIS refuses, or crashes on,
    smaller ones).

    Parameters
    ----------
    step : int
        Grid spacing (pixels) of the samples in image 0; grown when more than
        ``max_points`` samples would be taken.
    max_fb_error : float
        Largest forward-backward disagreement (pixels) of a kept pair.
    preset : {"ultrafast", "fast", "medium"}
        ``cv2.DISOpticalFlow`` preset.
    max_points : int
        Most samples taken from image 0.
    """

    step: int = 4
    max_fb_error: float = tol.VM_FLOW_FB_PX
    preset: str = "medium"
    max_points: int = 4000

    def __post_init__(self) -> None:
        for name in ("step", "max_points"):
            as_int(getattr(self, name), name, lo=1)
        if not float(self.max_fb_error) > 0.0:
            raise ValidationError(expected_got("max_fb_error", "a number > 0 (pixels)", self.max_fb_error))
        if self.preset not in DIS_PRESETS:
            raise ValidationError(expected_got("preset", f"one of {tuple(DIS_PRESETS)}", repr(self.preset)))

    def match(self, image0: np.ndarray, image1: np.ndarray) -> Correspondences:
        """Flow-consistent pairs of the two images.

        Parameters
        ----------
        image0, image1 : numpy.ndarray
            ``(H, W[, C])`` grey/RGB/RGBA images (any sizes).

        Returns
        -------
        Correspondences
            ``source="features"``; possibly fewer than 8 pairs.
        """
        g0, m0, _ = _gray_u8(image0)
        g1, m1, _ = _gray_u8(image1)
        h0, w0 = g0.shape
        h1, w1 = g1.shape
        H, W = max(h0, h1, tol.VM_FLOW_MIN_SIDE), max(w0, w1, tol.VM_FLOW_MIN_SIDE)
        g0p = cv2.copyMakeBorder(g0, 0, H - h0, 0, W - w0, cv2.BORDER_CONSTANT, value=0)
        g1p = cv2.copyMakeBorder(g1, 0, H - h1, 0, W - w1, cv2.BORDER_CONSTANT, value=0)
        dis = cv2.DISOpticalFlow_create(DIS_PRESETS[self.preset])
        f01 = dis.calc(g0p, g1p, None)
        f10 = dis.calc(g1p, g0p, None)
        on0 = np.ones((h0, w0), bool) if m0 is None else m0 > 0
        step = max(int(self.step), int(np.ceil(np.sqrt(np.count_nonzero(on0) / int(self.max_points)))))
        ys, xs = np.mgrid[0:h0:step, 0:w0:step]
        keep = on0[ys, xs]
        xs, ys = xs[keep], ys[keep]
        if xs.size == 0:
            return _empty()
        p0 = np.stack([xs, ys], axis=1).astype(np.float64)
        p1 = p0 + f01[ys, xs].astype(np.float64)
        back = cv2.remap(f10, p1[:, 0].astype(np.float32)[:, None], p1[:, 1].astype(np.float32)[:, None],
                         cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE).reshape(-1, 2)
        fb = np.linalg.norm(p1 + back - p0, axis=1)
        ok = (fb <= float(self.max_fb_error)) & (p1[:, 0] >= -0.5) & (p1[:, 0] <= w1 - 0.5) \
            & (p1[:, 1] >= -0.5) & (p1[:, 1] <= h1 - 0.5)
        if m1 is not None:
            c = np.clip(np.rint(p1).astype(np.int64), 0, [w1 - 1, h1 - 1])
            ok &= m1[c[:, 1], c[:, 0]] > 0
        return Correspondences(p0[ok], p1[ok], "features")


@dataclass(frozen=True)
class CombinedMatcher:
    """The pairs of several matchers, concatenated in order.

    Parameters
    ----------
    matchers : tuple of ImageMatcher
        Run in turn on the same images.
    """

    matchers: tuple[ImageMatcher, ...]

    def __post_init__(self) -> None:
        if not self.matchers or not all(isinstance(m, ImageMatcher) for m in self.matchers):
            raise ValidationError(expected_got("matchers", "a non-empty tuple of ImageMatcher",
                                               repr(self.matchers)[:80]))

    def match(self, image0: np.ndarray, image1: np.ndarray) -> Correspondences:
        """Every matcher's pairs (duplicates are dropped later by :meth:`Correspondences.cleaned`).

        Parameters
        ----------
        image0, image1 : numpy.ndarray
            ``(H, W[, C])`` grey/RGB/RGBA images.

        Returns
        -------
        Correspondences
            ``source="features"``.
        """
        return join_matches(self.match_each(image0, image1))

    def match_each(self, image0: np.ndarray, image1: np.ndarray) -> tuple[Correspondences, ...]:
        """Each matcher's pairs, in the order of :attr:`matchers` (:meth:`match` joins them).

        Parameters
        ----------
        image0, image1 : numpy.ndarray
            ``(H, W[, C])`` grey/RGB/RGBA images.

        Returns
        -------
        tuple of Correspondences
            One per matcher.
        """
        return tuple(m.match(image0, image1) for m in self.matchers)


def join_matches(parts: Sequence[Correspondences]) -> Correspondences:
    """Several matchers' pairs as one set, in order (what :meth:`CombinedMatcher.match` returns).

    Parameters
    ----------
    parts : sequence of Correspondences
        E.g. :meth:`CombinedMatcher.match_each`'s.

    Returns
    -------
    Correspondences
        ``source="features"``; duplicates kept (:meth:`Correspondences.cleaned` drops them).
    """
    if not parts:
        return _empty()
    return Correspondences(np.concatenate([c.pts0 for c in parts]), np.concatenate([c.pts1 for c in parts]),
                           "features")


#: What :func:`from_images` uses by default: SIFT (robust to large motion) and flow (dense).
DEFAULT_MATCHER = CombinedMatcher((SiftMatcher(), FlowMatcher()))


def _matched(matcher: ImageMatcher, image0: np.ndarray, image1: np.ndarray
             ) -> tuple[list[Correspondences], int | None]:
    """``matcher``'s pairs (one part per matcher it runs) and how many of them are distinctive
    (a :class:`SiftMatcher`'s, inside a :class:`CombinedMatcher` too); None when it runs none."""
    if isinstance(matcher, SiftMatcher):
        c = matcher.match(image0, image1)
        return [c], len(c)
    if isinstance(matcher, CombinedMatcher):
        parts: list[Correspondences] = []
        count: int | None = None
        for m in matcher.matchers:
            p, n = _matched(m, image0, image1)
            parts += p
            count = count if n is None else (count or 0) + n
        return parts, count
    return [matcher.match(image0, image1)], None


def from_images(image0: np.ndarray, image1: np.ndarray, *, matcher: ImageMatcher | None = None
                ) -> Correspondences:
    """Correspondences from the images alone, refused when the images do not seem to show one scene.

    Dense flow pairs any two images, so that two unrelated photos would be morphed into a double
    exposure (with ``fallback="morph"``, or wherever F happens to fit the flow): the images
    must share at least :data:`morphkit.tol.VM_MIN_SCENE_MATCHES` distinctive (SIFT) matches,
    the pairs F needs. A matcher that runs no :class:`SiftMatcher` cannot tell: its pairs are
    taken as they are.

    Parameters
    ----------
    image0, image1 : numpy.ndarray
        ``(H, W)``, ``(H, W, 3)`` or ``(H, W, 4)`` (straight alpha) images of
        uint8/uint16/float in [0, 1] (sizes may differ).
    matcher : ImageMatcher, optional
        Default :data:`DEFAULT_MATCHER` (SIFT and dense flow).

    Returns
    -------
    Correspondences
        ``source="features"``: every matcher's pairs joined (:func:`join_matches`), outliers
        included (the view morpher fits F robustly).

    Raises
    ------
    ValidationError
        ``matcher`` is not an :class:`ImageMatcher`; or the images share fewer distinctive
        matches than :data:`morphkit.tol.VM_MIN_SCENE_MATCHES`: they do not seem to show one
        scene (the message points to correspondences given explicitly).
    """
    m = DEFAULT_MATCHER if matcher is None else matcher
    if not isinstance(m, ImageMatcher):
        raise ValidationError(expected_got("matcher", "an ImageMatcher (with a match(image0, image1) method)",
                                           type(m).__name__))
    parts, distinctive = _matched(m, image0, image1)
    if distinctive is not None and distinctive < tol.VM_MIN_SCENE_MATCHES:
        raise ValidationError(expected_got(
            "images", f"two views of one scene, with at least {tol.VM_MIN_SCENE_MATCHES} distinctive (SIFT) "
            "matches (the pairs F needs, tol.VM_MIN_SCENE_MATCHES)",
            f"{distinctive}: the images do not seem to show one scene (if they do, give the "
            "correspondences explicitly: viewmorph --points FILE, or pairs to ViewMorpher.from_estimate)"))
    return join_matches(parts)
