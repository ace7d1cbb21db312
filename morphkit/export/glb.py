"""The binary glTF container (GLB): a mesh, images and a sidecar, written and read back.

:func:`glb_bytes` has trimesh write the mesh (its geometry, materials and textures: trimesh's glTF
exporter, ``trimesh.exchange.gltf.export_glb``) and adds, through the exporter's buffer hook, each
image as a ``bufferView`` of the one binary buffer with an ``images`` entry (``name``,
``mimeType``), the instances of a node, drawn many times, as ``EXT_mesh_gpu_instancing``
(:class:`NodeInstances`: one ``TRANSLATION``, ``ROTATION`` and ``SCALE`` accessor each, float32;
each instance's transform is applied before the node's own), a node's lower levels of detail as
``MSFT_lod`` (:class:`NodeLods`: the lower levels' nodes taken out of the scene and named in its
``ids``, the thresholds as ``extras.MSFT_screencoverage``), and the sidecar as
``extras.morphkit`` of the glTF root. :func:`read_glb` reads
a GLB's two chunks (glTF 2.0, section "GLB File Format Specification": a 12-byte header, a JSON
chunk, a BIN chunk, each 4-byte aligned) and gives the images back by name.

An image that no material uses is valid glTF (the Khronos validator lists it as unused, not as
an error): the engines' importers keep them, and morphkit's own reader finds them by name.
"""

from __future__ import annotations

import json
import os
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from trimesh.exchange.gltf import export_glb

from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import decode_image, open_regular
from ..validate import as_finite_array

__all__ = ["GlbImage", "NodeInstances", "NodeLods", "Glb", "glb_bytes", "read_glb", "SIDECAR_KEY",
           "INSTANCING", "LOD"]

#: The key of morphkit's sidecar in the glTF root's ``extras``.
SIDECAR_KEY = "morphkit"
#: The glTF extension that draws one node's mesh at many transforms.
INSTANCING = "EXT_mesh_gpu_instancing"
#: The glTF extension that names a node's lower levels of detail.
LOD = "MSFT_lod"
_MAGIC, _JSON, _BIN = 0x46546C67, 0x4E4F534A, 0x004E4942


@dataclass(frozen=True)
class GlbImage:
    """One image a GLB carries.

    Parameters
    ----------
    name : str
        Its name (unique in the file).
    data : bytes
        The encoded image (PNG).
    mime_type : str, optional
        Its media type.
    """

    name: str
    data: bytes
    mime_type: str = "image/png"


@dataclass(frozen=True)
class NodeInstances:
    """The instances of one node (``EXT_mesh_gpu_instancing``): a transform each, in the node's
    parent frame before the node's own transform.

    Parameters
    ----------
    translation : (N, 3) float
        Each instance's translation.
    rotation : (N, 4) float
        Each one's unit quaternion, ``(x, y, z, w)`` (glTF's order).
    scale : (N, 3) float
        Each one's scale.
    """

    translation: np.ndarray
    rotation: np.ndarray
    scale: np.ndarray

    def arrays(self) -> dict[str, np.ndarray]:
        """The accessors' data by attribute, float32, checked.

        Returns
        -------
        dict of str to (N, k) float32

        Raises
        ------
        ValidationError
            Shapes that do not agree, non-finite values, no instance.
        """
        out = {"TRANSLATION": as_finite_array(self.translation, "instance translations", shape=(None, 3)),
               "ROTATION": as_finite_array(self.rotation, "instance rotations", shape=(None, 4)),
               "SCALE": as_finite_array(self.scale, "instance scales", shape=(None, 3))}
        n = {len(a) for a in out.values()}
        if len(n) != 1 or 0 in n:
            raise ValidationError(expected_got("instances", "as many translations, rotations, scales",
                                               {k: len(a) for k, a in out.items()}))
        return {k: np.ascontiguousarray(a, np.float32) for k, a in out.items()}


@dataclass(frozen=True)
class NodeLods:
    """A node's lower levels of detail (``MSFT_lod``).

    Parameters
    ----------
    lower : tuple of str or None
        The nodes (by name) of the levels after the node's own, most exact first: each is taken out
        of the scene's roots (it is drawn in the node's place) and given the node's transform; None
        is a level that draws nothing (an empty node).
    coverage : tuple of float
        ``MSFT_screencoverage``: each level's least screen coverage, the node's first, decreasing;
        one per level.
    """

    lower: tuple[str | None, ...]
    coverage: tuple[float, ...]

    def __post_init__(self) -> None:
        cov = [float(c) for c in self.coverage]
        if (not self.lower or len(cov) != len(self.lower) + 1 or not all(np.isfinite(cov))
                or any(b > a for a, b in zip(cov, cov[1:], strict=False))):
            raise ValidationError(expected_got("levels of detail", "at least one lower level and a "
                                               "coverage per level, decreasing",
                                               f"{len(self.lower)} lower levels, coverage {cov}"))


def _add_lods(tree: dict[str, Any], lods: Mapping[str, NodeLods]) -> None:
    """Write ``lods`` into ``tree`` (the module notes)."""
    nodes = tree.get("nodes", [])
    index = {n.get("name"): k for k, n in enumerate(nodes)}
    roots = tree["scenes"][tree.get("scene", 0)]["nodes"]
    for name, lod in lods.items():
        if name not in index:
            raise ValidationError(expected_got("node with levels of detail", f"one of {sorted(index)}",
                                               repr(name)))
        base = nodes[index[name]]
        place = {k: base[k] for k in ("matrix", "translation", "rotation", "scale") if k in base}
        ids = []
        for low in lod.lower:
            if low is None:
                nodes.append({"name": f"{name}.none", **place})
                ids.append(len(nodes) - 1)
                continue
            if low not in index:
                raise ValidationError(expected_got("lower level of detail", f"one of {sorted(index)}",
                                                   repr(low)))
            k = index[low]
            if k in roots:
                roots.remove(k)
            for key in ("matrix", "translation", "rotation", "scale"):
                nodes[k].pop(key, None)
            nodes[k].update(place)
            ids.append(k)
        base.setdefault("extensions", {})[LOD] = {"ids": ids}
        base.setdefault("extras", {})["MSFT_screencoverage"] = [float(c) for c in lod.coverage]
    if lods:
        used = tree.setdefault("extensionsUsed", [])
        if LOD not in used:
            used.append(LOD)


def _pad4(data: bytes) -> bytes:
    return data + b"\0" * (-len(data) % 4)


def glb_bytes(geometry: trimesh.Trimesh | trimesh.Scene | None, images: Sequence[GlbImage],
              sidecar: dict[str, Any], instances: Mapping[str, NodeInstances] | None = None,
              lods: Mapping[str, NodeLods] | None = None) -> bytes:
    """A GLB of ``geometry`` (none: a scene without meshes), ``images`` and ``sidecar``.

    Parameters
    ----------
    geometry : trimesh.Trimesh, trimesh.Scene or None
        The meshes.
    images : sequence of GlbImage
        Added after the geometry's own textures, in order.
    sidecar : dict
        JSON values, written as ``extras.morphkit``.
    instances : mapping of str to NodeInstances, optional
        The nodes (by name in ``geometry``'s graph) drawn at many transforms.
    lods : mapping of str to NodeLods, optional
        The nodes (by name) with lower levels of detail.

    Returns
    -------
    bytes

    Raises
    ------
    ValidationError
        Instances or levels of detail of a node the geometry does not have.
    """
    scene = trimesh.Scene() if geometry is None else geometry
    if isinstance(scene, trimesh.Trimesh):
        scene = scene.scene()

    wanted = {name: inst.arrays() for name, inst in (instances or {}).items()}

    def add_images(buffer_items: Any, tree: dict[str, Any]) -> None:
        entries = tree.setdefault("images", [])
        for img in images:
            key = f"morphkit-image-{img.name}"
            buffer_items[key] = _pad4(img.data)
            index = list(buffer_items.keys()).index(key)
            entries.append({"name": img.name, "mimeType": img.mime_type, "bufferView": index})
        nodes = {n.get("name"): n for n in tree.get("nodes", [])}
        for name, arrays in wanted.items():
            if name not in nodes:
                raise ValidationError(expected_got("instanced node", f"one of {sorted(nodes)}", repr(name)))
            attributes = {}
            for attr, a in arrays.items():
                key = f"morphkit-instances-{name}-{attr}"
                buffer_items[key] = _pad4(a.tobytes())
                view = list(buffer_items.keys()).index(key)
                tree["accessors"][key] = {"bufferView": view, "componentType": 5126, "count": len(a),
                                          "type": "VEC3" if a.shape[1] == 3 else "VEC4"}
                attributes[attr] = list(tree["accessors"].keys()).index(key)
            nodes[name].setdefault("extensions", {})[INSTANCING] = {"attributes": attributes}
        if wanted:
            used = tree.setdefault("extensionsUsed", [])
            if INSTANCING not in used:
                used.append(INSTANCING)

    def add_sidecar(tree: dict[str, Any]) -> None:
        tree["asset"]["generator"] = "morphkit"
        _add_lods(tree, lods or {})
        tree.setdefault("extras", {})[SIDECAR_KEY] = sidecar
        for img in tree.get("images", []):  # the exact image bytes: the padding is not the image's
            name = img.get("name")
            for mine in images:
                if mine.name == name:
                    tree["bufferViews"][img["bufferView"]]["byteLength"] = len(mine.data)

    return export_glb(scene, buffer_postprocessor=add_images, tree_postprocessor=add_sidecar)


@dataclass(frozen=True)
class Glb:
    """A GLB read back (:func:`read_glb`).

    Parameters
    ----------
    tree : dict
        The glTF JSON.
    binary : bytes
        The BIN chunk (the first buffer).
    path : str
        Where it was read from (named in errors).
    """

    tree: dict[str, Any]
    binary: bytes
    path: str = ""

    @property
    def sidecar(self) -> dict[str, Any] | None:
        """``extras.morphkit`` of the root (None: a GLB morphkit did not write)."""
        extras = self.tree.get("extras")
        got = extras.get(SIDECAR_KEY) if isinstance(extras, dict) else None
        return got if isinstance(got, dict) else None

    def image_bytes(self, name: str) -> bytes:
        """The encoded image called ``name``.

        Parameters
        ----------
        name : str
            The image's name.

        Returns
        -------
        bytes

        Raises
        ------
        FileFormatError
            No such image, or one whose buffer view lies outside the binary chunk.
        """
        for img in self.tree.get("images", []):
            if isinstance(img, dict) and img.get("name") == name and "bufferView" in img:
                try:
                    view = self.tree["bufferViews"][img["bufferView"]]
                    start = int(view.get("byteOffset", 0))
                    end = start + int(view["byteLength"])
                except (KeyError, IndexError, TypeError, ValueError) as exc:
                    raise FileFormatError(expected_got(f"{self.path}: image {name!r}", "a buffer view",
                                                       f"{type(exc).__name__}: {exc}")) from exc
                if int(view.get("buffer", 0)) != 0 or end > len(self.binary) or start < 0:
                    raise FileFormatError(expected_got(f"{self.path}: image {name!r}",
                                                       f"bytes within the binary chunk ({len(self.binary)})",
                                                       f"{start}..{end}"))
                return self.binary[start:end]
        raise FileFormatError(expected_got(f"{self.path}: images", f"one named {name!r}",
                                           [i.get("name") for i in self.tree.get("images", [])]))

    def image(self, name: str) -> np.ndarray:
        """The image called ``name``, decoded (morphkit's channel order, its stored dtype).

        Parameters
        ----------
        name : str
            The image's name.

        Returns
        -------
        numpy.ndarray
        """
        return decode_image(self.image_bytes(name), f"{self.path}: image {name!r}")


def read_glb(path: str | os.PathLike[str]) -> Glb:
    """Read a GLB's JSON and binary chunks.

    Parameters
    ----------
    path : path-like
        A ``.glb`` file.

    Returns
    -------
    Glb

    Raises
    ------
    FileFormatError
        No such file, not a GLB (its magic, version or lengths), JSON that is not an object.
    """
    p = Path(path)
    if not p.is_file():
        raise FileFormatError(expected_got(f"GLB {str(p)!r}", "an existing file", "nothing there"))
    with open_regular(p, f"GLB {str(p)!r}") as f:
        data = f.read()
    what = f"GLB {str(p)!r}"
    if len(data) < 20:
        raise FileFormatError(expected_got(what, "a binary glTF (12-byte header and a JSON chunk)",
                                           f"{len(data)} bytes"))
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != _MAGIC or version != 2 or length != len(data):
        raise FileFormatError(expected_got(what, "a glTF 2.0 binary ('glTF', version 2, its length)",
                                           f"magic {magic:#x}, version {version}, length {length} of "
                                           f"{len(data)} bytes"))
    tree: Any = None
    binary = b""
    at = 12
    while at + 8 <= len(data):
        n, kind = struct.unpack_from("<II", data, at)
        chunk = data[at + 8 : at + 8 + n]
        if len(chunk) != n:
            raise FileFormatError(expected_got(what, f"a chunk of {n} bytes at {at}", f"{len(chunk)}"))
        if kind == _JSON and tree is None:
            try:
                tree = json.loads(chunk.decode("utf-8"))
            except (UnicodeDecodeError, json.JSONDecodeError) as exc:
                raise FileFormatError(expected_got(what, "a JSON chunk", f"{exc}"[:120])) from exc
        elif kind == _BIN and not binary:
            binary = chunk
        at += 8 + n + (-n % 4)
    if not isinstance(tree, dict):
        raise FileFormatError(expected_got(what, "a JSON chunk holding an object", type(tree).__name__))
    return Glb(tree, binary, str(p))
