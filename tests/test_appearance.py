"""Tests of morphkit.imaging.appearance: the 3-D checker colouring of a mesh's faces."""

from __future__ import annotations

import numpy as np
import trimesh

from morphkit.imaging.appearance import CHECKER, PALETTE, checker_items
from morphkit.meshes import sample_mesh


def test_checker_items_partition_the_faces_by_cell_colour():
    mesh = sample_mesh("chair")
    items = checker_items(mesh)
    assert 1 < len(items) <= len(PALETTE)
    assert sum(len(it.mesh.faces) for it in items) == len(mesh.faces)  # every face once
    colours = [tuple(it.color[:3]) for it in items]
    assert len(set(colours)) == len(items) and set(colours) <= {tuple(c) for c in PALETTE}
    for it in items:  # every face of an item lies in a cell of the item's colour
        cell = np.floor(it.mesh.triangles_center / CHECKER).astype(np.int64)
        key = (cell[:, 0] * 7 + cell[:, 1] * 3 + cell[:, 2] * 5) % len(PALETTE)
        assert np.all(key == key[0]) and PALETTE[key[0]] == tuple(it.color[:3])
        np.testing.assert_array_equal(it.pose, np.eye(4))


def test_a_mesh_inside_one_cell_is_one_colour():
    box = trimesh.creation.box(extents=[0.01, 0.01, 0.01])
    box.apply_translation([0.025, 0.025, 0.025])  # inside the cell [0, 0.05)^3
    items = checker_items(box)
    assert len(items) == 1 and len(items[0].mesh.faces) == 12
    assert tuple(items[0].color[:3]) == PALETTE[0]
