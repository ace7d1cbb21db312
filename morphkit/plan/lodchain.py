"""The levels of detail a plan implies for an engine: its bands as one chain of levels
(:class:`~morphkit.export.lod.LodChain`) switched on screen coverage.

A plan (:mod:`morphkit.plan.planfile`) chooses a representation per band of an asset's billboards:
an octave of on-screen height and an elevation band. An engine switches one node's level on one
number, its screen coverage (:mod:`morphkit.conventions`, "Level of detail"), so
:func:`lod_chain` turns the bands into a chain of levels, each drawn down to a least on-screen
height:

1. each octave takes the most exact representation any of its elevation bands chose (in the order
   of :data:`~morphkit.plan.representations.REPRESENTATIONS`: culled, classic card, nearest view,
   view morph, mesh), as the chain cannot see elevation;
2. going down in size no level is more exact than the one above it: an octave takes the most
   exact of its own and every smaller octave's choice (the least exact chain that is nowhere
   less exact than the plan; the plan's choices need not be monotone in size), and octaves
   smaller than the smallest the plan saw take that one's;
3. the mesh stays the mesh, culling draws nothing, and the billboard representations become the
   one stand-in an engine draws with its own shaders, :func:`~morphkit.export.lod.cross_card`;
4. level 0 is the mesh (a reader without ``MSFT_lod`` draws level 0 alone): where the plan's
   largest octave is not the mesh, the mesh is drawn from a coverage of 1 (the asset's disc as
   large as the screen) up.

The chain is therefore at least as exact as the plan at every size the plan saw, where the stand-in
is at least as exact as the billboard it replaces; what the stand-in errs is measured
(:func:`morphkit.programs.export.measure_representations`), not assumed.
"""

from __future__ import annotations

import math

from ..errors import ValidationError, expected_got
from ..export.lod import LOD_CARD, LOD_MESH, LodChain, LodLevel
from ..scenes.description import DEFAULT_SHAPE
from ..validate import as_shape
from .planfile import ScenePlan
from .representations import BILLBOARD_REPRESENTATIONS, CULL, MESH, REPRESENTATIONS

__all__ = ["lod_chain"]

_RANK = {r.name: k for k, r in enumerate(REPRESENTATIONS)}
_BILLBOARDS = {r.name for r in BILLBOARD_REPRESENTATIONS}


def _height_at(coverage: float, shape: tuple[int, int], radius: float, half_height: float) -> float:
    """The inverse of :func:`screen_coverage`."""
    h, w = shape
    return 2.0 * half_height / radius * math.sqrt(coverage * w * h / math.pi)


def lod_chain(plan: ScenePlan, asset: str, *, radius: float, half_height: float,
              shape: tuple[int, int] | None = None) -> LodChain:
    """The chain ``plan`` implies for ``asset`` (the module notes).

    Parameters
    ----------
    plan : ScenePlan
        The plan (its bands' heights known: :attr:`~morphkit.plan.planfile.ScenePlan.base_height`).
    asset : str
        One of its assets.
    radius : float
        The asset's bounding radius (:func:`bounding_radius`).
    half_height : float
        Its quad's half height, in the radius's units.
    shape : (H, W), optional
        The screen (default: the plan's; a plan that does not say: the scenes' default, noted).

    Returns
    -------
    LodChain

    Raises
    ------
    ValidationError
        An asset the plan does not plan; a plan without its bands' heights.

    Examples
    --------
    A plan that draws the mesh from 64 px up, a classic card from 16 to 64 px and nothing below:

    >>> from morphkit.plan import BandChoice, Budget, ScenePlan
    >>> choice = BandChoice({("tree", 0, 0): "mesh", ("tree", 1, 0): "classic",
    ...                      ("tree", 2, 1): "morph", ("tree", 3, 0): "cull"})
    >>> plan = ScenePlan(Budget.parse(["billboard-psnr=20"]), choice, True, ("tree",),
    ...                  base_height={"tree": 128}, shape=(480, 640))
    >>> from morphkit.plan.lodchain import lod_chain
    >>> chain = lod_chain(plan, "tree", radius=1.0, half_height=1.0)
    >>> [(lv.kind, lv.min_height_px) for lv in chain.levels]
    [('mesh', 64.0), ('card', 16.0)]
    """
    if asset not in plan.assets:
        raise ValidationError(expected_got("the plan's asset", f"one of {list(plan.assets)}", repr(asset)))
    notes: list[str] = []
    if shape is None:
        shape = plan.shape
    if shape is None:
        shape = DEFAULT_SHAPE
        notes.append(f"the plan does not say its image size: coverage is of {shape[1]}x{shape[0]}, "
                     "the scenes' default")
    shape = as_shape(shape, "screen shape")
    best: dict[int, int] = {}
    for (name, level, _), rep in plan.choice.choices.items():
        if name == asset:
            best[int(level)] = max(best.get(int(level), -1), _RANK[rep])
    if not best:
        notes.append("the plan never saw the asset on screen: the mesh at every size")
        return LodChain(asset, (LodLevel(LOD_MESH, 0.0, ()),), shape, radius, half_height, tuple(notes))
    h0 = plan.base_height.get(asset)
    if h0 is None:
        raise ValidationError(expected_got(f"the plan of {asset!r}", "its bands' heights (height_px)",
                                           "a plan without them"))
    deepest = max(best)
    chosen: list[int] = []  # octave L's rank: the most exact over it and every smaller octave
    run = -1
    for level in range(deepest, -1, -1):
        run = max(run, best.get(level, -1))
        chosen.append(run)
    chosen.reverse()
    names = [REPRESENTATIONS[k].name for k in chosen]

    def kind(rep: str) -> str | None:
        return LOD_MESH if rep == MESH else LOD_CARD if rep in _BILLBOARDS else None

    levels: list[LodLevel] = []
    for level, rep in enumerate(names):
        k = kind(rep)
        low = h0 / 2.0 ** (level + 1)
        if levels and levels[-1].kind == k:
            prev = levels[-1]
            reps = prev.stands_for + ((rep,) if rep not in prev.stands_for else ())
            levels[-1] = LodLevel(k, low, reps)
        elif k is not None:
            levels.append(LodLevel(k, low, (rep,)))
        else:
            break  # culled from here down
    if names[-1] != CULL and levels:
        levels[-1] = LodLevel(levels[-1].kind, 0.0, levels[-1].stands_for)
    if not levels or levels[0].kind != LOD_MESH:
        top = _height_at(1.0, shape, radius, half_height)
        notes.append("the plan draws no octave it saw as the mesh: the mesh from a coverage of 1 up")
        levels.insert(0, LodLevel(LOD_MESH, max(top, levels[0].min_height_px if levels else 0.0), ()))
    return LodChain(asset, tuple(levels), shape, float(radius), float(half_height), tuple(notes))
