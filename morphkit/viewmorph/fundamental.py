"""The fundamental matrix: estimation, quality, epipoles, and the degenerate cases.

Convention
----------
``F`` relates image 0 to image 1 by ``x1^T F x0 = 0`` for corresponding
homogeneous pixels ``x0 = (x, y, 1)`` in image 0 and ``x1`` in image 1 (the
order of ``cv2.findFundamentalMat(pts0, pts1)``). Pixels follow
:mod:`morphkit.conventions` (origin at the centre of the top-left pixel), so F is
expressed in those coordinates. The epipole ``e0`` (image 0) is the right null
vector of F (``F e0 = 0``), ``e1`` (image 1) the left one (``e1^T F = 0``); both
come from the SVD of F, never from an eigen-decomposition (F is not symmetric
and its eigenvectors are not its null vectors). F is returned with unit
Frobenius norm and its largest-magnitude entry positive.

Policy on degenerate input (refused, never repaired silently)
-------------------------------------------------------------
* fewer than 8 pairs: :class:`~morphkit.errors.ValidationError`;
* all points (in either image) on a line: :class:`~morphkit.errors.GeometryError`;
* the pairs are explained by one homography (planar scene, pure rotation, zero
  baseline, identical images): F is not determined,
  :class:`~morphkit.errors.DegenerateViewError` (the view morpher catches this
  case first and uses its documented homography fallback).

Affine fundamental matrix
-------------------------
Far from the object (its depth range small against its distance) two views are
nearly *affine*: every epipolar line in an image is parallel, the epipoles lie
at infinity, and F takes the form ``F_A = [[0, 0, a], [0, 0, b], [c, d, e]]``
(Hartley & Zisserman, ch. 14). Fitted to noisy matches, a general F then has
an epipole the data barely determine, often inside the image.
:func:`estimate_affine_fundamental` fits ``F_A`` (robustly, then by the Gold
Standard algorithm: total least squares on ``(x1, y1, x0, y0)``; its Sampson
distance is the exact geometric error); the view morpher uses it when the
general F is refused and ``F_A`` explains nearly as many pairs
(:data:`tol.VM_AFFINE_INLIER_RATIO`).

The normalised eight-point algorithm [1]_, RANSAC [2]_ and MAGSAC++ [3]_ are OpenCV's
(``cv2.findFundamentalMat``); the affine F, its Gold Standard fit and the Sampson distance
follow Hartley & Zisserman [4]_.

References
----------
.. [1] R. I. Hartley, "In Defense of the Eight-Point Algorithm", IEEE Trans. Pattern Analysis and
   Machine Intelligence, 19(6), pp. 580-593, 1997.
.. [2] M. A. Fischler and R. C. Bolles, "Random Sample Consensus: A Paradigm for Model Fitting with
   Applications to Image Analysis and Automated Cartography", Communications of the ACM, 24(6),
   pp. 381-395, 1981.
.. [3] D. Barath, J. Noskova, M. Ivashechkin and J. Matas, "MAGSAC++, a Fast, Reliable and Accurate
   Robust Estimator", Proc. CVPR, pp. 1304-1312, 2020.
.. [4] R. Hartley and A. Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
   University Press, 2004 (ch. 11: F, Sampson distance; ch. 14: the affine F and its Gold Standard
   algorithm 14.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import DegenerateViewError, GeometryError, ValidationError, expected_got
from ..validate import as_finite_array, as_points, as_positive

__all__ = [
    "FundamentalFit",
    "estimate_fundamental",
    "estimate_affine_fundamental",
    "AFFINE_SAMPLES",
    "fundamental_from_cameras",
    "epipoles",
    "epipole_pixel",
    "sampson_distance",
    "epipolar_distance",
    "check_spread",
    "homography_degeneracy",
    "normalize_f",
]

METHODS = ("auto", "8point", "magsac", "ransac")

#: Random minimal samples (4 pairs) drawn by :func:`estimate_affine_fundamental`:
#: with half the pairs outliers, one all-inlier sample is missed with probability
#: (1 - 0.5^4)^1000 < 1e-28.
AFFINE_SAMPLES = 1000


@dataclass(frozen=True)
class FundamentalFit:
    """A fitted fundamental matrix and its quality.

    Parameters
    ----------
    F : (3, 3) float64
        ``x1^T F x0 = 0`` (see the module convention), unit Frobenius norm.
    inliers : (N,) bool
        Pairs within ``threshold`` (Sampson distance, pixels) of F.
    method : str
        ``"8point"`` (normalised 8-point on all pairs) or ``"magsac"``/``"ransac"``
        followed by a normalised 8-point refit on the inliers; ``"affine"``
        (:func:`estimate_affine_fundamental`); ``"given"`` (a known F).
    threshold : float
        Inlier threshold in pixels.
    sampson_rms, sampson_max : float
        Sampson distance (first-order geometric error, pixels) over the inliers.
    epipolar_rms : float
        RMS symmetric point-to-epipolar-line distance (pixels) over the inliers.
    """

    F: np.ndarray
    inliers: np.ndarray = field(repr=False)
    method: str
    threshold: float
    sampson_rms: float
    sampson_max: float
    epipolar_rms: float

    @property
    def n_inliers(self) -> int:
        """Number of inlier pairs (``int``)."""
        return int(self.inliers.sum())

    def report(self) -> dict[str, Any]:
        """A JSON-friendly summary.

        Returns
        -------
        dict
            ``method``, ``n_points``, ``n_inliers``, ``threshold_px``,
            ``sampson_rms_px``, ``sampson_max_px``, ``epipolar_rms_px``.
        """
        return {"method": self.method, "n_points": int(self.inliers.size), "n_inliers": self.n_inliers,
                "threshold_px": self.threshold, "sampson_rms_px": self.sampson_rms,
                "sampson_max_px": self.sampson_max, "epipolar_rms_px": self.epipolar_rms}


def normalize_f(F: Any) -> np.ndarray:
    """``F`` scaled to unit Frobenius norm with its largest-magnitude entry positive.

    Parameters
    ----------
    F : (3, 3) float
        A fundamental matrix (any scale and sign).

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64, the same epipolar geometry.

    Raises
    ------
    GeometryError
        ``F`` is zero.
    """
    F = as_finite_array(F, "F", shape=(3, 3))
    n = np.linalg.norm(F)
    if n < tol.ZERO:
        raise GeometryError(expected_got("F", "a non-zero matrix", "all zeros"))
    F = F / n
    k = int(np.argmax(np.abs(F)))
    return F if F.flat[k] > 0 else -F


def _h(p: np.ndarray) -> np.ndarray:
    return np.c_[p, np.ones(len(p))]


def sampson_distance(F: Any, pts0: Any, pts1: Any) -> np.ndarray:
    """Sampson distance (pixels) of each pair to F: the first-order geometric error.

    ``d^2 = (x1^T F x0)^2 / ((F x0)_1^2 + (F x0)_2^2 + (F^T x1)_1^2 + (F^T x1)_2^2)``.

    Parameters
    ----------
    F : (3, 3) float
        ``x1^T F x0 = 0`` in pixels.
    pts0, pts1 : (N, 2) float
        The pairs in image-0 and image-1 pixels.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` float64 distances in pixels.
    """
    F = as_finite_array(F, "F", shape=(3, 3))
    x0, x1 = _h(as_points(pts0, "pts0")), _h(as_points(pts1, "pts1"))
    l1 = x0 @ F.T  # F x0: epipolar lines in image 1
    l0 = x1 @ F  # F^T x1: lines in image 0
    num = np.einsum("ij,ij->i", x1, l1)
    den = l1[:, 0] ** 2 + l1[:, 1] ** 2 + l0[:, 0] ** 2 + l0[:, 1] ** 2
    return np.abs(num) / np.sqrt(np.maximum(den, tol.ZERO))


def epipolar_distance(F: Any, pts0: Any, pts1: Any) -> np.ndarray:
    """Symmetric epipolar distance (pixels): RMS of the two point-to-epipolar-line distances.

    Parameters
    ----------
    F : (3, 3) float
        ``x1^T F x0 = 0`` in pixels.
    pts0, pts1 : (N, 2) float
        The pairs in image-0 and image-1 pixels.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` float64 distances in pixels.
    """
    F = as_finite_array(F, "F", shape=(3, 3))
    x0, x1 = _h(as_points(pts0, "pts0")), _h(as_points(pts1, "pts1"))
    l1 = x0 @ F.T
    l0 = x1 @ F
    num = np.abs(np.einsum("ij,ij->i", x1, l1))
    d1 = num / np.sqrt(np.maximum(l1[:, 0] ** 2 + l1[:, 1] ** 2, tol.ZERO))
    d0 = num / np.sqrt(np.maximum(l0[:, 0] ** 2 + l0[:, 1] ** 2, tol.ZERO))
    return np.sqrt(0.5 * (d0**2 + d1**2))


def epipoles(F: Any) -> tuple[np.ndarray, np.ndarray]:
    """Epipoles ``(e0, e1)`` as unit homogeneous 3-vectors from the SVD of F.

    ``e0`` is the right singular vector of the smallest singular value
    (``F e0 = 0``: the image of camera 1's centre in image 0), ``e1`` the left one
    (``e1^T F = 0``). Each is signed so that its last coordinate is >= 0 (an
    epipole at infinity has last coordinate 0).

    Parameters
    ----------
    F : (3, 3) float
        ``x1^T F x0 = 0``.

    Returns
    -------
    e0, e1 : numpy.ndarray
        ``(3,)`` float64 homogeneous epipoles in image 0 and image 1 (pixels of
        ``F``'s frames).
    """
    F = as_finite_array(F, "F", shape=(3, 3))
    U, _, Vt = np.linalg.svd(F)
    e0, e1 = Vt[2].copy(), U[:, 2].copy()
    for e in (e0, e1):
        if e[2] < 0 or (e[2] == 0 and e[np.argmax(np.abs(e[:2]))] < 0):
            e *= -1.0
    return e0, e1


def epipole_pixel(e: np.ndarray) -> np.ndarray | None:
    """Pixel position of a homogeneous epipole, or None when it is (numerically) at infinity.

    Parameters
    ----------
    e : (3,) float
        A homogeneous epipole (:func:`epipoles`).

    Returns
    -------
    numpy.ndarray or None
        ``(2,)`` float64 pixel ``(x, y)``, or None when ``|e_z|`` is at most
        :data:`tol.VM_EPIPOLE_INFINITY` times ``|(e_x, e_y)|``.
    """
    e = np.asarray(e, dtype=np.float64)
    if abs(e[2]) <= tol.VM_EPIPOLE_INFINITY * np.linalg.norm(e[:2]):
        return None
    return e[:2] / e[2]


def fundamental_from_cameras(camera0: CameraModel, camera1: CameraModel) -> np.ndarray:
    """Geometric F of two perspective cameras: ``F = K1^-T [t]x R K0^-1``.

    ``R, t`` take camera-0 coordinates to camera-1 coordinates
    (``X1 = R X0 + t``, OpenCV camera frames). Normalised like
    :func:`normalize_f`.

    Parameters
    ----------
    camera0, camera1 : CameraModel
        Two perspective cameras.

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 F with ``x1^T F x0 = 0`` (pixels of the two cameras).

    Examples
    --------
    Two cameras side by side (the second 1 unit along the first's ``+x``) see
    parallel views: F is the canonical form ``-F0`` (unit Frobenius norm), both
    epipoles lie at infinity along ``x`` (no pixel), and a pair on the same row
    satisfies the epipolar constraint.

    >>> import numpy as np
    >>> from morphkit.camera import perspective
    >>> from morphkit.scene import translation
    >>> from morphkit.viewmorph.fundamental import epipole_pixel, epipoles, fundamental_from_cameras
    >>> left = perspective(np.pi / 2, (64, 64), np.eye(4))
    >>> right = perspective(np.pi / 2, (64, 64), translation(1.0, 0.0, 0.0))
    >>> F = fundamental_from_cameras(left, right)
    >>> np.round(F * np.sqrt(2.0), 12) + 0.0
    array([[ 0.,  0.,  0.],
           [ 0.,  0.,  1.],
           [ 0., -1.,  0.]])
    >>> e0, e1 = epipoles(F)
    >>> e0, e1, epipole_pixel(e0)
    (array([1., 0., 0.]), array([1., 0., 0.]), None)
    >>> float(np.array([3.0, 20.0, 1.0]) @ F @ np.array([10.0, 20.0, 1.0]))
    0.0

    Raises
    ------
    ValidationError
        An orthographic camera (its F is affine; not handled here).
    DegenerateViewError
        The camera centres coincide (F = 0: no epipolar geometry).
    """
    for name, c in (("camera0", camera0), ("camera1", camera1)):
        if not isinstance(c, CameraModel) or c.projection != "perspective":
            raise ValidationError(expected_got(name, "a perspective CameraModel", repr(c)[:80]))
    w2c0, w2c1 = camera0.world2cam, camera1.world2cam
    R = w2c1[:3, :3] @ w2c0[:3, :3].T
    t = w2c1[:3, 3] - R @ w2c0[:3, 3]
    if np.linalg.norm(t) < tol.MIN_EXTENT:
        raise DegenerateViewError(expected_got("camera centres", "distinct (a baseline)", "the same point"))
    tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
    F = np.linalg.inv(camera1.K).T @ tx @ R @ np.linalg.inv(camera0.K)
    return normalize_f(F)


def check_spread(pts: Any, name: str) -> None:
    """Raise :class:`GeometryError` if the points lie (numerically) on a line or a point.

    Uses the singular values of the centred points: ``s2 / s1 <`` :data:`tol.VM_COLLINEAR_RATIO`.

    Parameters
    ----------
    pts : (N, 2) float
        The points (any one frame).
    name : str
        What they are, for the message.

    Raises
    ------
    GeometryError
        The points do not span a 2-D area.
    """
    p = as_points(pts, name)
    c = p - p.mean(axis=0)
    s = np.linalg.svd(c, compute_uv=False) if len(p) >= 2 else np.zeros(2)
    if s[0] <= tol.PX_EQUAL or s[1] < tol.VM_COLLINEAR_RATIO * s[0]:
        ratio = 0.0 if s[0] <= tol.PX_EQUAL else s[1] / s[0]
        raise GeometryError(expected_got(
            name, "points spanning a 2-D area (F and homographies are undetermined otherwise)",
            f"collinear points (spread ratio {ratio:.2e} < {tol.VM_COLLINEAR_RATIO})"))


def homography_degeneracy(pts0: Any, pts1: Any, *, threshold: float = tol.VM_THRESHOLD_PX,
                          f_inliers: int | None = None) -> tuple[np.ndarray | None, float]:
    """Do the pairs fit one homography (planar scene, pure rotation, zero baseline)?

    Fits ``H_1_0`` (image 0 pixels to image 1 pixels) by least squares when every
    pair fits within ``threshold``, else by RANSAC with that threshold.
    The pairs are called degenerate when the homography's inliers number at
    least :data:`tol.VM_HOMOGRAPHY_INLIER_RATIO` times ``f_inliers`` (the
    inliers of the fundamental matrix; default: all pairs). A homography-consistent
    pair is always F-consistent, so F then adds no information: it is not determined.

    RANSAC only has to find such a homography if one exists: with ``r`` the
    smallest inlier ratio that makes the pairs degenerate, a random 4-pair sample
    is all inliers with probability ``r^4``, so ``log(p) / log(1 - r^4)``
    samples (13 for ``r = 0.95``; at least 20, at most 2000) miss it with
    probability below ``p =`` :data:`tol.VM_HOMOGRAPHY_MISS_PROB`. (The best
    homography of non-degenerate pairs is not searched for further.)

    Parameters
    ----------
    pts0, pts1 : (N, 2) float
        The pairs in image-0 and image-1 pixels, ``N >= 4``.
    threshold : float
        Transfer error (pixels, in image 1) within which a pair fits.
    f_inliers : int, optional
        Inliers of the fundamental matrix (default: ``N``).

    Returns
    -------
    H_1_0 : (3, 3) float64 or None
        The homography (image-0 to image-1 pixels) when degenerate, else None.
    fraction : float
        Homography inliers / ``f_inliers`` (not degenerate: of the best sample
        tried, a lower bound).
    """
    p0 = as_points(pts0, "pts0", min_count=4)
    p1 = as_points(pts1, "pts1", min_count=4)
    threshold = as_positive(threshold, "threshold")
    n_ref = len(p0) if f_inliers is None else max(int(f_inliers), 1)
    H_1_0, _ = cv2.findHomography(p0, p1, 0)
    if H_1_0 is not None and np.all(np.isfinite(H_1_0)):
        err = _transfer(H_1_0, p0, p1)
        if np.max(err) <= threshold:
            return H_1_0 / H_1_0[2, 2], len(p0) / n_ref if len(p0) >= n_ref else 1.0
    r = min(1.0, tol.VM_HOMOGRAPHY_INLIER_RATIO * n_ref / len(p0))
    r4 = r**4
    iters = 20 if r4 >= 1.0 else 2000 if r4 <= tol.ZERO else \
        int(min(2000, max(20, math.ceil(math.log(tol.VM_HOMOGRAPHY_MISS_PROB) / math.log1p(-r4)))))
    H_1_0, mask = cv2.findHomography(p0, p1, cv2.RANSAC, threshold, maxIters=iters, confidence=0.999)
    if H_1_0 is None or not np.all(np.isfinite(H_1_0)):
        return None, 0.0
    inl = int(mask.ravel().astype(bool).sum())
    frac = inl / n_ref
    if frac >= tol.VM_HOMOGRAPHY_INLIER_RATIO:
        return H_1_0 / H_1_0[2, 2], min(frac, 1.0)
    return None, frac


def _transfer(H_1_0: np.ndarray, p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
    q = _h(p0) @ H_1_0.T
    with np.errstate(divide="ignore", invalid="ignore"):
        q = q[:, :2] / q[:, 2:3]
    d = np.linalg.norm(q - p1, axis=1)
    return np.where(np.isfinite(d), d, np.inf)


def _fit(pts0: np.ndarray, pts1: np.ndarray, flag: int, threshold: float, seed: int
         ) -> tuple[np.ndarray | None, np.ndarray | None]:
    try:
        if flag == cv2.FM_8POINT:
            F, mask = cv2.findFundamentalMat(pts0, pts1, cv2.FM_8POINT)
        else:
            cv2.setRNGSeed(int(seed))  # FM_RANSAC draws from cv::theRNG; USAC is seeded internally
            F, mask = cv2.findFundamentalMat(pts0, pts1, flag, threshold, 0.9999, 10000)
    except cv2.error:
        # OpenCV 5.0's USAC asserts (!model.empty() in setModelParameters) on some sets of
        # few pairs where it finds no model: no fit, as a None return would say
        return None, None
    if F is None or F.shape != (3, 3) or not np.all(np.isfinite(F)):
        return None, None
    return F, None if mask is None else mask.ravel().astype(bool)


def estimate_fundamental(pts0: Any, pts1: Any, *, method: str = "auto",
                         threshold: float = tol.VM_THRESHOLD_PX, seed: int = 0,
                         check_degenerate: bool = True) -> FundamentalFit:
    """Estimate F (``x1^T F x0 = 0``) from pixel correspondences with ``cv2.findFundamentalMat``.

    Parameters
    ----------
    pts0, pts1 : (N, 2) array_like
        Pixel positions (pixel-centre origin), ``N >= 8``.
    method : {"auto", "8point", "magsac", "ransac"}
        ``"8point"``: normalised 8-point algorithm on every pair (for exact
        points). ``"magsac"``/``"ransac"``: robust USAC fit (``USAC_MAGSAC``
        scoring, or plain RANSAC scoring) with ``threshold``, then an 8-point
        refit on its inliers. ``"auto"``: 8-point, kept if every pair lies within
        ``threshold`` of it (exact or clean points), otherwise MAGSAC.
    threshold : float
        Inlier threshold (pixels, Sampson distance).
    seed : int
        Seed of the USAC sampler (results are reproducible).
    check_degenerate : bool
        Refuse pairs explained by one homography (see :func:`homography_degeneracy`).

    Returns
    -------
    FundamentalFit

    Raises
    ------
    ValidationError
        Fewer than 8 pairs, NaN/inf, mismatched counts, unknown method.
    GeometryError
        Collinear points, or no fit found.
    DegenerateViewError
        The pairs fit one homography: F is not determined.

    References
    ----------
    .. [1] R. I. Hartley, "In Defense of the Eight-Point Algorithm", IEEE Trans. Pattern Analysis and
       Machine Intelligence, 19(6), pp. 580-593, 1997.
    .. [2] M. A. Fischler and R. C. Bolles, "Random Sample Consensus: A Paradigm for Model Fitting with
       Applications to Image Analysis and Automated Cartography", Communications of the ACM, 24(6),
       pp. 381-395, 1981.
    .. [3] D. Barath, J. Noskova, M. Ivashechkin and J. Matas, "MAGSAC++, a Fast, Reliable and Accurate
       Robust Estimator", Proc. CVPR, pp. 1304-1312, 2020.
    """
    if method not in METHODS:
        raise ValidationError(expected_got("method", f"one of {METHODS}", repr(method)))
    p0 = as_points(pts0, "pts0")
    p1 = as_points(pts1, "pts1")
    if p0.shape != p1.shape:
        raise ValidationError(expected_got("pts1", f"{len(p0)} points (as many as pts0)", f"{len(p1)}"))
    if len(p0) < 8:
        raise ValidationError(expected_got(
            "correspondences", "at least 8 pairs (F has 7 degrees of freedom; the 8-point algorithm "
            "needs 8)", f"{len(p0)}"))
    threshold = as_positive(threshold, "threshold")
    check_spread(p0, "pts0")
    check_spread(p1, "pts1")

    used = method
    F = inl = None
    if method in ("auto", "8point"):
        F, _ = _fit(p0, p1, cv2.FM_8POINT, threshold, seed)
        if F is not None:
            d = sampson_distance(F, p0, p1)
            inl = d <= threshold
            if method == "auto" and not inl.all():
                F = None
            used = "8point"
    if F is None and method != "8point":
        flag = cv2.USAC_MAGSAC if method in ("auto", "magsac") else cv2.FM_RANSAC
        F, mask = _fit(p0, p1, flag, threshold, seed)
        used = "magsac" if flag == cv2.USAC_MAGSAC else "ransac"
        if F is not None:
            inl = sampson_distance(F, p0, p1) <= threshold
            if inl.sum() >= 8:
                F8, _ = _fit(p0[inl], p1[inl], cv2.FM_8POINT, threshold, seed)
                if F8 is not None:
                    inl8 = sampson_distance(F8, p0, p1) <= threshold
                    if inl8.sum() >= inl.sum():
                        F, inl = F8, inl8
    if F is None or inl is None or inl.sum() < 8:
        raise GeometryError(expected_got("fundamental matrix fit", "a fit with >= 8 inliers",
                                         f"none (method {used}, threshold {threshold} px)"))
    F = normalize_f(F)
    if check_degenerate:
        H_1_0, frac = homography_degeneracy(p0[inl], p1[inl], threshold=threshold)
        if H_1_0 is not None:
            raise DegenerateViewError(expected_got(
                "correspondences", "a general 3-D configuration (F determined)",
                f"pairs explained by one homography ({100 * frac:.0f}% within {threshold} px): a planar "
                "scene, pure rotation or zero baseline; F is not determined"))
    d = sampson_distance(F, p0[inl], p1[inl])
    e = epipolar_distance(F, p0[inl], p1[inl])
    inl.setflags(write=False)
    F.setflags(write=False)
    return FundamentalFit(F, inl, used, threshold, float(np.sqrt(np.mean(d**2))), float(d.max()),
                          float(np.sqrt(np.mean(e**2))))


def _affine_tls(p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
    """Gold Standard affine F of the pairs: the hyperplane through the 4-vectors (x1, y1, x0, y0)
    that minimises the sum of squared orthogonal distances (smallest right singular vector)."""
    X = np.c_[p1, p0]
    m = X.mean(axis=0)
    n = np.linalg.svd(X - m, full_matrices=False)[2][-1]
    F = np.zeros((3, 3))
    F[0, 2], F[1, 2], F[2, 0], F[2, 1] = n
    F[2, 2] = -float(n @ m)
    return F


def estimate_affine_fundamental(pts0: Any, pts1: Any, *, threshold: float = tol.VM_THRESHOLD_PX,
                                seed: int = 0) -> FundamentalFit:
    """Estimate an affine F (both epipoles at infinity) robustly from pixel correspondences.

    ``F_A = [[0, 0, a], [0, 0, b], [c, d, e]]``, i.e. ``a x1 + b y1 + c x0 + d y0 + e = 0``:
    a hyperplane in the space of ``(x1, y1, x0, y0)``. RANSAC over minimal
    samples of 4 pairs (:data:`AFFINE_SAMPLES` of them, drawn by
    ``np.random.default_rng(seed)``) keeps the hyperplane with the most pairs
    within ``threshold``; it is refitted by total least squares on its inliers
    (Hartley & Zisserman's Gold Standard algorithm 14.1) until the inliers stop
    changing. The Sampson distance of ``F_A`` is the exact orthogonal distance
    of a pair's 4-vector to the hyperplane.

    Parameters
    ----------
    pts0, pts1 : (N, 2) array_like
        Pixel positions (pixel-centre origin), ``N >= 8``.
    threshold : float
        Inlier threshold (pixels, Sampson distance).
    seed : int
        Seed of the sampler (results are reproducible).

    Returns
    -------
    FundamentalFit
        ``method="affine"``; ``F`` normalised like :func:`normalize_f`.

    Raises
    ------
    ValidationError
        Fewer than 8 pairs, NaN/inf, mismatched counts.
    GeometryError
        Collinear points, or fewer than 8 pairs fit any affine F.

    References
    ----------
    .. [1] R. Hartley and A. Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
       University Press, 2004 (ch. 11: F, Sampson distance; ch. 14: the affine F and its Gold Standard
       algorithm 14.1).
    """
    p0 = as_points(pts0, "pts0")
    p1 = as_points(pts1, "pts1")
    if p0.shape != p1.shape:
        raise ValidationError(expected_got("pts1", f"{len(p0)} points (as many as pts0)", f"{len(p1)}"))
    if len(p0) < 8:
        raise ValidationError(expected_got("correspondences", "at least 8 pairs", f"{len(p0)}"))
    threshold = as_positive(threshold, "threshold")
    check_spread(p0, "pts0")
    check_spread(p1, "pts1")
    X = np.c_[p1, p0]
    rng = np.random.default_rng(seed)
    S = X[rng.integers(0, len(X), (AFFINE_SAMPLES, 4))]  # samples x pairs x (x1, y1, x0, y0)
    m = S.mean(axis=1)
    nrm = np.linalg.svd(S - m[:, None, :])[2][:, -1, :]  # each sample's hyperplane normal (unit)
    off = np.einsum("kj,kj->k", nrm, m)
    inl, best = np.zeros(len(X), bool), -1
    for lo in range(0, AFFINE_SAMPLES, 100):  # chunks keep the (N, 100) residuals small
        r = np.abs(X @ nrm[lo:lo + 100].T - off[lo:lo + 100])
        count = (r <= threshold).sum(axis=0)
        k = int(np.argmax(count))
        if count[k] > best:
            inl, best = r[:, k] <= threshold, int(count[k])
    F = np.zeros((3, 3))
    for _ in range(10):  # Gold Standard refit on the inliers until they stop changing
        if inl.sum() < 8:
            break
        F = _affine_tls(p0[inl], p1[inl])
        new = sampson_distance(F, p0, p1) <= threshold
        if np.array_equal(new, inl):
            break
        inl = new
    a, b, c, d = F[0, 2], F[1, 2], F[2, 0], F[2, 1]
    if inl.sum() < 8 or min(np.hypot(a, b), np.hypot(c, d)) < tol.REL_EQUAL:
        raise GeometryError(expected_got("affine fundamental matrix fit", "a rank-2 fit with >= 8 inliers",
                                         f"{int(inl.sum())} inliers (threshold {threshold} px)"))
    F = normalize_f(F)
    d = sampson_distance(F, p0[inl], p1[inl])
    e = epipolar_distance(F, p0[inl], p1[inl])
    inl.setflags(write=False)
    F.setflags(write=False)
    return FundamentalFit(F, inl, "affine", threshold, float(np.sqrt(np.mean(d**2))), float(d.max()),
                          float(np.sqrt(np.mean(e**2))))
