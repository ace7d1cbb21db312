"""A glTF's node graph, bounded before trimesh reads the file.

trimesh walks a glTF's node graph into its scene graph and morphkit then flattens every
node into one mesh, in Python per node: a file of a million nodes ran for minutes
without a word, and nodes whose children form a cycle failed deep in trimesh's graph
walk. :func:`check_node_graph` refuses both from the file's JSON alone, before trimesh
sees the file: at most :data:`morphkit.tol.MAX_GLTF_NODES` nodes, forming trees as
glTF 2.0 requires ("no node may be a direct descendant of more than one node", so no
cycles). :func:`gltf_document` reads that JSON cheaply: a ``.gltf`` is its JSON; of a
``.glb`` only the header and the JSON chunk are read, never the binary chunk.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

from .. import tol
from ..errors import MeshError, expected_got
from .assets import read_regular

__all__ = ["GLB_MAGIC", "GLB_JSON_CHUNK", "gltf_document", "check_node_graph"]

#: The first four bytes of a binary glTF (``.glb``), glTF 2.0 section 4.4.
GLB_MAGIC = b"glTF"
#: The chunk type of a ``.glb``'s first chunk, its JSON (``"JSON"`` as a little-endian uint32).
GLB_JSON_CHUNK = 0x4E4F534A


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
