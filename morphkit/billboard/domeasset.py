"""Relightable billboard assets seen from any height: a dome of views, morphed per pixel.

A :class:`DomeAsset` holds, for one (normalised) mesh, the views of a
:class:`~morphkit.views.dome.ViewDome` (rings at several elevations and a top view) rendered by
the camera rule of :class:`~morphkit.views.domecameras.DomeCameras`, each as a
:class:`~morphkit.views.gbuffer.ViewSurface`: albedo and coverage, object-frame normals and depth
(no light: the scene's lights shade it, :mod:`morphkit.imaging.shading`). For a viewing
direction it returns the surface of that direction's camera
(:meth:`DomeAsset.surface`): the three views around the direction
(:meth:`ViewDome.weights`) morphed with their depth (:mod:`morphkit.views.depthmorph`). The
baselines of the same views: :meth:`~DomeAsset.nearest_surface` (the view of the
largest weight, as an impostor that switches), :meth:`~DomeAsset.crossfade_surface`
(the three views blended by weight, no parallax) and
:meth:`~DomeAsset.classic_surface` (the front view for every direction).

Level ``l`` surfaces are the level-0 views downsampled
(:func:`~morphkit.views.gbuffer.downsample_surface`), made on first use and kept; every other
image is made per call (the scene's cache keeps what repeats,
:class:`~.cache.MorphCache`).

:func:`bake_dome` renders the views (:meth:`morphkit.render.Renderer.source_passes`:
supersampled coverage, albedo, normals, nearest depth) of the mesh in its look
(:func:`~.bakelook.bake_items`); a view that sees less than
:data:`morphkit.tol.BB_MIN_CORRESPONDENCES` pixels of the object cannot be morphed
and is refused, naming it and its neighbours.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel
from ..errors import (
    DegenerateViewError,
    FileFormatError,
    GeometryError,
    MeshError,
    ValidationError,
    expected_got,
)
from ..memo import Memo
from ..meshes import normalize
from ..protocols import PassRenderer
from ..scene import Item
from ..validate import as_int
from ..views.depthmorph import morph_views, plane_warp
from ..views.dome import ViewDome
from ..views.domecameras import DomeCameras
from ..views.gbuffer import (
    BYTES_PER_PIXEL,
    StoredSurface,
    ViewSurface,
    decode_surface,
    downsample_surface,
    encode_surface,
)
from .baking.bakelook import (
    BAKE_AMBIENT,
    bake_items,
    bake_lights,
    check_appearance,
    check_source_up,
    mesh_hash,
)
from .cameras import DISTANCE_FACTOR
from .formats.domefile import DomeRecord, read_dome, write_dome

__all__ = ["DomeAsset", "bake_dome", "DOME_SUPERSAMPLE"]

#: Supersampling per axis of the bake's renders (coverage alpha and anti-aliased albedo).
DOME_SUPERSAMPLE = 2


def _check_level(level: object, levels: int) -> int:
    return as_int(level, "level", lo=0, hi=levels - 1)


class DomeAsset:
    """One mesh's views over the hemisphere, relightable (module docstring).

    Build one with :func:`bake_dome` or :meth:`load`.

    Parameters
    ----------
    record : DomeRecord
        The stored data.

    Attributes
    ----------
    name, mesh_hash, appearance, source_up
        As :class:`~.asset.BillboardAsset`'s.
    dome : ViewDome
    cameras : DomeCameras
    levels : int
    """

    def __init__(self, record: DomeRecord) -> None:
        if not isinstance(record.name, str) or not record.name:
            raise ValidationError(expected_got("name", "a non-empty string", repr(record.name)))
        self.name = record.name
        self.mesh_hash = record.mesh_hash
        self.appearance = check_appearance(record.appearance)
        self.source_up = check_source_up(record.source_up)
        self.dome = ViewDome(tuple((e, k) for e, k in record.rings), bool(record.top))  # it checks them
        self.cameras = DomeCameras(np.asarray(record.pivot, np.float64), record.distance, record.radius,
                                   (record.size, record.size))
        self.levels = as_int(record.levels, "levels", lo=1)
        if min(self.cameras.level_shape(self.levels - 1)) < 8:
            raise ValidationError(expected_got("levels", "levels whose smallest image is >= 8 px",
                                               f"{self.levels} levels of {self.cameras.shape}"))
        v, n = self.dome.views, record.size
        if record.rgba.shape != (v, n, n, 4):
            raise ValidationError(expected_got("rgba", f"({v}, {n}, {n}, 4) for the dome's {v} views",
                                               record.rgba.shape))
        self._record = record
        self._stored = [StoredSurface(record.rgba[k], record.normal[k],
                                      (record.depth[k].astype(np.float32) + np.float32(record.distance)))
                        for k in range(v)]
        self._levels: Memo[tuple[int, int], ViewSurface] = Memo()
        self._cams: Memo[tuple[int, int], CameraModel] = Memo()
        self._front = int(np.flatnonzero((self.dome.azimuths_deg() == 0.0)
                                         & (self.dome.elevations_deg() == self.dome.rings[0][0]))[0])

    # ------------------------------------------------------------------ data
    @property
    def size(self) -> tuple[int, int]:
        """``(n, n)`` of the level-0 images."""
        return self.cameras.shape

    @property
    def half_extent(self) -> tuple[float, float]:
        """Half size of the square quad, scene units."""
        return self.cameras.half_extent

    @property
    def pivot(self) -> np.ndarray:
        """``(3,)`` quad centre, object frame."""
        return self.cameras.pivot

    @property
    def memory_bytes(self) -> int:
        """Bytes of the views at every pyramid level at :data:`~morphkit.views.gbuffer.BYTES_PER_PIXEL`
        (what a texture memory holds; the file stores level 0 and the levels are made on
        load), counted as :attr:`~.impostor.OctahedralImpostor.memory_bytes` counts its frames."""
        px = sum(int(np.prod(self.cameras.level_shape(lv))) for lv in range(self.levels))
        return self.dome.views * px * BYTES_PER_PIXEL

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
        return self.cameras.level_shape(_check_level(level, self.levels))

    def camera(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> CameraModel:
        """The camera of the surface shown for a direction (the elevation clamped by the dome).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame.
        level : int, optional
            Pyramid level.

        Returns
        -------
        CameraModel
            Object frame (render the mesh with it for a ground truth).
        """
        level = _check_level(level, self.levels)
        return self.cameras.camera(azimuth_deg, self.dome.clamp(elevation_deg), level)

    def reference_surface(self, k: int, level: int = 0) -> ViewSurface:
        """View ``k`` at ``level`` (shared, do not modify).

        Parameters
        ----------
        k : int
            View index.
        level : int, optional
            Pyramid level.

        Returns
        -------
        ViewSurface
            The view's surface in its own camera's frame.
        """
        k = as_int(k, "view index k", lo=0, hi=self.dome.views - 1)
        level = _check_level(level, self.levels)

        def make() -> ViewSurface:
            if level == 0:
                return decode_surface(self._stored[k])
            return downsample_surface(self.reference_surface(k, 0), self.cameras.level_shape(level))
        return self._levels.get((k, level), make)

    def reference_camera(self, k: int, level: int = 0) -> CameraModel:
        """The camera of view ``k`` at ``level``.

        Parameters
        ----------
        k : int
            View index.
        level : int, optional
            Pyramid level.

        Returns
        -------
        CameraModel
            Object frame.
        """
        k = as_int(k, "view index k", lo=0, hi=self.dome.views - 1)
        level = _check_level(level, self.levels)
        az, el = self.dome.azimuths_deg()[k], self.dome.elevations_deg()[k]
        return self._cams.get((k, level), lambda: self.cameras.camera(az, el, level))

    # ------------------------------------------------------------------ images
    def surface(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> ViewSurface:
        """The surface seen from a direction: its three views morphed with depth.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame (elevation clamped: :meth:`ViewDome.clamp`).
        level : int, optional
            Pyramid level.

        Returns
        -------
        ViewSurface
            New arrays, in the frame of :meth:`camera`; exactly the view at a view's direction.
        """
        level = _check_level(level, self.levels)
        views, weights = self.dome.weights(azimuth_deg, elevation_deg)
        used = [(int(k), float(w)) for k, w in zip(views, weights, strict=True) if w > 0]
        target = self.camera(azimuth_deg, elevation_deg, level)
        if len(used) == 1:  # at a view's direction: the view itself (turned about its axis at the top)
            k = used[0][0]
            ref = self.reference_surface(k, level)
            if self._same_frame(k, azimuth_deg, elevation_deg):
                return ViewSurface(ref.albedo.copy(), ref.normal.copy(), ref.depth.copy())
            if self.dome.elevations_deg()[k] == 90.0:
                return plane_warp(target, self.reference_camera(k, level), self.pivot, ref)
        return morph_views(target, self.pivot, self.cameras.radius,
                           [(self.reference_camera(k, level), self.reference_surface(k, level), w)
                            for k, w in used])

    def _same_frame(self, k: int, azimuth_deg: float, elevation_deg: float) -> bool:
        a, e = self.dome.azimuths_deg()[k], self.dome.elevations_deg()[k]
        ce = self.dome.clamp(elevation_deg)
        da = ((azimuth_deg - a) + 180.0) % 360.0 - 180.0
        return bool(abs(ce - e) <= tol.REL_EQUAL and abs(da) <= tol.REL_EQUAL)

    def nearest_surface(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> ViewSurface:
        """Baseline: the view of the largest weight drawn on its card (the plane through the
        pivot facing it), seen from the direction: an impostor that switches frames.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame.
        level : int, optional
            Pyramid level.

        Returns
        -------
        ViewSurface
            New arrays, in the frame of :meth:`camera`.
        """
        views, weights = self.dome.weights(azimuth_deg, elevation_deg)
        k = int(views[int(np.argmax(weights))])
        return plane_warp(self.camera(azimuth_deg, elevation_deg, level), self.reference_camera(k, level),
                          self.pivot, self.reference_surface(k, level))

    def crossfade_surface(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> ViewSurface:
        """Baseline: the three views on their cards blended by weight (premultiplied; normals
        renormalised, depth the nearest): an impostor's blend without parallax.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame.
        level : int, optional
            Pyramid level.

        Returns
        -------
        ViewSurface
            New arrays, in the frame of :meth:`camera`.
        """
        views, weights = self.dome.weights(azimuth_deg, elevation_deg)
        target = self.camera(azimuth_deg, elevation_deg, level)
        surfs = [(plane_warp(target, self.reference_camera(int(k), level), self.pivot,
                             self.reference_surface(int(k), level)), float(w))
                 for k, w in zip(views, weights, strict=True) if w > 0]
        albedo = sum(w * s.albedo for s, w in surfs)
        normal = sum(w * s.albedo[..., 3:] * s.normal for s, w in surfs)
        norm = np.linalg.norm(normal, axis=-1, keepdims=True)
        normal = np.where(norm > 0, normal / np.maximum(norm, np.float32(tol.ALPHA_FLOOR)), 0.0)
        depth = np.min(np.stack([s.depth for s, _ in surfs]), axis=0)
        return ViewSurface(np.asarray(albedo, np.float32), normal.astype(np.float32),
                           depth.astype(np.float32))

    def classic_surface(self, level: int = 0) -> ViewSurface:
        """Baseline: the front view (azimuth 0, lowest ring) for every direction (shared).

        Parameters
        ----------
        level : int, optional
            Pyramid level.

        Returns
        -------
        ViewSurface
            The front view.
        """
        return self.reference_surface(self._front, level)

    # ------------------------------------------------------------------ meshes and files
    def items(self, mesh: trimesh.Trimesh) -> list[Item]:
        """The render items of ``mesh`` in this asset's look: the ground truth of its billboards.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The mesh the asset was baked from.

        Returns
        -------
        list of Item
            Object frame, identity pose.

        Raises
        ------
        MeshError
            Not a Trimesh.
        ValidationError
            Another mesh or look (the message names both hashes).
        """
        if not isinstance(mesh, trimesh.Trimesh):
            raise MeshError(expected_got("mesh", "a trimesh.Trimesh", type(mesh).__name__))
        want = mesh_hash(mesh, self.appearance)
        if want != self.mesh_hash:
            raise ValidationError(expected_got(f"mesh of dome asset {self.name!r}",
                                               f"the mesh it was baked from (hash {self.mesh_hash})",
                                               f"a mesh of hash {want}"))
        return bake_items(normalize(mesh), self.appearance)

    def record(self) -> DomeRecord:
        """The stored data (what :meth:`save` writes).

        Returns
        -------
        DomeRecord
            The asset's data.
        """
        return self._record

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the asset to one versioned ``.npz`` (:mod:`.domefile`), atomically.

        Parameters
        ----------
        path : str or os.PathLike
            Output file; its folder must exist.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        return write_dome(path, self._record)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> DomeAsset:
        """Read an asset written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            The file.

        Returns
        -------
        DomeAsset
            The asset.

        Raises
        ------
        FileFormatError
            See :func:`~.domefile.read_dome` (a version-2 ring asset: re-bake), or contents
            that do not make an asset.
        """
        rec = read_dome(path)
        try:
            return cls(rec)
        except (ValidationError, GeometryError) as exc:
            raise FileFormatError(expected_got(f"dome asset {Path(path).name}", "consistent contents",
                                               str(exc))) from exc


def bake_dome(mesh: trimesh.Trimesh, renderer: PassRenderer, *, name: str = "asset",
              dome: ViewDome | None = None, size: int = 128, levels: int = 3,
              distance_factor: float = DISTANCE_FACTOR, appearance: str = "own",
              source_up: str | None = None) -> DomeAsset:
    """Render ``mesh``'s views over the hemisphere (module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh; normalised first (:func:`morphkit.meshes.normalize`).
    renderer : PassRenderer
        Draws the views' passes (:class:`morphkit.protocols.PassRenderer`, e.g.
        :class:`morphkit.render.Renderer`).
    name : str
        The asset's name.
    dome : ViewDome, optional
        The views (default :class:`ViewDome` ``()``).
    size : int
        Level-0 image side, pixels.
    levels : int
        Pyramid levels (the smallest >= 8 px).
    distance_factor : float
        Camera distance in bounding radii (:data:`~morphkit.views.framing.DISTANCE_FACTOR`).
    appearance : {"own", "checker"}
        The look (:func:`~.bakelook.bake_items`).
    source_up : {"z", "y"} or None
        Up axis the mesh file was loaded with, recorded.

    Returns
    -------
    DomeAsset
        The asset.

    Raises
    ------
    ValidationError
        Bad arguments.
    MeshError
        Not a usable mesh.
    DegenerateViewError
        A view sees too little of the object to be morphed (named with its neighbours).
    """
    if not isinstance(name, str) or not name:
        raise ValidationError(expected_got("name", "a non-empty string", repr(name)))
    dome = ViewDome() if dome is None else dome
    if not isinstance(dome, ViewDome):
        raise ValidationError(expected_got("dome", "a ViewDome", type(dome).__name__))
    size = as_int(size, "size", lo=8, hi=tol.MAX_BILLBOARD_SIDE)
    appearance = check_appearance(appearance)
    source_up = check_source_up(source_up)
    norm = normalize(mesh)
    digest = mesh_hash(norm, appearance)
    cams = DomeCameras.fit(norm, size, distance_factor=distance_factor)
    items, lights = bake_items(norm, appearance), bake_lights()
    az, el = dome.azimuths_deg(), dome.elevations_deg()
    stored = []
    for k in range(dome.views):
        p = renderer.source_passes(cams.camera(az[k], el[k]), items, lights, ambient=BAKE_AMBIENT,
                                   supersample=DOME_SUPERSAMPLE)
        covered = int(np.count_nonzero(np.isfinite(p.depth)))
        if covered < tol.BB_MIN_CORRESPONDENCES:
            tris = dome.triangles()
            nb = sorted({int(j) for t in tris if k in t for j in t if j != k})
            raise DegenerateViewError(expected_got(
                f"dome view {k} (azimuth {az[k]:g}, elevation {el[k]:g} deg) of {name!r}",
                f"at least {tol.BB_MIN_CORRESPONDENCES} object pixels to morph with its neighbours "
                f"{nb} (tol.BB_MIN_CORRESPONDENCES)", f"{covered} (the object is edge-on or outside it)"))
        a8 = np.clip(np.rint(p.alpha * 255), 0, 255).astype(np.uint8)
        rgba = np.concatenate([p.albedo, a8[..., None]], axis=2)
        stored.append(encode_surface(rgba, p.normal, p.depth))
    record = DomeRecord(
        name=name, mesh_hash=digest, appearance=appearance, source_up=source_up,
        rings=[[float(e), int(k)] for e, k in dome.rings], top=dome.top, pivot=cams.pivot.tolist(),
        distance=cams.distance, radius=cams.radius, size=size, levels=levels,
        rgba=np.stack([s.rgba for s in stored]), normal=np.stack([s.normal for s in stored]),
        depth=np.stack([(s.depth.astype(np.float32) - np.float32(cams.distance)) for s in stored]
                       ).astype(np.float16))
    return DomeAsset(record)
