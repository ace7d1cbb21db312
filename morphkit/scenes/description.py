"""What a scene is: its assets, where their instances stand, the camera, the sun, the image.

:class:`SceneDescription` is pure data: reading or writing one renders nothing; the programs bake
(or read) its assets and draw it (``morphkit render SCENE``). It is what a JSON scene file
(:mod:`morphkit.scenes.jsonfile`) or a glTF scene (:mod:`morphkit.scenes.gltfscene`) says, and
what the ``billboards`` command's flags say (``--save-scene``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import trimesh

from .. import tol
from ..billboard.frames.backdrop import Ground
from ..conventions import SUN_DISC_RADIUS_DEG
from ..errors import ValidationError, expected_got
from ..validate import as_int, as_positive, as_shape
from .camerapaths import Keyframes, NamedPath
from .placing import Listed, Scatter
from .suns import BakeLight, DaySun, FixedSun

__all__ = ["SceneAsset", "SceneShadows", "SceneDescription", "UP_AXES", "VIEWS_DOME", "SOFT_PCSS",
           "DEFAULT_SHAPE"]

#: A scene's image ``(H, W)`` when its file does not say.
DEFAULT_SHAPE: tuple[int, int] = (480, 640)

#: The up axes a mesh file may be read with (:func:`morphkit.meshes.load_mesh`).
UP_AXES: tuple[str, ...] = ("auto", "y", "z")
#: :attr:`SceneDescription.views` for relightable views over the hemisphere.
VIEWS_DOME = "dome"
#: :attr:`SceneShadows.soft` for one map filtered over the sun's disc (percentage-closer soft shadows).
SOFT_PCSS = "pcss"


@dataclass(frozen=True, eq=False)
class SceneAsset:
    """One asset of a scene: where it comes from and its size.

    Parameters
    ----------
    name : str
        The name its instances use (non-empty).
    source : str
        A sample mesh name (:data:`morphkit.meshes.BILLBOARD_MESHES`), a mesh file (``.obj``,
        ``.glb``/``.gltf``, ``.ply``), or a ``.npz`` billboard asset file; for a mesh of a glTF
        scene, ``"FILE#MESH"`` (with :attr:`mesh` set).
    scale : float, optional
        The asset's size: its normalised mesh (largest extent 1) times ``scale`` is one instance
        at scale 1, scene units (> 0).
    up : {"auto", "y", "z"}, optional
        The up axis of a mesh file (:func:`morphkit.meshes.load_mesh`).
    mesh : trimesh.Trimesh, optional
        The normalised mesh itself (a glTF scene's), baked in place of ``source``.
    """

    name: str
    source: str
    scale: float = 1.0
    up: str = "auto"
    mesh: trimesh.Trimesh | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        for what, v in (("asset name", self.name), ("asset source", self.source)):
            if not isinstance(v, str) or not v:
                raise ValidationError(expected_got(what, "a non-empty string", repr(v)))
        object.__setattr__(self, "scale", as_positive(self.scale, f"asset {self.name!r} scale"))
        if self.up not in UP_AXES:
            raise ValidationError(
                expected_got(f"asset {self.name!r} up", f"one of {list(UP_AXES)}", repr(self.up))
            )
        if self.mesh is not None and not isinstance(self.mesh, trimesh.Trimesh):
            raise ValidationError(
                expected_got(f"asset {self.name!r} mesh", "a trimesh.Trimesh", type(self.mesh).__name__)
            )


@dataclass(frozen=True)
class SceneShadows:
    """The instances cast shadows under the sun: each asset's sun atlas, and how soft.

    Parameters
    ----------
    soft : None, "pcss" or int, optional
        None: a hard shadow; ``"pcss"``: one map filtered over the sun's disc; N: N directions
        over the disc, one map each, averaged.
    sun_atlas_size : int or None, optional
        Texels a side of each asset's sun atlas views (None: the default).
    sun_radius_deg : float, optional
        The sun disc's angular radius, degrees (default: the real sun's).
    """

    soft: str | int | None = None
    sun_atlas_size: int | None = None
    sun_radius_deg: float = SUN_DISC_RADIUS_DEG

    def __post_init__(self) -> None:
        if self.soft is not None and self.soft != SOFT_PCSS:
            object.__setattr__(self, "soft", as_int(self.soft, "shadows soft", lo=1))
        if self.sun_atlas_size is not None:
            object.__setattr__(self, "sun_atlas_size", as_int(self.sun_atlas_size, "sun_atlas_size", lo=8))
        r = as_positive(self.sun_radius_deg, "sun_radius_deg")
        if r > 15.0:
            raise ValidationError(expected_got("sun_radius_deg", "degrees in (0, 15]", r))
        object.__setattr__(self, "sun_radius_deg", r)


@dataclass(frozen=True, eq=False)
class SceneDescription:
    """A scene written down (the module notes).

    Parameters
    ----------
    assets : tuple of SceneAsset
        Distinct names.
    instances : Listed or Scatter
        Where their instances stand.
    camera : NamedPath or Keyframes, optional
        The camera over the frames (default: the paper's pan).
    sun : BakeLight, FixedSun or DaySun, optional
        The sun (default: the light the assets were baked under).
    shape : (H, W), optional
        Frame size in pixels.
    frames : int, optional
        Frames along the camera path, >= 1.
    views : int, "dome" or None, optional
        Reference views of each baked asset: K on a ring, ``"dome"`` relightable views over the
        hemisphere, None what the scene needs (dome for a sun or a path seen from above the
        ring's band).
    asset_size : int, optional
        Reference view side of baked assets, pixels.
    shadows : SceneShadows or None, optional
        Shadows under the sun (None: none).
    fog : bool, optional
        Distance fog.
    ground : Ground, optional
        The ground's look.
    notes : tuple of str, optional
        What reading the scene ignored or chose by default, one line each (a glTF scene's).
    """

    assets: tuple[SceneAsset, ...]
    instances: Listed | Scatter
    camera: NamedPath | Keyframes = field(default_factory=lambda: NamedPath("pan"))
    sun: BakeLight | FixedSun | DaySun = field(default_factory=BakeLight)
    shape: tuple[int, int] = DEFAULT_SHAPE
    frames: int = 48
    views: int | str | None = None
    asset_size: int = 128
    shadows: SceneShadows | None = None
    fog: bool = True
    ground: Ground = field(default_factory=Ground)
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        assets = tuple(self.assets)
        for a in assets:
            if not isinstance(a, SceneAsset):
                raise ValidationError(expected_got("scene assets", "SceneAsset objects", type(a).__name__))
        names = [a.name for a in assets]
        twice = sorted({nm for nm in names if names.count(nm) > 1})
        if twice:
            raise ValidationError(expected_got("scene assets", "distinct names", f"{twice} more than once"))
        object.__setattr__(self, "assets", assets)
        # the limits of the commands' flags (morphkit.tol), so that a scene too large for memory is
        # refused when it is read, before any work
        object.__setattr__(self, "shape", as_shape(self.shape, "scene image shape"))
        object.__setattr__(self, "frames", as_int(self.frames, "scene frames", lo=1, hi=tol.MAX_FRAMES))
        object.__setattr__(
            self, "asset_size", as_int(self.asset_size, "scene asset_size", lo=16, hi=tol.MAX_BILLBOARD_SIDE)
        )
        if self.views is not None and self.views != VIEWS_DOME:
            object.__setattr__(
                self, "views", as_int(self.views, "scene views", lo=2, hi=tol.MAX_BILLBOARD_VIEWS)
            )
        object.__setattr__(self, "notes", tuple(str(n) for n in self.notes))
        if isinstance(self.views, int) and (not isinstance(self.sun, BakeLight) or self.shadows is not None):
            # a ring's views are lit by the bake light alone: a sun would be silently ignored
            raise ValidationError(expected_got(
                "scene views with a sun or shadows", '"dome" or null (relighting needs albedo, normals and '
                "depth)", f"a ring of {self.views} views baked under the bake light"))

    @property
    def names(self) -> tuple[str, ...]:
        """The assets' names, in order.

        Returns
        -------
        tuple of str
        """
        return tuple(a.name for a in self.assets)

    def asset(self, name: str) -> SceneAsset:
        """The asset called ``name``.

        Parameters
        ----------
        name : str

        Returns
        -------
        SceneAsset

        Raises
        ------
        ValidationError
            No asset of that name.
        """
        for a in self.assets:
            if a.name == name:
                return a
        raise ValidationError(expected_got("asset", f"one of {list(self.names)}", repr(name)))
