"""``morphkit shadows``: the scene of a baked shadow atlas along an object path, to frames and a video.

The object moves along a path (:class:`LinePath`, :class:`CirclePath`, or the
positions of a CSV file, :class:`PointsPath`) over the atlas's range; each
frame is rendered from a 3/4 view camera with the shadow of the warped atlas
(:func:`morphkit.shadow.frame.render_frame`): hard under the atlas's light, or
soft under an area light centred on it (:func:`morphkit.shadow.default_soft_shadow`:
PCSS on one reprojected map per light sample; the path then keeps to the range shrunk by the
light's extent, where every sample's map can be warped).

The frames. The camera looks at the range's centre from :data:`DEFAULT_VIEW` (azimuth,
elevation; ``view=``, ``--view``) at the distance that keeps the whole range in sight; the
light is *exposed* for the frame (:func:`exposed`: its intensity set so that the brightest
lit ground point reaches :data:`GROUND_PEAK`, not white); the warped shadow falls on the
ground (the receiver), the object shaded by its own facing (a self-shadow from a map of a few
hundred texels would be acne). Each frame's shadow is compared with the ray-cast truth on the
ground pixels it shows (:mod:`morphkit.imaging.groundtruth`): hard shadows by IoU of the shadowed
pixels, soft ones by the mean absolute visibility error.

The mesh. An atlas stores light-view maps, not the mesh the frames show. The bake's manifest
records each atlas's input file and its sha256, so :func:`baked_mesh` finds the
``manifest.json`` in the atlas's folder or a parent folder (another program's file of that
name, a web app's, is passed by: :func:`morphkit.bake.manifest.is_bake_manifest`) and loads
that file after checking its hash; ``mesh=`` (``--mesh``) names the file instead (still
checked against the manifest's hash when the atlas is listed in one, e.g. when the library
moved). Wherever the atlas lies, the mesh loaded must have the shape the atlas records (its
:attr:`~morphkit.shadow.baked.BakedAtlas.mesh_sha256`, :func:`morphkit.meshes.shape_hash`):
another mesh would cast a shadow that is not its own.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np
import trimesh
from tqdm import tqdm

from .. import tol
from ..bake.manifest import baked_from, file_digest
from ..camera import look_at, perspective
from ..errors import FileFormatError, MeshError, ValidationError, expected_got
from ..files.fileio import file_kind, write_image
from ..files.outfolder import FRAMES_FOLDER, frame_name
from ..imaging.groundtruth import area_visibility, hard_visibility
from ..imaging.metrics import shadow_iou
from ..meshes import load_mesh, shape_hash
from ..protocols import SceneRenderer
from ..scene import AreaLight, DirectionalLight, PointLight, Receiver, Scene, SceneObject
from ..shadow.atlas import ShadowAtlas
from ..shadow.filtering.penumbra import default_soft_shadow
from ..shadow.frame import render_frame
from ..shadow.lookup import shadow_visibility
from ..shadow.rig import MotionRange
from ..validate import as_int
from .video import VideoFile

__all__ = ["ObjectPath", "LinePath", "CirclePath", "PointsPath", "baked_mesh", "area_light_for",
           "playback_scene", "render_shadow_sequence", "VIDEO_NAME", "DEFAULT_VIEW", "GROUND_PEAK",
           "PLAYBACK_AMBIENT", "exposed"]

#: The video beside the frames.
VIDEO_NAME = "shadows.webm"


@runtime_checkable
class ObjectPath(Protocol):
    """Object positions ``(x, y)`` on the ground over a range of motion.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    def positions(self, motion: MotionRange) -> np.ndarray:
        """``(N, 2)`` float64 world positions, inside ``motion``.

        Parameters
        ----------
        motion : MotionRange
            The usable range of motion, world frame.

        Returns
        -------
        numpy.ndarray
            ``(N, 2)`` float64 object positions ``(x, y)`` on the ground, world frame.
        """
        ...


def _frames(n: Any) -> int:
    return as_int(n, "frames", lo=1, hi=tol.MAX_FRAMES)


@dataclass(frozen=True)
class LinePath:
    """``frames`` positions on the range's diagonal, from ``lo`` to ``hi``.

    Parameters
    ----------
    frames : int
        Number of positions, in [1, :data:`morphkit.tol.MAX_FRAMES`] (checked by :meth:`positions`).
    """

    frames: int = 48

    def positions(self, motion: MotionRange) -> np.ndarray:
        """``(N, 2)`` float64 world positions of the path, inside ``motion``.

        Parameters
        ----------
        motion : MotionRange
            The usable range of motion, world frame.

        Returns
        -------
        numpy.ndarray
            ``(N, 2)`` float64 object positions ``(x, y)`` on the ground, world frame.
        """
        t = np.linspace(0.0, 1.0, _frames(self.frames))[:, None]
        return motion.lo + t * (motion.hi - motion.lo)


@dataclass(frozen=True)
class CirclePath:
    """``frames`` positions once around an ellipse at the range's centre (radii 0.45 of its size).

    Parameters
    ----------
    frames : int
        Number of positions, in [1, :data:`morphkit.tol.MAX_FRAMES`] (checked by :meth:`positions`).
    """

    frames: int = 48

    def positions(self, motion: MotionRange) -> np.ndarray:
        """``(N, 2)`` float64 world positions of the path, inside ``motion``.

        Parameters
        ----------
        motion : MotionRange
            The usable range of motion, world frame.

        Returns
        -------
        numpy.ndarray
            ``(N, 2)`` float64 object positions ``(x, y)`` on the ground, world frame.
        """
        a = np.linspace(0.0, 2 * np.pi, _frames(self.frames), endpoint=False)
        r = 0.45 * (motion.hi - motion.lo)
        return motion.center + np.c_[r[0] * np.cos(a), r[1] * np.sin(a)]


@dataclass(frozen=True)
class PointsPath:
    """Given positions ``(N, 2)``; each must lie in the range.

    Parameters
    ----------
    points : numpy.ndarray
        ``(N, 2)`` float64 object positions ``(x, y)`` on the ground, world frame.
    """

    points: np.ndarray

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str]) -> PointsPath:
        """Rows ``x,y`` (a header line and ``#`` comments are skipped).

        Parameters
        ----------
        path : path-like
            A UTF-8 CSV file with one ``x,y`` row per position (world units).

        Returns
        -------
        PointsPath
            The rows in order, ``(N, 2)`` float64.

        Raises
        ------
        ValidationError
            Missing or unreadable file, or not two finite numbers per row.
        """
        p = Path(path)
        if not p.is_file():  # a FIFO or a folder too: never opened
            raise ValidationError(expected_got("path file", "an existing CSV file of x,y rows",
                                               f"{str(p)!r} ({_not_a_file(p)})"))
        rows = []
        for i, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines()):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            cells = [c.strip() for c in line.split(",")]
            try:
                xy = [float(c) for c in cells]
            except ValueError:
                if not rows and i == 0:  # a header
                    continue
                raise ValidationError(expected_got(f"path file {p.name} line {i + 1}",
                                                   "two numbers x,y", repr(line))) from None
            if len(xy) != 2 or not np.all(np.isfinite(xy)):
                raise ValidationError(expected_got(f"path file {p.name} line {i + 1}",
                                                   "two finite numbers x,y", repr(line)))
            rows.append(xy)
        if not rows:
            raise ValidationError(expected_got(f"path file {p.name}", "at least one x,y row", "none"))
        return cls(np.array(rows, np.float64))

    def positions(self, motion: MotionRange) -> np.ndarray:
        """``(N, 2)`` float64 world positions of the path, inside ``motion``.

        Parameters
        ----------
        motion : MotionRange
            The usable range of motion, world frame.

        Returns
        -------
        numpy.ndarray
            ``(N, 2)`` float64 object positions ``(x, y)`` on the ground, world frame.
        """
        return np.array([motion.check(xy) for xy in np.asarray(self.points, np.float64)])


def baked_mesh(atlas_path: str | os.PathLike[str], mesh: str | os.PathLike[str] | None = None, *,
               mesh_sha256: str | None = None) -> trimesh.Trimesh:
    """The mesh an atlas was baked from (see the module docstring), normalised as the bake did.

    Parameters
    ----------
    atlas_path : path-like
        The atlas file (``.atlas.npz``).
    mesh : path-like, optional
        The mesh file; default: the input the manifest records for the atlas.
    mesh_sha256 : str, optional
        The shape the atlas records (``ShadowAtlas.baked.mesh_sha256``); the loaded mesh
        must have it (:func:`morphkit.meshes.shape_hash`). None: not checked.

    Returns
    -------
    trimesh.Trimesh
        The mesh, normalised by :func:`morphkit.meshes.load_mesh`, object frame.

    Raises
    ------
    ValidationError
        No ``mesh`` and no manifest listing the atlas.
    FileFormatError
        The mesh file's content differs from the one the atlas was baked from, or the
        loaded mesh's shape from ``mesh_sha256``.
    MeshError
        The mesh file is missing or unreadable.
    """
    atlas = Path(atlas_path).resolve()
    found = baked_from(atlas)  # another program's manifest.json on the way is passed by
    if mesh is None and found is None:
        raise ValidationError(expected_got(f"mesh of {atlas.name}", "a bake manifest listing the atlas "
                                           "(its folder or a parent), or --mesh", "neither"))
    path = Path(mesh) if mesh is not None else found.input  # type: ignore[union-attr]
    if found is not None:
        if not path.is_file():  # a FIFO or a folder too: never opened
            hint = "; give its new place with --mesh" if mesh is None else ""
            raise MeshError(expected_got("mesh the atlas was baked from", "an existing file",
                                         f"{str(path)!r} ({_not_a_file(path)}{hint})"))
        got = file_digest(path)[0]
        if got != found.input_sha256:
            raise FileFormatError(expected_got(f"mesh {str(path)!r}", "the file the atlas was baked from "
                                               f"(sha256 {found.input_sha256[:12]})", f"sha256 {got[:12]}"))
    # the axis the atlas was baked with (the manifest's); a mesh given alone: its format's default
    loaded = load_mesh(path, up=found.up_axis if found is not None else "auto")
    shape = None if mesh_sha256 is None else shape_hash(loaded)
    if shape is not None and shape != mesh_sha256:
        raise FileFormatError(expected_got(
            f"mesh {str(path)!r}", f"the mesh {atlas.name} was baked from (shape sha256 {mesh_sha256[:12]})",
            f"another shape (sha256 {shape[:12]}; another mesh, or another up axis)"))
    return loaded


def _not_a_file(path: Path) -> str:
    """What ``path``, which is no regular file, is: ``not found``, or its kind (a FIFO, a folder)."""
    try:
        return file_kind(path.stat().st_mode)
    except OSError:
        return "not found"


def area_light_for(atlas: ShadowAtlas, width: float, height: float) -> AreaLight:
    """A ``width x height`` area light parallel to the ground, centred on the atlas's point light.

    Parameters
    ----------
    atlas : ShadowAtlas
        An atlas baked for a point light.
    width : float
        Extent along world x, world units (> 0).
    height : float
        Extent along world y, world units (> 0).

    Returns
    -------
    AreaLight
        Centre at the point light, half-extent vectors ``(width / 2, 0, 0)`` and ``(0, height / 2, 0)``,
        world frame.

    Raises
    ------
    ValidationError
        The atlas was baked for a directional light, or a size is not positive.
    """
    light = atlas.rig.light
    if not isinstance(light, PointLight):
        raise ValidationError(expected_got("atlas light for an area light", "a point light at its centre",
                                           type(light).__name__))
    w, h = float(width), float(height)
    if not (np.isfinite(w) and np.isfinite(h) and w > 0 and h > 0):
        raise ValidationError(expected_got("area light size", "width, height > 0", (width, height)))
    return AreaLight(light.position, [w / 2, 0.0, 0.0], [0.0, h / 2, 0.0])


def _usable_range(atlas: ShadowAtlas, area: AreaLight | None) -> MotionRange:
    motion = atlas.rig.motion
    if area is None:
        return motion
    ext = np.abs(area.u[:2]) + np.abs(area.v[:2])
    if np.any(motion.hi - motion.lo <= 2 * ext):
        raise ValidationError(expected_got(
            "area light", f"smaller than the baked range ({(motion.hi - motion.lo).round(6).tolist()}) "
            "on both axes, so some object positions see every light sample inside it",
            f"{(2 * ext).round(6).tolist()}"))
    return MotionRange(motion.lo + ext, motion.hi - ext)


#: The playback camera's direction from the range's centre: azimuth (degrees counter-clockwise
#: from world ``+x``) and elevation above the ground, degrees -- a 3/4 view from the front right.
DEFAULT_VIEW = (-43.2, 20.6)

#: The playback scene's ambient term (the unlit share of the ground's colour).
PLAYBACK_AMBIENT = 0.3

#: Linear brightness of the brightest lit ground point of a playback frame, in the receiver's
#: brightest channel (:func:`exposed`): below 1, so the ground keeps its shading in the light.
GROUND_PEAK = 0.8


def exposed(light: PointLight | DirectionalLight | AreaLight, receiver: Receiver, ambient: float
            ) -> PointLight | DirectionalLight | AreaLight:
    """``light`` with its intensity set so that the brightest lit point of the ground reaches
    :data:`GROUND_PEAK` (linear, the receiver's brightest channel) under ``ambient``.

    The renderer's diffuse term is ``albedo / pi * E * cos`` plus ``ambient * albedo``
    (:mod:`morphkit.render`'s shader), with ``E = I / d^2`` for a point light (brightest at its
    foot, ``d`` its height; an area light as a point at its centre) and ``E = I`` for a
    directional one (``cos`` its elevation's sine). A light that does not reach the ground
    (below or level with it) is returned as it is.

    Parameters
    ----------
    light : PointLight, DirectionalLight or AreaLight
        The light, world frame.
    receiver : Receiver
        The ground (its colour).
    ambient : float
        The scene's ambient term.

    Returns
    -------
    PointLight, DirectionalLight or AreaLight
        The same light with another intensity.
    """
    albedo = max(float(max(receiver.color)), 1e-3)
    irradiance = max(GROUND_PEAK - ambient * albedo, 0.05) * np.pi / albedo
    if isinstance(light, DirectionalLight):
        cos = -float(light.direction[2]) / float(np.linalg.norm(light.direction))
        return light if cos <= 0 else dataclasses.replace(light, intensity=irradiance / cos)
    height = float((light.center if isinstance(light, AreaLight) else light.position)[2])
    return light if height <= 0 else dataclasses.replace(light, intensity=irradiance * height**2)


def playback_scene(mesh: trimesh.Trimesh, atlas: ShadowAtlas, size: int,
                   light: AreaLight | None = None, *, view: tuple[float, float] = DEFAULT_VIEW) -> Scene:
    """The scene the frames show: the mesh on a ground square covering the range, the atlas's
    light (or ``light``), and a 3/4 view camera of ``size x size`` pixels that sees the whole
    range with the object anywhere on it.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The normalised mesh, object frame; placed at the range's centre.
    atlas : ShadowAtlas
        The atlas: its rig gives the range, the object pose and the light.
    size : int
        Side of the square camera image, in pixels.
    light : AreaLight, optional
        The light of the scene instead of the atlas's.
    view : (float, float)
        The camera's azimuth and elevation (degrees) from the range's centre
        (:data:`DEFAULT_VIEW`); the elevation in ``[5, 89]``.

    Returns
    -------
    Scene
        Object, light, camera (world frame) and a ground receiver; move the object with
        ``Scene.with_object_pose``.
    """
    az, el = (float(v) for v in view)
    if not (np.isfinite(az) and np.isfinite(el) and 5.0 <= el <= 89.0):
        raise ValidationError(expected_got("view", "an azimuth and an elevation in [5, 89] degrees",
                                           tuple(view)))
    motion = atlas.rig.motion
    # a sphere around the range and the object on it (normalised: size 1), seen whole at 40 deg
    fov = np.deg2rad(40)
    centre = np.r_[motion.center, 0.35]
    radius = 0.5 * float(np.linalg.norm(motion.hi - motion.lo)) + 0.6
    a, e = np.deg2rad(az), np.deg2rad(el)
    towards = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    dist = radius / np.sin(fov / 2)
    cam = perspective(fov, (size, size), look_at(centre + dist * towards, centre), znear=0.1,
                      zfar=dist + 4 * radius)
    half = max(2.0, float(np.max(np.abs(np.r_[motion.lo, motion.hi]))) + 1.5)
    obj = SceneObject(mesh, atlas.rig.object_pose(motion.center))
    ground = Receiver(half_size=half)
    return Scene(obj, exposed(atlas.rig.light if light is None else light, ground, PLAYBACK_AMBIENT), cam,
                 ground, ambient=PLAYBACK_AMBIENT)


def render_shadow_sequence(atlas: ShadowAtlas, mesh: trimesh.Trimesh, path: ObjectPath,
                           out: str | os.PathLike[str], *, renderer: SceneRenderer, size: int = 512,
                           area_light: AreaLight | None = None, samples: int = 3, fps: float = 24.0,
                           view: tuple[float, float] = DEFAULT_VIEW, progress: bool = True
                           ) -> dict[str, Any]:
    """Render the frames of ``mesh`` moving along ``path`` with the atlas's warped shadow.

    Parameters
    ----------
    atlas : ShadowAtlas
        The baked atlas; its warped maps give each frame's shadow.
    mesh : trimesh.Trimesh
        The mesh the atlas was baked from (:func:`baked_mesh`).
    path : ObjectPath
        The object's positions, one per frame, over the usable range (the atlas's range, shrunk by the
        area light's extent when there is one).
    out : path-like
        Output folder (created): ``frames/frame_NNNN.png`` (RGB,
        :func:`morphkit.files.outfolder.frame_name`) and :data:`VIDEO_NAME` (VP9).
    renderer : SceneRenderer
        Renders the frames.
    size : int
        Frame side in pixels, in [16, 8190] (:data:`morphkit.tol.MAX_VIDEO_SIDE`: the frames make
        a VP9 video).
    area_light : AreaLight, optional
        Soft shadows of this light (:func:`area_light_for`), ``samples x samples`` light samples.
    samples : int
        Light samples per axis of ``area_light``, in [1, 64]; unused without it.
    fps : float
        Frame rate of the video.
    view : (float, float)
        The camera's azimuth and elevation, degrees (:func:`playback_scene`).
    progress : bool
        Show a progress bar (tqdm).

    Returns
    -------
    dict
        ``frames`` (paths), ``video`` (path), ``positions`` (list of (x, y)), and ``errors``:
        per frame, the shadow on the ground pixels against the ray cast
        (:mod:`morphkit.imaging.groundtruth`) -- ``{"iou": ...}`` (hard: the shadowed pixels, IoU 1
        when neither has any) or ``{"mae": ...}`` (soft: mean absolute visibility error over
        the ground pixels).

    Raises
    ------
    ValidationError
        A bad ``size``, ``samples`` or ``path``, or an area light not smaller than the range.
    OutOfRangeError
        A position of the path lies outside the usable range.
    RenderError
        OpenCV has no VP9 video writer here, or none for frames of ``size`` (memory).
    """
    size = as_int(size, "frame size", lo=16, hi=tol.MAX_VIDEO_SIDE)
    samples = as_int(samples, "light samples per axis", lo=1, hi=64)
    if not isinstance(path, ObjectPath):
        raise ValidationError(expected_got("path", "an ObjectPath", type(path).__name__))
    motion = _usable_range(atlas, area_light)
    positions = path.positions(motion)
    soft = None if area_light is None else default_soft_shadow(atlas, area_light, (samples, samples))
    scene = playback_scene(mesh, atlas, size, area_light, view=view)
    folder = Path(out)
    (folder / FRAMES_FOLDER).mkdir(parents=True, exist_ok=True)
    frames: list[Path] = []
    errors: list[dict[str, float]] = []
    video = folder / VIDEO_NAME
    with VideoFile(video, fps, (size, size)) as writer:
        for i, xy in enumerate(tqdm(positions, desc="morphkit shadows", unit="frame",
                                    disable=None if progress else True, leave=False)):
            sc = scene.with_object_pose(atlas.rig.object_pose(xy))
            if soft is not None:
                vis = soft.visibility_fn(xy)
            else:
                depth, lcam = atlas.shadow_map(xy)
                vis = _hard(depth, lcam)
            drawn = render_frame(renderer, sc, vis, receiver_only=True)
            rgb = drawn["shaded"]
            frames.append(write_image(folder / frame_name(i), rgb))
            writer.write(rgb)
            errors.append(_against_truth(sc, drawn, area_light, samples))
    return {"frames": frames, "video": video, "positions": positions.tolist(), "errors": errors}


def _against_truth(scene: Scene, drawn: dict[str, np.ndarray], area_light: AreaLight | None,
                   samples: int) -> dict[str, float]:
    """The frame's shadow on its ground pixels against the ray cast (``errors`` of
    :func:`render_shadow_sequence`)."""
    world, valid = scene.camera.unproject(drawn["depth"])
    ground = valid & (np.abs(world[..., 2]) <= tol.GROUND_PIXEL_DZ)
    points = world[ground]
    shown = drawn["visibility"][ground]
    if not len(points):  # the ground is out of sight: nothing to be wrong about
        return {"iou": 1.0} if area_light is None else {"mae": 0.0}
    if area_light is None:
        truth = hard_visibility(points, scene.light, scene.obj)  # type: ignore[arg-type]
        return {"iou": shadow_iou(shown < 0.5, truth < 0.5)}
    truth = area_visibility(points, area_light, scene.obj, samples)
    return {"mae": float(np.mean(np.abs(shown - truth)))}


def _hard(depth: np.ndarray, lcam: Any) -> Any:
    return lambda p, n: shadow_visibility(p, depth, lcam, normals=n)


