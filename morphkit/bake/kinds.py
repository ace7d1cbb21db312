"""Kinds of baked asset: what ``morphkit bake`` makes of one mesh.

A kind is an object implementing :class:`AssetKind`: a ``name`` (the key in
the manifest), a file ``suffix`` (outputs are ``<out>/<asset><suffix>``), the
``version`` of the file format it writes, its ``options()`` (JSON: an asset
is re-baked when they change) and ``bake(mesh, renderer, source_up)``, which returns
something that saves itself to one file atomically (:class:`SavableAsset`:
:meth:`ShadowAtlas.save <morphkit.shadow.atlas.ShadowAtlas.save>`, a
billboard asset's ``save``). Kinds are pickled to the worker processes, so a
kind is plain data (a frozen dataclass) plus those methods.

Up axis. The worker loads each mesh once, turned ``+z`` up from the file's up
axis (:func:`morphkit.meshes.load_mesh`; the run's ``BakeOptions.up``, resolved
per file by :func:`morphkit.meshes.resolve_up`), and passes every kind the same
mesh and that resolved axis as ``source_up`` (``"z"`` or ``"y"``), for a kind
whose file records it. The manifest records it per asset either way.

Implemented here: :class:`ShadowAtlasKind` (Kang & Ihm's k x k shadow atlas,
:func:`morphkit.shadow.bake_atlas`) and :class:`BillboardKind` (the view-morphing
billboard asset, :func:`morphkit.billboard.bake_asset`, suffix ``.billboard.npz``) and
:class:`DomeKind` (the relightable billboard seen from any height,
:func:`morphkit.billboard.domeasset.bake_dome`, suffix ``.dome.npz``) and :class:`SunAtlasKind` (the
asset's light views over the sun's direction, :func:`morphkit.sunlit.sunatlas.bake_sun_atlas`, suffix
``.sunatlas.npz``: what ``billboards --shadows`` draws the asset's shadows with, read from the bake
instead of baked at the start of the run).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
import trimesh

from .. import tol
from ..billboard import bake_asset
from ..billboard.cameras import DISTANCE_FACTOR, check_distance_factor
from ..billboard.domeasset import bake_dome
from ..billboard.formats.assetfile import VERSION as BILLBOARD_VERSION
from ..billboard.formats.domefile import DOME_VERSION
from ..errors import ValidationError, expected_got
from ..protocols import SceneRenderer
from ..scene import DirectionalLight, PointLight
from ..shadow import ATLAS_VERSION, MotionRange, bake_atlas
from ..sunlit.receivers import SCENE_ATLAS_DOME, SCENE_ATLAS_SIZE
from ..sunlit.sunatlas import bake_sun_atlas
from ..sunlit.sunatlasfile import SUN_ATLAS_VERSION, SavableSunAtlas
from ..validate import as_finite_array, as_int
from ..views.dome import DEFAULT_RINGS

__all__ = ["SavableAsset", "AssetKind", "ShadowAtlasKind", "BillboardKind", "DomeKind", "SunAtlasKind",
           "output_name",
           "WARP_LIGHT", "WARP_RANGE"]

#: The default range of motion of a shadow atlas (:class:`ShadowAtlasKind`; the
#: warped-shadow demo's): the object moves over this range under this point light.
WARP_RANGE = ((-0.6, -0.6), (0.6, 0.6))
#: The default point light position of a shadow atlas (world frame; the warped-shadow demo's).
WARP_LIGHT = (0.25, -0.2, 2.4)


@runtime_checkable
class SavableAsset(Protocol):
    """A baked asset that writes itself to one file, atomically (through :mod:`morphkit.files.fileio`).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def save(self, path: str | Path) -> Path:
        """Write the asset to ``path`` (its folder exists); return ``path``.

        Parameters
        ----------
        path : str or pathlib.Path
            The output file; its folder exists. Written atomically.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        ...


@runtime_checkable
class AssetKind(Protocol):
    """One kind of baked asset (see the module docstring).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    #: Key of this kind in the manifest, e.g. ``"shadow-atlas"``.
    name: str
    #: Output file suffix, e.g. ``".atlas.npz"``.
    suffix: str
    #: Version of the file format written (recorded in the manifest; a change re-bakes).
    version: int

    def options(self) -> dict[str, Any]:
        """The options that determine the output, as plain JSON values.

        Returns
        -------
        dict of str to JSON value
            Recorded in the manifest; a change re-bakes the asset.
        """
        ...

    def bake(self, mesh: trimesh.Trimesh, renderer: SceneRenderer, source_up: str) -> SavableAsset:
        """Bake one normalised mesh (:func:`morphkit.meshes.load_mesh`) with ``renderer``.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The normalised mesh, object frame (already turned ``+z`` up).
        renderer : SceneRenderer
            The renderer of this worker thread (``morphkit.bake.worker.worker_renderer``).
        source_up : {"z", "y"}
            The up axis the mesh file was loaded with (:func:`morphkit.meshes.resolve_up`), for a kind
            whose file records it.

        Returns
        -------
        SavableAsset
            The baked asset, saved by the caller to ``<out>/<asset><suffix>``.
        """
        ...


@dataclass(frozen=True)
class ShadowAtlasKind:
    """The k x k warped-shadow atlas of an object moving over a range (:func:`~morphkit.shadow.bake_atlas`).

    Parameters
    ----------
    atlas_size : int
        Side of each square light-view depth map, in pixels (8..8192).
    grid : int
        Maps per axis, ``k >= 2`` (3: Kang & Ihm's 3 x 3).
    range : (x0, y0, x1, y1)
        The object's translations on the ground, world units (:class:`~morphkit.shadow.MotionRange`).
    light : (x, y, z), optional
        Point light position, above the ground (``z > 0``); with ``directional`` the direction
        the light travels, down (``z < 0``): a light that cannot reach the ground is refused.
        Default :data:`WARP_LIGHT`, or with ``directional`` its direction to the origin
        (``-WARP_LIGHT``).
    directional : bool
        A :class:`~morphkit.scene.DirectionalLight` instead of a point light.
    """

    atlas_size: int = 512
    grid: int = 3
    range: tuple[float, float, float, float] = (*WARP_RANGE[0], *WARP_RANGE[1])
    light: tuple[float, float, float] | None = None
    directional: bool = False

    name: ClassVar[str] = "shadow-atlas"
    suffix: ClassVar[str] = ".atlas.npz"
    version: ClassVar[int] = ATLAS_VERSION

    def __post_init__(self) -> None:
        size = as_int(self.atlas_size, "atlas size", lo=8, hi=8192)
        grid = as_int(self.grid, "grid", lo=2, hi=64)
        rng = as_finite_array(self.range, "range (x0, y0, x1, y1)", shape=(4,))
        given = self.light if self.light is not None else (
            tuple(-v for v in WARP_LIGHT) if self.directional else WARP_LIGHT)
        light = as_finite_array(given, "light", shape=(3,))
        object.__setattr__(self, "atlas_size", size)
        object.__setattr__(self, "grid", grid)
        object.__setattr__(self, "range", tuple(float(v) for v in rng))
        object.__setattr__(self, "light", tuple(float(v) for v in light))
        object.__setattr__(self, "directional", bool(self.directional))
        self.motion()  # validates the range
        self.scene_light()  # and the light
        # a light that cannot reach the ground (z = 0, morphkit.conventions) casts no shadow on it
        if self.directional and light[2] >= 0.0:
            raise ValidationError(expected_got("light with directional", "a direction travelling down "
                                               "(z < 0) to reach the ground",
                                               f"{self.light} (z >= 0: away from it)"))
        if not self.directional and light[2] <= 0.0:
            raise ValidationError(expected_got("light", "a point light above the ground (z > 0)",
                                               f"{self.light} (at or under the ground)"))

    def motion(self) -> MotionRange:
        """The object's range of motion.

        Returns
        -------
        MotionRange
            ``lo = (x0, y0)``, ``hi = (x1, y1)`` of ``range``, world frame.
        """
        x0, y0, x1, y1 = self.range
        return MotionRange(np.array([x0, y0]), np.array([x1, y1]))

    def scene_light(self) -> DirectionalLight | PointLight:
        """The light the atlas is baked for.

        Returns
        -------
        DirectionalLight or PointLight
            A directional light travelling along ``light`` when ``directional``, else a point
            light at ``light``, world frame.
        """
        v = np.array(self.light)
        return DirectionalLight(v) if self.directional else PointLight(v)

    def options(self) -> dict[str, Any]:
        """The options that decide the output (recorded in the manifest; a change re-bakes).

        Returns
        -------
        dict
            ``atlas_size``, ``grid``, ``range``, ``light``, ``directional`` as JSON values.
        """
        return {"atlas_size": self.atlas_size, "grid": self.grid, "range": list(self.range),
                "light": list(self.light), "directional": self.directional}

    def bake(self, mesh: trimesh.Trimesh, renderer: SceneRenderer, source_up: str = "z") -> SavableAsset:
        """The shadow atlas of ``mesh`` (:func:`~morphkit.shadow.bake_atlas`) with these options.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The normalised mesh, object frame, ``+z`` up (posed with the identity at the range's
            positions).
        renderer : SceneRenderer
            Renders the light-view depth maps.
        source_up : {"z", "y"}, optional
            The up axis the file was loaded with; not stored in the atlas file (the bake manifest
            records it per asset).

        Returns
        -------
        ShadowAtlas
            The ``grid x grid`` atlas of ``atlas_size x atlas_size`` maps.
        """
        return bake_atlas(mesh, np.eye(4), self.motion(), self.scene_light(),
                          (self.atlas_size, self.atlas_size), renderer=renderer, grid=self.grid,
                          progress=False)


@dataclass(frozen=True)
class BillboardKind:
    """The view-morphing billboard asset of a mesh (:func:`~morphkit.billboard.bake_asset`).

    Parameters
    ----------
    views : int
        Reference views on the ring: 2 is the paper's left/right pair, more a full ring.
    size : int
        Side of the square level-0 reference views, in pixels (16..2048).
    distance_factor : float
        Reference cameras' distance in bounding radii
        (:data:`~morphkit.views.framing.DISTANCE_FACTOR`; in its range).
    """

    views: int = 2
    size: int = 256
    distance_factor: float = DISTANCE_FACTOR

    name: ClassVar[str] = "billboard"
    suffix: ClassVar[str] = ".billboard.npz"
    version: ClassVar[int] = BILLBOARD_VERSION

    def __post_init__(self) -> None:
        object.__setattr__(self, "views", as_int(self.views, "billboard views", lo=2, hi=64))
        object.__setattr__(self, "size", as_int(self.size, "billboard size", lo=16, hi=2048))
        object.__setattr__(self, "distance_factor",
                           check_distance_factor(self.distance_factor, "billboard distance_factor"))

    def options(self) -> dict[str, Any]:
        """The options that decide the output (recorded in the manifest; a change re-bakes).

        Returns
        -------
        dict
            ``views``, ``size`` and ``distance_factor`` as JSON values (an asset baked with
            another distance, e.g. before the default changed, is re-baked).
        """
        return {"views": self.views, "size": self.size, "distance_factor": float(self.distance_factor)}

    def bake(self, mesh: trimesh.Trimesh, renderer: SceneRenderer, source_up: str = "z") -> SavableAsset:
        """The billboard asset of ``mesh`` (reference views and every pair's morph prepared).

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The normalised mesh, object frame, ``+z`` up.
        renderer : SceneRenderer
            Renders the reference views.
        source_up : {"z", "y"}, optional
            The up axis the file was loaded with (recorded in the bake manifest; see the note in the
            body on the asset file).

        Returns
        -------
        SavableAsset
            The billboard asset (:func:`~morphkit.billboard.bake_asset`), ``views`` reference views of
            ``size x size`` pixels.
        """
        # the resolved up axis is kept in the asset file too (and in the manifest)
        return bake_asset(mesh, renderer, views=self.views, size=self.size,
                          distance_factor=self.distance_factor, source_up=source_up)


@dataclass(frozen=True)
class DomeKind:
    """The relightable billboard asset of a mesh seen from any height
    (:func:`~morphkit.billboard.domeasset.bake_dome`: a :class:`~morphkit.views.dome.ViewDome`
    of albedo, normals and depth).

    Parameters
    ----------
    size : int
        Side of the square level-0 views, in pixels (16..2048).
    distance_factor : float
        Cameras' distance in bounding radii (:data:`~morphkit.views.framing.DISTANCE_FACTOR`).
    """

    size: int = 128
    distance_factor: float = DISTANCE_FACTOR

    name: ClassVar[str] = "dome"
    suffix: ClassVar[str] = ".dome.npz"
    version: ClassVar[int] = DOME_VERSION

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", as_int(self.size, "dome size", lo=16, hi=2048))
        object.__setattr__(self, "distance_factor",
                           check_distance_factor(self.distance_factor, "dome distance_factor"))

    def options(self) -> dict[str, Any]:
        """The options that decide the output (recorded in the manifest; a change re-bakes).

        Returns
        -------
        dict
            ``size``, ``distance_factor`` and the default dome's rings.
        """
        return {"size": self.size, "distance_factor": float(self.distance_factor),
                "rings": [[float(e), int(k)] for e, k in DEFAULT_RINGS]}

    def bake(self, mesh: trimesh.Trimesh, renderer: SceneRenderer, source_up: str = "z") -> SavableAsset:
        """The dome asset of ``mesh``.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The normalised mesh, object frame, ``+z`` up.
        renderer : SceneRenderer
            Renders the views.
        source_up : {"z", "y"}, optional
            The up axis the file was loaded with (recorded in the asset file).

        Returns
        -------
        SavableAsset
            The :class:`~morphkit.billboard.domeasset.DomeAsset`.
        """
        return bake_dome(mesh, renderer, size=self.size, distance_factor=self.distance_factor,
                         source_up=source_up)


@dataclass(frozen=True)
class SunAtlasKind:
    """The sun atlas of a mesh (:func:`~morphkit.sunlit.sunatlas.bake_sun_atlas` over the scenes'
    sun directions, :data:`~morphkit.sunlit.receivers.SCENE_ATLAS_DOME`): the light views a
    billboard field's shadows are drawn from.

    Parameters
    ----------
    size : int
        Texels a side of each light view, in ``tol.MIN_SUN_ATLAS_SIZE, tol.MAX_SUN_ATLAS_SIZE``
        (:mod:`morphkit.tol`).
    """

    size: int = SCENE_ATLAS_SIZE

    name: ClassVar[str] = "sun_atlas"
    suffix: ClassVar[str] = ".sunatlas.npz"
    version: ClassVar[int] = SUN_ATLAS_VERSION

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", as_int(self.size, "sun atlas size", lo=tol.MIN_SUN_ATLAS_SIZE,
                                                hi=tol.MAX_SUN_ATLAS_SIZE))

    def options(self) -> dict[str, Any]:
        """The options that decide the output (recorded in the manifest; a change re-bakes).

        Returns
        -------
        dict
            ``size`` and the sun directions' rings.
        """
        return {"size": self.size, "rings": [[float(e), int(k)] for e, k in SCENE_ATLAS_DOME.rings],
                "top": bool(SCENE_ATLAS_DOME.top)}

    def bake(self, mesh: trimesh.Trimesh, renderer: SceneRenderer, source_up: str = "z") -> SavableAsset:
        """The sun atlas of ``mesh``.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The normalised mesh, object frame, ``+z`` up.
        renderer : SceneRenderer
            Renders the light views' depth.
        source_up : {"z", "y"}, optional
            Not recorded (the atlas holds the shape's hash).

        Returns
        -------
        SavableAsset
            The atlas, with its ``save``.
        """
        return SavableSunAtlas(bake_sun_atlas(mesh, renderer, dome=SCENE_ATLAS_DOME, size=self.size))


def output_name(asset: str, kind: AssetKind) -> str:
    """The output file of ``asset`` for ``kind``, relative to the output folder (POSIX).

    Parameters
    ----------
    asset : str
        Asset name (``AssetInput.name``).
    kind : AssetKind
        The kind; its ``suffix`` is appended.

    Returns
    -------
    str
        ``<asset><kind.suffix>``, a POSIX path relative to the output folder.
    """
    return f"{asset}{kind.suffix}"
