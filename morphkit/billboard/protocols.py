"""Interfaces of the billboard wing, declared once (``typing.Protocol``).

:class:`ViewPairing` and :class:`BillboardSource` are what the billboard scene
(:mod:`morphkit.billboard`) asks of an asset: a ring of reference views and the
images of any viewing azimuth between two of them.
:class:`morphkit.billboard.asset.BillboardAsset` implements them; tests use small
doubles that draw their images without GL. (The renderer interface shared with
the rest of morphkit is :class:`morphkit.protocols.SceneRenderer`.)
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from ..camera import CameraModel
from ..views.gbuffer import ViewSurface

__all__ = ["ViewPairing", "Placeable", "BillboardSource", "SurfaceSource"]


@runtime_checkable
class ViewPairing(Protocol):
    """Where an asset's reference views are, about the object's up axis (``+z``).

    Azimuths are in degrees in the object frame: ``0`` looks at the object from
    its ``+x`` side (its front), counter-clockwise about ``+z``.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    @property
    def views(self) -> int:
        """``K >= 2``, the number of reference views."""
        ...

    def azimuths_deg(self) -> np.ndarray:
        """``(K,)`` float azimuths of the reference views, degrees."""
        ...

    def pair(self, azimuth_deg: float) -> tuple[int, int, float, float]:
        """``(i, j, s, outside_deg)``: the references bracketing ``azimuth_deg`` and the
        fraction ``s`` in ``[0, 1]`` from view ``i`` (``s = 0``) to view ``j`` (``s = 1``);
        ``outside_deg > 0`` where the azimuth lies outside a partial ring's arc by that
        much (``s`` is then clamped to the nearer view).

        Parameters
        ----------
        azimuth_deg : float
            Viewing azimuth, degrees, object frame.

        Returns
        -------
        i, j : int
            Indices of the bracketing reference views.
        s : float
            Fraction in ``[0, 1]`` from ``i`` to ``j``.
        outside_deg : float
            Degrees outside a partial ring's arc, ``0`` inside.
        """
        ...


@runtime_checkable
class Placeable(Protocol):
    """What a billboard scene needs of any asset to place its quads: a name, the level-0
    image size and pyramid levels (level of detail), the quad's half size and pivot
    (object frame) and its bytes. :class:`BillboardSource` (ring assets) and
    :class:`SurfaceSource` (relightable assets) both are; the modes ask for the one they draw.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str
    size: tuple[int, int]
    half_extent: tuple[float, float]
    pivot: np.ndarray
    levels: int
    memory_bytes: int


@runtime_checkable
class BillboardSource(Protocol):
    """A billboard asset: premultiplied RGBA images of an object for any viewing azimuth.

    Every image of level ``l`` has shape ``(h, w, 4)`` = ``size`` halved ``l`` times,
    float32 premultiplied RGBA in ``[0, 1]``, all in the same image frame: the image's
    outer edges (``[-0.5, w - 0.5] x [-0.5, h - 0.5]``) map to the billboard quad, a
    rectangle of half size ``half_extent`` (scene units, width then height) centred on
    ``pivot`` (``(3,)``, object frame), facing the viewer, its top edge up.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str
    ring: ViewPairing
    size: tuple[int, int]
    half_extent: tuple[float, float]
    pivot: np.ndarray
    levels: int
    memory_bytes: int

    def reference(self, k: int, level: int = 0) -> np.ndarray:
        """Reference view ``k``, ``(h, w, 4)`` float32 premultiplied.

        Parameters
        ----------
        k : int
            Reference view index.
        level : int, optional
            Mip level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA.
        """
        ...

    def classic(self, level: int = 0) -> np.ndarray:
        """The classic billboard's one image (the front view, azimuth 0), ``(h, w, 4)``.

        Parameters
        ----------
        level : int, optional
            Mip level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA.
        """
        ...

    def morph(self, i: int, j: int, s: float, level: int = 0, *, coverage: bool = True) -> np.ndarray:
        """The view at fraction ``s`` from reference ``i`` to ``j`` (view-morphed), ``(h, w, 4)``.

        Parameters
        ----------
        i, j : int
            Reference view indices.
        s : float
            Fraction in ``[0, 1]`` from ``i`` to ``j``.
        level : int, optional
            Mip level, ``0`` full size.
        coverage : bool
            Where the source knows its object's shape (depth), take the alpha from it
            and the colour from the morph; False: the view morph's own alpha.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA.
        """
        ...

    def crossfade(self, i: int, j: int, s: float, level: int = 0) -> np.ndarray:
        """The premultiplied blend ``(1 - s) ref_i + s ref_j`` (a baseline), ``(h, w, 4)``.

        Parameters
        ----------
        i, j : int
            Reference view indices.
        s : float
            Blend weight of ``j``, in ``[0, 1]``.
        level : int, optional
            Mip level, ``0`` full size.

        Returns
        -------
        (h, w, 4) float32
            Premultiplied RGBA.
        """
        ...


@runtime_checkable
class SurfaceSource(Protocol):
    """A relightable billboard asset: the unshaded surface of its object from any direction.

    Every surface of level ``l`` is a :class:`~morphkit.views.gbuffer.ViewSurface` of
    shape ``level_shape(l)`` (square), in the image frame of the quad of direction
    ``(azimuth_deg, elevation_deg)`` of :mod:`morphkit.views.domecameras`: the image's
    outer edges map to the square of half size ``half_extent`` about ``pivot``,
    perpendicular to the direction, with the rule's ``up``. Implemented by
    :class:`~morphkit.billboard.domeasset.DomeAsset` (views morphed) and
    :class:`~morphkit.billboard.impostor.OctahedralImpostor` (the engines' impostor).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str
    size: tuple[int, int]
    half_extent: tuple[float, float]
    pivot: np.ndarray
    levels: int
    memory_bytes: int

    def surface(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> ViewSurface:
        """The surface seen from direction ``(azimuth_deg, elevation_deg)`` at ``level``.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame (elevation clamped by the asset).
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        ViewSurface
            Unshaded albedo, normals (object frame) and depth.
        """
        ...

    def camera(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> CameraModel:
        """The camera of the surface of a direction (its depth is along this camera's axis).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame.
        level : int, optional
            Pyramid level.

        Returns
        -------
        CameraModel
            Object frame.
        """
        ...

    def level_shape(self, level: int) -> tuple[int, int]:
        """Image shape of pyramid level ``level``.

        Parameters
        ----------
        level : int
            Pyramid level.

        Returns
        -------
        (h, w) tuple of int
            Image shape.
        """
        ...
