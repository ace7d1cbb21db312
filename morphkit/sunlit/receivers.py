"""The sun's visibility at a billboard frame's receivers: the ground, the billboards, the meshes.

A relit billboard frame (:class:`~morphkit.sunlit.litmodes.LitMode`, its truth
:class:`~morphkit.sunlit.litmesh.LitMeshMode`) multiplies each sun's term of every shaded
pixel by the sun's **visibility** there (:mod:`morphkit.imaging.shading`, "Shadows"). A
:class:`SceneShadow` gives it, per frame, a :class:`FrameShadow`: the visibility of any world
points under each sun of the frame. Two of them:

* :class:`AtlasShadow` -- the field's shadow map from the assets' sun atlases
  (:class:`~.fieldshadow.FieldShadow`, its public ``build`` / ``plan`` / ``spheres``);
* :class:`~.raycast.RayCastShadow` -- the truth: rays from each point towards the sun against
  every posed real mesh (:func:`~.fieldbaselines.ray_cast_field`, Embree when installed).

**Receivers.** A billboard pixel's world point is its surface's per-pixel depth unprojected
through the camera of the image shown (the asset's camera for the direction,
:meth:`~morphkit.billboard.domeasset.DomeAsset.camera`, object frame) and posed by the
instance's ``object2world``; a real mesh's pixel is its depth pass unprojected through the
frame's camera; the ground's is the pixel's ray met with ``z = 0``
(:meth:`~morphkit.billboard.frames.backdrop.Backdrop.ground_points`). Billboards and meshes are
themselves drawn into the field's map, so their points are moved along their own normal by
:data:`~morphkit.tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS` field texels first (normal-offset
bias, its reason there); ground points are looked up as they are (the map's constant bias,
:data:`~morphkit.tol.SUN_GROUND_BIAS_TEXELS`). The ray cast moves a mesh pixel's point by
:data:`~morphkit.tol.SUN_RAY_NORMAL_OFFSET` along its normal (a depth pass's point lies a
depth quantum off its surface).

**The receiver rectangle.** The field's map skips casters whose shadow cannot reach the
receiver (:meth:`~.fieldshadow.FieldShadow.plan`). :func:`frame_receiver` gives the ground
rectangle of a frame: the bounding box of the ground the camera sees together with the
ground shadows of the visible instances' bounding spheres (a billboard is shadowed where the
ray from it to the sun meets a caster: its projection along the sun onto the ground lies in
its sphere's shadow, so a caster that shadows a billboard also reaches that shadow), clamped
to the box the field's shadows can reach at all. A caster outside the frame whose shadow falls
inside it is therefore kept; a caster inside the frame whose shadow falls outside it is drawn
(it is seen) and its shadow is simply not looked up. The rectangle is a superset (a bounding
box), never too small.

**Soft sun** (:func:`sun_disc`). ``N`` directions over the sun's disc of angular radius
``r`` (default the real sun's, :data:`~morphkit.conventions.SUN_DISC_RADIUS_DEG`; a larger
disc is allowed up to :data:`~morphkit.tol.MAX_SUN_DISC_DEG`): a Vogel (golden-angle)
spiral, point ``i`` at angle ``r sqrt((i + 1/2) / N)`` from the centre, evenly spread by
area (``N = 1``: the centre). Each direction gets its own hard visibility (one field map, or
one ray cast) and the visibilities are averaged, each with weight ``1 / N`` (Kang & Ihm's
accumulation of light samples). The ray-cast truth takes the same directions, so the two
compare sample for sample. :class:`FilteredAtlasShadow` instead filters one map along the
disc's centre (:mod:`.sundisc`, percentage-closer soft shadows).

**Atlases on demand** (:func:`bake_scene_atlases`). A scene's assets get their sun atlases
baked from their meshes when first needed, at :data:`SCENE_ATLAS_SIZE` texels over
:data:`SCENE_ATLAS_DOME` (21 sun directions: the measured recommendation of
``docs/results/field_shadows.md``, "A shadow atlas per asset": more views hardly help, texels
do), and kept in the mapping given (one bake per asset and run). An atlas already there is
checked against its mesh (:meth:`~.sunatlas.SunAtlas.check_mesh`: an atlas of another mesh is
refused, naming both hashes).

A sun at or below the horizon shadows nothing (visibility 1, no map, no error); the shading
model gives it no light anyway.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from functools import partial
from typing import Protocol, runtime_checkable

import numpy as np
import trimesh

from .. import tol
from ..billboard.frames.instances import Instances
from ..conventions import SUN_DISC_RADIUS_DEG
from ..errors import ValidationError, expected_got
from ..protocols import SceneRenderer
from ..validate import as_direction, as_finite_array, as_int, as_positive
from ..views.dome import ViewDome
from .fieldshadow import FieldMap, FieldShadow, field_sun
from .sunatlas import SunAtlas, bake_sun_atlas, sun_direction
from .sundisc import DiscMap

__all__ = ["sun_disc", "frame_receiver", "FrameShadow", "SceneShadow", "AtlasShadow", "FilteredAtlasShadow",
           "bake_scene_atlases", "SCENE_ATLAS_DOME", "SCENE_ATLAS_SIZE"]

_GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))

#: The sun directions of an atlas baked on demand: rings of 8, 8 and 4 at 10, 40 and 70
#: degrees and the top (21 views; module docstring, "Atlases on demand").
SCENE_ATLAS_DOME = ViewDome(((10.0, 8), (40.0, 8), (70.0, 4)), top=True)
#: The side (texels) of an atlas baked on demand (module docstring, "Atlases on demand").
SCENE_ATLAS_SIZE = 128


def bake_scene_atlases(meshes: Mapping[str, trimesh.Trimesh], renderer: SceneRenderer,
                       atlases: dict[str, SunAtlas] | None = None, *, size: int = SCENE_ATLAS_SIZE,
                       dome: ViewDome = SCENE_ATLAS_DOME) -> dict[str, SunAtlas]:
    """Each asset's sun atlas, baked where missing (module docstring, "Atlases on demand").

    Parameters
    ----------
    meshes : mapping of str to trimesh.Trimesh
        Each asset's mesh (normalised by the bake).
    renderer : SceneRenderer
        Renders the light views' depth.
    atlases : dict of str to SunAtlas, optional
        The atlases already made (filled in place: the run's cache).
    size : int
        Texels a side of the views baked.
    dome : ViewDome
        Their sun directions.

    Returns
    -------
    dict of str to SunAtlas
        ``atlases`` (a new dict when not given), one per mesh.

    Raises
    ------
    ValidationError
        An atlas given for an asset that was baked from another mesh (both hashes named).
    """
    out = {} if atlases is None else atlases
    for name, mesh in meshes.items():
        have = out.get(name)
        if have is None:
            out[name] = bake_sun_atlas(mesh, renderer, dome=dome, size=size)
        else:
            try:
                have.check_mesh(mesh)
            except ValidationError as exc:
                raise ValidationError(f"sun atlas of asset {name!r}: {exc}") from None
    return out


def sun_disc(sun_dir_world: np.ndarray, samples: int, radius_deg: float = SUN_DISC_RADIUS_DEG
             ) -> np.ndarray:
    """Directions over a sun's disc (module docstring, "Soft sun").

    Parameters
    ----------
    sun_dir_world : (3,) float
        Towards the disc's centre (any length > 0).
    samples : int
        ``N`` in ``[1, MAX_SUN_SAMPLES]`` (:data:`~morphkit.tol.MAX_SUN_SAMPLES`).
    radius_deg : float
        The disc's angular radius, degrees in ``[0, MAX_SUN_DISC_DEG]``.

    Returns
    -------
    (N, 3) float64
        Unit directions towards the sun (the centre alone for ``N = 1`` or radius 0).

    Raises
    ------
    ValidationError
        A zero direction, a count or radius out of range.

    Examples
    --------
    >>> import numpy as np
    >>> from morphkit.sunlit.receivers import sun_disc
    >>> d = sun_disc(np.array([0.0, 0.0, 1.0]), 8, 2.0)
    >>> d.shape, bool(np.degrees(np.arccos(d[:, 2])).max() < 2.0)
    ((8, 3), True)
    """
    d = as_direction(sun_dir_world, "sun_dir_world")
    n = as_int(samples, "sun samples", lo=1, hi=tol.MAX_SUN_SAMPLES)
    r = float(radius_deg)
    if not (math.isfinite(r) and 0.0 <= r <= tol.MAX_SUN_DISC_DEG):
        raise ValidationError(expected_got("sun disc radius", f"degrees in [0, {tol.MAX_SUN_DISC_DEG:g}]",
                                           radius_deg))
    if n == 1 or r == 0.0:
        return np.repeat(d[None], n, axis=0)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(d, helper)
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    i = np.arange(n, dtype=np.float64)
    ang = np.radians(r) * np.sqrt((i + 0.5) / n)
    th = i * _GOLDEN_ANGLE
    side = np.cos(th)[:, None] * u + np.sin(th)[:, None] * v
    out = np.cos(ang)[:, None] * d + np.sin(ang)[:, None] * side
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def frame_receiver(ground: np.ndarray, centres: np.ndarray, radii: np.ndarray, visible: np.ndarray,
                   sun_dir_world: np.ndarray) -> tuple[float, float, float, float] | None:
    """The ground rectangle a frame's shadows fall on (module docstring, "The receiver rectangle").

    Parameters
    ----------
    ground : (M, 3) float
        The frame's ground points (``z = 0``).
    centres : (N, 3) float
        All instances' bounding-sphere centres, world frame.
    radii : (N,) float
        Their radii.
    visible : (K,) int
        The instances the frame draws (receivers).
    sun_dir_world : (3,) float
        Towards the sun.

    Returns
    -------
    (xmin, ymin, xmax, ymax) or None
        ``None`` when nothing can be shadowed in the frame: no instance, the sun at or below
        the horizon, or no visible ground and no visible instance.
    """
    g = as_finite_array(ground, "ground points", shape=(None, 3))
    c = as_finite_array(centres, "centres", shape=(None, 3))
    r = as_finite_array(radii, "radii", shape=(len(c),))
    vis = np.asarray(visible, dtype=np.int64).reshape(-1)
    sun = field_sun(sun_dir_world)
    if sun is None or len(c) == 0 or (len(g) == 0 and len(vis) == 0):
        return None
    ell = sun_direction(*sun)  # the clamped sun, as the field's map
    foot = c[:, :2] - (c[:, 2] / ell[2])[:, None] * ell[:2]  # sphere centres along the sun onto z = 0
    half = (r / math.sin(math.radians(sun[1])))[:, None]  # the shadow ellipse's semi-major axis
    lo_all, hi_all = (foot - half).min(axis=0), (foot + half).max(axis=0)
    # the ground's box clipped to where shadows can fall: clipping is monotone, so the box of the
    # clipped points is the clipped box (reduced column by column: an axis-0 reduction over the
    # strided (M, 2) columns is an order of magnitude slower)
    pts = []
    if len(g):
        box = np.array([[g[:, 0].min(), g[:, 1].min()], [g[:, 0].max(), g[:, 1].max()]])
        pts.append(np.clip(box, lo_all, hi_all))
    if len(vis):
        pts += [foot[vis] - half[vis], foot[vis] + half[vis]]
    p = np.concatenate(pts)
    pad = float(r.min()) if float(r.min()) > 0 else 1.0
    lo, hi = np.maximum(p.min(axis=0) - pad, lo_all), np.minimum(p.max(axis=0) + pad, hi_all)
    if not (lo[0] < hi[0] and lo[1] < hi[1]):
        return None
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


class FrameShadow:
    """One frame's sun visibility at any world points (module docstring).

    Parameters
    ----------
    per_sun : sequence of (sequence of callable, float)
        Per sun of the frame: the hard visibility of each of its disc directions
        (``points (N, 3) -> (N,)``) and the normal offset (world units) of receivers drawn
        into the map. An empty sequence of callables: that sun shadows nothing.
    """

    def __init__(self, per_sun: Sequence[tuple[Sequence, float]]) -> None:
        self._per_sun = [(list(fns), float(off)) for fns, off in per_sun]

    @property
    def suns(self) -> int:
        """How many suns (the rows of :meth:`visibility`)."""
        return len(self._per_sun)

    @property
    def casts(self) -> bool:
        """Whether any sun can shadow anything in this frame."""
        return any(fns for fns, _ in self._per_sun)

    def visibility(self, points: np.ndarray, normals: np.ndarray | None = None) -> np.ndarray:
        """Visibility of world points, per sun (averaged over its disc).

        Parameters
        ----------
        points : (N, 3) float
            Receiver points, world frame.
        normals : (N, 3) float, optional
            Their unit normals (world): receivers drawn into the map (billboards, meshes),
            moved by the sun's normal offset; ``None`` for the ground (no offset).

        Returns
        -------
        (L, N) float32
            1 lit, 0 shadowed, in between under a soft sun's penumbra.
        """
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        out = np.ones((len(self._per_sun), len(pts)), np.float32)
        if len(pts) == 0:
            return out
        for k, (fns, off) in enumerate(self._per_sun):
            if not fns:
                continue
            p = pts
            if normals is not None and off != 0.0:
                p = pts + off * np.asarray(normals, np.float64).reshape(-1, 3)
            acc = np.zeros(len(pts), np.float32)
            for fn in fns:
                acc += fn(p)
            out[k] = acc * np.float32(1.0 / len(fns))
        return out


@runtime_checkable
class SceneShadow(Protocol):
    """What shadows a relit billboard frame: a :class:`FrameShadow` per frame.

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    name: str

    def frame(self, instances: Instances, suns: Sequence[np.ndarray], ground: np.ndarray,
              visible: np.ndarray) -> FrameShadow:
        """The visibility of one frame.

        Parameters
        ----------
        instances : Instances
            The scene's instances (the casters).
        suns : sequence of (3,) float
            Towards each sun of the frame, world frame.
        ground : (M, 3) float
            The frame's ground points.
        visible : (K,) int
            The instances the frame draws.

        Returns
        -------
        FrameShadow
            One row per sun.
        """
        ...


class AtlasShadow:
    """The field's shadow from the assets' sun atlases (module docstring).

    Parameters
    ----------
    atlases : mapping of str to SunAtlas, or FieldShadow
        Each asset's atlas (or a builder over them, whose light-view cache is then shared).
    samples : int
        Directions over the sun's disc (1: a hard shadow).
    disc_deg : float
        The disc's angular radius, degrees.
    texels_per_unit : float, optional
        The field map's resolution; default: the atlases' own (each atlas's side over its
        bounding diameter at the instances' mean scale, the finest of the assets), reduced so
        that the map's side stays under :data:`~morphkit.tol.SUN_FIELD_MAX_SIDE`.
    name : str
        Its name.

    Notes
    -----
    The builder keeps the last map it made (:meth:`~.fieldshadow.FieldShadow.build`): frames
    under the same sun with one disc direction (a camera moving at noon) reuse it; the
    builder's caches are emptied (:meth:`~.fieldshadow.FieldShadow.clear`) when a frame comes
    with other suns.
    """

    #: The default resolution's factor over the atlases' own (:meth:`resolution`); the
    #: receivers' normal offset keeps (at least) its world length at the unscaled map's.
    map_scale: float = 1.0

    def __init__(self, atlases: Mapping[str, SunAtlas] | FieldShadow, *, samples: int = 1,
                 disc_deg: float = SUN_DISC_RADIUS_DEG, texels_per_unit: float | None = None,
                 name: str = "atlas") -> None:
        self.field = atlases if isinstance(atlases, FieldShadow) else FieldShadow(atlases)
        sun_disc(np.array([0.0, 0.0, 1.0]), samples, disc_deg)  # validates both
        self.samples = int(samples)
        self.disc_deg = float(disc_deg)
        self.texels_per_unit = None if texels_per_unit is None else as_positive(texels_per_unit,
                                                                                "texels_per_unit")
        self.name = str(name)
        self.last_maps: list[FieldMap] = []
        self._suns: tuple[bytes, ...] = ()

    def resolution(self, instances: Instances, sun_dir_world: np.ndarray,
                   receiver: tuple[float, float, float, float] | None) -> float:
        """The field map's texels per unit for a frame (see the class's parameters).

        Parameters
        ----------
        instances : Instances
            The field.
        sun_dir_world : (3,) float
            Towards the sun (above the horizon).
        receiver : (xmin, ymin, xmax, ymax) or None
            The frame's receiver.

        Returns
        -------
        float
            Texels per scene unit.
        """
        if self.texels_per_unit is not None:
            return self.texels_per_unit
        used = sorted(set(instances.names[int(a)] for a in np.unique(instances.asset)))
        mean_scale = float(np.mean(instances.scale)) if len(instances) else 1.0
        atl = self.field.atlases
        native = self.map_scale * max(atl[nm].size / (2.0 * atl[nm].cameras.radius) for nm in used)
        native /= mean_scale
        probe = self.field.plan(instances, sun_dir_world, 1.0, receiver)
        if probe.camera is None:
            return native
        extent = float(max(probe.camera.shape)) + 2.0
        return min(native, (tol.SUN_FIELD_MAX_SIDE - 4) / extent)

    def frame(self, instances: Instances, suns: Sequence[np.ndarray], ground: np.ndarray,
              visible: np.ndarray) -> FrameShadow:
        """See :class:`SceneShadow`; the maps built are kept in :attr:`last_maps`.

        Parameters
        ----------
        instances : Instances
            The casters.
        suns : sequence of (3,) float
            Towards each sun.
        ground : (M, 3) float
            The frame's ground points.
        visible : (K,) int
            The instances drawn.

        Returns
        -------
        FrameShadow
            One row per sun.
        """
        per_sun: list[tuple[list, float]] = []
        self.last_maps = []
        key = tuple(np.round(np.asarray(d, np.float64), 12).tobytes() for d in suns)
        if key != self._suns:  # the sun moved: the last sun's light views are not needed again
            self.field.clear()
            self._suns = key
        centres, radii = self.field.spheres(instances)
        for d in suns:
            rect = frame_receiver(ground, centres, radii, visible, d)
            if rect is None:
                per_sun.append(([], 0.0))
                continue
            tpu = self.resolution(instances, d, rect)
            fns = self._sun_visibility(instances, d, tpu, rect)
            scale = self.map_scale if self.texels_per_unit is None else 1.0
            per_sun.append((fns, tol.SUN_RECEIVER_NORMAL_OFFSET_TEXELS * scale / tpu))
        return FrameShadow(per_sun)

    def _sun_visibility(self, instances: Instances, d: np.ndarray, tpu: float,
                        rect: tuple[float, float, float, float]) -> list:
        """One sun's visibility functions (averaged by :class:`FrameShadow`), the maps kept;
        empty when nothing casts."""
        maps = [self.field.build(instances, s, tpu, rect) for s in sun_disc(d, self.samples, self.disc_deg)]
        self.last_maps += maps
        # a direction that casts nothing counts lit (its 1/N share)
        fns = [m.visibility if m.camera is not None else _lit for m in maps]
        return fns if any(m.camera is not None for m in maps) else []


class FilteredAtlasShadow(AtlasShadow):
    """:class:`AtlasShadow` with the sun's disc filtered from one map along its centre
    (:func:`~.sundisc.disc_visibility`, PCSS) instead of ``samples`` maps averaged; the map's
    default resolution is :data:`~morphkit.tol.SUN_DISC_MAP_SCALE` times the atlases' own
    (its edges finer: the filter's error at the real sun is the texel grid's).

    Parameters
    ----------
    atlases : mapping of str to SunAtlas, or FieldShadow
        As :class:`AtlasShadow`.
    disc_deg : float
        The disc's angular radius, degrees.
    texels_per_unit : float, optional
        As :class:`AtlasShadow` (a value given is used as it is).
    name : str
        Its name.
    """

    map_scale = tol.SUN_DISC_MAP_SCALE

    def __init__(self, atlases: Mapping[str, SunAtlas] | FieldShadow, *,
                 disc_deg: float = SUN_DISC_RADIUS_DEG, texels_per_unit: float | None = None,
                 name: str = "atlas-pcss") -> None:
        super().__init__(atlases, samples=1, disc_deg=disc_deg, texels_per_unit=texels_per_unit, name=name)

    def _sun_visibility(self, instances: Instances, d: np.ndarray, tpu: float,
                        rect: tuple[float, float, float, float]) -> list:
        m = self.field.build(instances, d, tpu, rect)
        self.last_maps.append(m)
        if m.camera is None or m.depth is None:
            return []
        return [partial(DiscMap(m.depth, m.camera).visibility, radius_deg=self.disc_deg)]


def _lit(points: np.ndarray) -> np.ndarray:
    return np.ones(len(points), np.float32)
