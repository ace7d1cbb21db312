"""The camera rule of billboards seen from any height: views that look at the pivot.

A view direction is ``(azimuth a, elevation e)`` in degrees, object frame
(azimuth as in :mod:`morphkit.billboard.ring`: ``0`` is the asset's front ``+x``, counter-clockwise
about ``+z``; elevation above the horizontal plane through the pivot, up to 90
straight above). Its unit direction from the pivot towards the eye is

    ``d(a, e) = (cos e cos a, cos e sin a, sin e)``

and the billboard **quad** is the square through the pivot perpendicular to ``d``
with

    ``up(a, e) = (-sin e cos a, -sin e sin a, cos e)``   (``= dd/de``),
    ``right(a, e) = up x d``

and half size ``half_extent`` on both axes. ``up`` is defined at every direction,
straight above included, where it is ``-(cos a, sin a, 0)``: the azimuth then
only turns the image about the vertical (the scene passes the azimuth that makes
the quad's up the camera's, :class:`~morphkit.billboard.frames.facing.ViewpointFacing`). At
``e = 0`` the quad is the ring's (:mod:`morphkit.billboard.cameras`): ``up = +z``,
``right = (-sin a, cos a, 0)``.

The **camera** of a direction (:meth:`DomeCameras.camera`) sits at
``pivot + D d``, looks at the pivot with image ``x`` along ``right`` and image
``-y`` along ``up``, and its square image covers the quad exactly (pixel-centre
convention, :mod:`morphkit.conventions`): ``f = (W/2) D / half_extent``, principal
point at the image centre. ``half_extent`` is the bounding sphere's (radius ``r``
about ``pivot``) tangent cone cut by the quad's plane, ``r D / sqrt(D^2 - r^2)``,
plus :data:`~.framing.FRAME_MARGIN`: the object stays inside the image from every
direction. Level ``l`` of the pyramid has shape ``level_shape(l)`` (about ``2^-l``
of level 0) and the same quad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import trimesh

from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array, as_int, as_positive
from .framing import DISTANCE_FACTOR, FRAME_MARGIN, check_distance_factor

__all__ = ["DomeCameras", "direction", "quad_axes"]


def direction(azimuth_deg: np.ndarray | float, elevation_deg: np.ndarray | float) -> np.ndarray:
    """Unit directions ``d(a, e)`` from the pivot towards the eye, object frame.

    Parameters
    ----------
    azimuth_deg, elevation_deg : float or array
        Degrees (broadcast together).

    Returns
    -------
    (..., 3) float64
        Unit vectors.
    """
    a = np.radians(np.asarray(azimuth_deg, dtype=np.float64))
    e = np.radians(np.asarray(elevation_deg, dtype=np.float64))
    a, e = np.broadcast_arrays(a, e)
    return np.stack([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)], axis=-1)


def quad_axes(azimuth_deg: np.ndarray | float, elevation_deg: np.ndarray | float
              ) -> tuple[np.ndarray, np.ndarray]:
    """``(right, up)``: the quad's unit axes of directions ``(a, e)`` (module docstring).

    Parameters
    ----------
    azimuth_deg, elevation_deg : float or array
        Degrees (broadcast together).

    Returns
    -------
    right, up : (..., 3) float64
        Unit vectors, object frame.
    """
    a = np.radians(np.asarray(azimuth_deg, dtype=np.float64))
    e = np.radians(np.asarray(elevation_deg, dtype=np.float64))
    a, e = np.broadcast_arrays(a, e)
    up = np.stack([-np.sin(e) * np.cos(a), -np.sin(e) * np.sin(a), np.cos(e)], axis=-1)
    right = np.stack([-np.sin(a), np.cos(a), np.zeros_like(a)], axis=-1)  # = up x d
    return right, up


@dataclass(frozen=True)
class DomeCameras:
    """The camera rule of one asset seen from any direction (module docstring).

    Parameters
    ----------
    pivot : (3,) float
        Quad centre (the bounding sphere's centre), object frame.
    distance : float
        Camera distance ``D`` from the pivot, scene units.
    radius : float
        Bounding sphere radius ``r`` about the pivot (``0 < r < D``).
    shape : int
        Level-0 images are ``(shape, shape)`` (square: the quad is square).
    """

    pivot: np.ndarray
    distance: float
    radius: float
    shape: tuple[int, int]

    def __post_init__(self) -> None:
        object.__setattr__(self, "pivot", as_finite_array(self.pivot, "pivot", shape=(3,)))
        d = as_positive(self.distance, "distance")
        r = as_positive(self.radius, "radius")
        if not r < d:
            raise ValidationError(expected_got("radius", f"< the camera distance {d:g}", r))
        shape = self.shape
        n = as_int(shape if isinstance(shape, int | np.integer) else shape[0], "shape", lo=8)
        if not isinstance(shape, int | np.integer) and tuple(shape) != (n, n):
            raise ValidationError(expected_got("shape", "a square image (n, n)", tuple(shape)))
        object.__setattr__(self, "distance", d)
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "shape", (n, n))

    @classmethod
    def fit(cls, mesh: trimesh.Trimesh, size: int, *,
            distance_factor: float = DISTANCE_FACTOR) -> DomeCameras:
        """The rule for ``mesh`` (object frame): pivot at its bounding box's centre,
        ``r`` the largest vertex distance from it, ``D = distance_factor r``.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The (normalised) mesh.
        size : int
            Level-0 image side, pixels.
        distance_factor : float
            ``D / r`` (:data:`~.framing.DISTANCE_FACTOR_RANGE`).

        Returns
        -------
        DomeCameras
            The rule.
        """
        factor = check_distance_factor(distance_factor)
        pts = np.asarray(mesh.vertices, dtype=np.float64)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pivot = 0.5 * (lo + hi)
        radius = float(np.max(np.linalg.norm(pts - pivot, axis=1)))
        if not radius > 0:
            raise ValidationError(expected_got("mesh", "an object of positive size", f"radius {radius}"))
        return cls(pivot, factor * radius, radius, (int(size), int(size)))

    @property
    def half_extent(self) -> tuple[float, float]:
        """``(half, half)``: the square quad's half size (module docstring)."""
        d, r = self.distance, self.radius
        half = r * d / math.sqrt(d * d - r * r) * (1.0 + FRAME_MARGIN)
        return half, half

    def level_shape(self, level: int) -> tuple[int, int]:
        """Image shape of pyramid level ``level`` (``round(n 2^-level)``, at least 1).

        Parameters
        ----------
        level : int
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w) tuple of int
            Image shape.
        """
        lv = as_int(level, "level", lo=0)
        n = max(1, round(self.shape[0] / 2**lv))
        return n, n

    def eye(self, azimuth_deg: float, elevation_deg: float) -> np.ndarray:
        """``(3,)`` camera centre of direction ``(a, e)``, object frame.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Degrees.

        Returns
        -------
        (3,) float64
            ``pivot + D d(a, e)``.
        """
        return self.pivot + self.distance * direction(azimuth_deg, elevation_deg)

    def camera(self, azimuth_deg: float, elevation_deg: float, level: int = 0) -> CameraModel:
        """The perspective camera of direction ``(a, e)`` at ``level`` (module docstring).

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Degrees, object frame.
        level : int, optional
            Pyramid level.

        Returns
        -------
        CameraModel
            Object frame; its image covers the quad exactly.
        """
        h, w = self.level_shape(level)
        right, up = quad_axes(azimuth_deg, elevation_deg)
        d = direction(azimuth_deg, elevation_deg)
        pose = np.eye(4)
        pose[:3, 0], pose[:3, 1], pose[:3, 2] = right, -up, -d
        pose[:3, 3] = self.pivot + self.distance * d
        f = 0.5 * w * self.distance / self.half_extent[0]
        near, far = self.depth_range()
        return CameraModel("perspective", (h, w), f, f, (w - 1) / 2.0, (h - 1) / 2.0, near, far, pose)

    def depth_range(self) -> tuple[float, float]:
        """The views' near and far planes (linear depth, scene units): every drawn depth lies in it.

        Returns
        -------
        tuple of float
            ``(znear, zfar)``: ``D - 1.5 r`` (at least ``D / 1000``) and ``D + 1.5 r``.
        """
        d, r = self.distance, self.radius
        return max(d - 1.5 * r, 1e-3 * d), d + 1.5 * r

    def ortho_camera(self, azimuth_deg: float, elevation_deg: float, shape: tuple[int, int]) -> CameraModel:
        """An orthographic camera along ``-d(a, e)`` whose image of ``shape`` covers the quad.

        Parameters
        ----------
        azimuth_deg, elevation_deg : float
            Degrees, object frame.
        shape : tuple of 2 int
            ``(h, w)`` of its image.

        Returns
        -------
        CameraModel
            Object frame, same pose as :meth:`camera`.
        """
        h, w = shape
        right, up = quad_axes(azimuth_deg, elevation_deg)
        d = direction(azimuth_deg, elevation_deg)
        pose = np.eye(4)
        pose[:3, 0], pose[:3, 1], pose[:3, 2] = right, -up, -d
        pose[:3, 3] = self.pivot + self.distance * d
        f = 0.5 * w / self.half_extent[0]
        r = self.radius
        return CameraModel("orthographic", (h, w), f, 0.5 * h / self.half_extent[1], (w - 1) / 2.0,
                           (h - 1) / 2.0, self.distance - 1.5 * r, self.distance + 1.5 * r, pose)
