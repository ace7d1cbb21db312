"""Exact shadow references by ray casting, independent of any shadow map.

For each receiver point, a ray is cast towards the light (trimesh ray queries;
Embree through ``embreex`` when installed, trimesh's numpy/rtree intersector
otherwise) and tested against the occluding object. A hard-shadow visibility
is 0 or 1; an area light's visibility is the fraction of its samples that a
point sees. Rays are cast in the object's own frame (the object pose is rigid,
so distances are preserved), so the mesh's acceleration structure is built
once per mesh and reused for every pose.

Receivers are not occluders. Ray origins are pushed :data:`morphkit.tol.RAY_OFFSET`
towards the light so points on the object itself (self-shadowing) do not hit
their own triangle.

Cut-outs. An occluder whose own look is cut out (glTF ``alphaMode`` ``MASK``: a
leaf card, :func:`morphkit.imaging.cutout.mesh_cutout`) casts the shadow of its opaque
texels only, as the renderer draws it into a light's depth map: at each hit, the
triangle and barycentrics give the UV, the UV the texture's alpha (times the base
colour factor's and the vertex colour's alpha; sampled bilinearly as OpenGL does,
:mod:`morphkit.imaging.cutout`), and a hit below the cutoff is a hole: the ray is cast
again from :data:`~morphkit.tol.RAY_OFFSET` past it, at most
:data:`~morphkit.tol.CUTOUT_MAX_LAYERS` times (a ray still in holes then counts
as shadowed, with a :class:`CutoutLayersWarning`). The look is that of the mesh's
own visuals whatever colour a scene gives the object (a colour only paints).
Meshes without cut-outs (no ``TextureVisuals``, or an opaque material) take the
path without any of this: the same rays, the same results, the same cost.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import trimesh

from .. import tol
from ..errors import ValidationError, expected_got
from ..scene import AreaLight, DirectionalLight, PointLight, SceneObject
from ..validate import as_finite_array, as_positive, as_shape
from .cutout import Cutout, mesh_cutout

__all__ = ["hard_visibility", "area_visibility", "sampled_visibility", "receiver_grid",
           "ground_pixels", "CutoutLayersWarning"]

_CHUNK = 1 << 20  # rays per intersector call: bounds memory on 1M-ray queries


class CutoutLayersWarning(UserWarning):
    """Shadow rays crossed :data:`~morphkit.tol.CUTOUT_MAX_LAYERS` cut-out holes and were
    counted as shadowed."""


def _occluded(obj: SceneObject, origins: np.ndarray, dirs: np.ndarray,
              dist: np.ndarray) -> np.ndarray:
    """True where the ray ``origins + t dirs``, ``0 < t < dist``, hits the object."""
    R, t = obj.pose[:3, :3], obj.pose[:3, 3]
    o_local = (origins - t) @ R  # world -> object frame (R orthonormal)
    d_local = dirs @ R
    out = np.zeros(len(origins), bool)
    ray = obj.mesh.ray
    cut = mesh_cutout(obj.mesh)
    if cut is not None:
        for s in range(0, len(origins), _CHUNK):
            sl = slice(s, s + _CHUNK)
            out[sl] = _occluded_cutout(obj.mesh, cut, o_local[sl], d_local[sl], dist[sl])
        return out
    for s in range(0, len(origins), _CHUNK):
        sl = slice(s, s + _CHUNK)
        if np.all(np.isinf(dist[sl])):
            out[sl] = ray.intersects_any(o_local[sl], d_local[sl])
            continue
        loc, idx_ray, _ = ray.intersects_location(o_local[sl], d_local[sl], multiple_hits=False)
        if len(idx_ray):
            hit_t = np.einsum("ij,ij->i", loc - o_local[sl][idx_ray], d_local[sl][idx_ray])
            blocked = hit_t < dist[sl][idx_ray]
            out[s + idx_ray[blocked]] = True
    return out


def _occluded_cutout(mesh: trimesh.Trimesh, cut: Cutout, origins: np.ndarray, dirs: np.ndarray,
                     dist: np.ndarray) -> np.ndarray:
    """:func:`_occluded` for a cut-out mesh (object frame): a hit on a hole casts again
    from just past it (module notes)."""
    out = np.zeros(len(origins), bool)
    o = np.array(origins, dtype=np.float64)
    remaining = np.array(dist, dtype=np.float64)
    live = np.arange(len(o))
    for _layer in range(tol.CUTOUT_MAX_LAYERS):
        if not len(live):
            return out
        loc, idx, tri = mesh.ray.intersects_location(o[live], dirs[live], multiple_hits=False)
        rays = live[idx]
        hit_t = np.einsum("ij,ij->i", loc - o[rays], dirs[rays])
        near = hit_t < remaining[rays]
        rays, loc, tri, hit_t = rays[near], loc[near], tri[near], hit_t[near]
        bary = trimesh.triangles.points_to_barycentric(mesh.triangles[tri], loc)
        solid = cut.opaque(tri, bary)
        out[rays[solid]] = True
        live = rays[~solid]  # through a hole: on from just past it
        o[live] = loc[~solid] + dirs[live] * tol.RAY_OFFSET
        remaining[live] -= hit_t[~solid] + tol.RAY_OFFSET
    if len(live):
        warnings.warn(f"{len(live)} shadow rays crossed {tol.CUTOUT_MAX_LAYERS} cut-out holes "
                      "(tol.CUTOUT_MAX_LAYERS) and count as shadowed", CutoutLayersWarning, stacklevel=4)
        out[live] = True
    return out


def hard_visibility(points: np.ndarray, light: DirectionalLight | PointLight,
                    obj: SceneObject) -> np.ndarray:
    """Visibility (1 lit, 0 shadowed) of ``points (N, 3)`` from a point or
    directional light, occluded by ``obj``. Returns float32 ``(N,)``.

    A cut-out occluder shadows with its opaque texels only (module notes, "Cut-outs").

    Parameters
    ----------
    points : (N, 3) float
        Receiver points, world frame.
    light : DirectionalLight or PointLight
        The light.
    obj : SceneObject
        The occluder.

    Returns
    -------
    (N,) float32
        ``1`` lit, ``0`` shadowed.

    Raises
    ------
    ValidationError
        Bad ``points``, ``obj`` or ``light``.
    MeshError
        The occluder's visuals cannot be read (:func:`morphkit.meshes.look.mesh_look`).

    Warns
    -----
    CutoutLayersWarning
        Rays crossed :data:`~morphkit.tol.CUTOUT_MAX_LAYERS` cut-out holes (counted as shadowed).

    Examples
    --------
    A unit cube at height 1.5, lit from straight above, shadows the middle
    of a 4 x 4 grid on the ground square ``[-1, 1]^2`` (pixel centres at
    ``+-0.25`` fall under it, those at ``+-0.75`` do not).

    >>> import numpy as np
    >>> import trimesh
    >>> from morphkit.imaging.groundtruth import hard_visibility, receiver_grid
    >>> from morphkit.scene import DirectionalLight, SceneObject, translation
    >>> cube = SceneObject(trimesh.creation.box(extents=(1.0, 1.0, 1.0)), translation(0.0, 0.0, 1.5))
    >>> ground = receiver_grid(1.0, (4, 4)).reshape(-1, 3)
    >>> hard_visibility(ground, DirectionalLight(np.array([0.0, 0.0, -1.0])), cube).reshape(4, 4)
    array([[1., 1., 1., 1.],
           [1., 0., 0., 1.],
           [1., 0., 0., 1.],
           [1., 1., 1., 1.]], dtype=float32)
    """
    pts = as_finite_array(points, "points", shape=(None, 3))
    if not isinstance(obj, SceneObject):
        raise ValidationError(expected_got("obj", "a morphkit SceneObject", type(obj).__name__))
    if isinstance(light, AreaLight):
        raise ValidationError(expected_got("light", "a point or directional light (use "
                                           "area_visibility for an AreaLight)", "an AreaLight"))
    dirs, dist = light.to_light(pts)
    origins = pts + dirs * tol.RAY_OFFSET
    return (~_occluded(obj, origins, dirs, dist - tol.RAY_OFFSET)).astype(np.float32)


def area_visibility(points: np.ndarray, light: AreaLight, obj: SceneObject, n_u: int,
                    n_v: int | None = None, rng: np.random.Generator | None = None) -> np.ndarray:
    """Fraction ``(N,)`` float32 of an area light's ``n_u x n_v`` samples (cell
    centres, jittered when ``rng`` is given) that each point sees.

    Parameters
    ----------
    points : (N, 3) float
        Receiver points, world frame.
    light : AreaLight
        The light.
    obj : SceneObject
        The occluder.
    n_u : int
        Samples along ``u``.
    n_v : int, optional
        Samples along ``v``; defaults to ``n_u``.
    rng : numpy.random.Generator, optional
        Jitter source; ``None`` for cell centres.

    Returns
    -------
    (N,) float32
        Visible fraction in ``[0, 1]``.
    """
    return sampled_visibility(points, light.point_lights(n_u, n_v, rng), obj)


def sampled_visibility(points: np.ndarray, lights: Sequence[PointLight], obj: SceneObject
                       ) -> np.ndarray:
    """Fraction ``(N,)`` float32 of the point ``lights`` (an area light's samples)
    that each point sees.

    Parameters
    ----------
    points : (N, 3) float
        Receiver points, world frame.
    lights : sequence of PointLight
        The light samples.
    obj : SceneObject
        The occluder.

    Returns
    -------
    (N,) float32
        Visible fraction in ``[0, 1]``.
    """
    if len(lights) == 0:
        raise ValidationError(expected_got("lights", "at least one point light", "none"))
    pts = as_finite_array(points, "points", shape=(None, 3))
    acc = np.zeros(len(pts), np.float64)
    for pl in lights:
        acc += hard_visibility(pts, pl, obj)
    return (acc / len(lights)).astype(np.float32)


def receiver_grid(half_size: float, shape: tuple[int, int]) -> np.ndarray:
    """World points ``(H, W, 3)`` at the pixel centres of a top-down image of the
    ground square ``[-half_size, half_size]^2`` (``z = 0``).

    Pixel ``(x, y)`` maps to world ``(-h + (x + 0.5) s_x, h - (y + 0.5) s_y, 0)``
    with ``s = 2 h / (W, H)``: world ``+x`` is image right, world ``+y`` image up.

    Parameters
    ----------
    half_size : float
        Half side of the ground square, scene units.
    shape : (H, W)
        Image shape in pixels.

    Returns
    -------
    (H, W, 3) float64
        World points.

    Examples
    --------
    Pixel ``(0, 0)`` of a 4 x 4 image of ``[-1, 1]^2`` is the top-left cell,
    centred at ``(-0.75, 0.75)``; :func:`ground_pixels` maps it back.

    >>> from morphkit.imaging.groundtruth import ground_pixels, receiver_grid
    >>> grid = receiver_grid(1.0, (4, 4))
    >>> grid.shape, grid[0, 0]
    ((4, 4, 3), array([-0.75,  0.75,  0.  ]))
    >>> ground_pixels(grid[0, :2], 1.0, (4, 4))
    array([[0., 0.],
           [1., 0.]])
    """
    h = as_positive(half_size, "half_size")
    H, W = as_shape(shape, "shape")
    xs = -h + (np.arange(W) + 0.5) * (2 * h / W)
    ys = h - (np.arange(H) + 0.5) * (2 * h / H)
    X, Y = np.meshgrid(xs, ys)
    return np.stack([X, Y, np.zeros_like(X)], axis=-1)


def ground_pixels(points: np.ndarray, half_size: float, shape: tuple[int, int]) -> np.ndarray:
    """Inverse of :func:`receiver_grid`: pixel ``(x, y)`` of ground points ``(N, 2|3)``.

    Parameters
    ----------
    points : (N, 2) or (N, 3) float
        Ground points, world frame (``z`` ignored).
    half_size : float
        Half side of the ground square, scene units.
    shape : (H, W)
        Image shape in pixels.

    Returns
    -------
    (N, 2) float64
        Pixel coordinates ``(x, y)``.
    """
    h = as_positive(half_size, "half_size")
    H, W = as_shape(shape, "shape")
    p = np.asarray(points, dtype=np.float64)
    return np.stack([(p[:, 0] + h) * (W / (2 * h)) - 0.5, (h - p[:, 1]) * (H / (2 * h)) - 0.5], -1)
