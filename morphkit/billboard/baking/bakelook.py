"""The look and light of a billboard bake: its render items, lights and the hash of what it is baked from.

:func:`bake_items` draws a mesh in one of :data:`~.assetfile.APPEARANCES`:
``"own"`` (the mesh's own look, :func:`morphkit.meshes.look.mesh_look`) or
``"checker"`` (the 3-D checker of :func:`morphkit.imaging.appearance.checker_items`),
under :func:`bake_lights` with ambient :data:`BAKE_AMBIENT`. :func:`mesh_hash`
names the shape and the look an asset was baked from (:func:`look_hash`), so
the same shape with another texture is another asset. (Notes on the shading
model: :mod:`morphkit.billboard.asset`.)
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np
import trimesh

from ...errors import MeshError, ValidationError, expected_got
from ...imaging.appearance import CHECKER, PALETTE, checker_items
from ...meshes import UP_AXES, normalize
from ...meshes.look import mesh_look
from ...scene import DirectionalLight, Item, Light
from ..formats.assetfile import APPEARANCES

__all__ = ["BAKE_AMBIENT", "bake_lights", "bake_items", "mesh_hash", "look_hash", "check_appearance",
           "check_source_up", "sideways_colour"]

#: Ambient light level of the bake renders (:meth:`SceneRenderer.source_view`).
BAKE_AMBIENT = 0.35

def bake_lights() -> list[Light]:
    """The lights of the bake renders: one directional light straight down (``-z``),
    intensity 3 (yaw- and view-independent; with :data:`BAKE_AMBIENT`).

    Returns
    -------
    list of Light
        The one directional light, world (= object) frame.
    """
    return [DirectionalLight(np.array([0.0, 0.0, -1.0]), intensity=3.0)]


def check_appearance(appearance: Any) -> str:
    """``appearance`` checked: one of :data:`APPEARANCES`.

    Parameters
    ----------
    appearance : str
        ``"own"`` or ``"checker"``.

    Returns
    -------
    str
        ``appearance``.

    Raises
    ------
    ValidationError
        Anything else.
    """
    if not isinstance(appearance, str) or appearance not in APPEARANCES:
        raise ValidationError(expected_got("appearance", f"one of {list(APPEARANCES)}", repr(appearance)))
    return appearance


def check_source_up(source_up: Any) -> str | None:
    """``source_up`` checked: the up axis a mesh file was loaded with, or None (unknown).

    Parameters
    ----------
    source_up : str or None
        ``"z"`` or ``"y"`` (resolved, e.g. :func:`morphkit.meshes.resolve_up`), or None.

    Returns
    -------
    str or None
        ``source_up``.

    Raises
    ------
    ValidationError
        Anything else (``"auto"`` included: resolve it first).
    """
    if source_up is None or (isinstance(source_up, str) and source_up in UP_AXES):
        return source_up
    raise ValidationError(expected_got("source_up", f"None or one of {list(UP_AXES)} "
                                       "(resolve 'auto' with morphkit.meshes.resolve_up)", repr(source_up)))


def bake_items(mesh: trimesh.Trimesh, appearance: str = "own") -> list[Item]:
    """The render items of a bake: ``mesh`` (object frame, identity pose) in ``appearance``.
    Pass the normalised mesh (:func:`morphkit.meshes.normalize`) to match an asset's
    references (or use :meth:`BillboardAsset.items`, which checks the mesh and reads the
    asset's appearance).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The (normalised) mesh, object frame.
    appearance : {"own", "checker"}, optional
        ``"own"`` (default): one item without a colour, drawn in the mesh's own look
        (:func:`morphkit.meshes.look.mesh_look`; :data:`~morphkit.conventions.DEFAULT_COLOR`
        when it has none). ``"checker"``: the colour groups of
        :func:`morphkit.imaging.appearance.checker_items`.

    Returns
    -------
    list of Item
        Identity pose.

    Raises
    ------
    MeshError
        ``mesh`` is not a Trimesh.
    ValidationError
        An unknown ``appearance``.
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise MeshError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
    if check_appearance(appearance) == "checker":
        return checker_items(mesh)
    return [Item(mesh)]


def _update_array(h: Any, name: str, a: np.ndarray | None) -> None:
    """Feed a named array (dtype, shape and bytes) or its absence into a hash."""
    if a is None:
        h.update(f"{name}:none;".encode())
        return
    a = np.ascontiguousarray(a)
    h.update(f"{name}:{a.dtype.str}{a.shape};".encode())
    h.update(a.tobytes())


def look_hash(mesh: trimesh.Trimesh, appearance: str = "own") -> str:
    """sha256 (hex) of the look ``mesh`` is baked in: for ``"own"``, every term of
    :func:`morphkit.meshes.look.mesh_look` (base colour factor, texture bytes, UVs, vertex and
    face colours, alpha cutoff, metallic and roughness); for ``"checker"``, the checker's
    palette and cell size.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh (the look does not depend on the vertex positions).
    appearance : {"own", "checker"}, optional
        The appearance.

    Returns
    -------
    str
        64 hex digits.

    Raises
    ------
    MeshError
        Not a Trimesh, or malformed visuals (:func:`morphkit.meshes.look.mesh_look`).
    ValidationError
        An unknown ``appearance``.
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise MeshError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
    h = hashlib.sha256(f"appearance:{check_appearance(appearance)};".encode())
    if appearance == "checker":
        _update_array(h, "palette", np.asarray(PALETTE, dtype=np.float64))
        h.update(f"cell:{CHECKER!r};".encode())
        return h.hexdigest()
    look = mesh_look(mesh)
    _update_array(h, "factor", np.asarray(look.base_color, dtype=np.float64))
    _update_array(h, "texture", look.texture)
    _update_array(h, "uv", None if look.uv is None else np.round(np.asarray(look.uv, np.float64), 9) + 0.0)
    _update_array(h, "vertex_colors", look.vertex_colors)
    _update_array(h, "face_colors", look.face_colors)
    h.update(f"cutoff:{look.alpha_cutoff!r};metallic:{look.metallic!r};roughness:{look.roughness!r}".encode())
    return h.hexdigest()


def mesh_hash(mesh: trimesh.Trimesh, appearance: str = "own") -> str:
    """sha256 (hex) of what an asset is baked from: the normalised mesh's vertices (float64,
    rounded to 1e-9) and faces (int64), and its look in ``appearance`` (:func:`look_hash`).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh; it is normalised first (:func:`morphkit.meshes.normalize`), so
        the hash names the shape an asset was baked from. The rounding (1e-9 of
        the normalised size) makes a moved or rescaled copy hash alike: its
        normalisation differs from the original's in the last bits only.
    appearance : {"own", "checker"}, optional
        The look the hash covers: the same shape with another texture (``"own"``)
        hashes differently.

    Returns
    -------
    str
        64 hex digits.

    Raises
    ------
    MeshError
        Not a Trimesh, or malformed visuals.
    ValidationError
        An unknown ``appearance``.
    """
    lh = look_hash(mesh, appearance)
    norm = normalize(mesh)
    h = hashlib.sha256()
    v = np.round(np.asarray(norm.vertices, dtype=np.float64), 9) + 0.0  # + 0.0: no negative zeros
    h.update(np.ascontiguousarray(v).tobytes())
    h.update(np.ascontiguousarray(norm.faces, dtype=np.int64).tobytes())
    h.update(lh.encode())
    return h.hexdigest()


def _srgb_to_linear(c: np.ndarray) -> np.ndarray:
    """The exact sRGB decoding curve (the renderer's, :mod:`morphkit.conventions`), values in [0, 1]."""
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def sideways_colour(srgb: Any) -> np.ndarray:
    """The lit colour, in the bake's light, of an opaque surface of one stored colour whose
    normal is horizontal (at right angles to :func:`bake_lights`' light, so the light adds
    nothing): ``255 (BAKE_AMBIENT lin(c)) ^ (1 / 2.2)``, ``lin`` the sRGB decoding of the
    stored colour (a texel or a vertex colour; :mod:`morphkit.conventions`).

    Parameters
    ----------
    srgb : array_like of 3 numbers
        The stored colour, sRGB, 0..255.

    Returns
    -------
    (3,) float64
        The expected lit colour, 0..255 (not rounded).

    Examples
    --------
    >>> sideways_colour([255, 0, 0]).round(1).tolist()
    [158.2, 0.0, 0.0]
    """
    c = np.asarray(srgb, dtype=np.float64).reshape(3) / 255.0
    return 255.0 * np.clip(BAKE_AMBIENT * _srgb_to_linear(c), 0.0, 1.0) ** (1.0 / 2.2)
