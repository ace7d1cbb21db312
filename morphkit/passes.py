"""The passes of one rendered view (colour, albedo, normals, depth, coverage; lit and unlit)
and the pixel arithmetic that turns pyrender's depth and supersampled draws into them;
numpy/OpenCV only.

Colour spaces and frames are stated in :mod:`morphkit.conventions` ("Colour"); the draws
themselves are :class:`morphkit.render.Renderer`'s.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from . import tol
from .camera import CameraModel
from .conventions import BACKGROUND_DEPTH

__all__ = ["RenderPasses", "FramePass", "supersampled_camera", "area_straight", "area_passes", "area_rgba",
           "as_uint8", "decode_normals", "linear_depth"]


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


@dataclass(frozen=True)
class FramePass:
    """A view lit and unlit from one draw (:meth:`Renderer.frame_pass
    <morphkit.render.Renderer.frame_pass>`): what a shadowed frame blends.

    Parameters
    ----------
    lit : (H, W, 3) uint8
        Colour with the lights on (:meth:`Renderer.color_depth <morphkit.render.Renderer.color_depth>`'s).
    unlit : (H, W, 3) uint8
        The same colour with the lights off (ambient, occlusion and emission only).
    depth : (H, W) float32
        Linear depth, ``+inf`` where nothing is drawn.
    marked : (H, W) bool
        Pixels whose visible surface belongs to one of the items the draw was asked to mark.
    """

    lit: np.ndarray
    unlit: np.ndarray
    depth: np.ndarray
    marked: np.ndarray


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


def area_passes(big: RenderPasses, shape: tuple[int, int]) -> RenderPasses:
    """Passes drawn at an integer multiple of ``shape`` area-averaged down to it: ``alpha`` is
    pixel coverage, colour and albedo straight alpha, normals the renormalised mean over the
    covered samples, depth the nearest covered sample's (``+inf`` where none is covered).

    Parameters
    ----------
    big : RenderPasses
        Passes of ``(H s, W s)`` pixels (:func:`supersampled_camera`), ``alpha`` 0 or 1.
    shape : tuple of 2 int
        ``(H, W)``.

    Returns
    -------
    RenderPasses
        The passes at ``shape``.
    """
    h, w = shape
    s = big.depth.shape[0] // h
    cov = big.alpha
    alpha = cv2.resize(cov, (w, h), interpolation=cv2.INTER_AREA)
    color = as_uint8(area_straight(big.color, cov, alpha, (h, w)))
    albedo = as_uint8(area_straight(big.albedo, cov, alpha, (h, w)))
    n = cv2.resize(big.normal, (w, h), interpolation=cv2.INTER_AREA)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where((alpha[..., None] > 0) & (norm > 0), n / np.maximum(norm, tol.ALPHA_FLOOR), 0.0)
    depth = big.depth.reshape(h, s, w, s).min(axis=(1, 3))
    return RenderPasses(color, albedo, n.astype(np.float32), depth, alpha.astype(np.float32))


def area_rgba(color: np.ndarray, depth: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """A colour draw at an integer multiple of ``shape`` area-averaged down to straight-alpha
    RGBA, alpha the pixel coverage (the drawn samples, finite ``depth``).

    Parameters
    ----------
    color : (H s, W s, 3) uint8
        Supersampled colour.
    depth : (H s, W s) float32
        Its depth, ``+inf`` where nothing is drawn.
    shape : tuple of 2 int
        ``(H, W)``.

    Returns
    -------
    (H, W, 4) uint8
        Straight-alpha RGBA.
    """
    h, w = shape
    cov = np.isfinite(depth).astype(np.float32)
    alpha = cv2.resize(cov, (w, h), interpolation=cv2.INTER_AREA)
    out = np.empty((h, w, 4), np.uint8)
    out[..., :3] = as_uint8(area_straight(color, cov, alpha, (h, w)))
    out[..., 3] = as_uint8(alpha * 255)
    return out


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


def linear_depth(raw: np.ndarray, camera: CameraModel) -> np.ndarray:
    """pyrender's depth image of ``camera`` as linear depth, ``+inf`` where nothing was drawn.

    pyrender 0.1.45 (and its fork pyrender2) converts the depth buffer to linear depth with
    the *perspective* formula ``d = 2 n f / (f + n - z_ndc (f - n))`` for every camera, which
    is wrong for orthographic cameras (a plane at distance 0.5 with ``n = 0.05, f = 100``
    comes back as 0.0502). For orthographic views pyrender's formula is inverted back to NDC
    depth and the orthographic one applied, ``Z = (f + n + z_ndc (f - n)) / 2``, which
    simplifies to ``Z = f + n - n f / d``. Perspective depth is pyrender's value unchanged.

    Parameters
    ----------
    raw : (H, W) float
        pyrender's depth output, 0 where nothing was drawn.
    camera : CameraModel
        The view it was drawn from.

    Returns
    -------
    (H, W) float32
        Linear depth along the viewing axis, :data:`~morphkit.conventions.BACKGROUND_DEPTH`
        where nothing was drawn.
    """
    d = np.asarray(raw, dtype=np.float64)
    bg = d <= 0.0  # pyrender writes 0 where nothing was drawn
    if camera.projection == "orthographic":
        n, f = camera.znear, camera.zfar
        with np.errstate(divide="ignore"):
            d = f + n - n * f / np.where(bg, 1.0, d)
    out = d.astype(np.float32)
    out[bg] = BACKGROUND_DEPTH
    return out
