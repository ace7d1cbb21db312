"""A relightable dome asset as one GLB: its mesh, its views, its sun atlas, and a sidecar.

:func:`write_dome_glb` writes (atomically) a glTF 2.0 binary holding:

* the asset's mesh in the asset's frame and look (:meth:`~morphkit.billboard.DomeAsset.items`: a
  checker-textured sample's colour groups as linear vertex colours ``COLOR_0``, a mesh file's own
  materials and textures as trimesh exports them), when given, turned ``+y`` up as glTF is (the
  inverse of :data:`~morphkit.meshes.Y_UP_TO_Z_UP`, on its node: the vertices stay morphkit's);
* its dome views tiled into three atlases (:mod:`.tiles`, each view padded by its own edges):
  ``albedo`` (RGBA 8-bit PNG: the views' straight sRGB albedo and coverage, as baked), ``normal``
  (RGB 8-bit PNG, linear: ``round(127 n) + 128`` of the object-frame unit normal, ``+z`` up,
  :mod:`morphkit.conventions`) and ``depth`` (16-bit grey PNG whose values are the bits of the
  views' float16 depths: linear depth along the view's axis minus the camera distance ``D``,
  ``+inf`` where nothing is drawn; a shader reads them with ``texelFetch`` and
  ``unpackHalf2x16``, nearest, never filtered);
* its sun atlas, when given, alike: ``sun-depth`` (float16 bits) and ``sun-coverage`` (8-bit grey);
* its octahedral impostor, when given (:mod:`morphkit.billboard.impostor`): its level-0 frames tiled
  alike as ``impostor-albedo``, ``impostor-normal`` and ``impostor-depth`` (the frames' depths
  from their eye planes, float16 bits), the sidecar's ``impostor`` naming the grid, the camera
  rule and the layout;
* the sidecar ``extras.morphkit`` (:data:`SIDECAR_VERSION`): ``morphkit_export``, ``kind``
  (``"dome"``), ``name``, ``mesh_hash``, ``appearance``, ``source_up``, ``rings`` and ``top`` (the
  view dome), ``views`` (each view's ``azimuth_deg``, ``elevation_deg`` and atlas ``origin``),
  ``pivot``, ``distance``, ``radius``, ``size``, ``levels``, ``half_extent``, ``depth_range``
  (the views' near and far planes), ``bounds`` (the mesh's, or null), ``layout``
  (:meth:`~.tiles.TileLayout.to_json`), ``images`` (each atlas's image name), ``colour_spaces``,
  ``normal_convention``, ``depth_encoding``, ``sun_atlas`` (its dome, camera rule, mesh hash,
  layout and images, or null), ``impostor`` (or null), ``lod`` (the levels of detail, or null)
  and ``measured`` (the representations' measured errors, as the caller gives them), and
  ``frame``: the pivot, bounds and view directions
  are in morphkit's object frame (``+z`` up): its point ``(x, y, z)`` is ``(x, z, -y)`` in the file's
  ``+y``-up frame.

Given levels of detail (:class:`~.lod.LodChain`, from a plan:
:func:`~morphkit.plan.lodchain.lod_chain`), the mesh's items are the children of one node ``mesh``
(turned ``+y`` up) carrying ``MSFT_lod``: its lower levels are the stand-in
:func:`~.lod.cross_card` (node ``card``) or nothing (an empty node), switched at the chain's
screen coverages (``extras.MSFT_screencoverage``); a reader without ``MSFT_lod`` draws the mesh
alone.

:func:`read_dome_glb` reads one back: the :class:`~morphkit.billboard.DomeAsset` (its views
bit for bit, checked as a dome asset file is, :func:`~morphkit.billboard.formats.domefile.dome_record`),
the sun atlas, the impostor (its frames bit for bit) and the sidecar.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from .. import tol
from ..billboard.domeasset import DomeAsset
from ..billboard.formats.domefile import dome_record
from ..billboard.frames.instances import Instances
from ..billboard.impostor import OctahedralImpostor
from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import encode_image, write_bytes
from ..meshes import Y_UP_TO_Z_UP, normalize
from ..scene import Item
from ..sunlit.sunatlas import SunAtlas
from ..views.dome import ViewDome
from ..views.domecameras import DomeCameras
from ..views.gbuffer import StoredSurface
from .glb import INSTANCING, GlbImage, NodeInstances, NodeLods, glb_bytes, read_glb
from .lod import LOD_CARD, LodChain, cross_card
from .tiles import TileLayout, tile_views, untile_views

__all__ = ["SIDECAR_VERSION", "DomeGlb", "ExportedAsset", "write_dome_glb", "write_scene_glb",
           "read_dome_glb"]

#: The version of the sidecar :func:`write_dome_glb` writes and :func:`read_dome_glb` reads.
SIDECAR_VERSION = 1

_COLOUR_SPACES = {"albedo": "sRGB, straight alpha (coverage)", "normal": "linear",
                  "depth": "linear (float16 bits)"}
_NORMALS = "object frame, +z up; rgb = round(127 n) + 128"
_FRAME = ("pivot, bounds, view directions and normals in morphkit's object frame, +z up: its point "
          "(x, y, z) is (x, z, -y) in the file's +y-up frame")
_DEPTH = ("float16 bits in a 16-bit PNG: linear depth along the view's axis minus the camera distance "
          "(+inf: nothing drawn); read unfiltered")
_IMPOSTOR_GRID = ("hemi-octahedral, Unreal's HemiOctahedronToUnitVector: frame (i, j), index j N + i, looks "
                  "along -d from grid point (2 i / (N - 1) - 1, 2 j / (N - 1) - 1), x = (u + v) / 2, "
                  "y = (u - v) / 2, z = 1 - |x| - |y|, d normalised; orthographic, the quad of half_extent")
_IMPOSTOR_DEPTH = ("float16 bits in a 16-bit PNG: linear depth along the frame's axis from its eye plane at "
                   "distance D from the pivot (not an offset; +inf: nothing drawn); read unfiltered")


def _check_texture(layout: TileLayout, what: str) -> None:
    """Refuse an atlas wider than engines load (:data:`morphkit.tol.EXPORT_MAX_TEXTURE_SIDE`)."""
    if max(layout.shape) > tol.EXPORT_MAX_TEXTURE_SIDE:
        raise ValidationError(expected_got(
            what, f"at most {tol.EXPORT_MAX_TEXTURE_SIDE} px a side (the texture size WebGL 2 devices "
            "load: bake smaller views)", f"{layout.shape[1]} x {layout.shape[0]} px for {layout.views} "
            f"views of {layout.side} px"))


def _half_bits(depth: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(depth, np.float16).view(np.uint16)


def _png(array: np.ndarray) -> bytes:
    return encode_image("atlas.png", array)


@dataclass(frozen=True)
class DomeGlb:
    """A dome asset read back from a GLB (:func:`read_dome_glb`).

    Parameters
    ----------
    asset : DomeAsset
        The asset, its views as written.
    sidecar : dict
        ``extras.morphkit``.
    sun_atlas : SunAtlas or None
        Its sun atlas, when the file holds one.
    impostor : OctahedralImpostor or None
        Its octahedral impostor, when the file holds one (level 0, its frames bit for bit).
    """

    asset: DomeAsset
    sidecar: dict[str, Any]
    sun_atlas: SunAtlas | None = None
    impostor: OctahedralImpostor | None = None


def _sun_entry(atlas: SunAtlas, images: list[GlbImage], prefix: str) -> dict[str, Any]:
    depth, layout = tile_views(_half_bits(atlas.depth))
    coverage, _ = tile_views(atlas.coverage)
    names = {"depth": f"{prefix}sun-depth", "coverage": f"{prefix}sun-coverage"}
    images += [GlbImage(names["depth"], _png(depth)), GlbImage(names["coverage"], _png(coverage))]
    cams = atlas.cameras
    return {"rings": [[float(e), int(k)] for e, k in atlas.dome.rings], "top": bool(atlas.dome.top),
            "pivot": [float(x) for x in cams.pivot], "distance": float(cams.distance),
            "radius": float(cams.radius), "size": int(atlas.size), "mesh_hash": atlas.mesh_hash,
            "layout": layout.to_json(), "images": names}


def _impostor_entry(imp: OctahedralImpostor, images: list[GlbImage], prefix: str) -> dict[str, Any]:
    """The impostor's level-0 frames tiled (index ``j N + i``) as three images, and its entry."""
    if not isinstance(imp, OctahedralImpostor):
        raise ValidationError(expected_got("impostor", "an OctahedralImpostor", type(imp).__name__))
    nf, m = imp.frames**2, imp.frame_side
    _check_texture(TileLayout(nf, m), "the impostor's atlases")
    frames = [imp.stored_frame(k) for k in range(nf)]
    albedo, layout = tile_views(np.stack([f.rgba for f in frames]))
    normal, _ = tile_views((np.stack([f.normal for f in frames]).astype(np.int16) + 128).astype(np.uint8))
    depth, _ = tile_views(_half_bits(np.stack([f.depth for f in frames])))
    names = {k: f"{prefix}impostor-{k}" for k in ("albedo", "normal", "depth")}
    images += [GlbImage(names["albedo"], _png(albedo)), GlbImage(names["normal"], _png(normal)),
               GlbImage(names["depth"], _png(depth))]
    cams = imp.cameras
    return {"frames": int(imp.frames), "frame_side": int(m), "grid": _IMPOSTOR_GRID,
            "pivot": [float(x) for x in cams.pivot], "distance": float(cams.distance),
            "radius": float(cams.radius), "half_extent": [float(x) for x in imp.half_extent],
            "depth_encoding": _IMPOSTOR_DEPTH, "layout": layout.to_json(), "images": names}


@dataclass(frozen=True)
class ExportedAsset:
    """One asset as a scene's GLB holds it (:func:`write_scene_glb`).

    Parameters
    ----------
    asset : DomeAsset
        Its relightable views.
    items : list of Item, optional
        Its mesh in the asset's frame and look (:meth:`~morphkit.billboard.DomeAsset.items`).
    sun_atlas : SunAtlas, optional
        Its sun atlas.
    measured : dict, optional
        What was measured of its representations (JSON values).
    impostor : OctahedralImpostor, optional
        Its octahedral impostor (level 0 is written).
    """

    asset: DomeAsset
    items: list[Item] | None = None
    sun_atlas: SunAtlas | None = None
    measured: dict[str, Any] | None = None
    impostor: OctahedralImpostor | None = None


def _dome(asset: Any) -> DomeAsset:
    """``asset``, refused unless it is a dome asset."""
    if not isinstance(asset, DomeAsset):
        raise ValidationError(
            expected_got("asset", "a DomeAsset (bake_dome, DomeAsset.load)", type(asset).__name__)
        )
    return asset


def _part(exp: ExportedAsset, prefix: str, images: list[GlbImage]) -> dict[str, Any]:
    """One asset's images (appended to ``images``, named after ``prefix``) and sidecar entry."""
    asset, sun_atlas = _dome(exp.asset), exp.sun_atlas
    if sun_atlas is not None and not isinstance(sun_atlas, SunAtlas):
        raise ValidationError(expected_got("sun_atlas", "a SunAtlas", type(sun_atlas).__name__))
    rec = asset.record()
    _check_texture(TileLayout(asset.dome.views, rec.size), "the views' atlases")
    if sun_atlas is not None:
        _check_texture(TileLayout(sun_atlas.dome.views, sun_atlas.size), "the sun atlas's")
    albedo, layout = tile_views(rec.rgba)
    normal, _ = tile_views((rec.normal.astype(np.int16) + 128).astype(np.uint8))
    depth, _ = tile_views(_half_bits(rec.depth))
    names = {k: f"{prefix}{k}" for k in ("albedo", "normal", "depth")}
    images += [GlbImage(names["albedo"], _png(albedo)), GlbImage(names["normal"], _png(normal)),
               GlbImage(names["depth"], _png(depth))]
    near, far = asset.cameras.depth_range()
    az, el = asset.dome.azimuths_deg(), asset.dome.elevations_deg()
    bounds = None
    if exp.items:
        meshes = [it.mesh.copy().apply_transform(np.asarray(it.pose, np.float64)) for it in exp.items]
        bounds = np.asarray(trimesh.util.concatenate(meshes).bounds, float).tolist()
    return {
        "name": rec.name, "mesh_hash": rec.mesh_hash, "appearance": rec.appearance,
        "source_up": rec.source_up,
        "rings": [[float(e), int(k)] for e, k in rec.rings], "top": bool(rec.top),
        "views": [{"azimuth_deg": float(a), "elevation_deg": float(e), "origin": list(layout.origin(k))}
                  for k, (a, e) in enumerate(zip(az, el, strict=True))],
        "pivot": [float(x) for x in rec.pivot], "distance": float(rec.distance), "radius": float(rec.radius),
        "size": int(rec.size), "levels": int(rec.levels),
        "half_extent": [float(x) for x in asset.half_extent],
        "depth_range": [float(near), float(far)], "bounds": bounds,
        "layout": layout.to_json(), "images": names,
        "colour_spaces": dict(_COLOUR_SPACES), "normal_convention": _NORMALS, "depth_encoding": _DEPTH,
        "sun_atlas": None if sun_atlas is None else _sun_entry(sun_atlas, images, prefix),
        "impostor": None if exp.impostor is None else _impostor_entry(exp.impostor, images, prefix),
        "lod": None,
        "measured": dict(exp.measured or {}),
        "frame": _FRAME,
    }


def write_dome_glb(
    path: str | os.PathLike[str],
    asset: DomeAsset,
    *,
    mesh: trimesh.Trimesh | None = None,
    sun_atlas: SunAtlas | None = None,
    measured: dict[str, Any] | None = None,
    impostor: OctahedralImpostor | None = None,
    lod: LodChain | None = None,
) -> Path:
    """Write ``asset`` (with its ``mesh`` and ``sun_atlas``) as one GLB (the module notes).

    Parameters
    ----------
    path : path-like
        The ``.glb`` file (written atomically; the folder must exist).
    asset : DomeAsset
        The relightable views.
    mesh : trimesh.Trimesh, optional
        The mesh they were baked from (as given to the bake: checked by its hash).
    sun_atlas : SunAtlas, optional
        Its sun atlas (of the same mesh: checked by its hash when ``mesh`` is given).
    measured : dict, optional
        JSON values: what was measured of the asset's representations (the sidecar's ``measured``).
    impostor : OctahedralImpostor, optional
        Its octahedral impostor (the sidecar's ``impostor``; its level-0 frames as images).
    lod : LodChain, optional
        Its levels of detail (the module notes; with ``mesh``).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValidationError
        Not a dome asset; a mesh or sun atlas of another mesh than the asset's; atlases wider than
        :data:`morphkit.tol.EXPORT_MAX_TEXTURE_SIDE`; levels of detail without a mesh.
    """
    items = None
    if mesh is not None:
        items = _dome(asset).items(mesh)  # the mesh it was baked from, or refused naming both hashes
        if isinstance(sun_atlas, SunAtlas):
            sun_atlas.check_mesh(normalize(mesh))
    images: list[GlbImage] = []
    entry = _part(ExportedAsset(asset, items, sun_atlas, measured, impostor), "", images)
    sidecar = {"morphkit_export": SIDECAR_VERSION, "kind": "dome", **entry}
    if lod is not None and not isinstance(lod, LodChain):
        raise ValidationError(expected_got("lod", "a LodChain (lod_chain)", type(lod).__name__))
    if lod is not None and items is None:
        raise ValidationError(expected_got("levels of detail", "the asset's mesh to switch from", "no mesh"))
    if items is None:
        return write_bytes(path, glb_bytes(None, images, sidecar))
    if lod is None or not lod.switches:
        sidecar["lod"] = None if lod is None else lod.to_json()
        return write_bytes(path, glb_bytes(_geometry({"part": items})[0], images, sidecar))
    geometry, _ = _geometry({"part": items}, under="mesh")
    lower: list[str | None] = []
    for level in lod.levels[1:]:
        if level.kind == LOD_CARD and "card" not in lower:
            geometry.add_geometry(cross_card(asset), geom_name="card", node_name="card",
                                  transform=np.linalg.inv(Y_UP_TO_Z_UP))
            lower.append("card")
    if len(lod.levels) == 1:
        lower.append(None)
    sidecar["lod"] = {**lod.to_json(), "nodes": ["mesh", *(n or "mesh.none" for n in lower)]}
    lods = {"mesh": NodeLods(tuple(lower), tuple(lod.coverage()))}
    return write_bytes(path, glb_bytes(geometry, images, sidecar, lods=lods))


def _posed(it: Item) -> trimesh.Trimesh:
    """An item's mesh posed, in its colour (linear, as face colours) where it has one."""
    m = it.mesh.copy().apply_transform(np.asarray(it.pose, np.float64))
    if it.color is not None:
        rgba = np.array([*np.rint(255.0 * np.asarray(it.color)), 255], np.uint8)
        m.visual = trimesh.visual.ColorVisuals(m, face_colors=np.tile(rgba, (len(m.faces), 1)))
    return m


def _geometry(parts: Mapping[str, list[Item]], under: str | None = None
              ) -> tuple[trimesh.Scene, dict[str, list[str]]]:
    """The items of each named part as one scene (each item's mesh posed, in its colour, linear, as
    ``COLOR_0`` where it has one, else in its own look; every node turned ``+y`` up, or, ``under``
    a name, the children of one node of that name turned so), and the node names of each part."""
    scene = trimesh.Scene()
    to_file = np.linalg.inv(Y_UP_TO_Z_UP)  # glTF is +y up
    if under is not None:
        scene.graph.update(frame_to=under, frame_from=scene.graph.base_frame, matrix=to_file)
    nodes: dict[str, list[str]] = {}
    for name, items in parts.items():
        for k, it in enumerate(items):
            m = _posed(it)
            node = f"{name}.{k}"
            if under is None:
                scene.add_geometry(m, geom_name=node, node_name=node, transform=to_file)
            else:
                scene.add_geometry(m, geom_name=node, node_name=node, parent_node_name=under)
            nodes.setdefault(name, []).append(node)
    return scene, nodes


def _lod_instances(scene: trimesh.Scene, name: str, exp: ExportedAsset, chain: LodChain,
                   matrices: np.ndarray) -> tuple[dict[str, NodeLods], list[str]]:
    """The instances of an asset with levels of detail as nodes of their own (``NAME@i``, its
    items ``NAME@i.k`` sharing one mesh each, its card ``NAME@i.card``), and their levels."""
    if len(matrices) > tol.EXPORT_MAX_LOD_INSTANCES:
        raise ValidationError(expected_got(
            f"instances of {name!r} with levels of detail", f"at most {tol.EXPORT_MAX_LOD_INSTANCES} (each "
            "one a node: MSFT_lod switches per node; export the scene without --plan to instance it)",
            len(matrices)))
    base = scene.graph.base_frame
    carded = any(lv.kind == LOD_CARD for lv in chain.levels[1:])
    card = cross_card(exp.asset) if carded else None
    meshes = [(f"{name}.{k}", _posed(it)) for k, it in enumerate(exp.items or [])]
    lods: dict[str, NodeLods] = {}
    cover = tuple(chain.coverage())
    for i, mat in enumerate(matrices):
        node = f"{name}@{i}"
        scene.graph.update(frame_to=node, frame_from=base, matrix=mat)
        for k, (geom, m) in enumerate(meshes):
            if i == 0:
                scene.add_geometry(m, geom_name=geom, node_name=f"{node}.{k}", parent_node_name=node)
            else:
                scene.graph.update(frame_to=f"{node}.{k}", frame_from=node, geometry=geom)
        if card is not None:
            if i == 0:
                scene.add_geometry(card, geom_name=f"{name}.card", node_name=f"{node}.card", transform=mat)
            else:
                scene.graph.update(frame_to=f"{node}.card", frame_from=base, matrix=mat,
                                   geometry=f"{name}.card")
        lods[node] = NodeLods((f"{node}.card",) if card is not None else (None,), cover)
    return lods, [f"{name}@0.{k}" for k in range(len(meshes))]


def write_scene_glb(path: str | os.PathLike[str], assets: Mapping[str, ExportedAsset],
                    instances: Instances, lods: Mapping[str, LodChain] | None = None) -> Path:
    """A scene as one GLB: each asset's mesh once, drawn at its instances' poses by
    ``EXT_mesh_gpu_instancing`` (each instance's ``translation (x, y, 0)``, turn about ``+z`` by its
    yaw and uniform scale, in morphkit's world frame, before the node's turn ``+y`` up), its views
    and sun atlas as images named ``ASSET/albedo``, ..., and the sidecar ``extras.morphkit`` of
    kind ``"scene"``: ``assets`` (each asset's entry, as :func:`write_dome_glb`'s sidecar, with its
    ``nodes``, ``instances`` count and how they are drawn, ``instanced``) and ``frame``.

    An asset with levels of detail that switch (``lods``) has each instance as a node of its own
    instead, ``ASSET@i`` (its items its children, their meshes shared by every instance) with
    ``MSFT_lod`` as :func:`write_dome_glb` writes it (its card ``ASSET@i.card``): engines switch
    levels per node, and a node drawn by ``EXT_mesh_gpu_instancing`` has one level for all its
    instances (at most :data:`morphkit.tol.EXPORT_MAX_LOD_INSTANCES` such instances an asset).

    Parameters
    ----------
    path : path-like
        The ``.glb`` file (written atomically).
    assets : mapping of str to ExportedAsset
        Each asset the instances name.
    instances : Instances
        Where they stand.
    lods : mapping of str to LodChain, optional
        Levels of detail of assets (with their meshes).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValidationError
        An asset the instances name and ``assets`` lacks; an asset that is not a dome asset; levels
        of detail of an asset without its mesh, or of more instances than the limit.
    """
    missing = [nm for nm in instances.names if nm not in assets]
    if missing:
        want = f"one per asset of the instances {list(instances.names)}"
        raise ValidationError(expected_got("assets", want,
                                           f"{missing} missing"))
    chains = {nm: c for nm, c in (lods or {}).items() if c.switches}
    for nm in chains:
        if nm not in assets or not assets[nm].items:
            raise ValidationError(expected_got(f"levels of detail of {nm!r}", "an asset with its mesh",
                                               "none" if nm not in assets else "no mesh"))
    images: list[GlbImage] = []
    entries = {nm: _part(exp, f"{nm}/", images) for nm, exp in assets.items()}
    for nm, c in (lods or {}).items():
        if nm in entries:
            entries[nm]["lod"] = c.to_json()
    scene, nodes = _geometry({nm: exp.items for nm, exp in assets.items() if exp.items and nm not in chains})
    placed: dict[str, NodeInstances] = {}
    node_lods: dict[str, NodeLods] = {}
    for a, nm in enumerate(instances.names):
        idx = np.flatnonzero(instances.asset == a)
        entries[nm]["instances"] = len(idx)
        entries[nm]["instanced"] = "nodes" if nm in chains else INSTANCING
        if nm in chains:
            entries[nm]["nodes"] = []
            if len(idx):
                to_file = np.linalg.inv(Y_UP_TO_Z_UP)
                mats = np.stack([to_file @ instances.object2world(int(k)) for k in idx])
                got, entries[nm]["nodes"] = _lod_instances(scene, nm, assets[nm], chains[nm], mats)
                node_lods.update(got)
            continue
        entries[nm]["nodes"] = nodes.get(nm, [])
        if len(idx) == 0 or nm not in nodes:
            continue
        half = np.radians(instances.yaw_deg[idx]) / 2.0  # about +z: (0, 0, sin, cos)
        q = np.stack([np.zeros_like(half), np.zeros_like(half), np.sin(half), np.cos(half)], axis=1)
        t = np.column_stack([instances.xy[idx], np.zeros(len(idx))])
        sc = np.repeat(instances.scale[idx][:, None], 3, axis=1)
        for node in nodes[nm]:
            placed[node] = NodeInstances(t, q, sc)
    sidecar = {"morphkit_export": SIDECAR_VERSION, "kind": "scene", "assets": entries, "frame": _FRAME}
    return write_bytes(path, glb_bytes(scene, images, sidecar, placed, node_lods))


def _bad(path: Path, what: str, expected: Any, got: Any) -> FileFormatError:
    return FileFormatError(expected_got(f"morphkit GLB {str(path)!r}: {what}", expected, got))


def read_dome_glb(path: str | os.PathLike[str], name: str | None = None) -> DomeGlb:
    """The dome asset (and sun atlas) a GLB of :func:`write_dome_glb` holds, or one asset of a
    scene's (:func:`write_scene_glb`).

    Parameters
    ----------
    path : path-like
        The ``.glb`` file.
    name : str, optional
        The asset of a scene's file (default: its only one).

    Returns
    -------
    DomeGlb
        Its ``sidecar`` the asset's entry.

    Raises
    ------
    FileFormatError
        Not a GLB; no morphkit sidecar, or one of another version or kind; no such asset (or, without
        ``name``, a scene of several); images missing or of the wrong shape or dtype; views that a
        dome asset file would not pass.
    """
    p = Path(path)
    glb = read_glb(p)
    side = glb.sidecar
    if side is None:
        raise _bad(p, "extras", "a morphkit sidecar ('extras.morphkit': a file morphkit exported)", "none")
    if side.get("morphkit_export") != SIDECAR_VERSION or side.get("kind") not in ("dome", "scene"):
        raise _bad(p, "sidecar", f"morphkit_export {SIDECAR_VERSION} of kind 'dome'",
                   f"{side.get('morphkit_export')!r} of kind {side.get('kind')!r}")
    if side["kind"] == "scene":
        entries = side.get("assets") if isinstance(side.get("assets"), dict) else {}
        if name is None and len(entries) == 1:
            name = next(iter(entries))
        if name not in entries:
            raise _bad(p, "assets", f"an asset named {name!r}" if name else "one asset (or a name)",
                       sorted(entries))
        side = entries[name]
    layout = TileLayout.from_json(side.get("layout"))
    names = side.get("images") if isinstance(side.get("images"), dict) else {}

    def views(key: str, dtype: type, channels: int | None) -> np.ndarray:
        img = glb.image(str(names.get(key, key)))
        want = (*layout.shape, channels) if channels else layout.shape
        if img.dtype != dtype or img.shape != want:
            raise _bad(p, f"image {key!r}", f"{np.dtype(dtype)} {want}", f"{img.dtype} {img.shape}")
        return untile_views(img, layout)

    rgba = views("albedo", np.uint8, 4)
    normal = (views("normal", np.uint8, 3).astype(np.int16) - 128).astype(np.int8)
    depth = views("depth", np.uint16, None).view(np.float16)
    record = dome_record(side, {"rgba": rgba, "normal": normal, "depth": depth})
    try:
        asset = DomeAsset(record)
    except ValidationError as exc:
        raise _bad(p, "views", "a dome asset's views", str(exc)) from exc
    atlas = None
    sun = side.get("sun_atlas")
    if sun is not None:
        try:
            sl = TileLayout.from_json(sun["layout"])
            dimg, cimg = glb.image(sun["images"]["depth"]), glb.image(sun["images"]["coverage"])
            if dimg.dtype != np.uint16 or cimg.dtype != np.uint8:
                raise _bad(p, "sun atlas images", "16-bit depth and 8-bit coverage",
                           f"{dimg.dtype}, {cimg.dtype}")
            pivot = np.asarray(sun["pivot"], np.float64)
            cams = DomeCameras(pivot, float(sun["distance"]), float(sun["radius"]), int(sun["size"]))
            dome = ViewDome(tuple((float(e), int(k)) for e, k in sun["rings"]), bool(sun["top"]))
            depth_s = untile_views(dimg, sl).view(np.float16)
            atlas = SunAtlas(dome, cams, depth_s, untile_views(cimg, sl), str(sun["mesh_hash"]))
        except (KeyError, TypeError, ValueError, ValidationError) as exc:
            raise _bad(p, "sun_atlas", "a sun atlas's dome, cameras, layout and images",
                       f"{type(exc).__name__}: {exc}"[:200]) from exc
    return DomeGlb(asset, side, atlas, _read_impostor(p, glb, side, asset.name))


def _read_impostor(p: Path, glb: Any, side: dict[str, Any], name: str) -> OctahedralImpostor | None:
    """The impostor of an asset's sidecar entry, its frames read back bit for bit (or None)."""
    imp = side.get("impostor")
    if imp is None:
        return None
    try:
        layout = TileLayout.from_json(imp["layout"])
        imgs = {k: glb.image(imp["images"][k]) for k in ("albedo", "normal", "depth")}
        kinds = {"albedo": (np.uint8, 4), "normal": (np.uint8, 3), "depth": (np.uint16, None)}
        for k, (dtype, ch) in kinds.items():
            want = (*layout.shape, ch) if ch else layout.shape
            if imgs[k].dtype != dtype or imgs[k].shape != want:
                raise _bad(p, f"impostor image {k!r}", f"{np.dtype(dtype)} {want}",
                           f"{imgs[k].dtype} {imgs[k].shape}")
        rgba = untile_views(imgs["albedo"], layout)
        normal = (untile_views(imgs["normal"], layout).astype(np.int16) - 128).astype(np.int8)
        depth = untile_views(imgs["depth"], layout).view(np.float16)
        n, m = int(imp["frames"]), int(imp["frame_side"])
        cams = DomeCameras(np.asarray(imp["pivot"], np.float64), float(imp["distance"]),
                           float(imp["radius"]), m)
        frames = [StoredSurface(rgba[k], normal[k], depth[k]) for k in range(n * n)]
        return OctahedralImpostor.from_stored(name, cams, n, frames, levels=1)
    except (KeyError, TypeError, ValueError, ValidationError) as exc:
        raise _bad(p, "impostor", "an impostor's grid, cameras, layout and images",
                   f"{type(exc).__name__}: {exc}"[:200]) from exc
