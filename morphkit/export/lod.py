"""An asset's levels of detail for engines: the chain of levels, the stand-in engines draw, and the
screen coverage glTF's ``MSFT_lod`` switches at.

A :class:`LodChain` is a list of levels, most exact first, each drawn down to a least on-screen
height: :data:`LOD_MESH` (the asset's mesh) or :data:`LOD_CARD` (:func:`cross_card`, the stand-in an
engine draws with its own shaders), nothing below the last. :func:`screen_coverage` converts a
height into the coverage ``MSFT_screencoverage`` holds (:mod:`morphkit.conventions`, "Level of
detail"). The chain a plan implies is :func:`morphkit.plan.lodchain.lod_chain`'s.
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
from ..validate import as_positive, as_shape
from .tiles import tile_views

__all__ = ["LOD_MESH", "LOD_CARD", "LodLevel", "LodChain", "screen_coverage", "bounding_radius",
           "cross_card", "CARD_VIEWS"]

#: The kind of a level that draws the asset's mesh.
LOD_MESH = "mesh"
#: The kind of a level that draws the stand-in (:func:`cross_card`).
LOD_CARD = "card"
#: The quads of :func:`cross_card`.
CARD_VIEWS = 2


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
    """An asset's levels, most exact first (the module notes; a plan's:
    :func:`~morphkit.plan.lodchain.lod_chain`).

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
