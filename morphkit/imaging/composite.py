"""Compositing: shadows into a rendered frame, and premultiplied-alpha "over".

Shadows
-------
A frame is rendered by :mod:`morphkit.render` as ``lit`` (ambient + the light) and
``unlit`` (ambient only), from one draw (:meth:`Renderer.frame_pass
<morphkit.render.Renderer.frame_pass>`) or two. A pixel that sees a fraction ``v`` of the
light is ``unlit + v (lit - unlit)``: ``v = 1`` is fully lit, ``v = 0`` is in
full shadow (only the ambient term is left), fractional ``v`` is a penumbra.
This is exact for one light and a shading model linear in the light's
intensity (pyrender's is). Visibility comes from a shadow map lookup or from
:mod:`morphkit.imaging.groundtruth`.

Premultiplied alpha
-------------------
:func:`to_premultiplied` turns grey/RGB/RGBA images of any dtype into float32
``(H, W, C + 1)`` arrays of colour times alpha (input units) and alpha in
``[0, 1]``; warps and blends of such arrays never bleed a transparent
pixel's colour into its neighbours. :func:`over` composites one premultiplied
image over another (Porter & Duff); :func:`from_premultiplied` goes back.
:func:`over_warped` warps a premultiplied image by a homography into a region
of interest of another and composites it "over" there (a billboard quad onto a
frame), touching only that region.
"""

from __future__ import annotations

import cv2
import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..settings import WARP_THREADS, compile_kernel, use_compiled
from ..validate import as_image
from ..warp import PARALLEL_MIN_PIXELS, band_pool

__all__ = ["shade", "to_premultiplied", "from_premultiplied", "over", "over_warped", "warped_part",
           "box_from", "fade_towards"]


def shade(lit: np.ndarray, unlit: np.ndarray, visibility: np.ndarray) -> np.ndarray:
    """Blend ``unlit`` and ``lit`` uint8 ``(H, W, 3)`` frames by ``visibility (H, W)`` in [0, 1].

    Parameters
    ----------
    lit : (H, W, 3) uint8
        The frame rendered with the light on.
    unlit : (H, W, 3) uint8
        The same frame with the light off (in shadow).
    visibility : (H, W) float
        Light visibility per pixel in ``[0, 1]`` (1 lit, 0 in shadow).

    Returns
    -------
    (H, W, 3) uint8
        ``unlit + visibility * (lit - unlit)``, rounded.
    """
    lit = as_image(lit, "lit", channels=(3,))
    unlit = as_image(unlit, "unlit", channels=(3,))
    vis = as_image(np.asarray(visibility, dtype=np.float32), "visibility", channels=(1,))
    if lit.shape != unlit.shape or vis.shape != lit.shape[:2]:
        raise ValidationError(expected_got("shade inputs", "lit, unlit (H, W, 3) and visibility (H, W)",
                                           f"{lit.shape}, {unlit.shape}, {vis.shape}"))
    if vis.min() < 0 or vis.max() > 1:
        raise ValidationError(expected_got("visibility", "values in [0, 1]",
                                           f"[{vis.min():g}, {vis.max():g}]"))
    if use_compiled(_shade_kernel) and lit.dtype == unlit.dtype == np.uint8:
        out = np.empty(lit.shape, np.uint8)
        args = (np.ascontiguousarray(lit), np.ascontiguousarray(unlit), np.ascontiguousarray(vis), out)
        h = lit.shape[0]
        n = WARP_THREADS if vis.size >= PARALLEL_MIN_PIXELS else 1  # bands of rows (nogil kernel)
        futures = [band_pool().submit(_shade_kernel, *args, h * b // n, h * (b + 1) // n)
                   for b in range(1, n)]
        _shade_kernel(*args, 0, h // n)
        for f in futures:
            f.result()
        return out
    return _shade_numpy(lit, unlit, vis)


def _shade_numpy(lit: np.ndarray, unlit: np.ndarray, vis: np.ndarray) -> np.ndarray:
    """The numpy reference of :func:`shade` (inputs validated)."""
    lo, hi = unlit.astype(np.float32), lit.astype(np.float32)
    out = lo + vis[..., None] * (hi - lo)
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)


def _shade_loop(lit: np.ndarray, unlit: np.ndarray, vis: np.ndarray, out: np.ndarray, r0: int, r1: int
                ) -> None:
    """:func:`_shade_numpy` per pixel of rows ``r0:r1``, uint8 in and out (the same float32 operations)."""
    w, c = lit.shape[1:]
    for r in range(r0, r1):
        for x in range(w):
            v = vis[r, x]
            if v == 1 or v == 0:  # the blend is exactly lit or unlit there (integers in float32)
                src = lit if v == 1 else unlit
                for k in range(c):
                    out[r, x, k] = src[r, x, k]
                continue
            for k in range(c):
                lo = np.float32(unlit[r, x, k])
                y = np.rint(lo + v * (np.float32(lit[r, x, k]) - lo))
                out[r, x, k] = np.uint8(min(max(y, np.float32(0.0)), np.float32(255.0)))


_shade_kernel = compile_kernel(_shade_loop)


def _alpha_max(dtype: np.dtype) -> float:
    if dtype.kind == "f":
        return 1.0
    if dtype.kind in "iu":
        return float(np.iinfo(dtype).max)
    return 1.0


def to_premultiplied(image: np.ndarray, channels: int) -> np.ndarray:
    """float32 ``(H, W, C + 1)``: colour times alpha (input units), then alpha in [0, 1].

    ``channels`` is the layout to promote to (1 grey, 3 RGB, 4 RGBA); grey/RGB
    get alpha 1. Colour values stay in the input's units (0..255 for uint8).

    Parameters
    ----------
    image : (H, W) or (H, W, C) uint8, integer or float
        Straight (not premultiplied) image, ``C`` in 1, 3 or 4 (alpha last, in ``[0, 1]`` for
        floats, ``[0, 255]`` for uint8).
    channels : int
        Colour layout to promote to: 1 grey, 3 RGB, 4 RGBA.

    Returns
    -------
    (H, W, C' + 1) float32
        Premultiplied colour in the input's units, then alpha in ``[0, 1]``
        (``C'`` is the input's colour count, 1 or 3; grey becomes 3 when
        ``channels >= 3``).

    Raises
    ------
    ValidationError
        Not an image of 1, 3 or 4 channels; ``channels`` not 1, 3 or 4; values beyond float32's
        range; an alpha outside its range.
    """
    img = as_image(image, "image", channels=(1, 3, 4))
    if channels not in (1, 3, 4):
        raise ValidationError(expected_got("channels", "1, 3 or 4", repr(channels)))
    amax = _alpha_max(img.dtype)
    with np.errstate(over="ignore"):
        x = img.astype(np.float32)
    if img.dtype.kind == "f" and not np.all(np.isfinite(x)):
        raise ValidationError(expected_got("image", "pixel values within float32's range",
                                           f"values up to {float(np.abs(img).max()):g}"))
    if x.ndim == 2:
        x = x[:, :, None]
    c = x.shape[2]
    if c == 4:
        color, alpha = x[:, :, :3], x[:, :, 3:] / np.float32(amax)
        if alpha.size and (float(alpha.min()) < 0.0 or float(alpha.max()) > 1.0):
            a = img[:, :, 3]
            raise ValidationError(expected_got("image alpha", f"values in [0, {amax:g}]",
                                               f"{float(a.min()):g} to {float(a.max()):g}"))
    else:
        color, alpha = x, np.ones(x.shape[:2] + (1,), np.float32)
    if channels >= 3 and color.shape[2] == 1:
        color = np.repeat(color, 3, axis=2)
    return np.ascontiguousarray(np.concatenate([color * alpha, alpha], axis=2))


def from_premultiplied(acc: np.ndarray, channels: int, dtype: np.dtype) -> np.ndarray:
    """Inverse of :func:`to_premultiplied`: straight colour (+ alpha for RGBA) in ``dtype``.

    Parameters
    ----------
    acc : (H, W, C + 1) float32
        Premultiplied image, alpha in ``[0, 1]`` last (as from :func:`to_premultiplied`).
    channels : int
        Layout to return: 1 grey ``(H, W)``, 3 colour ``(H, W, 3)``, 4 colour
        and alpha ``(H, W, 4)``.
    dtype : numpy.dtype
        Output dtype; alpha is scaled to its range (255 for uint8, 1 for floats).

    Returns
    -------
    (H, W) or (H, W, channels) array of ``dtype``
        Straight colour (and alpha for ``channels == 4``), rounded and saturated
        for integer dtypes.
    """
    acc = np.asarray(acc, dtype=np.float32)
    alpha = acc[:, :, -1:]
    amax = _alpha_max(dtype)
    # where alpha ~ 0 the premultiplied colour is ~0 too: dividing by a floor keeps it ~0
    out = acc / np.maximum(alpha, np.float32(tol.ALPHA_FLOOR))
    if channels == 4:
        np.multiply(alpha[:, :, 0], np.float32(amax), out=out[:, :, -1])
    elif channels == 1:
        out = out[:, :, 0]
    else:
        out = out[:, :, :-1]
    if dtype.kind == "f":
        return out.astype(dtype, copy=False)
    if dtype == np.uint8:
        return cv2.convertScaleAbs(out)  # rounds and saturates; values are >= 0 up to float noise
    info = np.iinfo(dtype)
    np.rint(out, out=out)
    return np.clip(out, info.min, info.max).astype(dtype)


def over(out: np.ndarray | None, part: np.ndarray, roi: tuple[int, int, int, int],
          shape: tuple[int, int]) -> np.ndarray:
    """Premultiplied ``part`` (rows ``r0:r1``, columns ``c0:c1`` of ``roi`` in an image of
    ``shape``) composited "over" ``out`` (None: nothing drawn yet; it is updated in place).

    Parameters
    ----------
    out : (H, W, C) float32 or None
        Premultiplied image, alpha last, updated in place; None when nothing is
        drawn yet.
    part : (r1 - r0, c1 - c0, C) float32
        Premultiplied image, alpha last, to draw over ``out``.
    roi : (r0, r1, c0, c1)
        Rows ``r0:r1`` and columns ``c0:c1`` of ``out`` that ``part`` covers.
    shape : (H, W)
        Size of the whole image (used when ``out`` is None).

    Returns
    -------
    (H, W, C) float32
        ``out`` (or a new image, or ``part`` itself when it covers all of
        ``shape`` and ``out`` is None).

    References
    ----------
    .. [1] T. Porter and T. Duff, "Compositing Digital Images", Computer Graphics (Proc. SIGGRAPH 84),
       18(3), pp. 253-259, 1984.

    Examples
    --------
    One red pixel with alpha 0.4 (102 / 255) over an opaque grey 2 x 2 image, at row 0,
    column 1: ``0.4 * 255 + 0.6 * 100 = 162`` in red, ``0.6 * 100 = 60`` in green and blue.

    >>> import numpy as np
    >>> from morphkit.imaging.composite import from_premultiplied, over, to_premultiplied
    >>> back = to_premultiplied(np.full((2, 2, 3), 100, np.uint8), 3)  # (2, 2, 4), alpha 1
    >>> red = to_premultiplied(np.array([[[255, 0, 0, 102]]], np.uint8), 4)
    >>> out = over(back, red, (0, 1, 1, 2), (2, 2))
    >>> from_premultiplied(out, 3, np.dtype(np.uint8))[0]
    array([[100, 100, 100],
           [162,  60,  60]], dtype=uint8)
    """
    _check_over(out, part, roi, shape)
    r_0, r_1, c_0, c_1 = roi
    if out is None:
        if roi == (0, shape[0], 0, shape[1]):
            return part
        out = np.zeros(shape + (part.shape[2],), np.float32)
        out[r_0:r_1, c_0:c_1] = part
        return out
    view = out[r_0:r_1, c_0:c_1]
    view *= 1.0 - part[:, :, -1:]
    view += part
    return out


def _check_over(out: np.ndarray | None, part: np.ndarray, roi: tuple[int, int, int, int],
                shape: tuple[int, int]) -> None:
    """:func:`over`'s arguments agree: ``part`` fills ``roi``, inside ``shape``, with ``out``'s channels."""
    if not (isinstance(part, np.ndarray) and part.ndim == 3 and part.dtype.kind == "f"
            and part.shape[2] >= 2):
        raise ValidationError(expected_got("part", "a float (h, w, C) premultiplied image, C >= 2",
                                           f"{getattr(part, 'dtype', type(part).__name__)} "
                                           f"{getattr(part, 'shape', '')}"))
    h, w = shape
    r_0, r_1, c_0, c_1 = roi
    if not (0 <= r_0 <= r_1 <= h and 0 <= c_0 <= c_1 <= w and part.shape[:2] == (r_1 - r_0, c_1 - c_0)):
        raise ValidationError(expected_got("roi", f"rows and columns inside {tuple(shape)} that part "
                                           f"{part.shape[:2]} fills", roi))
    if out is not None and not (isinstance(out, np.ndarray) and out.dtype.kind == "f"
                                and out.shape == (h, w, part.shape[2])):
        raise ValidationError(expected_got("out", f"None or a float {(h, w, part.shape[2])} image",
                                           f"{getattr(out, 'dtype', type(out).__name__)} "
                                           f"{getattr(out, 'shape', '')}"))


def fade_towards(rgb: np.ndarray, alpha: np.ndarray, fraction: np.ndarray | float,
                 color: tuple[float, float, float]) -> np.ndarray:
    """Blend premultiplied colour towards a straight ``color`` by ``fraction``, keeping its
    alpha, in place: ``rgb (1 - f) + alpha f color`` (distance fog), in the colour units of
    ``rgb`` (the caller's encoding; no conversion here).

    Parameters
    ----------
    rgb : (..., 3) float32
        Premultiplied colour; updated in place.
    alpha : (..., 1) float
        Its alpha (``1`` for an opaque colour).
    fraction : float or (..., 1) float
        How much of ``color`` per pixel, in ``[0, 1]``.
    color : (3,) float
        Straight colour faded towards.

    Returns
    -------
    (..., 3) float32
        ``rgb``.

    Examples
    --------
    >>> import numpy as np
    >>> from morphkit.imaging.composite import fade_towards
    >>> rgb, alpha = np.array([[0.5, 0.5, 0.5]], np.float32), np.array([[0.5]], np.float32)
    >>> fade_towards(rgb, alpha, 0.5, (1.0, 0.0, 0.0))
    array([[0.5 , 0.25, 0.25]], dtype=float32)
    """
    f = np.asarray(fraction, np.float32)
    rgb *= np.float32(1.0) - f
    rgb += np.asarray(alpha, np.float32) * (f * np.asarray(color, np.float32))
    return rgb


def over_warped(out: np.ndarray, src: np.ndarray, H_out_src: np.ndarray,
                roi: tuple[int, int, int, int], *, mask: np.ndarray | None = None,
                fade: float = 0.0, fade_color: tuple[float, float, float] = (0.0, 0.0, 0.0),
                interpolation: int = cv2.INTER_LINEAR) -> np.ndarray:
    """Warp premultiplied ``src`` by ``H_out_src`` and composite it "over" ``out`` inside ``roi``.

    Parameters
    ----------
    out : (H, W, C) float32
        Premultiplied image, alpha last; updated in place (only rows ``r0:r1``,
        columns ``c0:c1``).
    src : (h, w, C) float32
        Premultiplied image, alpha last, same ``C`` (``C <= 4``).
    H_out_src : (3, 3) float
        Homography from ``src`` pixels to ``out`` pixels (pixel-centre convention
        of :mod:`morphkit.conventions`).
    roi : (r0, r1, c0, c1)
        The region of ``out`` to draw into (where the warped ``src`` lands).
    mask : (r1 - r0, c1 - c0) float32, optional
        Coverage in ``[0, 1]`` multiplied into the warped image (e.g. a polygon
        clipped at a camera's near plane).
    fade : float
        Blend the warped colour towards ``fade_color`` (straight RGB in the colour
        units of ``out``) by this fraction, keeping its alpha (distance fog).
    fade_color : (3,) float
        Straight colour the warped image fades towards (used when ``fade > 0``).
    interpolation : int
        OpenCV interpolation flag (bilinear by default).

    Returns
    -------
    (H, W, C) float32
        ``out``.
    """
    r0, r1, c0, c1 = roi
    part = warped_part(src, H_out_src, roi, mask=mask, fade=fade, fade_color=fade_color,
                       interpolation=interpolation)
    view = out[r0:r1, c0:c1]
    view *= 1.0 - part[:, :, -1:]
    view += part
    return out


def warped_part(src: np.ndarray, H_out_src: np.ndarray, roi: tuple[int, int, int, int], *,
                mask: np.ndarray | None = None, fade: float = 0.0,
                fade_color: tuple[float, float, float] = (0.0, 0.0, 0.0),
                interpolation: int = cv2.INTER_LINEAR) -> np.ndarray:
    """The part of :func:`over_warped` before the composite: premultiplied ``src`` warped by
    ``H_out_src`` into the box ``roi`` of the output, masked and faded.

    Parameters
    ----------
    src : (h, w, C) float32
        Premultiplied image, alpha last.
    H_out_src : (3, 3) float
        Homography from ``src`` pixels to output pixels (:mod:`morphkit.conventions`).
    roi : (r0, r1, c0, c1)
        The output box.
    mask, fade, fade_color, interpolation
        As for :func:`over_warped`.

    Returns
    -------
    (r1 - r0, c1 - c0, C) float32
        The warped image in the box's pixels.
    """
    r0, r1, c0, c1 = roi
    part = cv2.warpPerspective(src, box_from(roi) @ np.asarray(H_out_src, dtype=np.float64),
                               (c1 - c0, r1 - r0), flags=interpolation, borderMode=cv2.BORDER_CONSTANT,
                               borderValue=0)
    if part.ndim == 2:
        part = part[:, :, None]
    if mask is not None:
        part *= mask[:, :, None]
    if fade > 0.0:
        fade_towards(part[:, :, :-1], part[:, :, -1:], fade, fade_color)
    return part


def box_from(roi: tuple[int, int, int, int]) -> np.ndarray:
    """``(3, 3)`` translation from output pixels to the pixels of its box ``roi = (r0, r1, c0, c1)``
    (the box's top-left pixel is ``(0, 0)``).

    Parameters
    ----------
    roi : (r0, r1, c0, c1)
        The box: rows ``r0:r1``, columns ``c0:c1``.

    Returns
    -------
    (3, 3) float64
        ``[[1, 0, -c0], [0, 1, -r0], [0, 0, 1]]``.
    """
    r0, _, c0, _ = roi
    return np.array([[1.0, 0.0, -c0], [0.0, 1.0, -r0], [0.0, 0.0, 1.0]])
