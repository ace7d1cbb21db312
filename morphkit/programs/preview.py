"""``morphkit preview ASSET_OR_SCENE -o page.html``: one self-contained page that morphs in the browser.

What the page is given, by what ASSET_OR_SCENE is:

* a sample mesh name or a mesh file: baked as ``morphkit export`` bakes it
  (:func:`~morphkit.programs.export.bake_asset_parts`: a relightable dome asset and a sun atlas),
  one instance at the origin, and beside it (unless ``impostor=False``) its octahedral impostor
  whose frames take as many bytes as the dome's views, to compare;
* a dome asset file (``.npz``): its views, one instance, no shadow (it has no sun atlas: the page
  says so);
* a GLB ``morphkit export`` wrote of an asset (:func:`~morphkit.export.assetglb.read_dome_glb`): its
  views, its sun atlas and the errors its sidecar's ``measured`` holds;
* any other GLB or glTF file (a file from another tool, or a morphkit scene GLB): drawn as meshes by
  three.js's glTF loader, the page says so;
* a scene (``.json``, or a glTF scene with ``scene=True``): its assets baked as ``morphkit export``
  bakes a scene (:func:`~morphkit.programs.export.scene_parts`), every instance drawn, the sun's
  shadow of the whole scene in one light view.

The page is :mod:`morphkit.export.page`'s, its data :func:`morphkit.export.preview.preview_data`;
the first camera and sun are ``view``'s (default: the camera fitted to the scene) and the URL
fragment sets them (:meth:`~morphkit.export.preview.PreviewView.fragment`).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..billboard.impostor import OctahedralImpostor
from ..errors import FileFormatError, ValidationError, expected_got
from ..export.assetglb import read_dome_glb
from ..export.preview import (
    PreviewView,
    asset_entry,
    check_preview_output,
    impostor_entry,
    preview_data,
    write_preview,
)
from ..scenes.camerapaths import Keyframes
from ..scenes.description import SceneDescription
from ..sunlit.receivers import SCENE_ATLAS_SIZE
from .export import (
    DEFAULT_EXPORT_SIZE,
    bake_asset_parts,
    equal_bytes_impostor,
    measure_representations,
    scene_parts,
)

__all__ = ["preview_page", "preview_line"]

_GLTF_SUFFIXES = (".glb", ".gltf")


def _instances(inst: Any, name: str) -> np.ndarray:
    k = inst.names.index(name) if name in inst.names else -1
    pick = inst.asset == k
    xy = np.asarray(inst.xy, np.float64)[pick]
    return np.column_stack([xy[:, 0], xy[:, 1], np.zeros(len(xy)), np.asarray(inst.yaw_deg)[pick],
                            np.asarray(inst.scale)[pick]])


def preview_page(spec: str, out: str | os.PathLike[str], *, camera: Sequence[float] | None = None,
                 sun: Sequence[float] | None = None, image: tuple[int, int] = (640, 480),
                 size: int = DEFAULT_EXPORT_SIZE, sun_atlas_size: int = SCENE_ATLAS_SIZE, up: str = "auto",
                 scene: bool = False, impostor: bool = True, overwrite: bool = False) -> dict[str, Any]:
    """Write the preview page of an asset or a scene (the module notes).

    Parameters
    ----------
    spec : str
        A sample mesh name, a mesh file, a dome asset file, a GLB, or a scene file.
    out : path-like
        The ``.html`` file.
    camera : (azimuth_deg, elevation_deg, distance), optional
        The first camera, about the scene's centre (default: :class:`PreviewView`'s angles, the
        distance fitted to what is drawn).
    sun : (azimuth_deg, elevation_deg), optional
        The first sun (default: :class:`PreviewView`'s).
    image : (width, height), optional
        The first view's image (the page's canvas is the window unless the URL fragment sets it).
    size : int, optional
        The dome views' side when baking, pixels.
    sun_atlas_size : int, optional
        The sun atlas's side when baking, texels (0: none).
    up : {"auto", "y", "z"}, optional
        A mesh file's up axis.
    scene : bool, optional
        Read a glTF file as a scene (each mesh an asset, its nodes the instances).
    impostor : bool, optional
        Beside a baked asset, its octahedral impostor at equal bytes
        (:func:`~morphkit.programs.export.equal_bytes_impostor`), or a GLB's own.
    overwrite : bool, optional
        Replace an existing ``out``.

    Returns
    -------
    dict
        ``path``, ``bytes``, ``kind`` (``"asset"``, ``"scene"`` or ``"meshes"``), ``instances``,
        ``texture_bytes``, ``notes`` and ``fragment`` (the first view's URL fragment).

    Raises
    ------
    OutputExistsError
        ``out`` exists and ``overwrite`` is not given.
    ValidationError
        An output that is not an ``.html`` path; an unknown asset; views past WebGL's texture side.
    """
    p = check_preview_output(out, overwrite=overwrite)
    suffix = Path(spec).suffix.lower()
    notes: list[str] = []
    measured: list[str] = []
    gltf: bytes | None = None
    fov, scene_target = PreviewView().fov_deg, None
    entries: list[dict[str, Any]] = []
    placed: list[tuple[np.ndarray, float, np.ndarray]] = []  # each entry's pivot, radius, instances
    one = np.array([[0.0, 0.0, 0.0, 0.0, 1.0]])

    def put(entry: dict[str, Any], inst: np.ndarray) -> None:
        entries.append(entry)
        placed.append((np.asarray(entry["pivot"], np.float64), float(entry["radius"]), inst))

    if suffix == ".json" or (scene and suffix in _GLTF_SUFFIXES):
        kind = "scene"
        got_scene = scene_parts(spec, sun_atlas_size=sun_atlas_size, command="preview")
        for nm, a in got_scene.assets.items():
            inst = _instances(got_scene.instances, nm)
            put(asset_entry(a.asset, a.sun_atlas, inst, name=nm), inst)
        title = f"morphkit preview: the scene {Path(spec).name}"
        camera, sun, fov, scene_target = _scene_view(got_scene.scene, camera, sun)
    elif suffix in _GLTF_SUFFIXES:
        if not Path(spec).is_file():
            raise ValidationError(expected_got("ASSET_OR_SCENE", "an existing .glb or .gltf file",
                                               repr(spec)))
        try:
            got = read_dome_glb(spec)
        except FileFormatError as exc:
            kind = "meshes"
            gltf = Path(spec).read_bytes() if suffix == ".glb" else None
            if gltf is None:
                raise ValidationError(expected_got(
                    "ASSET_OR_SCENE", "a .glb file to draw as meshes (a .gltf with its files is not "
                    "inlined)", repr(spec))) from exc
            notes.append(f"not a morphkit asset GLB ({exc}): drawn as meshes")
            title = f"morphkit preview: {Path(spec).name} (meshes)"
        else:
            kind = "asset"
            put(asset_entry(got.asset, got.sun_atlas, one, name=f"{got.asset.name} (view morph)"), one)
            if impostor and got.impostor is not None:
                at = _beside(got.asset.cameras.radius, camera)
                put(_impostor_named(got.impostor, got.sun_atlas, at, got.asset.name), at)
            measured = _measured_lines(got.sidecar.get("measured") or {})
            title = f"morphkit preview: {got.asset.name}"
    else:
        kind = "asset"
        parts = bake_asset_parts(spec, size=size, sun_atlas_size=sun_atlas_size, up=up)
        put(asset_entry(parts.asset, parts.sun_atlas, one, name=f"{parts.name} (view morph)"), one)
        title = f"morphkit preview: {parts.name}"
        imp = equal_bytes_impostor(parts) if impostor and parts.mesh is not None else None
        if imp is not None:
            at = _beside(parts.asset.cameras.radius, camera)
            put(_impostor_named(imp, parts.sun_atlas, at, parts.name), at)
        if parts.mesh is not None:
            measured = _measured_lines(measure_representations(parts, imp))
        elif impostor:
            notes.append(f"{parts.name}: no octahedral impostor beside it (an asset file has no mesh to "
                         "bake it from)")
    target, reach = _extent(placed)
    w, h = image
    base = PreviewView(width=w, height=h)
    if kind == "scene":
        base = dataclasses.replace(base, fov_deg=fov)
        target = scene_target if scene_target is not None else target
    if sun is not None:
        base = dataclasses.replace(base, sun_azimuth_deg=float(sun[0]), sun_elevation_deg=float(sun[1]))
    if camera is None:
        first = base.fitted(reach)
    else:
        first = dataclasses.replace(base, azimuth_deg=float(camera[0]), elevation_deg=float(camera[1]),
                                    distance=float(camera[2]))
    data = preview_data(entries, first, target, reach, title=title, measured=measured, notes=notes,
                        gltf=gltf, ground=True)
    if kind == "meshes":
        data["fit_gltf"] = camera is None
    write_preview(p, data, overwrite=overwrite)
    return {"path": str(p), "bytes": p.stat().st_size, "kind": kind,
            "instances": int(sum(e["count"] for e in entries)), "texture_bytes": data["texture_bytes"],
            "notes": data["notes"], "fragment": first.fragment()}


def _measured_lines(m: dict[str, Any]) -> list[str]:
    """The page's lines of :func:`~morphkit.programs.export.measure_representations`' figures (or of
    any other ``measured`` entry, said as it is)."""
    if "morph" not in m:
        return [f"measured {k}: {v}" for k, v in sorted(m.items())]
    lines = [f"measured against the real mesh at #{m['view']} ({m['metric']}):"]
    for k, label in (("morph", "view morph"), ("impostor", "octahedral impostor")):
        if k in m:
            lines.append(f"  {label}: {m[k]['psnr_db']} dB, {m[k]['bytes']:,} bytes of views")
    return lines


def _beside(radius: float, camera: Sequence[float] | None) -> np.ndarray:
    """The instance beside the asset's at the origin: 2.2 bounding radii along the first camera's right."""
    az = math.radians(PreviewView().azimuth_deg if camera is None else float(camera[0]))
    off = 2.2 * radius
    return np.array([[-math.sin(az) * off, math.cos(az) * off, 0.0, 0.0, 1.0]])


def _impostor_named(imp: OctahedralImpostor, sun_atlas: Any, at: np.ndarray, name: str) -> dict[str, Any]:
    """The impostor's page entry, named with its grid and frame size."""
    n = imp.frames
    return impostor_entry(imp, sun_atlas, at,
                          name=f"{name} (octahedral impostor {n}x{n} of {imp.frame_side} px)")


def _scene_view(scene: SceneDescription, camera: Sequence[float] | None, sun: Sequence[float] | None
                ) -> tuple[Sequence[float] | None, Sequence[float] | None, float, np.ndarray | None]:
    """A scene's own first view, where the caller gave none: its first camera key (as azimuth,
    elevation and distance about its target, and its field of view) and its first sun."""
    fov, target = PreviewView().fov_deg, None
    cam = scene.camera
    if camera is None and isinstance(cam, Keyframes):
        rel = np.asarray(cam.eyes[0], np.float64) - np.asarray(cam.targets[0], np.float64)
        dist = float(np.linalg.norm(rel))
        el = float(np.clip(np.degrees(np.arcsin(rel[2] / dist)), -89.0, 89.0))
        camera = (float(np.degrees(np.arctan2(rel[1], rel[0]))), el, dist)
        fov, target = min(float(cam.yfov_deg), 169.0), np.asarray(cam.targets[0], np.float64)
    if sun is None:
        lights = scene.sun.suns(max(1, scene.frames))
        if lights:
            d = -np.asarray(lights[0].direction, np.float64)
            d /= np.linalg.norm(d)
            sun = (float(np.degrees(np.arctan2(d[1], d[0]))), float(np.degrees(np.arcsin(d[2]))))
    return camera, sun, fov, target


def _extent(placed: list[tuple[np.ndarray, float, np.ndarray]]) -> tuple[np.ndarray, float]:
    """The centre and radius of every instance's bounding sphere (a unit sphere when none)."""
    centres, radii = [], []
    for pivot, radius, inst in placed:
        yaw, s = np.radians(inst[:, 3]), inst[:, 4]
        c, sn = np.cos(yaw), np.sin(yaw)
        centres.append(inst[:, :3] + s[:, None] * np.column_stack(
            [c * pivot[0] - sn * pivot[1], sn * pivot[0] + c * pivot[1], np.full(len(inst), pivot[2])]))
        radii.append(s * radius)
    pts = np.concatenate(centres) if centres else np.zeros((0, 3))
    if not len(pts):
        return np.array([0.0, 0.0, 0.5]), 1.0
    r = np.concatenate(radii)
    target = 0.5 * ((pts - r[:, None]).min(axis=0) + (pts + r[:, None]).max(axis=0))
    return target, float(max(np.linalg.norm(pts - target, axis=1) + r))


def preview_line(got: dict[str, Any]) -> str:
    """The line ``morphkit preview`` prints of what :func:`preview_page` wrote.

    Parameters
    ----------
    got : dict
        Its summary.

    Returns
    -------
    str
    """
    what = {"asset": "an asset", "scene": "a scene",
            "meshes": "meshes (a glTF file from another tool)"}[got["kind"]]
    line = (f"morphkit preview: wrote {got['path']} ({got['bytes']:,} bytes, self-contained): {what}, "
            f"{got['instances']:,} instances, {got['texture_bytes']:,} bytes of textures; open it in a "
            "browser "
            f"with WebGL 2 (first view: #{got['fragment']})")
    return line + "".join(f"\nmorphkit preview: {n}" for n in got["notes"])
