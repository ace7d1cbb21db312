"""A mesh's identity: the hash of its shape, which a baked file records to find its mesh again.

:func:`shape_hash` covers the vertices (float64, rounded to 1e-9 units) and the faces (int64)
of the mesh as given -- its frame, its scale, its triangle order -- and nothing of its look:
two loads of one file hash alike, and so does a copy whose vertices differ in the last bits
only (the rounding); another mesh, or the same mesh moved or scaled, does not.
"""

from __future__ import annotations

import hashlib

import numpy as np
import trimesh

from .loading import check_mesh

__all__ = ["shape_hash", "HASH_DECIMALS"]

#: Decimals the vertices are rounded to before hashing (1e-9 units).
HASH_DECIMALS = 9


def shape_hash(mesh: trimesh.Trimesh) -> str:
    """sha256 (hex) of a mesh's shape: its vertices (rounded to
    :data:`~morphkit.meshes.identity.HASH_DECIMALS` decimals) and faces.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh as used (e.g. the normalised mesh an atlas was baked from).

    Returns
    -------
    str
        64 hex digits.

    Raises
    ------
    MeshError
        Not a usable mesh (:func:`morphkit.meshes.check_mesh`).

    Examples
    --------
    >>> import trimesh
    >>> from morphkit.meshes import shape_hash
    >>> box = trimesh.creation.box()
    >>> shape_hash(box) == shape_hash(box.copy()), shape_hash(box) == shape_hash(box.copy().apply_scale(2.0))
    (True, False)
    """
    m = check_mesh(mesh, "mesh")
    h = hashlib.sha256()
    v = np.round(np.asarray(m.vertices, dtype=np.float64), HASH_DECIMALS) + 0.0  # + 0.0: no -0.0
    h.update(np.ascontiguousarray(v).tobytes())
    h.update(np.ascontiguousarray(m.faces, dtype=np.int64).tobytes())
    return h.hexdigest()
