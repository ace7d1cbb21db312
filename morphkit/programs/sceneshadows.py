"""A scene's shadows: each asset's sun atlas, read from its bake or baked from its mesh, the
frames' shadow from them (:class:`~morphkit.sunlit.receivers.AtlasShadow`, or
:class:`~morphkit.sunlit.receivers.FilteredAtlasShadow` for ``soft: "pcss"``) and the ray cast the
truth is drawn with (:class:`~morphkit.sunlit.raycast.RayCastShadow`, over the same sun directions).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Any

import trimesh

from .. import tol
from ..errors import ValidationError, expected_got
from ..render import Renderer
from ..scenes.description import SOFT_PCSS, SceneShadows
from .sources import ResolvedAssets

__all__ = ["scene_shadows"]


def scene_shadows(
    shadows: SceneShadows,
    res: ResolvedAssets,
    renderer: Renderer,
    names: Sequence[str],
    specs: Sequence[str],
    head: str,
    what: str,
) -> tuple[Any, Any]:
    """Each asset's sun atlas, read from its bake when that holds one that serves
    (:func:`morphkit.bake.reuse.baked_sun_atlases`) or else baked from its mesh (once, for this
    run), and the frames' shadow from them; the comparisons' real meshes get the ray cast over
    the same sun directions."""
    from ..bake.reuse import baked_sun_atlases
    from ..sunlit.raycast import RayCastShadow
    from ..sunlit.receivers import SCENE_ATLAS_SIZE, AtlasShadow, FilteredAtlasShadow, bake_scene_atlases

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
    size = SCENE_ATLAS_SIZE if shadows.sun_atlas_size is None else shadows.sun_atlas_size
    atlases, said = baked_sun_atlases(list(specs), list(names), meshes, size)
    bake = [nm for nm in names if nm not in atlases]
    if bake:
        said.append(f"baking those of {', '.join(bake)} ({size} texels)")
    print(f"{head}sun atlases: " + "; ".join(said), file=sys.stderr)
    atlases = bake_scene_atlases(meshes, renderer, atlases, size=size)
    disc = shadows.sun_radius_deg
    if shadows.soft == SOFT_PCSS:
        return (
            FilteredAtlasShadow(atlases, disc_deg=disc),
            RayCastShadow(meshes, samples=tol.SUN_DISC_TRUTH_SAMPLES, disc_deg=disc),
        )
    samples = int(shadows.soft or 1)
    return (
        AtlasShadow(atlases, samples=samples, disc_deg=disc),
        RayCastShadow(meshes, samples=samples, disc_deg=disc),
    )
