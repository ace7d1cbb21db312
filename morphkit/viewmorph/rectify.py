"""Pre-warp: homographies that make two views parallel (rectified).

Two constructions, compared by :func:`rectify` (``method="auto"`` keeps the less
distorting one):

``"opencv"``
    ``cv2.stereoRectifyUncalibrated`` (Hartley 1999): send image 1's epipole to
    infinity, then choose image 0's homography that minimises the disparity.
``"seitz-dyer"``
    Seitz & Dyer's (1996) own construction (:func:`seitz_dyer_prewarps`): rotate
    each image plane about an axis ``d_i`` lying in it by
    ``theta_i = -pi/2 - atan((d_i^y e_i^x - d_i^x e_i^y) / e_i^z)`` (the epipole goes
    to infinity), then about the optical axis by ``phi_i = -atan(e_i^y / e_i^x)``
    (the epipole goes onto the x axis); ``d0`` is perpendicular to ``e0`` and
    ``d1`` is the direction of the epipolar line ``F d0`` that corresponds to
    it. F then has the form ``[[0, 0, 0], [0, 0, a], [0, b, c]]``, and image 1
    gets ``T = [[1, 0, 0], [0, -a, -c], [0, 0, b]]`` (the Appendix's fix of its
    scan lines), after which ``F`` is the canonical ``F0 = [[0,0,0],[0,0,-1],[0,1,0]]``.
    The rotations act on ``K^-1 x`` (true camera rotations when the intrinsics
    ``K_i`` are given; otherwise a default ``K`` with focal length
    ``max(H, W)`` and a centred principal point, which is still an exact
    rectification, only not a rigid rotation). ``theta_i`` is used modulo pi,
    in ``[-pi/2, pi/2]``, so the image stays in front of the rotated camera.

Both are then *normalised* identically (:func:`normalize_prewarps`): each
rectified image is made a similarity of the original at its correspondences'
centroid (a per-image shear/scale of x, a common scale of y: F0 is kept, and
linear interpolation stays physically valid because the rectified cameras only
differ in their intrinsics' first row), the common y scale keeps the
geometric-mean local scale at 1, and the centroids of both images'
correspondences go to the origin.

Convention
----------
``H_rect_0`` maps image-0 pixels to the shared rectified frame and
``H_rect_1`` image-1 pixels to it: warping image ``i`` *with* ``H_rect_i``
(``cv2.warpPerspective(img, H_rect_i, ...)``) rectifies it. After rectification
corresponding points share their ``y``: ``x1r^T F0 x0r = 0``. Pixels use the
pixel-centre origin of :mod:`morphkit.conventions`; the rectified frame has its
origin at the correspondences' centroid (it is not an image; see
:class:`morphkit.viewmorph.morph.ViewMorpher` for its canvas).

Refusals (:class:`~morphkit.errors.DegenerateViewError`): an epipole inside
(or within :data:`tol.VM_EPIPOLE_MARGIN` of) its image; a pre-warp that sends
part of its image through infinity, or whose local anisotropy exceeds
:data:`tol.VM_MAX_ANISOTROPY`, or whose local scales differ by more than
:data:`tol.VM_MAX_SCALE_RATIO`.

Hartley's rectification [1]_ (OpenCV's); Seitz & Dyer's construction [2]_.

References
----------
.. [1] R. I. Hartley, "Theory and Practice of Projective Rectification", International Journal of
   Computer Vision, 35(2), pp. 115-127, 1999.
.. [2] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from .. import tol
from ..errors import DegenerateViewError, GeometryError, ValidationError, expected_got
from ..validate import as_finite_array, as_points, as_shape
from .fundamental import epipole_pixel, epipoles, normalize_f

__all__ = [
    "F0",
    "Rectification",
    "rectify",
    "rectify_opencv",
    "seitz_dyer_prewarps",
    "seitz_dyer_angles",
    "normalize_prewarps",
    "prewarp_distortion",
    "apply_h",
    "default_intrinsics",
]

#: The fundamental matrix of two parallel (rectified) views: ``x1^T F0 x0 = y0 - y1``.
F0 = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
F0.setflags(write=False)

RECTIFIERS = ("auto", "opencv", "seitz-dyer")


@dataclass(frozen=True)
class Rectification:
    """A pair of pre-warps and their quality.

    Parameters
    ----------
    H_rect_0, H_rect_1 : (3, 3) float64
        The pre-warps (see the module convention).
    method : str
        ``"opencv"``, ``"seitz-dyer"``, ``"parallel"`` (views already parallel:
        identities), ``"homography"`` (the homography fallback: ``H_rect_0 = I``,
        ``H_rect_1 = H_0_1``) or ``"none"`` (plain morph: identities).
    y_rms : float
        RMS of ``y1r - y0r`` over the pairs after rectification (pixels).
    anisotropy : float
        Largest ratio of the local Jacobian's singular values over both images.
    scale_ratio : float
        Largest ratio between local area scales over both images.
    candidates : dict
        For ``"auto"``: the quality of each construction tried (or why it failed).
    """

    H_rect_0: np.ndarray
    H_rect_1: np.ndarray
    method: str
    y_rms: float
    anisotropy: float
    scale_ratio: float
    candidates: dict[str, Any]

    def report(self) -> dict[str, Any]:
        """A JSON-friendly summary.

        Returns
        -------
        dict
            ``method``, ``y_rms_px``, ``anisotropy``, ``scale_ratio``, ``candidates``.
        """
        return {"method": self.method, "y_rms_px": self.y_rms, "anisotropy": self.anisotropy,
                "scale_ratio": self.scale_ratio, "candidates": self.candidates}


# --------------------------------------------------------------------------- helpers


def apply_h(H: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Apply homography ``H`` to ``(N, 2)`` points (``H_dst_src``: src pixels to dst pixels).

    Parameters
    ----------
    H : (3, 3) float
        ``H_dst_src``.
    pts : (N, 2) float
        Points in the source frame.

    Returns
    -------
    numpy.ndarray
        ``(N, 2)`` float64 points in the destination frame (``inf``/NaN for
        points ``H`` sends to infinity).
    """
    p = np.c_[pts, np.ones(len(pts))] @ np.asarray(H, dtype=np.float64).T
    return p[:, :2] / p[:, 2:3]


def _jacobian(H: np.ndarray, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Jacobians ``(N, 2, 2)`` of the homography at ``pts`` and the homogeneous ``w``."""
    q = np.c_[pts, np.ones(len(pts))] @ H.T
    w = q[:, 2]
    u, v = q[:, 0] / w, q[:, 1] / w
    J = np.empty((len(pts), 2, 2))
    J[:, 0, 0] = (H[0, 0] - u * H[2, 0]) / w
    J[:, 0, 1] = (H[0, 1] - u * H[2, 1]) / w
    J[:, 1, 0] = (H[1, 0] - v * H[2, 0]) / w
    J[:, 1, 1] = (H[1, 1] - v * H[2, 1]) / w
    return J, w


def _grid(shape: tuple[int, int], n: int = 7) -> np.ndarray:
    h, w = shape
    xs = np.linspace(-0.5, w - 0.5, n)
    ys = np.linspace(-0.5, h - 0.5, n)
    return np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)


def prewarp_distortion(H: Any, shape: tuple[int, int]) -> dict[str, float]:
    """Distortion of pre-warp ``H`` over an image of ``shape``, sampled on a 7x7 grid.

    Returns ``{"w_min", "w_max"}`` (homogeneous w, sign-normalised so the
    centre is positive: ``w_min <= 0`` means the image crosses the line that goes
    to infinity), ``"anisotropy"`` (max singular-value ratio), ``"scale_min"``,
    ``"scale_max"`` (local area scale ``|det J|``).

    Parameters
    ----------
    H : (3, 3) float
        A pre-warp ``H_rect_i`` (image pixels to the rectified frame).
    shape : (H, W)
        The image's shape.

    Returns
    -------
    dict of str to float
        The five measures above, over the grid.
    """
    H = as_finite_array(H, "H", shape=(3, 3))
    shape = as_shape(shape, "shape")
    g = _grid(shape)
    c = np.array([[(shape[1] - 1) / 2, (shape[0] - 1) / 2]])
    _, wc = _jacobian(H, c)
    Hs = H * np.sign(wc[0]) if wc[0] != 0 else H
    J, w = _jacobian(Hs, g)
    sv = np.linalg.svd(J, compute_uv=False)
    with np.errstate(divide="ignore"):
        aniso = np.where(sv[:, 1] > 0, sv[:, 0] / sv[:, 1], np.inf)
    area = sv[:, 0] * sv[:, 1]
    return {"w_min": float(w.min()), "w_max": float(w.max()), "anisotropy": float(aniso.max()),
            "scale_min": float(area.min()), "scale_max": float(area.max())}


def default_intrinsics(shape: tuple[int, int]) -> np.ndarray:
    """A guess of ``K`` for an uncalibrated image: focal ``max(H, W)`` px, centred principal point.

    Parameters
    ----------
    shape : (H, W)

    Returns
    -------
    numpy.ndarray
        ``(3, 3)`` float64 intrinsics (pixel-centre origin).
    """
    h, w = as_shape(shape, "shape")
    f = float(max(h, w))
    return np.array([[f, 0.0, (w - 1) / 2], [0.0, f, (h - 1) / 2], [0.0, 0.0, 1.0]])


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Right-handed rotation by ``angle`` about unit ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * (K @ K)


# --------------------------------------------------------------------------- constructions


def rectify_opencv(F: Any, pts0: Any, pts1: Any, shape0: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Raw pre-warps ``(H_rect_0, H_rect_1)`` from ``cv2.stereoRectifyUncalibrated``.

    Convention: ``H_rect_i`` maps image-``i`` pixels (pixel-centre origin) to the
    rectified frame; ``x1r^T F0 x0r = 0`` up to the estimation error. Not yet
    normalised (see :func:`normalize_prewarps`).

    Parameters
    ----------
    F : (3, 3) float
        ``x1^T F x0 = 0`` in pixels.
    pts0, pts1 : (N, 2) float
        Inlier pairs, ``N >= 8``.
    shape0 : (H, W)
        Image 0's shape.

    Returns
    -------
    H_rect_0, H_rect_1 : numpy.ndarray
        ``(3, 3)`` float64 pre-warps.

    Raises
    ------
    GeometryError
        OpenCV reports failure or returns a singular homography.

    References
    ----------
    .. [1] R. I. Hartley, "Theory and Practice of Projective Rectification", International Journal of
       Computer Vision, 35(2), pp. 115-127, 1999.
    """
    F = as_finite_array(F, "F", shape=(3, 3))
    p0 = as_points(pts0, "pts0", min_count=8)
    p1 = as_points(pts1, "pts1", min_count=8)
    h, w = as_shape(shape0, "shape0")
    ok, H_rect_0, H_rect_1 = cv2.stereoRectifyUncalibrated(p0, p1, F, (w, h), threshold=0)
    if not ok or H_rect_0 is None or H_rect_1 is None or abs(np.linalg.det(H_rect_0)) < tol.ZERO \
            or abs(np.linalg.det(H_rect_1)) < tol.ZERO:
        raise GeometryError(expected_got("cv2.stereoRectifyUncalibrated", "two regular homographies",
                                         "failure"))
    return np.asarray(H_rect_0, dtype=np.float64), np.asarray(H_rect_1, dtype=np.float64)


def seitz_dyer_angles(F_hat: Any) -> dict[str, Any]:
    """Seitz & Dyer's rotation axes and angles for a normalised-coordinate F.

    ``F_hat`` relates normalised coordinates ``K1^-1 x1`` and ``K0^-1 x0``
    (``F_hat = K1^T F K0``). Returns ``d0, d1`` (unit in-plane axes), ``theta0,
    theta1`` (about ``d_i``, radians, reduced modulo pi into [-pi/2, pi/2]),
    ``phi0, phi1`` (about the optical axis) and the rotations ``R0, R1``
    (``R_i = R_z(phi_i) R_{d_i}(theta_i)``).

    Parameters
    ----------
    F_hat : (3, 3) float
        F in normalised coordinates.

    Returns
    -------
    dict
        ``d0, d1`` ``(3,)``, ``theta0, theta1, phi0, phi1`` float, ``R0, R1`` ``(3, 3)``.

    Raises
    ------
    DegenerateViewError
        An epipole on the optical axis (forward motion): no in-plane axis.
    """
    Fh = as_finite_array(F_hat, "F_hat", shape=(3, 3))
    e0, e1 = epipoles(Fh)
    d0 = np.array([-e0[1], e0[0], 0.0])
    if np.linalg.norm(d0) < tol.VM_UNIT_ZERO:
        raise DegenerateViewError(expected_got("epipole of image 0", "off the optical axis",
                                               "on it (pure forward motion)"))
    d0 /= np.linalg.norm(d0)
    line = Fh @ d0  # epipolar line in image 1 of the direction d0
    d1 = np.array([-line[1], line[0], 0.0])
    if np.linalg.norm(d1) < tol.VM_UNIT_ZERO:
        raise DegenerateViewError(expected_got("epipolar line F d0", "a line with a direction",
                                               "the line at infinity"))
    d1 /= np.linalg.norm(d1)
    out: dict[str, Any] = {"d0": d0, "d1": d1}
    for i, (e, d) in enumerate(((e0, d0), (e1, d1))):
        num = d[1] * e[0] - d[0] * e[1]
        theta = 0.0 if e[2] == 0 else -np.pi / 2 - np.arctan(num / e[2])
        theta = (theta + np.pi / 2) % np.pi - np.pi / 2  # modulo pi, in [-pi/2, pi/2)
        Rt = _rotation(d, theta)
        er = Rt @ e
        phi = -np.arctan(er[1] / er[0]) if er[0] != 0 else np.pi / 2
        Rz = _rotation(np.array([0.0, 0.0, 1.0]), phi)
        out[f"theta{i}"] = float(theta)
        out[f"phi{i}"] = float(phi)
        out[f"R{i}"] = Rz @ Rt
    return out


def seitz_dyer_prewarps(F: Any, shape0: tuple[int, int], shape1: tuple[int, int], *,
                        K0: Any = None, K1: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """Raw pre-warps ``(H_rect_0, H_rect_1)`` by Seitz & Dyer's construction.

    ``H_rect_0 = R0 K0^-1`` and ``H_rect_1 = T R1 K1^-1`` (see the module
    docstring), so that ``H_rect_1^-T F H_rect_0^-1`` is proportional to
    :data:`F0`. Convention: ``H_rect_i`` maps image-``i`` pixels (pixel-centre origin)
    to the rectified frame. Not yet normalised (see :func:`normalize_prewarps`).

    Parameters
    ----------
    F : (3, 3)
        ``x1^T F x0 = 0`` in pixels.
    shape0, shape1 : (H, W)
        Image shapes (for the default intrinsics).
    K0, K1 : (3, 3), optional
        Intrinsics; default :func:`default_intrinsics`.

    Returns
    -------
    H_rect_0, H_rect_1 : numpy.ndarray
        ``(3, 3)`` float64 pre-warps.

    Raises
    ------
    DegenerateViewError
        Forward motion (see :func:`seitz_dyer_angles`) or a rotated F that does
        not reach the form ``[[0,0,0],[0,0,a],[0,b,c]]`` (numerically singular).

    References
    ----------
    .. [1] S. M. Seitz and C. R. Dyer, "View Morphing", Proc. SIGGRAPH 96, pp. 21-30, 1996.
    """
    F = normalize_f(F)
    K0 = default_intrinsics(shape0) if K0 is None else as_finite_array(K0, "K0", shape=(3, 3))
    K1 = default_intrinsics(shape1) if K1 is None else as_finite_array(K1, "K1", shape=(3, 3))
    Fh = normalize_f(K1.T @ F @ K0)
    ang = seitz_dyer_angles(Fh)
    R0, R1 = ang["R0"], ang["R1"]
    Ft = R1 @ Fh @ R0.T  # = R1^-T Fh R0^-1
    Ft /= np.linalg.norm(Ft)
    a, b, c = Ft[1, 2], Ft[2, 1], Ft[2, 2]
    resid = np.abs([Ft[0, 0], Ft[0, 1], Ft[0, 2], Ft[1, 0], Ft[2, 0], Ft[1, 1]]).max()
    if resid > tol.VM_ROTATED_F_RESIDUAL or min(abs(a), abs(b)) < tol.REL_EQUAL:
        raise DegenerateViewError(expected_got(
            "rotated F", "the form [[0,0,0],[0,0,a],[0,b,c]] with a, b != 0",
            f"residual {resid:.1e}, a={a:.1e}, b={b:.1e}"))
    T = np.array([[1.0, 0.0, 0.0], [0.0, -a, -c], [0.0, 0.0, b]])
    return R0 @ np.linalg.inv(K0), T @ R1 @ np.linalg.inv(K1)


def normalize_prewarps(H_rect_0: Any, H_rect_1: Any, pts0: Any, pts1: Any) -> tuple[np.ndarray, np.ndarray]:
    """Normalise a rectifying pair so each image is locally a similarity of the original.

    With ``J_i`` the Jacobian of ``H_rect_i`` at the centroid of image ``i``'s points,
    the pair is left-multiplied by ``A_i = [[a_i, k_i, t_i], [0, s, t], [0, 0, 1]]``:
    a common ``y`` scale ``s`` and shift ``t`` (rectified ``y`` stays shared, F0
    is kept) and a per-image ``x`` row chosen so that ``A_i J_i`` is a rotation
    times a scale (no shear, no mirror). ``s`` makes the geometric mean of the
    two local scales 1; ``t_i, t`` put each image's centroid of rectified points at
    the origin. The homogeneous ``w`` is made positive at the centroids.

    Convention: input and output ``H_rect_i`` map image-``i`` pixels to the rectified frame.

    Parameters
    ----------
    H_rect_0, H_rect_1 : (3, 3) float
        A rectifying pair of pre-warps.
    pts0, pts1 : (N, 2) float
        The pairs in image-0 and image-1 pixels, ``N >= 1``.

    Returns
    -------
    H_rect_0, H_rect_1 : numpy.ndarray
        ``(3, 3)`` float64 normalised pre-warps.

    Raises
    ------
    DegenerateViewError
        A pre-warp with a singular local Jacobian.
    """
    H_rect_0 = as_finite_array(H_rect_0, "H_rect_0", shape=(3, 3))
    H_rect_1 = as_finite_array(H_rect_1, "H_rect_1", shape=(3, 3))
    p0 = as_points(pts0, "pts0", min_count=1)
    p1 = as_points(pts1, "pts1", min_count=1)
    out = []
    Js = []
    for H, p in ((H_rect_0, p0), (H_rect_1, p1)):
        c = p.mean(axis=0, keepdims=True)
        J, w = _jacobian(H, c)
        Hn = H / w[0]  # w = 1 at the centroid
        J, _ = _jacobian(Hn, c)
        out.append(Hn)
        Js.append(J[0])
    ny = [np.linalg.norm(J[1]) for J in Js]
    if min(ny) < tol.VM_UNIT_ZERO:
        raise DegenerateViewError(expected_got("pre-warp", "a regular local Jacobian", "a singular one"))
    s = 1.0 / np.sqrt(ny[0] * ny[1])
    res = []
    for H, J in zip(out, Js, strict=True):
        target = s * np.array([J[1, 1], -J[1, 0]])
        try:
            a, k = np.linalg.solve(J.T, target)
        except np.linalg.LinAlgError as exc:
            raise DegenerateViewError(expected_got("pre-warp", "a regular local Jacobian",
                                                   "a singular one")) from exc
        A = np.array([[a, k, 0.0], [0.0, s, 0.0], [0.0, 0.0, 1.0]])
        res.append(A @ H)
    r0, r1 = apply_h(res[0], p0), apply_h(res[1], p1)
    ty = -0.5 * (r0[:, 1].mean() + r1[:, 1].mean())
    final = []
    for H, r in zip(res, (r0, r1), strict=True):
        Tm = np.array([[1.0, 0.0, -r[:, 0].mean()], [0.0, 1.0, ty], [0.0, 0.0, 1.0]])
        final.append(Tm @ H)
    return final[0], final[1]


# --------------------------------------------------------------------------- checks + driver


def _epipole_check(F: np.ndarray, shape0: tuple[int, int], shape1: tuple[int, int]) -> None:
    e0, e1 = epipoles(F)
    for i, (e, shape) in enumerate(((e0, shape0), (e1, shape1))):
        px = epipole_pixel(e)
        if px is None:
            continue
        h, w = shape
        m = tol.VM_EPIPOLE_MARGIN * float(np.hypot(h, w))
        if -0.5 - m <= px[0] <= w - 0.5 + m and -0.5 - m <= px[1] <= h - 0.5 + m:
            raise DegenerateViewError(expected_got(
                f"epipole of image {i}", f"outside the image grown by {tol.VM_EPIPOLE_MARGIN:.0%} of its "
                "diagonal (rectification needs it sent to infinity)",
                f"({px[0]:.1f}, {px[1]:.1f}) in a {w}x{h} image: the cameras (nearly) see each other"))


def _quality(H_rect_0: np.ndarray, H_rect_1: np.ndarray, p0: np.ndarray, p1: np.ndarray,
             shape0: tuple[int, int], shape1: tuple[int, int]) -> dict[str, float]:
    d0 = prewarp_distortion(H_rect_0, shape0)
    d1 = prewarp_distortion(H_rect_1, shape1)
    r0, r1 = apply_h(H_rect_0, p0), apply_h(H_rect_1, p1)
    return {
        "y_rms": float(np.sqrt(np.mean((r1[:, 1] - r0[:, 1]) ** 2))),
        "w_min": min(d0["w_min"], d1["w_min"]),
        "anisotropy": max(d0["anisotropy"], d1["anisotropy"]),
        "scale_ratio": max(d0["scale_max"], d1["scale_max"]) / max(min(d0["scale_min"], d1["scale_min"]),
                                                                   tol.ZERO),
    }


def _refusal(q: dict[str, float]) -> str | None:
    if q["w_min"] <= 0:
        return "part of the image goes through infinity"
    if q["anisotropy"] > tol.VM_MAX_ANISOTROPY:
        return f"anisotropy {q['anisotropy']:.1f} > {tol.VM_MAX_ANISOTROPY}"
    if q["scale_ratio"] > tol.VM_MAX_SCALE_RATIO:
        return f"local scale ratio {q['scale_ratio']:.1f} > {tol.VM_MAX_SCALE_RATIO}"
    return None


def rectify(F: Any, pts0: Any, pts1: Any, shape0: tuple[int, int], shape1: tuple[int, int], *,
            method: str = "auto", K0: Any = None, K1: Any = None) -> Rectification:
    """Pre-warps that make the two views parallel, normalised and checked.

    Parameters
    ----------
    F : (3, 3)
        ``x1^T F x0 = 0`` in pixels.
    pts0, pts1 : (N, 2)
        Inlier correspondences (pixel-centre origin), ``N >= 8``.
    shape0, shape1 : (H, W)
        Image shapes.
    method : {"auto", "opencv", "seitz-dyer"}
        ``"auto"`` builds both and keeps the one with the smaller anisotropy
        among those that pass the checks.
    K0, K1 : (3, 3), optional
        Intrinsics for the Seitz & Dyer construction.

    Returns
    -------
    Rectification
        ``method="parallel"`` with identities when the views are already
        parallel (RMS ``y1 - y0`` <= :data:`tol.VM_PARALLEL_Y_PX`).

    Notes
    -----
    Convention: ``H_rect_i`` maps image-``i`` pixels to the rectified frame (see the module docstring).

    Raises
    ------
    DegenerateViewError
        Epipole inside or near an image, or every construction too distorting
        (the message lists why each was refused).
    """
    if method not in RECTIFIERS:
        raise ValidationError(expected_got("rectify method", f"one of {RECTIFIERS}", repr(method)))
    F = normalize_f(F)
    p0 = as_points(pts0, "pts0", min_count=8)
    p1 = as_points(pts1, "pts1", min_count=8)
    shape0, shape1 = as_shape(shape0, "shape0"), as_shape(shape1, "shape1")
    y_raw = float(np.sqrt(np.mean((p1[:, 1] - p0[:, 1]) ** 2)))
    if y_raw <= tol.VM_PARALLEL_Y_PX:
        return Rectification(np.eye(3), np.eye(3), "parallel", y_raw, 1.0, 1.0, {})
    _epipole_check(F, shape0, shape1)
    tried = ("opencv", "seitz-dyer") if method == "auto" else (method,)
    cands: dict[str, Any] = {}
    good: list[tuple[float, str, np.ndarray, np.ndarray, dict[str, float]]] = []
    for m in tried:
        try:
            if m == "opencv":
                H_rect_0, H_rect_1 = rectify_opencv(F, p0, p1, shape0)
            else:
                H_rect_0, H_rect_1 = seitz_dyer_prewarps(F, shape0, shape1, K0=K0, K1=K1)
            H_rect_0, H_rect_1 = normalize_prewarps(H_rect_0, H_rect_1, p0, p1)
        except GeometryError as exc:
            cands[m] = {"refused": str(exc)}
            continue
        q = _quality(H_rect_0, H_rect_1, p0, p1, shape0, shape1)
        why = _refusal(q)
        cands[m] = dict(q, refused=why) if why else q
        if why is None:
            good.append((q["anisotropy"], m, H_rect_0, H_rect_1, q))
    if not good:
        reasons = "; ".join(f"{m}: {c.get('refused')}" for m, c in cands.items())
        raise DegenerateViewError(expected_got("rectification", "pre-warps within the distortion limits",
                                               reasons))
    good.sort(key=lambda t: t[0])
    _, m, H_rect_0, H_rect_1, q = good[0]
    return Rectification(H_rect_0, H_rect_1, m, q["y_rms"], q["anisotropy"], q["scale_ratio"], cands)
