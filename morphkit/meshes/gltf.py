"""A glTF's node graph, bounded before trimesh reads the file.

trimesh walks a glTF's node graph into its scene graph and morphkit then flattens every
node into one mesh, in Python per node: a file of a million nodes ran for minutes
without a word, and nodes whose children form a cycle failed deep in trimesh's graph
walk. :func:`check_node_graph` refuses both from the file's JSON alone, before trimesh
sees the file: at most :data:`morphkit.tol.MAX_GLTF_NODES` nodes, forming trees as
glTF 2.0 requires ("no node may be a direct descendant of more than one node", so no
cycles). :func:`gltf_document` reads that JSON cheaply: a ``.gltf`` is its JSON; of a
``.glb`` only the header and the JSON chunk are read, never the binary chunk.

:func:`embedded_images` gives the bytes of the images a glTF stores in itself (data URIs,
buffer views), so that the loader can check them as it checks image files: trimesh drops an
image it cannot decode without a word.
"""

from __future__ import annotations

import base64
import binascii
import json
import struct
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import unquote_to_bytes

from .. import tol
from ..errors import MeshError, expected_got
from .assets import read_regular

__all__ = ["GLB_MAGIC", "GLB_JSON_CHUNK", "GLB_BIN_CHUNK", "gltf_document", "check_node_graph",
           "embedded_images"]

#: The first four bytes of a binary glTF (``.glb``), glTF 2.0 section 4.4.
GLB_MAGIC = b"glTF"
#: The chunk type of a ``.glb``'s first chunk, its JSON (``"JSON"`` as a little-endian uint32).
GLB_JSON_CHUNK = 0x4E4F534A
#: The chunk type of a ``.glb``'s binary chunk (``"BIN"`` and a zero byte, as a little-endian uint32).
GLB_BIN_CHUNK = 0x004E4942


def gltf_document(path: Path, name: str) -> dict[str, Any] | None:
    """The JSON document of a ``.gltf`` or ``.glb`` file; None when it has none to read.

    Parameters
    ----------
    path : pathlib.Path
        The file (``.gltf``: read whole; ``.glb``: its 12-byte header, the first chunk's
        8-byte header and that chunk only).
    name : str
        The file in error messages.

    Returns
    -------
    dict or None
        The document; None for a file that is not valid glTF JSON (a truncated header, a
        first chunk that is not JSON, bad JSON), which trimesh's own error then reports.

    Raises
    ------
    MeshError
        The file is not a regular file or cannot be read.
    """
    if path.suffix.lower() == ".glb":
        try:
            with open(path, "rb") as f:
                head = f.read(20)
                if len(head) < 20 or head[:4] != GLB_MAGIC:
                    return None
                length, kind = struct.unpack("<II", head[12:20])
                if kind != GLB_JSON_CHUNK:
                    return None
                text = f.read(length)
        except OSError as exc:
            raise MeshError(expected_got(name, "a readable file", exc.strerror or exc)) from exc
    else:
        text = read_regular(path, name)
    try:
        doc = json.loads(text.decode(errors="replace"))
    except ValueError:
        return None
    return doc if isinstance(doc, dict) else None


def check_node_graph(doc: dict[str, Any], name: str) -> int:
    """Refuse a glTF document whose nodes are too many or do not form trees; return their count.

    Parameters
    ----------
    doc : dict
        The glTF JSON (:func:`gltf_document`).
    name : str
        The file in error messages.

    Returns
    -------
    int
        The number of nodes.

    Raises
    ------
    MeshError
        More than :data:`morphkit.tol.MAX_GLTF_NODES` nodes; ``nodes`` or a node's
        ``children`` that is not a list, or a child that is not a node's index; a node that is
        the child of two nodes (or twice of one) or of itself, or nodes whose children form a
        cycle.
    """
    nodes = doc.get("nodes", [])
    if not isinstance(nodes, list):
        raise MeshError(expected_got(f"nodes of {name}", "a list", type(nodes).__name__))
    n = len(nodes)
    if n > tol.MAX_GLTF_NODES:
        raise MeshError(expected_got(f"nodes of {name}", f"at most {tol.MAX_GLTF_NODES} "
                                     "(tol.MAX_GLTF_NODES)", f"{n} nodes"))
    trees = "nodes forming trees (glTF 2.0: no node is a child of two nodes, no cycles)"
    parent = [-1] * n
    children: list[list[int]] = [[] for _ in range(n)]
    for i, node in enumerate(nodes):
        kids = node.get("children", []) if isinstance(node, dict) else []
        if not isinstance(kids, list):
            raise MeshError(expected_got(f"node {i} of {name}", "a list of children",
                                         type(kids).__name__))
        for c in kids:
            if isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < n:
                raise MeshError(expected_got(f"node {i} of {name}", f"children that are node indices in "
                                             f"[0, {n})", repr(c)[:40]))
            if c == i or parent[c] != -1:
                why = "itself" if c == i else f"node {parent[c]} and node {i}"
                raise MeshError(expected_got(f"nodes of {name}", trees, f"node {c} a child of {why}"))
            parent[c] = i
            children[i].append(c)
    seen = [False] * n
    stack = [i for i in range(n) if parent[i] == -1]
    for i in stack:
        seen[i] = True
    while stack:  # every node below a root; what is left lies on a cycle (each has one parent)
        for c in children[stack.pop()]:
            seen[c] = True
            stack.append(c)
    left = [i for i in range(n) if not seen[i]]
    if left:
        path = [left[0]]  # up its parents until one repeats: from there on, the cycle
        while parent[path[-1]] not in path:
            path.append(parent[path[-1]])
        cycle = path[path.index(parent[path[-1]]):][::-1]  # parent before child
        k = cycle.index(min(cycle))
        cycle = cycle[k:] + cycle[:k]  # from its lowest index
        ring = " -> ".join(map(str, [*cycle, cycle[0]][:9])) + (" -> ..." if len(cycle) > 8 else "")
        raise MeshError(expected_got(f"nodes of {name}", trees, f"a cycle of children {ring}"))
    return n


def _data_uri(uri: str) -> bytes | None:
    """The bytes of a ``data:`` URI (base64 or percent-encoded); None when they cannot be decoded."""
    head, _, body = uri.partition(",")
    if head.endswith(";base64"):
        try:
            return base64.b64decode(body, validate=True)
        except (binascii.Error, ValueError):
            return None
    return unquote_to_bytes(body)


def _glb_binary(path: Path, name: str) -> bytes | None:
    """The binary chunk of a ``.glb`` (after its JSON chunk); None when it has none."""
    data = read_regular(path, name)
    if len(data) < 20 or data[:4] != GLB_MAGIC:
        return None
    start = 20 + struct.unpack("<I", data[12:16])[0]
    if len(data) < start + 8:
        return None
    length, kind = struct.unpack("<II", data[start:start + 8])
    return data[start + 8:start + 8 + length] if kind == GLB_BIN_CHUNK else None


def embedded_images(path: Path, doc: dict[str, Any], name: str,
                    external: Callable[[str], bytes | None]) -> dict[int, tuple[str, bytes | None]]:
    """The images a glTF document stores in the file: those given by a ``data:`` URI or a buffer view.

    Parameters
    ----------
    path : pathlib.Path
        The ``.gltf`` or ``.glb`` file (a ``.glb``'s binary chunk is its buffer without a URI).
    doc : dict
        Its JSON (:func:`gltf_document`).
    name : str
        The file in error messages.
    external : callable
        The bytes of a buffer given by a file name (the mesh's resolver), or None when it
        cannot be had.

    Returns
    -------
    dict
        Image index -> ``(where, data)``: where it is stored (``"a data URI"``, ``"buffer view
        3"``) and its bytes, or None when they cannot be taken out (bad base64, a view past
        the end of its buffer, a buffer that cannot be read). Images given by a file name,
        and entries too malformed to say where they are, are left out (trimesh's error, or
        the loader's check of image files, follows).

    Raises
    ------
    MeshError
        A ``.glb`` that cannot be read.
    """
    images, views, buffers = (doc.get(k) for k in ("images", "bufferViews", "buffers"))
    if not isinstance(images, list):
        return {}
    loaded: dict[int, bytes | None] = {}

    def buffer(k: int) -> bytes | None:
        if k not in loaded:
            entry = buffers[k] if isinstance(buffers, list) and 0 <= k < len(buffers) else None
            uri = entry.get("uri") if isinstance(entry, dict) else None
            if isinstance(uri, str):
                loaded[k] = _data_uri(uri) if uri.startswith("data:") else external(uri)
            else:
                loaded[k] = _glb_binary(path, name) if path.suffix.lower() == ".glb" and k == 0 else None
        return loaded[k]

    out: dict[int, tuple[str, bytes | None]] = {}
    for i, img in enumerate(images):
        if not isinstance(img, dict):
            continue
        uri, view = img.get("uri"), img.get("bufferView")
        if isinstance(uri, str) and uri.startswith("data:"):
            out[i] = ("a data URI", _data_uri(uri))
        elif isinstance(view, int) and isinstance(views, list) and 0 <= view < len(views) \
                and isinstance(views[view], dict):
            v = views[view]
            k, offset, length = v.get("buffer"), v.get("byteOffset", 0), v.get("byteLength")
            if not all(isinstance(x, int) and not isinstance(x, bool) for x in (k, offset, length)):
                continue
            data = buffer(k)
            ok = data is not None and 0 <= offset and 0 < length and offset + length <= len(data)
            out[i] = (f"buffer view {view}", data[offset:offset + length] if ok else None)
    return out
