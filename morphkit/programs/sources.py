"""Where a scene's assets come from: a sample mesh name or a mesh file (baked now), or an asset file.

:func:`resolve_assets` turns the ``--asset`` arguments of ``morphkit billboards``
into assets and, for the mesh mode (the ground truth), the items each asset was
baked from (:meth:`~morphkit.billboard.asset.BillboardAsset.items`: the same look):

* a name of :data:`morphkit.meshes.BILLBOARD_MESHES` (``tree``, ``person``,
  ``teapot``, ...): the sample mesh is normalised and baked
  (:func:`~morphkit.billboard.baking.ringviews.bake_asset`) in the 3-D checker
  (``appearance="checker"``: the sample meshes have no look of their own);
* a path to an existing mesh file (:data:`MESH_SUFFIXES`: OBJ, GLB/glTF, PLY, ...):
  loaded with :func:`morphkit.meshes.load_mesh` (its look kept, turned ``+z`` up by
  ``up``), baked in its own look (``appearance="own"``), named after the file's stem;
* a path to an existing ``.npz`` file: the asset is loaded
  (:meth:`~morphkit.billboard.asset.BillboardAsset.load`) and keeps its own name
  (the file's stem when it has bake_asset's default name ``"asset"``); its mesh is
  known (for the mesh mode) when the asset's name is a sample mesh, or a mesh file
  named like the asset or the file (``NAME.obj``, ``.glb``, ...) lies beside it, or
  ``records`` name its input (a bake library's manifest, ``morphkit bake --billboard
  [--dome]``: the recorded input, unchanged since the bake, with its up axis), and
  that mesh's hash (shape and look) is the asset's. When none is found,
  :attr:`ResolvedAssets.skipped` says why.

Anything else is a :class:`~morphkit.errors.ValidationError` naming what was
expected.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import trimesh

from ..billboard.asset import BillboardAsset, mesh_hash
from ..billboard.baking.ringviews import bake_asset
from ..billboard.domeasset import DomeAsset, bake_dome
from ..billboard.formats.assetfile import peek_meta
from ..errors import MeshError, ValidationError, expected_got
from ..meshes import BILLBOARD_MESHES, load_mesh, normalize, resolve_up, sample_mesh
from ..protocols import InputRecords, SceneRenderer
from ..scene import Item
from ..views.dome import ViewDome

__all__ = ["asset_name", "asset_file_stem", "ResolvedAssets", "MESH_SUFFIXES", "check_specs",
           "resolve_assets", "default_levels"]

#: Mesh file extensions ``--asset`` bakes on the fly (what :func:`morphkit.meshes.load_mesh` reads).
MESH_SUFFIXES = (".obj", ".glb", ".gltf", ".ply", ".stl", ".off")


@dataclass(frozen=True)
class ResolvedAssets:
    """Assets by name, and the bake items of those whose mesh is known (object frame).

    Parameters
    ----------
    assets : dict of str to BillboardAsset or DomeAsset
        Assets by name (ring assets, or relightable ones when resolved with a dome).
    items : dict of str to list of Item
        Bake items (object frame) by asset name, for the assets whose mesh is known.
    skipped : dict of str to str
        Asset name -> why its mesh is not known (no comparison with the real mesh).
    """

    assets: dict[str, BillboardAsset | DomeAsset]
    items: dict[str, list[Item]]
    skipped: dict[str, str] = field(default_factory=dict)


def default_levels(size: int, most: int = 3) -> int:
    """Pyramid levels of a bake at ``size``: ``most``, fewer where the smallest level's side
    would be under 8 px (a 16 px asset has 2).

    Parameters
    ----------
    size : int
        Level-0 image side, pixels (>= 8).
    most : int
        The most levels wanted.

    Returns
    -------
    int
        At least 1.

    Examples
    --------
    >>> from morphkit.programs.sources import default_levels
    >>> default_levels(128), default_levels(16), default_levels(8)
    (3, 2, 1)
    """
    n = 1
    while n < most and round(size / 2**n) >= 8:
        n += 1
    return n


def asset_name(spec: str) -> str:
    """The name an asset of ``spec`` takes (as :func:`resolve_assets` names it): a sample's own, a
    mesh file's stem, an asset file's recorded name (its file's, without ``.npz``, ``.billboard``
    and ``.dome``, when it records none or the default ``"asset"``, or cannot be read here).

    Parameters
    ----------
    spec : str
        A sample mesh name, a mesh file or a ``.npz`` asset file.

    Returns
    -------
    str

    Examples
    --------
    >>> from morphkit.programs.sources import asset_name
    >>> asset_name("tree"), asset_name("models/oak.glb"), asset_name("bake/oak.dome.npz")
    ('tree', 'oak', 'oak')
    """
    path = Path(spec)
    if spec in BILLBOARD_MESHES:
        return spec
    if path.suffix.lower() in MESH_SUFFIXES:
        return path.stem
    recorded = (peek_meta(path) or {}).get("name")
    if isinstance(recorded, str) and recorded and recorded != "asset":
        return recorded
    return asset_file_stem(path)


def asset_file_stem(path: str | Path) -> str:
    """An asset file's name without ``.npz`` and the kind before it (``.billboard``, ``.dome``).

    Parameters
    ----------
    path : str or pathlib.Path

    Returns
    -------
    str

    Examples
    --------
    >>> from morphkit.programs.sources import asset_file_stem
    >>> asset_file_stem("bake/oak.dome.npz"), asset_file_stem("oak.npz"), asset_file_stem("oak")
    ('oak', 'oak', 'oak')
    """
    name = Path(path).name
    if name.lower().endswith(".npz"):
        name = name[: -len(".npz")]
    return name.removesuffix(".billboard").removesuffix(".dome")


def check_specs(specs: Sequence[str]) -> None:
    """Refuse, before any work, a spec that is neither a sample mesh name nor an existing
    ``.npz`` or mesh file (ValidationError), or an empty list.

    Parameters
    ----------
    specs : sequence of str
        Sample mesh names, mesh files or ``.npz`` asset file paths.

    Raises
    ------
    ValidationError
        An empty list or a spec that is neither.
    """
    if not specs:
        raise ValidationError(expected_got("assets", "at least one --asset", "none"))
    for spec in specs:
        path = Path(spec)
        suffix = path.suffix.lower()
        if spec not in BILLBOARD_MESHES and not (suffix in (".npz", *MESH_SUFFIXES) and path.is_file()):
            want = (f"a sample mesh name (one of {list(BILLBOARD_MESHES)}), an existing mesh file "
                    f"({', '.join(MESH_SUFFIXES)}) or an existing .npz asset file")
            raise ValidationError(expected_got("asset", want, repr(spec)))


def _beside(path: Path, asset: BillboardAsset | DomeAsset, records: InputRecords | None
            ) -> tuple[trimesh.Trimesh | None, str]:
    """The mesh of a loaded asset: a sample mesh of its name, or a mesh file beside the asset
    file named like the asset or the file; ``(None, why)`` when there is none that matches."""
    if asset.name in BILLBOARD_MESHES:
        mesh = normalize(sample_mesh(asset.name))
        if mesh_hash(mesh, asset.appearance) == asset.mesh_hash:
            return mesh, ""
        return None, f"sample mesh {asset.name!r} does not match the asset's hash (baked from another mesh)"
    stem = asset_file_stem(path)
    stems = list(dict.fromkeys([asset.name, stem]))
    found = [path.with_name(st + suf) for st in stems for suf in MESH_SUFFIXES
             if path.with_name(st + suf).is_file()]
    up = asset.source_up or "auto"
    for f in found:
        try:
            mesh = load_mesh(f, up=up)
        except MeshError:
            continue
        if mesh_hash(mesh, asset.appearance) == asset.mesh_hash:
            return mesh, ""
    record = None if records is None else records.find(path)  # a bake library's: its recorded input
    if isinstance(record, tuple):
        try:
            mesh = load_mesh(record[0], up=record[1])
        except MeshError:
            mesh = None
        if mesh is not None and mesh_hash(mesh, asset.appearance) == asset.mesh_hash:
            return mesh, ""
        record = f"{record[0]} (recorded for {path.name}) does not match the asset's hash"
    if record is not None:
        return None, f"{record} (pass the mesh file itself as --asset)"
    if found:
        return None, (f"{', '.join(f.name for f in found)} beside {path.name} does not match the asset's "
                      f"hash (another shape or look)")
    return None, (f"no mesh file {' or '.join(stems)}{{{','.join(MESH_SUFFIXES)}}} beside {path.name} "
                  "(pass the mesh file itself as --asset to bake and compare it)")


def resolve_assets(specs: Sequence[str], renderer: SceneRenderer, *, views: int = 8, size: int = 128,
                   levels: int | None = None, up: str = "auto", progress: bool = False,
                   dome: ViewDome | None = None, records: InputRecords | None = None,
                   meshes: Mapping[str, trimesh.Trimesh] | None = None) -> ResolvedAssets:
    """Bake or load each of ``specs`` (see the module notes).

    Parameters
    ----------
    specs : sequence of str
        Sample mesh names, mesh files or ``.npz`` asset files.
    renderer : SceneRenderer
        For baking.
    views, size : int
        Bake options (:func:`~morphkit.billboard.baking.ringviews.bake_asset`): K, level-0 image side.
    levels : int, optional
        Pyramid levels; default: 3, fewer where the smallest level would be under 8 px
        (:func:`default_levels`).
    up : {"auto", "z", "y"}
        Up axis of the mesh files (:func:`morphkit.meshes.load_mesh`); recorded in their assets.
    progress : bool
        Progress bars while baking.
    dome : ViewDome, optional
        Relightable assets over these views instead (:func:`~.domeasset.bake_dome`, ``views``
        not used; ``.npz`` files are read as :class:`~.domeasset.DomeAsset` -- a ring asset
        file is refused with "re-bake").
    records : InputRecords, optional
        Where baked files' inputs are recorded (``morphkit.bake.manifest.ManifestRecords()``:
        the bake library's manifests), so that a loaded asset finds its mesh there too.
    meshes : mapping of str to trimesh.Trimesh, optional
        More assets, baked from these meshes (normalised, :func:`morphkit.meshes.normalize`; a
        glTF scene's) under these names, in their own look, after ``specs``.

    Returns
    -------
    ResolvedAssets
        The assets, the items of those whose mesh is known, and why the others' is not.

    Raises
    ------
    ValidationError
        A spec that is neither, or two assets with one name.
    FileFormatError
        An asset file that cannot be read.
    MeshError
        A mesh file that cannot be loaded, or a bad ``up``.
    """
    if specs or not meshes:
        check_specs(specs)
    levels = default_levels(size) if levels is None else levels
    assets: dict[str, BillboardAsset | DomeAsset] = {}
    items: dict[str, list[Item]] = {}
    skipped: dict[str, str] = {}
    for spec in specs:
        path = Path(spec)
        known: trimesh.Trimesh | None = None
        why = ""
        asset: BillboardAsset | DomeAsset
        if spec in BILLBOARD_MESHES:
            known = normalize(sample_mesh(spec))
            if dome is not None:
                asset = bake_dome(known, renderer, name=spec, dome=dome, size=size, levels=levels,
                                  appearance="checker")
            else:
                asset = bake_asset(known, renderer, name=spec, views=views, size=size, levels=levels,
                                   progress=progress, appearance="checker")
        elif path.suffix.lower() in MESH_SUFFIXES:
            known = load_mesh(path, up=up)
            if dome is not None:
                asset = bake_dome(known, renderer, name=path.stem, dome=dome, size=size, levels=levels,
                                  appearance="own", source_up=resolve_up(path, up))
            else:
                asset = bake_asset(known, renderer, name=path.stem, views=views, size=size, levels=levels,
                                   progress=progress, appearance="own", source_up=resolve_up(path, up))
        else:
            asset = BillboardAsset.load(path) if dome is None else DomeAsset.load(path)
            if asset.name == "asset":  # bake_asset's default name: the file's is more telling
                asset.name = asset_file_stem(path)
            known, why = _beside(path, asset, records)
        _add(assets, items, skipped, asset, known, why)
    for name, mesh in (meshes or {}).items():
        if dome is not None:
            asset = bake_dome(mesh, renderer, name=name, dome=dome, size=size, levels=levels,
                              appearance="own")
        else:
            asset = bake_asset(mesh, renderer, name=name, views=views, size=size, levels=levels,
                               progress=progress, appearance="own")
        _add(assets, items, skipped, asset, mesh, "")
    return ResolvedAssets(assets, items, skipped)


def _add(assets: dict[str, BillboardAsset | DomeAsset], items: dict[str, list[Item]], skipped: dict[str, str],
         asset: BillboardAsset | DomeAsset, known: trimesh.Trimesh | None, why: str) -> None:
    """One resolved asset into the run's tables (its name distinct)."""
    if asset.name in assets:
        raise ValidationError(expected_got("assets", "distinct names", f"{asset.name!r} twice"))
    assets[asset.name] = asset
    if known is not None:
        items[asset.name] = asset.items(known)
    else:
        skipped[asset.name] = why
