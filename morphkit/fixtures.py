"""The scenes shared by the demo, the benchmarks, the samples and the tests.

One place for each set-up, so that a figure in ``docs/RESULTS.md``, a demo
image and a test are about the same scene:

* the shadow scenes: a normalised sample mesh on a ground square, a
  directional light and a 3/4 view camera (:func:`demo_scene`); the point
  light and range of motion of the warped-shadow scenes (:data:`WARP_LIGHT`,
  :data:`WARP_RANGE`) and the area light of the soft-shadow scenes
  (:data:`SOFT_LIGHT`);
* the view-morphing scenes: cameras on a circle about the object
  (:func:`circle_camera`), the sample meshes with a 3-D colour checker
  (:func:`textured_items`, the look of :func:`morphkit.appearance.checker_items`)
  and their reference views (:func:`render_pair`).

The warped-shadow scenes' light and range are the shadow atlas defaults of
:mod:`morphkit.bake.kinds`, re-exported here. Nothing here imports
:mod:`morphkit.bench`; the benchmark imports from here. The library does not
import this module (``tests/test_structure.py`` checks it): only the
benchmarks, the demo, the CLI, the samples and the tests do.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import trimesh

from .appearance import checker_items
from .bake.kinds import WARP_LIGHT, WARP_RANGE
from .camera import CameraModel, look_at, perspective
from .groundtruth import hard_visibility
from .meshes import sample_mesh
from .protocols import SceneRenderer
from .scene import AreaLight, DirectionalLight, Receiver, Scene, SceneObject
from .shadow.frame import SKY, render_frame

__all__ = ["DEMO_MESHES", "DEMO_LIGHT_DIRECTION", "demo_scene", "ground_truth_frame", "WARP_RANGE",
           "WARP_LIGHT", "WARP_POSITION", "SOFT_LIGHT", "VIEWMORPH_BASELINE_DEG", "CENTRE_AZIMUTH",
           "circle_camera", "textured_items", "render_pair"]


#: The sample meshes (:func:`morphkit.meshes.sample_mesh` names) every demo scene shows.
DEMO_MESHES = ("teapot", "chair", "cow")

#: The demo light: from the upper right-front, casting shadows back-left.
DEMO_LIGHT_DIRECTION = (-0.55, 0.35, -1.0)


def demo_scene(mesh: trimesh.Trimesh, size: int = 512) -> Scene:
    """A normalised mesh at the origin on the ground, a directional light and a
    3/4 view camera (45 deg vertical field of view).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The object's mesh (normalised by this function).
    size : int, optional
        Side of the square image, pixels.

    Returns
    -------
    Scene
        The demo scene.
    """
    cam = perspective(np.deg2rad(40), (size, size), look_at([1.45, -1.35, 1.05], [-0.2, 0.2, 0.2]),
                      znear=0.1, zfar=20.0)
    return Scene(SceneObject(mesh), DirectionalLight(DEMO_LIGHT_DIRECTION, intensity=2.2), cam,
                 Receiver(half_size=2.0), ambient=0.3)


def ground_truth_frame(renderer: SceneRenderer, scene: Scene) -> dict[str, np.ndarray]:
    """Render ``scene`` and shadow it exactly by ray casting every visible pixel.

    Returns the images ``lit``, ``unlit``, ``depth``, ``visibility`` and ``shaded``.

    Parameters
    ----------
    renderer : SceneRenderer
        Renderer for the colour and depth images.
    scene : Scene
        Scene to render.

    Returns
    -------
    dict of str to numpy.ndarray
        Images keyed ``lit``, ``unlit``, ``depth``, ``visibility``, ``shaded``,
        each of ``scene.camera.shape`` (``depth`` float32 linear, ``+inf`` background).
    """
    return render_frame(renderer, scene, lambda pts, _n: hard_visibility(pts, scene.light, scene.obj),
                        background=SKY)


#: The object position ``(x, y)`` the warped-shadow demo shows.
WARP_POSITION = (0.23, -0.31)  # between the 3 x 3 samples


#: Soft-shadow demo: the warped-shadow light grown into a 0.6 x 0.6 area light.
SOFT_LIGHT = AreaLight(WARP_LIGHT, [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])


#: View-morphing demo: references on a circle around the object, 20 deg apart.
VIEWMORPH_BASELINE_DEG = 20.0


#: Azimuth (degrees) of the view-morphing scenes' middle view.
CENTRE_AZIMUTH = 60.0
RADIUS, HEIGHT = 2.2, 1.0
LOOK_AT = np.array([0.0, 0.0, 0.25])
def circle_camera(azimuth_deg: float, size: int) -> CameraModel:
    """The bench camera at ``azimuth_deg`` on the circle (square image of side ``size``).

    Parameters
    ----------
    azimuth_deg : float
        Azimuth about world ``+z``, degrees, ``0`` on ``+x``.
    size : int
        Image side in pixels.

    Returns
    -------
    CameraModel
        A perspective camera looking at the circle's centre.
    """
    a = np.radians(azimuth_deg)
    eye = np.array([RADIUS * np.cos(a), RADIUS * np.sin(a), HEIGHT])
    return perspective(np.radians(30.0), (size, size), look_at(eye, LOOK_AT))


def textured_items(name: str) -> tuple[Any, list[Any]]:
    """The sample mesh and its colour groups (:func:`checker_items`) as render items.

    Parameters
    ----------
    name : str
        Name of a sample mesh.

    Returns
    -------
    mesh : trimesh.Trimesh
        The sample mesh.
    items : list of Item
        Its colour groups, identity pose.
    """
    mesh = sample_mesh(name)
    return mesh, checker_items(mesh)


def render_pair(renderer: SceneRenderer, items: list[Any], cams: list[CameraModel]
                ) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(rgba, depth)`` for each camera.

    Parameters
    ----------
    renderer : SceneRenderer
        The renderer.
    items : list of Item
        Items to draw, world poses.
    cams : list of CameraModel
        One camera per view.

    Returns
    -------
    list of (rgba, depth)
        Per camera: ``(H, W, 4)`` uint8 straight-alpha RGBA and ``(H, W)``
        float32 linear depth, ``+inf`` background.
    """
    light = [DirectionalLight(np.array([-1.0, -0.5, -1.0]))]
    return [(renderer.source_view(c, items, light), renderer.depth(c, items)) for c in cams]
