"""Scenes whose every pixel has a derivable value: the renderer's texture fidelity.

Used by the tests and by ``morphkit bench render``. One square, the quad
``[-h, h]^2`` in the plane ``z = 0`` facing ``+z``, with UV coordinates
``u = (x + h) / 2h``, ``v = (y + h) / 2h`` (trimesh's UV convention: ``v = 0``
is the image's bottom row), seen head-on by :func:`head_on_camera`:

* **textured** (:func:`textured_quad`): the truth at a pixel is the texture
  sampled at the UV where the pixel centre's ray meets the quad, bilinearly
  between texel centres with wrap-around (:func:`sample_texture`): OpenGL's
  ``GL_LINEAR`` magnification with ``REPEAT`` wrapping, glTF's default sampler.
  The texel ``image[r, c]`` is centred at ``u = (c + 0.5) / W``,
  ``v = 1 - (r + 0.5) / H``.
* **gradient** (:func:`gradient_quad`): vertex colours that are an affine
  function of position, ``(R, G, B) = 255 (u, v, 1 - u)``, so the colour
  interpolated across each triangle is that function at every point
  (:func:`gradient_truth`).
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel, look_at, perspective
from ..errors import ValidationError, expected_got
from ..validate import as_positive

__all__ = ["quad", "textured_quad", "gradient_quad", "head_on_camera", "quad_uv", "sample_texture",
           "gradient_truth"]


def quad(half_size: float = 1.0) -> trimesh.Trimesh:
    """The square ``[-h, h]^2`` in ``z = 0``, facing ``+z``, two triangles, no visuals.

    Parameters
    ----------
    half_size : float, optional
        ``h``, scene units.

    Returns
    -------
    trimesh.Trimesh
        Four vertices in the order ``(-h, -h), (h, -h), (h, h), (-h, h)``.
    """
    h = as_positive(half_size, "half_size")
    return trimesh.Trimesh([[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]], [[0, 1, 2], [0, 2, 3]],
                           process=False)


#: UV of :func:`quad`'s four vertices.
_QUAD_UV = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def textured_quad(image: Any, half_size: float = 1.0, *, alpha_mode: str | None = None,
                  alpha_cutoff: float | None = None,
                  base_color: tuple[float, float, float, float] | None = None) -> trimesh.Trimesh:
    """:func:`quad` with ``image`` as its base colour texture (a glTF-style ``PBRMaterial``).

    Parameters
    ----------
    image : PIL.Image.Image or numpy.ndarray
        The texture (any layout :func:`morphkit.meshes.texture.texture_rgba` reads).
    half_size : float, optional
        ``h``, scene units.
    alpha_mode : {None, "OPAQUE", "MASK", "BLEND"}, optional
        The material's ``alphaMode`` (``None``: unset, i.e. opaque).
    alpha_cutoff : float, optional
        The material's ``alphaCutoff`` (``None``: unset).
    base_color : tuple of 4 float, optional
        The material's ``baseColorFactor`` in ``[0, 1]`` (``None``: unset, white).

    Returns
    -------
    trimesh.Trimesh
        The quad with ``TextureVisuals``.
    """
    mat = trimesh.visual.material.PBRMaterial(
        baseColorTexture=image, alphaMode=alpha_mode, alphaCutoff=alpha_cutoff,
        baseColorFactor=None if base_color is None else np.asarray(base_color, dtype=np.float64))
    m = quad(half_size)
    m.visual = trimesh.visual.TextureVisuals(uv=_QUAD_UV.copy(), material=mat)
    return m


def gradient_quad(half_size: float = 1.0) -> trimesh.Trimesh:
    """:func:`quad` with vertex colours ``255 (u, v, 1 - u)`` (opaque).

    Parameters
    ----------
    half_size : float, optional
        ``h``, scene units.

    Returns
    -------
    trimesh.Trimesh
        The quad with vertex ``ColorVisuals``.
    """
    m = quad(half_size)
    u, v = _QUAD_UV[:, 0], _QUAD_UV[:, 1]
    rgb = np.rint(255 * np.stack([u, v, 1 - u], -1)).astype(np.uint8)
    m.visual.vertex_colors = np.column_stack([rgb, np.full(4, 255, np.uint8)])
    return m


def head_on_camera(shape: tuple[int, int], half_size: float = 1.0, *, fill: float = 0.9,
                   yfov_deg: float = 30.0) -> CameraModel:
    """A perspective camera on the ``+z`` axis looking at the quad's centre, image up ``+y``,
    the quad ``fill`` of the image height.

    Parameters
    ----------
    shape : (H, W)
        Image shape in pixels.
    half_size : float, optional
        The quad's ``h``, scene units.
    fill : float, optional
        Fraction of the image height the quad spans.
    yfov_deg : float, optional
        Vertical field of view, degrees.

    Returns
    -------
    CameraModel
        The camera.
    """
    h = as_positive(half_size, "half_size")
    fill = as_positive(fill, "fill")
    dist = h / (fill * np.tan(np.radians(yfov_deg) / 2))
    return perspective(np.radians(yfov_deg), shape, look_at([0.0, 0.0, dist], [0.0, 0.0, 0.0], up=[0, 1, 0]),
                       znear=dist / 10, zfar=dist * 10)


def quad_uv(camera: CameraModel, half_size: float = 1.0, *, margin_px: int = 1
            ) -> tuple[np.ndarray, np.ndarray]:
    """UV where each pixel centre's ray meets the quad's plane, and where that lies inside it.

    Parameters
    ----------
    camera : CameraModel
        The view (not parallel to the quad's plane).
    half_size : float, optional
        The quad's ``h``, scene units.
    margin_px : int, optional
        Pixels within this many pixels of a pixel outside the quad are not ``inside``
        (edge pixels are partly covered).

    Returns
    -------
    uv : (H, W, 2) float64
        ``(u, v)`` per pixel (outside ``[0, 1]`` off the quad).
    inside : (H, W) bool
        Pixel centres on the quad, at least ``margin_px`` pixels from its edge.
    """
    h = as_positive(half_size, "half_size")
    o, d = camera.rays()
    if np.any(np.abs(d[..., 2]) < tol.PARALLEL_DOT):
        raise ValidationError(expected_got("camera", "rays crossing the plane z = 0", "rays parallel to it"))
    t = -o[..., 2] / d[..., 2]
    p = o + t[..., None] * d
    uv = (p[..., :2] + h) / (2 * h)
    inside = (t > 0) & np.all((uv >= 0) & (uv <= 1), axis=-1)
    if margin_px > 0:
        k = np.ones((2 * margin_px + 1, 2 * margin_px + 1), np.uint8)
        inside = cv2.erode(inside.astype(np.uint8), k, borderValue=0).astype(bool)
    return uv, inside


def sample_texture(texture: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """``texture`` sampled at ``uv`` bilinearly between texel centres, wrapping around
    (OpenGL ``GL_LINEAR`` with ``REPEAT``; texel centres as in the module notes).

    Parameters
    ----------
    texture : (H, W) or (H, W, C) array
        The texture, row 0 at the top (``v = 1``).
    uv : (..., 2) float
        Texture coordinates.

    Returns
    -------
    (..., C) float32
        Sampled values, in the texture's units.
    """
    tex = np.asarray(texture, dtype=np.float32)
    uv = np.asarray(uv, dtype=np.float64)
    th, tw = tex.shape[:2]
    mx = (uv[..., 0] * tw - 0.5).astype(np.float32)
    my = ((1.0 - uv[..., 1]) * th - 0.5).astype(np.float32)
    out = cv2.remap(tex, mx, my, interpolation=cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP)
    return out.reshape(*uv.shape[:-1], *tex.shape[2:])


def gradient_truth(uv: np.ndarray) -> np.ndarray:
    """The colour of :func:`gradient_quad` at ``uv``: ``255 (u, v, 1 - u)``.

    Parameters
    ----------
    uv : (..., 2) float
        Texture coordinates (the quad's parameters).

    Returns
    -------
    (..., 3) float64
        RGB in ``[0, 255]``.
    """
    uv = np.asarray(uv, dtype=np.float64)
    return 255 * np.stack([uv[..., 0], uv[..., 1], 1 - uv[..., 0]], -1)
