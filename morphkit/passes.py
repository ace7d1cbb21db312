"""The passes of one rendered view (colour, albedo, normals, depth, coverage) and the
pixel arithmetic that turns supersampled draws into them; numpy/OpenCV only.

Colour spaces and frames are stated in :mod:`morphkit.conventions` ("Colour"); the draws
themselves are :class:`morphkit.render.Renderer`'s.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from . import tol
from .camera import CameraModel

__all__ = ["RenderPasses", "supersampled_camera", "area_straight", "as_uint8", "decode_normals"]


@dataclass(frozen=True)
class RenderPasses:
    """The passes of one view, drawn by :meth:`Renderer.passes` or :meth:`Renderer.source_passes`.

    Colour spaces and frames: :mod:`morphkit.conventions` ("Colour").

    Parameters
    ----------
    color : (H, W, 3) uint8
        Lit colour.
    albedo : (H, W, 3) uint8
        Unlit base colour (factor x texture x vertex colour as stored), 0 where nothing is drawn.
    normal : (H, W, 3) float32
        World-frame unit normals of the side facing the camera, 0 where nothing is drawn.
    depth : (H, W) float32
        Linear depth, ``+inf`` where nothing is drawn.
    alpha : (H, W) float32
        Coverage in ``[0, 1]`` (0 or 1 from :meth:`Renderer.passes`).
    """

    color: np.ndarray
    albedo: np.ndarray
    normal: np.ndarray
    depth: np.ndarray
    alpha: np.ndarray


def supersampled_camera(camera: CameraModel, s: int) -> CameraModel:
    """``camera`` with ``s`` times the pixels per axis over the same image area.

    Parameters
    ----------
    camera : CameraModel
        The view.
    s : int
        Supersampling factor per axis.

    Returns
    -------
    CameraModel
        The same view and frustum with ``(H s, W s)`` pixels.
    """
    h, w = camera.shape
    return CameraModel(camera.projection, (h * s, w * s), camera.fx * s, camera.fy * s,
                       (camera.cx + 0.5) * s - 0.5, (camera.cy + 0.5) * s - 0.5,
                       camera.znear, camera.zfar, camera.cam2world)


def area_straight(img: np.ndarray, cov: np.ndarray, alpha: np.ndarray, shape: tuple[int, int]
                   ) -> np.ndarray:
    """Area-average ``img`` premultiplied by coverage ``cov`` down to ``shape`` and
    un-premultiply by the averaged coverage ``alpha`` (0 where ``alpha`` is 0).

    Parameters
    ----------
    img : (h, w, C) array
        Supersampled straight colour.
    cov : (h, w) float32
        Its coverage (0 or 1).
    alpha : (H, W) float32
        ``cov`` area-averaged down to ``shape``.
    shape : tuple of 2 int
        ``(H, W)``.

    Returns
    -------
    (H, W, C) float32
        Straight colour.
    """
    h, w = shape
    premul = img.astype(np.float32) * cov[..., None]
    out = cv2.resize(premul, (w, h), interpolation=cv2.INTER_AREA)
    return np.where(alpha[..., None] > 0, out / np.maximum(alpha[..., None], tol.ALPHA_FLOOR), 0.0)


def as_uint8(img: np.ndarray) -> np.ndarray:
    """``img`` rounded and clipped to uint8.

    Parameters
    ----------
    img : array
        Values on the 0-255 scale.

    Returns
    -------
    array of uint8
        Rounded to the nearest integer, clipped to ``[0, 255]``.
    """
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def decode_normals(encoded: np.ndarray, covered: np.ndarray) -> np.ndarray:
    """Unit normals from the normals draw's ``127 n + 128`` uint8 encoding; 0 where not ``covered``.

    Parameters
    ----------
    encoded : (H, W, 3) uint8
        The normals draw.
    covered : (H, W) bool
        Where something was drawn.

    Returns
    -------
    (H, W, 3) float32
        Unit normals, 0 where not covered.
    """
    n = encoded.astype(np.float32)
    n -= np.float32(128.0)  # 127 n: the scale goes with the normalisation
    norm2 = np.einsum("ijk,ijk->ij", n, n)
    with np.errstate(divide="ignore"):
        inv = np.where(covered & (norm2 > 0), 1.0 / np.sqrt(norm2), 0.0).astype(np.float32)
    n *= inv[..., None]
    return n
