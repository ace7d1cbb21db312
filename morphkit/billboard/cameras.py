"""The cameras of a billboard asset and the quad their images map onto.

The camera rule
---------------
A camera with centre ``eye`` (object frame, off the pivot's vertical line) has
a **horizontal** optical axis, towards the pivot's vertical line: its image
plane is vertical, and its principal point is shifted up
(``cy = (H - 1)/2 - fy tan e``, ``tan e`` = height of ``eye`` above the pivot
over its horizontal distance ``rho``) so that the pivot projects to the image
centre ``((W - 1)/2, (H - 1)/2)`` (:meth:`QuadCameras.camera_at`). A reference
view at azimuth ``a`` (degrees, :mod:`.ring`) and elevation ``e`` has
``eye = pivot + D (cos e cos a, cos e sin a, sin e)``
(:meth:`QuadCameras.camera`), ``D = f r``, ``f`` the distance factor (default
:data:`DISTANCE_FACTOR`), ``r`` the radius of
the mesh's bounding sphere about the pivot; the view a morph shows between two
references is the one from the point on the chord between their centres
(:meth:`QuadCameras.chord_camera`).

The quad
--------
The billboard quad at azimuth ``a`` is the vertical rectangle through the
pivot facing ``(cos a, sin a)``, with ``right = (-sin a, cos a, 0)``,
``up = +z`` and half width/height ``half_extent``. A camera of the rule is a
central projection onto the plane of its quad, and the focal lengths
``fx = (W/2) D cos(e) / half_width``, ``fy = (H/2) D cos(e) / half_height``
(``rho`` in place of ``D cos(e)`` off the ring) make the image cover the quad
exactly: image ``(h, w)``, covering
``[-0.5, w - 0.5] x [-0.5, h - 0.5]`` (:mod:`morphkit.conventions`), has its
top-left corner at ``pivot - half_width right + half_height up`` and its
bottom-right corner at ``pivot + half_width right - half_height up``. Seen
from its own camera, the textured quad is exactly the rendered view. The same
rule holds at every azimuth (references and in-between views alike) and at
every level of the pyramid (level ``l`` has shape ``level_shape(l)``, about
``2^-l`` of level 0, and the same quad), so one quad geometry serves every
image of the asset. ``half_extent`` is fitted once per asset so that the
object stays inside the image from every azimuth at that elevation, with
pixels square (``half_width / half_height = W / H``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import trimesh

from .. import tol
from ..camera import CameraModel, look_at
from ..errors import ValidationError, expected_got
from ..validate import as_finite_array, as_int, as_positive, as_shape
from ..views.framing import DISTANCE_FACTOR, DISTANCE_FACTOR_RANGE, FRAME_MARGIN, check_distance_factor

__all__ = ["QuadCameras", "DISTANCE_FACTOR", "DISTANCE_FACTOR_RANGE", "FRAME_MARGIN", "check_distance_factor"]


#: Azimuth step (degrees) of the directions the quad is fitted over (plus the ring's own).
_FIT_STEP_DEG = 5.0


@dataclass(frozen=True)
class QuadCameras:
    """The camera rule and quad of one asset (see the module docstring).

    Parameters
    ----------
    pivot : (3,) float
        Quad centre in the object frame.
    distance : float
        Camera distance ``D`` from the pivot (scene units).
    elevation_deg : float
        Camera elevation, degrees.
    half_extent : (2,) float
        ``(half_width, half_height)`` of the quad, scene units.
    shape : (H, W)
        Level-0 image shape.
    """

    pivot: np.ndarray
    distance: float
    elevation_deg: float
    half_extent: tuple[float, float]
    shape: tuple[int, int]

    def __post_init__(self) -> None:
        pivot = as_finite_array(self.pivot, "pivot", shape=(3,)).copy()
        pivot.setflags(write=False)
        object.__setattr__(self, "pivot", pivot)
        object.__setattr__(self, "distance", as_positive(self.distance, "distance"))
        e = float(self.elevation_deg)
        if not 0.0 <= e <= 60.0:
            raise ValidationError(expected_got("elevation_deg", "an angle in [0, 60]", e))
        object.__setattr__(self, "elevation_deg", e)
        he = as_finite_array(self.half_extent, "half_extent", shape=(2,))
        if np.any(he <= 0):
            raise ValidationError(expected_got("half_extent", "two positive half sizes", he.tolist()))
        object.__setattr__(self, "half_extent", (float(he[0]), float(he[1])))
        object.__setattr__(self, "shape", as_shape(self.shape, "shape"))

    @property
    def horizontal_distance(self) -> float:
        """``D cos e``: the distance from a camera to the plane of its quad."""
        return self.distance * math.cos(math.radians(self.elevation_deg))

    def level_shape(self, level: int) -> tuple[int, int]:
        """Image shape of pyramid level ``level`` (``round(2^-level)`` of level 0, at least 1).

        Parameters
        ----------
        level : int
            Pyramid level, ``0`` full size.

        Returns
        -------
        (h, w) tuple of int
            Image shape in pixels.
        """
        lv = _level(level)
        h, w = self.shape
        return max(1, round(h / 2**lv)), max(1, round(w / 2**lv))

    def eye(self, azimuth_deg: float) -> np.ndarray:
        """``(3,)`` camera centre of the rule at ``azimuth_deg`` (object frame).

        Parameters
        ----------
        azimuth_deg : float
            Azimuth, degrees, object frame.

        Returns
        -------
        (3,) float64
            Camera centre, object frame.
        """
        a = float(azimuth_deg)
        if not math.isfinite(a):
            raise ValidationError(expected_got("azimuth_deg", "a finite angle", a))
        ar, er = math.radians(a), math.radians(self.elevation_deg)
        return self.pivot + self.distance * np.array([math.cos(er) * math.cos(ar),
                                                      math.cos(er) * math.sin(ar), math.sin(er)])

    def camera(self, azimuth_deg: float, level: int = 0) -> CameraModel:
        """The camera of the rule at ``azimuth_deg`` (on the ring, distance ``D``) for
        images of ``level_shape(level)``: a reference view's camera.

        Parameters
        ----------
        azimuth_deg : float
            Azimuth, degrees, object frame.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        CameraModel
            Perspective camera, ``cam2world`` in the object frame.
        """
        return self.camera_at(self.eye(azimuth_deg), level)

    def chord_camera(self, azimuth0_deg: float, azimuth1_deg: float, s: float, level: int = 0
                     ) -> CameraModel:
        """The camera whose view a morph of the views at ``azimuth0_deg`` and ``azimuth1_deg``
        shows at ``s``: centre ``(1 - s) eye(azimuth0) + s eye(azimuth1)`` (Seitz & Dyer's
        in-between camera, on the chord between the two), image plane and quad by the rule.

        Parameters
        ----------
        azimuth0_deg, azimuth1_deg : float
            Azimuths of the two views, degrees, object frame.
        s : float
            Fraction in ``[0, 1]`` from the first view to the second.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        CameraModel
            Perspective camera, ``cam2world`` in the object frame.
        """
        s = float(s)
        if not 0.0 <= s <= 1.0:
            raise ValidationError(expected_got("s", "a number in [0, 1]", s))
        return self.camera_at((1.0 - s) * self.eye(azimuth0_deg) + s * self.eye(azimuth1_deg), level)

    def camera_at(self, eye: np.ndarray, level: int = 0) -> CameraModel:
        """The camera of the rule with centre ``eye`` (object frame; not on the pivot's
        vertical line): optical axis horizontal towards that line, image plane parallel
        to the quad facing ``eye``, pivot at the image centre, quad edges on image edges.

        Depth range ``[D/10, 2 D]``: the bounding sphere (radius ``D / f``, ``f`` the distance factor)
        lies inside it for the ring's cameras and any point between two of them.

        Parameters
        ----------
        eye : (3,) float
            Camera centre, object frame.
        level : int, optional
            Pyramid level, ``0`` full size.

        Returns
        -------
        CameraModel
            Perspective camera, ``cam2world`` in the object frame.
        """
        e = as_finite_array(eye, "eye", shape=(3,))
        h, w = self.level_shape(level)
        horiz = e[:2] - self.pivot[:2]
        rho = float(np.hypot(*horiz))
        if not rho > tol.BB_ABOVE_RATIO * self.distance:
            raise ValidationError(expected_got("eye", "a point off the pivot's vertical line", e.tolist()))
        fwd = np.array([-horiz[0] / rho, -horiz[1] / rho, 0.0])
        tan_e = (e[2] - self.pivot[2]) / rho
        fx = 0.5 * w * rho / self.half_extent[0]
        fy = 0.5 * h * rho / self.half_extent[1]
        return CameraModel("perspective", (h, w), fx, fy, 0.5 * (w - 1), 0.5 * (h - 1) - fy * tan_e,
                           0.1 * self.distance, 2.0 * self.distance, look_at(e, e + fwd))

    def quad_corners(self, azimuth_deg: float) -> np.ndarray:
        """``(4, 3)`` corners of the quad at ``azimuth_deg`` in the object frame: top-left,
        top-right, bottom-right, bottom-left (the image corners, in that order).

        Parameters
        ----------
        azimuth_deg : float
            Viewing azimuth, degrees, object frame.

        Returns
        -------
        (4, 3) float64
            Quad corners, object frame.
        """
        ar = math.radians(float(azimuth_deg))
        right = np.array([-math.sin(ar), math.cos(ar), 0.0])
        up = np.array([0.0, 0.0, 1.0])
        hw, hh = self.half_extent
        return np.array([self.pivot + sx * hw * right + sy * hh * up
                         for sx, sy in ((-1, 1), (1, 1), (1, -1), (-1, -1))])

    @classmethod
    def fit(cls, mesh: trimesh.Trimesh, shape: tuple[int, int], elevation_deg: float,
            azimuths_deg: np.ndarray | None = None, *, distance_factor: float = DISTANCE_FACTOR
            ) -> QuadCameras:
        """The rule for ``mesh`` (in its object frame): pivot at the centre of its
        bounding box's vertical axis ``(0, 0, z_max / 2)`` shifted to the box's ``x, y``
        centre, ``D = distance_factor r`` and the smallest quad (grown by
        :data:`FRAME_MARGIN`, square pixels) that holds the object's projection from
        every azimuth in 5-degree steps and in ``azimuths_deg``.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            The object, its own frame.
        shape : (H, W)
            Level-0 image shape in pixels.
        elevation_deg : float
            Camera elevation above the horizontal, degrees.
        azimuths_deg : array of float, optional
            Extra azimuths (degrees) the quad must cover.
        distance_factor : float
            Camera distance in radii ``r`` of the bounding sphere, in
            :data:`DISTANCE_FACTOR_RANGE` (default :data:`DISTANCE_FACTOR`).

        Returns
        -------
        QuadCameras
            The fitted rule.
        """
        shape = as_shape(shape, "shape")
        factor = check_distance_factor(distance_factor)
        lo, hi = np.asarray(mesh.bounds, dtype=np.float64)
        pivot = np.array([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])])
        try:
            pts = np.asarray(mesh.convex_hull.vertices, dtype=np.float64)
        except Exception:  # qhull refuses flat or degenerate point sets: use every vertex
            pts = np.asarray(mesh.vertices, dtype=np.float64)
        radius = float(np.max(np.linalg.norm(pts - pivot, axis=1)))
        if not radius > 0:
            raise ValidationError(expected_got("mesh", "an object of positive size", f"radius {radius}"))
        rule = cls(pivot, factor * radius, elevation_deg, (1.0, 1.0), shape)
        az = np.arange(0.0, 360.0, _FIT_STEP_DEG)
        if azimuths_deg is not None:
            az = np.r_[az, np.asarray(azimuths_deg, dtype=np.float64)]
        dh = rule.horizontal_distance
        tan_e = math.tan(math.radians(rule.elevation_deg))
        umax = vmax = 0.0
        for a in az:
            cam = rule.camera(float(a))
            p = pts @ cam.world2cam[:3, :3].T + cam.world2cam[:3, 3]
            u = p[:, 0] / p[:, 2] * dh
            v = (p[:, 1] / p[:, 2] - tan_e) * dh
            umax, vmax = max(umax, float(np.max(np.abs(u)))), max(vmax, float(np.max(np.abs(v))))
        h, w = shape
        hw = (1.0 + FRAME_MARGIN) * max(umax, vmax * w / h)
        return cls(pivot, rule.distance, rule.elevation_deg, (hw, hw * h / w), shape)


def _level(level: int) -> int:
    return as_int(level, "level", lo=0)
