"""``morphkit export ASSET_OR_SCENE -o OUT.glb``: an asset or a scene baked (or read) and written as
a GLB for engines.

ASSET is what ``morphkit render`` takes as an asset source (:mod:`morphkit.programs.sources`): a
sample mesh name or a mesh file is baked into a relightable dome asset
(:func:`~morphkit.billboard.bake_dome`, views of ``size`` pixels) and a sun atlas
(:func:`~morphkit.sunlit.receivers.bake_scene_atlases`, ``sun_atlas_size`` texels; 0: none) and
written with its mesh (:func:`~morphkit.export.assetglb.write_dome_glb`) and, given a plan of a
scene holding the asset (``morphkit plan``'s ``plan.json``), its levels of detail from that plan
(:func:`~morphkit.plan.lodchain.lod_chain`: the mesh, the crossed card, nothing); a dome asset file
(``.npz``) is written as it is, its views alone (no mesh, no sun atlas: said in the summary). The
output follows the usual rule: an existing file is replaced only with ``overwrite``.

A scene (:func:`export_scene`: a JSON scene file, or a glTF scene with ``scene=True``) is placed
as ``morphkit render`` places it (:func:`~morphkit.programs.scenerender.prepare_scene`, its assets
baked as relightable dome assets whatever views the scene asks for) and written as one GLB
(:func:`~morphkit.export.assetglb.write_scene_glb`): each asset's mesh once, drawn at its
instances by ``EXT_mesh_gpu_instancing``, with its views and its sun atlas.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from ..billboard.domeasset import DomeAsset
from ..billboard.frames.instances import Instances
from ..billboard.impostor import DEFAULT_FRAMES, OctahedralImpostor, bake_impostor, impostor_frame_size
from ..errors import ValidationError, expected_got
from ..export.assetglb import ExportedAsset, write_dome_glb, write_scene_glb
from ..export.lod import LOD_CARD, LodChain, bounding_radius, cross_card
from ..export.preview import PreviewView
from ..export.previewref import reference_image, stand_in_image, truth_image
from ..files.outfolder import check_output_file
from ..imaging.metrics import psnr
from ..meshes import BILLBOARD_MESHES, load_mesh, normalize, sample_mesh
from ..plan.lodchain import lod_chain
from ..plan.planfile import ScenePlan, read_plan
from ..render import Renderer
from ..scene import Item
from ..scenes.description import SceneDescription
from ..sunlit.receivers import SCENE_ATLAS_SIZE, bake_scene_atlases
from ..sunlit.sunatlas import SunAtlas
from ..views.dome import ViewDome
from ..views.gbuffer import BYTES_PER_PIXEL
from .sceneshadows import SceneCasters
from .sources import MESH_SUFFIXES, asset_name, check_specs, resolve_assets

__all__ = ["export_asset", "export_scene", "export_line", "DEFAULT_EXPORT_SIZE", "AssetParts",
           "bake_asset_parts", "equal_bytes_impostor", "IMPOSTOR_FRAMES",
           "measure_representations", "MEASURE_VIEW", "plan_lods", "lod_words", "measure_lods",
           "LOD_ELEVATIONS_DEG",
           "scene_parts", "SceneParts"]

#: The dome views' side (pixels) an exported mesh is baked at: the scenes' default.
DEFAULT_EXPORT_SIZE = 128


def _output(out: str | os.PathLike[str], overwrite: bool) -> Path:
    return check_output_file(out, "a .glb", (".glb",), overwrite=overwrite)


@dataclass(frozen=True)
class AssetParts:
    """One asset as ``export`` and ``preview`` take it.

    Parameters
    ----------
    name : str
        Its name.
    asset : DomeAsset
        Its relightable views.
    mesh : trimesh.Trimesh or None
        Its normalised mesh (None for an asset file).
    sun_atlas : SunAtlas or None
        Its sun atlas (None: not baked).
    """

    name: str
    asset: DomeAsset
    mesh: trimesh.Trimesh | None
    sun_atlas: SunAtlas | None


def bake_asset_parts(spec: str, *, size: int = DEFAULT_EXPORT_SIZE, sun_atlas_size: int = SCENE_ATLAS_SIZE,
                     up: str = "auto") -> AssetParts:
    """Bake (or read) one asset for export (the module notes).

    Parameters
    ----------
    spec : str
        A sample mesh name, a mesh file or a dome asset file.
    size : int, optional
        The dome views' side when baking, pixels.
    sun_atlas_size : int, optional
        The sun atlas's side when baking, texels (0: no sun atlas).
    up : {"auto", "y", "z"}, optional
        A mesh file's up axis.

    Returns
    -------
    AssetParts

    Raises
    ------
    ValidationError
        An unknown asset; a bad ``sun_atlas_size``.
    """
    check_specs([spec])
    if not isinstance(sun_atlas_size, int) or sun_atlas_size < 0:
        raise ValidationError(
            expected_got("--sun-atlas-size", "an int >= 0 (0: none)", repr(sun_atlas_size))
        )
    baked = spec in BILLBOARD_MESHES or Path(spec).suffix.lower() in MESH_SUFFIXES
    with Renderer() as r:
        res = resolve_assets([spec], r, size=size, dome=ViewDome(), up=up)
        (name,) = res.assets
        asset = res.assets[name]
        mesh = None
        if baked:
            mesh = normalize(sample_mesh(spec) if spec in BILLBOARD_MESHES else load_mesh(spec, up=up))
        atlas = None
        if baked and sun_atlas_size and mesh is not None:
            atlas = bake_scene_atlases({name: mesh}, r, size=sun_atlas_size)[name]
    return AssetParts(name, asset, mesh, atlas)


#: The octahedral impostor's grid, frames a side (the engines' default,
#: :data:`morphkit.billboard.impostor.DEFAULT_FRAMES`).
IMPOSTOR_FRAMES = DEFAULT_FRAMES


def equal_bytes_impostor(parts: AssetParts) -> OctahedralImpostor:
    """The asset's octahedral impostor (:data:`IMPOSTOR_FRAMES` a side, one mip level) whose frames take
    as many bytes as the dome's views (:func:`~morphkit.billboard.impostor.impostor_frame_size`):
    the anchor an engine would use instead, to compare.

    Parameters
    ----------
    parts : AssetParts
        With its mesh (baked from it in the asset's look).

    Returns
    -------
    OctahedralImpostor

    Raises
    ------
    ValidationError
        An asset without a mesh (an asset file).
    """
    if parts.mesh is None:
        raise ValidationError(expected_got("the asset", "its mesh, to bake its impostor from",
                                           "an asset file"))
    a = parts.asset
    budget = a.dome.views * a.size[0] * a.size[1] * BYTES_PER_PIXEL
    m = impostor_frame_size(budget, frames=IMPOSTOR_FRAMES, levels=1)
    with Renderer() as r:
        return bake_impostor(parts.mesh, r, name=a.name, frames=IMPOSTOR_FRAMES, frame_size=m, levels=1,
                             appearance=a.appearance)


#: The view the representations' errors are measured at (:func:`measure_representations`): the
#: preview's first view of one asset, fitted to its bounding sphere, 320 x 240.
MEASURE_VIEW = PreviewView(width=320, height=240)


def measure_representations(parts: AssetParts, impostor: OctahedralImpostor | None,
                            card: trimesh.Trimesh | None = None) -> dict[str, Any]:
    """The error of each representation against the real mesh at :data:`MEASURE_VIEW`: the dome's
    view morph and the impostor (when given) drawn by morphkit
    (:func:`~morphkit.export.previewref.reference_image`) and the crossed card (when given) drawn as
    a mesh (``stand_in_image``), against the mesh rendered with its ground shadow ray cast
    (``truth_image``), PSNR of the whole image; and the bytes of each one's views.

    Parameters
    ----------
    parts : AssetParts
        With its mesh.
    impostor : OctahedralImpostor or None
        Its impostor.
    card : trimesh.Trimesh, optional
        Its crossed card (:func:`~morphkit.export.lod.cross_card`).

    Returns
    -------
    dict
        JSON values: ``view`` (the fragment), ``truth``, ``metric``, and per representation
        (``morph``, ``impostor``, ``card``) its ``psnr_db`` and ``bytes``.

    Raises
    ------
    ValidationError
        An asset without a mesh.
    """
    if parts.mesh is None:
        raise ValidationError(expected_got("the asset", "its mesh, to measure against", "an asset file"))
    a = parts.asset
    view = MEASURE_VIEW.fitted(a.cameras.radius)
    one = np.array([[0.0, 0.0, 0.0, 0.0, 1.0]])
    with Renderer() as r:
        truth = truth_image(parts.mesh, a.items(parts.mesh), r, view, a.pivot)
        drawn_card = None if card is None else stand_in_image([Item(card)], parts.sun_atlas, r, view, a.pivot)
    out: dict[str, Any] = {
        "view": view.fragment(), "truth": "the mesh rendered, its ground shadow ray cast (no self-shadow)",
        "metric": "PSNR of the whole image, dB (morphkit.export.previewref)",
        "morph": {"psnr_db": round(psnr(reference_image(a, parts.sun_atlas, one, view, a.pivot), truth,
                                        data_range=1.0), 2),
                  "bytes": int(a.dome.views * a.size[0] * a.size[1] * BYTES_PER_PIXEL)},
    }
    if impostor is not None:
        got = reference_image(impostor, parts.sun_atlas, one, view, a.pivot)
        out["impostor"] = {"psnr_db": round(psnr(got, truth, data_range=1.0), 2),
                           "bytes": int(impostor.frames**2 * impostor.frame_side**2 * BYTES_PER_PIXEL)}
    if card is not None and drawn_card is not None:
        tex = card.visual.material.baseColorTexture
        out["card"] = {"psnr_db": round(psnr(drawn_card, truth, data_range=1.0), 2),
                       "bytes": int(tex.width * tex.height * 4)}
    return out


#: The elevations (degrees) :func:`measure_lods` views a level from: inside each of the plan's
#: elevation bands (:data:`~morphkit.plan.representations.ELEVATION_EDGES_DEG`).
LOD_ELEVATIONS_DEG = (10.0, 45.0, 75.0)


def measure_lods(parts: AssetParts, chain: LodChain, card: trimesh.Trimesh) -> list[dict[str, Any]]:
    """What each card level of ``chain`` errs at the largest size it is drawn at: the crossed card
    drawn as a mesh (``stand_in_image``) and the dome's view morph (``reference_image``), each
    against the mesh (``truth_image``), PSNR of an image twice the quad's height a side, the quad at
    its centre, seen from azimuth 30 degrees at each of :data:`LOD_ELEVATIONS_DEG`, the sun at
    :data:`MEASURE_VIEW`'s.

    The size is the level's least height doubled (the top of its first octave, where a stand-in
    errs most), at most the height the level above takes over, and 32 px for a level drawn down
    to nothing.

    Parameters
    ----------
    parts : AssetParts
        With its mesh.
    chain : LodChain
        Its levels.
    card : trimesh.Trimesh
        Its crossed card.

    Returns
    -------
    list of dict
        Per card level: ``level``, ``height_px``, ``image_px`` and ``views``: per elevation
        ``card_psnr_db`` and ``morph_psnr_db``.
    """
    if parts.mesh is None:
        raise ValidationError(expected_got("the asset", "its mesh, to measure against", "an asset file"))
    a = parts.asset
    one = np.array([[0.0, 0.0, 0.0, 0.0, 1.0]])
    hh = float(a.half_extent[1])
    out = []
    with Renderer() as r:
        items = a.items(parts.mesh)
        for k, level in enumerate(chain.levels):
            if level.kind != LOD_CARD:
                continue
            upper = chain.levels[k - 1].min_height_px if k else np.inf
            height = min(upper, 2.0 * level.min_height_px if level.min_height_px > 0 else 32.0)
            side = max(8, int(round(2.0 * height)))
            fy = side / (2.0 * np.tan(np.radians(MEASURE_VIEW.fov_deg) / 2.0))
            rows = []
            for el in LOD_ELEVATIONS_DEG:
                view = PreviewView(azimuth_deg=30.0, elevation_deg=el, distance=2.0 * hh * fy / height,
                                   fov_deg=MEASURE_VIEW.fov_deg, sun_azimuth_deg=MEASURE_VIEW.sun_azimuth_deg,
                                   sun_elevation_deg=MEASURE_VIEW.sun_elevation_deg, width=side, height=side)
                truth = truth_image(parts.mesh, items, r, view, a.pivot)
                got = stand_in_image([Item(card)], parts.sun_atlas, r, view, a.pivot)
                morph = reference_image(a, parts.sun_atlas, one, view, a.pivot)
                rows.append({"elevation_deg": el,
                             "card_psnr_db": round(psnr(got, truth, data_range=1.0), 2),
                             "morph_psnr_db": round(psnr(morph, truth, data_range=1.0), 2)})
            out.append({"level": k, "height_px": round(float(height), 2), "image_px": side, "views": rows})
    return out


def plan_lods(plan: ScenePlan, name: str, asset: DomeAsset, items: list[Item]) -> LodChain:
    """An asset's levels of detail from ``plan`` (:func:`~morphkit.plan.lodchain.lod_chain`), its
    bounding radius that of its mesh and its quad's half height the views'.

    Parameters
    ----------
    plan : ScenePlan
        A plan of a scene holding the asset (:func:`~morphkit.plan.read_plan`).
    name : str
        The plan's name for the asset.
    asset : DomeAsset
        Its views.
    items : list of Item
        Its mesh's render items (:meth:`~morphkit.billboard.DomeAsset.items`).

    Returns
    -------
    LodChain

    Raises
    ------
    ValidationError
        An asset the plan does not plan.
    """
    meshes = [it.mesh.copy().apply_transform(np.asarray(it.pose, np.float64)) for it in items]
    return lod_chain(plan, name, radius=bounding_radius(meshes), half_height=float(asset.half_extent[1]))


def export_asset(spec: str, out: str | os.PathLike[str], *, size: int = DEFAULT_EXPORT_SIZE,
                 sun_atlas_size: int = SCENE_ATLAS_SIZE, up: str = "auto", impostor: bool = True,
                 plan: str | os.PathLike[str] | None = None, plan_asset: str | None = None,
                 overwrite: bool = False) -> dict[str, Any]:
    """Export one asset as a GLB (the module notes).

    Parameters
    ----------
    spec : str
        A sample mesh name, a mesh file or a dome asset file.
    out : path-like
        The ``.glb`` file.
    size : int, optional
        The dome views' side when baking, pixels.
    sun_atlas_size : int, optional
        The sun atlas's side when baking, texels (0: no sun atlas).
    up : {"auto", "y", "z"}, optional
        A mesh file's up axis.
    impostor : bool, optional
        With a mesh, add its octahedral impostor at equal bytes (:func:`equal_bytes_impostor`).
    plan : path-like, optional
        ``morphkit plan``'s ``plan.json`` (or its folder) of a scene holding the asset: its levels of
        detail (:func:`plan_lods`), read before anything is baked.
    plan_asset : str, optional
        The plan's name for the asset (default: its own).
    overwrite : bool, optional
        Replace an existing ``out``.

    Returns
    -------
    dict
        What was written: ``path``, ``bytes``, ``name``, ``views``, ``size``, ``mesh`` (bool),
        ``sun_atlas`` (its side, or None), ``impostor`` (its frames' side, or None) and ``lod``
        (the chain's JSON, or None) and ``lod_measured`` (:func:`measure_lods`' or None). With a
        mesh, the sidecar's ``measured`` is
        :func:`measure_representations`' (the card's too, with levels of detail that draw it).

    Raises
    ------
    OutputExistsError
        ``out`` exists and ``overwrite`` is not given.
    FileFormatError
        A ``plan`` that is not a plan.
    ValidationError
        An output path that is not a ``.glb`` file; an unknown asset; a plan without the asset, or
        with an asset file.

    Examples
    --------
    ``morphkit export tree -o tree.glb``::

        from morphkit.programs.export import export_asset

        print(export_asset("tree", "tree.glb"))
    """
    p = _output(out, overwrite)
    planned = None if plan is None else read_plan(plan)
    if planned is not None:
        check_specs([spec])
        if (plan_asset or asset_name(spec)) not in planned.assets:
            raise ValidationError(expected_got(
                "the plan's asset", f"one of {list(planned.assets)} (name it with --plan-asset)",
                repr(plan_asset or asset_name(spec))))
    got = bake_asset_parts(spec, size=size, sun_atlas_size=sun_atlas_size, up=up)
    name, asset, mesh, atlas = got.name, got.asset, got.mesh, got.sun_atlas
    chain = None
    if planned is not None:
        if mesh is None:
            raise ValidationError(expected_got("the asset", "its mesh, to switch levels of detail from",
                                               "an asset file"))
        chain = plan_lods(planned, plan_asset or name, asset, asset.items(mesh))
    carded = chain is not None and chain.switches and any(lv.kind == LOD_CARD for lv in chain.levels)
    imp = equal_bytes_impostor(got) if impostor and mesh is not None else None
    card = cross_card(asset) if carded else None
    measured = measure_representations(got, imp, card) if mesh is not None else None
    if card is not None and chain is not None and measured is not None:
        measured["lod"] = {"truth": measured["truth"], "levels": measure_lods(got, chain, card),
                           "metric": "PSNR of an image twice the quad's height a side, dB "
                           "(morphkit.programs.export.measure_lods)"}
    p.parent.mkdir(parents=True, exist_ok=True)
    write_dome_glb(p, asset, mesh=mesh, sun_atlas=atlas, impostor=imp, measured=measured, lod=chain)
    return {"path": str(p), "bytes": p.stat().st_size, "name": name, "views": asset.dome.views,
            "size": int(asset.cameras.shape[0]), "mesh": mesh is not None,
            "sun_atlas": None if atlas is None else atlas.size,
            "impostor": None if imp is None else imp.frame_side,
            "lod": None if chain is None else chain.to_json(),
            "lod_measured": None if measured is None else measured.get("lod")}


def export_scene(path: str | os.PathLike[str], out: str | os.PathLike[str], *,
                 sun_atlas_size: int = SCENE_ATLAS_SIZE, plan: str | os.PathLike[str] | None = None,
                 overwrite: bool = False) -> dict[str, Any]:
    """Export a scene as one GLB (the module notes).

    Parameters
    ----------
    path : path-like
        A scene file (``.json``) or a glTF scene (``.glb``, ``.gltf``).
    out : path-like
        The ``.glb`` file.
    sun_atlas_size : int, optional
        Each asset's sun atlas side, texels (0: none).
    plan : path-like, optional
        ``morphkit plan``'s ``plan.json`` (or its folder) of this scene: each asset's levels of
        detail (:func:`plan_lods`; its instances then nodes of their own, as
        :func:`~morphkit.export.assetglb.write_scene_glb` says), read before anything is baked.
    overwrite : bool, optional
        Replace an existing ``out``.

    Returns
    -------
    dict
        ``path``, ``bytes``, ``assets`` (per asset: ``instances``, ``views``, ``size``, ``mesh``,
        ``sun_atlas``, ``lod``).

    Raises
    ------
    OutputExistsError
        ``out`` exists and ``overwrite`` is not given.
    FileFormatError
        A ``plan`` that is not a plan.
    ValidationError
        An output path that is not a ``.glb`` file; a scene morphkit refuses; a plan of other assets.
    """
    from ..scenes import load_scene

    p = _output(out, overwrite)
    planned = None if plan is None else read_plan(plan)
    if planned is not None:
        planned.check_assets(list(load_scene(path).names))
    got = scene_parts(path, sun_atlas_size=sun_atlas_size, command="export")
    assets, inst = got.assets, got.instances
    chains: dict[str, LodChain] = {}
    if planned is not None:
        chains = {nm: plan_lods(planned, nm, exp.asset, exp.items) for nm, exp in assets.items() if exp.items}
    p.parent.mkdir(parents=True, exist_ok=True)
    write_scene_glb(p, assets, inst, chains)
    return {"path": str(p), "bytes": p.stat().st_size,
            "assets": {nm: {"instances": int((inst.asset == inst.names.index(nm)).sum()) if nm in inst.names
                            else 0, "views": a.asset.dome.views, "size": int(a.asset.cameras.shape[0]),
                            "mesh": a.items is not None, "sun_atlas": a.sun_atlas is not None,
                            "lod": chains[nm].to_json() if nm in chains else None}
                       for nm, a in assets.items()}}


@dataclass(frozen=True)
class SceneParts:
    """A scene as ``export`` and ``preview`` take it.

    Parameters
    ----------
    assets : dict of str to ExportedAsset
        Per asset name: the dome asset, its render items and its sun atlas.
    instances : Instances
        The scene's instances, placed.
    scene : SceneDescription
        The scene as described (its camera, its sun).
    """

    assets: dict[str, ExportedAsset]
    instances: Instances
    scene: SceneDescription


def scene_parts(path: str | os.PathLike[str], *, sun_atlas_size: int = SCENE_ATLAS_SIZE,
                command: str = "export") -> SceneParts:
    """A scene's assets, baked as relightable dome assets with their sun atlases, and its
    instances, placed as ``morphkit render`` places them (the module notes).

    Parameters
    ----------
    path : path-like
        A scene file (``.json``) or a glTF scene (``.glb``, ``.gltf``).
    sun_atlas_size : int, optional
        Each asset's sun atlas side, texels (0: none).
    command : str, optional
        The command named in the lines said on stdout.

    Returns
    -------
    SceneParts

    Raises
    ------
    ValidationError
        A bad ``sun_atlas_size``; a scene morphkit refuses.
    """
    import dataclasses

    from ..scenes import load_scene
    from .scenerender import prepare_scene

    if not isinstance(sun_atlas_size, int) or sun_atlas_size < 0:
        raise ValidationError(
            expected_got("--sun-atlas-size", "an int >= 0 (0: none)", repr(sun_atlas_size))
        )
    scene = dataclasses.replace(load_scene(path), views="dome")
    head = f"morphkit {command}: "
    with Renderer() as r:
        prep = prepare_scene(scene, r, None, head=head, command=command)
        names = list(scene.names)
        known = [nm for nm in names if nm in prep.resolved.items]
        atlases: dict[str, Any] = {}
        if sun_atlas_size and known:
            casters = prep.casters or SceneCasters.of(
                prep.resolved, known, [a.source for a in scene.assets if a.name in known], head, command
            )
            atlases = casters.atlases(r, sun_atlas_size)
    assets = {nm: ExportedAsset(prep.scene.assets[nm], prep.resolved.items.get(nm), atlases.get(nm))
              for nm in names}
    return SceneParts(assets, prep.scene.instances, scene)


def export_line(got: dict[str, Any]) -> str:
    """The line ``morphkit export`` prints of what :func:`export_asset` or :func:`export_scene` wrote.

    Parameters
    ----------
    got : dict
        Their summary.

    Returns
    -------
    str
    """
    head = f"morphkit export: wrote {got['path']} ({got['bytes']:,} bytes"
    if "assets" in got:
        each = "; ".join(f"{nm}: {a['instances']} instances, {a['views']} views of {a['size']} px"
                         + ("" if a["mesh"] else ", no mesh") + ("" if a["sun_atlas"] else ", no sun atlas")
                         + (f", {lod_words(a['lod'])}" if a.get("lod") else "")
                         for nm, a in got["assets"].items())
        own = [nm for nm, a in got["assets"].items()
               if a.get("lod") and (len(a["lod"]["levels"]) > 1 or a["lod"]["culled_below_px"])]
        how = "the instances drawn by EXT_mesh_gpu_instancing"
        if own:
            how = f"the instances of {', '.join(own)} nodes of their own (MSFT_lod switches per node), the " \
                "others drawn by EXT_mesh_gpu_instancing"
        return f"{head}; {how}): {each}"
    parts = [f"{got['views']} views of {got['size']} px (albedo, normals, depth)",
             "its mesh" if got["mesh"] else "no mesh (an asset file's views alone)",
             f"its sun atlas of {got['sun_atlas']} texels" if got["sun_atlas"] else "no sun atlas"]
    if got.get("impostor"):
        parts.append(f"its octahedral impostor ({IMPOSTOR_FRAMES}x{IMPOSTOR_FRAMES} frames of "
                     f"{got['impostor']} px, as many bytes as the views)")
    if got.get("lod"):
        parts.append(lod_words(got["lod"]))
    for level in (got.get("lod_measured") or {}).get("levels", []):
        card = [v["card_psnr_db"] for v in level["views"]]
        morph = [v["morph_psnr_db"] for v in level["views"]]
        parts.append(f"the card at {level['height_px']:g} px: {min(card):.1f}-{max(card):.1f} dB against the "
                     f"mesh over elevations {LOD_ELEVATIONS_DEG[0]:g}-{LOD_ELEVATIONS_DEG[-1]:g} deg (the "
                     f"view morph {min(morph):.1f}-{max(morph):.1f} dB)")
    return f"{head}): {got['name']}, " + ", ".join(parts)


def lod_words(lod: dict[str, Any]) -> str:
    """The levels of detail of :meth:`~morphkit.export.lod.LodChain.to_json` in words.

    Parameters
    ----------
    lod : dict
        The chain's JSON.

    Returns
    -------
    str
    """
    levels = lod["levels"]
    if len(levels) == 1 and not lod["culled_below_px"]:
        text = "no levels of detail (the plan draws the mesh at every size)"
    else:
        each = [f"{lv['kind']} from {lv['min_height_px']:g} px (coverage {lv['screen_coverage']:.4g})"
                if lv["min_height_px"] > 0 else f"{lv['kind']} below" for lv in levels]
        tail = f", nothing below {lod['culled_below_px']:g} px" if lod["culled_below_px"] else ""
        text = "MSFT_lod from the plan: " + ", ".join(each) + tail
    return text + "".join(f"; {n}" for n in lod.get("notes", []))
