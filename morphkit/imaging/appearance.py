"""How a mesh looks when drawn: the colours of its render items.

Today one look: :func:`checker_items`, a 3-D colour checker of the face centres
(texture for feature matching and PSNR; the renderer has no texture maps), the
look every billboard is baked with and the view-morphing scenes show.
"""

from __future__ import annotations

import numpy as np
import trimesh

from ..scene import Item

__all__ = ["PALETTE", "CHECKER", "checker_items"]


#: Colours of the 3-D checker of :func:`checker_items` (RGB in [0, 1]).
PALETTE = ((0.85, 0.3, 0.25), (0.3, 0.6, 0.85), (0.9, 0.8, 0.3), (0.35, 0.75, 0.4), (0.8, 0.8, 0.8),
           (0.55, 0.35, 0.7), (0.95, 0.55, 0.2), (0.2, 0.3, 0.35))
#: Cell size of the 3-D checker of :func:`checker_items`, scene units (meshes are normalised to size 1).
CHECKER = 0.05


def checker_items(mesh: trimesh.Trimesh) -> list[Item]:
    """``mesh`` split into colour groups by a 3-D checker of its face centres, as render items.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh, in its own frame (cells of :data:`CHECKER` scene units from the origin).

    Returns
    -------
    list of Item
        One item per colour of :data:`PALETTE` that occurs (identity pose), each a
        submesh of the faces whose centre falls in a cell of that colour: texture for
        SIFT and for PSNR (the renderer has no texture maps).
    """
    cell = np.floor(mesh.triangles_center / CHECKER).astype(np.int64)
    key = (cell[:, 0] * 7 + cell[:, 1] * 3 + cell[:, 2] * 5) % len(PALETTE)
    return [Item(mesh.submesh([np.flatnonzero(key == k)], append=True), color=PALETTE[k])
            for k in range(len(PALETTE)) if np.any(key == k)]
