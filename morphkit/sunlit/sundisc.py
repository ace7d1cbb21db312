"""A sun disc's soft shadow from one orthographic light view: percentage-closer soft shadows.

The sun is a disc of angular radius ``a`` around its direction. Seen from a receiver point at
depth ``z`` along the light, an occluder at depth ``d < z`` hides the disc where it covers
it; moving the light direction by an angle ``b`` moves the occluder's shadow by
``(z - d) tan b`` across the light, so the disc's penumbra is ``2 (z - d) tan a`` wide, in
map texels ``2 fx (z - d) tan a`` (``fx`` texels per unit of the orthographic view). With
one depth map along the disc's centre, the visible fraction of the disc is estimated by
percentage-closer filtering with a kernel that wide (Reeves et al. [1]_), its occluder depth
``d`` from a blocker search first (PCSS, Fernando [2]_), as :mod:`.filtered` does for the
perspective maps of an area light's samples:

1. **Search.** The texels that the square of half-width ``h_s + r`` around the point's
   projection overlaps (``h_s = fx tan(a) (z - z_min)``, ``z_min`` the map's nearest occluder:
   no penumbra can be wider; capped at :data:`~morphkit.tol.SUN_DISC_MAX_HALF_TEXELS`; ``r``
   below) that are closer than the point by more than the bias: their mean depth is ``d``.
   None: the whole disc is seen (1).
2. **Filter.** The disc's kernel is the square of its area, half-width
   ``h = (sqrt(pi) / 2) fx tan(a) (z - d)``, convolved with a box of half-width ``r``
   (:data:`~morphkit.tol.SUN_DISC_RASTER_HALF_TEXEL`): separable, a trapezoid along each
   axis. The visibility is one less the kernel's weight (each texel counting with the
   kernel's integral over it) on texels closer than the point by more than the bias.
   Texels outside the map hold no occluder. A fraction within
   :data:`~morphkit.tol.PENUMBRA_EPS` of 0 or 1 is the sums' round-off: 0 or 1.

**Why the box.** The map holds an occluder's edge only to the texel: a texel is drawn when its
centre is covered, so the true edge lies anywhere within half a texel of the drawn one. At the
real sun (:data:`~morphkit.conventions.SUN_DISC_RADIUS_DEG`) the disc's own penumbra is mostly
narrower than a texel: the square alone (or the hard lookup) puts the edge on the texel grid,
where ``N`` maps along slightly different directions dither it. The box spreads the drawn edge
over part of that uncertainty; its width is measured (``tol``). **A disc of zero radius** is
the hard lookup (the nearest texel) exactly: a point light's shadow is not blurred. **Bias:**
the field map's constant one (:data:`~morphkit.tol.SUN_GROUND_BIAS_TEXELS` texels), grown by
``w / fx`` for a kernel of half-width ``w`` texels (``h + r``; ``h_s + r`` in the search): a
receiver drawn into the map itself, sloped by up to 45 degrees to the light, is not its own
occluder inside the kernel (the receivers' normal offset, :mod:`.receivers`, does the rest).

Compared with averaging ``N`` maps over the disc (``N + 1`` levels: bands): one map, a
smooth penumbra; its error is the single-depth assumption (an occluder at several depths in
one kernel). Figures: ``docs/RESULTS.md``.

References
----------
.. [1] W. T. Reeves, D. H. Salesin and R. L. Cook, "Rendering Antialiased Shadows with Depth
   Maps", Computer Graphics (Proc. SIGGRAPH 87), 21(4), pp. 283-291, 1987.
.. [2] R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 Sketches, 2005.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..settings import NUMBA_AVAILABLE, compile_kernel, use_compiled
from ..shadow.lookup import check_depth_map
from ..validate import as_finite_array

__all__ = ["disc_visibility", "DiscMap"]

#: Half-width of the square of a disc's area per unit radius: ``sqrt(pi) / 2``.
DISC_SQUARE = math.sqrt(math.pi) / 2.0


def _spread_cdf(t: float, h: float, f: float) -> float:
    """``P(X + Y <= t)`` for ``X`` uniform over ``[-h, h]`` and ``Y`` over ``[-f, f]`` (``h, f >= 0``,
    not both 0): the trapezoid's cumulative, piecewise quadratic."""
    if h < f:
        h, f = f, h
    if t <= -(h + f):
        return 0.0
    if t >= h + f:
        return 1.0
    if f <= 0.0:
        return (t + h) / (2.0 * h)
    if t < f - h:
        s = t + h + f
        return s * s / (8.0 * h * f)
    if t <= h - f:
        return f / (2.0 * h) + (t + h - f) / (2.0 * h)
    s = h + f - t
    return 1.0 - s * s / (8.0 * h * f)


def _hard(u: float, v: float, z: float, dm: np.ndarray, bias: float) -> float:
    """The nearest texel's lookup: 0 behind an occluder, else 1."""
    H, W = dm.shape
    c, r = int(math.floor(u + 0.5)), int(math.floor(v + 0.5))
    return 0.0 if 0 <= c < W and 0 <= r < H and dm[r, c] < z - bias else 1.0


def _disc_loop(vis: np.ndarray, pts: np.ndarray, T: np.ndarray, dm: np.ndarray, sat: np.ndarray,
               z_min: float, k: float, bias: float, fx: float, raster: float, max_half: float,
               eps: float) -> None:
    """The per-point loop (module docstring); ``vis`` holds ones on entry; ``sat`` the drawn
    texels' summed-area table (``(H + 1, W + 1)``): a search box without one is lit at once."""
    H, W = dm.shape
    wcol = np.empty(int(2.0 * (max_half + raster)) + 4, np.float64)  # a kernel row's column weights
    for n in range(pts.shape[0]):
        x, y, z0 = pts[n, 0], pts[n, 1], pts[n, 2]
        u = T[0, 0] * x + T[0, 1] * y + T[0, 2] * z0 + T[0, 3]
        v = T[1, 0] * x + T[1, 1] * y + T[1, 2] * z0 + T[1, 3]
        z = T[2, 0] * x + T[2, 1] * y + T[2, 2] * z0 + T[2, 3]
        if k == 0.0:  # a disc of zero radius: the hard lookup
            vis[n] = np.float32(_hard(u, v, z, dm, bias))
            continue
        hs = min(k * (z - z_min), max_half) + raster
        # the texels the widest kernel overlaps (texel i covers [i - 1/2, i + 1/2])
        r0, r1 = max(int(math.floor(v - hs + 0.5)), 0), min(int(math.floor(v + hs + 0.5)), H - 1)
        c0, c1 = max(int(math.floor(u - hs + 0.5)), 0), min(int(math.floor(u + hs + 0.5)), W - 1)
        if r1 < r0 or c1 < c0 or sat[r1 + 1, c1 + 1] - sat[r0, c1 + 1] - sat[r1 + 1, c0] + sat[r0, c0] == 0:
            continue  # no occluder texel in reach: the whole disc is seen
        zt = z - bias - hs / fx
        total, count = 0.0, 0
        for r in range(r0, r1 + 1):
            for c in range(c0, c1 + 1):
                d = dm[r, c]
                if d < zt:
                    total += d
                    count += 1
        if count == 0:
            continue
        h = min(DISC_SQUARE * k * (z - total / count), max_half)
        w = h + raster
        zt = z - bias - w / fx
        kr0, kr1 = max(int(math.floor(v - w + 0.5)), 0), min(int(math.floor(v + w + 0.5)), H - 1)
        kc0, kc1 = max(int(math.floor(u - w + 0.5)), 0), min(int(math.floor(u + w + 0.5)), W - 1)
        for c in range(kc0, kc1 + 1):
            wcol[c - kc0] = _spread_cdf(c + 0.5 - u, h, raster) - _spread_cdf(c - 0.5 - u, h, raster)
        blocked = 0.0
        for r in range(kr0, kr1 + 1):
            wy = _spread_cdf(r + 0.5 - v, h, raster) - _spread_cdf(r - 0.5 - v, h, raster)
            if wy <= 0.0:
                continue
            for c in range(kc0, kc1 + 1):
                if dm[r, c] < zt:
                    blocked += wy * wcol[c - kc0]
        f = 1.0 - blocked
        vis[n] = np.float32(0.0 if f < eps else (1.0 if f > 1.0 - eps else f))


if NUMBA_AVAILABLE:  # the inlined helpers first: the kernel resolves them when it compiles
    _spread_cdf = compile_kernel(_spread_cdf, error_model="numpy", inline="always")
    _hard = compile_kernel(_hard, error_model="numpy", inline="always")
_disc_kernel = compile_kernel(_disc_loop, error_model="numpy")


class DiscMap:
    """One orthographic map prepared for :func:`disc_visibility`'s lookups: checked once, its
    drawn texels' summed-area table and nearest depth made once (a frame looks up once per
    billboard; each lookup would otherwise pass over the whole map three times).

    Parameters
    ----------
    depth_map : (H, W) float32
        The light view's depth (``+inf`` where empty).
    light_cam : CameraModel
        Its orthographic camera, looking along the disc's centre.

    Raises
    ------
    ValidationError
        A camera that is not orthographic, a bad map.
    """

    def __init__(self, depth_map: np.ndarray, light_cam: CameraModel) -> None:
        if not isinstance(light_cam, CameraModel) or light_cam.projection != "orthographic":
            got = light_cam.projection if isinstance(light_cam, CameraModel) else type(light_cam).__name__
            raise ValidationError(expected_got("light_cam", "an orthographic CameraModel (a sun view)", got))
        self.depth = np.ascontiguousarray(check_depth_map(depth_map, light_cam.shape), np.float32)
        self.camera = light_cam
        drawn = np.isfinite(self.depth)
        self.empty = not drawn.any()
        self.z_min = float(self.depth[drawn].min()) if not self.empty else float("inf")
        self.sat = cv2.integral(drawn.astype(np.uint8))  # (H + 1, W + 1) int32
        self.T = np.ascontiguousarray(light_cam.texture_matrix()[:3], np.float64)

    def visibility(self, points: np.ndarray, radius_deg: float) -> np.ndarray:
        """Fraction ``(N,)`` float32 of the disc each world point sees (module docstring).

        Parameters
        ----------
        points : (N, 3) float
            Receiver points, world frame.
        radius_deg : float
            The disc's angular radius, degrees, in ``[0, 90)``.

        Returns
        -------
        (N,) float32
            In ``[0, 1]``: 1 the whole disc seen.

        Raises
        ------
        ValidationError
            Points not ``(N, 3)`` finite, a bad radius.
        """
        pts = np.ascontiguousarray(as_finite_array(points, "points", shape=(None, 3)), np.float64)
        a = float(radius_deg)
        if not (np.isfinite(a) and 0.0 <= a < 90.0):
            raise ValidationError(expected_got("radius_deg", "degrees in [0, 90)", radius_deg))
        vis = np.ones(len(pts), np.float32)
        if self.empty or len(pts) == 0:
            return vis
        fx = float(self.camera.fx)
        args = (vis, pts, self.T, self.depth, self.sat, self.z_min, fx * math.tan(math.radians(a)),
                tol.SUN_GROUND_BIAS_TEXELS / fx, fx, float(tol.SUN_DISC_RASTER_HALF_TEXEL),
                float(tol.SUN_DISC_MAX_HALF_TEXELS), float(tol.PENUMBRA_EPS))
        (_disc_kernel if use_compiled(_disc_kernel) else _disc_loop)(*args)
        return vis


def disc_visibility(points: np.ndarray, depth_map: np.ndarray, light_cam: CameraModel,
                    radius_deg: float) -> np.ndarray:
    """Fraction ``(N,)`` float32 of a sun disc each world point sees, from one orthographic map
    along its centre (module docstring; one lookup: :class:`DiscMap` for many on one map).

    Parameters
    ----------
    points : (N, 3) float
        Receiver points, world frame.
    depth_map : (H, W) float32
        The light view's depth (``+inf`` where empty).
    light_cam : CameraModel
        Its orthographic camera, looking along the disc's centre.
    radius_deg : float
        The disc's angular radius, degrees, in ``[0, 90)``.

    Returns
    -------
    (N,) float32
        In ``[0, 1]``: 1 the whole disc seen.

    Raises
    ------
    ValidationError
        Points not ``(N, 3)`` finite, a camera that is not orthographic, a bad map or radius.
    """
    return DiscMap(depth_map, light_cam).visibility(points, radius_deg)
