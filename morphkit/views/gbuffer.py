"""What a relightable billboard image holds: albedo with coverage, normals and depth.

A :class:`ViewSurface` is one billboard image before shading (a small G-buffer):
premultiplied **linear** albedo and coverage alpha, unit normals in the asset's
object frame, and linear depth along the image's camera axis. Shading it with the
scene's lights (:func:`morphkit.imaging.shading.shade`) gives the premultiplied colour the
compositor draws; the same shading of a mesh's passes is the ground truth
(:mod:`morphkit.imaging.shading`), so billboards and meshes are lit by one model.

Storage (:func:`encode_surface`, :func:`decode_surface`): straight albedo sRGB-encoded
and alpha as uint8 RGBA (4 bytes), normals as int8 ``round(127 n)`` (3 bytes; at most
:data:`morphkit.conventions.NORMAL_ENCODING_DEG` off), depth as float16 (2 bytes,
``+inf`` where nothing is drawn): 9 bytes per pixel for every relightable asset kind
(:data:`BYTES_PER_PIXEL`), so assets compare at equal bytes by their pixel counts.
Colour spaces: :mod:`morphkit.conventions` ("Colour").
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .. import tol
from ..errors import ValidationError, expected_got
from ..meshes.parts import linear_to_srgb as linear_curve_to_srgb
from ..meshes.parts import srgb_to_linear as srgb_curve_to_linear

__all__ = ["ViewSurface", "StoredSurface", "encode_surface", "decode_surface", "BYTES_PER_PIXEL",
           "srgb_to_linear", "linear_to_srgb", "downsample_surface"]

#: Bytes per stored pixel of a relightable view: RGBA uint8, normal int8 x 3, depth float16.
BYTES_PER_PIXEL = 9


#: Entries of the encoding table of :func:`linear_to_srgb` (steps of 1/16383 in linear
#: light: at most 0.2/255 off the exact curve, where it is steepest, near black).
_ENCODE_STEPS = 16384
_DECODE_LUT = srgb_curve_to_linear(np.arange(256) / 255.0).astype(np.float32)
_ENCODE_LUT = linear_curve_to_srgb(np.arange(_ENCODE_STEPS) / (_ENCODE_STEPS - 1.0)).astype(np.float32)


def srgb_to_linear(img: np.ndarray) -> np.ndarray:
    """uint8 sRGB-encoded values to linear light in ``[0, 1]`` (the exact curve, by table).

    Parameters
    ----------
    img : array of uint8
        Encoded values.

    Returns
    -------
    array of float32
        Linear values, same shape.
    """
    return _DECODE_LUT[np.asarray(img, dtype=np.uint8)]


def linear_to_srgb(img: np.ndarray) -> np.ndarray:
    """Linear light (clipped to ``[0, 1]``) to sRGB-encoded values in ``[0, 1]`` (by table).

    Parameters
    ----------
    img : array of float
        Linear values.

    Returns
    -------
    array of float32
        Encoded values in ``[0, 1]``, same shape.
    """
    x = np.clip(np.asarray(img, dtype=np.float32), 0.0, 1.0) * np.float32(_ENCODE_STEPS - 1)
    return _ENCODE_LUT[(x + np.float32(0.5)).astype(np.int32)]


@dataclass(frozen=True, eq=False)
class ViewSurface:
    """One billboard image before shading.

    Parameters
    ----------
    albedo : (h, w, 4) float32
        Premultiplied linear albedo (RGB) and coverage alpha, in ``[0, 1]``.
    normal : (h, w, 3) float32
        Unit normals, object frame; 0 where alpha is 0.
    depth : (h, w) float32
        Linear depth along the image camera's axis; ``+inf`` where nothing is drawn.
    """

    albedo: np.ndarray
    normal: np.ndarray
    depth: np.ndarray

    def __post_init__(self) -> None:
        h, w = self.depth.shape[:2]
        if self.albedo.shape != (h, w, 4) or self.normal.shape != (h, w, 3) or self.depth.ndim != 2:
            raise ValidationError(expected_got(
                "ViewSurface", "albedo (h, w, 4), normal (h, w, 3), depth (h, w) of one size",
                f"{self.albedo.shape}, {self.normal.shape}, {self.depth.shape}"))

    @property
    def shape(self) -> tuple[int, int]:
        """``(h, w)``."""
        return int(self.depth.shape[0]), int(self.depth.shape[1])

    @property
    def alpha(self) -> np.ndarray:
        """``(h, w)`` coverage (a view of :attr:`albedo`)."""
        return self.albedo[..., 3]


@dataclass(frozen=True, eq=False)
class StoredSurface:
    """A :class:`ViewSurface` at storage precision (:func:`encode_surface`).

    Parameters
    ----------
    rgba : (h, w, 4) uint8
        Straight sRGB-encoded albedo and alpha.
    normal : (h, w, 3) int8
        ``round(127 n)``.
    depth : (h, w) float16
        Linear depth, ``+inf`` where nothing is drawn.
    """

    rgba: np.ndarray
    normal: np.ndarray
    depth: np.ndarray

    @property
    def nbytes(self) -> int:
        """Bytes of the three arrays."""
        return int(self.rgba.nbytes + self.normal.nbytes + self.depth.nbytes)


def encode_surface(rgba: np.ndarray, normal: np.ndarray, depth: np.ndarray) -> StoredSurface:
    """Pack a rendered view (straight uint8 RGBA albedo, float normals, float depth) for storage.

    Parameters
    ----------
    rgba : (h, w, 4) uint8
        Straight sRGB-encoded albedo and coverage alpha.
    normal : (h, w, 3) float
        Unit normals, object frame (0 where nothing is drawn).
    depth : (h, w) float
        Linear depth, ``+inf`` where nothing is drawn.

    Returns
    -------
    StoredSurface
        The packed view (:data:`BYTES_PER_PIXEL` bytes per pixel).

    Raises
    ------
    ValidationError
        Shapes or dtypes that do not match, NaN normals or depths.
    """
    rgba = np.asarray(rgba)
    h, w = rgba.shape[:2]
    if rgba.shape != (h, w, 4) or rgba.dtype != np.uint8:
        raise ValidationError(expected_got("rgba", "(h, w, 4) uint8", f"{rgba.dtype} {rgba.shape}"))
    n = np.asarray(normal, dtype=np.float32)
    d = np.asarray(depth, dtype=np.float32)
    if n.shape != (h, w, 3) or d.shape != (h, w):
        raise ValidationError(expected_got("normal, depth", f"({h}, {w}, 3), ({h}, {w})",
                                           f"{n.shape}, {d.shape}"))
    if np.isnan(n).any() or np.isnan(d).any() or (d <= 0).any():
        raise ValidationError(expected_got("normal, depth",
                                           "finite normals and positive depths (+inf: empty)",
                                           "NaN or non-positive values"))
    return StoredSurface(rgba.copy(), np.clip(np.rint(127.0 * n), -127, 127).astype(np.int8),
                         d.astype(np.float16))


def decode_surface(stored: StoredSurface) -> ViewSurface:
    """The working form of a stored view: premultiplied linear albedo, unit normals, float32 depth.

    Parameters
    ----------
    stored : StoredSurface
        As :func:`encode_surface` made it.

    Returns
    -------
    ViewSurface
        New arrays.
    """
    a = stored.rgba[..., 3:].astype(np.float32) * np.float32(1.0 / 255.0)
    albedo = np.empty(stored.rgba.shape, np.float32)
    albedo[..., :3] = srgb_to_linear(stored.rgba[..., :3]) * a
    albedo[..., 3:] = a
    n = stored.normal.astype(np.float32)
    norm = np.sqrt(np.einsum("ijk,ijk->ij", n, n))[..., None]
    n = np.where(norm > 0, n / np.maximum(norm, np.float32(tol.ALPHA_FLOOR)), np.float32(0.0))
    return ViewSurface(albedo, n.astype(np.float32), stored.depth.astype(np.float32))


def downsample_surface(surface: ViewSurface, shape: tuple[int, int]) -> ViewSurface:
    """``surface`` at a smaller ``shape``: albedo area-averaged (premultiplied), normals
    area-averaged and renormalised, depth the nearest drawn sample of each block
    (a min over the block, ``+inf`` where none is drawn).

    Parameters
    ----------
    surface : ViewSurface
        Full-size surface.
    shape : tuple of 2 int
        ``(h, w)``, at most the surface's.

    Returns
    -------
    ViewSurface
        New arrays of ``shape``.
    """
    h, w = shape
    if (h, w) == surface.shape:
        return surface
    albedo = cv2.resize(surface.albedo, (w, h), interpolation=cv2.INTER_AREA)
    n = cv2.resize(surface.normal, (w, h), interpolation=cv2.INTER_AREA)
    norm = np.sqrt(np.einsum("ijk,ijk->ij", n, n))[..., None]
    n = np.where(norm > 0, n / np.maximum(norm, np.float32(tol.ALPHA_FLOOR)), np.float32(0.0))
    d = surface.depth
    big = np.where(np.isfinite(d), d, np.float32(np.finfo(np.float32).max))
    small = -cv2.resize(-cv2.erode(big, np.ones((3, 3), np.uint8)), (w, h), interpolation=cv2.INTER_NEAREST)
    small = np.where(small >= np.finfo(np.float32).max, np.float32(np.inf), small)
    return ViewSurface(albedo.astype(np.float32), n.astype(np.float32), small.astype(np.float32))
