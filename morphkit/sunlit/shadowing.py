"""Shadows in a relit billboard frame: the ground's and the billboards' sun visibility per pixel.

The glue between a frame mode (:class:`~.litmodes.LitMode`, :class:`~.litmesh.LitMeshMode`)
and a :class:`~morphkit.sunlit.receivers.SceneShadow` (the atlases' field map, or the ray
cast): :func:`frame_shadow` makes the frame's :class:`~morphkit.sunlit.receivers.FrameShadow`
from the lighting's suns, the ground the camera sees and the instances it draws;
:func:`surface_visibility` gives a billboard image's per-pixel visibility (its depth's world
points, :mod:`morphkit.sunlit.receivers`, "Receivers"); :func:`points_visibility` that of a
mesh pass's pixels; :func:`shadowed_backdrop` the backdrop with the ground's light share
(:func:`morphkit.imaging.shading.sun_shadow_factor`, ground normal ``+z``) where the layer leaves the
ground visible (covered pixels keep full sun: nobody sees them). :func:`darkened` is the pixels a
frame's shadows darken, :func:`darkened_iou` a frame's shadow on the ground against the truth's.
"""

from __future__ import annotations

import numpy as np

from .. import tol
from ..billboard.frames.field import BillboardScene
from ..billboard.frames.frametypes import Frame
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..imaging.shading import Lighting, sun_shadow_factor, sun_terms
from ..scene import DirectionalLight
from ..views.gbuffer import ViewSurface
from .receivers import FrameShadow, SceneShadow

__all__ = ["frame_shadow", "surface_visibility", "points_visibility", "shadowed_backdrop", "FrameGround",
           "darkened", "darkened_iou", "DARK_LEVELS"]

#: A pixel is in a frame's shadow (:func:`darkened`) when the shadow takes at least this many
#: levels (of 255) off one of its channels: more than the frame's rounding (1 level), less
#: than the faintest shadow the bench's suns leave (the ambient share of the darkest ground).
DARK_LEVELS = 3

_UP = np.array([0.0, 0.0, 1.0])


class FrameGround:
    """The ground a camera sees (:meth:`~.backdrop.Backdrop.ground_points`) with the frame's shadow.

    Parameters
    ----------
    hit : (H, W) bool
        Pixels that see the ground.
    points : (M, 3) float64
        Their world points, row-major.
    shadow : FrameShadow or None
        The frame's visibility (``None``: no sun casts).
    """

    def __init__(self, hit: np.ndarray, points: np.ndarray, shadow: FrameShadow | None) -> None:
        self.hit, self.points, self.shadow = hit, points, shadow


def frame_shadow(shadow: SceneShadow, scene: BillboardScene, camera: CameraModel, lighting: Lighting,
                 visible: np.ndarray) -> FrameGround:
    """The frame's ground and visibility (module docstring).

    Parameters
    ----------
    shadow : SceneShadow
        What casts.
    scene : BillboardScene
        The scene (its instances cast; its backdrop's ground receives).
    camera : CameraModel
        The frame's camera.
    lighting : Lighting
        World frame; its suns above the horizon, in order, are the visibility's rows.
    visible : (K,) int
        The instances the frame draws.

    Returns
    -------
    FrameGround
        ``shadow`` ``None`` when no sun is above the horizon or the field is empty.

    Raises
    ------
    ValidationError
        ``shadow`` is not a SceneShadow.
    """
    if not isinstance(shadow, SceneShadow):
        raise ValidationError(expected_got("shadow", "a morphkit.sunlit.receivers.SceneShadow",
                                           type(shadow).__name__))
    hit, ground = scene.backdrop.ground_points(camera)
    suns = [-lt.direction for lt in lighting.above_horizon().lights if isinstance(lt, DirectionalLight)]
    if not suns or len(scene.instances) == 0:
        return FrameGround(hit, ground, None)
    fs = shadow.frame(scene.instances, suns, ground, np.asarray(visible, dtype=np.int64))
    return FrameGround(hit, ground, fs if fs.casts else None)


def surface_visibility(fs: FrameShadow, surface: ViewSurface, camera: CameraModel,
                       object2world: np.ndarray) -> np.ndarray:
    """Per-pixel sun visibility ``(L, h, w)`` of a billboard image (1 where nothing is drawn).

    Parameters
    ----------
    fs : FrameShadow
        The frame's visibility.
    surface : ViewSurface
        The image's surface (depth along ``camera``'s axis, object-frame normals).
    camera : CameraModel
        The image's camera, object frame.
    object2world : (4, 4) float
        The instance's pose (a yaw, a uniform scale, a translation).

    Returns
    -------
    (L, h, w) float32
        One map per sun.
    """
    h, w = surface.shape
    out = np.ones((fs.suns, h, w), np.float32)
    drawn = np.isfinite(surface.depth) & (surface.albedo[..., 3] > 0)
    if not drawn.any():
        return out
    local, _ = camera.unproject(np.where(drawn, surface.depth, np.inf))
    T = np.asarray(object2world, dtype=np.float64)
    pts = local[drawn] @ T[:3, :3].T + T[:3, 3]
    rot = T[:3, :3] / np.cbrt(np.linalg.det(T[:3, :3]))
    nrm = surface.normal[drawn].astype(np.float64) @ rot.T
    out[:, drawn] = fs.visibility(pts, nrm)
    return out


def points_visibility(fs: FrameShadow, points: np.ndarray, normals: np.ndarray, valid: np.ndarray
                      ) -> np.ndarray:
    """Per-pixel sun visibility ``(L, H, W)`` of a mesh pass (1 where ``valid`` is False).

    Parameters
    ----------
    fs : FrameShadow
        The frame's visibility.
    points : (H, W, 3) float
        World points of the pixels (the depth pass unprojected).
    normals : (H, W, 3) float
        Their world normals.
    valid : (H, W) bool
        Pixels with a surface.

    Returns
    -------
    (L, H, W) float32
        One map per sun.
    """
    out = np.ones((fs.suns, *valid.shape), np.float32)
    if valid.any():
        out[:, valid] = fs.visibility(points[valid], normals[valid])
    return out


def shadowed_backdrop(scene: BillboardScene, camera: CameraModel, lighting: Lighting, ground: FrameGround,
                      cover: np.ndarray) -> np.ndarray:
    """The scene's backdrop with the ground's shadows (module docstring).

    Parameters
    ----------
    scene : BillboardScene
        The scene.
    camera : CameraModel
        The frame's camera.
    lighting : Lighting
        World frame.
    ground : FrameGround
        From :func:`frame_shadow` for the same frame.
    cover : (H, W) float
        The layer's alpha over the backdrop (ground pixels at full cover are not looked up).

    Returns
    -------
    (H, W, 3) float32
        RGB in ``[0, 1]``.
    """
    if ground.shadow is None or len(ground.points) == 0:
        return scene.backdrop.draw(camera)
    seen = np.asarray(cover)[ground.hit] < np.float32(1.0 - tol.ALPHA_FLOOR)
    ambient, terms = sun_terms(lighting)
    factor = np.ones(len(ground.points), np.float32)
    if seen.any():
        vis = ground.shadow.visibility(ground.points[seen])
        factor[seen] = sun_shadow_factor(_UP, ambient, terms, vis)
    return scene.backdrop.draw(camera, factor)


def darkened(plain: np.ndarray, shadowed: np.ndarray, levels: int = DARK_LEVELS) -> np.ndarray:
    """The pixels a frame's shadows darken: where ``shadowed`` is at least ``levels`` below
    ``plain`` (the same frame without shadows) in any channel. A pixel turned away from the
    sun, which no shadow can darken, is not counted: the mask is what a viewer sees shadowed.

    Parameters
    ----------
    plain, shadowed : (H, W, 3) uint8
        The frame without and with shadows.
    levels : int
        The threshold (of 255).

    Returns
    -------
    (H, W) bool
        True where darkened.
    """
    return (plain.astype(np.int16) - shadowed.astype(np.int16)).max(axis=2) >= levels


def darkened_iou(plain: Frame, shadowed: Frame, truth_plain: Frame, truth: Frame) -> float | None:
    """A frame's shadow on the ground against the truth's: the IoU of the pixels each frame's shadows
    darken (:func:`darkened`, each frame against itself drawn without shadows), over the pixels both
    frames show as bare ground (layer alpha 0 in both: no object's coverage, not even a
    silhouette's soft edge, whose colour changes with the object's own shading). Where one draws
    an object and the other ground the silhouettes differ, the billboards' error; and the shadows
    on the instances themselves are part of what their billboards look like, measured with them:
    what is left is the shadows the instances cast.

    Parameters
    ----------
    plain, shadowed : Frame
        The frame without and with its shadows (the same billboards or meshes).
    truth_plain, truth : Frame
        The truth's frame without and with its shadows.

    Returns
    -------
    float or None
        In ``[0, 1]``; None where neither frame darkens a pixel of that ground (nothing to measure).

    Examples
    --------
    Two frames whose shadows darken 3 ground pixels each, 2 of them shared: ``IoU = 2 / 4``.

    >>> import numpy as np
    >>> from morphkit.billboard.frames.frametypes import Frame
    >>> from morphkit.sunlit.shadowing import darkened_iou
    >>> def frame(dark):
    ...     rgb = np.full((1, 5, 3), 200, np.uint8)
    ...     rgb[0, dark] = 100
    ...     return Frame(rgb, np.zeros((1, 5, 4), np.float32), [], None)
    >>> lit = frame([])
    >>> darkened_iou(lit, frame([0, 1, 2]), lit, frame([1, 2, 3]))
    0.5
    >>> darkened_iou(lit, lit, lit, lit) is None
    True
    """
    a, b = darkened(plain.rgb, shadowed.rgb), darkened(truth_plain.rgb, truth.rgb)
    ground = (shadowed.layer[..., 3] == 0.0) & (truth.layer[..., 3] == 0.0)
    union = int(np.count_nonzero((a | b) & ground))
    if union == 0:
        return None
    return float(np.count_nonzero(a & b & ground)) / union
