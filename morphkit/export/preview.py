"""What a preview page shows: its camera and sun, and the data it draws them from.

A :class:`PreviewView` is the page's camera and sun: an orbit camera about a target (azimuth,
elevation, distance, vertical field of view) and a sun (azimuth, elevation), as the page's URL
fragment says them (:meth:`PreviewView.fragment`, e.g.
``#camera=30,25,3.5&fov=40&sun=120,45&size=480x360``). :meth:`PreviewView.camera` is the camera
morphkit renders the same view with (:mod:`morphkit.export.previewref`).

:func:`asset_entry` packs one dome asset, its sun atlas and its instances as the page reads them:
the views as stored (zlib-compressed, in base64; straight sRGB albedo and coverage,
``round(127 n) + 128`` normals, float16 depth offsets from the views' distance, ``+inf`` written
as float16's largest value 65504), each view's camera (object frame), the dome's triangles with
their barycentric inverses, and ``(x, y, z, yaw_deg, scale)`` per instance. :func:`preview_data`
is the page's whole data, :func:`write_preview` writes the page
(:func:`morphkit.export.page.page_html`) atomically.

Convention
----------
The world is ``+z`` up, cameras are OpenCV's (:mod:`morphkit.conventions`). Directions
``d(a, e)`` are :func:`morphkit.views.domecameras.direction`'s: from the target towards the eye
or the sun. The page draws the ground plane ``z = 0`` in :data:`GROUND_ALBEDO` (linear) under the
lighting ``Lighting(BAKE_AMBIENT, (sun(a, e),))`` and the sky in :data:`SKY` (encoded).
"""

from __future__ import annotations

import base64
import dataclasses
import math
import os
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import tol
from ..billboard.baking.bakelook import BAKE_AMBIENT
from ..billboard.domeasset import DomeAsset
from ..billboard.impostor import OctahedralImpostor
from ..camera import CameraModel, look_at
from ..errors import ValidationError, expected_got
from ..files.fileio import write_text
from ..files.outfolder import check_output_file
from ..sunlit.sunatlas import SunAtlas
from ..sunpath import SUN_INTENSITY
from ..views.depthmorph import DEPTH_AGREE_STEPS, REFINE_STEPS, THICKNESS_STEPS
from ..views.dome import ViewDome
from ..views.domecameras import direction
from ..views.gbuffer import BYTES_PER_PIXEL
from .page import page_html

__all__ = ["PreviewView", "asset_entry", "preview_data", "write_preview", "GROUND_ALBEDO", "SKY",
           "PREVIEW_VERSION", "SHADOW_MAX_TEXELS",
           "check_preview_output", "drawn_bounds", "impostor_entry"]

#: The page data's version (``morphkit_preview``).
PREVIEW_VERSION = 1
#: The ground's linear albedo.
GROUND_ALBEDO = (0.30, 0.30, 0.24)
#: The sky's encoded colour (where a ray misses the ground).
SKY = (0.62, 0.72, 0.84)
#: The largest side of the page's sun shadow map, texels (WebGL's textures are at least 4096).
SHADOW_MAX_TEXELS = 2048
#: float16's largest finite value: the page's "empty" depth texel.
_EMPTY_HALF = np.float16(65504.0)


@dataclass(frozen=True)
class PreviewView:
    """The page's camera and sun (module docstring).

    Parameters
    ----------
    azimuth_deg, elevation_deg : float
        The camera's direction from the target, degrees (elevation in ``[-89, 89]``).
    distance : float
        From the target, scene units (> 0).
    fov_deg : float
        Vertical field of view, degrees in ``(0, 170)``.
    sun_azimuth_deg, sun_elevation_deg : float
        Towards the sun, degrees (elevation ``<= 0``: no sun, ambient light only).
    width, height : int
        The image, pixels.
    """

    azimuth_deg: float = 30.0
    elevation_deg: float = 20.0
    distance: float = 3.0
    fov_deg: float = 40.0
    sun_azimuth_deg: float = 135.0
    sun_elevation_deg: float = 45.0
    width: int = 640
    height: int = 480

    def __post_init__(self) -> None:
        for name in ("azimuth_deg", "elevation_deg", "distance", "fov_deg", "sun_azimuth_deg",
                     "sun_elevation_deg"):
            v = getattr(self, name)
            if not isinstance(v, int | float) or not math.isfinite(v):
                raise ValidationError(expected_got(name, "a finite number", repr(v)))
        if not -89.0 <= self.elevation_deg <= 89.0:
            raise ValidationError(expected_got("elevation_deg", "degrees in [-89, 89]", self.elevation_deg))
        if self.distance <= 0:
            raise ValidationError(expected_got("distance", "> 0", self.distance))
        if not 0.0 < self.fov_deg < 170.0:
            raise ValidationError(expected_got("fov_deg", "degrees in (0, 170)", self.fov_deg))
        for name in ("width", "height"):
            v = getattr(self, name)
            if not isinstance(v, int) or not 8 <= v <= tol.EXPORT_MAX_TEXTURE_SIDE:
                raise ValidationError(expected_got(name, f"an int in [8, {tol.EXPORT_MAX_TEXTURE_SIDE}]",
                                                   repr(v)))

    def fitted(self, reach: float) -> PreviewView:
        """This view with its distance set to see a sphere of radius ``reach`` about the target whole
        (its angles, sun and image kept).

        Parameters
        ----------
        reach : float
            The sphere's radius (> 0).

        Returns
        -------
        PreviewView
        """
        half = math.radians(0.5 * self.fov_deg) * min(1.0, self.width / self.height)
        return dataclasses.replace(self, distance=float(1.25 * reach / math.sin(half)))

    def fragment(self) -> str:
        """The page's URL fragment for this view (without ``#``).

        Returns
        -------
        str
        """
        def r(v: float) -> str:
            return f"{v:.3f}".rstrip("0").rstrip(".")
        return (f"camera={r(self.azimuth_deg)},{r(self.elevation_deg)},{r(self.distance)}"
                f"&fov={r(self.fov_deg)}"
                f"&sun={r(self.sun_azimuth_deg)},{r(self.sun_elevation_deg)}&size={self.width}x{self.height}")

    def eye(self, target: np.ndarray) -> np.ndarray:
        """The camera's centre, world frame.

        Parameters
        ----------
        target : (3,) float
            The point orbited.

        Returns
        -------
        (3,) float64
        """
        d = direction(self.azimuth_deg, self.elevation_deg)
        return np.asarray(target, np.float64) + self.distance * d

    def camera(self, target: np.ndarray) -> CameraModel:
        """The perspective camera of this view, as the page makes it.

        Parameters
        ----------
        target : (3,) float
            The point orbited.

        Returns
        -------
        CameraModel
            World frame; principal point at the image centre, square pixels.
        """
        target = np.asarray(target, np.float64)
        f = 0.5 * self.height / math.tan(math.radians(0.5 * self.fov_deg))
        pose = look_at(self.eye(target), target)
        return CameraModel("perspective", (self.height, self.width), f, f, (self.width - 1) / 2.0,
                           (self.height - 1) / 2.0, max(1e-3, 0.01 * self.distance), self.distance + 100.0,
                           pose)

    def sun_direction(self) -> np.ndarray:
        """Towards the sun, world frame (unit).

        Returns
        -------
        (3,) float64
        """
        return direction(self.sun_azimuth_deg, self.sun_elevation_deg)


def _b64(a: np.ndarray) -> str:
    """The array's bytes, zlib-compressed (the page inflates them with ``DecompressionStream``), in base64."""
    raw = np.ascontiguousarray(a).tobytes()
    return base64.b64encode(zlib.compress(raw, 6)).decode("ascii")


def _half_bits(depth: np.ndarray) -> np.ndarray:
    d = np.asarray(depth, np.float16)
    return np.where(np.isfinite(d), d, _EMPTY_HALF).astype(np.float16).view(np.uint16)


def _dome_json(dome: ViewDome) -> dict[str, Any]:
    tris = dome.triangles()
    inv = dome.barycentric_inverses()
    return {"rings": [list(r) for r in dome.rings], "top": dome.top,
            "azimuths": dome.azimuths_deg().tolist(), "triangles": tris.tolist(),
            "inverse": inv.reshape(len(tris), 9).tolist()}


def _camera_json(cam: CameraModel) -> dict[str, Any]:
    return {"R": cam.cam2world[:3, :3].reshape(-1).tolist(), "C": cam.cam2world[:3, 3].tolist()}


def drawn_bounds(cameras: list[CameraModel], depths: np.ndarray, pad: float) -> list[list[float]]:
    """The box holding every point the views draw (their depth maps unprojected), grown by ``pad``:
    where a ray misses it, no view can be hit, so the page draws no pixel there.

    Parameters
    ----------
    cameras : list of CameraModel
        The views' cameras (object frame).
    depths : (V, n, n) float
        Their linear depths, ``+inf`` where nothing is drawn.
    pad : float
        Added on every side (scene units).

    Returns
    -------
    list
        ``[[x0, y0, z0], [x1, y1, z1]]``; a box of side ``2 pad`` at the origin when nothing is drawn.
    """
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for cam, d in zip(cameras, depths, strict=True):
        pts, valid = cam.unproject(np.asarray(d, np.float32))
        ok = valid & np.isfinite(np.asarray(d))
        if ok.any():
            lo = np.minimum(lo, pts[ok].min(axis=0))
            hi = np.maximum(hi, pts[ok].max(axis=0))
    if not np.all(np.isfinite(lo)):
        lo, hi = np.zeros(3), np.zeros(3)
    return [(lo - pad).tolist(), (hi + pad).tolist()]


def _checked(sun_atlas: SunAtlas | None, instances: np.ndarray, side: int) -> np.ndarray:
    """The instances as float64 ``(N, 5)``, once the sun atlas and the views' side are checked."""
    if sun_atlas is not None and not isinstance(sun_atlas, SunAtlas):
        raise ValidationError(expected_got("sun_atlas", "a SunAtlas or None", type(sun_atlas).__name__))
    inst = np.asarray(instances, np.float64)
    if inst.ndim != 2 or inst.shape[1] != 5 or not np.all(np.isfinite(inst)) or np.any(inst[:, 4] <= 0):
        raise ValidationError(expected_got("instances", "(N, 5) finite (x, y, z, yaw_deg, scale), scales > 0",
                                           f"shape {inst.shape}"))
    limit = tol.EXPORT_MAX_TEXTURE_SIDE
    if side > limit or (sun_atlas is not None and sun_atlas.size > limit):
        big = max(side, 0 if sun_atlas is None else sun_atlas.size)
        raise ValidationError(expected_got("views", f"sides of at most {limit} px (WebGL's texture limit "
                                           "morphkit writes to)", f"{big} px"))
    return inst


def _add_sun_atlas(entry: dict[str, Any], sun_atlas: SunAtlas | None) -> None:
    """``entry["sun_atlas"]``: the atlas as the page reads it (or None), its bytes counted."""
    entry["sun_atlas"] = None
    if sun_atlas is None:
        return
    sc = sun_atlas.view_camera(0)
    scams = [sun_atlas.view_camera(k) for k in range(sun_atlas.dome.views)]
    sdepth = sun_atlas.depth.astype(np.float32) + np.float32(sun_atlas.cameras.distance)
    entry["sun_atlas"] = {
        "size": sun_atlas.size, "distance": float(sun_atlas.cameras.distance),
        "radius": float(sun_atlas.cameras.radius), "pivot": sun_atlas.cameras.pivot.tolist(),
        "half_extent": float(sun_atlas.cameras.half_extent[0]), "fx": float(sc.fx), "fy": float(sc.fy),
        "c": float(sc.cx), "dome": _dome_json(sun_atlas.dome),
        "views": [_camera_json(c) for c in scams],
        "bounds": drawn_bounds(scams, sdepth, 2.0 / sc.fx),
        "depth": _b64(_half_bits(sun_atlas.depth)), "coverage": _b64(sun_atlas.coverage),
    }
    entry["texture_bytes"] += int(sun_atlas.depth.size * 2 + sun_atlas.coverage.nbytes)


def impostor_entry(impostor: OctahedralImpostor, sun_atlas: SunAtlas | None, instances: np.ndarray,
                   name: str | None = None) -> dict[str, Any]:
    """An octahedral impostor as the page reads it: its level-0 frames as stored (their depths
    along each frame's axis, not offsets), each frame's direction and axes, and what
    :func:`asset_entry` gives of an asset.

    Parameters
    ----------
    impostor : OctahedralImpostor
        The frames (level 0).
    sun_atlas : SunAtlas or None
        Its asset's sun atlas (None: no shadow).
    instances : (N, 5) float
        ``(x, y, z, yaw_deg, scale)`` per instance, world frame.
    name : str, optional
        Shown on the page (default the impostor's).

    Returns
    -------
    dict
        JSON values (``kind``: ``"impostor"``).

    Raises
    ------
    ValidationError
        As :func:`asset_entry`.
    """
    if not isinstance(impostor, OctahedralImpostor):
        raise ValidationError(expected_got("impostor", "an OctahedralImpostor", type(impostor).__name__))
    m, nf = int(impostor.frame_side), impostor.frames**2
    inst = _checked(sun_atlas, instances, m)
    stored = [impostor.stored_frame(k) for k in range(nf)]
    rgba = np.stack([f.rgba for f in stored])
    normal = np.zeros((nf, m, m, 4), np.uint8)
    normal[..., :3] = (np.stack([f.normal for f in stored]).astype(np.int16) + 128).astype(np.uint8)
    depth = np.stack([f.depth for f in stored])
    cams = [impostor.cameras.ortho_camera(float(az), float(el), (m, m)) for az, el in impostor.frame_angles]
    half = float(impostor.half_extent[0])
    axes = np.zeros((3, nf, 4), np.float32)
    axes[0, :, :3], axes[1, :, :3] = impostor.frame_dirs, impostor.frame_right
    axes[2, :, :3] = impostor.frame_up
    entry: dict[str, Any] = {
        "kind": "impostor", "name": name or impostor.name, "size": m, "frames": impostor.frames,
        "distance": float(impostor.distance), "radius": float(impostor.cameras.radius), "half_extent": half,
        "pivot": impostor.pivot.tolist(), "scale": m / (2.0 * half), "centre": (m - 1) / 2.0,
        "frame_axes": axes.reshape(-1).tolist(),
        "bounds": drawn_bounds(cams, depth.astype(np.float32), 4.0 * half / m),
        "rgba": _b64(rgba), "normal": _b64(normal), "depth": _b64(_half_bits(depth)),
        "instances": _b64(inst.astype(np.float32)), "count": int(len(inst)),
        "texture_bytes": int(rgba.nbytes + normal.nbytes + depth.size * 2),
        "view_bytes": int(nf * m * m * BYTES_PER_PIXEL),
    }
    _add_sun_atlas(entry, sun_atlas)
    return entry


def asset_entry(asset: DomeAsset, sun_atlas: SunAtlas | None, instances: np.ndarray,
                name: str | None = None) -> dict[str, Any]:
    """One asset as the page reads it (module docstring).

    Parameters
    ----------
    asset : DomeAsset
        Its views (level 0).
    sun_atlas : SunAtlas or None
        Its sun atlas (None: it casts no shadow on the page, which says so).
    instances : (N, 5) float
        ``(x, y, z, yaw_deg, scale)`` per instance, world frame.
    name : str, optional
        Shown on the page (default the asset's).

    Returns
    -------
    dict
        JSON values.

    Raises
    ------
    ValidationError
        Not a dome asset or a sun atlas; instances not ``(N, 5)`` finite with scales > 0; views
        or a sun atlas past WebGL's texture side :data:`morphkit.tol.EXPORT_MAX_TEXTURE_SIDE`.
    """
    if not isinstance(asset, DomeAsset):
        raise ValidationError(expected_got("asset", "a DomeAsset", type(asset).__name__))
    n = int(asset.size[0])
    inst = _checked(sun_atlas, instances, n)
    rec = asset.record()
    normal = np.zeros((*rec.normal.shape[:3], 4), np.uint8)
    normal[..., :3] = (rec.normal.astype(np.int16) + 128).astype(np.uint8)
    cam0 = asset.reference_camera(0)
    cams = [asset.reference_camera(k) for k in range(asset.dome.views)]
    depths = rec.depth.astype(np.float32) + np.float32(asset.cameras.distance)
    texel = 2.0 * asset.half_extent[0] / n  # one texel at the pivot
    entry: dict[str, Any] = {
        "kind": "dome", "name": name or asset.name, "size": n, "distance": float(asset.cameras.distance),
        "radius": float(asset.cameras.radius), "half_extent": float(asset.half_extent[0]),
        "pivot": asset.pivot.tolist(), "f": float(cam0.fx),
        "c": float(cam0.cx), "dome": _dome_json(asset.dome),
        "views": [_camera_json(c) for c in cams], "bounds": drawn_bounds(cams, depths, 2.0 * texel),
        "rgba": _b64(rec.rgba), "normal": _b64(normal), "depth": _b64(_half_bits(rec.depth)),
        "instances": _b64(inst.astype(np.float32)), "count": int(len(inst)),
        "texture_bytes": int(rec.rgba.nbytes + normal.nbytes + rec.depth.size * 2),
        "view_bytes": int(asset.dome.views * n * n * BYTES_PER_PIXEL),
    }
    _add_sun_atlas(entry, sun_atlas)
    return entry


def preview_data(entries: list[dict[str, Any]], view: PreviewView, target: np.ndarray, reach: float, *,
                 title: str, measured: list[str] | None = None, notes: list[str] | None = None,
                 gltf: bytes | None = None, ground: bool = True) -> dict[str, Any]:
    """The page's data (module docstring).

    Parameters
    ----------
    entries : list of dict
        :func:`asset_entry` of each asset.
    view : PreviewView
        The page's first camera and sun (the URL fragment overrides them).
    target : (3,) float
        The point the camera orbits, world frame.
    reach : float
        The scene's radius about ``target`` (the camera's far plane).
    title : str
        The page's first line.
    measured : list of str, optional
        Lines of measured figures shown on the page.
    notes : list of str, optional
        Lines said on the page (e.g. an asset without a sun atlas).
    gltf : bytes, optional
        A GLB drawn as meshes (a file from another tool).
    ground : bool, optional
        Draw the ground plane.

    Returns
    -------
    dict
        JSON values.
    """
    notes = list(notes or [])
    for e in entries:
        if e["sun_atlas"] is None:
            notes.append(f"{e['name']}: no sun atlas, so it casts no shadow here")
    return {
        "morphkit_preview": PREVIEW_VERSION, "title": title,
        "camera": {"azimuth_deg": view.azimuth_deg, "elevation_deg": view.elevation_deg,
                   "distance": view.distance, "fov_deg": view.fov_deg},
        "sun": {"azimuth_deg": view.sun_azimuth_deg, "elevation_deg": view.sun_elevation_deg},
        "target": [float(v) for v in np.asarray(target, np.float64)], "reach": float(reach),
        "lighting": {"ambient": BAKE_AMBIENT, "sun_intensity": SUN_INTENSITY},
        "ground": {"albedo": list(GROUND_ALBEDO), "sky": list(SKY), "show": bool(ground)},
        "constants": {"thickness_steps": THICKNESS_STEPS, "depth_agree_steps": DEPTH_AGREE_STEPS,
                      "refine_steps": REFINE_STEPS, "alpha_floor": tol.ALPHA_FLOOR,
                      "sun_view_min_coverage": tol.SUN_VIEW_MIN_COVERAGE,
                      "sun_ground_bias_texels": tol.SUN_GROUND_BIAS_TEXELS,
                      "sun_min_elevation_deg": tol.SUN_MIN_ELEVATION_DEG,
                      "shadow_max_texels": SHADOW_MAX_TEXELS, "imp_min_cos": tol.IMP_MIN_COS},
        "assets": entries, "texture_bytes": int(sum(e["texture_bytes"] for e in entries)),
        "measured": list(measured or []), "notes": notes,
        "gltf": None if gltf is None else base64.b64encode(gltf).decode("ascii"),
    }


def check_preview_output(path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """``path`` if a page may be written there (before any work is done), else the error.

    Parameters
    ----------
    path : path-like
        An ``.html`` file.
    overwrite : bool, optional
        An existing file may be replaced.

    Returns
    -------
    Path

    Raises
    ------
    OutputExistsError
        ``path`` exists and ``overwrite`` is not given.
    ValidationError
        Not an ``.html`` path, or a folder, or under a file.
    """
    return check_output_file(path, "an .html", (".html", ".htm"), overwrite=overwrite)


def write_preview(path: str | os.PathLike[str], data: dict[str, Any], *, overwrite: bool = False) -> Path:
    """Write the page of ``data`` to ``path``, atomically.

    Parameters
    ----------
    path : path-like
        An ``.html`` file.
    data : dict
        :func:`preview_data`.
    overwrite : bool, optional
        Replace an existing file.

    Returns
    -------
    Path

    Raises
    ------
    OutputExistsError
        ``path`` exists and ``overwrite`` is not given.
    ValidationError
        Not an ``.html`` path, or a folder.
    """
    p = check_preview_output(path, overwrite=overwrite)
    p.parent.mkdir(parents=True, exist_ok=True)
    return write_text(p, page_html(data))
