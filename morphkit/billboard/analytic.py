"""An analytic sphere as a dome asset: views computed exactly, no GL.

:func:`sphere_view` ray-casts a coloured sphere (its albedo varies with latitude and
longitude, so a misplaced pixel shows) from any camera: albedo, coverage, normals and
depth, exactly. :func:`sphere_dome_asset` builds a :class:`~.domeasset.DomeAsset` from
such views, the same data a bake of a sphere mesh would store: the ground truth of the
dome's tests, and a relightable asset for examples that need no renderer;
:func:`sphere_impostor` the octahedral impostor of its frames alike.
"""

from __future__ import annotations

import numpy as np

from ..camera import CameraModel
from ..views.dome import ViewDome
from ..views.domecameras import DomeCameras
from ..views.gbuffer import encode_surface
from .domeasset import DomeAsset
from .formats.domefile import DomeRecord
from .impostor import OctahedralImpostor, frame_grid_uv, hemi_oct_decode

__all__ = ["SPHERE_PIVOT", "SPHERE_RADIUS", "sphere_view", "sphere_dome_asset", "sphere_impostor"]

#: Centre of the analytic sphere (object frame) and the pivot of its asset.
SPHERE_PIVOT = np.array([0.0, 0.0, 1.0])
#: Radius of the analytic sphere; its asset's bounding radius is 1 (a margin about it).
SPHERE_RADIUS = 0.6
_BOUND = 1.0
_DISTANCE = 12.0


def sphere_view(camera: CameraModel) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The sphere seen by ``camera`` (object frame).

    Parameters
    ----------
    camera : CameraModel
        Any camera.

    Returns
    -------
    rgba : (H, W, 4) uint8
        Straight sRGB albedo, alpha 255 on the sphere (one sample a pixel).
    normal : (H, W, 3) float32
        Unit normals, 0 off the sphere.
    depth : (H, W) float32
        Depth along the camera axis, ``+inf`` off the sphere.
    hit : (H, W) bool
        Pixels whose centre's ray meets the sphere.
    """
    o, d = camera.rays()
    oc = o - SPHERE_PIVOT
    b = np.einsum("ijk,ijk->ij", d, oc)
    c = np.einsum("ijk,ijk->ij", oc, oc) - SPHERE_RADIUS**2
    disc = b * b - c
    hit = disc > 0
    t = np.where(hit, -b - np.sqrt(np.where(hit, disc, 0.0)), np.inf)
    p = o + np.where(hit, t, 0.0)[..., None] * d
    n = np.where(hit[..., None], (p - SPHERE_PIVOT) / SPHERE_RADIUS, 0.0)
    depth = np.where(hit, (p - camera.cam2world[:3, 3]) @ camera.cam2world[:3, 2], np.inf)
    lon = np.arctan2(n[..., 1], n[..., 0])
    rgb = np.stack([0.5 + 0.4 * np.sin(3 * lon), 0.5 + 0.4 * n[..., 2], 0.5 + 0.2 * np.cos(2 * lon)], -1)
    rgba = np.zeros(camera.shape + (4,), np.uint8)
    rgba[..., :3] = np.where(hit[..., None], np.rint(255 * rgb), 0).astype(np.uint8)
    rgba[..., 3] = np.where(hit, 255, 0)
    return rgba, n.astype(np.float32), depth.astype(np.float32), hit


def sphere_dome_asset(dome: ViewDome | None = None, size: int = 48, levels: int = 2,
                      name: str = "ball") -> DomeAsset:
    """A :class:`DomeAsset` of the analytic sphere.

    Parameters
    ----------
    dome : ViewDome, optional
        The views (default :class:`ViewDome` ``()``).
    size : int
        Level-0 image side.
    levels : int
        Pyramid levels.
    name : str
        Asset name.

    Returns
    -------
    DomeAsset
        Pivot :data:`SPHERE_PIVOT`, bounding radius 1, camera distance 12.

    Examples
    --------
    >>> from morphkit.billboard.analytic import sphere_dome_asset
    >>> asset = sphere_dome_asset(size=16, levels=1)
    >>> asset.dome.views, asset.surface(20.0, 45.0).shape
    (27, (16, 16))
    """
    dome = ViewDome() if dome is None else dome
    cams = DomeCameras(SPHERE_PIVOT, _DISTANCE, _BOUND, (size, size))
    az, el = dome.azimuths_deg(), dome.elevations_deg()
    stored = [encode_surface(*sphere_view(cams.camera(az[k], el[k]))[:3]) for k in range(dome.views)]
    rec = DomeRecord(name=name, mesh_hash="0" * 64, appearance="own", source_up=None,
                     rings=[[e, k] for e, k in dome.rings], top=dome.top, pivot=SPHERE_PIVOT.tolist(),
                     distance=_DISTANCE, radius=_BOUND, size=size, levels=levels,
                     rgba=np.stack([s.rgba for s in stored]), normal=np.stack([s.normal for s in stored]),
                     depth=np.stack([s.depth.astype(np.float32) - _DISTANCE
                                     for s in stored]).astype(np.float16))
    return DomeAsset(rec)


def sphere_impostor(frames: int = 8, size: int = 32, name: str = "ball") -> OctahedralImpostor:
    """The octahedral impostor of the analytic sphere, its frames ray-cast (one mip level).

    Parameters
    ----------
    frames : int
        Frames a side of the hemi-octahedral grid.
    size : int
        Each frame's side, pixels.
    name : str
        Asset name.

    Returns
    -------
    OctahedralImpostor
        About :data:`SPHERE_PIVOT`, bounding radius 1, camera distance 12 (as
        :func:`sphere_dome_asset`).

    Examples
    --------
    >>> from morphkit.billboard.analytic import sphere_impostor
    >>> imp = sphere_impostor(frames=4, size=16)
    >>> imp.frames, imp.frame_side
    (4, 16)
    """
    cams = DomeCameras(SPHERE_PIVOT, _DISTANCE, _BOUND, (size, size))
    d = hemi_oct_decode(frame_grid_uv(frames).reshape(-1, 2))
    horiz = np.hypot(d[:, 0], d[:, 1])
    az = np.where(horiz > 0, np.degrees(np.arctan2(d[:, 1], d[:, 0])), 0.0)
    el = np.degrees(np.arctan2(d[:, 2], horiz))
    stored = [encode_surface(*sphere_view(cams.ortho_camera(a, e, (size, size)))[:3])
              for a, e in zip(az, el, strict=True)]
    return OctahedralImpostor.from_stored(name, cams, frames, stored, levels=1)
