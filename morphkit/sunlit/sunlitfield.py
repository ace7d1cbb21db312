"""A field of billboards with shadows under a sun, from a few meshes: :class:`SunlitField`.

The recipe of ``morphkit billboards --shadows`` as one object. Each asset's mesh is baked into
a relightable dome asset (:func:`~morphkit.billboard.domeasset.bake_dome`) and a sun atlas
(:func:`~morphkit.sunlit.receivers.bake_scene_atlases`); instances are scattered over a
square field (:func:`~morphkit.billboard.frames.instances.place_random`) and moved apart so that none
stands inside another (:func:`~morphkit.billboard.frames.instances.separate`). A frame under a sun
is then drawn two ways:

* the method: relit view-morphed billboards (:class:`~morphkit.sunlit.litmodes.LitMode`,
  facing the eye: :class:`~morphkit.billboard.frames.facing.ViewpointFacing`) shadowed by the assets'
  sun atlases (:class:`~morphkit.sunlit.receivers.AtlasShadow`), :meth:`SunlitField.render`;
* the truth: the real meshes shaded by the same model
  (:class:`~morphkit.sunlit.litmesh.LitMeshMode`) and shadowed by ray casting towards the
  sun (:class:`~morphkit.sunlit.raycast.RayCastShadow`), :meth:`SunlitField.truth`.

:meth:`SunlitField.compare` measures the one against the other as ``morphkit demo`` does: the
IoU of the pixels the shadows darken (:func:`~morphkit.sunlit.shadowing.darkened`), on the
ground (where neither frame draws an object) and on the objects (where both do).

Nothing here imports pyrender: the renderer is passed in (:class:`morphkit.render.Renderer`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import trimesh

from ..billboard.baking.bakelook import BAKE_AMBIENT
from ..billboard.domeasset import DomeAsset, bake_dome
from ..billboard.frames.backdrop import Backdrop
from ..billboard.frames.facing import ViewpointFacing
from ..billboard.frames.field import BillboardScene
from ..billboard.frames.frametypes import Frame
from ..billboard.frames.instances import field_half_size, footprint_radius, place_random, separate
from ..camera import CameraModel, look_at, perspective
from ..errors import MeshError, ValidationError, expected_got
from ..imaging.metrics import shadow_iou
from ..imaging.shading import Lighting
from ..meshes import normalize
from ..protocols import PassRenderer
from ..scene import DirectionalLight
from ..validate import as_int, as_shape
from .litmesh import LitMeshMode
from .litmodes import LitMode
from .raycast import RayCastShadow
from .receivers import SCENE_ATLAS_SIZE, AtlasShadow, bake_scene_atlases
from .shadowing import darkened
from .sunatlas import SunAtlas

__all__ = ["SunlitField", "FieldComparison", "FIELD_CAMERA_FOV_DEG", "FIELD_CAMERA_EYE",
           "FIELD_CAMERA_TARGET"]

#: The field camera's vertical field of view, degrees (:meth:`SunlitField.camera`).
FIELD_CAMERA_FOV_DEG = 50.0
#: The field camera's eye in half sizes of the field (:meth:`SunlitField.camera`): beyond its
#: ``-y`` edge, a little above it (``morphkit demo``'s view of its shadowed field).
FIELD_CAMERA_EYE = (0.0, -1.92, 0.76)
#: The point the field camera looks at: the field's middle, 0.3 scene units up.
FIELD_CAMERA_TARGET = (0.0, 0.0, 0.3)


@dataclass(frozen=True)
class FieldComparison:
    """One frame of a :class:`SunlitField` drawn by the method and by the truth.

    Parameters
    ----------
    billboards : Frame
        Relit view-morphed billboards shadowed by the assets' sun atlases.
    truth : Frame
        The real meshes shadowed by ray casting.
    shadow_iou : dict of str to float
        IoU of the pixels each frame's shadows darken: ``"ground"`` (where neither frame draws
        an object) and ``"objects"`` (where both do); NaN where the frame shows no such pixel.
    """

    billboards: Frame
    truth: Frame
    shadow_iou: dict[str, float]

    @property
    def strip(self) -> np.ndarray:
        """The two frames side by side, billboards | real meshes: ``(H, 2 W, 3)`` uint8."""
        return np.concatenate([self.billboards.rgb, self.truth.rgb], axis=1)


def _suns(sun: DirectionalLight | Sequence[DirectionalLight]) -> tuple[DirectionalLight, ...]:
    suns = (sun,) if isinstance(sun, DirectionalLight) else tuple(sun) if isinstance(sun, Sequence) else None
    if not suns or not all(isinstance(s, DirectionalLight) for s in suns):
        raise ValidationError(expected_got(
            "sun", "a DirectionalLight (e.g. morphkit.sun(azimuth, elevation)) or a sequence of them",
            type(sun).__name__))
    return suns


def _region_iou(pred: np.ndarray, truth: np.ndarray, region: np.ndarray) -> float:
    return shadow_iou(pred, truth, mask=region) if region.any() else math.nan


class SunlitField:
    """Relit view-morphed billboards over a field under the sun, with their shadows, beside the
    truth (module docstring). Build one from meshes with :meth:`from_meshes`.

    Parameters
    ----------
    scene : BillboardScene
        The field: dome assets (:class:`~morphkit.billboard.domeasset.DomeAsset`) and their
        instances.
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh, as its dome asset was baked from it (normalised).
    atlases : mapping of str to SunAtlas
        Each asset's sun atlas.
    renderer : PassRenderer
        Draws the truth's passes (:class:`morphkit.render.Renderer`); keep it open while
        frames are drawn.
    ambient : float
        The frames' ambient level (default the bake's).

    Raises
    ------
    ValidationError
        Assets that are not dome assets; meshes or atlases missing for an asset, or of
        another mesh.

    Examples
    --------
    Twelve trees and boxes under a sun 35 degrees up, and the shadows' agreement with the
    ray-cast truth (needs GL)::

        import trimesh
        import morphkit

        meshes = {"tree": morphkit.sample_mesh("tree"), "box": trimesh.creation.box((0.4, 0.4, 1.0))}
        with morphkit.Renderer() as r:
            field = morphkit.SunlitField.from_meshes(meshes, r, n=12, seed=3)
            cmp = field.compare(field.camera((96, 128)), morphkit.sun(30.0, 35.0))
        print(cmp.shadow_iou)  # {'ground': ..., 'objects': ...}
    """

    def __init__(self, scene: BillboardScene, meshes: Mapping[str, trimesh.Trimesh],
                 atlases: Mapping[str, SunAtlas], renderer: PassRenderer, *,
                 ambient: float = BAKE_AMBIENT) -> None:
        if not isinstance(scene, BillboardScene):
            raise ValidationError(expected_got("scene", "a BillboardScene", type(scene).__name__))
        names = list(scene.assets)
        for what, given in (("meshes", meshes), ("atlases", atlases)):
            if not isinstance(given, Mapping) or set(given) != set(names):
                got = sorted(given) if isinstance(given, Mapping) else type(given).__name__
                raise ValidationError(expected_got(what, f"one per asset of the scene, {sorted(names)}", got))
        for nm in names:
            if not isinstance(scene.assets[nm], DomeAsset):
                raise ValidationError(expected_got(f"asset {nm!r}", "a DomeAsset (bake_dome)",
                                                   type(scene.assets[nm]).__name__))
            if not isinstance(atlases[nm], SunAtlas):
                raise ValidationError(expected_got(f"sun atlas of {nm!r}", "a SunAtlas",
                                                   type(atlases[nm]).__name__))
        self.scene = scene
        self.meshes = dict(meshes)
        self.atlases = dict(atlases)
        self.items = {nm: scene.assets[nm].items(self.meshes[nm]) for nm in names}  # checks the meshes
        base = Lighting(ambient)
        self.ambient = base.ambient
        self._billboards = LitMode(lighting=base, shadow=AtlasShadow(self.atlases))
        self._billboards_unshadowed = LitMode(lighting=base)
        self._truth = LitMeshMode(renderer, self.items, base, shadow=RayCastShadow(self.meshes))
        self._truth_unshadowed = LitMeshMode(renderer, self.items, base)

    @classmethod
    def from_meshes(cls, meshes: Mapping[str, trimesh.Trimesh], renderer: PassRenderer, *, n: int = 16,
                    seed: int = 0, half_size: float | None = None, view_size: int = 96,
                    atlas_size: int = SCENE_ATLAS_SIZE, spread: bool = True) -> SunlitField:
        """Bake each mesh's dome asset and sun atlas and scatter ``n`` instances of them.

        Parameters
        ----------
        meshes : mapping of str to trimesh.Trimesh
            The assets' meshes by name, in their own look (normalised here: size 1, on the
            ground); e.g. :func:`morphkit.meshes.load_mesh` of the user's files.
        renderer : PassRenderer
            Bakes the assets and draws the truth (:class:`morphkit.render.Renderer`).
        n : int
            Instances (>= 1), the assets chosen uniformly.
        seed : int
            The scatter's random seed (positions, yaws, scales, assets).
        half_size : float, optional
            The field is ``[-half_size, half_size]^2``; default about one instance per 1.5 x 1.5
            (:func:`~morphkit.billboard.frames.instances.field_half_size`).
        view_size : int
            The dome assets' view side, pixels.
        atlas_size : int
            The sun atlases' view side, texels.
        spread : bool
            Move instances apart so that no two footprints overlap.

        Returns
        -------
        SunlitField
            The field.

        Raises
        ------
        ValidationError
            No meshes, a name that is not a non-empty string, bad counts or sizes.
        MeshError
            A mesh that cannot be drawn.
        """
        if not isinstance(meshes, Mapping) or not meshes:
            raise ValidationError(expected_got("meshes", "a non-empty mapping name -> trimesh.Trimesh",
                                               type(meshes).__name__ if not isinstance(meshes, Mapping)
                                               else "an empty mapping"))
        for nm, mesh in meshes.items():
            if not isinstance(nm, str) or not nm:
                raise ValidationError(expected_got("asset name", "a non-empty string", repr(nm)))
            if not isinstance(mesh, trimesh.Trimesh):
                raise MeshError(expected_got(f"mesh of {nm!r}", "a trimesh.Trimesh", type(mesh).__name__))
        n = as_int(n, "instance count n", lo=1)
        norm = {nm: normalize(mesh) for nm, mesh in meshes.items()}
        assets = {nm: bake_dome(mesh, renderer, name=nm, size=view_size) for nm, mesh in norm.items()}
        atlases = bake_scene_atlases(norm, renderer, size=atlas_size)
        rng = np.random.default_rng(seed)
        half = field_half_size(n) if half_size is None else half_size
        inst = place_random(list(norm), n, rng, half_size=half)
        if spread:
            radius = {nm: footprint_radius(assets[nm].items(mesh)) for nm, mesh in norm.items()}
            inst = separate(inst, radius, rng, half_size=half).instances
        scene = BillboardScene(assets, inst, backdrop=Backdrop(), facing=ViewpointFacing())
        return cls(scene, norm, atlases, renderer)

    @property
    def half_size(self) -> float:
        """Half the side of the square the instances stand in (their largest ``|x|`` or ``|y|``)."""
        xy = self.scene.instances.xy
        return max(1.0, float(np.abs(xy).max())) if len(xy) else 1.0

    def camera(self, shape: tuple[int, int] = (288, 384)) -> CameraModel:
        """A perspective camera overlooking the field from its ``-y`` side, a little above it.

        Parameters
        ----------
        shape : (H, W)
            Image size, pixels.

        Returns
        -------
        CameraModel
            World frame; it sees the field's middle and the instances beyond.
        """
        eye = self.half_size * np.array(FIELD_CAMERA_EYE)
        return perspective(math.radians(FIELD_CAMERA_FOV_DEG), as_shape(shape, "shape"),
                           look_at(eye, np.array(FIELD_CAMERA_TARGET), up=np.array([0.0, 0.0, 1.0])))

    def _lit(self, sun: DirectionalLight | Sequence[DirectionalLight]) -> Lighting:
        return Lighting(self.ambient, _suns(sun))

    def render(self, camera: CameraModel, sun: DirectionalLight | Sequence[DirectionalLight]) -> Frame:
        """The field's billboards under ``sun``, shadowed by the sun atlases (the method).

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        sun : DirectionalLight or sequence of DirectionalLight
            The sun(s) (:func:`morphkit.sunpath.sun`), world frame.

        Returns
        -------
        Frame
            ``rgb`` the image; ``layer`` the billboards alone.
        """
        self._billboards.lighting = self._lit(sun)
        return self.scene.render(camera, self._billboards)

    def truth(self, camera: CameraModel, sun: DirectionalLight | Sequence[DirectionalLight]) -> Frame:
        """The real meshes at the instances' poses under ``sun``, shadowed by ray casting (the truth).

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        sun : DirectionalLight or sequence of DirectionalLight
            The sun(s), world frame.

        Returns
        -------
        Frame
            ``rgb`` the image; ``layer`` the meshes alone.
        """
        self._truth.lighting = self._lit(sun)
        return self.scene.render(camera, self._truth)

    def compare(self, camera: CameraModel, sun: DirectionalLight | Sequence[DirectionalLight]
                ) -> FieldComparison:
        """The method's and the truth's frame under ``sun``, and their shadows' agreement.

        Parameters
        ----------
        camera : CameraModel
            The view, world frame.
        sun : DirectionalLight or sequence of DirectionalLight
            The sun(s), world frame.

        Returns
        -------
        FieldComparison
            Both frames and the shadow IoU on the ground and on the objects.
        """
        lit = self._lit(sun)
        self._billboards_unshadowed.lighting = self._truth_unshadowed.lighting = lit
        bb, mesh = self.render(camera, sun), self.truth(camera, sun)
        bb0 = self.scene.render(camera, self._billboards_unshadowed)
        mesh0 = self.scene.render(camera, self._truth_unshadowed)
        db, dm = darkened(bb0.rgb, bb.rgb), darkened(mesh0.rgb, mesh.rgb)
        ab, am = bb.layer[..., 3], mesh.layer[..., 3]
        iou = {"ground": _region_iou(db, dm, (ab < 0.5) & (am < 0.5)),
               "objects": _region_iou(db, dm, (ab > 0.5) & (am > 0.5))}
        return FieldComparison(bb, mesh, iou)
