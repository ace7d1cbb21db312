"""Suite ``warp``: piecewise-affine mesh warping against its baselines.

Methods, all timed in the same run and interleaved per case:

* ``morphkit`` -- :class:`morphkit.warp.MeshWarper` built once per source mesh;
  each call computes the maps for new destination points and applies them
  (the per-frame cost).
* ``morphkit_apply`` -- :meth:`morphkit.warp.WarpMaps.apply` alone (maps reused:
  the same warp applied to another image/channel).
* ``remap`` -- one ``cv2.remap`` of the same size with precomputed float32 maps
  (the maps morphkit computed): the floor every ratio refers to.
* ``per_triangle`` -- the common OpenCV recipe: per triangle, ``cv2.warpAffine``
  of the source bounding-box ROI into the destination bounding-box ROI and a
  ``cv2.fillConvexPoly`` mask, composited with ``cv2.copyTo``.
* ``skimage`` -- ``PiecewiseAffineTransform.estimate`` + ``warp(order=1)``
  (when scikit-image is missing, or for sizes above 512 in the full run and 256
  in ``--quick`` because it is slow, there is no skimage row and the morphkit
  row's note says so). Timed separately with 3-5 repeats.

Every case uses the same mesh for all methods: a ``rows x cols`` lattice over
the image with interior points jittered, triangulated by Delaunay of the
destination points (what skimage does internally, so the outputs are comparable).
``metrics`` hold ``mean_abs_err``/``max_abs_err`` against the skimage output over
the pixels morphkit's mask covers, as a fraction of the value range (1.0 for
float32, 255 for uint8). Images: float32 single channel (a depth-map stand-in)
and uint8 RGBA, both a smooth texture (so OpenCV's 1/32-px interpolation
quantisation shows as ~1e-4, not as texture noise).
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from ..warp import MeshWarper, WarpMaps, delaunay_triangles
from .harness import auto_repeats, make_row, time_call, time_calls

__all__ = ["run", "per_triangle_warp", "make_case", "FLOOR_METHOD", "PLOT_OPTIONS"]

#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "remap"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS: dict[str, Any] = {
    "error_key": "mean_abs_err", "panel_keys": ("dtype", "grid"),
    "scene_keys": ("dtype", "channels", "size", "grid"), "defaults": ({"method": "morphkit"},),
    "default_label": "default: morphkit (warp_mesh)"}

SIZES_FULL = (64, 128, 256, 512, 1024)
GRIDS_FULL = ((5, 15), (7, 15), (16, 16), (33, 33))
SIZES_QUICK = (64, 256, 512)
GRIDS_QUICK = ((5, 15), (33, 33))
DTYPES = ("float32", "uint8")

#: A jittered benchmark mesh is kept only if every source triangle's area is above
#: this fraction of the largest destination triangle's (no sliver triangles, which
#: would time a degenerate case rather than the warp).
MIN_TRIANGLE_AREA_RATIO = 1e-3


def per_triangle_warp(image: np.ndarray, src: np.ndarray, dst: np.ndarray, tris: np.ndarray,
                      out_shape: tuple[int, int], fill: float = 0.0) -> np.ndarray:
    """The per-triangle OpenCV recipe, written fairly (bounding-box ROIs, sub-pixel masks).

    For each triangle: crop the source bounding box (+1 px for interpolation),
    ``cv2.warpAffine`` it into the destination bounding box (clipped to the
    output), rasterise the destination triangle with ``cv2.fillConvexPoly``
    (4 fractional bits) and copy through that mask. Edge pixels are covered by
    both neighbours (the later one wins), so it is not exact along edges.

    Parameters
    ----------
    image : numpy.ndarray
        ``(H, W)`` or ``(H, W, C)`` source image, any dtype ``cv2.warpAffine`` takes.
    src : numpy.ndarray
        ``(N, 2)`` mesh points ``(x, y)`` in ``image``, pixel coordinates (:mod:`morphkit.conventions`).
    dst : numpy.ndarray
        ``(N, 2)`` the same points in the output, pixel coordinates.
    tris : numpy.ndarray
        ``(T, 3)`` vertex indices of the triangles.
    out_shape : (int, int)
        Output ``(H, W)``.
    fill : float
        Value of the pixels no triangle covers.

    Returns
    -------
    numpy.ndarray
        ``out_shape + image.shape[2:]`` warped image, ``image``'s dtype.
    """
    H, W = out_shape
    out = np.full((H, W) + image.shape[2:], fill, dtype=image.dtype)
    h_img, w_img = image.shape[:2]
    src32 = src.astype(np.float32)
    dst32 = dst.astype(np.float32)
    for t in tris:
        s = src32[t]
        d = dst32[t]
        sx0 = max(int(np.floor(s[:, 0].min())) - 1, 0)
        sy0 = max(int(np.floor(s[:, 1].min())) - 1, 0)
        sx1 = min(int(np.ceil(s[:, 0].max())) + 2, w_img)
        sy1 = min(int(np.ceil(s[:, 1].max())) + 2, h_img)
        dx0 = max(int(np.floor(d[:, 0].min())), 0)
        dy0 = max(int(np.floor(d[:, 1].min())), 0)
        dx1 = min(int(np.ceil(d[:, 0].max())) + 1, W)
        dy1 = min(int(np.ceil(d[:, 1].max())) + 1, H)
        if sx1 <= sx0 or sy1 <= sy0 or dx1 <= dx0 or dy1 <= dy0:
            continue
        A = cv2.getAffineTransform(s - np.float32([sx0, sy0]), d - np.float32([dx0, dy0]))
        patch = cv2.warpAffine(image[sy0:sy1, sx0:sx1], A, (dx1 - dx0, dy1 - dy0),
                               flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT_101)
        mask = np.zeros((dy1 - dy0, dx1 - dx0), dtype=np.uint8)
        poly = np.round((d - np.float32([dx0, dy0])) * 16).astype(np.int32)
        cv2.fillConvexPoly(mask, poly, 1, cv2.LINE_8, 4)
        roi = out[dy0:dy1, dx0:dx1]
        cv2.copyTo(patch, mask, roi)
    return out


def _texture(size: int, dtype: str) -> np.ndarray:
    yy, xx = np.mgrid[0:size, 0:size].astype(np.float32) * (256.0 / size)
    base = 0.5 + 0.2 * np.sin(xx / 11.0) + 0.15 * np.cos(yy / 7.0) + 0.1 * np.sin((xx + 2 * yy) / 13.0)
    if dtype == "float32":
        return base.astype(np.float32)
    rgba = np.stack([base, 1.0 - base, np.roll(base, size // 3, axis=1), np.full_like(base, 0.8)], axis=2)
    return np.clip(np.rint(255.0 * rgba), 0, 255).astype(np.uint8)


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def make_case(size: int, rows: int, cols: int, rng: np.random.Generator
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(src, dst, triangles)``: a lattice over a ``size``-pixel square, interior points jittered.

    Triangles are Delaunay of ``dst``; the jitter (a fraction of the smaller cell
    side) is halved until every triangle is non-degenerate and keeps its
    orientation in the source.

    Parameters
    ----------
    size : int
        Side of the square image, in pixels.
    rows : int
        Lattice points per column (at least 2).
    cols : int
        Lattice points per row (at least 2).
    rng : numpy.random.Generator
        Draws the jitter.

    Returns
    -------
    src : numpy.ndarray
        ``(rows * cols, 2)`` float64 lattice points ``(x, y)``, pixel coordinates
        (:mod:`morphkit.conventions`).
    dst : numpy.ndarray
        ``(rows * cols, 2)`` float64 jittered points (border points unmoved).
    triangles : numpy.ndarray
        ``(T, 3)`` vertex indices, Delaunay of ``dst``.
    """
    xs = np.linspace(0.0, size - 1.0, cols)
    ys = np.linspace(0.0, size - 1.0, rows)
    X, Y = np.meshgrid(xs, ys)
    src = np.stack([X.ravel(), Y.ravel()], axis=1)
    inner = (X > 0).ravel() & (X < size - 1).ravel() & (Y > 0).ravel() & (Y < size - 1).ravel()
    amp = 0.2 * min(xs[1] - xs[0], ys[1] - ys[0])
    noise = rng.uniform(-1.0, 1.0, src.shape)
    for _ in range(20):
        dst = src.copy()
        dst[inner] += amp * noise[inner]
        tris = delaunay_triangles(dst)
        sv, dv = src[tris], dst[tris]
        a_s = _cross2(sv[:, 1] - sv[:, 0], sv[:, 2] - sv[:, 0])
        a_d = _cross2(dv[:, 1] - dv[:, 0], dv[:, 2] - dv[:, 0])
        if np.all(np.abs(a_s) > MIN_TRIANGLE_AREA_RATIO * np.abs(a_d).max()) \
                and np.all(np.sign(a_s) == np.sign(a_d)):
            return src, dst, tris
        amp *= 0.5
    raise RuntimeError("could not build a valid jittered mesh")  # pragma: no cover


def _sk_transform(cls: Any, dst: np.ndarray, src: np.ndarray) -> Any:
    """skimage transform mapping output (dst) coordinates to input (src) ones."""
    if hasattr(cls, "from_estimate"):  # skimage >= 0.26
        return cls.from_estimate(dst, src)
    tf = cls()
    tf.estimate(dst, src)
    return tf


def _errors(out: np.ndarray, ref: np.ndarray, mask: np.ndarray, value_range: float) -> dict[str, float]:
    diff = np.abs(out.astype(np.float64) - ref.astype(np.float64))[mask]
    if diff.size == 0:
        return {}
    return {"mean_abs_err": float(diff.mean() / value_range), "max_abs_err": float(diff.max() / value_range)}


def run(*, quick: bool = False, sizes: tuple[int, ...] | None = None,
        grids: tuple[tuple[int, int], ...] | None = None, dtypes: tuple[str, ...] | None = None,
        skimage_max_size: int | None = None, budget_s: float | None = None) -> list[dict[str, Any]]:
    """Run the suite; the keyword overrides exist for tests and ad-hoc sweeps.

    Parameters
    ----------
    quick : bool
        The quick sizes and grids, smaller skimage limit and timing budget.
    sizes : tuple of int, optional
        Image sides in pixels (default by ``quick``).
    grids : tuple of (int, int), optional
        Lattices ``(rows, cols)`` of mesh points (default by ``quick``).
    dtypes : tuple of str, optional
        Image types, ``"float32"`` (one channel) and/or ``"uint8"`` (RGBA) (default both).
    skimage_max_size : int, optional
        Largest size timed with scikit-image (default by ``quick``).
    budget_s : float, optional
        Seconds of timing per method and case that set the repeats (default by ``quick``).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    try:
        from skimage.transform import PiecewiseAffineTransform
        from skimage.transform import warp as sk_warp
    except ImportError:  # pragma: no cover - depends on the environment
        PiecewiseAffineTransform = None  # noqa: N806
    sizes = sizes or (SIZES_QUICK if quick else SIZES_FULL)
    grids = grids or (GRIDS_QUICK if quick else GRIDS_FULL)
    dtypes = dtypes or DTYPES
    sk_max = skimage_max_size if skimage_max_size is not None else (256 if quick else 512)
    budget = budget_s if budget_s is not None else (0.08 if quick else 0.25)
    rng = np.random.default_rng(12345)
    rows: list[dict[str, Any]] = []
    for size in sizes:
        for gr, gc in grids:
            src, dst, tris = make_case(size, gr, gc, rng)
            for dtype in dtypes:
                img = _texture(size, dtype)
                vrange = 1.0 if dtype == "float32" else 255.0
                shape = (size, size)
                params = {"size": size, "grid": f"{gr}x{gc}", "dtype": dtype,
                          "channels": 1 if img.ndim == 2 else img.shape[2], "triangles": int(len(tris))}
                warper = MeshWarper(src, tris)
                wm = warper.maps(dst, shape)
                m1, m2 = wm.map1, wm.map2

                def f_morphkit(img: np.ndarray = img, warper: MeshWarper = warper, dst: np.ndarray = dst,
                               shape: tuple[int, int] = shape) -> np.ndarray:
                    return warper(img, dst, shape)

                def f_apply(img: np.ndarray = img, wm: WarpMaps = wm) -> np.ndarray:
                    return wm.apply(img)

                def f_remap(img: np.ndarray = img, m1: np.ndarray = m1,
                            m2: np.ndarray | None = m2) -> np.ndarray:
                    return cv2.remap(img, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                                     borderValue=0)

                def f_tri(img: np.ndarray = img, src: np.ndarray = src, dst: np.ndarray = dst,
                          tris: np.ndarray = tris, shape: tuple[int, int] = shape) -> np.ndarray:
                    return per_triangle_warp(img, src, dst, tris, shape)

                fns = {"morphkit": f_morphkit, "morphkit_apply": f_apply, "remap": f_remap,
                       "per_triangle": f_tri}
                notes = {"remap": "floor: one cv2.remap with morphkit's precomputed maps",
                         "morphkit_apply": "maps reused (WarpMaps.apply)"}
                ref = None
                sk_note = ""
                if PiecewiseAffineTransform is None:
                    sk_note = "skimage not installed: no skimage row, no error metrics"
                elif size > sk_max:
                    sk_note = f"skimage only run for size <= {sk_max} (slow): no error metrics"
                n = auto_repeats(f_tri, budget_s=budget, lo=3, hi=30)
                timings = time_calls(fns, repeats=n, warmup=1)
                if PiecewiseAffineTransform is not None and size <= sk_max:

                    def f_sk(img: np.ndarray = img, src: np.ndarray = src,
                             dst: np.ndarray = dst) -> np.ndarray:
                        return sk_warp(img, _sk_transform(PiecewiseAffineTransform, dst, src), order=1,
                                       preserve_range=True, cval=0.0)

                    ref = f_sk()  # also the warm-up
                    timings["skimage"] = time_call(f_sk, repeats=3 if size >= 256 else 5, warmup=0)
                    fns["skimage"] = f_sk
                    notes["skimage"] = "reference for the error metrics; timed separately (3-5 repeats)"
                for method in fns:
                    metrics = {}
                    if ref is not None:
                        out = ref if method == "skimage" else fns[method]()
                        metrics = _errors(out, ref, wm.mask, vrange)
                    note = notes.get(method, "")
                    if method == "morphkit" and sk_note:
                        note = sk_note
                    rows.append(make_row("warp", method, params, timings[method], metrics=metrics,
                                         note=note))
    return rows

