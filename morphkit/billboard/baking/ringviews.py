"""The bake: render a mesh's reference views on a ring and prepare every pair's morph.

:func:`bake_asset` normalises the mesh (keeping its look), fits the camera rule
(:meth:`~morphkit.billboard.cameras.QuadCameras.fit`), renders each reference
view (premultiplied RGBA and linear depth) with :func:`~morphkit.billboard.baking.bakelook.bake_items` (in the
asset's appearance: the mesh's own look by default, or the 3-D checker) under
:func:`~morphkit.billboard.baking.bakelook.bake_lights`, renders the front view when no reference is at
azimuth 0, and, for each pair of neighbouring references, the dense
correspondences from their depth (:func:`~morphkit.viewmorph.from_depth`) plus
each view's outline points (:data:`RIM_STEP`). The result is one
:class:`~.assetfile.AssetRecord` turned into a :class:`~.asset.BillboardAsset`
whose level-0 morphers are built now, so a pair that cannot be morphed is
refused at bake time (see :mod:`.asset` for the morph itself).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import trimesh

from ... import tol
from ...camera import CameraModel
from ...errors import DegenerateViewError, ValidationError, expected_got
from ...meshes import normalize
from ...protocols import SceneRenderer
from ...viewmorph import from_depth
from ..asset import (
    BAKE_AMBIENT,
    DEFAULT_LAYERS,
    BillboardAsset,
    bake_items,
    bake_lights,
    check_appearance,
    check_levels,
    check_source_up,
    mesh_hash,
)
from ..cameras import DISTANCE_FACTOR, QuadCameras
from ..formats.assetfile import AssetRecord
from ..ring import ViewRing

__all__ = ["bake_asset", "RIM_STEP"]

#: Outline ("rim") points of each reference are kept in its pairs' correspondences even
#: where the other view does not see them (:func:`~morphkit.viewmorph.from_depth` with
#: ``rtol=inf``), every ``RIM_STEP`` times the outline spacing of the shared points: they
#: carry each view's silhouette along its geometric motion, where the shared points alone
#: leave it to the mesh's interpolation (a half-transparent halo at the outline). Denser
#: rims fold over more and cost bake time for no gain (``morphkit bench billboards``).
RIM_STEP = 4


def _sampling(shape: tuple[int, int]) -> tuple[int, int]:
    """``(step, contour_step)`` of :func:`from_depth` for views of ``shape``: the
    bench's 6 and 2 at 256^2, scaled with the image (so the pairs cover the object alike)."""
    side = min(shape)
    return max(2, round(6 * side / 256)), max(1, round(2 * side / 256))


def _camera_dict(azimuth_deg: float, cam: CameraModel) -> dict[str, Any]:
    return {"azimuth_deg": float(azimuth_deg), "K": cam.K.tolist(), "cam2world": cam.cam2world.tolist()}


def bake_asset(mesh: trimesh.Trimesh, renderer: SceneRenderer, *, name: str = "asset", views: int = 2,
               size: int | tuple[int, int] = 256, arc_deg: float | None = None, elevation_deg: float = 10.0,
               levels: int = 3, layers: int | str = DEFAULT_LAYERS, distance_factor: float = DISTANCE_FACTOR,
               progress: bool = False, appearance: str = "own", source_up: str | None = None
               ) -> BillboardAsset:
    """Render ``mesh``'s reference views and prepare every pair's morph (see the module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh; it is normalised (:func:`morphkit.meshes.normalize`) first: the
        asset's object frame is the normalised mesh's.
    renderer : SceneRenderer
        E.g. :class:`morphkit.render.Renderer`.
    name : str
        The asset's name (cache keys, file names).
    views : int
        ``K >= 2`` (:class:`ViewRing`); ``K = 1`` is refused (the classic billboard
        needs no bake: :meth:`BillboardAsset.classic` of any asset).
    size : int or (H, W)
        Level-0 image shape (an int: square).
    arc_deg : float, optional
        ``K = 2``: angle between the two views (default 60: +-30 degrees). Leave out for ``K >= 3``.
    elevation_deg : float
        Camera elevation, degrees.
    levels : int
        Pyramid levels (each half the resolution of the one before; the smallest >= 8 px).
    layers : int or "auto"
        Depth layers of the morphs (``ViewMorpher(layers=...)``).
    distance_factor : float
        Reference cameras' distance from the pivot in radii of the mesh's bounding
        sphere (:data:`~morphkit.views.framing.DISTANCE_FACTOR`): about the distance
        the scene sees the asset from, so the views have its perspective.
    progress : bool
        Show a progress bar (tqdm; silent when not a terminal).
    appearance : {"own", "checker"}
        The look of the references and morphs (:func:`~.bakelook.bake_items`): ``"own"``
        (default) the mesh's own look (textures, vertex/face colours, cut-outs;
        :data:`~morphkit.conventions.DEFAULT_COLOR` when it has none), ``"checker"``
        morphkit's 3-D checker (texture for matching and PSNR). Recorded in the asset
        and covered by its :func:`~morphkit.billboard.baking.bakelook.mesh_hash`.
    source_up : {"z", "y"} or None
        The up axis the mesh file was loaded with (:func:`morphkit.meshes.resolve_up`),
        recorded in the asset file; None (default) when not known.

    Returns
    -------
    BillboardAsset
        With every pair's level-0 morpher built (the rest on first use or by ``prepare()``).

    Raises
    ------
    ValidationError
        Bad arguments (``K = 1`` included).
    MeshError
        ``mesh`` is not a usable mesh.
    DegenerateViewError
        A pair of neighbouring views shares fewer than :data:`tol.BB_MIN_CORRESPONDENCES`
        correspondences even when sampled at every pixel (the fallback when the image's
        spacing gives too few), or cannot be morphed (F, pre-warp); the message names the pair.
    """
    from tqdm import tqdm

    ring = ViewRing(views, arc_deg, elevation_deg)
    shape = (size, size) if isinstance(size, (int, np.integer)) and not isinstance(size, bool) else size
    if not isinstance(name, str) or not name:
        raise ValidationError(expected_got("name", "a non-empty string", repr(name)))
    appearance = check_appearance(appearance)
    source_up = check_source_up(source_up)
    norm = normalize(mesh)
    digest = mesh_hash(norm, appearance)
    az = ring.azimuths_deg()
    cams = QuadCameras.fit(norm, shape, ring.elevation_deg, az, distance_factor=distance_factor)
    check_levels(levels, cams)
    items, lights = bake_items(norm, appearance), bake_lights()
    front_view = next((k for k in range(ring.views) if az[k] == 0.0), -1)
    pairs = ring.pairs()
    bar = tqdm(total=ring.views + (front_view < 0) + len(pairs) + 1, desc=f"baking billboard {name}",
               unit="step", disable=None if progress else True, leave=False)
    try:
        images, depths = [], []
        for a in az:
            cam = cams.camera(a)
            images.append(renderer.source_view(cam, items, lights, ambient=BAKE_AMBIENT))
            depths.append(renderer.depth(cam, items))
            bar.update()
        if front_view < 0:
            front = renderer.source_view(cams.camera(0.0), items, lights, ambient=BAKE_AMBIENT)
            bar.update()
        else:
            front = np.zeros((0, 0, 4), np.uint8)
        step, contour_step = _sampling(cams.shape)
        points = []
        for i, j in pairs:
            ci, cj = cams.camera(az[i]), cams.camera(az[j])
            corr = from_depth(ci, cj, depths[i], depths[j], step=step, contour_step=contour_step,
                              rtol=tol.BB_VISIBILITY_RADII / distance_factor)
            if len(corr) < tol.BB_MIN_CORRESPONDENCES and (step, contour_step) != (1, 1):
                # too few pairs at the image's spacing (a small or thin object): every pixel
                corr = from_depth(ci, cj, depths[i], depths[j], step=1, contour_step=1,
                                  rtol=tol.BB_VISIBILITY_RADII / distance_factor)
            if len(corr) < tol.BB_MIN_CORRESPONDENCES:
                raise DegenerateViewError(expected_got(
                    f"billboard pair {(i, j)} (azimuths {az[i]:g}, {az[j]:g} deg) of {name!r}",
                    f"at least {tol.BB_MIN_CORRESPONDENCES} correspondences (tol.BB_MIN_CORRESPONDENCES) "
                    "between the two views", len(corr)))
            rim = from_depth(ci, cj, depths[i], depths[j], step=0, contour_step=RIM_STEP * contour_step,
                             rtol=np.inf)
            assert corr.points3d is not None and rim.points3d is not None
            points.append(np.concatenate([corr.points3d, rim.points3d]).astype(np.float32))
            bar.update()
        record = AssetRecord(
            name=name, mesh_hash=digest,
            ring={"views": ring.views, "arc_deg": ring.arc_deg, "elevation_deg": ring.elevation_deg},
            quad={"pivot": cams.pivot.tolist(), "distance": cams.distance,
                  "elevation_deg": cams.elevation_deg, "half_extent": list(cams.half_extent),
                  "shape": list(cams.shape)},
            levels=levels, layers=layers, pairs=pairs, front_view=front_view,
            cameras=[_camera_dict(a, cams.camera(a)) for a in az],
            images=np.stack(images), depth=np.stack(depths).astype(np.float16),
            points3d=np.concatenate(points),
            offsets=np.cumsum([0] + [len(p) for p in points]).astype(np.int64),
            front=front, appearance=appearance, source_up=source_up)
        asset = BillboardAsset(record).prepare(levels=[0])
        bar.update()
    finally:
        bar.close()
    return asset
