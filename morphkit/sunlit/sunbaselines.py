"""The baselines of a sun atlas's shadow: the direct light render and the ray-cast truth.

* **direct** (:func:`direct_light_view`, :func:`direct_ground_shadow`): the normalised
  mesh rendered into an orthographic depth map along the exact sun direction (the
  atlas's own camera rule, :meth:`~morphkit.views.domecameras.DomeCameras.ortho_camera`,
  at the same resolution) and looked up as the atlas's views are
  (:func:`~.sunatlas.ground_visibility`): the best a light view of that many texels
  can do, the upper bound of an atlas at that size.
* **truth** (:func:`ray_cast_ground_shadow`): a ray from each receiver point towards the
  sun against the posed mesh (:func:`morphkit.imaging.groundtruth.hard_visibility`, Embree when
  installed), with the exact sun: no clamp at the grazing cut-off.

Both follow the atlas's conventions (:mod:`.sunatlas`): the pose maps the *normalised*
mesh's frame to the world; a sun at or below the horizon casts no shadow.
"""

from __future__ import annotations

import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel
from ..imaging.groundtruth import hard_visibility
from ..meshes import normalize
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, Item, SceneObject
from ..validate import as_finite_array, as_shape
from .sunatlas import SunAtlas, ground_visibility, instance_frame, sun_in_object

__all__ = ["direct_light_view", "direct_ground_shadow", "ray_cast_ground_shadow"]


def _angles(d: np.ndarray) -> tuple[float, float]:
    return (float(np.degrees(np.arctan2(d[1], d[0]))),
            float(np.degrees(np.arcsin(np.clip(d[2], -1.0, 1.0)))))


def direct_light_view(atlas: SunAtlas, normalized_mesh: trimesh.Trimesh, renderer: SceneRenderer,
                      sun_dir_object: np.ndarray, shape: tuple[int, int] | None = None
                      ) -> tuple[CameraModel, np.ndarray] | None:
    """The light view :meth:`~morphkit.sunlit.sunatlas.SunAtlas.light_view` approximates, rendered directly.

    Parameters
    ----------
    atlas : SunAtlas
        Gives the camera rule.
    normalized_mesh : trimesh.Trimesh
        The atlas's mesh, normalised (:func:`morphkit.meshes.normalize`; not checked here:
        :meth:`~morphkit.sunlit.sunatlas.SunAtlas.check_mesh` does, :func:`direct_ground_shadow` calls it).
    renderer : SceneRenderer
        Draws the depth.
    sun_dir_object : (3,) float
        Towards the sun, object frame.
    shape : tuple of 2 int, optional
        ``(h, w)`` (default: the atlas's).

    Returns
    -------
    (CameraModel, (h, w) float32) or None
        As :meth:`~morphkit.sunlit.sunatlas.SunAtlas.light_view` (the same grazing clamp;
        ``None`` at or below the horizon).

    Raises
    ------
    ValidationError
        A zero direction; a bad shape.
    """
    d = as_finite_array(sun_dir_object, "sun_dir_object", shape=(3,))
    shape = atlas.cameras.shape if shape is None else as_shape(shape, "shape")
    if atlas.light_view(d, (8, 8)) is None:  # validates the direction; None below the horizon
        return None
    az, el = _angles(d / np.linalg.norm(d))
    cam = atlas.cameras.ortho_camera(az, max(el, tol.SUN_MIN_ELEVATION_DEG), shape)
    return cam, renderer.depth(cam, [Item(normalized_mesh)])


def direct_ground_shadow(atlas: SunAtlas, mesh: trimesh.Trimesh, renderer: SceneRenderer,
                         pose: np.ndarray, sun_dir_world: np.ndarray, points: np.ndarray, *,
                         shape: tuple[int, int] | None = None) -> np.ndarray:
    """:func:`~.sunatlas.ground_shadow` with the light view rendered directly (module docstring).

    Parameters
    ----------
    atlas : SunAtlas
        The camera rule (and the mesh's hash).
    mesh : trimesh.Trimesh
        The caster (normalised here; checked against the atlas by hash).
    renderer : SceneRenderer
        Draws the depth.
    pose : (4, 4) float
        The instance's ``object2world``.
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    points : (N, 3) float
        Receiver points, world frame.
    shape : tuple of 2 int, optional
        The light view's ``(h, w)`` (default: the atlas's).

    Returns
    -------
    (N,) float32
        1 lit, 0 shadowed.

    Raises
    ------
    ValidationError
        Another mesh than the atlas's (both hashes named); bad pose, direction or points.
    """
    atlas.check_mesh(mesh)
    pts = as_finite_array(points, "points", shape=(None, 3))
    sun = sun_in_object(pose, sun_dir_world)
    view = None if sun is None else direct_light_view(atlas, normalize(mesh), renderer, sun, shape)
    if view is None:
        return np.ones(len(pts), np.float32)
    return ground_visibility(view[0], view[1], pose, pts)


def ray_cast_ground_shadow(mesh: trimesh.Trimesh, pose: np.ndarray, sun_dir_world: np.ndarray,
                           points: np.ndarray) -> np.ndarray:
    """The truth: rays from each point towards the exact sun against the posed mesh.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The caster (normalised here: the pose places the normalised mesh).
    pose : (4, 4) float
        The instance's ``object2world`` (a yaw, a uniform scale, a translation).
    sun_dir_world : (3,) float
        Towards the sun, world frame.
    points : (N, 3) float
        Receiver points, world frame.

    Returns
    -------
    (N,) float32
        1 lit, 0 shadowed; all 1 for a sun at or below the horizon.
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    scale, _, _ = instance_frame(pose)
    if sun_in_object(pose, sun_dir_world) is None:
        return np.ones(len(pts), np.float32)
    body = normalize(mesh)
    if scale != 1.0:
        body.apply_scale(scale)
    rigid = np.array(pose, dtype=np.float64)
    rigid[:3, :3] /= scale
    d = np.asarray(sun_dir_world, dtype=np.float64)
    return hard_visibility(pts, DirectionalLight(-d), SceneObject(body, rigid))
