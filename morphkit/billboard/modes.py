"""Modes of one billboard scene: the view-morphed billboards and their baselines.

Each mode is an object with a ``name`` and ``render(scene, camera) -> Frame``
(:class:`~.field.FrameMode`), so a scene is drawn the same way in every mode and the
frames compare like with like:

* :class:`MorphMode` -- the paper's technique, extended to rings of K views:
  each billboard's viewing azimuth picks the two bracketing references and
  ``s`` (:meth:`ViewPairing.pair`), the asset view-morphs them, through a
  bounded LRU :class:`~.cache.MorphCache` keyed ``(asset, i, j, quantised s,
  level)``; ``s`` lies on a grid of about ``quantum_deg`` of azimuth. By default
  the two cached morphs on the grid around ``s`` are blended by where ``s`` lies
  between them (:func:`~.cache.bracket_s`): the image changes continuously with
  the view (no step when ``s`` crosses a grid line) while the cache keys change
  only every ``quantum_deg``; ``blend=False`` rounds ``s`` to the nearest grid
  step instead (:func:`~.cache.quantise_s`). On the grid's ends (``s = 0`` or
  ``1``) the reference itself is used.
* :class:`ClassicMode` -- a classic billboard: one fixed image per asset (its
  front view, azimuth 0, :meth:`BillboardSource.classic`) whatever the viewing
  direction.
* :class:`NearestMode` -- an impostor that switches to the nearest reference.
* :class:`CrossfadeMode` -- the two nearest references blended by ``s``.
* :class:`MeshMode` -- the real meshes, rendered by a
  :class:`~morphkit.protocols.SceneRenderer` at every instance's pose: the
  ground truth and the speed anchor. Its coverage (the depth buffer, or the
  supersampled alpha) and colour make the same kind of layer as the billboards,
  composited over the same backdrop.

Billboard modes share :class:`BillboardMode`: plan the frame, ask the mode for
each placement's image, composite back to front, put the layer over the
backdrop.

K = 2 outside the arc: the ring clamps to the nearer reference (``s`` 0 or 1)
and the frame's :attr:`FrameStats.max_outside_deg` says how far outside it was.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import cv2
import numpy as np

from ..camera import CameraModel
from ..errors import ValidationError, expected_got
from ..memo import Memo
from ..protocols import SceneRenderer
from ..scene import Item, Light
from ..validate import as_flag, as_int
from .frames.cache import CacheCounts, MorphCache, bracket_s, morph_key, quantise_s
from .frames.compositor import draw, finish, new_layer
from .frames.field import BillboardScene
from .frames.frametypes import Frame, FramePlan, FrameStats, Placement
from .protocols import BillboardSource

__all__ = ["BillboardMode", "MorphMode", "ClassicMode", "NearestMode", "CrossfadeMode",
           "MeshMode", "pair_span_deg", "frame_stats"]


def pair_span_deg(asset: BillboardSource, i: int, j: int) -> float:
    """Azimuth from reference ``i`` to reference ``j`` of ``asset``, degrees in ``(0, 360]``
    (counter-clockwise; a two-view ring's arc).

    Parameters
    ----------
    asset : BillboardSource
        The asset.
    i, j : int
        Reference view indices.

    Returns
    -------
    float
        The span, degrees.
    """
    az = np.asarray(asset.ring.azimuths_deg(), dtype=np.float64)
    d = float((az[j] - az[i]) % 360.0)
    return d if d > 0 else 360.0


def frame_stats(name: str, plan: FramePlan, counts: CacheCounts, cache: MorphCache | None,
                outside: float, t0: float) -> FrameStats:
    """A frame's stats: its plan's counts, the cache's traffic during it, its time since ``t0``.

    Parameters
    ----------
    name : str
        The mode's name.
    plan : FramePlan
        The frame's plan.
    counts : CacheCounts
        The cache's hits, misses and evictions during the frame.
    cache : MorphCache or None
        The mode's cache (its size and bytes), None for a mode without one.
    outside : float
        The most degrees a billboard lay outside a partial ring's arc.
    t0 : float
        ``time.perf_counter()`` when the frame began.

    Returns
    -------
    FrameStats
    """
    return FrameStats(name, plan.n_instances, len(plan.placements), plan.n_frustum_culled, plan.n_behind,
                      plan.n_offscreen, plan.n_small, plan.n_near_clipped, plan.n_above, counts.hits,
                      counts.misses, counts.evictions, len(cache) if cache is not None else 0,
                      cache.nbytes if cache is not None else 0, outside,
                      1e3 * (time.perf_counter() - t0))


class BillboardMode(ABC):
    """A mode that draws each billboard from one image; subclasses say which image."""

    name: str = "billboard"

    @property
    def cache(self) -> MorphCache | None:
        """The mode's image cache (None when it needs none)."""
        return None

    @abstractmethod
    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """``(image, outside_deg)``: the premultiplied ``(h, w, 4)`` image of ``asset`` for
        ``placement`` (at ``placement.level``) and how far outside a partial ring's arc it lies.

        Parameters
        ----------
        asset : BillboardSource
            The instance's asset.
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA.
        outside_deg : float
            Degrees outside the arc, 0 inside.
        """

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """Plan, draw every placement's image back to front, finish over the backdrop.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
            The frame.
        """
        t0 = time.perf_counter()
        cache = self.cache
        before = cache.counts if cache is not None else CacheCounts()
        plan = scene.plan(camera)
        layer = new_layer(camera.shape)
        outside = self.draw_placements(scene, plan.placements, layer)
        rgb = finish(layer, scene.backdrop.draw(camera))
        counts = (cache.counts - before) if cache is not None else CacheCounts()
        return Frame(rgb, layer, plan.placements, frame_stats(self.name, plan, counts, cache, outside, t0))


    def draw_placements(self, scene: BillboardScene, placements: Sequence[Placement], layer: np.ndarray,
                        zbuf: np.ndarray | None = None) -> float:
        """Composite ``placements``' images (back to front) into ``layer``; with ``zbuf`` (what was
        drawn before, e.g. real meshes: :mod:`morphkit.plan.mixed`), each billboard meeting a pixel
        it holds is depth-tested there at its pivot's depth (a ring image has no depth of its own).

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        placements : sequence of Placement
            Back to front (a frame plan's order).
        layer : (H, W, 4) float32
            Premultiplied layer, updated in place.
        zbuf : (H, W) float32, optional
            Depth buffer, ``+inf`` where nothing is drawn; updated in place.

        Returns
        -------
        float
            The most degrees any billboard lay outside a partial ring's arc.

        Raises
        ------
        ValidationError
            An asset that is not a ring asset.
        """
        fog = scene.backdrop.fog
        fog_color = fog.color if fog is not None else (0.0, 0.0, 0.0)
        outside = 0.0
        for pl in placements:
            asset = scene.assets[pl.asset]
            if not isinstance(asset, BillboardSource):
                raise ValidationError(expected_got(
                    f"asset {pl.asset!r} for the {self.name} mode", "a ring asset (BillboardSource; "
                    "relightable assets are drawn by litmodes.LitMode)", type(asset).__name__))
            img, out = self.image(asset, pl)
            outside = max(outside, out)
            r0, r1, c0, c1 = pl.roi
            if zbuf is not None and bool(np.isfinite(zbuf[r0:r1, c0:c1]).any()):
                draw(layer, pl, img, fog_color, zbuf=zbuf)
            else:
                draw(layer, pl, img, fog_color)
        return outside


def _check_quantum(q: float) -> float:
    q = float(q)
    if not np.isfinite(q) or q < 0:
        raise ValidationError(expected_got("quantum_deg", "a finite number >= 0 (0: exact s)", q))
    return q


class MorphMode(BillboardMode):
    """View-morphed billboards through a bounded LRU cache (see the module notes).

    Parameters
    ----------
    cache : MorphCache, optional
        Default: ``MorphCache()``.
    quantum_deg : float
        Grid step of ``s`` in degrees of viewing azimuth (0: exact ``s``, a cache
        entry per distinct azimuth).
    blend : bool
        Blend the two cached images around ``s`` (default) or round ``s`` to the grid.
    coverage : bool
        ``BillboardSource.morph(..., coverage=)``: the alpha from the asset's depth
        (default), or the paper's view morph alone (False). Keep one cache per setting
        (the cache keys do not hold it).
    """

    name = "morph"

    def __init__(self, cache: MorphCache | None = None, *, quantum_deg: float = 1.0,
                 blend: bool = True, coverage: bool = True) -> None:
        self._cache = MorphCache() if cache is None else cache
        if not isinstance(self._cache, MorphCache):
            raise ValidationError(expected_got("cache", "a MorphCache", type(cache).__name__))
        self.quantum_deg = _check_quantum(quantum_deg)
        self.blend = bool(blend)
        self.coverage = as_flag(coverage, "coverage")
        self._spans: Memo[tuple[str, int, int], float] = Memo()  # pair_span_deg per (asset, i, j)

    @property
    def cache(self) -> MorphCache:
        """The morph cache."""
        return self._cache

    def _make(self, asset: BillboardSource, i: int, j: int, s: float, level: int) -> np.ndarray:
        return asset.morph(i, j, s, level, coverage=self.coverage)

    def _at(self, asset: BillboardSource, i: int, j: int, s: float, level: int) -> np.ndarray:
        if s <= 0.0:
            return asset.reference(i, level)
        if s >= 1.0:
            return asset.reference(j, level)
        return self._cache.get(morph_key(asset.name, i, j, s, level),
                               lambda: self._make(asset, i, j, s, level))

    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """The image at the placement's azimuth (on the grid, or blended between two grid
        steps), from the cache; see :class:`BillboardMode`.

        Parameters
        ----------
        asset : BillboardSource
            The instance's asset.
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA (read-only when from the cache).
        outside_deg : float
            Degrees outside the arc, 0 inside.
        """
        i, j, s, outside = asset.ring.pair(placement.azimuth_deg)
        lv = placement.level
        span = self._spans.get((asset.name, i, j), lambda: pair_span_deg(asset, i, j))
        if self.quantum_deg == 0.0 or not self.blend:
            return self._at(asset, i, j, quantise_s(s, span, self.quantum_deg), lv), outside
        s_lo, s_hi, w = bracket_s(s, span, self.quantum_deg)
        lo = self._at(asset, i, j, s_lo, lv)
        if w == 0.0:
            return lo, outside
        hi = self._at(asset, i, j, s_hi, lv)
        return cv2.addWeighted(lo, 1.0 - w, hi, w, 0.0), outside


class CrossfadeMode(MorphMode):
    """The two nearest references blended by ``s`` (an impostor's frame blend), cached like
    :class:`MorphMode` (its own cache).

    Parameters
    ----------
    cache : MorphCache, optional
        Default: ``MorphCache()``.
    quantum_deg : float
        Grid step of ``s`` in degrees of viewing azimuth, as for :class:`MorphMode`.
    blend : bool
        Blend the two cached images around ``s``, as for :class:`MorphMode`.
    """

    name = "crossfade"

    def __init__(self, cache: MorphCache | None = None, *, quantum_deg: float = 1.0,
                 blend: bool = True) -> None:
        super().__init__(cache, quantum_deg=quantum_deg, blend=blend, coverage=False)

    def _make(self, asset: BillboardSource, i: int, j: int, s: float, level: int) -> np.ndarray:
        return asset.crossfade(i, j, s, level)


class NearestMode(BillboardMode):
    """The nearest reference view (an impostor that switches views)."""

    name = "nearest"

    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """Reference ``i`` for ``s < 0.5``, else ``j``; see :class:`BillboardMode`.

        Parameters
        ----------
        asset : BillboardSource
            The instance's asset.
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA, read-only.
        outside_deg : float
            Degrees outside the arc, 0 inside.
        """
        i, j, s, outside = asset.ring.pair(placement.azimuth_deg)
        return asset.reference(i if s < 0.5 else j, placement.level), outside


class ClassicMode(BillboardMode):
    """A classic billboard: the asset's one fixed image (:meth:`BillboardSource.classic`, its
    front view) from every direction."""

    name = "classic"

    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """The front image; ``outside_deg`` 0 (a classic billboard has no arc).

        Parameters
        ----------
        asset : BillboardSource
            The instance's asset.
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA, read-only.
        outside_deg : float
            ``0``.
        """
        return asset.classic(placement.level), 0.0


@dataclass
class MeshMode:
    """The real meshes at every instance's pose, rendered by a :class:`SceneRenderer`.

    Parameters
    ----------
    renderer : SceneRenderer
    meshes : mapping of str to sequence of Item
        Per asset name, the items (meshes with colours, object frame, ``pose``
        relative to the object frame) the asset was baked from, in the asset's look:
        ``asset.items(mesh)`` (:meth:`~morphkit.billboard.BillboardAsset.items`, which
        reads the asset's ``appearance`` and checks the mesh's hash).
    lights : sequence of Light
        World-frame lights (use the bake's for a like-with-like comparison).
    ambient : float
        Ambient light level.
    supersample : int
        1: colour and depth in one render, coverage from the depth buffer (hard
        edges; the speed anchor). ``s > 1``: the renderer's supersampled
        transparent view (coverage alpha; for accuracy references).
    cull : bool
        Draw only the instances whose bounding sphere meets the frustum (as the
        billboards); False draws all.
    name : str, optional
        The mode's name in frames, strips and reports.

    Notes
    -----
    Fog, when the scene has it, is applied per pixel from the depth buffer's
    distance with ``supersample=1``; the supersampled view (``> 1``) has no depth
    and draws no fog (accuracy references are measured without fog).
    """

    renderer: SceneRenderer
    meshes: Mapping[str, Sequence[Item]]
    lights: Sequence[Light] = field(default_factory=tuple)
    ambient: float = 0.35
    supersample: int = 1
    cull: bool = True
    name: str = "mesh"

    def __post_init__(self) -> None:
        if not isinstance(self.renderer, SceneRenderer):
            raise ValidationError(expected_got("renderer", "a SceneRenderer", type(self.renderer).__name__))
        self.supersample = as_int(self.supersample, "supersample", lo=1)
        for nm, items in self.meshes.items():
            for it in items:
                if not isinstance(it, Item):
                    raise ValidationError(expected_got(f"meshes[{nm!r}]", "a sequence of morphkit.scene.Item",
                                                       type(it).__name__))

    def items(self, scene: BillboardScene, indices: np.ndarray) -> list[Item]:
        """The posed items of instances ``indices`` (world frame).

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        indices : (M,) int
            Instance indices.

        Returns
        -------
        list of Item
            The posed items, world frame.
        """
        missing = [nm for nm in scene.instances.names if nm not in self.meshes]
        if missing:
            raise ValidationError(expected_got("mesh mode meshes", f"items for every asset {missing}",
                                               f"only {sorted(self.meshes)}"))
        out: list[Item] = []
        inst = scene.instances
        for k in indices:
            T = inst.object2world(int(k))
            for it in self.meshes[inst.names[int(inst.asset[k])]]:
                out.append(replace(it, pose=T @ np.asarray(it.pose, dtype=np.float64)))
        return out

    def render(self, scene: BillboardScene, camera: CameraModel) -> Frame:
        """Render the meshes; their coverage and colour as a layer over the backdrop.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.

        Returns
        -------
        Frame
            The frame.
        """
        t0 = time.perf_counter()
        plan = scene.plan(camera)
        idx = plan.visible if self.cull else np.arange(len(scene))
        if self.supersample == 1:
            layer, _ = self.depth_layer(scene, camera, idx)
        else:
            items = self.items(scene, idx)
            rgba = self.renderer.source_view(camera, items, self.lights, ambient=self.ambient,
                                             supersample=int(self.supersample))
            a = rgba[:, :, 3:].astype(np.float32) / 255.0
            layer = np.concatenate([rgba[:, :, :3].astype(np.float32) / 255.0 * a, a], axis=2)
        rgb = finish(layer, scene.backdrop.draw(camera))
        return Frame(rgb, layer, plan.placements, frame_stats(self.name, plan, CacheCounts(), None, 0.0, t0))

    def depth_layer(self, scene: BillboardScene, camera: CameraModel,
                    indices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The meshes of instances ``indices`` in one render of colour and depth (coverage from the
        depth buffer, whatever :attr:`supersample` says), fogged: :meth:`render`'s layer at
        ``supersample=1``, and its depth.

        Parameters
        ----------
        scene : BillboardScene
            The scene.
        camera : CameraModel
            Perspective view, world frame.
        indices : (M,) int
            The instances drawn.

        Returns
        -------
        layer : (H, W, 4) float32
            Premultiplied colour and coverage.
        depth : (H, W) float32
            Camera depth ``Z``, ``+inf`` where no mesh is drawn.
        """
        items = self.items(scene, np.asarray(indices, np.int64))
        fog = scene.backdrop.fog
        color, depth = self.renderer.color_depth(camera, items, self.lights, ambient=self.ambient)
        alpha = np.isfinite(depth).astype(np.float32)
        layer = np.empty(camera.shape + (4,), np.float32)
        layer[:, :, :3] = color.astype(np.float32) * (alpha[:, :, None] / 255.0)
        layer[:, :, 3] = alpha
        if fog is not None:
            fog.blend_layer(layer, depth, camera)
        return layer, np.asarray(depth, np.float32)
