"""Interfaces shared across morphkit, declared once (``typing.Protocol``).

:class:`SceneRenderer` is what every module that needs pictures of meshes asks
for (:class:`PassRenderer`, :class:`GBufferRenderer` and :class:`FrameRenderer` add draws some
modules use when a renderer has them): :class:`morphkit.render.Renderer` (pyrender, OSMesa)
implements it, and a test or a user can pass any other object with the same methods. Only
:mod:`morphkit.render` imports pyrender; code typed against this protocol runs
and type-checks without a GL context.

The billboard wing's own interfaces (what a billboard scene asks of an asset)
live in :mod:`morphkit.billboard.protocols`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from .camera import CameraModel
from .passes import FramePass, RenderPasses
from .scene import Item, Light

__all__ = ["SceneRenderer", "PassRenderer", "GBufferRenderer", "FrameRenderer", "InputRecords"]


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
class PassRenderer(SceneRenderer, Protocol):
    """A :class:`~morphkit.protocols.SceneRenderer` that also draws deferred passes
    (:class:`morphkit.render.Renderer` does).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def passes(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
               ambient: float = 0.35, background: tuple[float, float, float] = (0.0, 0.0, 0.0),
               ) -> RenderPasses:
        """Colour, albedo, normals, depth and coverage of one view (:meth:`Renderer.passes
        <morphkit.render.Renderer.passes>`).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights of the colour pass (not used here).
        ambient : float, optional
            Ambient level of the colour pass.
        background : tuple of 3 float, optional
            Colour pass background.

        Returns
        -------
        RenderPasses
            The passes.
        """
        ...

    def source_passes(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                      ambient: float = 0.35, supersample: int = 3) -> RenderPasses:
        """:meth:`passes` supersampled and area-averaged (:meth:`Renderer.source_passes
        <morphkit.render.Renderer.source_passes>`).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights of the colour pass (not used here).
        ambient : float, optional
            Ambient level of the colour pass.
        supersample : int, optional
            Supersampling factor per axis.

        Returns
        -------
        RenderPasses
            The passes at ``camera.shape``.
        """
        ...


@runtime_checkable
class GBufferRenderer(PassRenderer, Protocol):
    """A :class:`~morphkit.protocols.PassRenderer` that draws the deferred passes a shader needs in
    one draw (:class:`morphkit.render.Renderer` does; :class:`morphkit.sunlit.litmesh.LitMeshMode`
    uses it).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def gbuffer_pass(self, camera: CameraModel, items: Sequence[Item]) -> RenderPasses:
        """:meth:`passes` without the lit colour, from one draw (:meth:`Renderer.gbuffer_pass
        <morphkit.render.Renderer.gbuffer_pass>`).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.

        Returns
        -------
        RenderPasses
            Albedo, normals, depth and coverage (0 or 1) as :meth:`passes`'; ``color`` is the albedo.
        """
        ...


@runtime_checkable
class FrameRenderer(SceneRenderer, Protocol):
    """A :class:`~morphkit.protocols.SceneRenderer` that draws a view lit and unlit in one pass
    (:class:`morphkit.render.Renderer` does; :func:`morphkit.shadow.frame.render_frame` uses it).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def frame_pass(self, camera: CameraModel, items: Sequence[Item], lights: Iterable[Light], *,
                   ambient: float = 0.35, background: tuple[float, float, float] = (0.0, 0.0, 0.0),
                   marked: Sequence[int] = ()) -> FramePass:
        """:meth:`color_depth` with ``lights`` on and off from one draw, and the pixels of the items
        ``marked`` (:meth:`Renderer.frame_pass <morphkit.render.Renderer.frame_pass>`).

        Parameters
        ----------
        camera : CameraModel
            The view.
        items : sequence of Item
            Items to draw, world poses.
        lights : iterable of Light
            Lights, world frame (on in ``lit``, off in ``unlit``).
        ambient : float, optional
            Ambient light level.
        background : tuple of 3 float, optional
            RGB in ``[0, 1]`` where nothing is drawn.
        marked : sequence of int, optional
            Indices into ``items`` of the items whose visible pixels ``marked`` shows.

        Returns
        -------
        FramePass
            ``lit``, ``unlit``, ``depth`` and ``marked``.
        """
        ...


@runtime_checkable
class InputRecords(Protocol):
    """Where the input a file was baked from is recorded (a bake library's manifests:
    :class:`morphkit.bake.manifest.ManifestRecords`), for a reader that needs the mesh back.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def find(self, output: Path) -> tuple[Path, str] | str | None:
        """The recorded input of ``output``.

        Parameters
        ----------
        output : pathlib.Path
            A baked file.

        Returns
        -------
        (pathlib.Path, str) or str or None
            The input mesh file and the up axis it was loaded with, when a record lists
            ``output`` and the input is unchanged since; a sentence saying why not when a
            record lists it but the input is missing or changed; None when no record lists it.
        """
        ...

