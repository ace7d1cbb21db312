"""Image and shadow error metrics, each optionally restricted to a boolean mask.

Conventions shared by every metric here:

* ``a``/``b`` (or ``pred``/``truth``) must have the same shape, be non-empty
  and finite; they are compared as float64.
* ``mask`` is ``None`` (every element counts) or a boolean array of the
  inputs' shape; for a multi-channel image ``(H, W, C)`` a per-pixel mask of
  shape ``(H, W)`` is also accepted and applies to every channel. A mask
  without a single ``True`` element is refused (there is nothing to average).
* Errors are :class:`~morphkit.errors.ValidationError` with an
  expected-vs-got message.

Images follow :mod:`morphkit.conventions` (``(H, W)`` or ``(H, W, C)``).
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from ..errors import ValidationError, expected_got
from ..validate import as_array, as_bool_array, as_positive

__all__ = [
    "shadow_iou",
    "mean_abs_error",
    "rmse",
    "psnr",
    "ssim",
    "SSIM_SIGMA",
    "SSIM_WINDOW",
]

#: Standard deviation (pixels) of SSIM's Gaussian window (Wang et al. 2004).
SSIM_SIGMA = 1.5
#: Side (pixels) of SSIM's Gaussian window: radius ``int(3.5 * 1.5 + 0.5) = 5``,
#: as in scikit-image's ``structural_similarity(gaussian_weights=True)``.
SSIM_WINDOW = 11
_SSIM_K1 = 0.01
_SSIM_K2 = 0.03


def _pair(a: Any, b: Any, names: tuple[str, str] = ("a", "b")) -> tuple[np.ndarray, np.ndarray]:
    """Validate two arrays of equal shape and return them as float64."""
    a = as_array(a, names[0])
    b = as_array(b, names[1])
    if a.shape != b.shape:
        raise ValidationError(
            expected_got(f"{names[1]} shape", f"the shape of {names[0]} {a.shape}", f"{b.shape}")
        )
    return a.astype(np.float64), b.astype(np.float64)


def _mask(mask: Any, shape: tuple[int, ...]) -> np.ndarray | None:
    """Validate ``mask`` for inputs of ``shape``; return it broadcast to ``shape``."""
    if mask is None:
        return None
    as_bool_array(mask, "mask")
    if mask.shape == shape:
        out = mask
    elif len(shape) == 3 and mask.shape == shape[:2]:
        out = np.broadcast_to(mask[..., None], shape)
    else:
        want = f"{shape}" + (f" or {shape[:2]}" if len(shape) == 3 else "")
        raise ValidationError(expected_got("mask shape", want, f"{mask.shape}"))
    if not out.any():
        raise ValidationError(expected_got("mask", "a mask with at least one True pixel", "no True pixel"))
    return out


def _masked_mean(values: np.ndarray, mask: np.ndarray | None) -> float:
    m = float(values.mean() if mask is None else values[mask].mean())
    return _finite(m)


def _finite(v: float) -> float:
    """``v``, or a ValidationError when finite inputs overflowed float64 on the way (values near
    1e154 squared, 1e308 subtracted): a metric is never inf or NaN from finite inputs."""
    if not np.isfinite(v):
        raise ValidationError(expected_got("a, b", "values whose differences and squares fit in float64",
                                           f"an overflow to {v}"))
    return v


def shadow_iou(pred: Any, truth: Any, mask: Any = None) -> float:
    """Intersection over union of two boolean shadow masks.

    ``IoU = |pred & truth| / |pred | truth|``, counted over the pixels where
    ``mask`` is True (all pixels if ``mask`` is None).

    Parameters
    ----------
    pred, truth : numpy.ndarray of bool
        Shadow masks of equal shape (True = in shadow).
    mask : numpy.ndarray of bool, optional
        Region to compare (e.g. the visible ground), same shape.

    Returns
    -------
    float
        IoU in ``[0, 1]``; 1 is a perfect match. When neither mask has a
        shadow pixel in the region (empty union) the masks agree and the
        result is **1.0**.

    Raises
    ------
    ValidationError
        If the inputs are not boolean arrays of equal, non-empty shape, or the
        mask has the wrong shape or no True pixel.

    Examples
    --------
    Two shadows of 3 pixels overlapping in 2: ``IoU = 2 / 4``.

    >>> import numpy as np
    >>> from morphkit.imaging.metrics import shadow_iou
    >>> pred = np.array([True, True, True, False, False])
    >>> truth = np.array([False, True, True, True, False])
    >>> shadow_iou(pred, truth)
    0.5
    """
    as_bool_array(pred, "pred")
    as_bool_array(truth, "truth")
    _pair(pred, truth, ("pred", "truth"))
    m = _mask(mask, pred.shape)
    inter = pred & truth
    union = pred | truth
    if m is not None:
        inter, union = inter[m], union[m]
    n_union = int(np.count_nonzero(union))
    if n_union == 0:
        return 1.0
    return int(np.count_nonzero(inter)) / n_union


def mean_abs_error(a: Any, b: Any, mask: Any = None) -> float:
    """Mean absolute difference ``mean(|a - b|)`` over the mask.

    Suited to quantities with a fixed scale such as visibility fractions in
    ``[0, 1]`` (the result is then in ``[0, 1]`` too).

    Parameters
    ----------
    a, b : numpy.ndarray
        Arrays of equal shape (any number of dimensions), finite.
    mask : numpy.ndarray of bool, optional
        Elements to average over (see the module notes for the shapes).

    Returns
    -------
    float
        ``>= 0``, in the units of the inputs; 0 for identical inputs.

    Raises
    ------
    ValidationError
        On mismatched, empty or non-finite inputs (or so large that their
        differences overflow) or a bad/empty mask.
    """
    x, y = _pair(a, b)
    return _masked_mean(np.abs(x - y), _mask(mask, x.shape))


def rmse(a: Any, b: Any, mask: Any = None) -> float:
    """Root-mean-square difference ``sqrt(mean((a - b)^2))`` over the mask.

    Parameters
    ----------
    a, b : numpy.ndarray
        Arrays of equal shape (any number of dimensions), finite.
    mask : numpy.ndarray of bool, optional
        Elements to average over (see the module notes for the shapes).

    Returns
    -------
    float
        ``>= 0``, in the units of the inputs; 0 for identical inputs. Always
        ``>= mean_abs_error(a, b, mask)``.

    Raises
    ------
    ValidationError
        On mismatched, empty or non-finite inputs (or so large that their
        differences overflow) or a bad/empty mask.
    """
    x, y = _pair(a, b)
    return float(np.sqrt(_masked_mean((x - y) ** 2, _mask(mask, x.shape))))


def psnr(a: Any, b: Any, *, data_range: float, mask: Any = None) -> float:
    """Peak signal-to-noise ratio ``10 log10(data_range^2 / MSE)`` in decibels.

    ``MSE`` is the mean squared difference over the mask.

    Parameters
    ----------
    a, b : numpy.ndarray
        Arrays of equal shape, finite.
    data_range : float
        Span of possible values (1.0 for images in ``[0, 1]``, 255 for 8-bit).
    mask : numpy.ndarray of bool, optional
        Elements to average over (see the module notes for the shapes).

    Returns
    -------
    float
        PSNR in dB, higher is better; ``inf`` when the inputs are identical
        over the mask (``MSE = 0``). Can be negative if errors exceed the range.

    Raises
    ------
    ValidationError
        On mismatched, empty or non-finite inputs, a non-positive
        ``data_range`` or a bad/empty mask.

    Examples
    --------
    An 8-bit image off by 1 everywhere has ``MSE = 1``: ``10 log10(255^2)``
    dB; a mask can leave the differing pixels out.

    >>> import numpy as np
    >>> from morphkit.imaging.metrics import psnr
    >>> a = np.zeros((4, 4))
    >>> round(psnr(a, a + 1, data_range=255), 4)
    48.1308
    >>> b = a.copy()
    >>> b[0] = 10
    >>> psnr(a, b, data_range=255, mask=np.arange(16).reshape(4, 4) >= 4)
    inf
    """
    rng = as_positive(data_range, "data_range")
    x, y = _pair(a, b)
    mse = _masked_mean((x - y) ** 2, _mask(mask, x.shape))
    if mse == 0.0:
        return float("inf")
    return float(10.0 * np.log10(rng * rng / mse))


def _blur(img: np.ndarray) -> np.ndarray:
    # BORDER_REFLECT (fedcba|abcdef) is scipy.ndimage's mode="reflect", used by scikit-image.
    return cv2.GaussianBlur(
        img, (SSIM_WINDOW, SSIM_WINDOW), SSIM_SIGMA, sigmaY=SSIM_SIGMA, borderType=cv2.BORDER_REFLECT
    )


def _ssim_map(x: np.ndarray, y: np.ndarray, data_range: float) -> np.ndarray:
    """Per-pixel SSIM of two float64 ``(H, W)`` images."""
    c1 = (_SSIM_K1 * data_range) ** 2
    c2 = (_SSIM_K2 * data_range) ** 2
    ux, uy = _blur(x), _blur(y)
    vx = _blur(x * x) - ux * ux
    vy = _blur(y * y) - uy * uy
    vxy = _blur(x * y) - ux * uy
    num = (2.0 * ux * uy + c1) * (2.0 * vxy + c2)
    den = (ux * ux + uy * uy + c1) * (vx + vy + c2)
    return num / den


def ssim(a: Any, b: Any, *, data_range: float, mask: Any = None) -> float:
    """Mean structural similarity (Wang et al. 2004) of two images.

    The SSIM map is ``((2 mu_a mu_b + C1)(2 s_ab + C2)) / ((mu_a^2 + mu_b^2 + C1)
    (s_a^2 + s_b^2 + C2))`` with ``C1 = (0.01 L)^2``, ``C2 = (0.03 L)^2``,
    ``L = data_range``, and local means, variances and covariance weighted by
    an 11 x 11 Gaussian window of sigma 1.5 (truncated at 3.5 sigma, borders
    reflected; population, not sample, covariance). The result is the mean of
    the map over the pixels at least 5 pixels (the window radius) from the
    image border, as scikit-image does to avoid edge effects: it matches
    ``skimage.metrics.structural_similarity(a, b, gaussian_weights=True,
    sigma=1.5, use_sample_covariance=False, data_range=L)`` (and
    ``channel_axis=-1`` for colour). For a multi-channel image the map is
    computed per channel and averaged over channels.

    With a ``mask``, the mean is taken over the mask's pixels inside that
    interior (an all-True mask gives the unmasked value); a full-shape
    ``(H, W, C)`` mask pools the masked entries of all channels.

    Parameters
    ----------
    a, b : numpy.ndarray
        Images ``(H, W)`` or ``(H, W, C)`` of equal shape, finite, with
        ``H, W >= 11``.
    data_range : float
        Span of possible values (1.0 for images in ``[0, 1]``, 255 for 8-bit).
    mask : numpy.ndarray of bool, optional
        Pixels to average over, ``(H, W)`` or the image's shape.

    Returns
    -------
    float
        SSIM in ``[-1, 1]``; 1 for identical images.

    Raises
    ------
    ValidationError
        On mismatched, empty, too small or non-finite images, a non-positive
        ``data_range``, or a mask of the wrong shape or without a True pixel
        in the interior.

    References
    ----------
    .. [1] Z. Wang, A. C. Bovik, H. R. Sheikh and E. P. Simoncelli, "Image Quality Assessment: From
       Error Visibility to Structural Similarity", IEEE Trans. Image Processing, 13(4), pp. 600-612,
       2004.
    """
    rng = as_positive(data_range, "data_range")
    x, y = _pair(a, b)
    if x.ndim not in (2, 3):
        raise ValidationError(expected_got("a", "an (H, W) or (H, W, C) image", f"shape {x.shape}"))
    if min(x.shape[:2]) < SSIM_WINDOW:
        raise ValidationError(
            expected_got("image size", f"H and W >= {SSIM_WINDOW} (the SSIM window)", f"{x.shape[:2]}")
        )
    m = _mask(mask, x.shape)
    if x.ndim == 2:
        smap = _ssim_map(x, y, rng)
    else:
        smap = np.stack(
            [_ssim_map(np.ascontiguousarray(x[..., c]), np.ascontiguousarray(y[..., c]), rng)
             for c in range(x.shape[2])],
            axis=-1,
        )
    pad = (SSIM_WINDOW - 1) // 2
    interior = np.zeros(x.shape, dtype=bool)
    interior[pad:-pad, pad:-pad] = True
    if m is not None:
        interior &= m
        if not interior.any():
            raise ValidationError(
                expected_got(
                    "mask",
                    f"a mask with at least one True pixel at least {pad} pixels from the border",
                    "none",
                )
            )
    return _finite(float(smap[interior].mean()))
