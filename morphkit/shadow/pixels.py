"""The drawn pixels of a frame's depth image: world points, normals, and whether they face the light.

:func:`drawn_pixels` is the per-pixel geometry of :func:`morphkit.shadow.frame.render_frame`: the
pixels holding a finite positive depth (in row-major order), their world points
(:meth:`~morphkit.camera.CameraModel.unproject`), their central-difference normals
(:func:`~morphkit.shadow.lookup.normals_from_points`) and the facing test (normal towards the
light). The numpy reference does it as those functions do, on whole ``(H, W, 3)`` images; the
compiled kernel (numba, :func:`morphkit.settings.compile_kernel`) does it in one pass over the
rows, keeping three rows of points (no ``(H, W, 3)`` image), with the same float32 arithmetic for
the normals, and writes only the drawn pixels; in bands of rows on
:data:`~morphkit.settings.WARP_THREADS` threads for frames of at least
:data:`~morphkit.warp.PARALLEL_MIN_PIXELS` pixels (the same output as one band). The tests compare
it with the reference: the same pixels and facing, normals within float32 rounding, points within
the last bit or two of float64 (numpy's matrix product sums in BLAS's order).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..scene import AreaLight, DirectionalLight, Light
from ..settings import WARP_THREADS, compile_kernel, use_compiled
from ..warp import PARALLEL_MIN_PIXELS, in_bands
from .lookup import normals_from_points

__all__ = ["DrawnPixels", "drawn_pixels"]


class DrawnPixels(NamedTuple):
    """The drawn pixels of a depth image (:func:`drawn_pixels`).

    Parameters
    ----------
    index : (N,) intp
        Flat (row-major) indices of the pixels with a finite positive depth, ascending.
    points : (N, 3) float64
        Their world points.
    normals : (N, 3) float32
        Their unit normals (zero where undefined: image border, degenerate neighbourhood).
    facing : (H, W) bool
        Drawn pixels whose normal faces the light.
    """

    index: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    facing: np.ndarray


def drawn_pixels(camera: CameraModel, depth: np.ndarray, light: Light) -> DrawnPixels:
    """World points, normals and light facing of the drawn pixels of ``depth``.

    Parameters
    ----------
    camera : morphkit.camera.CameraModel
        The camera ``depth`` was rendered with.
    depth : (H, W) float
        Linear depth; background pixels hold ``+inf`` (or any non-finite, or non-positive).
    light : morphkit.scene.Light
        The light the facing test looks at (a directional light's direction, else the position
        of a point light or an area light's centre).

    Returns
    -------
    DrawnPixels
        ``index``, ``points``, ``normals`` and ``facing``.

    Raises
    ------
    ValidationError
        ``depth`` is not of the camera's shape.
    """
    depth = np.asarray(depth)
    if depth.shape != camera.shape:
        raise ValidationError(expected_got("depth", f"shape {camera.shape}", f"shape {depth.shape}"))
    directional = isinstance(light, DirectionalLight)
    if directional:
        toward = -np.asarray(light.direction, np.float64)
    else:
        toward = np.asarray(light.center if isinstance(light, AreaLight) else light.position, np.float64)
    if not use_compiled(_pixels_kernel):
        return _drawn_numpy(camera, depth, directional, toward)
    if depth.dtype not in (np.float32, np.float64):
        depth = depth.astype(np.float64)
    depth = np.ascontiguousarray(depth)
    h, w = camera.shape
    index = np.empty(h * w, np.intp)
    points = np.empty((h * w, 3), np.float64)
    normals = np.empty((h * w, 3), np.float32)
    facing = np.zeros((h, w), bool)
    pose = camera.cam2world
    args = (depth, np.ascontiguousarray(pose[:3, :3], np.float64),
            np.ascontiguousarray(pose[:3, 3], np.float64), float(camera.cx), float(camera.cy),
            float(camera.fx), float(camera.fy),
            camera.projection == "perspective", directional, np.ascontiguousarray(toward))
    # bands of rows on WARP_THREADS threads (band 0 in this one), each writing its drawn pixels
    # after those of the bands above it: the same output as one band
    n = WARP_THREADS if h * w >= PARALLEL_MIN_PIXELS else 1
    bands = [(h * b // n, h * (b + 1) // n) for b in range(n)]
    counts = in_bands(lambda b: _count_kernel(depth, *bands[b]), n)
    starts = np.concatenate([[0], np.cumsum(counts)])
    in_bands(lambda b: _pixels_kernel(*args, *bands[b], int(starts[b]), index, points, normals, facing), n)
    total = int(starts[-1])
    return DrawnPixels(index[:total], points[:total], normals[:total], facing)


def _drawn_numpy(camera: CameraModel, depth: np.ndarray, directional: bool, toward: np.ndarray
                 ) -> DrawnPixels:
    """The numpy reference of :func:`drawn_pixels` (whole images, then the drawn pixels by index)."""
    world, valid = camera.unproject(depth)
    normals = normals_from_points(world, valid)
    index = np.flatnonzero(valid)
    points = world.reshape(-1, 3).take(index, axis=0)
    pixel_normals = normals.reshape(-1, 3).take(index, axis=0)
    to_light = np.broadcast_to(toward, points.shape) if directional else toward - points
    facing = np.zeros(camera.shape, bool)
    facing.reshape(-1)[index] = np.einsum("nk,nk->n", pixel_normals, to_light) > 0
    return DrawnPixels(index, points, pixel_normals, facing)


def _row_points(depth: np.ndarray, r: int, R: np.ndarray, t: np.ndarray, cx: float, cy: float, fx: float,
                fy: float, persp: bool, out: np.ndarray) -> None:
    """World points ``out (W, 3)`` of image row ``r`` (:meth:`CameraModel.unproject`'s; 0 where not drawn)."""
    Y0 = (r - cy) / fy
    for c in range(depth.shape[1]):
        z = np.float64(depth[r, c])
        if not (np.isfinite(z) and z > 0):
            out[c, 0] = out[c, 1] = out[c, 2] = 0.0
            continue
        X = (c - cx) / fx
        Y = Y0
        if persp:
            X, Y = X * z, Y * z
        out[c, 0] = R[0, 0] * X + R[0, 1] * Y + R[0, 2] * z + t[0]
        out[c, 1] = R[1, 0] * X + R[1, 1] * Y + R[1, 2] * z + t[1]
        out[c, 2] = R[2, 0] * X + R[2, 1] * Y + R[2, 2] * z + t[2]


def _count_drawn(depth: np.ndarray, r0: int, r1: int) -> int:
    """The drawn pixels (finite positive depth) of rows ``r0:r1``."""
    n = 0
    for r in range(r0, r1):
        for c in range(depth.shape[1]):
            z = depth[r, c]
            if np.isfinite(z) and z > 0:
                n += 1
    return n


def _pixels_loop(depth: np.ndarray, R: np.ndarray, t: np.ndarray, cx: float, cy: float, fx: float,
                 fy: float, persp: bool, directional: bool, toward: np.ndarray, r0: int, r1: int, n0: int,
                 index: np.ndarray, points: np.ndarray, normals: np.ndarray, facing: np.ndarray) -> int:
    """:func:`_drawn_numpy` for rows ``r0:r1`` in one pass, keeping three rows of world points;
    their drawn pixels go to ``index``, ``points`` and ``normals`` from entry ``n0`` on.
    Returns the number of them."""
    h, w = depth.shape
    rows = np.empty((3, w, 3), np.float64)  # world points of rows r - 1, r, r + 1 (ring)
    for r in range(max(r0 - 1, 0), r0 + 1):
        _row_points(depth, r, R, t, cx, cy, fx, fy, persp, rows[r % 3])
    n = n0
    zero = np.float32(0.0)
    for r in range(r0, r1):
        if r + 1 < h:
            _row_points(depth, r + 1, R, t, cx, cy, fx, fy, persp, rows[(r + 1) % 3])
        up, mid, down = rows[(r + 2) % 3], rows[r % 3], rows[(r + 1) % 3]
        inner = 0 < r < h - 1
        for c in range(w):
            z = np.float64(depth[r, c])
            if not (np.isfinite(z) and z > 0):
                continue
            px, py, pz = mid[c, 0], mid[c, 1], mid[c, 2]
            index[n] = r * w + c
            points[n, 0], points[n, 1], points[n, 2] = px, py, pz
            n0 = n1 = n2 = zero
            if inner and 0 < c < w - 1:
                # central differences of the float32 points (normals_from_points' arithmetic)
                a0 = np.float32(down[c, 0]) - np.float32(up[c, 0])  # d/dy
                a1 = np.float32(down[c, 1]) - np.float32(up[c, 1])
                a2 = np.float32(down[c, 2]) - np.float32(up[c, 2])
                b0 = np.float32(mid[c + 1, 0]) - np.float32(mid[c - 1, 0])  # d/dx
                b1 = np.float32(mid[c + 1, 1]) - np.float32(mid[c - 1, 1])
                b2 = np.float32(mid[c + 1, 2]) - np.float32(mid[c - 1, 2])
                c0 = a1 * b2 - a2 * b1  # np.cross(d/dy, d/dx), numpy's order of operations
                c1 = a2 * b0 - a0 * b2
                c2 = a0 * b1 - a1 * b0
                norm = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
                if norm > 0:
                    n0, n1, n2 = c0 / norm, c1 / norm, c2 / norm
            normals[n, 0], normals[n, 1], normals[n, 2] = n0, n1, n2
            if directional:
                tx, ty, tz = toward[0], toward[1], toward[2]
            else:
                tx, ty, tz = toward[0] - px, toward[1] - py, toward[2] - pz
            facing[r, c] = np.float64(n0) * tx + np.float64(n1) * ty + np.float64(n2) * tz > 0
            n += 1
    return n - n0


_row_points = compile_kernel(_row_points)  # called by the kernel below (None without numba: unused)
_pixels_kernel = compile_kernel(_pixels_loop)
_count_kernel = compile_kernel(_count_drawn)
