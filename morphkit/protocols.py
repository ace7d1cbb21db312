"""Interfaces shared across morphkit, declared once (``typing.Protocol``).

:class:`SceneRenderer` is what every module that needs pictures of meshes asks
for: :class:`morphkit.render.Renderer` (pyrender, OSMesa) implements it, and a
test or a user can pass any other object with the same methods. Only
:mod:`morphkit.render` imports pyrender; code typed against this protocol runs
and type-checks without a GL context.

:class:`ViewPairing` and :class:`BillboardSource` are what the billboard scene
(:mod:`morphkit.billboard`) asks of an asset: a ring of reference views and the
images of any viewing azimuth between two of them.
:class:`morphkit.billboard.asset.BillboardAsset` implements them; tests use small
doubles that draw their images without GL.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Protocol, runtime_checkable

import numpy as np

from .camera import CameraModel
from .scene import Item, Light

__all__ = ["SceneRenderer", "ViewPairing", "BillboardSource"]


@runtime_checkable
class SceneRenderer(Protocol):
    """Renders :class:`~morphkit.scene.Item` lists through a :class:`~morphkit.camera.CameraModel`.

    Frames and units follow :mod:`morphkit.conventions`: images ``(H, W[, C])``
    of ``camera.shape``, linear depth ``Z`` in scene units, background ``+inf``.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def depth(self, camera: CameraModel, items: Sequence[Item]) -> np.ndarray:
        """Linear depth, float32 ``(H, W)``; ``+inf`` where nothing was hit.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        (H, W) float32
            Linear depth, ``+inf`` background.
        """
        ...

    def color_depth(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                    ambient: float = 0.35,
                    background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Shaded colour, uint8 ``(H, W, 3)`` RGB, and linear depth, float32 ``(H, W)``.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        background : tuple of 3 float, optional
            RGB in ``[0, 1]`` where nothing is drawn.

        Returns
        -------
        color : (H, W, 3) uint8
            Shaded RGB.
        depth : (H, W) float32
            Linear depth, ``+inf`` background.
        """
        ...

    def source_view(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                    ambient: float = 0.35, supersample: int = 3) -> np.ndarray:
        """Straight-alpha RGBA, uint8 ``(H, W, 4)``, of ``items`` on a transparent background.

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame.
        ambient : float, optional
            Ambient light level.
        supersample : int, optional
            Supersampling factor per axis for the coverage alpha.

        Returns
        -------
        (H, W, 4) uint8
            Straight-alpha RGBA.
        """
        ...


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
