"""What a bake made, found again by a run that needs it: the sun atlases beside baked assets.

``morphkit bake --dome --sun-atlas`` writes an asset's relightable billboard and its sun atlas side by
side, both listed in the manifest under the asset (:func:`~.manifest.baked_beside`); ``morphkit
billboards --shadows`` given the ``.dome.npz`` files reads the atlases instead of baking them
(:func:`baked_sun_atlases`), when they are of the size and sun directions asked and of the assets'
own meshes; the others are baked at the run, as without a bake, and the run's line says why. An atlas
file that is there but cannot be read (damaged, of another version) is refused: one
:class:`~morphkit.errors.FileFormatError` naming the asset and the file and what to do, never baked
over in silence.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import trimesh

from ..errors import FileFormatError, ValidationError
from ..sunlit.receivers import SCENE_ATLAS_DOME
from ..sunlit.sunatlas import SunAtlas
from ..sunlit.sunatlasfile import read_sun_atlas
from .kinds import SunAtlasKind
from .manifest import baked_beside

__all__ = ["baked_sun_atlases"]


def baked_sun_atlases(specs: Sequence[str], names: Sequence[str], meshes: Mapping[str, trimesh.Trimesh],
                      size: int) -> tuple[dict[str, SunAtlas], list[str]]:
    """The sun atlases a bake made beside the asset files among ``specs``.

    Parameters
    ----------
    specs : sequence of str
        The assets as given (sample names, mesh files, ``.npz`` asset files), one per name.
    names : sequence of str
        The assets' names, in the order of ``specs``.
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh: an atlas is taken only if it was baked from it (by hash).
    size : int
        The texels a side asked for: an atlas of another size is not taken.

    Returns
    -------
    atlases : dict of str to SunAtlas
        The atlases taken, by asset name.
    said : list of str
        A phrase for each atlas found: taken, or why not.

    Raises
    ------
    FileFormatError
        A damaged atlas file (naming the asset and the file, and what to do) or manifest.
    """
    found: dict[str, SunAtlas] = {}
    said: list[str] = []
    if len(specs) != len(names):
        return found, said
    for spec, nm in zip(specs, names, strict=True):
        if not spec.lower().endswith(".npz") or not Path(spec).is_file() or nm not in meshes:
            continue
        path = baked_beside(spec, SunAtlasKind.name)
        if path is None:
            continue
        try:
            atlas = read_sun_atlas(path)
        except FileFormatError as exc:
            raise FileFormatError(f"the bake's sun atlas of asset {nm!r}: {exc} (bake it again with morphkit "
                                  "bake --sun-atlas, or remove the file to bake one at the run)") from None
        if atlas.size != size:
            said.append(f"{path.name}: {atlas.size} texels, not {size}: baked again")
            continue
        if (atlas.dome.rings, atlas.dome.top) != (SCENE_ATLAS_DOME.rings, SCENE_ATLAS_DOME.top):
            said.append(f"{path.name}: {atlas.dome.views} sun directions, not the scene's "
                        f"{SCENE_ATLAS_DOME.views}: baked again")
            continue
        try:
            atlas.check_mesh(meshes[nm])
        except ValidationError:
            said.append(f"{path.name}: baked from another mesh than {nm}'s: baked again")
            continue
        found[nm] = atlas
        said.append(f"{nm}'s from the bake ({path.name}, {size} texels)")
    return found, said
