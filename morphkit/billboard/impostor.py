"""The anchor baseline of relightable billboards: an octahedral impostor, as the game engines build it.

Unreal's impostor baker and Amplify Impostors bake an object's upper hemisphere of
views on a **hemi-octahedral grid** of ``N x N`` frames (``N`` = 12 to 16 in their
defaults), each an orthographic view storing albedo, normals and depth, and at run
time blend the **three frames of the grid triangle** around the viewing direction with
a **depth-based parallax offset**. :class:`OctahedralImpostor` does the same in the
:class:`~morphkit.billboard.protocols.SurfaceSource` interface (the unshaded surface of
any viewing direction, relit by the scene), so the view-morph assets are measured
against it at equal bytes (:func:`impostor_frame_size`).

Hemi-octahedral map (Unreal's ``HemiOctahedronToUnitVector`` and its inverse). A grid
point ``(u, v)`` in ``[-1, 1]^2`` maps to the unit direction (object frame, ``+z`` up)

    ``x = (u + v) / 2,  y = (u - v) / 2,  z = 1 - |x| - |y|,  d = (x, y, z) / |(x, y, z)|``

(:func:`hemi_oct_decode`): the centre is straight above, the square's edges are the
horizon, its corners ``(1, 1), (1, -1), (-1, -1), (-1, 1)`` are ``+x, +y, -x, -y``.
The inverse (:func:`hemi_oct_encode`) of a direction with ``z >= 0`` is
``p = d / (|d_x| + |d_y| + d_z)``, ``(u, v) = (p_x + p_y, p_x - p_y)``.
Frame ``(i, j)`` (column ``i``, row ``j``, ``0 <= i, j < N``; stored at index
``j N + i``) looks along ``-d`` from the grid point ``(2 i / (N - 1) - 1, 2 j / (N - 1) - 1)``
(the engines' spacing: the grid's border frames lie on the horizon; for odd ``N`` the
centre frame is straight above).

Frames. Each is an orthographic view along ``-d`` (:meth:`DomeCameras.ortho_camera`
of its azimuth and elevation; straight above, azimuth 0, which only sets the frame's
roll) whose square image of ``m x m`` pixels covers the quad of ``half_extent`` through
the pivot: every frame covers the same bounding sphere. Frames are stored with
:func:`~morphkit.views.gbuffer.encode_surface` (9 bytes a pixel) at ``levels`` mip
levels of ``round(m 2^-l)`` pixels a side (:func:`~morphkit.views.gbuffer.downsample_surface`).

Runtime (:meth:`OctahedralImpostor.surface`). The viewing direction (elevation below 0
clamped to 0: the impostor has no views from below) maps to the grid coordinate ``g =
(uv + 1) (N - 1) / 2``; the cell ``c = floor(g)`` (clamped to ``[0, N - 2]``) and ``f =
g - c`` pick the triangle as Amplify does: frames ``c``, ``c + (1, 1)`` and ``c + (1,
0)`` where ``f_x > f_y``, else ``c + (0, 1)``, with weights ``min(1 - f_x, 1 - f_y)``,
``min(f_x, f_y)`` and ``|f_x - f_y|`` (barycentric: they sum to 1 and reproduce ``f``; a
direction at a frame has that frame alone). Every output pixel is a point ``P`` of the
output quad, and its ray runs from the eye of the direction's camera
(:meth:`DomeCameras.camera`, ``pivot + D d``) through ``P``
(``projection="perspective"``, the default: the image the quad shows for that camera,
and what Amplify's shader does, whose rays start at the real camera), or along ``-d``
through ``P`` (``"orthographic"``: the frames' own projection). For each frame of
positive weight the ray is intersected with the frame's plane (through the pivot,
perpendicular to the frame's direction ``d_k``), which gives the frame's UV; then the
**parallax offset**: the frame's height ``h = D - depth`` (``D`` =
the camera rule's ``distance``; the height of the surface seen there above the frame's
plane along ``d_k``) is read at that UV and the UV moved along the ray to where the ray
is at that height: one step, as Amplify's shader does (``parallax_samples = 1``, the
default; the move is the exact ray-height intersection, ``h tan(angle)``, where
Amplify's offset is ``h sin(angle)``: a few percent apart within a 12-frame cell).
``parallax_samples = n >= 2`` instead marches the ray through the bounding sphere's
height range ``[-r, r]`` in ``n`` even steps, stops at the first sample that is covered
(alpha > 0) and at or below the frame's height, and refines between it and the sample
before by one secant step (a parallax-occlusion search, more than the engines do; for
comparison). Heights are read as coverage-weighted means (bilinear ``h alpha`` over
bilinear ``alpha``; height 0, no offset, where the frame is empty), so a silhouette's
height is not pulled towards the plane. At the final UV the frame's premultiplied albedo
and alpha, normals and height are read (bilinear), and the three frames are blended by
weight: albedo premultiplied, normals summed and renormalised, depth the
coverage-weighted mean.

Output depth is along the output direction, measured from the eye plane of the
direction's camera (:meth:`DomeCameras.camera`, at distance ``D`` from the pivot):
``depth = D - (X - pivot) . d`` for the surface point ``X`` a frame puts on the ray
(the camera's depth, for either projection). It is meant for ordering only (the frames'
heights are float16 and blended).
Output images are ``out_size`` pixels a side at level 0 (default: the frame size),
``round(out_size 2^-l)`` at level ``l``; level ``l`` reads the frames' level ``l``.
Straight above, the azimuth passed in sets the output's roll (the quad rule's ``up``).

Not done here: files (an impostor is baked when needed, in seconds; no save/load),
the engines' frame-atlas layout and texture-border padding (each frame is sampled
with an empty border instead), dithered frame selection.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import cv2
import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..meshes import normalize
from ..protocols import PassRenderer
from ..validate import as_int
from ..views.domecameras import DomeCameras, direction, quad_axes
from ..views.gbuffer import (
    BYTES_PER_PIXEL,
    StoredSurface,
    ViewSurface,
    decode_surface,
    downsample_surface,
    encode_surface,
    linear_to_srgb,
)
from .baking.bakelook import BAKE_AMBIENT, bake_items, bake_lights, check_appearance
from .cameras import DISTANCE_FACTOR

__all__ = ["OctahedralImpostor", "bake_impostor", "impostor_frame_size", "hemi_oct_encode",
           "hemi_oct_decode", "frame_grid_uv", "DEFAULT_FRAMES", "DEFAULT_LEVELS", "MIN_LEVEL_SIDE",
           "PROJECTIONS"]

#: Frames a side of the grid (the engines' defaults are 12 to 16).
DEFAULT_FRAMES = 12

#: Mip levels of the frames.
DEFAULT_LEVELS = 3

#: The smallest mip level of a frame must be at least this many pixels a side.
MIN_LEVEL_SIDE = 4

#: The output's rays (:class:`OctahedralImpostor` ``projection``).
PROJECTIONS = ("perspective", "orthographic")


def hemi_oct_decode(uv: np.ndarray) -> np.ndarray:
    """Unit directions of hemi-octahedral grid points (module docstring).

    Parameters
    ----------
    uv : (..., 2) array
        Grid points in ``[-1, 1]^2`` (not checked: outside, the map folds).

    Returns
    -------
    (..., 3) float64
        Unit directions with ``z >= 0``, object frame.
    """
    uv = np.asarray(uv, dtype=np.float64)
    x = 0.5 * (uv[..., 0] + uv[..., 1])
    y = 0.5 * (uv[..., 0] - uv[..., 1])
    z = 1.0 - np.abs(x) - np.abs(y)
    d = np.stack([x, y, z], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def hemi_oct_encode(d: np.ndarray) -> np.ndarray:
    """Hemi-octahedral grid points of directions (the inverse of :func:`hemi_oct_decode`).

    Parameters
    ----------
    d : (..., 3) array
        Nonzero directions (need not be unit); ``z < 0`` is taken as 0 (the horizon).

    Returns
    -------
    (..., 2) float64
        Grid points in ``[-1, 1]^2``.
    """
    d = np.asarray(d, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], np.maximum(d[..., 2], 0.0)
    s = np.abs(x) + np.abs(y) + z
    px, py = x / s, y / s
    return np.stack([px + py, px - py], axis=-1)


def frame_grid_uv(frames: int) -> np.ndarray:
    """``(N, N, 2)`` grid points of the frames, indexed ``[j, i]`` (row, column).

    Parameters
    ----------
    frames : int
        ``N >= 3``, frames a side.

    Returns
    -------
    (N, N, 2) float64
        ``(2 i / (N - 1) - 1, 2 j / (N - 1) - 1)``.
    """
    n = _check_frames(frames)
    t = 2.0 * np.arange(n) / (n - 1) - 1.0
    u, v = np.meshgrid(t, t)
    return np.stack([u, v], axis=-1)


def _check_frames(frames: Any) -> int:
    return as_int(frames, "frames", lo=3)


def _angles(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and elevation (degrees) of unit directions; straight above: azimuth 0."""
    horiz = np.hypot(d[..., 0], d[..., 1])
    az = np.where(horiz > 0, np.degrees(np.arctan2(d[..., 1], d[..., 0])), 0.0)
    el = np.degrees(np.arctan2(d[..., 2], horiz))
    return az, el


def _side(m: int, level: int) -> int:
    """Side of mip level ``level`` of an ``m``-pixel image (as :meth:`DomeCameras.level_shape`)."""
    return max(1, round(m / 2**level))


def _stored_bytes(m: int, frames: int, levels: int) -> int:
    return frames * frames * BYTES_PER_PIXEL * sum(_side(m, lv) ** 2 for lv in range(levels))


def impostor_frame_size(budget_bytes: int, frames: int = DEFAULT_FRAMES, levels: int = DEFAULT_LEVELS) -> int:
    """The largest frame side ``m`` whose impostor (``frames^2`` frames, ``levels`` mip
    levels, :data:`~morphkit.views.gbuffer.BYTES_PER_PIXEL` a pixel) fits ``budget_bytes``
    (its :attr:`OctahedralImpostor.memory_bytes`).

    Parameters
    ----------
    budget_bytes : int
        Bytes available.
    frames : int, optional
        Frames a side.
    levels : int, optional
        Mip levels.

    Returns
    -------
    int
        The frame side, pixels.

    Raises
    ------
    ValidationError
        Bad arguments, or a budget too small for frames of 8 pixels whose smallest level
        has :data:`MIN_LEVEL_SIDE` pixels.
    """
    budget = as_int(budget_bytes, "budget_bytes", lo=1)
    n = _check_frames(frames)
    lv = as_int(levels, "levels", lo=1)
    m = int(math.isqrt(budget // (BYTES_PER_PIXEL * n * n))) + 1
    while m > 0 and _stored_bytes(m, n, lv) > budget:
        m -= 1
    if m < 8 or _side(m, lv - 1) < MIN_LEVEL_SIDE:
        raise ValidationError(expected_got(
            "budget_bytes", f"room for {n}x{n} frames of at least 8 px with {lv} levels "
            f"(the smallest >= {MIN_LEVEL_SIDE} px)", f"{budget} bytes (frame side {m})"))
    return m


def _store(surface: ViewSurface) -> StoredSurface:
    """A working surface at storage precision (straight sRGB albedo, int8 normals, float16 depth)."""
    a = surface.alpha
    straight = surface.albedo[..., :3] / np.maximum(a, np.float32(tol.ALPHA_FLOOR))[..., None]
    rgba = np.empty(surface.albedo.shape, np.uint8)
    rgba[..., :3] = np.rint(255.0 * linear_to_srgb(np.where(a[..., None] > 0, straight, 0.0)))
    rgba[..., 3] = np.rint(255.0 * np.clip(a, 0.0, 1.0))
    return encode_surface(rgba, surface.normal, surface.depth)


class OctahedralImpostor:
    """An octahedral impostor: ``N x N`` frames on the hemi-octahedral grid (module docstring).

    Build one with :func:`bake_impostor` (from a mesh) or :meth:`OctahedralImpostor.from_surfaces`.

    Parameters
    ----------
    name : str
        The asset's name.
    cameras : DomeCameras
        The camera rule (pivot, distance ``D``, ``half_extent``) the frames were made with.
    frames : int
        ``N >= 3``, frames a side.
    stored : sequence of sequence of StoredSurface
        ``stored[l][j N + i]``: frame ``(i, j)`` at mip level ``l``, square, of side
        ``round(m 2^-l)``, ``m`` the side of level 0.
    out_size : int, optional
        Side of the level-0 output images (default ``m``).
    parallax_samples : int, optional
        Parallax search per frame (module docstring): 1, one offset step (the engines'),
        or ``n >= 2`` ray-march samples and a secant step.
    projection : {"perspective", "orthographic"}, optional
        The output's rays (module docstring): from the eye of :meth:`DomeCameras.camera`
        (default), or parallel to the viewing direction.

    Raises
    ------
    ValidationError
        Bad arguments.
    """

    def __init__(self, name: str, cameras: DomeCameras, frames: int,
                 stored: Sequence[Sequence[StoredSurface]], *, out_size: int | None = None,
                 parallax_samples: int = 1, projection: str = "perspective") -> None:
        if not isinstance(name, str) or not name:
            raise ValidationError(expected_got("name", "a non-empty string", repr(name)))
        if not isinstance(cameras, DomeCameras):
            raise ValidationError(expected_got("cameras", "a DomeCameras", type(cameras).__name__))
        n = _check_frames(frames)
        if len(stored) < 1 or not all(len(lv) == n * n for lv in stored):
            raise ValidationError(expected_got("stored", f"levels of {n * n} frames each",
                                               [len(lv) for lv in stored]))
        first = stored[0][0]
        m = first.rgba.shape[0] if isinstance(first, StoredSurface) else 0
        for lv, level in enumerate(stored):
            side = _side(m, lv)
            for s in level:
                if not isinstance(s, StoredSurface) or s.rgba.shape[:2] != (side, side):
                    got = getattr(getattr(s, "rgba", None), "shape", type(s).__name__)
                    raise ValidationError(expected_got(f"stored level {lv}",
                                                       f"StoredSurface frames of ({side}, {side})", got))
        if _side(m, len(stored) - 1) < MIN_LEVEL_SIDE:
            raise ValidationError(expected_got("levels", f"a smallest level of >= {MIN_LEVEL_SIDE} px",
                                               f"{len(stored)} levels of {m} px frames"))
        self.name = name
        self.cameras = cameras
        self.frames = n
        self._stored = [list(level) for level in stored]
        self._nbytes = int(sum(s.nbytes for level in self._stored for s in level))
        self.frame_side = int(m)
        out = m if out_size is None else as_int(out_size, "out_size", lo=1)
        self.size = (out, out)
        self.parallax_samples = as_int(parallax_samples, "parallax_samples", lo=1)
        if projection not in PROJECTIONS:
            raise ValidationError(expected_got("projection", f"one of {list(PROJECTIONS)}", repr(projection)))
        self.projection = projection
        self.half_extent = cameras.half_extent
        self.pivot = cameras.pivot.copy()
        self.levels = len(stored)
        #: The frames' directions, right and up axes, ``(N*N, 3)`` each, index ``j N + i``.
        uv = frame_grid_uv(n).reshape(-1, 2)
        self.frame_dirs = hemi_oct_decode(uv)
        az, el = _angles(self.frame_dirs)
        self.frame_angles = np.stack([az, el], axis=-1)
        self.frame_right, self.frame_up = quad_axes(az, el)
        self._textures: dict[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    @classmethod
    def from_surfaces(cls, name: str, cameras: DomeCameras, frames: int, surfaces: Sequence[ViewSurface], *,
                      levels: int = DEFAULT_LEVELS, out_size: int | None = None,
                      parallax_samples: int = 1, projection: str = "perspective") -> OctahedralImpostor:
        """An impostor of level-0 frames given as working surfaces (stored, then mip-mapped).

        Parameters
        ----------
        name : str
            The asset's name.
        cameras : DomeCameras
            The camera rule of the frames.
        frames : int
            ``N``, frames a side.
        surfaces : sequence of ViewSurface
            ``N * N`` square frames of one size, index ``j N + i``; depth along each
            frame's axis from its eye plane (:meth:`DomeCameras.ortho_camera`).
        levels : int, optional
            Mip levels.
        out_size : int, optional
            Side of the level-0 output images (default the frames').
        parallax_samples : int, optional
            Parallax search (class docstring).
        projection : {"perspective", "orthographic"}, optional
            The output's rays (class docstring).

        Returns
        -------
        OctahedralImpostor
            The impostor.

        Raises
        ------
        ValidationError
            Bad arguments.
        """
        n = _check_frames(frames)
        lv = as_int(levels, "levels", lo=1)
        if len(surfaces) != n * n:
            raise ValidationError(expected_got("surfaces", f"{n * n} frames", len(surfaces)))
        level0 = [_store(s) for s in surfaces]
        return cls.from_stored(name, cameras, n, level0, levels=lv, out_size=out_size,
                               parallax_samples=parallax_samples, projection=projection)

    @classmethod
    def from_stored(cls, name: str, cameras: DomeCameras, frames: int, level0: Sequence[StoredSurface], *,
                    levels: int = DEFAULT_LEVELS, out_size: int | None = None,
                    parallax_samples: int = 1, projection: str = "perspective") -> OctahedralImpostor:
        """An impostor of stored level-0 frames, mip-mapped here.

        Parameters
        ----------
        name : str
            The asset's name.
        cameras : DomeCameras
            The camera rule of the frames.
        frames : int
            ``N``, frames a side.
        level0 : sequence of StoredSurface
            ``N * N`` square frames of one size, index ``j N + i``.
        levels : int, optional
            Mip levels.
        out_size : int, optional
            Side of the level-0 output images (default the frames').
        parallax_samples : int, optional
            Parallax search (class docstring).
        projection : {"perspective", "orthographic"}, optional
            The output's rays (class docstring).

        Returns
        -------
        OctahedralImpostor
            The impostor.
        """
        lv = as_int(levels, "levels", lo=1)
        stored = [list(level0)]
        if level0:
            m = level0[0].rgba.shape[0]
            if _side(m, lv - 1) < MIN_LEVEL_SIDE:
                raise ValidationError(expected_got("levels", f"a smallest level of >= {MIN_LEVEL_SIDE} px",
                                                   f"{lv} levels of {m} px frames"))
            work = [decode_surface(s) for s in level0]
            for level in range(1, lv):
                side = _side(m, level)
                stored.append([_store(downsample_surface(w, (side, side))) for w in work])
        return cls(name, cameras, frames, stored, out_size=out_size, parallax_samples=parallax_samples,
                   projection=projection)

    @property
    def distance(self) -> float:
        """``D``: the frames' eye planes' distance from the pivot (depth origin)."""
        return float(self.cameras.distance)

    @property
    def memory_bytes(self) -> int:
        """Stored bytes: every frame at every mip level, 9 bytes a pixel (RGBA uint8,
        normal int8 x 3, depth float16); the frame directions are computed from the grid,
        not stored, and the float32 working copies the runtime decodes are not counted."""
        return self._nbytes  # counted once: a runtime-checked protocol reads it on every isinstance

    def camera(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> CameraModel:
        """The camera of the surface of a direction at ``level`` (its depth is along this
        camera's axis): :meth:`DomeCameras.camera` of the clamped direction with the output's
        shape -- perspective, or the same pose orthographic (:attr:`projection`).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame (elevation clamped to ``[0, 90]``).
        level : int, optional
            Mip level.

        Returns
        -------
        CameraModel
            Object frame.
        """
        shape = self.level_shape(level)
        e = min(max(float(elevation_deg), 0.0), 90.0)
        if self.projection == "orthographic":
            return self.cameras.ortho_camera(azimuth_deg, e, shape)
        cam = self.cameras.camera(azimuth_deg, e)
        scale = shape[1] / cam.shape[1]
        return CameraModel("perspective", shape, cam.fx * scale, cam.fy * scale, (shape[1] - 1) / 2.0,
                           (shape[0] - 1) / 2.0, cam.znear, cam.zfar, cam.cam2world)

    def level_shape(self, level: int) -> tuple[int, int]:
        """Output image shape of level ``level``: ``round(out_size 2^-level)`` a side.

        Parameters
        ----------
        level : int
            Mip level, ``0`` full size.

        Returns
        -------
        (h, w) tuple of int
            Image shape.
        """
        lv = as_int(level, "level", lo=0, hi=self.levels - 1)
        side = _side(self.size[0], lv)
        return side, side

    def frame_surface(self, k: int, level: int = 0) -> ViewSurface:
        """Frame ``k`` (``= j N + i``) at mip ``level``, decoded.

        Parameters
        ----------
        k : int
            Frame index.
        level : int, optional
            Mip level.

        Returns
        -------
        ViewSurface
            New arrays.
        """
        k = as_int(k, "k", lo=0, hi=self.frames**2 - 1)
        lv = as_int(level, "level", lo=0, hi=self.levels - 1)
        return decode_surface(self._stored[lv][k])

    def stored_frame(self, k: int, level: int = 0) -> StoredSurface:
        """Frame ``k`` (``= j N + i``) at mip ``level`` as stored (shared, do not modify).

        Parameters
        ----------
        k : int
            Frame index.
        level : int, optional
            Mip level.

        Returns
        -------
        StoredSurface
            Straight sRGB albedo and alpha, int8 normals, float16 depth.
        """
        k = as_int(k, "k", lo=0, hi=self.frames**2 - 1)
        lv = as_int(level, "level", lo=0, hi=self.levels - 1)
        return self._stored[lv][k]

    def weights(self, azimuth_deg: float, elevation_deg: float) -> list[tuple[int, float]]:
        """The frames of the grid triangle around a viewing direction and their weights.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees (elevation in ``[-90, 90]``; below 0 clamped to 0).

        Returns
        -------
        list of (int, float)
            ``(frame index, weight)`` of the frames of positive weight (1 to 3 of them),
            weights summing to 1.

        Raises
        ------
        ValidationError
            A non-finite angle or an elevation outside ``[-90, 90]``.
        """
        a, e = _check_angles(azimuth_deg, elevation_deg)
        n = self.frames
        g = (hemi_oct_encode(direction(a, e)) + 1.0) * 0.5 * (n - 1)
        near = np.rint(g)
        g = np.where(np.abs(g - near) <= tol.IMP_GRID_SNAP, near, g)
        c = np.clip(np.floor(g), 0, n - 2).astype(int)
        fx, fy = (g - c).tolist()
        ci, cj = int(c[0]), int(c[1])
        mid = (ci + 1, cj) if fx > fy else (ci, cj + 1)
        out: dict[int, float] = {}
        for (i, j), w in (((ci, cj), min(1.0 - fx, 1.0 - fy)), ((ci + 1, cj + 1), min(fx, fy)),
                          (mid, abs(fx - fy))):
            if w > 0:
                out[j * n + i] = out.get(j * n + i, 0.0) + w
        total = sum(out.values())
        return [(k, w / total) for k, w in out.items()]

    def _frame_textures(self, k: int, level: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Working textures of frame ``k``: premultiplied albedo and alpha, (normal, h alpha),
        (alpha, h alpha); ``h`` the height above the frame's plane."""
        key = (level, k)
        tex = self._textures.get(key)
        if tex is None:
            s = decode_surface(self._stored[level][k])
            a = s.alpha
            h = np.where(np.isfinite(s.depth), np.float32(self.distance) - s.depth, np.float32(0.0)) * a
            nb = np.concatenate([s.normal, h[..., None]], axis=-1).astype(np.float32)
            tex = (np.ascontiguousarray(s.albedo), nb, np.ascontiguousarray(np.stack([a, h], axis=-1)))
            self._textures[key] = tex
        return tex

    @staticmethod
    def _height(tex_h: np.ndarray, maps: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Coverage and coverage-weighted height of a frame at ``maps`` (0 where empty)."""
        ah = cv2.remap(tex_h, maps[0], maps[1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                       borderValue=0)
        a = ah[..., 0]
        floor = np.float32(tol.ALPHA_FLOOR)
        h = np.where(a > floor, ah[..., 1] / np.maximum(a, floor), np.float32(0.0))
        return a, h

    @classmethod
    def _one_step(cls, base: np.ndarray, qk: np.ndarray, tex_h: np.ndarray, frame_maps: Any) -> np.ndarray:
        """The engines' parallax: the height at the plane's UV, then the ray at that height."""
        _, h = cls._height(tex_h, frame_maps(-base / qk))
        return (h - base) / qk

    def _march(self, base: np.ndarray, qk: np.ndarray, tex_h: np.ndarray, frame_maps: Any) -> np.ndarray:
        """Ray march over heights ``[r, -r]`` in ``parallax_samples`` steps, then one secant step."""
        r = np.float32(self.cameras.radius)
        n = self.parallax_samples
        mu = (r - base) / qk  # the ray's front: height r
        step = (np.float32(-2.0) * r / np.float32(n - 1)) / qk
        found = np.zeros(base.shape, bool)
        out = -base / qk  # no hit: the plane (empty there)
        prev_f = np.full(base.shape, np.nan, np.float32)
        for _ in range(n):
            a, h = self._height(tex_h, frame_maps(mu))
            f = base + mu * qk - h  # the ray's height above the frame's surface
            hit = ~found & (a > tol.ALPHA_FLOOR) & (f <= 0)
            ok = hit & np.isfinite(prev_f) & (prev_f > f)
            t = np.where(ok, prev_f / np.where(ok, prev_f - f, np.float32(1.0)), np.float32(1.0))
            out = np.where(hit, mu - (np.float32(1.0) - t) * step, out)
            found |= hit
            prev_f = np.where(a > tol.ALPHA_FLOOR, f, np.float32(np.nan))
            mu = mu + step
        return out

    def surface(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> ViewSurface:
        """The surface seen from direction ``(azimuth_deg, elevation_deg)`` (module docstring).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Viewing direction, degrees, object frame; elevation in ``[-90, 90]``, below 0
            clamped to 0 (the impostor has no views from below).
        level : int, optional
            Mip level, ``0`` full size.

        Returns
        -------
        ViewSurface
            Of :meth:`OctahedralImpostor.level_shape`, in the image frame of the direction's quad
            (:mod:`~morphkit.views.domecameras`); depth from the direction's eye plane.

        Raises
        ------
        ValidationError
            Bad angles or level.
        """
        lv = as_int(level, "level", lo=0, hi=self.levels - 1)
        a, e = _check_angles(azimuth_deg, elevation_deg)
        side = self.level_shape(lv)[0]
        half = float(self.half_extent[0])
        d = direction(a, e)
        right, up = quad_axes(a, e)
        # output pixel centres as quad offsets (scene units) along right and up
        t = (np.arange(side, dtype=np.float32) - np.float32((side - 1) / 2.0)) * np.float32(2.0 * half / side)
        xo, yo = t[None, :], -t[:, None]
        fside = _side(self.frame_side, lv)
        scale = fside / (2.0 * half)
        centre = (fside - 1) / 2.0
        albedo = np.zeros((side, side, 4), np.float32)
        normal = np.zeros((side, side, 3), np.float32)
        dsum = np.zeros((side, side), np.float32)
        dist = np.float32(self.distance)
        persp = self.projection == "perspective"
        for k, w in self.weights(a, e):
            tex_a, tex_nb, tex_h = self._frame_textures(k, lv)
            dk, rk, uk = self.frame_dirs[k], self.frame_right[k], self.frame_up[k]
            # the ray X(mu) = pivot + p + mu q through the quad point p = xo right + yo up:
            # q = p - D d from the eye (perspective), q = -d (orthographic). Its height above
            # frame k's plane is base + mu qk, its frame coordinates (fx0, fy0) + mu (qx, qy)
            base = xo * np.float32(right @ dk) + yo * np.float32(up @ dk)
            fx0 = xo * np.float32(right @ rk) + yo * np.float32(up @ rk)
            fy0 = xo * np.float32(right @ uk) + yo * np.float32(up @ uk)
            cos, drk, duk = np.float32(d @ dk), np.float32(d @ rk), np.float32(d @ uk)
            if persp:
                qk = np.minimum(base - dist * cos, -np.float32(tol.IMP_MIN_COS) * dist)
                qx, qy = fx0 - dist * drk, fy0 - dist * duk
            else:
                qk = np.full(base.shape, -max(float(cos), tol.IMP_MIN_COS), np.float32)
                qx, qy = -drk, -duk

            def frame_maps(mu: np.ndarray, fx0: np.ndarray = fx0, fy0: np.ndarray = fy0, qx: Any = qx,
                           qy: Any = qy) -> tuple[np.ndarray, np.ndarray]:
                mx = (fx0 + mu * qx) * np.float32(scale) + np.float32(centre)
                my = -(fy0 + mu * qy) * np.float32(scale) + np.float32(centre)
                return np.ascontiguousarray(mx, np.float32), np.ascontiguousarray(my, np.float32)

            if self.parallax_samples == 1:
                mu = self._one_step(base, qk, tex_h, frame_maps)
            else:
                mu = self._march(base, qk, tex_h, frame_maps)
            mx, my = frame_maps(mu)
            fa = cv2.remap(tex_a, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            fnb = cv2.remap(tex_nb, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            fal = fa[..., 3]
            h = np.where(fal > tol.ALPHA_FLOOR, fnb[..., 3] / np.maximum(fal, np.float32(tol.ALPHA_FLOOR)),
                         np.float32(0.0))
            mu = (h - base) / qk  # the ray's point at the frame's height there
            wk = np.float32(w)
            albedo += wk * fa
            normal += wk * fnb[..., :3]
            dsum += (wk * fal) * (dist * mu if persp else mu)  # depth beyond the quad's plane
        alpha = albedo[..., 3]
        drawn = alpha > tol.ALPHA_FLOOR
        norm = np.sqrt(np.einsum("ijk,ijk->ij", normal, normal))
        ok = drawn & (norm > 0)
        normal = np.where(ok[..., None], normal / np.maximum(norm, np.float32(tol.ALPHA_FLOOR))[..., None],
                          np.float32(0.0))
        dmean = dsum / np.maximum(alpha, np.float32(tol.ALPHA_FLOOR))
        depth = np.where(drawn, dist + dmean, np.float32(np.inf))
        albedo = np.where(drawn[..., None], np.clip(albedo, 0.0, 1.0), np.float32(0.0))
        return ViewSurface(albedo.astype(np.float32), normal.astype(np.float32), depth.astype(np.float32))


def _check_angles(azimuth_deg: Any, elevation_deg: Any) -> tuple[float, float]:
    """Finite azimuth, and elevation in ``[-90, 90]`` clamped to ``[0, 90]``."""
    try:
        a, e = float(azimuth_deg), float(elevation_deg)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got("azimuth_deg, elevation_deg", "numbers",
                                           f"{azimuth_deg!r}, {elevation_deg!r}")) from exc
    if not (math.isfinite(a) and math.isfinite(e)) or not -90.0 <= e <= 90.0:
        raise ValidationError(expected_got("azimuth_deg, elevation_deg",
                                           "a finite azimuth and an elevation in [-90, 90]", f"{a!r}, {e!r}"))
    return a, max(e, 0.0)


def bake_impostor(mesh: trimesh.Trimesh, renderer: PassRenderer, *, name: str = "asset",
                  frames: int = DEFAULT_FRAMES, frame_size: int = 64, levels: int = DEFAULT_LEVELS,
                  out_size: int | None = None,
                  appearance: str = "own", distance_factor: float = DISTANCE_FACTOR,
                  parallax_samples: int = 1, projection: str = "perspective", supersample: int = 3,
                  progress: bool = False) -> OctahedralImpostor:
    """Render ``mesh``'s octahedral impostor: ``frames x frames`` orthographic frames (module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Any mesh; normalised first (:func:`morphkit.meshes.normalize`), as
        :func:`~.baking.ringviews.bake_asset` does: the object frame is the normalised mesh's.
    renderer : PassRenderer
        Draws the frames' passes (:class:`morphkit.protocols.PassRenderer`, e.g.
        :class:`morphkit.render.Renderer`).
    name : str, optional
        The asset's name.
    frames : int, optional
        ``N >= 3``, frames a side.
    frame_size : int, optional
        Frame side ``m`` at level 0, pixels (``>= 8``; :func:`impostor_frame_size` for a budget).
    levels : int, optional
        Mip levels of the frames.
    out_size : int, optional
        Side of the level-0 output images (default ``frame_size``).
    appearance : {"own", "checker"}, optional
        The look (:func:`~morphkit.billboard.baking.bakelook.bake_items`).
    distance_factor : float, optional
        ``D / r`` of :meth:`DomeCameras.fit` (pivot, ``half_extent``, the depth origin ``D``).
    parallax_samples : int, optional
        Parallax search at run time (1: the engines' one step; :class:`OctahedralImpostor`).
    projection : {"perspective", "orthographic"}, optional
        The output's rays (:class:`OctahedralImpostor`).
    supersample : int, optional
        Supersampling of the frame renders (:meth:`~morphkit.render.Renderer.source_passes`).
    progress : bool, optional
        Show a progress bar (tqdm; silent when not a terminal).

    Returns
    -------
    OctahedralImpostor
        The impostor. Only albedo, normals, depth and coverage of the renders are kept
        (lights :func:`~morphkit.billboard.baking.bakelook.bake_lights`, ambient
        :data:`~morphkit.billboard.baking.bakelook.BAKE_AMBIENT` are passed, but the colour pass is dropped).

    Raises
    ------
    ValidationError
        Bad arguments, or a renderer that is not a :class:`~morphkit.protocols.PassRenderer`.
    MeshError
        ``mesh`` is not a usable mesh.
    """
    from tqdm import tqdm

    if not isinstance(name, str) or not name:
        raise ValidationError(expected_got("name", "a non-empty string", repr(name)))
    n = _check_frames(frames)
    m = as_int(frame_size, "frame_size", lo=8)
    lv = as_int(levels, "levels", lo=1)
    if _side(m, lv - 1) < MIN_LEVEL_SIDE:
        raise ValidationError(expected_got("levels", f"a smallest level of >= {MIN_LEVEL_SIDE} px",
                                           f"{lv} levels of {m} px frames"))
    appearance = check_appearance(appearance)
    if not isinstance(renderer, PassRenderer):
        raise ValidationError(expected_got("renderer", "a PassRenderer (morphkit.protocols; "
                                           "morphkit.render.Renderer is one)", type(renderer).__name__))
    norm = normalize(mesh)
    cams = DomeCameras.fit(norm, m, distance_factor=distance_factor)
    items, lights = bake_items(norm, appearance), bake_lights()
    az, el = _angles(hemi_oct_decode(frame_grid_uv(n).reshape(-1, 2)))
    level0 = []
    for a, e in tqdm(list(zip(az.tolist(), el.tolist(), strict=True)), desc=f"baking impostor {name}",
                     unit="frame", disable=None if progress else True, leave=False):
        p = renderer.source_passes(cams.ortho_camera(a, e, (m, m)), items, lights, ambient=BAKE_AMBIENT,
                                   supersample=supersample)
        alpha8 = np.rint(255.0 * np.clip(p.alpha, 0.0, 1.0)).astype(np.uint8)
        rgba = np.concatenate([p.albedo, alpha8[..., None]], axis=-1)
        level0.append(encode_surface(rgba, p.normal, p.depth))
    return OctahedralImpostor.from_stored(name, cams, n, level0, levels=lv, out_size=out_size,
                                          parallax_samples=parallax_samples, projection=projection)
