"""Mesh loading and validation: the user's meshes, checked and normalised.

Every mesh morphkit draws passes :func:`check_mesh`; :func:`load_mesh` reads a
file and :func:`normalize` scales it to the package's unit size: uniformly
scaled so that the largest bounding-box extent is 1.0 scene unit, centred on the
origin in ``x`` and ``y`` and resting on the ground plane (``min z = 0``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from .. import tol
from ..errors import MeshError, expected_got

__all__ = ["normalize", "check_mesh", "load_mesh"]


# --------------------------------------------------------------------------
# Normalisation
# --------------------------------------------------------------------------


def normalize(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Return a normalised copy of ``mesh``: unit size, centred, on the ground.

    The copy is scaled uniformly so that the largest axis-aligned bounding-box
    extent is 1.0 scene unit, translated so that the bounding box is centred on
    the origin in ``x`` and ``y``, and translated in ``z`` so that its lowest
    vertex lies on the ground plane (``min z = 0``). The orientation is kept:
    the world is ``+z`` up (:mod:`morphkit.conventions`).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Mesh with at least one face and finite vertices. It is not modified.

    Returns
    -------
    trimesh.Trimesh
        The normalised copy.

    Raises
    ------
    MeshError
        If ``mesh`` is not a ``trimesh.Trimesh``, has no faces, has non-finite
        vertices or a bounding box smaller than ``tol.MIN_EXTENT``.

    Examples
    --------
    A 2 x 4 x 1 box centred on the origin becomes 0.5 x 1 x 0.25 (its longest
    side, ``y``, is 1), centred in ``x`` and ``y``, on the ground.

    >>> import trimesh
    >>> from morphkit.meshes import normalize
    >>> normalize(trimesh.creation.box(extents=(2.0, 4.0, 1.0))).bounds
    array([[-0.25, -0.5 ,  0.  ],
           [ 0.25,  0.5 ,  0.25]])
    """
    check_mesh(mesh, "mesh")
    out = mesh.copy()
    lo, hi = out.bounds
    extent = float(np.max(hi - lo))
    if not extent > tol.MIN_EXTENT:
        raise MeshError(
            expected_got("mesh", f"a bounding box larger than {tol.MIN_EXTENT}", f"extent {extent}")
        )
    centre = np.array([(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0, lo[2]])
    out.apply_translation(-centre)
    out.apply_scale(1.0 / extent)
    # Exact ground contact and centring despite rounding in the two steps above.
    lo, hi = out.bounds
    out.apply_translation([-(lo[0] + hi[0]) / 2.0, -(lo[1] + hi[1]) / 2.0, -lo[2]])
    return out


def check_mesh(mesh: Any, name: str) -> trimesh.Trimesh:
    """Check that ``mesh`` is a triangle mesh morphkit can draw, and return it unchanged.

    Every entry point that takes a user's mesh calls this first (:func:`load_mesh`,
    :func:`normalize`, :func:`morphkit.shadow.bake_atlas`, ...), so a bad mesh is a
    :class:`~morphkit.errors.MeshError` naming what is wrong, never a raw
    ``TypeError``/``IndexError`` later, nor an empty result (an all-collinear mesh
    bakes an empty shadow atlas).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh (any frame; not modified).
    name : str
        How the error message names it (``"mesh"``, ``"mesh file 'x.obj'"``).

    Returns
    -------
    trimesh.Trimesh
        ``mesh`` itself.

    Raises
    ------
    MeshError
        ``mesh`` is not a ``trimesh.Trimesh``; has no faces; has face indices
        outside its vertices; has NaN/inf vertex coordinates; its bounding box
        is at most ``tol.MIN_EXTENT`` (a point); all its vertices lie on one
        line (a bounding box with a zero extent, relative to the largest,
        ``tol.MESH_ZERO_LENGTH_REL``, in all but one axis); or every face has
        zero area (below ``tol.MESH_ZERO_AREA_REL`` times the largest extent
        squared).

    Examples
    --------
    A triangle whose three corners lie on one line is refused, naming the mesh:

    >>> import trimesh
    >>> from morphkit.meshes import check_mesh
    >>> line = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0]], faces=[[0, 1, 2]])
    >>> check_mesh(line, "mesh 'line'")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    morphkit.errors.MeshError: mesh 'line': expected a surface (...), got all vertices on one line
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise MeshError(expected_got(name, "a trimesh.Trimesh", type(mesh).__name__))
    faces = np.asarray(mesh.faces)
    if len(faces) == 0:
        raise MeshError(expected_got(name, "a mesh with at least one face", "0 faces"))
    v = np.asarray(mesh.vertices)
    if faces.min() < 0 or faces.max() >= len(v):
        raise MeshError(expected_got(name, f"face indices in [0, {len(v)})",
                                     f"indices up to {int(faces.max())}"))
    if not np.all(np.isfinite(v)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(v), axis=1)))
        raise MeshError(expected_got(name, "finite vertex coordinates", f"{bad} non-finite vertices"))
    used = v[np.unique(faces)]
    ext = np.sort(used.max(0) - used.min(0))
    if not ext[2] > tol.MIN_EXTENT:
        raise MeshError(expected_got(name, f"a bounding box larger than {tol.MIN_EXTENT}",
                                     f"extent {float(ext[2])}"))
    # a line: project the vertices off their principal direction (not only the
    # axis-aligned box: a diagonal line has three non-zero box extents)
    c = used - used.mean(0)
    sv = np.linalg.svd(c, compute_uv=False)
    if sv[1] <= tol.MESH_ZERO_LENGTH_REL * sv[0] or ext[1] <= tol.MESH_ZERO_LENGTH_REL * ext[2]:
        raise MeshError(expected_got(name, "a surface (a bounding box with at most one zero extent)",
                                     "all vertices on one line"))
    tri = v[faces]
    area2 = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    if not np.any(area2 / 2 > tol.MESH_ZERO_AREA_REL * ext[2] ** 2):
        raise MeshError(expected_got(name, "a surface with area", f"{len(faces)} faces of zero area"))
    return mesh


# --------------------------------------------------------------------------
# Loading and lookup
# --------------------------------------------------------------------------


def load_mesh(path: str | Path) -> trimesh.Trimesh:
    """Load a mesh file and return it normalised (see :func:`normalize`).

    Any format trimesh reads (OBJ, PLY, STL, GLB/GLTF, OFF, ...) is accepted;
    a file holding a scene is flattened into one mesh with every node's
    transform applied. The file's axes are kept: morphkit's world is ``+z``
    up, so a ``+y``-up file (e.g. glTF) has to be rotated by the caller.

    Parameters
    ----------
    path : str or pathlib.Path
        Path of the file; the format is taken from its extension.

    Returns
    -------
    trimesh.Trimesh
        The normalised mesh.

    Raises
    ------
    MeshError
        If the file does not exist, cannot be read or has an unsupported
        format, holds no triangles (e.g. a point cloud), or has non-finite
        vertex coordinates.
    """
    p = Path(path)
    if not p.is_file():
        why = "a directory" if p.is_dir() else "file not found"
        raise MeshError(expected_got("mesh path", "an existing mesh file", f"{str(p)!r} ({why})"))
    try:
        # process=False: trimesh's processing would silently drop non-finite vertices.
        loaded = trimesh.load(str(p), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types for bad files
        raise MeshError(
            expected_got(f"mesh file {str(p)!r}", "a file trimesh can read",
                         f"{type(exc).__name__}: {exc}"[:200])
        ) from exc
    if isinstance(loaded, trimesh.Scene):  # force="mesh" leaves empty scenes as scenes
        loaded = loaded.to_geometry() if len(loaded.geometry) else None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError(
            expected_got(f"mesh file {str(p)!r}", "a mesh with at least one face", "0 faces")
        )
    check_mesh(loaded, f"mesh file {str(p)!r}")
    loaded.merge_vertices()  # formats like OBJ/STL split vertices per face or per normal
    return normalize(loaded)
