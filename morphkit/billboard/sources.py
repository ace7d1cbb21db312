"""Where a scene's assets come from: a sample mesh name (baked now) or an asset file (loaded).

:func:`resolve_assets` turns the ``--asset`` arguments of ``morphkit billboards``
into assets and, for the mesh mode (the ground truth), the items each asset was
baked from:

* a name of :data:`morphkit.meshes.BILLBOARD_MESHES` (``tree``, ``person``,
  ``teapot``, ...): the sample mesh is normalised and baked
  (:func:`~morphkit.billboard.bake.bake_asset`);
* a path to an existing ``.npz`` file: the asset is loaded
  (:meth:`~morphkit.billboard.asset.BillboardAsset.load`); its mesh is known
  (for the mesh mode) when the asset's name is a sample mesh whose hash matches.

Anything else is a :class:`~morphkit.errors.ValidationError` naming what was
expected.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..errors import ValidationError, expected_got
from ..meshes import BILLBOARD_MESHES, normalize, sample_mesh
from ..protocols import SceneRenderer
from ..scene import Item
from .asset import BillboardAsset, bake_items, mesh_hash
from .bake import bake_asset

__all__ = ["ResolvedAssets", "check_specs", "resolve_assets"]


@dataclass(frozen=True)
class ResolvedAssets:
    """Assets by name, and the bake items of those whose mesh is known (object frame).

    Parameters
    ----------
    assets : dict of str to BillboardAsset
        Assets by name.
    items : dict of str to list of Item
        Bake items (object frame) by asset name, for the assets whose mesh is known.
    """

    assets: dict[str, BillboardAsset]
    items: dict[str, list[Item]]


def check_specs(specs: Sequence[str]) -> None:
    """Refuse, before any work, a spec that is neither a sample mesh name nor an existing
    ``.npz`` file (ValidationError), or an empty list.

    Parameters
    ----------
    specs : sequence of str
        Sample mesh names or ``.npz`` asset file paths.

    Raises
    ------
    ValidationError
        An empty list or a spec that is neither.
    """
    if not specs:
        raise ValidationError(expected_got("assets", "at least one --asset", "none"))
    for spec in specs:
        path = Path(spec)
        if spec not in BILLBOARD_MESHES and not (path.suffix.lower() == ".npz" and path.is_file()):
            want = f"a sample mesh name (one of {list(BILLBOARD_MESHES)}) or an existing .npz asset file"
            raise ValidationError(expected_got("asset", want, repr(spec)))


def resolve_assets(specs: Sequence[str], renderer: SceneRenderer, *, views: int = 8, size: int = 128,
                   levels: int = 3, progress: bool = False) -> ResolvedAssets:
    """Bake or load each of ``specs`` (see the module notes).

    Parameters
    ----------
    specs : sequence of str
        Sample mesh names or ``.npz`` asset files.
    renderer : SceneRenderer
        For baking.
    views, size, levels : int
        Bake options (:func:`~morphkit.billboard.bake.bake_asset`): K, level-0 image side, pyramid levels.
    progress : bool
        Progress bars while baking.

    Returns
    -------
    ResolvedAssets

    Raises
    ------
    ValidationError
        A spec that is neither, or two assets with one name.
    FileFormatError
        An asset file that cannot be read.
    """
    check_specs(specs)
    assets: dict[str, BillboardAsset] = {}
    items: dict[str, list[Item]] = {}
    for spec in specs:
        path = Path(spec)
        if spec in BILLBOARD_MESHES:
            mesh = normalize(sample_mesh(spec))
            asset = bake_asset(mesh, renderer, name=spec, views=views, size=size, levels=levels,
                               progress=progress)
            known = mesh
        else:
            asset = BillboardAsset.load(path)
            known = None
            if asset.name in BILLBOARD_MESHES:
                mesh = normalize(sample_mesh(asset.name))
                known = mesh if mesh_hash(mesh) == asset.mesh_hash else None
        if asset.name in assets:
            raise ValidationError(expected_got("assets", "distinct names", f"{asset.name!r} twice"))
        assets[asset.name] = asset
        if known is not None:
            items[asset.name] = bake_items(known)
    return ResolvedAssets(assets, items)
