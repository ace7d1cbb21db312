"""The impostor way of a field's shadow: each instance's billboard card drawn into the light view.

What engines do with impostors (Unreal's and Amplify's octahedral impostors, a billboard's
card): the shadow pass draws each instance's **flat card through its pivot, facing the light**,
textured with one of the impostor's frames and **alpha-tested**
(:data:`~morphkit.tol.IMPOSTOR_CARD_ALPHA_TEST`, the frame's coverage sampled bilinearly as a
GPU samples the card's texture); the card's depth is flat, its plane's. Drawn into the field's
light view (:meth:`~morphkit.sunlit.fieldshadow.FieldShadow.plan`'s camera, min depth), it
gives a :class:`~morphkit.sunlit.fieldshadow.FieldMap` looked up like the atlas's.

Two images (:data:`CARD_IMAGES`), both from an
:class:`~morphkit.billboard.impostor.OctahedralImpostor` of the asset:

* ``"camera"`` -- the card shows **the image the camera sees**: the frame nearest to the
  direction from the instance's pivot to the camera (object frame), the billboard's
  current view, mapped onto the card's corners (its right along the card's right, the
  light's :func:`~morphkit.views.domecameras.quad_axes`). The shadow has the camera's
  silhouette and turns with the camera: the complaint about impostor shadows.
* ``"light"`` -- the card shows **the frame nearest to the light direction** (object frame,
  the sun turned back by the yaw): the silhouette the light sees, up to the grid's step.
  Each card point is looked up where it projects onto the frame's own image plane (along
  the frame's direction), so the frame's roll holds (the frame straight above included).

The nearest frame is the one whose direction has the largest dot product with the wanted
direction. Frames hold the whole bounding sphere (``half_extent`` about the pivot), so the
card is the frame's square at the instance's scale. The sun is clamped at the field's
grazing cut-off as the atlas's is (:func:`~morphkit.sunlit.fieldshadow.field_sun`); at or
below the horizon nothing casts.
"""

from __future__ import annotations

from collections.abc import Mapping

import cv2
import numpy as np

from .. import tol
from ..billboard.frames.instances import Instances
from ..billboard.impostor import OctahedralImpostor
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array
from ..views.domecameras import quad_axes
from .fieldshadow import FieldMap, FieldShadow, field_sun
from .sunatlas import sun_direction

__all__ = ["card_field_map", "nearest_frame", "CARD_IMAGES"]

#: The card's image: the camera's view, or the frame nearest the light (module docstring).
CARD_IMAGES = ("camera", "light")


def nearest_frame(impostor: OctahedralImpostor, direction_object: np.ndarray) -> int:
    """The impostor's frame whose direction is nearest to a direction (largest dot product).

    Parameters
    ----------
    impostor : OctahedralImpostor
        The asset's impostor.
    direction_object : (3,) float
        Any non-zero direction, object frame (below the horizon: the nearest horizon frame).

    Returns
    -------
    int
        The frame's index (``j N + i``).

    Raises
    ------
    ValidationError
        A zero or non-finite direction.
    """
    d = as_finite_array(direction_object, "direction_object", shape=(3,))
    n = float(np.linalg.norm(d))
    if not n > tol.MIN_EXTENT:
        raise ValidationError(expected_got("direction_object", "a non-zero direction (3,)", d.tolist()))
    return int(np.argmax(impostor.frame_dirs @ (d / n)))


def _angles(d: np.ndarray) -> tuple[float, float]:
    return float(np.degrees(np.arctan2(d[1], d[0]))), float(np.degrees(np.arcsin(np.clip(d[2], -1.0, 1.0))))


class _Alphas:
    """Frames' coverage (float32), decoded once per (asset, frame)."""

    def __init__(self) -> None:
        self._held: dict[tuple[str, int], np.ndarray] = {}

    def get(self, name: str, impostor: OctahedralImpostor, k: int) -> np.ndarray:
        a = self._held.get((name, k))
        if a is None:
            a = self._held[(name, k)] = np.ascontiguousarray(impostor.frame_surface(k).alpha, np.float32)
        return a


def card_field_map(field: FieldShadow, impostors: Mapping[str, OctahedralImpostor], instances: Instances,
                   sun_dir_world: np.ndarray, texels_per_unit: float,
                   receiver: tuple[float, float, float, float] | None = None, *, image: str = "light",
                   camera_position: np.ndarray | None = None) -> FieldMap:
    """The field's light view drawn the impostor way: alpha-tested light-facing cards (module docstring).

    Parameters
    ----------
    field : FieldShadow
        Gives the camera and the instances kept (:meth:`~.fieldshadow.FieldShadow.plan`), so
        the map is the atlas's view of the same field.
    impostors : mapping of str to OctahedralImpostor
        Each asset name of the instances, its impostor.
    instances : Instances
        The field.
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    texels_per_unit : float
        The view's resolution.
    receiver : (xmin, ymin, xmax, ymax), optional
        As :meth:`~.fieldshadow.FieldShadow.build`.
    image : {"camera", "light"}
        The card's image (:data:`CARD_IMAGES`).
    camera_position : (3,) float, optional
        The viewer, world frame; needed for ``image="camera"``.

    Returns
    -------
    FieldMap
        Same camera and instances as the atlas's map; no camera when nothing casts.

    Raises
    ------
    ValidationError
        Bad arguments; an asset without an impostor; ``image="camera"`` without a camera.
    """
    if image not in CARD_IMAGES:
        raise ValidationError(expected_got("image", f"one of {list(CARD_IMAGES)}", repr(image)))
    eye = None
    if image == "camera":
        if camera_position is None:
            raise ValidationError(expected_got("camera_position", "the viewer's position (3,) for "
                                               "image='camera'", None))
        eye = as_finite_array(camera_position, "camera_position", shape=(3,))
    names = instances.names if isinstance(instances, Instances) else ()  # plan() refuses a non-Instances
    missing = [nm for nm in names if nm not in impostors]
    if missing:
        raise ValidationError(expected_got("impostors", "one per asset name of the instances",
                                           f"none for {missing}"))
    plan = field.plan(instances, sun_dir_world, texels_per_unit, receiver)
    if plan.camera is None:
        return plan
    cam = plan.camera
    sun = field_sun(sun_dir_world)
    assert sun is not None
    l_world = sun_direction(*sun)
    w2c = cam.world2cam
    s_dst = np.array([[cam.fx, 0.0, cam.cx], [0.0, cam.fy, cam.cy], [0.0, 0.0, 1.0]])
    depth = np.full(cam.shape, np.inf, np.float32)
    alphas = _Alphas()
    for k in plan.kept:
        k = int(k)
        name = instances.names[int(instances.asset[k])]
        imp = impostors[name]
        pose = instances.object2world(k)
        c, s = np.cos(np.radians(instances.yaw_deg[k])), np.sin(np.radians(instances.yaw_deg[k]))
        turn = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # world -> object: Rz(-yaw)
        l_obj = turn @ l_world
        pivot_world = pose[:3, :3] @ imp.pivot + pose[:3, 3]
        if eye is not None:
            frame = nearest_frame(imp, turn @ (eye - pivot_world))
        else:
            frame = nearest_frame(imp, l_obj)
        _draw_card(depth, s_dst, w2c, pose, imp, frame, l_obj, alphas.get(name, imp, frame),
                   on_frame_plane=eye is None)
    return FieldMap(cam, depth, plan.kept, plan.skipped)


def _draw_card(depth: np.ndarray, s_dst: np.ndarray, w2c: np.ndarray, pose: np.ndarray,
               imp: OctahedralImpostor, frame: int, l_obj: np.ndarray, alpha: np.ndarray, *,
               on_frame_plane: bool) -> None:
    """Min one alpha-tested card into the field's depth: card plane coordinates ``(x, y)`` (object
    units from the pivot along the light's quad axes) map affinely to field pixels and to frame texels."""
    right, up = (np.asarray(v, float) for v in quad_axes(*_angles(l_obj)))
    m = alpha.shape[0]
    f = 0.5 * m / float(imp.half_extent[0])
    cxy = (m - 1) / 2.0
    if on_frame_plane:  # the frame's own image plane (its roll kept)
        rk, uk = imp.frame_right[frame], imp.frame_up[frame]
        B = np.array([[f * (right @ rk), f * (up @ rk), cxy], [-f * (right @ uk), -f * (up @ uk), cxy],
                      [0.0, 0.0, 1.0]])
    else:  # the image on the card's corners
        B = np.array([[f, 0.0, cxy], [0.0, -f, cxy], [0.0, 0.0, 1.0]])
    if abs(np.linalg.det(B[:2, :2])) < tol.MIN_EXTENT:
        return  # a frame seen edge-on casts nothing
    # (x, y, 1) -> world -> field camera
    P = np.zeros((4, 3))
    P[:3, 0], P[:3, 1], P[:3, 2], P[3, 2] = right, up, imp.pivot, 1.0
    M = w2c @ pose @ P  # (4, 3): camera coordinates of the card point (x, y)
    A = s_dst @ np.vstack([M[:2], [0.0, 0.0, 1.0]]) @ np.linalg.inv(B)  # frame texel -> field pixel
    z = np.float32(M[2, 2])  # the pivot's depth: the card is perpendicular to the light
    corners = A @ np.array([[-0.5, m - 0.5, -0.5, m - 0.5], [-0.5, -0.5, m - 0.5, m - 0.5], [1, 1, 1, 1]])
    H, W = depth.shape
    x0, y0 = max(int(np.floor(corners[0].min())), 0), max(int(np.floor(corners[1].min())), 0)
    x1, y1 = min(int(np.ceil(corners[0].max())) + 1, W), min(int(np.ceil(corners[1].max())) + 1, H)
    if x1 <= x0 or y1 <= y0:
        return
    A_roi = np.array([[1.0, 0.0, -x0], [0.0, 1.0, -y0], [0.0, 0.0, 1.0]]) @ A
    cover = cv2.warpAffine(alpha, A_roi[:2], (x1 - x0, y1 - y0), flags=cv2.INTER_LINEAR,
                           borderMode=cv2.BORDER_CONSTANT, borderValue=0.0)
    roi = depth[y0:y1, x0:x1]
    roi[(cover >= np.float32(tol.IMPOSTOR_CARD_ALPHA_TEST)) & (roi > z)] = z
