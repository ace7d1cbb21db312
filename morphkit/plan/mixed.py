"""Frames that draw some bands as the real meshes, leave some out and draw the others as billboards.

A plan may choose :class:`~morphkit.plan.representations.RealMesh` for a band: its instances are
drawn as their meshes, every other billboard in its band's billboard representation; or
:class:`~morphkit.plan.representations.Culled`: its instances are not drawn (the frame still lists
their placements, so the frame's figures count their boxes, and they still cast the frame's
shadow). One frame holds all of them:

1. the frame is planned once (:meth:`~morphkit.billboard.BillboardScene.plan`), and its placements
   split by their band's representation, the culled ones dropped;
2. the meshes of the real-mesh placements are drawn in one render, as the truth draws them
   (:meth:`~morphkit.sunlit.litmesh.LitMeshMode.shaded_layer` for relit assets, the sun's visibility
   from the frame's shadow; :meth:`~morphkit.billboard.MeshMode.depth_layer` for ring assets): a
   layer and its depth buffer;
3. the billboards are composited over that layer back to front, each one that meets a mesh pixel
   depth-tested against the meshes' depth (:meth:`~morphkit.sunlit.LitMode.draw_placements`: the
   surface's own depth; :meth:`~morphkit.billboard.BillboardMode.draw_placements`: a ring image at its
   pivot's depth), so a billboard behind a mesh is hidden by it and one in front covers it;
4. the layer goes over the backdrop (the ground shadowed by every drawn instance, for relit assets).

:class:`LitMeshBands` draws relit dome assets, :class:`RingMeshBands` ring assets. With no band of
the real mesh either draws what its billboard mode draws alone; with every band the real mesh, what
the truth draws (the ground's shadows aside: the frame's own, not the truth's ray cast).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..billboard import BillboardMode, BillboardScene, MeshMode
from ..billboard.frames.cache import CacheCounts, MorphCache
from ..billboard.frames.compositor import finish, new_depth, new_layer
from ..billboard.frames.facing import ViewpointFacing
from ..billboard.frames.frametypes import Frame, Placement
from ..billboard.modes import frame_stats
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..imaging.shading import Lighting
from ..sunlit import LitMode
from ..sunlit.litmesh import LitMeshMode
from ..sunlit.receivers import SceneShadow
from ..sunlit.shadowing import frame_shadow, shadowed_backdrop
from .representations import (
    CULL,
    MESH,
    BandChoice,
    BandedRing,
    BandedSurface,
    BillboardRepresentation,
    Representation,
)

__all__ = ["LitMeshBands", "RingMeshBands", "split_placements", "banded_mode", "uniform_mode"]


def split_placements(
    choice: BandChoice,
    placements: Sequence[Placement],
    elevation: Callable[[Placement], float] | None = None,
) -> tuple[list[Placement], list[Placement]]:
    """``placements`` split by their band's representation: the real mesh's, and the billboards'
    (each list in the plan's back-to-front order); the culled bands' in neither.

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    placements : sequence of Placement
        A frame plan's placements.
    elevation : callable, optional
        The elevation a placement's band is decided at, as the billboard mode decides it (relit:
        :meth:`LitMode.direction <morphkit.sunlit.LitMode.direction>`'s, rounded for its cache);
        default the placement's own.

    Returns
    -------
    meshes, billboards : list of Placement
    """
    meshes: list[Placement] = []
    billboards: list[Placement] = []
    for pl in placements:
        e = pl.elevation_deg if elevation is None else elevation(pl)
        rep = choice.of(pl.asset, pl.level, e)
        if rep != CULL:
            (meshes if rep == MESH else billboards).append(pl)
    return meshes, billboards


def _indices(placements: Sequence[Placement]) -> np.ndarray:
    return np.array([pl.index for pl in placements], np.int64)


def _check(choice: Any, billboards: Any, billboard_type: type, meshes: Any, mesh_type: type) -> None:
    """A mixed mode's parts checked: the meshes may be None only when no band is the real mesh."""
    for what, v, cls in (("choice", choice, BandChoice), ("billboards", billboards, billboard_type)):
        if not isinstance(v, cls):
            raise ValidationError(expected_got(what, f"a {cls.__name__}", type(v).__name__))
    if meshes is None and MESH in (choice.default, *choice.choices.values()):
        raise ValidationError(
            expected_got("meshes", "the scene's real meshes (some bands are drawn as the real mesh)", "none")
        )
    if meshes is not None and not isinstance(meshes, mesh_type):
        raise ValidationError(expected_got("meshes", f"a {mesh_type.__name__}", type(meshes).__name__))


class LitMeshBands:
    """Relit dome assets: the real-mesh bands drawn as meshes, the others as relit billboards
    (module docstring).

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    billboards : LitMode
        Draws the billboards (its choice a :class:`~morphkit.plan.representations.BandedSurface` of
        ``choice``) with the frame's shadow (its ``shadow``).
    meshes : LitMeshMode or None
        Draws the meshes (supersample 1: coverage and depth of one sample); its own shadow is not
        used (the frame's is). None: no band is the real mesh.
    name : str, optional
        The mode's name.
    """

    def __init__(
        self, choice: BandChoice, billboards: LitMode, meshes: LitMeshMode | None, name: str = "plan"
    ) -> None:
        _check(choice, billboards, LitMode, meshes, LitMeshMode)
        self.choice, self.billboards, self.meshes, self.name = choice, billboards, meshes, str(name)
        if self.meshes is not None:
            self.meshes.lighting = self.billboards.lighting

    @property
    def lighting(self) -> Lighting:
        """The frame's lights (both the billboards' and the meshes'; replace between frames)."""
        return self.billboards.lighting

    @lighting.setter
    def lighting(self, value: Lighting) -> None:
        if not isinstance(value, Lighting):
            raise ValidationError(
                expected_got("lighting", "a morphkit.imaging.shading.Lighting", type(value).__name__)
            )
        self.billboards.lighting = value
        if self.meshes is not None:
            self.meshes.lighting = value

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """One frame (module docstring).

        Parameters
        ----------
        scene : BillboardScene
            A scene of relightable assets with :class:`~morphkit.billboard.frames.facing.ViewpointFacing`.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame

        Raises
        ------
        ValidationError
            A scene whose facing is not :class:`ViewpointFacing`.
        """
        t0 = time.perf_counter()
        if not isinstance(scene.facing, ViewpointFacing):
            raise ValidationError(
                expected_got(
                    "scene facing for relit billboards",
                    "ViewpointFacing (quads facing the eye in elevation too)",
                    type(scene.facing).__name__,
                )
            )
        cache = self.billboards.cache
        before = cache.counts
        plan = scene.plan(camera)
        meshes, billboards = split_placements(
            self.choice, plan.placements, lambda pl: self.billboards.direction(pl)[1]
        )
        lit = self.lighting.above_horizon()
        shadow = self.billboards.shadow
        ground = (
            None if shadow is None else frame_shadow(shadow, scene, camera, lit, _indices(plan.placements))
        )
        fs = None if ground is None else ground.shadow
        if meshes and self.meshes is not None:
            layer, depth = self.meshes.shaded_layer(scene, camera, _indices(meshes), fs)
            zbuf = np.array(depth, np.float32)
        else:
            layer, zbuf = new_layer(camera.shape), new_depth(camera.shape)
        self.billboards.draw_placements(scene, camera, billboards, layer, zbuf, fs)
        back = (
            scene.backdrop.draw(camera)
            if ground is None
            else shadowed_backdrop(scene, camera, lit, ground, layer[:, :, 3])
        )
        rgb = finish(layer, back)
        return Frame(
            rgb, layer, plan.placements, frame_stats(self.name, plan, cache.counts - before, cache, 0.0, t0)
        )


class RingMeshBands:
    """Ring assets: the real-mesh bands drawn as meshes, the others as ring billboards (module
    docstring).

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    billboards : BillboardMode
        Draws the billboards (a :class:`~morphkit.plan.representations.BandedRing` of ``choice``).
    meshes : MeshMode or None
        Draws the meshes (one render of colour and depth). None: no band is the real mesh.
    name : str, optional
        The mode's name.
    """

    def __init__(
        self, choice: BandChoice, billboards: BillboardMode, meshes: MeshMode | None, name: str = "plan"
    ) -> None:
        _check(choice, billboards, BillboardMode, meshes, MeshMode)
        self.choice, self.billboards, self.meshes, self.name = choice, billboards, meshes, str(name)

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """One frame (module docstring).

        Parameters
        ----------
        scene : BillboardScene
            A scene of ring assets.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
        """
        t0 = time.perf_counter()
        cache = self.billboards.cache
        before = cache.counts if cache is not None else CacheCounts()
        plan = scene.plan(camera)
        meshes, billboards = split_placements(self.choice, plan.placements)
        if meshes and self.meshes is not None:
            layer, depth = self.meshes.depth_layer(scene, camera, _indices(meshes))
            zbuf: np.ndarray | None = np.array(depth, np.float32)
        else:
            layer, zbuf = new_layer(camera.shape), None
        outside = self.billboards.draw_placements(scene, billboards, layer, zbuf)
        rgb = finish(layer, scene.backdrop.draw(camera))
        counts = (cache.counts - before) if cache is not None else CacheCounts()
        return Frame(rgb, layer, plan.placements, frame_stats(self.name, plan, counts, cache, outside, t0))


def banded_mode(
    choice: BandChoice,
    relit: bool,
    base: Lighting,
    shadow: SceneShadow | None = None,
    meshes: LitMeshMode | MeshMode | None = None,
) -> LitMode | BillboardMode | LitMeshBands | RingMeshBands:
    """The mode drawing each billboard in its band's representation: relit billboards
    (:class:`~morphkit.plan.representations.BandedSurface`) or ring ones
    (:class:`~morphkit.plan.representations.BandedRing`), inside a :class:`LitMeshBands` or
    :class:`RingMeshBands` when a band is the real mesh or culled.

    Parameters
    ----------
    choice : BandChoice
        The bands' representations.
    relit : bool
        Relit dome assets (else ring assets).
    base : Lighting
        The relit mode's lighting until a frame sets its sun.
    shadow : SceneShadow, optional
        The frames' shadow (relit).
    meshes : LitMeshMode or MeshMode, optional
        Draws the real meshes (needed when a band is the real mesh).

    Returns
    -------
    FrameMode

    Raises
    ------
    ValidationError
        A band of the real mesh and no ``meshes`` (or meshes of the other kind).
    """
    billboards: LitMode | BillboardMode = (
        LitMode(BandedSurface(choice), base, shadow=shadow) if relit else BandedRing(choice, MorphCache())
    )
    reps = (choice.default, *choice.choices.values())
    if MESH not in reps and CULL not in reps:
        return billboards
    if MESH not in reps:
        meshes = None  # only culled bands: no mesh drawn
    if relit:
        return LitMeshBands(choice, billboards, meshes)  # type: ignore[arg-type]
    return RingMeshBands(choice, billboards, meshes)  # type: ignore[arg-type]


def uniform_mode(
    rep: Representation,
    relit: bool,
    base: Lighting | None,
    shadow: SceneShadow | None = None,
    meshes: LitMeshMode | MeshMode | None = None,
) -> LitMode | BillboardMode | LitMeshBands | RingMeshBands:
    """The mode drawing every billboard as ``rep``: a billboard representation's own surface or ring
    mode (no band looked up), else :func:`banded_mode` with every band ``rep``.

    Parameters
    ----------
    rep : Representation
        One of :data:`~morphkit.plan.representations.REPRESENTATIONS`.
    relit : bool
        Relit dome assets (else ring assets).
    base : Lighting or None
        The relit mode's lighting until a frame sets its sun.
    shadow : SceneShadow, optional
        The frames' shadow (relit).
    meshes : LitMeshMode or MeshMode, optional
        Draws the real meshes (needed where ``rep`` is the real mesh).

    Returns
    -------
    FrameMode
    """
    if isinstance(rep, BillboardRepresentation):
        return LitMode(rep.surface(), base, shadow=shadow) if relit else rep.ring_mode(MorphCache())
    return banded_mode(BandChoice(default=rep.name), relit, base, shadow, meshes)  # type: ignore[arg-type]
