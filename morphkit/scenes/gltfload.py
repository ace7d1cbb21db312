"""A glTF scene as a :class:`~morphkit.scenes.description.SceneDescription`.

:func:`~morphkit.scenes.gltfscene.read_gltf_scene` reads the file (its meshes, the nodes that use
them, its sun and camera, in its own units); :func:`gltf_scene_description` makes that a scene:

* each mesh an asset of its size in the file (:attr:`SceneAsset.scale`), its nodes the instances
  (their own scales kept);
* its directional light a fixed sun, the instances casting hard shadows under it
  (:class:`~morphkit.scenes.description.SceneShadows`); without one, the light the assets are baked
  under, without shadows;
* its camera a still camera (:class:`~morphkit.scenes.camerapaths.Keyframes` of one key, its field
  of view and depth range; the image's up is world ``+z``, so a rolled camera is drawn level) for
  :data:`GLTF_STILL_FRAMES` frame, the image :data:`GLTF_IMAGE_HEIGHT` rows high at the camera's
  aspect; without one, morphkit's orbit around the instances over :data:`GLTF_ORBIT_FRAMES` frames.

What was ignored or chosen by default is in :attr:`SceneDescription.notes`, one line each (the
``render`` command prints them).
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import numpy as np

from .camerapaths import Keyframes, NamedPath
from .description import SceneAsset, SceneDescription, SceneShadows
from .gltfscene import NO_CAMERA, NO_SUN, read_gltf_scene
from .placing import Listed
from .suns import BakeLight, sun_from_light

__all__ = ["gltf_scene_description", "GLTF_STILL_FRAMES", "GLTF_ORBIT_FRAMES", "GLTF_IMAGE_HEIGHT"]

#: Frames of a glTF scene seen by its own (still) camera.
GLTF_STILL_FRAMES = 1
#: Frames of the orbit a glTF scene without a camera is seen along.
GLTF_ORBIT_FRAMES = 24
#: Rows of a glTF scene's frames (the width from its camera's aspect, else 4:3).
GLTF_IMAGE_HEIGHT = 480


def gltf_scene_description(path: str | os.PathLike[str], *, up: str = "auto") -> SceneDescription:
    """The scene a glTF file describes (the module notes).

    Parameters
    ----------
    path : path-like
        A ``.glb`` or ``.gltf`` file.
    up : {"auto", "z", "y"}, optional
        The file's up axis (:func:`~morphkit.scenes.gltfscene.read_gltf_scene`).

    Returns
    -------
    SceneDescription
        Assets holding their meshes (:attr:`SceneAsset.mesh`), listed instances, notes.

    Raises
    ------
    MeshError
        What :func:`~morphkit.scenes.gltfscene.read_gltf_scene` refuses.
    """
    p = Path(path)
    g = read_gltf_scene(p, up=up)
    said = {
        NO_SUN: "the light the assets are baked under, no shadows",
        NO_CAMERA: f"morphkit's orbit around the instances, {GLTF_ORBIT_FRAMES} frames",
    }
    notes = [f"{n}: {said[n]}" if n in said else n for n in g.notes]
    assets = tuple(SceneAsset(a.name, f"{p.name}#{a.name}", scale=a.scale, mesh=a.mesh) for a in g.assets)
    inst = g.instances
    if len(inst):  # the scene's assets carry the file's sizes: instances keep their nodes' own scales
        size = np.array([next(a.scale for a in g.assets if a.name == nm) for nm in inst.names], np.float64)
        inst = dataclasses.replace(inst, scale=inst.scale / size[inst.asset])
    if g.sun is not None:
        sun = sun_from_light(g.sun)
        shadows: SceneShadows | None = SceneShadows()
    else:
        sun, shadows = BakeLight(), None
    if g.camera is not None:
        cam = g.camera
        eye = cam.cam2world[:3, 3]
        forward = cam.cam2world[:3, 2]  # the OpenCV camera frame's z: the viewing direction
        camera: Keyframes | NamedPath = Keyframes(
            eye[None],
            (eye + forward)[None],
            yfov_deg=float(np.degrees(cam.yfov)),
            znear=cam.znear,
            zfar=cam.zfar,
        )
        aspect = cam.aspect if cam.aspect else 4.0 / 3.0
        shape = (GLTF_IMAGE_HEIGHT, max(16, int(round(GLTF_IMAGE_HEIGHT * aspect))))
        frames = GLTF_STILL_FRAMES
    else:
        camera, shape, frames = (
            NamedPath("orbit"),
            (GLTF_IMAGE_HEIGHT, GLTF_IMAGE_HEIGHT * 4 // 3),
            GLTF_ORBIT_FRAMES,
        )
    return SceneDescription(
        assets,
        Listed(inst),
        camera=camera,
        sun=sun,
        shape=shape,
        frames=frames,
        shadows=shadows,
        notes=tuple(notes),
    )
