"""A field of instances' shadow on the ground from their assets' sun atlases: one light view.

A scene of many instances (:class:`~morphkit.billboard.frames.instances.Instances`) of a few assets,
each with its :class:`~morphkit.sunlit.sunatlas.SunAtlas`, under a directional sun: the
field's shadow map is **one orthographic light view along the sun** (world frame) that
covers the instances' bounding spheres at ``texels_per_unit`` texels per scene unit
(:func:`field_camera`). What the instances cast is drawn into it by a :class:`FieldDrawer`,
with a minimum of depths: each instance's light view comes from its atlas, with the sun
turned into its object frame by its yaw (:func:`~morphkit.sunlit.sunatlas.sun_in_object`).

**Drawers.** :class:`~.fieldsplat.SplatDrawer` (the default) reprojects the drawn texels
of the atlas views around each instance's object-frame sun point by point into the field
view: one compiled pass, nothing per sun to make or keep; an instance whose atlas texel is
smaller than the field's is drawn from a coarser level of its atlas's points (its module
docstring, "Levels"). A drawer is any :class:`FieldDrawer`.

**The cache.** :meth:`FieldShadow.build` returns the last map it made when neither the
instances, the sun, the resolution nor the receiver changed (:attr:`FieldShadow.reused`);
:meth:`FieldShadow.clear` forgets it and empties the drawer's caches.

**Only what a scene needs.** Given a ground rectangle (the receiver), an instance whose
bounding sphere's footprint in the field view (a disc) does not meet the receiver's (the
bounding box of its corners' projections along the sun) cannot shadow it and is skipped
(:attr:`FieldMap.skipped`).

**Lookup** (:meth:`FieldMap.visibility`): a ground point is projected along the sun into the
field view and shadowed where it lies behind the stored depth by more than
:data:`~morphkit.tol.SUN_GROUND_BIAS_TEXELS` texels (as
:func:`~morphkit.sunlit.sunatlas.ground_visibility`).

A sun at or below the horizon casts no shadow (every point lit, no error); under
:data:`~morphkit.tol.SUN_MIN_ELEVATION_DEG` the sun is clamped there, azimuth kept, as the
atlas does (:mod:`.sunatlas`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from .. import tol
from ..billboard.frames.instances import Instances
from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..shadow.lookup import ShadowBias, check_depth_map, lookup_into
from ..validate import as_finite_array, as_positive
from ..views.domecameras import direction, quad_axes
from .fieldsplat import SplatDrawer
from .sunatlas import SunAtlas

__all__ = ["FieldShadow", "FieldMap", "FieldDrawer", "field_camera", "field_sun",
           "receiver_footprint"]


def field_sun(sun_dir_world: np.ndarray) -> tuple[float, float] | None:
    """The sun's ``(azimuth, elevation)`` in degrees as the field uses it (clamped; module docstring).

    Parameters
    ----------
    sun_dir_world : (3,) float
        Towards the sun, world frame (any length > 0).

    Returns
    -------
    (float, float) or None
        Degrees; the elevation at least :data:`~morphkit.tol.SUN_MIN_ELEVATION_DEG`;
        ``None`` at or below the horizon.

    Raises
    ------
    ValidationError
        A zero or non-finite direction.
    """
    d = as_finite_array(sun_dir_world, "sun_dir_world", shape=(3,))
    n = float(np.linalg.norm(d))
    if not n > tol.MIN_EXTENT:
        raise ValidationError(expected_got("sun_dir_world", "a non-zero direction (3,)", d.tolist()))
    d = d / n
    if d[2] <= 0.0:
        return None
    el = float(np.degrees(np.arcsin(min(d[2], 1.0))))
    return float(np.degrees(np.arctan2(d[1], d[0]))), max(el, tol.SUN_MIN_ELEVATION_DEG)


def _axes(az: float, el: float) -> np.ndarray:
    """(3, 3) rows: image right, image down, towards the sun (world)."""
    right, up = quad_axes(az, el)
    return np.stack([np.asarray(right, float), -np.asarray(up, float), np.asarray(direction(az, el), float)])


def field_camera(centres: np.ndarray, radii: np.ndarray, azimuth_deg: float, elevation_deg: float,
                 texels_per_unit: float) -> CameraModel:
    """The orthographic light view along the sun covering spheres (module docstring).

    Parameters
    ----------
    centres : (K, 3) float
        Sphere centres, world frame (``K >= 1``).
    radii : (K,) float
        Their radii (> 0).
    azimuth_deg, elevation_deg : float
        The sun (:func:`field_sun`).
    texels_per_unit : float
        The view's resolution (its ``fx = fy``).

    Returns
    -------
    CameraModel
        Looking along the light (``-d(a, e)``), its window the spheres' footprints plus a
        texel, its depth range the spheres' plus a unit.

    Raises
    ------
    ValidationError
        No sphere; a view over :data:`~morphkit.tol.MAX_TEXTURE_SIDE` texels a side.
    """
    c = as_finite_array(centres, "centres", shape=(None, 3))
    r = as_finite_array(radii, "radii", shape=(len(c),))
    tpu = as_positive(texels_per_unit, "texels_per_unit")
    if len(c) == 0:
        raise ValidationError(expected_got("centres", "at least one sphere", "none"))
    ax = _axes(azimuth_deg, elevation_deg)
    p = c @ ax.T
    pad = 1.0 / tpu
    lo = (p[:, :2] - r[:, None]).min(axis=0) - pad
    hi = (p[:, :2] + r[:, None]).max(axis=0) + pad
    w, h = (int(math.ceil((hi[k] - lo[k]) * tpu)) for k in (0, 1))
    if max(w, h) > tol.MAX_TEXTURE_SIDE:
        raise ValidationError(expected_got("field light view",
                                           f"at most {tol.MAX_TEXTURE_SIDE} texels a side",
                                           f"{w} x {h} (fewer texels_per_unit, or a smaller receiver)"))
    mid = 0.5 * (lo + hi)
    top = float((p[:, 2] + r).max()) + 1.0
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2] = ax[0], ax[1], -ax[2]
    pose[:3, 3] = mid[0] * ax[0] + mid[1] * ax[1] + top * ax[2]
    zfar = top - float((p[:, 2] - r).min()) + 1.0
    return CameraModel("orthographic", (h, w), tpu, tpu, (w - 1) / 2.0, (h - 1) / 2.0, 0.5, zfar, pose)


def receiver_footprint(rect: tuple[float, float, float, float], azimuth_deg: float,
                       elevation_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box, in the light's image plane, of a ground rectangle (``z = 0``).

    Parameters
    ----------
    rect : (xmin, ymin, xmax, ymax)
        The receiver, world units.
    azimuth_deg, elevation_deg : float
        The sun.

    Returns
    -------
    lo, hi : (2,) float64
        The box's corners, along the view's right and down axes (world units).

    Raises
    ------
    ValidationError
        Not four finite numbers with ``xmin < xmax``, ``ymin < ymax``.
    """
    x0, y0, x1, y1 = as_finite_array(rect, "receiver", shape=(4,))
    if not (x0 < x1 and y0 < y1):
        raise ValidationError(expected_got("receiver", "(xmin, ymin, xmax, ymax) with min < max",
                                           [x0, y0, x1, y1]))
    corners = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x0, y1, 0.0], [x1, y1, 0.0]])
    p = corners @ _axes(azimuth_deg, elevation_deg)[:2].T
    return p.min(axis=0), p.max(axis=0)


@dataclass(frozen=True, eq=False)
class FieldMap:
    """The field's light view under one sun (:meth:`FieldShadow.build`).

    Parameters
    ----------
    camera : CameraModel or None
        The field's light camera (world); ``None`` when nothing casts (no instance kept, or
        the sun at or below the horizon).
    depth : (H, W) float32 or None
        Nearest caster's depth along the light (``+inf`` where none).
    kept : (M,) int64
        Indices of the instances drawn.
    skipped : int
        Instances whose shadow cannot reach the receiver.
    """

    camera: CameraModel | None
    depth: np.ndarray | None
    kept: np.ndarray
    skipped: int = 0
    _checked: bool = field(default=False, init=False, repr=False)

    def visibility(self, points: np.ndarray) -> np.ndarray:
        """Visibility of world points under the field (module docstring, "Lookup").

        Parameters
        ----------
        points : (N, 3) float
            Receiver points, world frame.

        Returns
        -------
        (N,) float32
            1 lit, 0 shadowed (all 1 when nothing casts).

        Raises
        ------
        ValidationError
            Points not ``(N, 3)`` finite.
        """
        pts = as_finite_array(points, "points", shape=(None, 3))
        if self.camera is None or self.depth is None:
            return np.ones(len(pts), np.float32)
        if not self._checked:  # the map is checked once, not at every lookup (a frame makes one per
            check_depth_map(self.depth, self.camera.shape)  # billboard): a whole-map pass each
            object.__setattr__(self, "_checked", True)
        vis = np.ones(len(pts), np.float32)
        lookup_into(vis, pts, self.depth, self.camera, None,
                    ShadowBias(constant=tol.SUN_GROUND_BIAS_TEXELS, slope=0.0))
        return vis


@runtime_checkable
class FieldDrawer(Protocol):
    """How a field's light-view depth is drawn from the instances' atlases.

    :class:`~.fieldsplat.SplatDrawer` (the default: per-point reprojection, one pass) is one;
    a test or a user may pass any other object with these members.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its methods.
    """

    name: str

    def draw(self, atlases: Mapping[str, SunAtlas], instances: Instances, kept: np.ndarray,
             camera: CameraModel, sun: tuple[float, float]) -> np.ndarray:
        """The light view's depth of ``camera``.

        Parameters
        ----------
        atlases : mapping of str to SunAtlas
            Each asset name's atlas.
        instances : Instances
            The field.
        kept : (K,) int64
            The instances to draw.
        camera : CameraModel
            The field's light view (orthographic, world frame).
        sun : (azimuth_deg, elevation_deg)
            The field's sun (clamped, above the horizon).

        Returns
        -------
        (H, W) float32
            Nearest caster's depth along the light (``+inf`` where none).
        """
        ...  # pragma: no cover - a protocol

    def clear(self) -> None:
        """Drop whatever the drawer keeps between draws."""
        ...  # pragma: no cover - a protocol


class FieldShadow:
    """The field shadow builder of a set of assets' sun atlases.

    Parameters
    ----------
    atlases : mapping of str to SunAtlas
        Each asset name of the instances to come, its atlas.
    drawer : FieldDrawer, optional
        How the light view is drawn (default: a new :class:`~.fieldsplat.SplatDrawer`).

    Attributes
    ----------
    reused : int
        Builds answered by the last map (module docstring, "The cache").

    Raises
    ------
    ValidationError
        No atlas, a value that is not a SunAtlas, a drawer that is not a FieldDrawer.
    """

    def __init__(self, atlases: Mapping[str, SunAtlas], drawer: FieldDrawer | None = None) -> None:
        if not isinstance(atlases, Mapping) or not atlases:
            raise ValidationError(expected_got("atlases", "a non-empty mapping name -> SunAtlas",
                                               type(atlases).__name__))
        for name, a in atlases.items():
            if not isinstance(a, SunAtlas):
                raise ValidationError(expected_got(f"atlases[{name!r}]", "a SunAtlas", type(a).__name__))
        drawer = SplatDrawer() if drawer is None else drawer
        if not isinstance(drawer, FieldDrawer):
            raise ValidationError(expected_got("drawer", "a FieldDrawer (name, draw, clear)",
                                               type(drawer).__name__))
        self.atlases = dict(atlases)
        self.drawer = drawer
        self._last: tuple[tuple, FieldMap] | None = None
        self.reused = 0

    def clear(self) -> None:
        """Forget the last map and empty the drawer's caches."""
        self._last = None
        self.reused = 0
        self.drawer.clear()

    def _atlas_of(self, instances: Instances) -> list[SunAtlas]:
        if not isinstance(instances, Instances):
            raise ValidationError(expected_got("instances", "an Instances", type(instances).__name__))
        missing = [nm for nm in instances.names if nm not in self.atlases]
        if missing:
            raise ValidationError(expected_got("instances' assets",
                                               f"names with an atlas ({sorted(self.atlases)})", missing))
        return [self.atlases[nm] for nm in instances.names]

    def spheres(self, instances: Instances) -> tuple[np.ndarray, np.ndarray]:
        """The instances' bounding spheres, world frame (their atlases' pivot and radius, posed).

        Parameters
        ----------
        instances : Instances
            The field.

        Returns
        -------
        centres : (N, 3) float64
        radii : (N,) float64
        """
        atl = self._atlas_of(instances)
        if len(instances) == 0:
            return np.zeros((0, 3)), np.zeros(0)
        centres = instances.pivots([a.cameras.pivot for a in atl])
        radii = np.array([a.cameras.radius for a in atl])[instances.asset] * instances.scale
        return centres, radii

    def plan(self, instances: Instances, sun_dir_world: np.ndarray, texels_per_unit: float,
             receiver: tuple[float, float, float, float] | None = None) -> FieldMap:
        """The field's camera and the instances it draws, before drawing (depth ``None``).

        Parameters
        ----------
        instances : Instances
            The field.
        sun_dir_world : (3,) float
            Towards the sun, world frame.
        texels_per_unit : float
            The field view's resolution.
        receiver : (xmin, ymin, xmax, ymax), optional
            The ground rectangle to shadow; instances that cannot reach it are skipped
            (default: none skipped).

        Returns
        -------
        FieldMap
            ``camera`` ``None`` when nothing casts.

        Raises
        ------
        ValidationError
            Bad arguments (an asset without an atlas included).
        """
        tpu = as_positive(texels_per_unit, "texels_per_unit")
        centres, radii = self.spheres(instances)
        sun = field_sun(sun_dir_world)
        foot = None if receiver is None else receiver_footprint(receiver, 0.0, 45.0)  # validates
        empty = np.zeros(0, np.int64)
        if sun is None:
            return FieldMap(None, None, empty, 0)
        keep = np.arange(len(instances))
        if foot is not None and len(keep):
            lo, hi = receiver_footprint(receiver, *sun)  # type: ignore[arg-type]
            p = centres @ _axes(*sun)[:2].T
            meets = np.all((p + radii[:, None] >= lo) & (p - radii[:, None] <= hi), axis=1)
            keep = np.flatnonzero(meets)
        skipped = len(instances) - len(keep)
        if len(keep) == 0:
            return FieldMap(None, None, empty, skipped)
        cam = field_camera(centres[keep], radii[keep], sun[0], sun[1], tpu)
        return FieldMap(cam, None, keep.astype(np.int64), skipped)

    def build(self, instances: Instances, sun_dir_world: np.ndarray, texels_per_unit: float,
              receiver: tuple[float, float, float, float] | None = None) -> FieldMap:
        """The field's light view under a sun (module docstring).

        Parameters
        ----------
        instances : Instances
            The field (its asset names keys of the atlases).
        sun_dir_world : (3,) float
            Towards the sun, world frame.
        texels_per_unit : float
            The field view's resolution, texels per scene unit.
        receiver : (xmin, ymin, xmax, ymax), optional
            The ground rectangle to shadow (instances that cannot reach it are skipped).

        Returns
        -------
        FieldMap
            The map; no camera when nothing casts. The same object as the last build's
            when neither the instances, the sun, the resolution nor the receiver changed.

        Raises
        ------
        ValidationError
            Bad arguments; a field view over :data:`~morphkit.tol.MAX_TEXTURE_SIDE` a side.
        """
        plan = self.plan(instances, sun_dir_world, texels_per_unit, receiver)
        key = (instances.names, instances.xy.tobytes(), instances.yaw_deg.tobytes(),
               instances.scale.tobytes(), instances.asset.tobytes(),
               np.asarray(sun_dir_world, np.float64).tobytes(), float(texels_per_unit),
               None if receiver is None else tuple(map(float, receiver)))
        if self._last is not None and self._last[0] == key:
            self.reused += 1
            return self._last[1]
        if plan.camera is None:
            out = plan
        else:
            sun = field_sun(sun_dir_world)
            assert sun is not None
            depth = self.drawer.draw(self.atlases, instances, plan.kept, plan.camera, sun)
            out = FieldMap(plan.camera, depth, plan.kept, plan.skipped)
        self._last = (key, out)
        return out
