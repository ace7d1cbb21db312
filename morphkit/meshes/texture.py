"""Texture images as the renderer uploads them: RGBA uint8, checked for size.

A texture arrives as a PIL image (trimesh's materials hold them) or a numpy
array, in any of the layouts image files come in; :func:`texture_rgba` turns it
into one layout, ``(H, W, 4)`` uint8 with straight alpha, the texels unchanged
in value apart from the bit depth:

* greyscale (``L``, ``1``, 2-D arrays) repeats the grey into R, G, B; grey +
  alpha (``LA``, ``(H, W, 2)``) keeps its alpha;
* 16-bit (``I;16``, ``I``, uint16 arrays) is rounded to 8 bits (``v / 257``);
  float (``F``, float arrays) is taken as ``[0, 1]`` and rounded (``255 v``);
* palette (``P``, ``PA``), ``CMYK``, ``YCbCr`` are converted by PIL to RGBA;
* RGB gets alpha 255.

Always four channels: rows of a ``W x 4``-byte image are 4-byte aligned at any
width, so a non-power-of-two width uploads correctly under OpenGL's default
``GL_UNPACK_ALIGNMENT`` of 4 (an RGB texture of width 3 would not). Colour
values are left as stored (sRGB, see :mod:`morphkit.conventions`).

Textures larger than :data:`morphkit.tol.MAX_TEXTURE_PIXELS` or wider/taller than
:data:`morphkit.tol.MAX_TEXTURE_SIDE` are refused before any conversion.

An image file's bytes are checked by :func:`image_problem` before a mesh loader takes them: PIL
opens an image lazily, so a file that is not an image is dropped by trimesh without a word and
a damaged one fails only when its texels are first read, far from the file.
"""

from __future__ import annotations

import io
import warnings
from typing import Any

import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got

__all__ = ["texture_rgba", "texture_shape", "image_problem"]

#: PIL modes read as unsigned 16-bit values (PNG 16-bit greyscale opens as ``I;16`` or ``I``).
_PIL_16BIT = ("I;16", "I;16B", "I;16L", "I;16N", "I")


def _is_pil(image: Any) -> bool:
    return hasattr(image, "mode") and hasattr(image, "size") and hasattr(image, "convert")


def texture_shape(image: Any, name: str = "texture") -> tuple[int, int]:
    """``(H, W)`` of a texture (PIL image or array), refused when empty or over the limits.

    Parameters
    ----------
    image : PIL.Image.Image or numpy.ndarray
        The texture.
    name : str, optional
        What to call it in error messages.

    Returns
    -------
    (int, int)
        Height and width in texels.

    Raises
    ------
    ValidationError
        Not an image, an empty image, or one over :data:`morphkit.tol.MAX_TEXTURE_PIXELS`
        texels or :data:`morphkit.tol.MAX_TEXTURE_SIDE` on a side.
    """
    if _is_pil(image):
        w, h = (int(v) for v in image.size)
    elif isinstance(image, np.ndarray):
        if image.ndim not in (2, 3):
            raise ValidationError(expected_got(name, "an (H, W) or (H, W, C) image", f"shape {image.shape}"))
        h, w = int(image.shape[0]), int(image.shape[1])
    else:
        raise ValidationError(expected_got(name, "a PIL image or a numpy array", type(image).__name__))
    if h < 1 or w < 1:
        raise ValidationError(expected_got(name, "at least one texel", f"{h} x {w}"))
    if h * w > tol.MAX_TEXTURE_PIXELS or max(h, w) > tol.MAX_TEXTURE_SIDE:
        raise ValidationError(expected_got(
            name, f"at most {tol.MAX_TEXTURE_PIXELS} texels (morphkit.tol.MAX_TEXTURE_PIXELS) and "
                  f"{tol.MAX_TEXTURE_SIDE} on a side (morphkit.tol.MAX_TEXTURE_SIDE); downscale it",
            f"{w} x {h} texels"))
    return h, w


def image_problem(data: bytes) -> str | None:
    """Why the bytes of an image file cannot be drawn as a texture, or None when they decode.

    The image is decoded whole (every texel read), so that a damaged file (truncated, a
    broken chunk) is found here and not when it is first drawn. An image over the texture
    limits is not decoded: :func:`texture_shape` refuses it, naming the limits, when it is
    drawn.

    Parameters
    ----------
    data : bytes
        The file's content.

    Returns
    -------
    str or None
        The reason as a phrase (``"is empty"``, ``"is not an image morphkit can decode
        ..."``, ``"is damaged (...)"``), or None for an image that decodes.
    """
    from PIL import Image, UnidentifiedImageError

    if not data:
        return "is empty"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # sizes: texture_shape's
            with Image.open(io.BytesIO(data)) as img:
                w, h = (int(v) for v in img.size)
                if w * h > tol.MAX_TEXTURE_PIXELS or max(w, h) > tol.MAX_TEXTURE_SIDE:
                    return None
                img.load()
    except UnidentifiedImageError:
        return "is not an image morphkit can decode (PNG, JPEG, or another format Pillow reads)"
    except Image.DecompressionBombError as exc:
        return f"is too large to decode ({exc})"
    except Exception as exc:  # Pillow's decoders raise many types for damaged data
        return " ".join(f"is damaged ({type(exc).__name__}: {exc})".split())[:200]
    return None


def _to_uint8(a: np.ndarray, name: str) -> np.ndarray:
    if a.dtype == np.uint8:
        return a
    if a.dtype == np.bool_:
        return a.astype(np.uint8) * 255
    if a.dtype == np.uint16:
        return np.rint(a.astype(np.float32) / 257.0).astype(np.uint8)
    if np.issubdtype(a.dtype, np.floating):
        if not np.all(np.isfinite(a)):
            raise ValidationError(expected_got(name, "finite texel values", "NaN or inf"))
        return np.rint(np.clip(a.astype(np.float64), 0.0, 1.0) * 255.0).astype(np.uint8)
    raise ValidationError(expected_got(name, "uint8, uint16, bool or float [0, 1] texels",
                                       f"dtype {a.dtype}"))


def _pil_array(image: Any) -> np.ndarray:
    mode = image.mode
    if mode in ("RGB", "RGBA", "L", "LA"):
        return np.asarray(image)
    if mode == "1":
        return np.asarray(image.convert("L"))
    if mode in _PIL_16BIT:
        a = np.asarray(image).astype(np.int64)
        return np.clip(a, 0, 65535).astype(np.uint16)
    if mode == "F":
        return np.asarray(image, dtype=np.float32)
    return np.asarray(image.convert("RGBA"))  # P, PA, CMYK, YCbCr, RGBX, ...


def texture_rgba(image: Any, name: str = "texture") -> np.ndarray:
    """The texture as ``(H, W, 4)`` uint8 straight-alpha RGBA (see the module notes).

    Parameters
    ----------
    image : PIL.Image.Image or numpy.ndarray
        The texture: a PIL image of any mode, or an array ``(H, W)``, ``(H, W, 1)``,
        ``(H, W, 2)`` (grey, alpha), ``(H, W, 3)`` or ``(H, W, 4)`` of uint8, uint16,
        bool or float in ``[0, 1]``.
    name : str, optional
        What to call it in error messages.

    Returns
    -------
    (H, W, 4) uint8
        C-contiguous RGBA, a new array (the input is not modified).

    Raises
    ------
    ValidationError
        Over the size limits (checked first, see :func:`texture_shape`), an unknown
        layout or dtype, or non-finite float texels.

    Examples
    --------
    >>> import numpy as np
    >>> texture_rgba(np.array([[0, 65535]], np.uint16))[0].tolist()
    [[0, 0, 0, 255], [255, 255, 255, 255]]
    """
    h, w = texture_shape(image, name)
    a = _pil_array(image) if _is_pil(image) else np.asarray(image)
    a = _to_uint8(a, name)
    if a.ndim == 2:
        a = a[..., None]
    c = a.shape[2]
    out = np.empty((h, w, 4), np.uint8)
    if c == 1:
        out[..., :3] = a
        out[..., 3] = 255
    elif c == 2:
        out[..., :3] = a[..., :1]
        out[..., 3] = a[..., 1]
    elif c == 3:
        out[..., :3] = a
        out[..., 3] = 255
    elif c == 4:
        out[...] = a
    else:
        raise ValidationError(expected_got(name, "1 to 4 channels", f"{c} channels"))
    return out
