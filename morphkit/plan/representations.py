"""What a plan chooses among for each band of an asset's billboards, and the modes that draw a scene
with one representation per band.

A **band** is ``(asset, level, elevation band)``: the asset's pyramid level the frame draws a
billboard at (:func:`~morphkit.billboard.frames.lod.select_levels`: on-screen sizes doubling, so a
band is one octave of on-screen height, level 0 holding every billboard at least half the baked
image's height) and which of :data:`ELEVATION_EDGES_DEG`' intervals its viewing elevation falls in
(:func:`elevation_band`). Every billboard a frame draws is in exactly one band, decided by the
frame's own plan (:meth:`~morphkit.billboard.BillboardScene.plan`), so a table lookup, a
prediction and the frame drawn agree on it.

The **representations**, cheapest first (:attr:`Representation.cost`; the cost model is the work
per billboard, which the planner's verification then times):

* :class:`Culled` -- not drawn: the band's instances are left out of the frame (their shadows are
  still cast: the frame's shadow is the whole field's), so its error is the background against the
  mesh (the game engines' distance and screen-size culling, chosen here by its measured error);
* :class:`ClassicCard` -- the asset's one fixed image from every direction
  (:class:`~morphkit.sunlit.litmodes.ClassicSurface`, :class:`~morphkit.billboard.ClassicMode`);
* :class:`NearestView` -- the reference view nearest the viewing direction, switched, not
  blended (:class:`~morphkit.sunlit.litmodes.NearestSurface`, :class:`~morphkit.billboard.NearestMode`);
* :class:`ViewMorph` -- the view morph of the views around the direction: the dome's per-pixel
  depth morph for relit assets, the ring's pre-warp, morph and post-warp otherwise
  (:class:`~morphkit.sunlit.litmodes.MorphSurface`, :class:`~morphkit.billboard.MorphMode`), cached;
* :class:`RealMesh` -- the asset's own mesh, drawn with the frame's other meshes in one render
  (:mod:`morphkit.plan.mixed`): the truth's drawing, so its error is what the frame's shadows and
  the billboards around it add.

The three between are billboard representations (:class:`BillboardRepresentation`,
:data:`BILLBOARD_REPRESENTATIONS`): each
draws a billboard from an image. :class:`BandChoice` maps bands to representations;
:class:`BandedSurface` (relit dome assets, a :class:`~morphkit.sunlit.litmodes.SurfaceChoice`) and
:class:`BandedRing` (ring assets, a :class:`~morphkit.billboard.BillboardMode`) draw each billboard in
its band's billboard representation, and :mod:`morphkit.plan.mixed` draws the bands of
the real mesh as meshes with them and leaves the culled bands out.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar, NamedTuple, Protocol, runtime_checkable

import numpy as np

from ..billboard import (
    BillboardMode,
    BillboardSource,
    ClassicMode,
    MorphCache,
    MorphMode,
    NearestMode,
    Placement,
)
from ..errors import ValidationError, expected_got
from ..sunlit import ClassicSurface, MorphSurface, NearestSurface
from ..sunlit.litmodes import SurfaceChoice
from ..views.gbuffer import ViewSurface

__all__ = [
    "Representation",
    "Culled",
    "ClassicCard",
    "NearestView",
    "ViewMorph",
    "RealMesh",
    "BillboardRepresentation",
    "BILLBOARD_REPRESENTATIONS",
    "REPRESENTATIONS",
    "MESH",
    "CULL",
    "representation",
    "ELEVATION_EDGES_DEG",
    "elevation_band",
    "band_label",
    "Band",
    "BandChoice",
    "BandedSurface",
    "BandedRing",
]

#: Elevations (degrees) at which one elevation band ends and the next begins: eye level, oblique,
#: from above (a classic card holds at eye level and fails from above; a ring fails above its band).
ELEVATION_EDGES_DEG: tuple[float, ...] = (30.0, 60.0)

class Band(NamedTuple):
    """One band of an asset's billboards: the asset, the pyramid level drawn (its on-screen size)
    and the elevation band (:func:`elevation_band`). A plain ``(asset, level, eband)`` tuple
    compares and hashes equal to it.

    Parameters
    ----------
    asset : str
        The asset's name.
    level : int
        The pyramid level (0 the base, each level half the height of the one before).
    eband : int
        The elevation band.
    """

    asset: str
    level: int
    eband: int


@runtime_checkable
class Representation(Protocol):
    """One way to draw an asset's instances: its name and its place in the cost order.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str
    cost: int


@runtime_checkable
class BillboardRepresentation(Representation, Protocol):
    """A representation drawing each instance as a billboard from one image.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    def surface(self) -> SurfaceChoice:
        """The surface a relit dome asset's billboard takes.

        Returns
        -------
        SurfaceChoice
        """
        ...

    def ring_mode(self, cache: MorphCache) -> BillboardMode:
        """The mode drawing a ring asset's billboards.

        Parameters
        ----------
        cache : MorphCache
            The cache a morph keeps its images in.

        Returns
        -------
        BillboardMode
        """
        ...


@dataclass(frozen=True)
class _ModePair:
    """A representation drawn by one surface choice (relit) and one billboard mode (ring): its
    subclasses name the two classes."""

    name: ClassVar[str] = ""
    cost: ClassVar[int] = 0
    surface_type: ClassVar[type] = MorphSurface
    ring_type: ClassVar[type] = MorphMode

    def surface(self) -> SurfaceChoice:
        """The surface a relit dome asset's billboard takes (:attr:`surface_type`).

        Returns
        -------
        SurfaceChoice
        """
        return self.surface_type()

    def ring_mode(self, cache: MorphCache) -> BillboardMode:
        """The mode drawing a ring asset's billboards (:attr:`ring_type`; a morph keeps its images
        in ``cache``).

        Parameters
        ----------
        cache : MorphCache
            The morphs' cache (a mode that makes none ignores it).

        Returns
        -------
        BillboardMode
        """
        return self.ring_type(cache) if self.ring_type is MorphMode else self.ring_type()


@dataclass(frozen=True)
class ClassicCard(_ModePair):
    """The classic billboard: one image from every direction (the cheapest;
    :class:`~morphkit.sunlit.litmodes.ClassicSurface`, :class:`~morphkit.billboard.ClassicMode`)."""

    name: ClassVar[str] = "classic"
    cost: ClassVar[int] = 1
    surface_type: ClassVar[type] = ClassicSurface
    ring_type: ClassVar[type] = ClassicMode


@dataclass(frozen=True)
class NearestView(_ModePair):
    """The nearest reference view, switched as the direction changes
    (:class:`~morphkit.sunlit.litmodes.NearestSurface`, :class:`~morphkit.billboard.NearestMode`)."""

    name: ClassVar[str] = "nearest"
    cost: ClassVar[int] = 2
    surface_type: ClassVar[type] = NearestSurface
    ring_type: ClassVar[type] = NearestMode


@dataclass(frozen=True)
class ViewMorph(_ModePair):
    """The view morph of the views around the direction, today's default
    (:class:`~morphkit.sunlit.litmodes.MorphSurface`, :class:`~morphkit.billboard.MorphMode`)."""

    name: ClassVar[str] = "morph"
    cost: ClassVar[int] = 3


@dataclass(frozen=True)
class RealMesh:
    """The asset's own mesh at the instance's pose, drawn as the truth draws it (the costliest;
    :mod:`morphkit.plan.mixed`)."""

    name: ClassVar[str] = "mesh"
    cost: ClassVar[int] = 4


@dataclass(frozen=True)
class Culled:
    """Not drawn: the band's instances left out of the frame, their shadows still cast (the
    cheapest; :mod:`morphkit.plan.mixed`)."""

    name: ClassVar[str] = "cull"
    cost: ClassVar[int] = 0


#: The representations drawing billboards, cheapest first.
BILLBOARD_REPRESENTATIONS: tuple[BillboardRepresentation, ...] = (ClassicCard(), NearestView(), ViewMorph())
#: Every representation a plan chooses among, cheapest first.
REPRESENTATIONS: tuple[Representation, ...] = (Culled(), *BILLBOARD_REPRESENTATIONS, RealMesh())
#: The name of :class:`RealMesh`.
MESH = RealMesh.name
#: The name of :class:`Culled`.
CULL = Culled.name


def representation(name: str) -> Representation:
    """The representation called ``name``.

    Parameters
    ----------
    name : str
        One of :data:`REPRESENTATIONS`' names.

    Returns
    -------
    Representation

    Raises
    ------
    ValidationError
        Another name.
    """
    for r in REPRESENTATIONS:
        if r.name == name:
            return r
    raise ValidationError(
        expected_got("representation", f"one of {[r.name for r in REPRESENTATIONS]}", repr(name))
    )


def elevation_band(elevation_deg: float | np.ndarray) -> np.ndarray:
    """The elevation band of each elevation: ``0`` below the first edge, ... (:data:`ELEVATION_EDGES_DEG`).

    Parameters
    ----------
    elevation_deg : float or array
        Degrees.

    Returns
    -------
    int64 array
        Of the input's shape.

    Examples
    --------
    >>> from morphkit.plan.representations import elevation_band
    >>> elevation_band([0.0, 29.9, 30.0, 75.0]).tolist()
    [0, 0, 1, 2]
    """
    return np.searchsorted(
        np.asarray(ELEVATION_EDGES_DEG), np.asarray(elevation_deg, np.float64), side="right"
    ).astype(np.int64)


def band_label(band: Band, base_height: int) -> str:
    """A band in words: ``tree, 32-64 px, 30-60 deg``.

    Parameters
    ----------
    band : Band
        ``(asset, level, elevation band)``.
    base_height : int
        The asset's image height at level 0 (pixels).

    Returns
    -------
    str
    """
    name, level, e = band
    edges = (0.0, *ELEVATION_EDGES_DEG, 90.0)
    hi = base_height / 2.0**level
    size = f">= {hi / 2:g} px" if level == 0 else f"{hi / 2:g}-{hi:g} px"
    return f"{name}, {size}, {edges[e]:g}-{edges[e + 1]:g} deg"


@dataclass(frozen=True)
class BandChoice:
    """Which representation each band takes; bands not listed take ``default``.

    Parameters
    ----------
    choices : mapping of Band to str
        Representation names (:data:`REPRESENTATIONS`).
    default : str, optional
        The representation of every other band.

    Raises
    ------
    ValidationError
        An unknown representation name, a band that is not ``(str, int >= 0, int >= 0)``.
    """

    choices: Mapping[Band, str] = field(default_factory=dict)
    default: str = "morph"

    def __post_init__(self) -> None:
        representation(self.default)
        clean: dict[Band, str] = {}
        for band, name in self.choices.items():
            ok = (
                isinstance(band, tuple)
                and len(band) == 3
                and isinstance(band[0], str)
                and all(isinstance(v, (int, np.integer)) and v >= 0 for v in band[1:])
            )
            if not ok:
                raise ValidationError(
                    expected_got("band", "(asset name, level >= 0, elevation band >= 0)", repr(band))
                )
            representation(name)
            clean[(band[0], int(band[1]), int(band[2]))] = name
        object.__setattr__(self, "choices", clean)

    def of(self, asset: str, level: int, elevation_deg: float) -> str:
        """The representation of a billboard of ``asset`` drawn at ``level`` from ``elevation_deg``.

        Parameters
        ----------
        asset : str
            The asset's name.
        level : int
            Pyramid level.
        elevation_deg : float
            Viewing elevation, degrees.

        Returns
        -------
        str
        """
        return self.choices.get((asset, int(level), int(elevation_band(elevation_deg))), self.default)


def _not_billboard(rep: str, asset: str, level: int, elevation_deg: float) -> str:
    return expected_got(
        f"the band of {asset!r} at level {level}, {elevation_deg:.0f} deg",
        "a billboard representation (a band of the real mesh or culled is drawn by morphkit.plan.mixed)",
        rep,
    )


class BandedSurface:
    """A :class:`~morphkit.sunlit.litmodes.SurfaceChoice` taking each billboard's surface from its
    band's representation (relit dome assets).

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    name : str, optional
        The mode name it gives.
    """

    def __init__(self, choice: BandChoice, name: str = "plan") -> None:
        if not isinstance(choice, BandChoice):
            raise ValidationError(expected_got("choice", "a BandChoice", type(choice).__name__))
        self.choice = choice
        self.name = name
        self._surfaces = {r.name: r.surface() for r in BILLBOARD_REPRESENTATIONS}

    def surface(self, asset: object, azimuth_deg: float, elevation_deg: float, level: int) -> ViewSurface:
        """See :class:`~morphkit.sunlit.litmodes.SurfaceChoice`.

        Parameters
        ----------
        asset : SurfaceSource
            The asset.
        azimuth_deg, elevation_deg : float
            Direction, degrees.
        level : int
            Pyramid level.

        Returns
        -------
        ViewSurface
            Unshaded.
        """
        rep = self.choice.of(asset.name, level, elevation_deg)  # type: ignore[attr-defined]
        if rep not in self._surfaces:
            raise ValidationError(_not_billboard(rep, asset.name, level, elevation_deg))  # type: ignore[attr-defined]
        return self._surfaces[rep].surface(asset, azimuth_deg, elevation_deg, level)  # type: ignore[arg-type]


class BandedRing(BillboardMode):
    """A :class:`~morphkit.billboard.BillboardMode` drawing each ring billboard in its band's
    representation.

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    cache : MorphCache, optional
        The morphs' cache (default a new one).
    """

    name = "plan"

    def __init__(self, choice: BandChoice, cache: MorphCache | None = None) -> None:
        if not isinstance(choice, BandChoice):
            raise ValidationError(expected_got("choice", "a BandChoice", type(choice).__name__))
        self.choice = choice
        self._cache = MorphCache() if cache is None else cache
        self._modes = {r.name: r.ring_mode(self._cache) for r in BILLBOARD_REPRESENTATIONS}

    @property
    def cache(self) -> MorphCache:
        """The morphs' cache."""
        return self._cache

    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """The image of ``placement``'s band's representation.

        Parameters
        ----------
        asset : BillboardSource
            The instance's asset.
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA.
        outside_deg : float
            Degrees outside a partial ring's arc.
        """
        pl = placement
        rep = self.choice.of(pl.asset, pl.level, pl.elevation_deg)
        if rep not in self._modes:
            raise ValidationError(_not_billboard(rep, pl.asset, pl.level, pl.elevation_deg))
        return self._modes[rep].image(asset, placement)
