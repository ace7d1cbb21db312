"""Warp maps and their application: :class:`WarpMaps` and the ``cv2.remap``
helpers (interpolation flags, fill values, dtype conversion, channel grouping)."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..validate import as_image
from .pool import recycle

__all__ = ["WarpMaps", "OUTSIDE", "interp_flag"]

_INTERP = {"linear": cv2.INTER_LINEAR, "nearest": cv2.INTER_NEAREST}

#: Map coordinate (source ``x`` and ``y``, pixels) given to output pixels outside
#: the mesh: far enough outside any image that cv2.remap writes the border value
#: exactly (no blending).
OUTSIDE = -64.0

#: dtypes cv2.remap handles natively; others are converted (see _to_cv).
_CV_DTYPES = (np.uint8, np.uint16, np.int16, np.float32, np.float64)


# --------------------------------------------------------------------------- images


def interp_flag(interpolation: Any) -> int:
    """The OpenCV flag of an interpolation name.

    Parameters
    ----------
    interpolation : {"linear", "nearest"}

    Returns
    -------
    int
        ``cv2.INTER_LINEAR`` or ``cv2.INTER_NEAREST``.

    Raises
    ------
    ValidationError
        Any other value.
    """
    if interpolation not in _INTERP:
        raise ValidationError(expected_got("interpolation", "'linear' or 'nearest'", repr(interpolation)))
    return _INTERP[interpolation]


def _fill_values(fill: Any, channels: int, dtype: np.dtype) -> tuple[float, ...]:
    try:
        vals = np.broadcast_to(np.asarray(fill, dtype=np.float64).ravel(), (channels,))
    except (TypeError, ValueError) as exc:
        raise ValidationError(
            expected_got("fill", f"a number or {channels} numbers (one per channel)", repr(fill))
        ) from exc
    if dtype.kind != "f" and not np.all(np.isfinite(vals)):
        raise ValidationError(expected_got("fill", f"finite values for a {dtype} image", repr(fill)))
    return tuple(float(v) for v in vals)


def _to_cv(image: np.ndarray) -> np.ndarray:
    """Return ``image`` in a dtype cv2.remap accepts (values preserved exactly)."""
    dt = image.dtype
    if dt in _CV_DTYPES:
        return np.ascontiguousarray(image)
    if dt == np.bool_:
        return image.astype(np.uint8) * np.uint8(255)
    if dt == np.int8:
        return image.astype(np.int16)
    if dt == np.float16:
        return image.astype(np.float32)
    return image.astype(np.float64)  # (u)int32/64: exact below 2**53


def _from_cv(out: np.ndarray, dtype: np.dtype) -> np.ndarray:
    if out.dtype == dtype:
        return out
    if dtype == np.bool_:
        return out > 127
    if dtype.kind in "iu":
        info = np.iinfo(dtype)
        return np.clip(np.rint(out), info.min, info.max).astype(dtype)
    return out.astype(dtype)


def _remap(img: np.ndarray, m1: np.ndarray, m2: np.ndarray | None, flag: int,
           fill: tuple[float, ...]) -> np.ndarray:
    """cv2.remap with constant border ``fill``; any channel count (cv2 borders take <= 4).

    Channels go to OpenCV in groups of 4, 3 or 1, never 2: its vectorised remap
    covers 1, 3 and 4 channels, and a two-channel image takes a slower path
    (slower than two one-plane remaps: ``docs/RESULTS.md``, mesh warp) that also
    samples with 1/32-pixel fixed-point weights; so every channel count is fast
    and gets the same interpolation.
    """
    c = 1 if img.ndim == 2 else img.shape[2]
    if c <= 4 and c != 2:
        border = fill + (0.0,) * (4 - c)
        return cv2.remap(img, m1, m2, flag, borderMode=cv2.BORDER_CONSTANT, borderValue=border)
    step = 1 if c == 2 else 4
    parts = [
        _remap(np.ascontiguousarray(img[:, :, k:k + step]), m1, m2, flag, fill[k:k + step])
        for k in range(0, c, step)
    ]
    parts = [p[:, :, None] if p.ndim == 2 else p for p in parts]
    return np.concatenate(parts, axis=2)


class WarpMaps:
    """Per-pixel sampling maps of one warp, reusable across images and channels.

    Built by :meth:`~morphkit.warp.MeshWarper.maps`. The maps cover the bounding
    box of the destination mesh clipped to the output (``roi``); the rest of the
    output is ``fill``. See :mod:`morphkit.warp` for the convention.

    Parameters
    ----------
    out_shape, roi, map1, map2
        As the attributes below.
    run_lens : (2 k + 1,) int64 or None
        Run lengths over the ROI in row-major order, alternating outside and
        inside the mesh (outside first); with ``covered`` None, the coverage mask
        comes from them.
    covered : (r1 - r0, c1 - c0) bool, callable or None
        The ROI's coverage (or a callable returning it), when the maps come from
        the compiled scanline.

    Attributes
    ----------
    out_shape : tuple[int, int]
        ``(H, W)`` of the outputs.
    roi : tuple[int, int, int, int]
        ``(r0, r1, c0, c1)``: the rows ``r0:r1`` and columns ``c0:c1`` the maps cover.
    map1, map2 : numpy.ndarray or None
        The ``cv2.remap`` maps of the ROI: float32 source ``x`` and ``y``
        planes ``(r1 - r0, c1 - c0)``, or an interleaved ``(..., 2)`` map1 and
        ``map2 = None``. Pixels outside the mesh hold :data:`OUTSIDE`.
        ``map1`` is None when the mesh covers no pixel centre.
    """

    __slots__ = ("out_shape", "roi", "map1", "map2", "_lens", "_mask", "_covered", "_pooled")

    def __init__(self, out_shape: tuple[int, int], roi: tuple[int, int, int, int],
                 map1: np.ndarray | None, map2: np.ndarray | None,
                 run_lens: np.ndarray | None, covered: np.ndarray | None = None) -> None:
        self.out_shape = out_shape
        self.roi = roi
        self.map1 = map1
        self.map2 = map2
        self._lens = run_lens
        self._covered = covered  # ROI coverage, when the maps come from the compiled scanline
        self._mask: np.ndarray | None = None
        self._pooled = map2 is not None and (run_lens is not None or covered is not None)

    def __del__(self) -> None:
        try:
            if self._pooled:
                m1, m2 = self.map1, self.map2
                self.map1 = self.map2 = None
                recycle(m1)
                recycle(m2)
        except Exception:  # pragma: no cover - interpreter shutdown
            pass

    @property
    def map_xy(self) -> np.ndarray | None:
        """``(r1 - r0, c1 - c0, 2)`` float32 source ``(x, y)`` of each ROI pixel (a copy when split)."""
        if self.map1 is None or self.map2 is None:
            return self.map1
        return np.stack([self.map1, self.map2], axis=2)

    @property
    def mask(self) -> np.ndarray:
        """``(H, W)`` bool: True where an output pixel centre lies in a destination triangle."""
        if self._mask is None:
            m = np.zeros(self.out_shape, dtype=bool)
            if self.map1 is not None:
                r0, r1, c0, c1 = self.roi
                if self._covered is not None:
                    m[r0:r1, c0:c1] = self._covered() if callable(self._covered) else self._covered
                else:
                    pattern = np.zeros(self._lens.size, dtype=bool)
                    pattern[1::2] = True
                    m[r0:r1, c0:c1] = np.repeat(pattern, self._lens).reshape(r1 - r0, c1 - c0)
            m.setflags(write=False)
            self._mask = m
        return self._mask

    def apply(self, image: Any, *, interpolation: str = "linear", fill: Any = 0.0) -> np.ndarray:
        """Warp ``image`` with these maps.

        Parameters
        ----------
        image : numpy.ndarray
            ``(h, w)`` or ``(h, w, C)`` of any numeric or bool dtype; float images
            may hold +-inf (see the module docstring), not NaN.
        interpolation : {"linear", "nearest"}
            Sampling of the source image.
        fill : float or sequence of float
            Value of uncovered pixels and of source positions outside ``image``;
            one number or one per channel.

        Returns
        -------
        numpy.ndarray
            ``out_shape`` (+ ``(C,)``), same dtype as ``image``.

        Raises
        ------
        ValidationError
            A NaN pixel (the count is named): it would spread silently.
        """
        img = as_image(image, "image", allow_nonfinite=True)
        if img.dtype.kind == "f":
            n_nan = int(np.count_nonzero(np.isnan(img)))
            if n_nan:
                raise ValidationError(expected_got("image", "no NaN pixels (+-inf is allowed: a depth "
                                                   "background)", f"{n_nan} NaN values"))
        flag = interp_flag(interpolation)
        c = 1 if img.ndim == 2 else img.shape[2]
        fills = _fill_values(fill, c, img.dtype)
        src = _to_cv(img)
        if src.dtype == np.uint8 and img.dtype == np.bool_:
            fills = tuple(255.0 * (v != 0) for v in fills)
        h, w = self.out_shape
        full_shape = (h, w) if img.ndim == 2 else (h, w, c)
        if self.map1 is None:
            out = np.empty(full_shape, dtype=src.dtype)
            out[...] = fills if c > 1 else fills[0]
            return _from_cv(out, img.dtype)
        res = _remap(src, self.map1, self.map2, flag, fills)
        if res.ndim == 2 and img.ndim == 3:
            res = res[:, :, None]
        # inf * 0 -> NaN guard: footprints touching a non-finite value go nearest.
        # Only a non-finite source can make one; check whichever array is
        # smaller (the source is also more likely cached than the fresh output).
        if (flag == cv2.INTER_LINEAR and src.dtype.kind == "f"
                and not np.isfinite(src if src.size <= res.size else res).all()):
            bad = ~np.isfinite(res)
            if bad.any():
                near = _remap(src, self.map1, self.map2, cv2.INTER_NEAREST, fills)
                if near.ndim == 2 and img.ndim == 3:
                    near = near[:, :, None]
                res = np.where(bad, near, res)
        r0, r1, c0, c1 = self.roi
        if (r0, r1, c0, c1) != (0, h, 0, w):
            out = np.empty(full_shape, dtype=res.dtype)
            out[...] = fills if c > 1 else fills[0]
            out[r0:r1, c0:c1] = res
            res = out
        return _from_cv(res, img.dtype)
