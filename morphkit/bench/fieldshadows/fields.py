"""The scenes of ``morphkit bench scene``: fields of two textured assets, their atlases and impostors,
the methods that make a field's shadow map, and the ray-cast truth they are scored against.

Assets (:data:`ASSETS`): the packaged photo crate (:func:`morphkit.programs.fixtures.textured_demo_asset`,
12 faces, opaque) and the alpha-masked leaf plant (:func:`morphkit.programs.fixtures.write_leaf_plant`,
a stem and three leaf cards cut out by their texture's alpha), written into a temporary folder
and loaded ``+z`` up by :func:`morphkit.meshes.load_mesh` (no network). For the timing
sections each is subdivided to a face count (:func:`subdivided`: UVs and the cut-out kept).

A field of ``n`` instances (:meth:`SceneKit.field`): :func:`~morphkit.billboard.frames.instances.place_random`
of both assets with a seeded generator (random positions about one per 1.5 x 1.5 units, yaws in
``[0, 360)``, scales 0.8-1.25); the receiver is the ground square over the field plus
:data:`RECEIVER_MARGIN` a side, sampled on a ``grid x grid`` lattice of pixel centres
(:func:`morphkit.imaging.groundtruth.receiver_grid`). Truth:
:func:`~morphkit.sunlit.fieldbaselines.ray_cast_field`
(Embree; each asset's instances posed into one mesh that keeps its cut-out) towards the exact sun.

Methods (:data:`METHODS`; each a :class:`~morphkit.sunlit.fieldshadow.FieldMap` of the same light
view, ``FieldShadow.plan``'s camera, looked up with ``FieldMap.visibility``):

* ``atlas`` -- :meth:`FieldShadow.build <morphkit.sunlit.fieldshadow.FieldShadow.build>` from the
  assets' sun atlases (whatever the builder does: only its public API is called);
* ``direct`` -- :func:`~morphkit.sunlit.fieldbaselines.direct_field_map`: all posed meshes drawn
  from the sun into the same view;
* ``card-camera`` and ``card-light`` -- the impostor way
  (:func:`~morphkit.sunlit.cardbaselines.card_field_map`): each instance's alpha-tested card
  facing the light, showing the camera's view (the camera at :data:`CAMERA_AZIMUTH_DEG`,
  :data:`CAMERA_ELEVATION_DEG` from the field's centre, :data:`CAMERA_DISTANCE_FACTOR` times the
  field's half side plus :data:`CAMERA_DISTANCE_PAD` away) or the frame nearest the light, of an
  :class:`~morphkit.billboard.impostor.OctahedralImpostor` baked at the atlas's texel size.

The field view's resolution (texels per unit) is the atlases' (an atlas view's side over its
square's side, the smaller of the two assets'), lowered where the view would exceed
:data:`MAX_FIELD_SIDE` texels a side (large fields).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import trimesh

from ...billboard.frames.instances import Instances, place_random
from ...billboard.impostor import OctahedralImpostor, bake_impostor
from ...errors import ValidationError, expected_got
from ...imaging.cutout import mesh_cutout
from ...imaging.groundtruth import receiver_grid
from ...imaging.metrics import shadow_iou
from ...meshes import load_mesh, normalize
from ...programs.fixtures import textured_demo_asset, write_leaf_plant
from ...protocols import PassRenderer
from ...sunlit.cardbaselines import card_field_map
from ...sunlit.fieldbaselines import direct_field_map, posed_asset_meshes, ray_cast_field
from ...sunlit.fieldshadow import FieldMap, FieldShadow
from ...sunlit.sunatlas import SunAtlas, bake_sun_atlas
from ...sunpath import SunPath
from ...views.dome import ViewDome

__all__ = ["ASSETS", "METHODS", "DOMES", "SceneKit", "Field", "textured_meshes", "subdivided",
           "day_suns", "path_suns", "field_tpu", "score", "MAX_FIELD_SIDE", "surface_receivers",
           "RECEIVER_MARGIN", "CAMERA_AZIMUTH_DEG", "CAMERA_ELEVATION_DEG", "CAMERA_DISTANCE_FACTOR",
           "CAMERA_DISTANCE_PAD"]

#: The scene's two textured assets (built from photographs at run time, the plant alpha-masked).
ASSETS = ("photo-crate", "leaf-plant")
#: The field-shadow methods compared (module docstring).
METHODS = ("atlas", "direct", "card-camera", "card-light")
#: Sun-direction grids of the atlases (the sparse one is the recommended, the suite's default).
DOMES: dict[str, ViewDome] = {
    "sparse": ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True),
    "default": ViewDome(),
    "dense": ViewDome(((0.0, 16), (20.0, 16), (40.0, 12), (60.0, 8), (75.0, 6)), top=True),
}
#: Largest side (texels) of the field's light view; a larger field gets fewer texels per unit
#: (1000 instances keep the atlases' 78 texels a unit: a view of about 5800 texels a side).
MAX_FIELD_SIDE = 6144
#: Ground added to each side of the field's square for the receiver, scene units.
RECEIVER_MARGIN = 1.5
#: The camera of ``card-camera``: azimuth and elevation (degrees) seen from the field's centre.
CAMERA_AZIMUTH_DEG, CAMERA_ELEVATION_DEG = -120.0, 25.0
#: Its distance: this times the field's half side, plus :data:`CAMERA_DISTANCE_PAD` units.
CAMERA_DISTANCE_FACTOR, CAMERA_DISTANCE_PAD = 2.0, 6.0
#: The day the suns are drawn from (:class:`~morphkit.sunpath.SunPath`: azimuth -90 to 90,
#: 60 degrees at noon, 5 below the horizon at both ends, so the path's suns cross the horizon).
DAY = SunPath(rise_deg=-5.0)


def textured_meshes(folder: str | Path) -> dict[str, trimesh.Trimesh]:
    """The two textured assets (module docstring), the leaf plant written into ``folder``.

    Parameters
    ----------
    folder : str or pathlib.Path
        An existing (temporary) folder.

    Returns
    -------
    dict of str to trimesh.Trimesh
        By :data:`ASSETS` name, ``+z`` up.
    """
    return {"photo-crate": load_mesh(textured_demo_asset()),
            "leaf-plant": load_mesh(write_leaf_plant(folder))}


def subdivided(mesh: trimesh.Trimesh, faces: int) -> trimesh.Trimesh:
    """``mesh`` subdivided to at least ``faces`` faces (its shape, UVs and look kept).

    Whole 4-way subdivisions while they stay under ``faces``, then the first faces split
    once more (3 faces more each) up to the count: T-junctions on flat faces, which a
    depth render and a ray cast do not see.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh (not changed).
    faces : int
        Wanted face count; a mesh already that large is returned as it is.

    Returns
    -------
    trimesh.Trimesh
        ``faces`` to ``faces + 2`` faces.
    """
    m = mesh
    while 4 * len(m.faces) <= faces:
        m = m.subdivide()
    extra = math.ceil(max(faces - len(m.faces), 0) / 3)
    return m.subdivide(face_index=np.arange(extra)) if extra else m


def day_suns(count: int) -> list[np.ndarray]:
    """``count`` suns of a morning, low to high: ``t`` from 0.1 (15 degrees up) to 0.5 (noon, 60).

    Parameters
    ----------
    count : int
        Number of suns (>= 1; one: noon).

    Returns
    -------
    list of (3,) float64
        Directions towards the sun, world frame.
    """
    ts = np.linspace(0.1, 0.5, count) if count > 1 else np.array([0.5])
    return [-DAY.sun_at(float(t)).direction for t in ts]


def path_suns(count: int) -> tuple[list[np.ndarray], np.ndarray]:
    """The day's ``count`` suns from sunrise to sunset (:meth:`SunPath.suns`) and their elevations.

    Parameters
    ----------
    count : int
        Number of suns (>= 2).

    Returns
    -------
    suns : list of (3,) float64
        Directions towards the sun, world frame.
    elevations : (count,) float64
        Degrees (the first and last below the horizon).
    """
    ts = np.linspace(0.0, 1.0, count)
    return ([-DAY.sun_at(float(t)).direction for t in ts],
            np.array([DAY.elevation_at(float(t)) for t in ts]))


def field_tpu(atlases: dict[str, SunAtlas], rect: tuple[float, float, float, float], scale: float = 1.0
              ) -> float:
    """The field view's texels per unit: the atlases' (times ``scale``), capped at
    :data:`MAX_FIELD_SIDE` a side.

    Parameters
    ----------
    atlases : dict of str to SunAtlas
        The assets' atlases.
    rect : (xmin, ymin, xmax, ymax)
        The receiver.
    scale : float
        A factor on the atlases' resolution (the filtered sun disc's map:
        :data:`~morphkit.tol.SUN_DISC_MAP_SCALE`).

    Returns
    -------
    float
        Texels per scene unit.
    """
    tpu = scale * min(a.size / (2.0 * a.cameras.half_extent[0]) for a in atlases.values())
    # the receiver's diagonal bounds its extent across the light whatever the sun's azimuth; the
    # casters' spheres reach past it
    span = math.hypot(rect[2] - rect[0], rect[3] - rect[1]) + 4.0
    return float(min(tpu, MAX_FIELD_SIDE / span))


@dataclass
class Field:
    """One field of instances, its receiver grid and its ray-cast truth per sun (cached).

    Parameters
    ----------
    instances : Instances
        The field.
    rect : (xmin, ymin, xmax, ymax)
        The receiver.
    grid : int
        Receiver points a side.
    points : (grid * grid, 3) float64
        The receiver points.
    camera_position : (3,) float64
        The viewer of ``card-camera``.
    posed : list of trimesh.Trimesh
        The truth's posed meshes (one per asset).
    meshes : dict of str to trimesh.Trimesh
        The assets' meshes.
    """

    instances: Instances
    rect: tuple[float, float, float, float]
    grid: int
    points: np.ndarray
    camera_position: np.ndarray
    posed: list[trimesh.Trimesh]
    meshes: dict[str, trimesh.Trimesh]
    _truths: dict[bytes, np.ndarray] = field(default_factory=dict, init=False, repr=False)

    def truth(self, sun: np.ndarray) -> np.ndarray:
        """The ray-cast visibility of the receiver points under ``sun`` (computed once).

        Parameters
        ----------
        sun : (3,) float
            Towards the sun, world frame.

        Returns
        -------
        (grid * grid,) float32
            1 lit, 0 shadowed.
        """
        key = np.asarray(sun, np.float64).tobytes()
        if key not in self._truths:
            self._truths[key] = ray_cast_field(self.meshes, self.instances, sun, self.points,
                                               posed=self.posed)
        return self._truths[key]


def score(fm: FieldMap, fld: Field, sun: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Shadow IoU (visibility < 0.5) and mean absolute visibility error of a map against the truth.

    Parameters
    ----------
    fm : FieldMap
        A method's map.
    fld : Field
        The field (its truth).
    sun : (3,) float
        The sun.

    Returns
    -------
    iou : float
        :func:`morphkit.imaging.metrics.shadow_iou` of the shadow masks.
    mae : float
        Mean absolute visibility error over the receiver points.
    shadow : (grid * grid,) bool
        The method's shadow mask.
    """
    vis = fm.visibility(fld.points)
    truth = fld.truth(sun)
    shadow = vis < 0.5
    return shadow_iou(shadow, truth < 0.5), float(np.abs(vis - truth).mean()), shadow


def surface_receivers(fld: Field, count: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Points on the instances' own surfaces, with their normals: the receivers of the
    ``receivers`` section (a shadow on the casters themselves, their own or a neighbour's).

    ``count`` points are drawn on each asset's posed mesh by area (:func:`trimesh.sample.sample_surface`,
    seeded from ``rng``); a point on a cut-out texel (no surface there,
    :func:`morphkit.imaging.cutout.mesh_cutout`) is dropped.

    Parameters
    ----------
    fld : Field
        The field (its posed meshes).
    count : int
        Points drawn per asset.
    rng : numpy.random.Generator
        Seeds the draws.

    Returns
    -------
    points : (M, 3) float64
        World frame.
    normals : (M, 3) float64
        The faces' unit normals (as the mesh winds them).
    """
    pts, nrm = [], []
    for body in fld.posed:
        p, fi = trimesh.sample.sample_surface(body, count, seed=int(rng.integers(2**31)))
        keep = np.ones(len(p), bool)
        cut = mesh_cutout(body)
        if cut is not None:
            bary = trimesh.triangles.points_to_barycentric(body.triangles[fi], p)
            keep = cut.opaque(fi, bary)
        pts.append(p[keep])
        nrm.append(body.face_normals[fi[keep]])
    return np.concatenate(pts), np.concatenate(nrm)


class SceneKit:
    """Meshes, atlases, impostors and fields shared by the suite's sections (each made once).

    Parameters
    ----------
    renderer : PassRenderer
        Bakes and draws (:class:`morphkit.render.Renderer`).
    folder : str or pathlib.Path
        A temporary folder for the leaf plant's file.
    atlas_size : int
        Atlas views' side (texels); the impostors' frames get the same.
    impostor_frames : int
        Frames a side of the octahedral impostors.
    impostor_supersample : int
        Supersampling of the impostor bakes.
    seed : int
        Seeds the fields (``seed + n`` for ``n`` instances).
    """

    def __init__(self, renderer: PassRenderer, folder: str | Path, *, atlas_size: int = 128,
                 impostor_frames: int = 12, impostor_supersample: int = 3, seed: int = 26) -> None:
        self.renderer = renderer
        self.base = textured_meshes(folder)
        self.atlas_size = atlas_size
        self.impostor_frames = impostor_frames
        self.impostor_supersample = impostor_supersample
        self.seed = seed
        self._meshes: dict[int | None, dict[str, trimesh.Trimesh]] = {None: self.base}
        self._normalized: dict[int | None, dict[str, trimesh.Trimesh]] = {}
        self._atlases: dict[tuple[Any, ...], dict[str, SunAtlas]] = {}
        self.bake_seconds: dict[tuple[Any, ...], float] = {}
        self._impostors: dict[str, OctahedralImpostor] | None = None
        self._fields: dict[tuple[int, int, tuple[str, ...]], Field] = {}

    def meshes(self, faces: int | None = None) -> dict[str, trimesh.Trimesh]:
        """The assets' meshes, as loaded or subdivided (:func:`subdivided`).

        Parameters
        ----------
        faces : int, optional
            Faces an asset; ``None``: as loaded.

        Returns
        -------
        dict of str to trimesh.Trimesh
            By asset name (made once).
        """
        if faces not in self._meshes:
            assert faces is not None
            self._meshes[faces] = {nm: subdivided(m, faces) for nm, m in self.base.items()}
        return self._meshes[faces]

    def normalized(self, faces: int | None = None) -> dict[str, trimesh.Trimesh]:
        """The meshes normalised (as the atlases and the direct render pose them).

        Parameters
        ----------
        faces : int, optional
            As :meth:`meshes`.

        Returns
        -------
        dict of str to trimesh.Trimesh
            By asset name (made once).
        """
        if faces not in self._normalized:
            self._normalized[faces] = {nm: normalize(m) for nm, m in self.meshes(faces).items()}
        return self._normalized[faces]

    def atlases(self, faces: int | None = None, dome: str = "sparse", size: int | None = None
                ) -> dict[str, SunAtlas]:
        """The assets' sun atlases (baked once; the time in :attr:`bake_seconds`).

        Parameters
        ----------
        faces : int, optional
            As :meth:`meshes`.
        dome : str
            A key of :data:`DOMES`.
        size : int, optional
            Texels a side (default the kit's ``atlas_size``).

        Returns
        -------
        dict of str to SunAtlas
            By asset name.
        """
        key = (faces, dome, self.atlas_size if size is None else size)
        if key not in self._atlases:
            t0 = time.perf_counter()
            self._atlases[key] = {nm: bake_sun_atlas(m, self.renderer, dome=DOMES[dome], size=key[2])
                                  for nm, m in self.meshes(faces).items()}
            self.bake_seconds[key] = time.perf_counter() - t0
        return self._atlases[key]

    def impostors(self) -> dict[str, OctahedralImpostor]:
        """The assets' octahedral impostors (frames at the atlas's size, one mip level; baked once).

        Returns
        -------
        dict of str to OctahedralImpostor
            By asset name.
        """
        if self._impostors is None:
            self._impostors = {nm: bake_impostor(m, self.renderer, name=nm, frames=self.impostor_frames,
                                                 frame_size=self.atlas_size, levels=1,
                                                 supersample=self.impostor_supersample)
                               for nm, m in self.base.items()}
        return self._impostors

    def field(self, n: int, grid: int, assets: tuple[str, ...] = ASSETS) -> Field:
        """The field of ``n`` instances with a ``grid x grid`` receiver (module docstring; made once).

        Parameters
        ----------
        n : int
            Instances.
        grid : int
            Receiver points a side.
        assets : tuple of str
            The assets drawn from (default both).

        Returns
        -------
        Field
            The field.
        """
        if (n, grid, assets) not in self._fields:
            inst = place_random(assets, n, np.random.default_rng(self.seed + n))
            half = max(1.0, 1.5 * math.sqrt(n) / 2.0) + RECEIVER_MARGIN
            pts = receiver_grid(half, (grid, grid)).reshape(-1, 3)
            a, e = np.radians(CAMERA_AZIMUTH_DEG), np.radians(CAMERA_ELEVATION_DEG)
            dist = CAMERA_DISTANCE_FACTOR * half + CAMERA_DISTANCE_PAD
            eye = dist * np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
            self._fields[(n, grid, assets)] = Field(inst, (-half, -half, half, half), grid, pts, eye,
                                                    posed_asset_meshes(self.base, inst), self.base)
        return self._fields[(n, grid, assets)]

    def method(self, name: str, fs: FieldShadow, fld: Field, tpu: float, faces: int | None = None, *,
               cold: bool = True) -> Callable[[np.ndarray], FieldMap]:
        """A function ``sun -> FieldMap`` of one of :data:`METHODS` on ``fld`` with ``fs``'s view.

        Parameters
        ----------
        name : str
            One of :data:`METHODS`.
        fs : FieldShadow
            The atlases' builder (its plan gives every method's camera).
        fld : Field
            The field.
        tpu : float
            The view's resolution.
        faces : int, optional
            The meshes the direct render draws (default: as loaded).
        cold : bool
            ``atlas``: empty the builder's cache first (a new sun, nothing cached).

        Returns
        -------
        callable
            ``sun -> FieldMap``.
        """
        inst, rect = fld.instances, fld.rect
        if name == "atlas":
            def atlas(sun: np.ndarray) -> FieldMap:
                if cold:
                    fs.clear()
                return fs.build(inst, sun, tpu, rect)
            return atlas
        if name == "direct":
            norm = self.normalized(faces)
            return lambda sun: direct_field_map(fs, norm, self.renderer, inst, sun, tpu, rect)
        if name in ("card-camera", "card-light"):
            imps, image = self.impostors(), name.split("-")[1]
            return lambda sun: card_field_map(fs, imps, inst, sun, tpu, rect, image=image,
                                              camera_position=fld.camera_position)
        raise ValidationError(expected_got("method", f"one of {list(METHODS)}", repr(name)))
