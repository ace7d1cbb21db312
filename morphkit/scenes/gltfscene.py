"""A glTF file read as a scene: each mesh an asset, each node that uses it an instance.

:func:`read_gltf_scene` reads a ``.glb``/``.gltf`` into pure data (:class:`GltfScene`; no
rendering): the meshes the nodes use, each normalised as :func:`morphkit.meshes.normalize` does
(:class:`GltfAsset`, with the factor back to the file's units), one billboard instance per node
that uses a mesh and per entry of its ``EXT_mesh_gpu_instancing``
(:class:`~morphkit.billboard.frames.instances.Instances`, in the file's own units: no asset is
normalised inside the scene), the first directional ``KHR_lights_punctual`` light as the sun and the first
perspective camera (:class:`GltfCamera`). What the file holds but morphkit does not draw
(skins, animations, point and spot lights, tilts, non-uniform scales) is listed in
:attr:`GltfScene.notes`, one line each.

Frames follow :mod:`morphkit.conventions`: the file is turned ``+z`` up as
:func:`morphkit.meshes.load_mesh` turns it (:data:`morphkit.meshes.Y_UP_TO_Z_UP`, ``up=`` as
:func:`morphkit.meshes.resolve_up`), and the same turn applies to node transforms, light and
camera. An instance's ``object2world`` (:mod:`morphkit.billboard.frames.instances`) puts the
normalised mesh where the node puts the file's mesh, but for what an instance cannot hold:

* **tilt**: the node's rotation is reduced to its twist about world ``+z`` (the yaw,
  ``atan2(R10 - R01, R00 + R11)``, the swing-twist decomposition's angle); a swing beyond
  :data:`morphkit.tol.POSE_ORTHO` is dropped, with a note;
* **non-uniform scale**: the mean of the node's world scales (its singular values) is kept, with a
  note when they differ by more than :data:`morphkit.tol.POSE_ORTHO` of the largest; a mirroring
  node's mirror is dropped, with a note;
* **height**: the base (the centre of the bottom of the asset's box) is set on ``z = 0``; a base
  further off than :data:`morphkit.tol.GLTF_GROUND_REL` of the asset's size is noted.

The file is bounded and checked as :func:`morphkit.meshes.load_mesh` checks it: its node graph
(:func:`morphkit.meshes.gltf.check_node_graph`) before trimesh reads it, every file it refers to
through the asset resolver (:mod:`morphkit.meshes.assets`), its images
(:func:`morphkit.meshes.loading.gltf_warnings`). trimesh reads the meshes only: it is given a copy
of the document whose nodes are one per used mesh, so a file's camera nodes, instancing and node
count never reach its scene graph.
"""

from __future__ import annotations

import io
import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from .. import settings, tol
from ..billboard import Instances
from ..camera import CameraModel, perspective
from ..conventions import cv_pose_from_gl
from ..errors import MeshError, expected_got
from ..meshes import Y_UP_TO_Z_UP, check_mesh, merge_parts, normalize, resolve_up
from ..meshes import assets as asset_files
from ..meshes.assets import AssetResolver, read_regular
from ..meshes.gltf import check_node_graph, gltf_document
from ..meshes.loading import check_parts, gltf_warnings, loaded_looks, trimesh_load
from ..scene import DirectionalLight
from ..sunpath import SUN_INTENSITY
from .gltfdata import (
    buffer_reader,
    gltf_index,
    node_matrix,
    node_what,
    pack_glb,
    read_accessor,
    refuse_document,
    split_glb,
    world_nodes,
)

__all__ = ["GltfAsset", "GltfCamera", "GltfScene", "read_gltf_scene", "EXT_INSTANCING", "KHR_LIGHTS",
           "ZFAR_BOUNDS_FACTOR", "ZFAR_MIN_RATIO", "NO_SUN", "NO_CAMERA"]

#: The glTF extension of instanced meshes (per-instance TRANSLATION, ROTATION, SCALE accessors).
EXT_INSTANCING = "EXT_mesh_gpu_instancing"
#: The glTF extension of lights (directional, point, spot).
KHR_LIGHTS = "KHR_lights_punctual"
#: The note of a file without a directional light (:attr:`GltfScene.sun` None; the caller says
#: its default).
NO_SUN = f"no directional light ({KHR_LIGHTS})"
#: The note of a file without a perspective camera (:attr:`GltfScene.camera` None; the caller
#: says its default).
NO_CAMERA = "no perspective camera"

#: A camera without ``zfar`` (infinite in glTF) gets this many times the distance from the camera to
#: the farthest corner of the scene's instance boxes ...
ZFAR_BOUNDS_FACTOR = 2.0
#: ... and at least this many times its ``znear`` (a scene without meshes, or behind the camera).
ZFAR_MIN_RATIO = 1e3

#: The metadata key the reader tags each glTF mesh's primitives with in the copy trimesh reads.
_MESH_TAG = "morphkit_gltf_mesh"

# --------------------------------------------------------------------------
# The data
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class GltfAsset:
    """One glTF mesh (all its primitives, with their look) that some node uses.

    Parameters
    ----------
    name : str
        The glTF mesh name, made distinct and non-empty (``mesh<index>`` when it has none).
    mesh : trimesh.Trimesh
        The mesh, ``+z`` up and normalised (:func:`morphkit.meshes.normalize`: largest extent 1,
        centred in ``x``/``y``, on ``z = 0``), with its textures, material and vertex colours as
        :func:`morphkit.meshes.load_mesh` keeps them.
    scale : float
        The factor back to the file's units: the mesh's largest extent in the file, in its own
        frame (before any node's scale).
    """

    name: str
    mesh: trimesh.Trimesh
    scale: float


@dataclass(frozen=True, eq=False)
class GltfCamera:
    """A glTF perspective camera, in morphkit's world and camera frames.

    Parameters
    ----------
    cam2world : (4, 4) float64
        ``cam_cv2world`` (:mod:`morphkit.conventions`), rigid: a node scale is dropped.
    yfov : float
        Vertical field of view, radians.
    znear, zfar : float
        Depth range, scene (file) units; a file without ``zfar`` gets a finite one
        (:func:`read_gltf_scene`).
    aspect : float or None
        The file's ``aspectRatio`` (width over height), None when it has none; :meth:`model`
        keeps ``yfov`` and takes the aspect of the shape it is given, as glTF viewers do.
    """

    cam2world: np.ndarray = field(repr=False)
    yfov: float
    znear: float
    zfar: float
    aspect: float | None = None

    def __post_init__(self) -> None:
        pose = np.array(self.cam2world, dtype=np.float64)
        pose.setflags(write=False)
        object.__setattr__(self, "cam2world", pose)

    def model(self, shape: tuple[int, int]) -> CameraModel:
        """The camera for images of ``shape`` (:func:`morphkit.camera.perspective`).

        Parameters
        ----------
        shape : (H, W)
            Image shape in pixels.

        Returns
        -------
        CameraModel
            A perspective camera with this vertical field of view, pose and depth range.

        Examples
        --------
        >>> import numpy as np
        >>> from morphkit.scenes.gltfscene import GltfCamera
        >>> cam = GltfCamera(np.eye(4), np.pi / 2, 0.1, 100.0).model((480, 640))
        >>> round(cam.fy, 9), cam.zfar
        (240.0, 100.0)
        """
        return perspective(self.yfov, shape, self.cam2world, znear=self.znear, zfar=self.zfar)


@dataclass(frozen=True, eq=False)
class GltfScene:
    """A glTF file read as a scene (:func:`read_gltf_scene`).

    Parameters
    ----------
    assets : tuple of GltfAsset
        One per glTF mesh some node uses, in the order of the file's meshes.
    instances : morphkit.billboard.Instances
        One per node that uses a mesh (per entry of its ``EXT_mesh_gpu_instancing``);
        ``instances.names`` are the assets' names, the scales in the file's units.
    sun : morphkit.scene.DirectionalLight or None
        The first directional light a node uses (nodes taken depth first, in the scene's order),
        or None.
    camera : GltfCamera or None
        The first perspective camera a node uses (in the same order), or None.
    notes : tuple of str
        One line for each thing ignored or defaulted.
    """

    assets: tuple[GltfAsset, ...]
    instances: Instances
    sun: DirectionalLight | None
    camera: GltfCamera | None
    notes: tuple[str, ...] = ()


def _instancing(ext: Any, doc: dict[str, Any], buffer: Callable[[int], bytes], what: str) -> list[np.ndarray]:
    """The per-instance ``instance2node`` transforms of a node's ``EXT_mesh_gpu_instancing``."""
    attrs = ext.get("attributes") if isinstance(ext, dict) else None
    if not isinstance(attrs, dict) or not attrs:
        raise MeshError(expected_got(f"{EXT_INSTANCING} of {what}",
                                     "attributes (TRANSLATION, ROTATION, SCALE)", repr(attrs)[:60]))
    got = {key: read_accessor(doc, attrs[key], types, buffer, what)
           for key, types in (("TRANSLATION", ("VEC3",)), ("ROTATION", ("VEC4",)), ("SCALE", ("VEC3",)))
           if key in attrs}
    counts = {len(a) for a in got.values()}
    if len(counts) != 1:
        counted = {k: len(a) for k, a in got.items()} or "none of TRANSLATION, ROTATION, SCALE"
        raise MeshError(expected_got(f"{EXT_INSTANCING} of {what}", "accessors of one count", counted))
    n = counts.pop()
    t = got.get("TRANSLATION", np.zeros((n, 3)))
    r = got.get("ROTATION", np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)))
    s = got.get("SCALE", np.ones((n, 3)))
    return [node_matrix({"translation": t[j], "rotation": r[j], "scale": s[j]}, f"instance {j} of {what}")
            for j in range(n)]


# --------------------------------------------------------------------------
# Meshes, through trimesh
# --------------------------------------------------------------------------


def _mesh_parts(p: Path, doc: dict[str, Any], binary: bytes | None, used: list[int], resolver: AssetResolver,
                name: str, warned: bool) -> dict[int, list[trimesh.Trimesh]]:
    """The triangle primitives of the glTF meshes ``used``, read by trimesh from a copy of the document
    with one plain node per used mesh (each primitive tagged with its mesh's index)."""
    meshes = doc.get("meshes", [])
    copy = {k: v for k, v in doc.items() if k not in ("nodes", "scenes", "scene", "skins", "animations",
                                                      "cameras", "extensionsRequired")}
    copy["meshes"] = [dict(m) if isinstance(m, dict) else m for m in meshes]
    for i in used:
        extras = copy["meshes"][i].get("extras")
        copy["meshes"][i]["extras"] = {**(extras if isinstance(extras, dict) else {}), _MESH_TAG: i}
    copy["nodes"] = [{"mesh": i} for i in used]
    copy["scenes"], copy["scene"] = [{"nodes": list(range(len(used)))}], 0
    if p.suffix.lower() == ".glb":
        source, kind = io.BytesIO(pack_glb(copy, binary)), "glb"
    else:
        source, kind = io.BytesIO(json.dumps(copy).encode()), "gltf"
    loaded = trimesh_load(source, name, resolver, file_type=kind)
    loaded_looks(loaded, name, {}, warned)
    geoms = loaded.geometry.values() if isinstance(loaded, trimesh.Scene) else [loaded]
    parts: dict[int, list[trimesh.Trimesh]] = {i: [] for i in used}
    for g in geoms:
        tag = getattr(g, "metadata", {}).get(_MESH_TAG)
        if isinstance(g, trimesh.Trimesh) and len(g.faces) and tag in parts:
            parts[tag].append(g)
    return parts


def _asset_names(doc: dict[str, Any], used: list[int]) -> dict[int, str]:
    """Distinct, non-empty names of the used meshes: their glTF names, else ``mesh<index>``."""
    meshes = doc.get("meshes", [])
    out: dict[int, str] = {}
    taken: set[str] = set()
    for i in used:
        nm = meshes[i].get("name") if isinstance(meshes[i], dict) else None
        base = nm.strip() if isinstance(nm, str) and nm.strip() else f"mesh{i}"
        cand, k = base, 1
        while cand in taken:
            cand, k = f"{base}_{k}", k + 1
        taken.add(cand)
        out[i] = cand
    return out


# --------------------------------------------------------------------------
# The reader
# --------------------------------------------------------------------------


def _said(what: str, names: list[str]) -> str:
    """``"3 nodes tilted ... ('a', 'b', 'c')"``: a count and the first few names."""
    shown = ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")
    return f"{len(names)} {what} ({shown})"


def _rotation(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
    """The rotation of the 3x3 ``a`` (its polar factor), its singular values, and whether ``a``
    mirrors: then the rotation is that of ``a`` with the mirror across its frame's ``x``-``z`` plane
    undone first (a mesh facing ``+x`` shown unmirrored, still upright)."""
    mirror = bool(np.linalg.det(a) < 0)
    u, s, vt = np.linalg.svd(a @ np.diag([1.0, -1.0, 1.0]) if mirror else a)
    return u @ vt, s, mirror


def read_gltf_scene(path: str | Path, *, up: str = "auto",
                    asset_root: str | os.PathLike[str] | None = None) -> GltfScene:
    """Read a ``.glb``/``.gltf`` file as a scene of assets, instances, a sun and a camera.

    The rules (frames, what an instance keeps of a node, the checks) are in the module notes.
    The sun's intensity is :data:`morphkit.sunpath.SUN_INTENSITY`, morphkit's default sun: glTF's
    lux do not map onto morphkit's (pyrender's) light units, so the file's intensity and colour
    are not used. A camera without ``zfar`` (infinite) gets :data:`ZFAR_BOUNDS_FACTOR` times the
    distance from the camera to the farthest corner of the instances' boxes, at least
    :data:`ZFAR_MIN_RATIO` times its ``znear``. A file without meshes is not an error: no assets,
    no instances, and a note.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.glb`` or ``.gltf`` file.
    up : {"auto", "z", "y"}, optional
        The file's up axis (:func:`morphkit.meshes.resolve_up`; ``"auto"`` is glTF's ``+y``).
    asset_root : str or os.PathLike, optional
        The folder every file the glTF refers to must lie in, as ``asset_root`` of
        :func:`morphkit.meshes.load_mesh`; default :data:`morphkit.settings.ASSET_ROOT`, else the
        file's folder.

    Returns
    -------
    GltfScene
        The scene, in morphkit's world frame and the file's units.

    Raises
    ------
    MeshError
        ``up`` unknown; the file missing, not a ``.glb``/``.gltf``, not glTF 2.0, or of broken JSON;
        nodes too many or not trees (:func:`morphkit.meshes.gltf.check_node_graph`); a node's
        matrix, TRS or instance transform non-finite or singular, alone or composed with its
        parents'; a mesh, camera or light index out of range; an accessor out of range of its
        buffer; a camera's ``yfov``, ``znear`` or ``zfar`` out of range; what
        :func:`morphkit.meshes.load_mesh` refuses of its meshes.

    Warns
    -----
    AssetWarning
        An image that cannot be drawn (as :func:`morphkit.meshes.load_mesh`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from morphkit.scenes.gltfscene import pack_glb, read_gltf_scene
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "empty.glb").write_bytes(pack_glb({"asset": {"version": "2.0"}}, None))
    >>> scene = read_gltf_scene(folder / "empty.glb")
    >>> len(scene.assets), len(scene.instances), scene.sun, scene.camera
    (0, 0, None, None)
    >>> scene.notes[0]
    'no meshes: the scene is empty'
    """
    p = Path(path)
    axis = resolve_up(p, up)
    name = f"glTF file {str(p)!r}"
    if not p.is_file():
        why = "a directory" if p.is_dir() else "file not found"
        raise MeshError(expected_got("glTF path", "an existing glTF file", f"{str(p)!r} ({why})"))
    if p.suffix.lower() not in (".glb", ".gltf"):
        raise MeshError(expected_got(name, "a .glb or .gltf file", f"the extension {p.suffix!r}"))
    doc = gltf_document(p, name)
    if doc is None:
        refuse_document(p, name)
    check_node_graph(doc, name)  # bounded before anything walks it
    version = doc.get("asset", {}).get("version") if isinstance(doc.get("asset"), dict) else None
    if not isinstance(version, str) or not version.startswith("2."):
        raise MeshError(expected_got(f"asset.version of {name}", "'2.0' (glTF 2.0)", repr(version)))
    binary = split_glb(read_regular(p, name), name)[1] if p.suffix.lower() == ".glb" else None
    root = asset_files.asset_root(p, asset_root if asset_root is not None else settings.ASSET_ROOT)
    resolver = AssetResolver(p, root)
    buffer = buffer_reader(doc, binary, resolver, name)
    turn = Y_UP_TO_Z_UP if axis == "y" else np.eye(4)  # file -> morphkit world
    notes: list[str] = []
    nodes = doc.get("nodes", [])
    world, note = world_nodes(doc, name)
    if note:
        notes.append(note)

    # --- what the nodes use ---------------------------------------------------------------
    ext = doc.get("extensions", {}) if isinstance(doc.get("extensions"), dict) else {}
    lights = ext.get(KHR_LIGHTS, {}).get("lights", []) if isinstance(ext.get(KHR_LIGHTS), dict) else []
    meshes, cameras = doc.get("meshes", []), doc.get("cameras", [])
    for key, entries in (("meshes", meshes), ("cameras", cameras), (f"{KHR_LIGHTS} lights", lights)):
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            raise MeshError(expected_got(f"{key} of {name}", "a list of objects", repr(entries)[:60]))
    placed: list[tuple[int, str, np.ndarray]] = []  # (mesh, instance name, instance2file)
    sun_dir, cam, skinned = None, None, []
    ignored_lights: dict[str, list[str]] = {}
    ignored_cams: dict[str, list[str]] = {}
    for i, node2file in world:
        node = nodes[i] if isinstance(nodes[i], dict) else {}
        what = f"{node_what(node, i)} of {name}"
        label = node.get("name") if isinstance(node.get("name"), str) and node.get("name") else f"node{i}"
        if "skin" in node:
            skinned.append(repr(label))
        if "mesh" in node:
            m = gltf_index(node, "mesh", len(meshes), what)
            extensions = node.get("extensions") if isinstance(node.get("extensions"), dict) else {}
            if EXT_INSTANCING in extensions:
                for j, inst2node in enumerate(_instancing(extensions[EXT_INSTANCING], doc, buffer, what)):
                    placed.append((m, f"{label}[{j}]", node2file @ inst2node))
            else:
                placed.append((m, label, node2file))
        if "camera" in node:
            c = gltf_index(node, "camera", len(cameras), what)
            entry = cameras[c] if isinstance(cameras[c], dict) else {}
            kind = entry.get("type")
            if kind == "perspective" and cam is None:
                cam = (entry.get("perspective"), node2file, f"camera {c} of {name}")
            else:
                ignored_cams.setdefault("another perspective" if kind == "perspective" else str(kind),
                                        []).append(repr(label))
        light_ext = node.get("extensions", {}).get(KHR_LIGHTS) if isinstance(node.get("extensions"), dict) \
            else None
        if isinstance(light_ext, dict) and "light" in light_ext:
            k = gltf_index(light_ext, "light", len(lights), f"{KHR_LIGHTS} of {what}")
            kind = lights[k].get("type") if isinstance(lights[k], dict) else None
            if kind == "directional" and sun_dir is None:
                sun_dir = (turn @ node2file)[:3, :3] @ [0.0, 0.0, -1.0]
            else:
                ignored_lights.setdefault("another directional" if kind == "directional" else str(kind),
                                          []).append(repr(label))

    # --- the assets -----------------------------------------------------------------------
    used = sorted({m for m, _, _ in placed})
    assets: list[GltfAsset] = []
    base: dict[int, tuple[int, np.ndarray, float]] = {}  # mesh -> (asset index, base centre, scale)
    if used:
        warned = gltf_warnings(p, root, doc, resolver) > 0
        parts = _mesh_parts(p, doc, binary, used, resolver, name, warned)
        names = _asset_names(doc, used)
        for i in used:
            if not parts[i]:
                notes.append(f"mesh {i} {names[i]!r} has no triangles: its nodes are left out")
                continue
            what = f"mesh {i} {names[i]!r} of {name}"
            check_parts(parts[i], what)
            mesh = check_mesh(merge_parts(parts[i], what), what)
            mesh.apply_transform(turn)
            lo, hi = mesh.bounds
            scale = float(np.max(hi - lo))
            base[i] = (len(assets), np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2], 1.0]), scale)
            assets.append(GltfAsset(names[i], normalize(mesh), scale))
    else:
        notes.append("no meshes: the scene is empty" if not meshes else
                     f"no node uses a mesh ({len(meshes)} meshes unused): the scene is empty")

    # --- the instances --------------------------------------------------------------------
    rows: list[tuple[int, float, float, float, float]] = []
    tilted, stretched, mirrored, lifted = [], [], [], []
    for m, label, inst2file in placed:
        if m not in base:
            continue
        k, centre, size = base[m]
        with np.errstate(over="ignore", invalid="ignore"):
            inst2world = turn @ inst2file @ turn.T  # the mesh's own frame turned as the mesh was
        if not np.all(np.isfinite(inst2world)):
            raise MeshError(expected_got(f"world transform of {label!r} in {name}", "finite numbers",
                                         "an overflow of its node's and instance's transforms"))
        rot, s, mirror = _rotation(inst2world[:3, :3])
        if not s[-1] > tol.REL_EQUAL * s[0] or not s[-1] * size > 0:
            raise MeshError(expected_got(f"world transform of {label!r} in {name}", "an invertible matrix",
                                         f"singular values {s.tolist()} (its parents' scales multiplied)"))
        scale = float(np.mean(s))
        if s[0] - s[-1] > tol.POSE_ORTHO * s[0]:
            stretched.append(repr(label))
        if mirror:
            mirrored.append(repr(label))
        if np.linalg.norm(rot[:, 2] - [0.0, 0.0, 1.0]) > tol.POSE_ORTHO:
            tilted.append(repr(label))
        foot = inst2world @ centre
        if abs(foot[2]) > tol.GLTF_GROUND_REL * scale * size:
            lifted.append(repr(label))
        yaw = float(np.degrees(np.arctan2(rot[1, 0] - rot[0, 1], rot[0, 0] + rot[1, 1])))
        rows.append((k, float(foot[0]), float(foot[1]), yaw, scale * size))
    arr = np.array([r[1:] for r in rows], dtype=np.float64).reshape(-1, 4)
    instances = Instances(tuple(a.name for a in assets), np.array([r[0] for r in rows], dtype=np.int64),
                          arr[:, :2], arr[:, 2], arr[:, 3])
    for what, labels in (("nodes tilt their asset off the ground: yaw kept, tilt dropped", tilted),
                         ("nodes scale non-uniformly: the mean scale kept", stretched),
                         ("nodes mirror their asset: the mirror dropped", mirrored),
                         ("instances do not stand on the ground: set on the ground", lifted)):
        if labels:
            notes.append(_said(what, labels))

    # --- sun, camera, the rest ------------------------------------------------------------
    sun = DirectionalLight(sun_dir, SUN_INTENSITY) if sun_dir is not None else None
    if sun is None:
        notes.append(NO_SUN)
    for kind, labels in ignored_lights.items():
        notes.append(_said(f"{kind} lights ignored (morphkit draws one sun)", labels))
    camera = _camera(cam, turn, instances, assets) if cam is not None else None
    if camera is None:
        notes.append(NO_CAMERA)
    for kind, labels in ignored_cams.items():
        notes.append(_said(f"{kind} cameras ignored", labels))
    if skinned or doc.get("skins"):
        notes.append(_said("skinned nodes: skins ignored, drawn in the rest pose", skinned) if skinned
                     else f"{len(doc['skins'])} skins ignored (no node uses them)")
    if doc.get("animations"):
        notes.append(f"{len(doc['animations'])} animations ignored: morphkit draws the rest pose")
    return GltfScene(tuple(assets), instances, sun, camera, tuple(n for n in notes if n))


def _camera(cam: tuple[Any, np.ndarray, str], turn: np.ndarray, instances: Instances,
            assets: list[GltfAsset]) -> GltfCamera:
    """The glTF perspective camera ``(its perspective object, node2file, name)`` in morphkit's frames."""
    persp, node2file, what = cam
    if not isinstance(persp, dict):
        raise MeshError(expected_got(what, "a perspective object", repr(persp)[:60]))
    yfov, znear, zfar, aspect = (persp.get(k) for k in ("yfov", "znear", "zfar", "aspectRatio"))
    for key, v in (("yfov", yfov), ("znear", znear)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
            raise MeshError(expected_got(f"{key} of {what}", "a finite number > 0", repr(v)[:40]))
    if yfov >= np.pi:
        raise MeshError(expected_got(f"yfov of {what}", "an angle in (0, pi) radians", yfov))
    if aspect is not None and (isinstance(aspect, bool) or not isinstance(aspect, (int, float))
                               or not np.isfinite(aspect) or aspect <= 0):
        raise MeshError(expected_got(f"aspectRatio of {what}", "a finite number > 0", repr(aspect)[:40]))
    rot, _, _ = _rotation(node2file[:3, :3])
    gl2file = np.eye(4)
    gl2file[:3, :3], gl2file[:3, 3] = rot, node2file[:3, 3]
    cam2world = cv_pose_from_gl(turn @ gl2file)
    if zfar is None:
        far = 0.0
        for k in range(len(instances)):
            lo, hi = assets[int(instances.asset[k])].mesh.bounds
            corners = np.array(np.meshgrid(*zip(lo, hi, strict=True), indexing="ij")).reshape(3, -1).T
            pts = (instances.object2world(k) @ np.c_[corners, np.ones(8)].T).T[:, :3]
            far = max(far, float(np.max(np.linalg.norm(pts - cam2world[:3, 3], axis=1))))
        zfar = max(ZFAR_BOUNDS_FACTOR * far, ZFAR_MIN_RATIO * float(znear))
    elif isinstance(zfar, bool) or not isinstance(zfar, (int, float)) or not np.isfinite(zfar) \
            or zfar <= znear * (1 + tol.REL_EQUAL):
        raise MeshError(expected_got(f"zfar of {what}", f"a finite number > znear {znear}", repr(zfar)[:40]))
    return GltfCamera(cam2world, float(yfov), float(znear), float(zfar),
                      None if aspect is None else float(aspect))
