"""A small glTF village: morphkit's sample glTF scene (``samples/scenes/village.glb``).

:func:`write_village` builds it from the sample meshes (:func:`morphkit.meshes.sample_mesh`):
three meshes, a tree, a person and a box house, each at its own real size in the file's units
(metres: trees :data:`TREE_HEIGHT` tall, people :data:`PERSON_HEIGHT`, houses
:data:`HOUSE_EXTENTS`), used by several nodes each (:data:`VILLAGE_NODES`: positions, yaws and
scales varied), a ``KHR_lights_punctual`` directional light (the sun, :data:`SUN_ELEVATION_DEG`
up) and a perspective camera at :data:`CAMERA_EYE` looking at :data:`CAMERA_TARGET`. The layout
is given in morphkit's world (:mod:`morphkit.conventions`, ``+z`` up) and written ``+y`` up, as
glTF is (turned by the inverse of :data:`morphkit.meshes.Y_UP_TO_Z_UP`), so that
:func:`morphkit.scenes.gltfscene.read_gltf_scene` reads it back as laid out here.

trimesh exports the meshes and their nodes; the light and the camera are then added to the
document's JSON chunk and the ``.glb`` packed again (:func:`morphkit.scenes.gltfdata.pack_glb`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import trimesh

from ..files.fileio import write_bytes
from ..meshes import Y_UP_TO_Z_UP, sample_mesh
from ..scenes.gltfdata import pack_glb, split_glb
from ..scenes.gltfscene import KHR_LIGHTS

__all__ = ["write_village", "VILLAGE_NODES", "TREE_HEIGHT", "PERSON_HEIGHT", "HOUSE_EXTENTS",
           "SUN_AZIMUTH_DEG", "SUN_ELEVATION_DEG", "CAMERA_EYE", "CAMERA_TARGET", "CAMERA_YFOV",
           "CAMERA_ZNEAR", "CAMERA_ZFAR", "CAMERA_ASPECT", "village_meshes"]

#: Height of the village's tree (the sample tree is as tall as it is wide or less), metres.
TREE_HEIGHT = 4.0
#: Height of its person, metres.
PERSON_HEIGHT = 1.8
#: The house: a box ``(x, y, z)`` metres, 3 m tall.
HOUSE_EXTENTS = (4.0, 3.0, 3.0)

#: The nodes, in morphkit's world: ``(mesh, node name, x, y, yaw_deg, scale)``.
VILLAGE_NODES: tuple[tuple[str, str, float, float, float, float], ...] = (
    ("house", "house_a", -6.0, 5.0, 15.0, 1.0),
    ("house", "house_b", 1.0, 8.0, -10.0, 1.2),
    ("house", "house_c", 7.0, 4.0, 200.0, 0.9),
    ("tree", "tree_a", -9.0, -1.0, 0.0, 1.1),
    ("tree", "tree_b", -3.5, -4.0, 40.0, 0.8),
    ("tree", "tree_c", 4.0, -5.0, 120.0, 1.0),
    ("tree", "tree_d", 10.0, 0.5, 300.0, 1.2),
    ("person", "person_a", -1.0, 0.0, 90.0, 1.0),
    ("person", "person_b", 2.0, 1.5, 250.0, 0.9),
    ("person", "person_c", 0.5, -2.0, 10.0, 1.1),
)

#: The sun's azimuth, degrees counter-clockwise from world ``+x`` (it shines from the north-west) ...
SUN_AZIMUTH_DEG = 135.0
#: ... and its elevation above the ground, degrees.
SUN_ELEVATION_DEG = 40.0

#: The camera: eye a little above eye height south of the village, looking at its centre.
CAMERA_EYE = (0.0, -20.0, 3.0)
#: The point it looks at (world frame).
CAMERA_TARGET = (0.0, 2.0, 1.0)
#: Its vertical field of view, radians (50 degrees).
CAMERA_YFOV = float(np.radians(50.0))
#: Its near plane, metres ...
CAMERA_ZNEAR = 0.1
#: ... and its far plane.
CAMERA_ZFAR = 200.0
#: Its aspect ratio (width over height).
CAMERA_ASPECT = 16.0 / 9.0

#: Linear base colours of the meshes' materials.
_COLORS = {"house": (0.55, 0.27, 0.15, 1.0), "tree": (0.12, 0.40, 0.08, 1.0),
           "person": (0.20, 0.25, 0.60, 1.0)}

#: morphkit's world (``+z`` up) to the file's (``+y`` up).
_WORLD2FILE = Y_UP_TO_Z_UP.T


def village_meshes() -> dict[str, trimesh.Trimesh]:
    """The village's three meshes at their real sizes, ``+z`` up, standing on ``z = 0``.

    Returns
    -------
    dict
        ``"tree"``, ``"person"``, ``"house"`` -> mesh (a base-colour material each).
    """
    tree = sample_mesh("tree")
    tree.apply_scale(TREE_HEIGHT / tree.extents[2])
    person = sample_mesh("person")
    person.apply_scale(PERSON_HEIGHT / person.extents[2])
    house = trimesh.creation.box(extents=HOUSE_EXTENTS)
    house.apply_translation([0.0, 0.0, HOUSE_EXTENTS[2] / 2])
    out = {"tree": tree, "person": person, "house": house}
    for key, mesh in out.items():
        material = trimesh.visual.material.PBRMaterial(name=key, baseColorFactor=_COLORS[key])
        mesh.visual = trimesh.visual.TextureVisuals(material=material)
    return out


def _look_rotation(forward_world: np.ndarray) -> np.ndarray:
    """The 3x3 ``node2file`` rotation of a glTF camera or light (looking along its local ``-Z``,
    ``+Y`` up) that looks along ``forward_world`` (morphkit's world) with the world's ``+z`` up."""
    f = np.asarray(forward_world, dtype=np.float64)
    f = f / np.linalg.norm(f)
    z = -f  # the node's +Z points backwards
    x = np.cross([0.0, 0.0, 1.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return _WORLD2FILE[:3, :3] @ np.column_stack([x, y, z])


def _quaternion_xyzw(rot: np.ndarray) -> list[float]:
    """glTF's ``(x, y, z, w)`` unit quaternion of a rotation matrix."""
    m = np.eye(4)
    m[:3, :3] = rot
    w, x, y, z = trimesh.transformations.quaternion_from_matrix(m)
    return [float(x), float(y), float(z), float(w)]


def write_village(path: str | os.PathLike[str]) -> Path:
    """Write the village (module notes) to ``path`` as a ``.glb``, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The file; its folder must exist.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    meshes = village_meshes()
    scene = trimesh.Scene()
    for key, node, x, y, yaw, scale in VILLAGE_NODES:
        node2world = trimesh.transformations.translation_matrix([x, y, 0.0]) \
            @ trimesh.transformations.rotation_matrix(np.radians(yaw), [0.0, 0.0, 1.0]) \
            @ np.diag([scale, scale, scale, 1.0])
        node2file = _WORLD2FILE @ node2world @ Y_UP_TO_Z_UP  # the mesh is stored turned too
        if key not in scene.geometry:  # one glTF mesh per key, used by all its nodes
            turned = meshes[key].copy()
            turned.apply_transform(_WORLD2FILE)
            scene.add_geometry(turned, geom_name=key, node_name=node, transform=node2file)
        else:
            scene.graph.update(frame_from=scene.graph.base_frame, frame_to=node, geometry=key,
                               matrix=node2file)
    doc, binary = split_glb(scene.export(file_type="glb"), "the village")
    el, az = np.radians(SUN_ELEVATION_DEG), np.radians(SUN_AZIMUTH_DEG)
    towards_sun = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    eye, target = np.array(CAMERA_EYE), np.array(CAMERA_TARGET)
    nodes = doc.setdefault("nodes", [])
    nodes.append({"name": "sun", "rotation": _quaternion_xyzw(_look_rotation(-towards_sun)),
                  "extensions": {KHR_LIGHTS: {"light": 0}}})
    nodes.append({"name": "camera", "camera": 0, "translation": [float(v) for v in _WORLD2FILE[:3, :3] @ eye],
                  "rotation": _quaternion_xyzw(_look_rotation(target - eye))})
    doc["scenes"][doc.get("scene", 0)]["nodes"] += [len(nodes) - 2, len(nodes) - 1]
    doc["cameras"] = [{"name": "camera", "type": "perspective",
                       "perspective": {"yfov": CAMERA_YFOV, "znear": CAMERA_ZNEAR, "zfar": CAMERA_ZFAR,
                                       "aspectRatio": CAMERA_ASPECT}}]
    doc.setdefault("extensions", {})[KHR_LIGHTS] = {
        "lights": [{"name": "sun", "type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 3.0}]}
    doc["extensionsUsed"] = sorted({*doc.get("extensionsUsed", []), KHR_LIGHTS})
    return write_bytes(path, pack_glb(doc, binary))
