"""The one shading model of relit images: Lambert under ambient light, suns and point lights.

Relit billboards (:class:`~morphkit.views.gbuffer.ViewSurface`, :func:`shade`) and
their ground truth, the real meshes' deferred passes (:func:`shade_passes`,
:class:`~morphkit.sunlit.litmesh.LitMeshMode`), are shaded by this one model, so a
difference between them is a difference of geometry, albedo or normals, never of lighting.

Model
-----
A surface point of straight **linear** albedo ``rho`` (RGB), unit normal ``n`` and
position ``p`` under a :class:`Lighting` has the linear colour

.. math::

    L = \\rho \\Big( a + \\sum_k \\frac{I_k}{\\pi} \\max(0, n \\cdot \\hat l_k)
        + \\sum_j \\frac{I_j}{\\pi d_j^2} \\max(0, n \\cdot \\hat v_j) \\Big)

with ``a`` the ambient level, ``I_k`` and ``l_k = -direction_k`` the intensity and the
unit direction towards each :class:`~morphkit.scene.DirectionalLight` (a sun), ``I_j``
the intensity of each :class:`~morphkit.scene.PointLight` at ``P_j``, ``d_j = |P_j - p|``
and ``v_j = (P_j - p) / d_j``. The ``1 / pi`` is the Lambertian BRDF's (pyrender's units
for the same light intensities). No specular term.

* **Shadows.** A sun's term may be multiplied by a per-pixel **visibility** ``V_k`` in
  ``[0, 1]`` (1 lit, 0 in the sun's shadow; a soft sun's: the fraction of its disc seen):
  ``I_k / pi max(0, n . l_k) V_k``. Ambient and point lights are never shadowed. The
  ``visibility`` arguments take ``(h, w)`` (every sun the same: the one-sun scenes of a
  sun path) or ``(L, h, w)`` (one map per sun above the horizon, in the lighting's
  order); ``None`` is all lit. :func:`sun_shadow_factor` is the bracket's ratio with
  and without the visibility: what a receiver drawn in its lit colour (the billboard
  scene's ground) keeps in shadow.

* **Horizon.** A sun at or below the horizon adds nothing (ambient and point lights
  only): ``l_k . up <= 0`` with ``up`` the world's ``+z`` (:attr:`Lighting.up`,
  carried through :meth:`Lighting.in_frame`, so the test is the world frame's in every
  frame; :meth:`Lighting.above_horizon`). It is a hard cut: the ground hides the sun.
* **Frames.** Normals, points and lights are in one frame: the world for mesh passes,
  an asset's object frame for billboard images (:meth:`Lighting.in_frame` with the
  instance's ``world2object``; exact for rotation, translation and uniform scale, the
  instance poses of :mod:`morphkit.billboard.frames.instances`).
* **Output.** Premultiplied RGBA float32 ``(encode(L) alpha, alpha)``, where ``rho``
  is the premultiplied albedo over its alpha and ``encode(L) = min(L, 1) ^ (1/2.2)``
  (:data:`LIT_GAMMA`): the encoding of the renderer's lit colour
  (:mod:`morphkit.conventions`, "Colour"), so a relit image and a lit render of the same
  light compare directly; one ``cv2.pow`` per image. Zero alpha gives zero.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import cv2
import numpy as np

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..passes import RenderPasses
from ..scene import DirectionalLight, PointLight
from ..validate import as_finite_array

if TYPE_CHECKING:  # pragma: no cover
    from ..views.gbuffer import ViewSurface

__all__ = ["Lighting", "shade", "shade_passes", "sun_terms", "shade_suns", "sun_shadow_factor",
           "encode_premultiplied", "decode_premultiplied", "LIT_GAMMA"]

#: Exponent of the output encoding (gamma 1/2.2, as the renderer's lit colour pass).
LIT_GAMMA = 1.0 / 2.2

SceneLight = DirectionalLight | PointLight
_EYE3 = np.eye(3)
_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])


def _as_lights(lights: Iterable[SceneLight]) -> tuple[SceneLight, ...]:
    out = tuple(lights)
    for i, lt in enumerate(out):
        if not isinstance(lt, DirectionalLight | PointLight):
            raise ValidationError(expected_got(f"lights[{i}]", "a DirectionalLight or a PointLight",
                                               type(lt).__name__))
    return out


def _scale_of(linear: np.ndarray, name: str) -> float:
    """The uniform scale ``s`` of ``linear = s R`` (``R`` a rotation), or an error."""
    g = linear.T @ linear
    s2 = float(g[0, 0] + g[1, 1] + g[2, 2]) / 3.0
    # not np.allclose: this runs once per instance and frame, where allclose's overhead shows
    if not s2 > 0 or float(np.abs(g / s2 - _EYE3).max()) > tol.POSE_ORTHO or np.linalg.det(linear) < 0:
        raise ValidationError(expected_got(name, "rotation, uniform scale and translation",
                                           "a shear, a non-uniform scale or a reflection"))
    return math.sqrt(s2)


@dataclass(frozen=True, eq=False)
class Lighting:
    """Ambient level and lights of one frame, in one coordinate frame (module docstring).

    Parameters
    ----------
    ambient : float
        Ambient level ``a >= 0`` (multiplies the albedo).
    lights : sequence of DirectionalLight or PointLight
        The lights (stored as a tuple).
    up : (3,) float, optional
        The world's up (``+z``) in this lighting's frame: the horizon of the suns.
        World frame: the default; :meth:`in_frame` carries it.

    Examples
    --------
    A sun 30 degrees above the horizon and one below it: the second lights nothing.

    >>> import numpy as np
    >>> from morphkit.scene import DirectionalLight
    >>> from morphkit.imaging.shading import Lighting
    >>> e = np.radians(30.0)
    >>> day = Lighting(0.2, (DirectionalLight([-np.cos(e), 0.0, -np.sin(e)]),
    ...                      DirectionalLight([1.0, 0.0, 0.1])))
    >>> len(day.above_horizon().lights)
    1
    """

    ambient: float
    lights: tuple[SceneLight, ...] = ()
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        try:
            a = float(self.ambient)
        except (TypeError, ValueError):
            a = math.nan
        if not math.isfinite(a) or a < 0:
            raise ValidationError(expected_got("ambient", "a finite number >= 0", repr(self.ambient)))
        up = as_finite_array(self.up, "up", shape=(3,))
        n = float(np.linalg.norm(up))
        if not n > tol.MIN_EXTENT:
            raise ValidationError(expected_got("up", "a non-zero vector", up.tolist()))
        object.__setattr__(self, "ambient", a)
        object.__setattr__(self, "lights", _as_lights(self.lights))
        object.__setattr__(self, "up", tuple(float(v) for v in up / n))

    def above_horizon(self) -> Lighting:
        """The same lighting without the suns at or below the horizon (``l . up <= 0``).

        Returns
        -------
        Lighting
            ``self`` when every sun is above the horizon, else a new one.
        """
        up = np.asarray(self.up)
        keep = tuple(lt for lt in self.lights
                     if not isinstance(lt, DirectionalLight) or float(-lt.direction @ up) > 0.0)
        return self if len(keep) == len(self.lights) else self._checked(self.ambient, keep, self.up)

    def in_frame(self, frame_from_world: np.ndarray) -> Lighting:
        """The same lights seen in another frame (e.g. an instance's object frame).

        Suns below the horizon are dropped first (in this frame, :meth:`above_horizon`);
        directions turn with the linear part and are renormalised, positions are
        transformed, and point intensities are scaled by ``s^2`` (``s`` the transform's
        scale) so that ``I / d^2`` is the same in both frames.

        Parameters
        ----------
        frame_from_world : (4, 4) float
            Maps a point of this lighting's frame (the world) to the new frame
            (``world2object``: the inverse of an instance's ``object2world``); rotation,
            translation and a uniform scale.

        Returns
        -------
        Lighting
            New lighting, its :attr:`up` the world's up in the new frame.

        Raises
        ------
        ValidationError
            A transform that is not rotation, uniform scale and translation.
        """
        T = as_finite_array(frame_from_world, "frame_from_world", shape=(4, 4))
        if float(np.abs(T[3] - _LAST_ROW).max()) > tol.POSE_ORTHO:
            raise ValidationError(expected_got("frame_from_world", "last row 0 0 0 1", T[3].tolist()))
        L = T[:3, :3]
        s = _scale_of(L, "frame_from_world")
        lights: list[SceneLight] = []
        for lt in self.above_horizon().lights:
            if isinstance(lt, DirectionalLight):
                lights.append(DirectionalLight(L @ lt.direction, lt.intensity))
            else:
                lights.append(PointLight(L @ lt.position + T[:3, 3], lt.intensity * s * s))
        up = L @ np.asarray(self.up)
        return self._checked(self.ambient, tuple(lights), tuple((up / np.linalg.norm(up)).tolist()))

    @classmethod
    def _checked(cls, ambient: float, lights: tuple[SceneLight, ...], up: tuple[float, float, float]
                 ) -> Lighting:
        """A Lighting of parts already checked (skips the validation: once per instance and frame)."""
        out = object.__new__(cls)
        object.__setattr__(out, "ambient", ambient)
        object.__setattr__(out, "lights", lights)
        object.__setattr__(out, "up", up)
        return out


def _visibility_maps(visibility: np.ndarray | None, suns: int, shape: tuple[int, int]
                     ) -> np.ndarray | None:
    """``(L, h, w)`` float32 of a ``visibility`` argument (module docstring, "Shadows"), or None."""
    if visibility is None:
        return None
    v = np.asarray(visibility, dtype=np.float32)
    if v.shape == shape:
        return np.broadcast_to(v, (suns, *shape))
    if v.shape != (suns, *shape):
        raise ValidationError(expected_got("visibility", f"{shape} or ({suns}, {shape[0]}, {shape[1]}) "
                                           "(one map per sun above the horizon)", v.shape))
    return v


def _irradiance(normal: np.ndarray, lighting: Lighting, points: np.ndarray | None,
                visibility: np.ndarray | None = None) -> np.ndarray:
    """``(h, w)`` float32: the bracket of the model (module docstring) at every pixel."""
    h, w = normal.shape[:2]
    e = np.full((h, w), lighting.ambient, np.float32)
    suns = sum(isinstance(lt, DirectionalLight) for lt in lighting.lights)
    vis = _visibility_maps(visibility, suns, (h, w))
    k = 0
    for lt in lighting.lights:
        if isinstance(lt, DirectionalLight):
            m = (-lt.direction * (lt.intensity / math.pi)).astype(np.float32).reshape(1, 3)
            ndl = cv2.max(cv2.transform(normal, m).reshape(h, w), 0.0)
            if vis is not None:
                ndl = cv2.multiply(ndl, np.ascontiguousarray(vis[k]))
            k += 1
            cv2.add(e, ndl, dst=e)
        else:
            assert points is not None  # checked by the caller
            v = np.subtract(lt.position.astype(np.float32), points, dtype=np.float32)
            d2 = np.maximum(np.einsum("ijk,ijk->ij", v, v), np.float32(tol.MIN_EXTENT ** 2))
            ndv = np.maximum(np.einsum("ijk,ijk->ij", normal, v), np.float32(0.0))
            cv2.add(e, ndv * (np.float32(lt.intensity / math.pi) / (d2 * np.sqrt(d2))), dst=e)
    return e


def shade(surface: ViewSurface, lighting: Lighting, points: np.ndarray | None = None,
          visibility: np.ndarray | None = None) -> np.ndarray:
    """A :class:`~morphkit.views.gbuffer.ViewSurface` lit by ``lighting`` (the model of
    :mod:`morphkit.imaging.shading`).

    Parameters
    ----------
    surface : ViewSurface
        Premultiplied linear albedo and alpha, unit normals, depth.
    lighting : Lighting
        In the frame of the surface's normals (for an asset's image: the scene's
        lighting :meth:`~Lighting.in_frame` of the instance's ``world2object``).
    points : (h, w, 3) float, optional
        Surface positions in the same frame; needed with point lights only.
    visibility : (h, w) or (L, h, w) float, optional
        The suns' visibility (module docstring, "Shadows"; ``L`` the suns above the
        horizon); default all lit.

    Returns
    -------
    (h, w, 4) float32
        Premultiplied RGBA, colour sRGB-encoded (module docstring); 0 where alpha is 0.

    Raises
    ------
    ValidationError
        Point lights without ``points``, or ``points`` of another shape; a visibility of
        another shape.
    """
    lighting = lighting.above_horizon()
    h, w = surface.shape
    if any(isinstance(lt, PointLight) for lt in lighting.lights):
        if points is None:
            raise ValidationError(expected_got("points", "(h, w, 3) surface positions with point lights",
                                               "None"))
        points = np.asarray(points)
        if points.shape != (h, w, 3):
            raise ValidationError(expected_got("points", f"({h}, {w}, 3)", points.shape))
    normal = np.ascontiguousarray(surface.normal, dtype=np.float32)
    return _lit(surface, _irradiance(normal, lighting, points, visibility))


def _lit(surface: ViewSurface, e: np.ndarray) -> np.ndarray:
    """Premultiplied encoded RGBA of ``surface`` under irradiance bracket ``e`` (h, w)."""
    return encode_premultiplied(_lit_linear(surface, e))


def _lit_linear(surface: ViewSurface, e: np.ndarray) -> np.ndarray:
    """Premultiplied linear RGBA ``(rho E alpha, alpha)``, ``rho E`` clipped to 1."""
    albedo = np.ascontiguousarray(surface.albedo, dtype=np.float32)
    alpha = np.ascontiguousarray(albedo[..., 3])
    # rho E alpha = premultiplied albedo times E, clipped where rho E > 1 (at alpha)
    out = cv2.multiply(albedo, cv2.merge((e, e, e, np.ones_like(e))))
    cv2.min(out, cv2.merge((alpha, alpha, alpha, alpha)), dst=out)
    return out


def encode_premultiplied(image: np.ndarray) -> np.ndarray:
    """Premultiplied linear RGBA encoded in place: each pixel's straight colour ``c``
    becomes ``min(c, 1) ^ LIT_GAMMA`` (the model's output encoding, by a table of 65536
    entries: steps of 1/65535 in linear light), premultiplied again.

    Parameters
    ----------
    image : (h, w, 4) float32
        Premultiplied linear RGBA.

    Returns
    -------
    (h, w, 4) float32
        ``image``, encoded.
    """
    alpha = np.ascontiguousarray(image[..., 3])
    inv = cv2.divide(1.0, cv2.max(alpha, tol.ALPHA_FLOOR))
    rgb = np.ascontiguousarray(image[..., :3])
    # (numpy for the scalars: cv2 takes a scalar as (v, 0, 0, 0), one channel)
    straight = np.minimum(cv2.multiply(rgb, cv2.merge((inv, inv, inv))), np.float32(1.0))
    enc = _ENCODE_LUT[(straight * np.float32(_ENCODE_STEPS - 1) + np.float32(0.5)).astype(np.int32)]
    image[..., :3] = cv2.multiply(enc, cv2.merge((alpha, alpha, alpha)))
    return image


def decode_premultiplied(image: np.ndarray) -> np.ndarray:
    """The premultiplied linear RGB of a premultiplied encoded RGBA image (the inverse of
    :func:`encode_premultiplied` on colours in ``[0, 1]``).

    Parameters
    ----------
    image : (h, w, 4) float32
        Premultiplied encoded RGBA.

    Returns
    -------
    (h, w, 3) float32
        Premultiplied linear RGB (a new array).
    """
    a = np.maximum(image[..., 3:], np.float32(tol.ALPHA_FLOOR))
    return (np.power(np.clip(image[..., :3] / a, 0.0, 1.0), np.float32(1.0 / LIT_GAMMA)) * image[..., 3:]
            ).astype(np.float32)


#: Entries of the output encoding table (steps of 1/65535 in linear light).
_ENCODE_STEPS = 65536
_ENCODE_LUT = np.power(np.linspace(0.0, 1.0, _ENCODE_STEPS), LIT_GAMMA).astype(np.float32)


def sun_terms(lighting: Lighting) -> tuple[float, np.ndarray]:
    """The directional part of ``lighting`` as numbers: ``(ambient, T)``, ``T`` ``(L, 3)``
    float32 with one row ``I l / pi`` per sun above the horizon (``l`` towards the light),
    so that the model's bracket is ``ambient + sum_k max(0, dot(T_k, n))``.

    Parameters
    ----------
    lighting : Lighting
        Any lighting (its point lights are left out: see :func:`shade`).

    Returns
    -------
    ambient : float
        The ambient level.
    terms : (L, 3) float32
        The suns' rows, in ``lighting``'s frame (turn them with the frame's rotation:
        rows times ``R`` for ``R = object2world``'s rotation, to the object frame).
    """
    rows = [-lt.direction * (lt.intensity / math.pi) for lt in lighting.above_horizon().lights
            if isinstance(lt, DirectionalLight)]
    return lighting.ambient, np.array(rows, np.float32).reshape(-1, 3)


def shade_suns(surface: ViewSurface, ambient: float, terms: np.ndarray,
               visibility: np.ndarray | None = None) -> np.ndarray:
    """:func:`shade` for suns and ambient only, from :func:`sun_terms` already in the
    surface's frame: the same model, without building a :class:`Lighting` per image (a
    frame of many billboards turns the rows by each instance's yaw).

    Parameters
    ----------
    surface : ViewSurface
        Premultiplied linear albedo and alpha, unit normals, depth.
    ambient : float
        The ambient level.
    terms : (L, 3) float32
        The suns' rows (:func:`sun_terms`) in the surface's frame.
    visibility : (h, w) or (L, h, w) float, optional
        The suns' visibility (module docstring, "Shadows"); default all lit.

    Returns
    -------
    (h, w, 4) float32
        Premultiplied **linear** RGBA: :func:`encode_premultiplied` of it is :func:`shade` of
        the same lights (a frame of many images encodes its layer once instead).

    Raises
    ------
    ValidationError
        A visibility of another shape.
    """
    h, w = surface.shape
    normal = np.ascontiguousarray(surface.normal, dtype=np.float32)
    e = np.full((h, w), ambient, np.float32)
    rows = np.asarray(terms, np.float32).reshape(-1, 3)
    vis = _visibility_maps(visibility, len(rows), (h, w))
    for k, row in enumerate(rows):
        ndl = cv2.max(cv2.transform(normal, row.reshape(1, 3)).reshape(h, w), 0.0)
        if vis is not None:
            ndl = cv2.multiply(ndl, np.ascontiguousarray(vis[k]))
        cv2.add(e, ndl, dst=e)
    return _lit_linear(surface, e)


def sun_shadow_factor(normal: np.ndarray, ambient: float, terms: np.ndarray, visibility: np.ndarray
                      ) -> np.ndarray:
    """The model's bracket with the suns' visibility over the bracket without it (module
    docstring, "Shadows"): what a receiver drawn in its fully lit colour keeps in shadow.

    Parameters
    ----------
    normal : (3,) float
        The receivers' unit normal (one for all: a plane, e.g. the ground's ``+z``), in
        the frame of ``terms``.
    ambient : float
        The ambient level.
    terms : (L, 3) float32
        The suns' rows (:func:`sun_terms`).
    visibility : (N,) or (L, N) float
        The suns' visibility at ``N`` receiver points (``(N,)``: every sun the same).

    Returns
    -------
    (N,) float32
        ``(a + sum_k V_k max(0, n . T_k)) / (a + sum_k max(0, n . T_k))`` in ``[0, 1]``;
        1 where the bracket is 0 (no light at all: nothing to take away).

    Raises
    ------
    ValidationError
        A visibility of another shape.
    """
    rows = np.asarray(terms, np.float64).reshape(-1, 3)
    ndl = np.maximum(rows @ np.asarray(normal, np.float64).reshape(3), 0.0)
    v = np.asarray(visibility, dtype=np.float32)
    n = v.shape[-1] if v.ndim else 0
    if v.ndim == 1:
        v = np.broadcast_to(v, (len(rows), n))
    if v.shape != (len(rows), n):
        raise ValidationError(expected_got("visibility", f"(N,) or ({len(rows)}, N)", v.shape))
    full = float(ambient) + float(ndl.sum())
    if not full > 0.0:
        return np.ones(n, np.float32)
    return ((float(ambient) + ndl.astype(np.float32) @ v) / np.float32(full)).astype(np.float32)


def shade_passes(passes: RenderPasses, lighting: Lighting, camera: CameraModel,
                 visibility: np.ndarray | None = None) -> np.ndarray:
    """The deferred passes of a mesh render lit by ``lighting`` (world frame): the ground
    truth of relit billboards, by the same model as :func:`shade`.

    Parameters
    ----------
    passes : RenderPasses
        From :meth:`~morphkit.render.Renderer.passes` or ``source_passes``: albedo
        sRGB-encoded (decoded here by :func:`~morphkit.views.gbuffer.srgb_to_linear`),
        world-frame normals, linear depth, coverage alpha.
    lighting : Lighting
        World frame.
    camera : CameraModel
        The view the passes were drawn through (points from the depth when there are
        point lights).
    visibility : (H, W) or (L, H, W) float, optional
        The suns' visibility per pixel (module docstring, "Shadows"); default all lit.

    Returns
    -------
    (H, W, 4) float32
        Premultiplied RGBA, colour sRGB-encoded.

    Raises
    ------
    ValidationError
        Passes whose shape is not the camera's.
    """
    from ..views.gbuffer import ViewSurface, srgb_to_linear  # see shade

    h, w = camera.shape
    if passes.albedo.shape != (h, w, 3) or passes.alpha.shape != (h, w):
        raise ValidationError(expected_got("passes", f"images of the camera's shape {(h, w)}",
                                           f"albedo {passes.albedo.shape}, alpha {passes.alpha.shape}"))
    a = np.asarray(passes.alpha, dtype=np.float32)
    albedo = np.empty((h, w, 4), np.float32)
    np.multiply(srgb_to_linear(passes.albedo), a[..., None], out=albedo[..., :3])
    albedo[..., 3] = a
    surface = ViewSurface(albedo, np.asarray(passes.normal, dtype=np.float32),
                          np.asarray(passes.depth, dtype=np.float32))
    points = None
    if any(isinstance(lt, PointLight) for lt in lighting.lights):
        points = camera.unproject(passes.depth)[0].astype(np.float32)
    return shade(surface, lighting, points, visibility)
