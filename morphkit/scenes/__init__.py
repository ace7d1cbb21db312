"""A user's scene, written down: the assets, their instances, the camera, the sun, the ground.

A scene is data (what a file says), read from and written to files here, and drawn by the
programs (``morphkit render SCENE``). Two kinds of file describe one:

* a JSON scene file (versioned, checked against the JSON Schema shipped with morphkit) naming
  asset files, listed or scattered instances, a camera path, a sun and the image size;
* a glTF scene (``.glb``/``.gltf``): each mesh an asset, the nodes that use it its instances,
  its directional light the sun and its camera the camera, in the file's own units.

The scene's assets are baked (or read) by the programs, not here: reading a scene file does no
rendering.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import FileFormatError, expected_got
from .camerapaths import Keyframes, NamedPath, SceneCamera
from .description import SceneAsset, SceneDescription, SceneShadows
from .jsonfile import SCHEMA_PATH, read_scene_file, write_scene_file
from .placing import Listed, Scatter, ScenePlacement
from .suns import BakeLight, DaySun, FixedSun, SceneSun

__all__ = ["load_scene", "SceneDescription", "SceneAsset", "SceneShadows", "SceneCamera", "NamedPath",
           "Keyframes", "ScenePlacement", "Listed", "Scatter", "SceneSun", "BakeLight", "FixedSun", "DaySun",
           "read_scene_file", "write_scene_file", "SCHEMA_PATH", "SCENE_SUFFIXES"]

#: The files :func:`load_scene` reads: a JSON scene file, or a glTF scene.
SCENE_SUFFIXES: tuple[str, ...] = (".json", ".glb", ".gltf")


def load_scene(path: str | os.PathLike[str]) -> SceneDescription:
    """The scene a file describes: a JSON scene file (:func:`read_scene_file`) or a glTF scene
    (:func:`morphkit.scenes.gltfscene.read_gltf_scene`), told apart by the suffix.

    Parameters
    ----------
    path : path-like
        ``.json``, ``.glb`` or ``.gltf``.

    Returns
    -------
    SceneDescription

    Raises
    ------
    FileFormatError
        Another suffix, or a file that cannot be read as one.
    ValidationError
        Values the scene cannot be.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".json":
        return read_scene_file(p)
    if suffix in (".glb", ".gltf"):
        from .gltfload import gltf_scene_description

        return gltf_scene_description(p)
    raise FileFormatError(expected_got(f"scene {p}", f"a file ending in {', '.join(SCENE_SUFFIXES)}",
                                       repr(p.suffix or p.name)))
