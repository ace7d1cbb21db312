"""Meshes: the user's (loaded, checked, normalised) and the built-in samples.

* :mod:`morphkit.meshes.loading` -- :func:`load_mesh`, :func:`check_mesh`,
  :func:`normalize` (unit size, centred, on the ground), :func:`resolve_up`
  (the up axis of a file, with the per-format table);
* :mod:`morphkit.meshes.assets` -- the files a mesh file refers to (materials, textures,
  buffers): :class:`~morphkit.meshes.assets.AssetResolver`, confined to the asset root,
  regular files only;
* :mod:`morphkit.meshes.gltf` -- a glTF's node graph bounded before trimesh reads it
  (node count, trees only);
* :mod:`morphkit.meshes.parts` -- :func:`merge_parts` (a multi-part file as one
  mesh keeping every part's look), :func:`face_base_colors`;
* :mod:`morphkit.meshes.identity` -- :func:`shape_hash` (what a baked file records of
  its mesh);
* :mod:`morphkit.meshes.samples` -- the sample meshes (:func:`sample_mesh`:
  teapot, chair, cow, tree, person) and the mesh files shipped with morphkit
  (:func:`sample_file`: a photo-textured crate).

The names are re-exported here: ``from morphkit.meshes import sample_mesh, load_mesh``.
"""

from __future__ import annotations

from .identity import shape_hash
from .loading import (
    UP_AXES,
    UP_AXIS_BY_FORMAT,
    Y_UP_TO_Z_UP,
    check_mesh,
    closed_volume,
    load_mesh,
    normalize,
    resolve_up,
)
from .parts import copy_with_look, face_base_colors, merge_parts, scene_parts
from .samples import (
    BILLBOARD_MESHES,
    SAMPLE_FILES,
    SAMPLE_MESHES,
    chair,
    cow,
    person,
    sample_file,
    sample_mesh,
    teapot,
    teapot_face_count,
    tree,
)

__all__ = [
    "SAMPLE_MESHES",
    "BILLBOARD_MESHES",
    "normalize",
    "check_mesh",
    "closed_volume",
    "load_mesh",
    "resolve_up",
    "shape_hash",
    "UP_AXES",
    "UP_AXIS_BY_FORMAT",
    "Y_UP_TO_Z_UP",
    "merge_parts",
    "scene_parts",
    "copy_with_look",
    "face_base_colors",
    "sample_mesh",
    "teapot",
    "teapot_face_count",
    "chair",
    "cow",
    "tree",
    "person",
    "SAMPLE_FILES",
    "sample_file",
]
