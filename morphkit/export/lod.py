"""An asset's levels of detail for engines: the chain a plan implies, the stand-in engines draw,
and the thresholds glTF's ``MSFT_lod`` switches at.

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
   one stand-in an engine draws with its own shaders, :func:`cross_card`;
4. level 0 is the mesh (a reader without ``MSFT_lod`` draws level 0 alone): where the plan's
   largest octave is not the mesh, the mesh is drawn from a coverage of 1 (the asset's disc as
   large as the screen) up.

The chain is therefore at least as exact as the plan at every size the plan saw, where the stand-in
is at least as exact as the billboard it replaces; what the stand-in errs is measured
(:func:`morphkit.programs.export.measure_representations`), not assumed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import PIL.Image
import trimesh

from ..billboard.domeasset import DomeAsset
from ..conventions import ALPHA_CUTOFF
from ..errors import ValidationError, expected_got
from ..meshes.look import DIELECTRIC
from ..plan.planfile import ScenePlan
from ..plan.representations import BILLBOARD_REPRESENTATIONS, CULL, MESH, REPRESENTATIONS
from ..validate import as_positive, as_shape
from .tiles import tile_views

__all__ = ["LOD_MESH", "LOD_CARD", "LodLevel", "LodChain", "lod_chain", "screen_coverage",
           "bounding_radius", "cross_card", "CARD_VIEWS"]

#: The kind of a level that draws the asset's mesh.
LOD_MESH = "mesh"
#: The kind of a level that draws the stand-in (:func:`cross_card`).
LOD_CARD = "card"
#: The quads of :func:`cross_card`.
CARD_VIEWS = 2
_RANK = {r.name: k for k, r in enumerate(REPRESENTATIONS)}
_BILLBOARDS = {r.name for r in BILLBOARD_REPRESENTATIONS}


def screen_coverage(height_px: float, shape: tuple[int, int], radius: float, half_height: float) -> float:
    """The screen coverage of an asset whose quad is ``height_px`` high on screen
    (:mod:`morphkit.conventions`, "Level of detail").

    Parameters
    ----------
    height_px : float
        The quad's on-screen height, pixels (>= 0).
    shape : (H, W)
        The screen, pixels.
    radius : float
        The asset's bounding-sphere radius (:func:`bounding_radius`), in the quad's units.
    half_height : float
        The quad's half height.

    Returns
    -------
    float
        ``pi (radius height_px / (2 half_height))^2 / (W H)``.

    Examples
    --------
    A sphere whose quad is its own diameter, 240 px high on a 640 x 480 screen: its disc's area
    ``pi 120^2`` over the screen's.

    >>> from morphkit.export.lod import screen_coverage
    >>> round(screen_coverage(240.0, (480, 640), 1.0, 1.0), 4)
    0.1473
    """
    h, w = as_shape(shape, "screen shape")
    hh = as_positive(half_height, "half height")
    r = as_positive(radius, "bounding radius") * float(height_px) / (2.0 * hh)
    return math.pi * r * r / (w * h)


def _height_at(coverage: float, shape: tuple[int, int], radius: float, half_height: float) -> float:
    """The inverse of :func:`screen_coverage`."""
    h, w = shape
    return 2.0 * half_height / radius * math.sqrt(coverage * w * h / math.pi)


def bounding_radius(meshes: list[trimesh.Trimesh]) -> float:
    """The radius screen coverage is measured with: half the diagonal of the meshes' bounding box
    (Babylon.js's bounding sphere).

    Parameters
    ----------
    meshes : list of trimesh.Trimesh
        Posed.

    Returns
    -------
    float
    """
    lo = np.min([m.bounds[0] for m in meshes], axis=0)
    hi = np.max([m.bounds[1] for m in meshes], axis=0)
    return float(np.linalg.norm(hi - lo) / 2.0)


@dataclass(frozen=True)
class LodLevel:
    """One level of a chain.

    Parameters
    ----------
    kind : str
        :data:`LOD_MESH` or :data:`LOD_CARD`.
    min_height_px : float
        The least on-screen quad height it is drawn at (0: down to nothing).
    stands_for : tuple of str
        The plan's representations it draws in place of (none: a level the plan did not ask for).
    """

    kind: str
    min_height_px: float
    stands_for: tuple[str, ...] = ()


@dataclass(frozen=True)
class LodChain:
    """An asset's levels, most exact first (the module notes).

    Parameters
    ----------
    asset : str
        The asset's name.
    levels : tuple of LodLevel
        Level 0 the mesh.
    shape : (H, W)
        The screen the plan's heights are of.
    radius : float
        The bounding radius coverage is measured with.
    half_height : float
        The quad's half height, in the radius's units.
    notes : tuple of str, optional
        What the chain assumed, in words.
    """

    asset: str
    levels: tuple[LodLevel, ...]
    shape: tuple[int, int]
    radius: float
    half_height: float
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def switches(self) -> bool:
        """Whether there is anything to switch: more than one level, or culling."""
        return len(self.levels) > 1 or self.levels[-1].min_height_px > 0

    def coverage(self) -> list[float]:
        """``MSFT_screencoverage``: each level's least coverage, then 0 for the empty level after a
        culled chain of one level (the writer's empty node).

        Returns
        -------
        list of float
        """
        out = [screen_coverage(lv.min_height_px, self.shape, self.radius, self.half_height)
               for lv in self.levels]
        if len(self.levels) == 1 and out[0] > 0:
            out.append(0.0)
        return out

    def to_json(self) -> dict[str, Any]:
        """The chain as the sidecar holds it.

        Returns
        -------
        dict
        """
        cov = self.coverage()
        h = self.shape[0]
        return {
            "levels": [{"kind": lv.kind, "min_height_px": round(lv.min_height_px, 3),
                        "min_height_fraction": round(lv.min_height_px / h, 6),
                        "screen_coverage": c, "stands_for": list(lv.stands_for)}
                       for lv, c in zip(self.levels, cov, strict=False)],
            "culled_below_px": round(self.levels[-1].min_height_px, 3),
            "image_size": [int(self.shape[1]), int(self.shape[0])], "radius": self.radius,
            "half_height": self.half_height,
            "coverage": "MSFT_screencoverage: pi (r fy / d)^2 / (W H) of the bounding sphere (Babylon.js); "
            "min_height_fraction: the quad's on-screen height over the screen's",
            "notes": list(self.notes),
        }


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
        from ..scenes.description import SceneDescription

        shape = SceneDescription.__dataclass_fields__["shape"].default
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


def _card_views(asset: DomeAsset) -> list[int]:
    """The views of the dome's lowest ring nearest azimuths 0 and 90 degrees."""
    el = asset.dome.elevations_deg()
    az = asset.dome.azimuths_deg()
    ring = np.flatnonzero(el == el.min())
    out: list[int] = []
    for want in (0.0, 90.0):
        off = np.abs((az[ring] - want + 180.0) % 360.0 - 180.0)
        k = int(ring[int(np.argmin(off))])
        if k not in out:
            out.append(k)
    return out


def cross_card(asset: DomeAsset) -> trimesh.Trimesh:
    """The stand-in an engine draws without morphkit's shaders: the classic crossed card, two quads
    through the pivot, each the image plane of one of the asset's views (of its lowest ring, nearest
    azimuths 0 and 90 degrees) showing that view's albedo, cut out where its coverage is under
    :data:`~morphkit.conventions.ALPHA_CUTOFF`, drawn from both sides.

    Each quad is its view's image plane at the pivot (perpendicular to the view's axis), so the
    texture maps affinely onto it and the card seen from a view's own camera is that view.

    Parameters
    ----------
    asset : DomeAsset
        The views.

    Returns
    -------
    trimesh.Trimesh
        Object frame (``+z`` up), 8 vertices and 4 faces, its ``TextureVisuals`` a ``PBRMaterial``
        (``MASK``, double-sided, dielectric) of the two views tiled (:func:`~.tiles.tile_views`).
    """
    if not isinstance(asset, DomeAsset):
        raise ValidationError(expected_got("asset", "a DomeAsset", type(asset).__name__))
    ks = _card_views(asset)
    rec = asset.record()
    atlas, layout = tile_views(np.stack([rec.rgba[k] for k in ks]))
    ah, aw = atlas.shape[:2]
    vertices, uv, faces = [], [], []
    for t, k in enumerate(ks):
        cam = asset.reference_camera(k)
        h, w = cam.shape
        dist = float(np.linalg.norm(cam.position - asset.pivot))
        corners = np.array([[-0.5, h - 0.5], [w - 0.5, h - 0.5], [w - 0.5, -0.5], [-0.5, -0.5]])
        ray = np.c_[(corners - [cam.cx, cam.cy]) / [cam.fx, cam.fy], np.ones(4)] * dist
        world = (cam.cam2world[:3, :3] @ ray.T).T + cam.position
        ox, oy = layout.origin(t)
        base = len(vertices)
        vertices.extend(world)
        # glTF's texture origin is the top-left; trimesh's UVs are bottom-up (it flips v on export)
        uv.extend([((ox + x + 0.5) / aw, 1.0 - (oy + y + 0.5) / ah) for x, y in corners])
        faces.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]])
    material = trimesh.visual.material.PBRMaterial(
        name="card", baseColorTexture=PIL.Image.fromarray(atlas), alphaMode="MASK",
        alphaCutoff=ALPHA_CUTOFF, doubleSided=True, metallicFactor=DIELECTRIC[0],
        roughnessFactor=DIELECTRIC[1])
    mesh = trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=np.asarray(uv), material=material)
    return mesh
