"""Meshes: the user's (loaded, checked, normalised) and the built-in samples.

* :mod:`morphkit.meshes.loading` -- :func:`load_mesh`, :func:`check_mesh`,
  :func:`normalize` (unit size, centred, on the ground);
* :mod:`morphkit.meshes.samples` -- the sample meshes (:func:`sample_mesh`:
  teapot, chair, cow, tree, person).

The names are re-exported here: ``from morphkit.meshes import sample_mesh, load_mesh``.
"""

from __future__ import annotations

from .loading import check_mesh, load_mesh, normalize
from .samples import (
    BILLBOARD_MESHES,
    SAMPLE_MESHES,
    chair,
    cow,
    person,
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
    "load_mesh",
    "sample_mesh",
    "teapot",
    "teapot_face_count",
    "chair",
    "cow",
    "tree",
    "person",
]
