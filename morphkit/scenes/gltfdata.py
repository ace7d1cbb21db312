"""The glTF file's own data, read without trimesh: the GLB container, node transforms, accessors.

morphkit's glTF scene reader (:mod:`morphkit.scenes.gltfscene`) reads what trimesh does not
(node transforms of camera and light nodes, ``EXT_mesh_gpu_instancing``'s accessors) from the
document itself, checked: every index in range, every number finite, every accessor within its
buffer view and buffer, every node transform invertible (:class:`~morphkit.errors.MeshError`
otherwise, with an :func:`~morphkit.errors.expected_got` message). Frames are the file's
(``node2file``: a node's frame to the file's world, ``+y`` up by glTF's rule); the turn to
morphkit's world is the reader's. The container layout is glTF 2.0 section 4.4.
"""

from __future__ import annotations

import base64
import binascii
import json
import struct
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
import trimesh

from .. import tol
from ..errors import MeshError, expected_got
from ..meshes.assets import AssetResolver, read_regular
from ..meshes.gltf import GLB_BIN_CHUNK, GLB_JSON_CHUNK, GLB_MAGIC

__all__ = ["split_glb", "pack_glb", "refuse_document", "trs_matrix", "node_matrix", "node_what",
           "world_nodes", "buffer_reader", "gltf_index", "read_accessor"]

#: Accessor component types (glTF 2.0 section 3.6.2.2): numpy type, and the divisor of a normalised integer.
_COMPONENTS: dict[int, tuple[type, float]] = {5120: (np.int8, 127.0), 5121: (np.uint8, 255.0),
                                              5122: (np.int16, 32767.0), 5123: (np.uint16, 65535.0),
                                              5125: (np.uint32, 1.0), 5126: (np.float32, 1.0)}
#: Components per element of the accessor types the reader takes.
_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}



# --------------------------------------------------------------------------
# The GLB container (glTF 2.0 section 4.4)
# --------------------------------------------------------------------------


def split_glb(data: bytes, name: str) -> tuple[dict[str, Any], bytes | None]:
    """The JSON document and the binary chunk of a ``.glb``'s bytes.

    Parameters
    ----------
    data : bytes
        The whole file.
    name : str
        The file in error messages.

    Returns
    -------
    doc : dict
        The JSON chunk, parsed.
    binary : bytes or None
        The ``BIN`` chunk, None when the file has none.

    Raises
    ------
    MeshError
        Not a binary glTF 2.0 (magic, version), a length past the end, a first chunk that is
        not JSON, JSON that does not parse or is not an object.
    """
    if len(data) < 20 or data[:4] != GLB_MAGIC:
        raise MeshError(expected_got(name, "a binary glTF 2.0 file (the magic b'glTF', a 12-byte header)",
                                     f"first bytes {data[:4]!r}"))
    version, total = struct.unpack("<II", data[4:12])
    if version != 2:
        raise MeshError(expected_got(name, "glTF container version 2", version))
    length, kind = struct.unpack("<II", data[12:20])
    if kind != GLB_JSON_CHUNK or 20 + length > min(total, len(data)):
        raise MeshError(expected_got(name, "a JSON chunk first, within the file",
                                     f"chunk type {kind:#x} of {length} bytes in a file of {len(data)}"))
    try:
        doc = json.loads(data[20:20 + length].decode())
    except (UnicodeDecodeError, ValueError) as exc:
        raise MeshError(expected_got(name, "a JSON chunk that parses", str(exc)[:120])) from exc
    if not isinstance(doc, dict):
        raise MeshError(expected_got(name, "a JSON object", type(doc).__name__))
    start = 20 + length
    if len(data) < start + 8:
        return doc, None
    blen, bkind = struct.unpack("<II", data[start:start + 8])
    if bkind != GLB_BIN_CHUNK:
        return doc, None
    return doc, data[start + 8:start + 8 + blen]


def pack_glb(doc: dict[str, Any], binary: bytes | None) -> bytes:
    """A ``.glb``'s bytes: the 12-byte header, the JSON chunk (padded with spaces to 4 bytes),
    the ``BIN`` chunk (padded with zeros).

    Parameters
    ----------
    doc : dict
        The glTF JSON.
    binary : bytes or None
        The binary buffer (buffer 0 without a URI), or None for none.

    Returns
    -------
    bytes
        The file.

    Examples
    --------
    >>> from morphkit.scenes.gltfscene import pack_glb, split_glb
    >>> data = pack_glb({"asset": {"version": "2.0"}}, b"abc")
    >>> len(data) % 4, split_glb(data, "x")
    (0, ({'asset': {'version': '2.0'}}, b'abc\\x00'))
    """
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), GLB_JSON_CHUNK) + text
    if binary is not None:
        binary = bytes(binary) + b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), GLB_BIN_CHUNK) + binary
    return GLB_MAGIC + struct.pack("<II", 2, 12 + len(chunks)) + chunks


def refuse_document(path: Path, name: str) -> NoReturn:
    """Raise the error of a file :func:`morphkit.meshes.gltf.gltf_document` found no document in.

    Parameters
    ----------
    path : pathlib.Path
        The ``.glb`` or ``.gltf`` file.
    name : str
        The file in error messages.

    Raises
    ------
    MeshError
        Always: a ``.glb``'s container error (:func:`split_glb`), or a ``.gltf``'s JSON that does
        not parse or is not an object.
    """
    data = read_regular(path, name)
    if path.suffix.lower() == ".glb":
        split_glb(data, name)  # raises, saying what is wrong
        got = "a document that is not a JSON object"
    else:
        try:
            json.loads(data.decode(errors="replace"))
            got = "JSON that is not an object"
        except ValueError as exc:
            got = f"JSON that does not parse ({str(exc)[:100]})"
    raise MeshError(expected_got(name, "a glTF 2.0 file (.gltf: a JSON object)", got))


# --------------------------------------------------------------------------
# Nodes
# --------------------------------------------------------------------------


def _numbers(value: Any, n: int, what: str) -> np.ndarray:
    """``value`` as ``n`` finite floats, else a MeshError."""
    try:
        a = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        a = np.zeros(0)
    if a.size != n or isinstance(value, (str, bytes)):
        raise MeshError(expected_got(what, f"{n} numbers", repr(value)[:60]))
    if not np.all(np.isfinite(a)):
        raise MeshError(expected_got(what, "finite numbers", repr(value)[:60]))
    return a


def _quat_matrix(q: np.ndarray, what: str) -> np.ndarray:
    """The 3x3 rotation of a glTF ``(x, y, z, w)`` quaternion (normalised; zero refused)."""
    norm = float(np.linalg.norm(q))
    if not norm > tol.ZERO:
        raise MeshError(expected_got(what, "a unit quaternion (x, y, z, w)", list(q)))
    return trimesh.transformations.quaternion_matrix(q[[3, 0, 1, 2]] / norm)[:3, :3]


def trs_matrix(translation: Any, rotation: Any, scale: Any, what: str) -> np.ndarray:
    """``T @ R @ S`` (glTF's order) as a 4x4 matrix.

    Parameters
    ----------
    translation : (3,) float
        Translation.
    rotation : (4,) float
        Unit quaternion ``(x, y, z, w)`` (glTF's order; normalised here).
    scale : (3,) float
        Scale along each axis.
    what : str
        The node (or instance) in error messages.

    Returns
    -------
    (4, 4) float64
        The transform.

    Raises
    ------
    MeshError
        A value of the wrong length, non-finite, or a zero quaternion.

    Examples
    --------
    >>> from morphkit.scenes.gltfdata import trs_matrix
    >>> trs_matrix([1, 2, 3], [0, 0, 0, 1], [2, 2, 2], "node 0")[:3].tolist()
    [[2.0, 0.0, 0.0, 1.0], [0.0, 2.0, 0.0, 2.0], [0.0, 0.0, 2.0, 3.0]]
    """
    m = np.eye(4)
    m[:3, :3] = _quat_matrix(_numbers(rotation, 4, f"rotation of {what}"), f"rotation of {what}") \
        * _numbers(scale, 3, f"scale of {what}")
    m[:3, 3] = _numbers(translation, 3, f"translation of {what}")
    return m


def node_matrix(node: dict[str, Any], what: str) -> np.ndarray:
    """A node's ``node2parent`` (file frame): its ``matrix`` (column-major) or its TRS.

    Parameters
    ----------
    node : dict
        The node's JSON.
    what : str
        The node in error messages.

    Returns
    -------
    (4, 4) float64
        The transform, affine and invertible.

    Raises
    ------
    MeshError
        Numbers missing, of the wrong count or non-finite; a matrix that is not affine; a
        singular transform (smallest singular value within :data:`morphkit.tol.REL_EQUAL` of
        zero, relative to the largest: a zero scale).
    """
    if "matrix" in node:
        m = _numbers(node["matrix"], 16, f"matrix of {what}").reshape(4, 4).T
        if not np.allclose(m[3], [0.0, 0.0, 0.0, 1.0], rtol=0.0, atol=tol.POSE_ORTHO):
            raise MeshError(expected_got(f"matrix of {what}", "an affine matrix (last row 0, 0, 0, 1)",
                                         list(m[3])))
        m[3] = [0.0, 0.0, 0.0, 1.0]
    else:
        m = trs_matrix(node.get("translation", [0, 0, 0]), node.get("rotation", [0, 0, 0, 1]),
                       node.get("scale", [1, 1, 1]), what)
    s = np.linalg.svd(m[:3, :3], compute_uv=False)
    if s[-1] <= tol.REL_EQUAL * s[0]:
        raise MeshError(expected_got(f"transform of {what}", "an invertible matrix (no zero scale)",
                                     f"singular values {np.round(s, 12).tolist()}"))
    return m


def node_what(node: dict[str, Any], i: int) -> str:
    """How messages name node ``i``: ``"node 3 'tree_a'"``, or ``"node 3"`` when it has no name.

    Parameters
    ----------
    node : dict
        The node's JSON.
    i : int
        Its index.

    Returns
    -------
    str
        The phrase.
    """
    nm = node.get("name")
    return f"node {i} {nm!r}" if isinstance(nm, str) and nm else f"node {i}"


def world_nodes(doc: dict[str, Any], name: str) -> tuple[list[tuple[int, np.ndarray]], str | None]:
    """Every node of the file's scene with its ``node2file`` (the file's world frame), parents first.

    The scene is ``doc["scene"]`` (default the first); a file without scenes takes every node that
    is no node's child as a root. The nodes must form trees
    (:func:`morphkit.meshes.gltf.check_node_graph`, called first).

    Parameters
    ----------
    doc : dict
        The glTF JSON.
    name : str
        The file in error messages.

    Returns
    -------
    nodes : list of (int, (4, 4) float64)
        ``(node index, node2file)``, each node of the scene once.
    note : str or None
        A note when the file has no scene.

    Raises
    ------
    MeshError
        A scene index or a root out of range; a node's transform refused (:func:`node_matrix`), or
        one that overflows composed with its parents'.
    """
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes")
    note = None
    if isinstance(scenes, list) and scenes:
        k = doc.get("scene", 0)
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(scenes):
            raise MeshError(expected_got(f"scene of {name}", f"an index in [0, {len(scenes)})", repr(k)))
        scene = scenes[k] if isinstance(scenes[k], dict) else {}
        roots = scene.get("nodes", [])
        if not isinstance(roots, list) or not all(isinstance(r, int) and not isinstance(r, bool)
                                                  and 0 <= r < len(nodes) for r in roots):
            raise MeshError(expected_got(f"nodes of scene {k} of {name}",
                                         f"a list of node indices in [0, {len(nodes)})", repr(roots)[:60]))
    else:
        children = {c for n in nodes if isinstance(n, dict) for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
        if roots:
            note = f"no scene: every root node taken ({len(roots)})"
    out: list[tuple[int, np.ndarray]] = []
    stack = [(r, np.eye(4)) for r in reversed(roots)]
    seen: set[int] = set()
    while stack:  # trees (check_node_graph): each node once, below its one parent
        i, parent2file = stack.pop()
        if i in seen:
            raise MeshError(expected_got(f"nodes of scene of {name}", "each node once", f"node {i} twice"))
        seen.add(i)
        node = nodes[i] if isinstance(nodes[i], dict) else {}
        what = f"{node_what(node, i)} of {name}"
        local = node_matrix(node, what)
        with np.errstate(over="ignore", invalid="ignore"):
            node2file = parent2file @ local
        if not np.all(np.isfinite(node2file)):
            raise MeshError(expected_got(f"world transform of {what}", "finite numbers",
                                         "an overflow of its parents' transforms"))
        out.append((i, node2file))
        stack.extend((c, node2file) for c in reversed(node.get("children", [])))
    return out, note


# --------------------------------------------------------------------------
# Buffers and accessors (for EXT_mesh_gpu_instancing, which trimesh does not read)
# --------------------------------------------------------------------------


def buffer_reader(doc: dict[str, Any], binary: bytes | None, resolver: AssetResolver,
                  name: str) -> Callable[[int], bytes]:
    """A function giving buffer ``k``'s bytes, each read once.

    Parameters
    ----------
    doc : dict
        The glTF JSON.
    binary : bytes or None
        A ``.glb``'s ``BIN`` chunk (buffer 0 without a URI).
    resolver : AssetResolver
        Reads a buffer given by a file name (inside the asset root only:
        :mod:`morphkit.meshes.assets`).
    name : str
        The file in error messages.

    Returns
    -------
    callable
        ``k -> bytes`` (the buffer's first ``byteLength`` bytes); it raises
        :class:`~morphkit.errors.MeshError` for an index out of range, a buffer that cannot be had
        (no URI and no ``BIN`` chunk, bad base64, a file refused or missing), or a ``byteLength``
        past its data.
    """
    cache: dict[int, bytes] = {}
    buffers = doc.get("buffers", [])

    def get(k: int) -> bytes:
        if k in cache:
            return cache[k]
        what = f"buffer {k} of {name}"
        if not isinstance(buffers, list) or not 0 <= k < len(buffers) or not isinstance(buffers[k], dict):
            raise MeshError(expected_got(what, f"a buffer index in [0, {len(buffers)})", k))
        uri = buffers[k].get("uri")
        if uri is None:
            if binary is None or k != 0:
                raise MeshError(expected_got(what, "a uri, or the .glb's BIN chunk as buffer 0", "neither"))
            data = binary
        elif isinstance(uri, str) and uri.startswith("data:"):
            head, _, body = uri.partition(",")
            try:
                data = base64.b64decode(body, validate=True) if head.endswith(";base64") else b""
            except (binascii.Error, ValueError) as exc:
                raise MeshError(expected_got(what, "a base64 data URI", str(exc)[:80])) from exc
        elif isinstance(uri, str):
            try:
                data = resolver.get(uri)
            except OSError as exc:
                raise MeshError(expected_got(what, "a readable file inside the asset root",
                                             f"{uri!r} ({exc})"[:160])) from exc
        else:
            raise MeshError(expected_got(what, "a uri string", repr(uri)[:60]))
        length = buffers[k].get("byteLength")
        if not isinstance(length, int) or isinstance(length, bool) or not 0 <= length <= len(data):
            raise MeshError(expected_got(f"byteLength of {what}", f"an integer in [0, {len(data)}]",
                                         repr(length)[:40]))
        cache[k] = data[:length]
        return cache[k]

    return get


def gltf_index(entry: dict[str, Any], key: str, n: int, what: str) -> int:
    """``entry[key]`` as an index in ``[0, n)``.

    Parameters
    ----------
    entry : dict
        A JSON object (a node, an accessor, ...).
    key : str
        The key holding the index.
    n : int
        How many there are to index.
    what : str
        The entry in error messages.

    Returns
    -------
    int
        The index.

    Raises
    ------
    MeshError
        Missing, not an integer, or out of range.
    """
    v = entry.get(key)
    if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < n:
        raise MeshError(expected_got(f"{key} of {what}", f"an integer in [0, {n})", repr(v)[:40]))
    return v


def read_accessor(doc: dict[str, Any], k: Any, types: tuple[str, ...], buffer: Callable[[int], bytes],
                  name: str) -> np.ndarray:
    """Accessor ``k``'s elements as float64 (glTF 2.0 section 3.6.2).

    Parameters
    ----------
    doc : dict
        The glTF JSON.
    k : int
        The accessor's index.
    types : tuple of str
        The accessor types taken (``"VEC3"``, ...).
    buffer : callable
        Buffer index -> bytes (:func:`buffer_reader`).
    name : str
        What refers to it, in error messages.

    Returns
    -------
    (count, width) float64
        The elements; normalised integers mapped to ``[-1, 1]`` (signed) or ``[0, 1]``; zeros
        for an accessor without a buffer view.

    Raises
    ------
    MeshError
        An index out of range; a type not in ``types``, an unknown component type; a count below 1;
        a sparse accessor (not read); offsets or a stride that are not integers or too small;
        elements past the end of the buffer view, or a view past the end of its buffer; values
        that are not finite.
    """
    accessors = doc.get("accessors", [])
    what = f"accessor {k!r} of {name}"
    if isinstance(k, bool) or not isinstance(k, int) or not isinstance(accessors, list) \
            or not 0 <= k < len(accessors) or not isinstance(accessors[k], dict):
        raise MeshError(expected_got(what, f"an accessor index in [0, {len(accessors)})", repr(k)[:40]))
    acc = accessors[k]
    kind, comp, count = acc.get("type"), acc.get("componentType"), acc.get("count")
    if kind not in types or comp not in _COMPONENTS:
        raise MeshError(expected_got(what, f"type {' or '.join(types)} of a glTF component type",
                                     f"{kind!r}, componentType {comp!r}"))
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise MeshError(expected_got(f"count of {what}", "an integer >= 1", repr(count)[:40]))
    if "sparse" in acc:
        raise MeshError(expected_got(what, "a dense accessor", "a sparse one (not read)"))
    dtype, divisor = _COMPONENTS[comp]
    width = _WIDTHS[kind]
    if "bufferView" not in acc:  # glTF: all zeros
        return np.zeros((count, width))
    views = doc.get("bufferViews", [])
    view = views[gltf_index(acc, "bufferView", len(views), what)]
    if not isinstance(view, dict):
        raise MeshError(expected_got(f"buffer view of {what}", "an object", repr(view)[:40]))
    data = buffer(gltf_index(view, "buffer", len(doc.get("buffers", [])), f"buffer view of {what}"))
    vstart, vlen = view.get("byteOffset", 0), view.get("byteLength")
    astart, stride = acc.get("byteOffset", 0), view.get("byteStride")
    item = np.dtype(dtype).itemsize * width
    stride = item if stride is None else stride
    ints = (vstart, vlen, astart, stride)
    if not all(isinstance(x, int) and not isinstance(x, bool) and x >= 0 for x in ints) or stride < item:
        raise MeshError(expected_got(f"buffer view of {what}", "non-negative integer offsets, a stride >= "
                                     f"{item}", f"offsets {vstart!r}, {astart!r}, stride {stride!r}"))
    end = astart + stride * (count - 1) + item
    if vstart + vlen > len(data) or end > vlen:
        raise MeshError(expected_got(what, f"{count} elements within its buffer view ({vlen} bytes at "
                                     f"{vstart}, of a buffer of {len(data)})",
                                     f"elements reaching byte {end} of the view"))
    raw = np.frombuffer(data, dtype=np.uint8, count=end - astart, offset=vstart + astart)
    rows = np.lib.stride_tricks.as_strided(raw, (count, item), (stride, 1))
    out = np.ascontiguousarray(rows).view(dtype).reshape(count, width).astype(np.float64)
    if acc.get("normalized") and divisor != 1.0:
        out = np.maximum(out / divisor, -1.0)
    if not np.all(np.isfinite(out)):
        raise MeshError(expected_got(what, "finite values", "NaN or infinity"))
    return out
