"""Soft shadows of a rectangular area light, by warping (Kang & Ihm 2002, 2.3.2).

Heckbert & Herf sample an area light as ``N`` point lights, render a hard shadow
for each and average them. Kang & Ihm observe that a light sample moved by
``D`` from the light's centre casts the shadow of the object moved by ``-D``
(:mod:`morphkit.shadow.rig`, "Moving light"), so every sample's shadow map comes
from the *same* pre-rendered atlas by warping, with no re-rendering; the ``N``
hard shadows are accumulated with weight ``1/N``.

What morphkit accumulates. Kang & Ihm blend the ``N`` projected shadow textures
in the frame buffer with ``alpha = 1/N``. morphkit does the same per receiver
point: each sample's map is looked up with its own light camera
(:func:`~morphkit.shadow.lookup.shadow_visibility`) and the visibilities are
averaged, so the result is the fraction of light samples a point sees -- the
quantity the ray-cast ground truth
(:func:`~morphkit.imaging.groundtruth.area_visibility`) computes with the same samples,
and self-shadowing works as for hard shadows.

Conditions (checked, with a specific error):

* the light is an :class:`~morphkit.scene.AreaLight` *parallel to the motion
  plane* (its half-extent vectors have no ``z`` component): only then is moving
  the light the same as moving the object the other way;
* the atlas (or other method) was made for a :class:`~morphkit.scene.PointLight`
  at the area light's centre, over the object's range *grown by the light's
  extent* -- :func:`soft_motion_range` gives exactly that range ("model only what
  the scene needs"), :func:`bake_soft_atlas` bakes it. A light sample whose
  equivalent position falls outside the baked range raises
  :class:`~morphkit.errors.OutOfRangeError` (or clamps with a warning when
  ``clamp=True``).

Sampling. ``samples=(n_u, n_v)`` takes the centres of an ``n_u x n_v`` grid of
cells on the light (:meth:`~morphkit.scene.AreaLight.samples`), jittered inside
each cell when an ``rng`` is given; an explicit ``(N, 2)`` array of light
coordinates ``(a, b)`` in ``[-1, 1]^2`` (position ``center + a u + b v``) is also
accepted, e.g. the paper's 5 samples (centre and corners).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import trimesh

from .. import tol
from ..errors import ValidationError, expected_got
from ..protocols import SceneRenderer
from ..scene import AreaLight, PointLight
from ..validate import as_finite_array
from .atlas import ShadowAtlas, bake_atlas
from .lookup import ShadowBias, lookup_into
from .method import ShadowMethod
from .rig import MotionRange

__all__ = ["SoftShadow", "bake_soft_atlas", "light_offsets", "soft_motion_range"]

#: The paper's 5 light samples (Table 5): the centre and the four corners.
FIVE_SAMPLES = np.array([[0.0, 0.0], [-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]])


def _check_parallel(light: AreaLight) -> AreaLight:
    if not isinstance(light, AreaLight):
        raise ValidationError(expected_got("light", "an AreaLight", type(light).__name__))
    z = max(abs(float(light.u[2])), abs(float(light.v[2])))
    if z > tol.MIN_EXTENT:
        raise ValidationError(expected_got(
            "area light", "half-extent vectors u, v parallel to the motion plane (z = 0): only "
            "then is moving the light the same as moving the object the other way",
            f"u={light.u.tolist()}, v={light.v.tolist()}"))
    return light


def light_offsets(light: AreaLight, samples: Any = (3, 3),
                  rng: np.random.Generator | None = None) -> np.ndarray:
    """Offsets ``(N, 2)`` of the light samples from the light's centre, in the
    motion plane (see the module docstring for ``samples``; at most
    :data:`morphkit.tol.MAX_LIGHT_SAMPLES` of them).

    Parameters
    ----------
    light : morphkit.scene.AreaLight
        The area light (``u``, ``v`` parallel to the motion plane).
    samples : int, (n_u, n_v) or (N, 2) array
        Grid size, or light coordinates in ``[-1, 1]^2``.
    rng : numpy.random.Generator, optional
        Jitter of grid samples.

    Returns
    -------
    (N, 2) float64
        Offsets, world units.
    """
    light = _check_parallel(light)
    try:
        arr = np.asarray(samples, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValidationError(expected_got("light samples", "an int k, a pair (n_u, n_v) or an (N, 2) "
                                           "array of light coordinates", repr(samples)[:120])) from exc
    if arr.ndim == 2:
        ab = as_finite_array(arr, "light samples (a, b)", shape=(None, 2))
        if len(ab) > tol.MAX_LIGHT_SAMPLES:
            raise ValidationError(expected_got(
                "light samples (a, b)", f"at most {tol.MAX_LIGHT_SAMPLES} "
                "(morphkit.tol.MAX_LIGHT_SAMPLES)", len(ab)))
        if len(ab) == 0 or np.any(np.abs(ab) > 1 + tol.REL_EQUAL):
            raise ValidationError(expected_got("light samples (a, b)",
                                               "at least one, each in [-1, 1]^2",
                                               f"{len(ab)} samples, max |a|, |b| = "
                                               f"{np.abs(ab).max(initial=0):g}"))
        pos = light.center + ab[:, :1] * light.u + ab[:, 1:] * light.v
    else:
        if arr.shape not in ((), (2,)) or np.any(arr != np.round(arr)):
            raise ValidationError(expected_got("light samples", "an int k, a pair (n_u, n_v) or "
                                               "an (N, 2) array of light coordinates",
                                               repr(samples)))
        n_u, n_v = (int(arr), int(arr)) if arr.ndim == 0 else (int(arr[0]), int(arr[1]))
        pos = light.samples(n_u, n_v, rng)
    return (pos - light.center)[:, :2]


def soft_motion_range(motion: MotionRange, light: AreaLight) -> MotionRange:
    """The range of *equivalent* object positions an area light needs: ``motion``
    grown by the light's extent in the plane (``xy - D`` for every offset ``D``).

    Parameters
    ----------
    motion : MotionRange
        The object's range.
    light : morphkit.scene.AreaLight
        The area light.

    Returns
    -------
    MotionRange
        The grown range.
    """
    light = _check_parallel(light)
    ext = np.abs(light.u[:2]) + np.abs(light.v[:2])
    return MotionRange(motion.lo - ext, motion.hi + ext)


def bake_soft_atlas(mesh: trimesh.Trimesh, base_pose: np.ndarray, motion: MotionRange,
                    light: AreaLight, shape: tuple[int, int], *, renderer: SceneRenderer,
                    **kwargs: Any) -> ShadowAtlas:
    """Bake the atlas an area light needs: a point light at its centre, over
    :func:`soft_motion_range` (keyword arguments go to
    :func:`~morphkit.shadow.atlas.bake_atlas`).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The occluder, object frame.
    base_pose : (4, 4) float
        ``object2world`` at translation ``(0, 0)``.
    motion : MotionRange
        The object's range (world units).
    light : morphkit.scene.AreaLight
        The area light.
    shape : (H, W)
        Size of each map.
    renderer : morphkit.render.Renderer
        Renders the maps.
    **kwargs : Any
        Options of ``bake_atlas``.

    Returns
    -------
    morphkit.shadow.atlas.ShadowAtlas
        The atlas.
    """
    centre = PointLight(_check_parallel(light).center)
    return bake_atlas(mesh, base_pose, soft_motion_range(motion, light), centre, shape,
                      renderer=renderer, **kwargs)


class SoftShadow:
    """Area-light visibility from any hard-shadow method, one map per light sample.

    Parameters
    ----------
    method : ShadowMethod
        Any :class:`~morphkit.shadow.method.ShadowMethod` whose ``rig`` is made for
        a point light at the area light's centre: a
        :class:`~morphkit.shadow.atlas.ShadowAtlas` or one of its methods
        (``atlas.method(warps="reproject")``), a
        :class:`~morphkit.shadow.baselines.DirectShadow` (``N`` renders) or an
        :class:`~morphkit.shadow.baselines.ImageBasedShadow`.
    light : AreaLight
    samples
        ``k``, ``(n_u, n_v)`` or an ``(N, 2)`` array of light coordinates.
    rng : numpy.random.Generator, optional
        Jitter the grid samples (drawn once, here: the same samples every frame).
    bias : ShadowBias, optional
        Depth-comparison bias of every lookup.
    """

    def __init__(self, method: ShadowMethod, light: AreaLight, samples: Any = (3, 3), *,
                 rng: np.random.Generator | None = None, bias: ShadowBias | None = None) -> None:
        self.offsets = light_offsets(light, samples, rng)
        if not isinstance(method, ShadowMethod):
            raise ValidationError(expected_got("method", "a ShadowMethod (name, rig, memory_bytes, "
                                               "shadow_map)", type(method).__name__))
        rig = method.rig
        if not isinstance(rig.light, PointLight):
            raise ValidationError(expected_got(
                "method", "a shadow method made for a PointLight at the area light's centre",
                f"{type(method).__name__} for {type(rig.light).__name__}"))
        if not np.allclose(rig.light.position, light.center, rtol=0, atol=tol.REL_EQUAL):
            raise ValidationError(expected_got(
                "method's light", f"a point light at the area light's centre {light.center.tolist()}",
                f"at {rig.light.position.tolist()}"))
        self.method, self.light, self.bias = method, light, bias

    @property
    def n_samples(self) -> int:
        """The number ``N`` of light samples (each a warped map, weight ``1/N``)."""
        return len(self.offsets)

    def point_lights(self) -> list[PointLight]:
        """The light samples as point lights (for the ray-cast truth with the same
        samples: :func:`~morphkit.imaging.groundtruth.sampled_visibility`).

        Returns
        -------
        list of morphkit.scene.PointLight
            One per sample, world frame.
        """
        return [PointLight(self.light.center + np.r_[d, 0.0]) for d in self.offsets]

    def maps(self, xy: Any, *, clamp: bool = False) -> Iterator[tuple[np.ndarray, Any]]:
        """The ``N`` hard shadow maps ``(depth, light camera)``, one per light sample,
        made one at a time.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        clamp : bool
            Clamp into the range instead of raising.

        Yields
        ------
        depth : (H, W) float32
            Light-view linear depth, ``+inf`` background.
        camera : morphkit.camera.CameraModel
            Its light camera.
        """
        for d in self.offsets:
            yield self.method.shadow_map(xy, light_offset=d, clamp=clamp)

    def visibility(self, xy: Any, points: Any, normals: np.ndarray | None = None, *,
                   clamp: bool = False) -> np.ndarray:
        """Fraction ``(P,)`` float32 of the light samples each world point sees,
        with the object at ``xy``: a multiple of ``1/N`` in ``[0, 1]``.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        points : (P, 3) float
            Points, world frame.
        normals : (P, 3) float, optional
            Unit normals for the slope bias.
        clamp : bool
            Clamp into the range instead of raising.

        Returns
        -------
        (P,) float32
            Fraction of samples seen.
        """
        pts = as_finite_array(points, "points", shape=(None, 3))
        if normals is not None:
            normals = as_finite_array(normals, "normals", shape=(len(pts), 3), dtype=np.float32)
        bias = ShadowBias() if self.bias is None else self.bias
        acc = np.zeros(len(pts), np.float32)
        lit = np.empty(len(pts), np.float32)
        for depth, cam in self.maps(xy, clamp=clamp):  # inputs validated once, above
            lit.fill(1.0)
            lookup_into(lit, pts, depth, cam, normals, bias)
            acc += lit
        acc /= np.float32(self.n_samples)
        return np.clip(acc, 0.0, 1.0)

    def visibility_fn(self, xy: Any, *, clamp: bool = False) -> Any:
        """A :data:`~morphkit.shadow.frame.VisibilityFn` for
        :func:`~morphkit.shadow.frame.render_frame`, the object at ``xy``.

        Parameters
        ----------
        xy : (2,) float
            Object translation (world units).
        clamp : bool
            Clamp into the range instead of raising.

        Returns
        -------
        callable
            ``(points (N, 3), normals (N, 3)) -> (N,) float32``.
        """
        return lambda p, n: self.visibility(xy, p, n, clamp=clamp)
