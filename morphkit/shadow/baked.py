"""The baked shadow atlas as data: :class:`BakedAtlas`, what :func:`~morphkit.shadow.atlas.bake_atlas`
renders and derives and :mod:`morphkit.shadow.formats.atlasfile` saves, and nothing computed at run time.

A :class:`BakedAtlas` is frozen: its maps, anchors, control points and rig are
set when it is made (baked or loaded) and read by everything after. The
run-time side -- caches of per-map building blocks and counts of fallbacks --
is :class:`~morphkit.shadow.runtime.AtlasRuntime`; the user-facing
:class:`~morphkit.shadow.atlas.ShadowAtlas` holds one of each. The geometry
here (projection of anchors, the anchor's light depth, the grid cell of a
position) is pure: the same answer for the same input, no cache.

How the maps, anchors and control points are made, and what they mean:
:mod:`morphkit.shadow.atlas`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..warp import grid_triangles
from .baking.fold import signed_areas
from .rig import LightRig

__all__ = ["BakedAtlas", "project_points", "anchor_depth_at"]


def project_points(T: np.ndarray, xy: np.ndarray, anchors: np.ndarray) -> np.ndarray:
    """Pixel positions ``(N, 2)`` of ``anchors (N, 3)`` moved by ``xy``, through texture matrix ``T``.

    Parameters
    ----------
    T : (4, 4) float64
        The light camera's texture matrix with the object at ``xy``
        (:meth:`~morphkit.camera.CameraModel.texture_matrix`).
    xy : (2,) float64
        The object's ground translation (world units).
    anchors : (N, 3) float64
        Points in world frame at translation ``(0, 0)``.

    Returns
    -------
    (N, 2) float64
        Their pixel positions.
    """
    q = (anchors + np.r_[xy, 0.0]) @ T[:, :3].T + T[:, 3]
    return q[:, :2] / q[:, 3:]


def anchor_depth_at(T: np.ndarray, anchor0: np.ndarray, xy: Any) -> float:
    """Light depth of the anchor ``anchor0`` moved by ``xy``, through texture matrix ``T``.

    Parameters
    ----------
    T : (4, 4) float64
        The light camera's texture matrix with the object at ``xy``.
    anchor0 : (3,) float64
        The object's anchor at translation ``(0, 0)`` (world frame).
    xy : (2,) float
        The object's ground translation (world units).

    Returns
    -------
    float
        Its depth in that light camera.
    """
    return float(T[2, :3] @ (anchor0 + np.r_[np.asarray(xy, float), 0.0]) + T[2, 3])


@dataclass(frozen=True, eq=False)
class BakedAtlas:
    """A baked k x k set of light-view depth maps with control points (frozen data).

    Parameters
    ----------
    rig : morphkit.shadow.rig.LightRig
        The light, object and motion range the maps were rendered for.
    xs, ys : (kx,) and (ky,) float64
        Sample positions of the object's ground translation along x and y
        (world units, ascending).
    maps : (ky, kx, H, W) float32
        Light-view linear depth maps, ``+inf`` background.
    anchors : (ky, kx, N, 3) float64
        Each map's control points lifted to 3-D, world frame, with the object
        at translation ``(0, 0)``.
    plane_anchors : (ky, kx, N, 3) float64
        The same control points lifted onto the plane through the object's
        anchor depth (the fold fallback).
    control_grid : (rows, cols)
        Control points per map, ``N = rows * cols``.
    anchor_kind : {"sample", "shared", "plane"}
        How the anchors were lifted (:func:`~morphkit.shadow.atlas.bake_atlas`).
    mesh_sha256 : str or None
        :func:`morphkit.meshes.shape_hash` of the occluder the maps were rendered from
        (what a playback checks its mesh against); None when not known.

    Attributes
    ----------
    triangles : (M, 3) int
        The control mesh's triangles (:func:`morphkit.warp.grid_triangles`).
    control : (ky, kx, N, 2) float64
        Each map's control points: its anchors projected at its own sample.
    plane_control : (ky, kx, N, 2) float64
        The same for the plane anchors (the fold fallback's sources).
    src_sign : (ky, kx, M) float64
        Orientation (sign of the area) of each map's source triangles.
    """

    rig: LightRig
    xs: np.ndarray
    ys: np.ndarray
    maps: np.ndarray  # (ky, kx, H, W) float32, +inf background
    anchors: np.ndarray  # (ky, kx, N, 3) world points at translation (0, 0)
    plane_anchors: np.ndarray  # (ky, kx, N, 3)
    control_grid: tuple[int, int]
    anchor_kind: str = "sample"
    mesh_sha256: str | None = None
    triangles: np.ndarray = field(init=False, repr=False)
    control: np.ndarray = field(init=False, repr=False)
    plane_control: np.ndarray = field(init=False, repr=False)
    src_sign: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        ky, kx = self.maps.shape[:2]
        tri = grid_triangles(*self.control_grid)

        def at_samples(anchors: np.ndarray) -> np.ndarray:
            return np.stack([np.stack([self.project(self.sample_xy(j, i), anchors[j, i])
                                       for i in range(kx)]) for j in range(ky)])

        control = at_samples(self.anchors)
        # orientation of each map's source triangles, for the fold test per frame
        sign = np.sign(np.stack([np.stack([signed_areas(control[j, i], tri)
                                           for i in range(kx)]) for j in range(ky)]))
        object.__setattr__(self, "triangles", tri)
        object.__setattr__(self, "control", control)
        object.__setattr__(self, "plane_control", at_samples(self.plane_anchors))
        object.__setattr__(self, "src_sign", sign)

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of every map (the light rig's image shape)."""
        return self.rig.shape

    @property
    def grid(self) -> tuple[int, int]:
        """``(ky, kx)`` sample grid."""
        return self.maps.shape[0], self.maps.shape[1]

    @property
    def memory_bytes(self) -> int:
        """Bytes of the precomputed, persisted data (maps + anchors + control points).

        At run time each map in use is also held premultiplied (2 channels), i.e.
        up to twice the maps' bytes more; the image-based baselines pay the same."""
        return int(self.maps.nbytes + self.anchors.nbytes + self.control.nbytes)

    def sample_xy(self, j: int, i: int) -> np.ndarray:
        """The ground translation ``(xs[i], ys[j])`` of map ``(j, i)``.

        Parameters
        ----------
        j, i : int
            The map's sample indices (row in ``ys``, column in ``xs``).

        Returns
        -------
        (2,) float64
            The sample position (world units).
        """
        return np.array([self.xs[i], self.ys[j]], dtype=np.float64)

    def project(self, xy: Any, anchors: np.ndarray) -> np.ndarray:
        """Pixel positions ``(N, 2)`` of ``anchors (N, 3)`` with the object at ``xy``
        (:func:`project_points`; uncached, see
        :meth:`AtlasRuntime.project <morphkit.shadow.runtime.AtlasRuntime.project>`).

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).
        anchors : (N, 3) float64
            Points in world frame at translation ``(0, 0)``.

        Returns
        -------
        (N, 2) float64
            Their pixel positions in the light camera at ``xy``.
        """
        xy = np.asarray(xy, dtype=np.float64)
        return project_points(self.rig.camera_at(xy).texture_matrix(), xy, anchors)

    def cell(self, xy: np.ndarray) -> tuple[int, int, float, float]:
        """``(j, i, v, u)``: the cell's lower sample indices and the fractions in it.

        Parameters
        ----------
        xy : (2,) float
            The object's ground translation (world units).

        Returns
        -------
        tuple
            ``(j, i, v, u)``: ints, then fractions in ``[0, 1]`` (clamped).
        """
        # scalar min/max, not np.clip (per frame; the same values, -0.0 included)
        i = min(max(int(np.searchsorted(self.xs, xy[0], side="right")) - 1, 0), len(self.xs) - 2)
        j = min(max(int(np.searchsorted(self.ys, xy[1], side="right")) - 1, 0), len(self.ys) - 2)
        u = float((xy[0] - self.xs[i]) / (self.xs[i + 1] - self.xs[i]))
        v = float((xy[1] - self.ys[j]) / (self.ys[j + 1] - self.ys[j]))
        return j, i, min(max(v, 0.0), 1.0), min(max(u, 0.0), 1.0)
