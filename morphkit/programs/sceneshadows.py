"""A scene's shadows: each asset's sun atlas, read from its bake or baked from its mesh, the
frames' shadow from them (:class:`~morphkit.sunlit.receivers.AtlasShadow`, or
:class:`~morphkit.sunlit.receivers.FilteredAtlasShadow` for ``soft: "pcss"``) and the ray cast the
truth is drawn with (:class:`~morphkit.sunlit.raycast.RayCastShadow`, over the same sun directions).
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import trimesh

from .. import tol
from ..errors import FileFormatError, ValidationError, expected_got
from ..render import Renderer
from ..scenes.description import SOFT_PCSS, SceneShadows
from ..sunlit.sunatlasfile import read_sun_atlas, write_sun_atlas
from .sources import ResolvedAssets

__all__ = ["scene_shadows", "SceneCasters"]


@dataclass(eq=False)
class SceneCasters:
    """The casters of a scene's shadows: each asset's mesh (its parts concatenated) and where it
    came from; their sun atlases at any size, read from their bakes where those serve
    (:func:`morphkit.bake.reuse.baked_sun_atlases`) or baked (once a size, for this run).

    Parameters
    ----------
    meshes : dict of str to trimesh.Trimesh
        Each asset's mesh, as its billboards were baked from it.
    specs : list of str
        Each asset's source (its bake is looked for there), in the order of ``meshes``.
    head : str, optional
        The start of the line said when atlases are read or baked.
    cache : path-like, optional
        A folder the atlases baked are kept in between runs, named by mesh hash, size and sun
        directions, and read from (None: none kept; ``morphkit plan`` keeps its candidates' there).
    """

    meshes: dict[str, trimesh.Trimesh]
    specs: list[str]
    head: str = ""
    cache: Path | None = None
    _atlases: dict[int, dict[str, Any]] = field(default_factory=dict, repr=False, init=False)

    @classmethod
    def of(cls, res: ResolvedAssets, names: Sequence[str], specs: Sequence[str], head: str,
           what: str) -> SceneCasters:
        """The casters of ``names`` from the resolved assets.

        Parameters
        ----------
        res : ResolvedAssets
            The scene's assets, with their meshes' items.
        names : sequence of str
            The asset names.
        specs : sequence of str
            Their sources.
        head : str
            The start of the lines said.
        what : str
            What asked for shadows (named in the error).

        Returns
        -------
        SceneCasters

        Raises
        ------
        ValidationError
            An asset without a mesh (its sun atlas is baked from it).
        """
        missing = [nm for nm in names if nm not in res.items]
        if missing:
            raise ValidationError(
                expected_got(
                    what,
                    "every asset's mesh (its sun atlas is baked from it)",
                    "; ".join(f"{nm}: {res.skipped.get(nm, 'no mesh')}" for nm in missing),
                )
            )
        meshes = {}
        for nm in names:
            parts = [it.mesh for it in res.items[nm]]
            meshes[nm] = parts[0] if len(parts) == 1 else trimesh.util.concatenate(parts)
        return cls(meshes, list(specs), head)

    def atlases(self, renderer: Renderer, size: int | None = None) -> dict[str, Any]:
        """Each asset's sun atlas of ``size`` texels a side (default
        :data:`~morphkit.sunlit.receivers.SCENE_ATLAS_SIZE`), read or baked once per size.

        Parameters
        ----------
        renderer : Renderer
            Bakes the atlases not read.
        size : int, optional
            Texels.

        Returns
        -------
        dict of str to SunAtlas
        """
        from ..bake.reuse import baked_sun_atlases
        from ..sunlit.receivers import SCENE_ATLAS_SIZE, bake_scene_atlases

        size = SCENE_ATLAS_SIZE if size is None else int(size)
        if size not in self._atlases:
            names = list(self.meshes)
            atlases, said = baked_sun_atlases(self.specs, names, self.meshes, size)
            kept = {nm: self._kept(nm, size) for nm in names if nm not in atlases}
            for nm, path in kept.items():
                if path is not None and path.is_file():
                    try:
                        atlases[nm] = read_sun_atlas(path)
                    except FileFormatError:
                        continue  # a damaged copy: baked again
            read = [nm for nm in kept if nm in atlases]
            if read:
                said.append(f"those of {', '.join(read)} read from the cache {self.cache}")
            bake = [nm for nm in names if nm not in atlases]
            if bake:
                said.append(f"baking those of {', '.join(bake)} ({size} texels)")
            print(f"{self.head}sun atlases: " + "; ".join(said), file=sys.stderr)
            self._atlases[size] = bake_scene_atlases(self.meshes, renderer, atlases, size=size)
            for nm in bake:
                path = kept.get(nm)
                if path is not None:
                    path.parent.mkdir(parents=True, exist_ok=True)
                    write_sun_atlas(path, self._atlases[size][nm])
        return self._atlases[size]

    def _kept(self, name: str, size: int) -> Path | None:
        """Where the cache keeps ``name``'s atlas of ``size`` texels (None: no cache)."""
        from ..billboard.baking.bakelook import mesh_hash
        from ..sunlit.receivers import SCENE_ATLAS_DOME

        if self.cache is None:
            return None
        dome = hashlib.sha256(repr((SCENE_ATLAS_DOME.rings, SCENE_ATLAS_DOME.top)).encode()).hexdigest()[:8]
        return Path(self.cache) / f"{name}.{mesh_hash(self.meshes[name])[:16]}.{size}.{dome}.npz"

    def shadow(self, shadows: SceneShadows, renderer: Renderer) -> Any:
        """The frames' shadow ``shadows`` describes, from the atlases of its size: the atlases' field
        map (:class:`~morphkit.sunlit.receivers.AtlasShadow`, one map per direction over the sun's
        disc), or one map filtered over the disc for ``"pcss"``
        (:class:`~morphkit.sunlit.receivers.FilteredAtlasShadow`).

        Parameters
        ----------
        shadows : SceneShadows
            How soft, and the atlases' size.
        renderer : Renderer
            Bakes atlases not read.

        Returns
        -------
        SceneShadow
        """
        from ..sunlit.receivers import AtlasShadow, FilteredAtlasShadow

        atlases = self.atlases(renderer, shadows.sun_atlas_size)
        if shadows.soft == SOFT_PCSS:
            return FilteredAtlasShadow(atlases, disc_deg=shadows.sun_radius_deg)
        return AtlasShadow(atlases, samples=int(shadows.soft or 1), disc_deg=shadows.sun_radius_deg)

    def truth(self, shadows: SceneShadows) -> Any:
        """The ray cast the truth is drawn with, over the sun directions of ``shadows``
        (:data:`~morphkit.tol.SUN_DISC_TRUTH_SAMPLES` of them for ``"pcss"``).

        Parameters
        ----------
        shadows : SceneShadows
            How soft.

        Returns
        -------
        RayCastShadow
        """
        from ..sunlit.raycast import RayCastShadow

        samples = tol.SUN_DISC_TRUTH_SAMPLES if shadows.soft == SOFT_PCSS else int(shadows.soft or 1)
        return RayCastShadow(self.meshes, samples=samples, disc_deg=shadows.sun_radius_deg)


def scene_shadows(
    shadows: SceneShadows,
    res: ResolvedAssets,
    renderer: Renderer,
    names: Sequence[str],
    specs: Sequence[str],
    head: str,
    what: str,
) -> tuple[Any, Any, SceneCasters]:
    """The frames' shadow ``shadows`` describes and the ray-cast truth's, with their casters
    (:class:`SceneCasters`: a plan's other shadows are made from them).

    Parameters
    ----------
    shadows : SceneShadows
        The scene's shadows.
    res : ResolvedAssets
        Its assets.
    renderer : Renderer
        Bakes the atlases not read.
    names, specs : sequence of str
        The asset names and their sources.
    head : str
        The start of the lines said.
    what : str
        What asked for shadows (named in an error).

    Returns
    -------
    shadow : SceneShadow
        The frames'.
    truth : RayCastShadow
        The truth's.
    casters : SceneCasters

    Raises
    ------
    ValidationError
        An asset without a mesh.
    """
    casters = SceneCasters.of(res, names, specs, head, what)
    return casters.shadow(shadows, renderer), casters.truth(shadows), casters
