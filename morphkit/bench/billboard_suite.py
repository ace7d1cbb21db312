"""Suite ``billboards``: view-morphed billboard assets against the classic billboard and impostors.

Assets. Each mesh of :data:`morphkit.meshes.BILLBOARD_MESHES` (teapot, chair, cow,
tree, person; normalised, coloured by the 3-D checker of
:func:`morphkit.billboard.bake_items`, lit by :func:`morphkit.billboard.bake_lights`)
is baked with :func:`morphkit.billboard.bake_asset` (elevation 10 degrees).

Ground truth. For a viewing azimuth the asset shows the view of a virtual camera
(:meth:`BillboardAsset.camera`: the in-between camera of the morph, on the chord
between the two references); pyrender renders the mesh with that camera, the
bake's items and lights, and every method's image is compared with it in the
image frame of the billboard quad (the whole image is the billboard's box).
Beyond the arc of a ``K = 2`` asset the truth is the view from the ring camera
at the true azimuth (``asset.cameras.camera``), while the asset shows the
clamped reference.

Metrics (per azimuth, then averaged): ``iou`` -- silhouette IoU (alpha > 0.5,
:func:`morphkit.metrics.shadow_iou`), ``err_iou = 1 - iou``; ``psnr`` -- on the
premultiplied RGB (the billboard over black) over the whole box, data range 1
(:func:`morphkit.metrics.psnr`; identical images are capped at 99 dB); ``*_min``
-- the worst azimuth. ``ms_*``: one call of the method (medians over the azimuths).

Sections (a list, :data:`SECTIONS`, of functions ``(cache, quick) -> rows``;
other sections -- frame time, temporal stability -- append theirs):

* ``pair`` -- ``K = 2`` (+-30 degrees): ``morph`` (the asset's morph: alpha from
  depth), ``morph-paper`` (the view morph's own alpha, ``coverage=False``),
  ``classic`` (one image: the front view at azimuth 0), ``nearest`` and
  ``crossfade`` of the same two references, at azimuths +-5, +-15, +-25 inside the arc (``pair-inside``: the
  midpoints of six equal parts of the arc, so no method meets its own reference)
  and +-35, +-45, +-60 (``pair-outside``, 5-30 degrees beyond it);
* ``ring`` -- ``K = 6, 8, 12`` over 360 degrees, at 24 azimuths ``7.5 + 15 n``
  (never a reference): ``morph``, ``morph-paper``, ``nearest``, ``crossfade`` of the ring,
  ``classic``;
* ``equal-memory`` -- the ``K = 8`` and ``K = 12`` morph rings at ``S^2`` against
  ``nearest`` / ``crossfade`` over a denser ring of ``(S/2)^2`` views holding the same
  bytes: the same colour bytes (``dense-images``: 4 K views) and the same bytes in all
  (``dense-total``: as many views as the morph asset's
  :attr:`~morphkit.billboard.asset.BillboardAsset.memory_bytes`, which adds its depth
  maps and correspondences, pays for); the dense views are
  upsampled (bilinear) to ``S^2`` and compared with their own chord camera's
  render; 24 azimuths ``5 + 137.5 m`` degrees (the golden angle: none falls on
  a reference of any ring);
* ``bake`` -- :func:`bake_asset` ``K = 8`` at 256^2, three levels (renders, every
  pair's correspondences and level-0 morpher, as a bake does; ``cpu_ms``: the process's CPU
  time, all threads, next to the wall time: on a loaded machine the wall time
  includes waiting), and one ``morph`` / ``crossfade`` / ``nearest`` call of
  that asset.

* ``scene-*`` -- scenes of many billboards against the real meshes
  (:func:`scene_rows`; each kind of row is its own function):

  - :func:`scene_accuracy_rows` (``scene-accuracy``) -- per-billboard silhouette
    IoU (alpha > 0.5) and PSNR (final RGB, data range 255) over each billboard's
    screen box (:func:`morphkit.billboard.compare.box_errors`), against the real
    meshes rendered from the same camera with the same instance poses, items and
    lights (:class:`~morphkit.billboard.MeshMode`, supersampled coverage like the
    assets' references), composited over the same backdrop (no fog), along an
    orbit (24 frames, 8 units, 10 degrees up) of 9 instances of the cow on a
    3 x 3 grid with random yaws; for morph, morph-paper, classic, nearest,
    crossfade and :class:`TrueViewMode` (``true-view``: the mesh rendered by the
    asset's camera at each billboard's azimuth, on the same quad: the best a
    billboard of that bake can show).
    ``K = 2`` rows are split by where each billboard's viewing azimuth lies:
    ``inside`` the arc, ``outside<=30``; ring rows cover 360 degrees. Unlike the
    asset rows above, the scene camera is not the bake's camera (its distance,
    so its perspective, differs) and billboards are small (level 1-2).
    ``scene-distance`` rows: the ``K = 2`` scene again with the asset baked at
    4 and 8 bounding radii (``distance_factor``; the default is 12).
  - :func:`temporal_rows` (``scene-temporal``) -- the billboard layer's mean
    absolute change per 0.5-degree orbit step about one instance (the quad stays
    centred, so only its image changes), its maximum over its median: popping
    shows as spikes where a nearest view switches (``max_over_median`` is 1e9
    where the median change is 0: nothing moves between most steps).
  - :func:`speed_rows` (``scene-speed``) -- frame time of 10, 100 and 1000
    billboards at 640 x 480 (the pan's middle frame over a field of one
    instance per 1.5^2 units; cow at ~6k and ~59k faces, K = 8, 256^2, 3 levels)
    for the morph (cold: a new cache every frame; warm: the same frame again),
    crossfade (cold, warm), classic (``x_classic``: each row's median over
    classic's; the warm modes and classic are timed interleaved) and the real
    meshes (one render of every instance in the frustum). ``gl-quads`` draws
    one untextured quad per instance through pyrender: a lower bound of
    compositing the billboards as textured quads in GL instead of OpenCV.
  - :func:`hit_rate_rows` (``scene-hit-rate``) -- the morph cache's hit rate,
    entries and bytes along orbits of the 1000-billboard field, 0.5 and 3
    degrees per frame (warm from frame to frame), with the frame times.

Rows with ``mesh = "all"`` average the per-mesh rows.
``--quick``: chair and tree, 128^2 (``equal-memory``: 128^2 vs 64^2), ``K = 8``
rings only, 12 ring azimuths, one bake; scenes at 320 x 240, 10 and 100
billboards, the ~6k-face cow only.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import cv2
import numpy as np
import trimesh

from ..billboard import (
    BAKE_AMBIENT,
    Backdrop,
    BillboardAsset,
    BillboardMode,
    BillboardScene,
    ClassicMode,
    CrossfadeMode,
    Instances,
    MeshMode,
    MorphCache,
    MorphMode,
    NearestMode,
    OrbitPath,
    PanPath,
    Placement,
    QuadCameras,
    ViewRing,
    bake_asset,
    bake_items,
    bake_lights,
    place_random,
)
from ..billboard.cameras import DISTANCE_FACTOR
from ..billboard.compare import box_errors
from ..billboard.protocols import BillboardSource
from ..camera import CameraModel
from ..composite import to_premultiplied
from ..errors import ValidationError, expected_got
from ..meshes import BILLBOARD_MESHES, normalize, sample_mesh
from ..metrics import psnr, shadow_iou
from ..protocols import SceneRenderer
from ..scene import Item, Light
from .harness import Timing, make_row, time_call, time_calls

__all__ = ["run", "AssetCache", "SECTIONS", "FLOOR_METHOD", "PLOT_OPTIONS", "quality", "scene_rows",
           "TrueViewMode", "scene_accuracy_rows", "temporal_rows", "speed_rows", "hit_rate_rows",
           "step_changes"]

#: The suite's name in bench rows.
SUITE = "billboards"
#: The method the table's ratio column divides by.
FLOOR_METHOD = "crossfade"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite.
PLOT_OPTIONS: dict[str, Any] = {"error_key": "err_iou", "panel_keys": ("section",)}

PAIR_INSIDE = (-25.0, -15.0, -5.0, 5.0, 15.0, 25.0)
PAIR_OUTSIDE = (-60.0, -45.0, -35.0, 35.0, 45.0, 60.0)
RINGS = (6, 8, 12)
PSNR_CAP = 99.0


class AssetCache:
    """Meshes, baked assets and ground-truth renders shared by the suite's sections.

    Parameters
    ----------
    renderer : SceneRenderer
        Bakes the assets and renders the ground truth.
    max_assets : int
        Baked assets kept (least recently used dropped; an asset with its morphers
        holds ~100 MB at 256^2): a section asking again re-bakes.
    """

    def __init__(self, renderer: SceneRenderer, max_assets: int = 4) -> None:
        self.renderer = renderer
        self.max_assets = int(max_assets)
        self._meshes: dict[str, trimesh.Trimesh] = {}
        self._items: dict[str, list[Any]] = {}
        # (name, views, size, levels, distance factor) -> (asset, bake seconds)
        self._assets: OrderedDict[tuple[Any, ...], tuple[BillboardAsset, float]] = OrderedDict()

    def mesh(self, name: str) -> trimesh.Trimesh:
        """The normalised sample mesh ``name``.

        Parameters
        ----------
        name : str
            A sample mesh name (:func:`morphkit.meshes.sample_mesh`), e.g. ``"cow"``.

        Returns
        -------
        trimesh.Trimesh
            The normalised mesh, object frame (loaded once).
        """
        if name not in self._meshes:
            self._meshes[name] = normalize(sample_mesh(name))
            self._items[name] = bake_items(self._meshes[name])
        return self._meshes[name]

    def asset(self, name: str, views: int, size: int, levels: int = 1,
              distance_factor: float = DISTANCE_FACTOR) -> BillboardAsset:
        """``bake_asset(mesh(name), views=views, size=size, levels=levels, distance_factor=...)``,
        baked once.

        Parameters
        ----------
        name : str
            A sample mesh name.
        views : int
            Reference views on the ring.
        size : int
            Side of the square level-0 reference views, in pixels.
        levels : int
            Pyramid levels of the reference views.
        distance_factor : float
            Bake camera distance in bounding radii.

        Returns
        -------
        BillboardAsset
            The asset (kept while among the ``max_assets`` most recently used).
        """
        key = (name, views, size, levels, float(distance_factor))
        if key not in self._assets:
            while len(self._assets) >= self.max_assets:
                self._assets.popitem(last=False)
            t0 = time.perf_counter()
            a = bake_asset(self.mesh(name), self.renderer, name=name, views=views, size=size, levels=levels,
                           distance_factor=distance_factor)
            self._assets[key] = (a, time.perf_counter() - t0)
        self._assets.move_to_end(key)
        return self._assets[key][0]

    def bake_seconds(self, name: str, views: int, size: int, levels: int = 1) -> float:
        """Wall time of the (first) bake of that asset.

        Parameters
        ----------
        name : str
            A sample mesh name.
        views : int
            Reference views on the ring.
        size : int
            Side of the square level-0 reference views, in pixels.
        levels : int
            Pyramid levels of the reference views.

        Returns
        -------
        float
            Seconds (the asset is baked now if it is not cached).
        """
        self.asset(name, views, size, levels)
        return self._assets[(name, views, size, levels, float(DISTANCE_FACTOR))][1]

    def truth(self, name: str, camera: CameraModel) -> np.ndarray:
        """Premultiplied float32 RGBA render of mesh ``name`` by ``camera`` (bake items and lights).

        Parameters
        ----------
        name : str
            A sample mesh name.
        camera : CameraModel
            The camera, world frame (the mesh at its normalised pose).

        Returns
        -------
        numpy.ndarray
            ``(H, W, 4)`` float32 premultiplied RGBA in [0, 1], the camera's image size.
        """
        self.mesh(name)
        img = self.renderer.source_view(camera, self._items[name], bake_lights(), ambient=BAKE_AMBIENT)
        a = img.astype(np.float32) / 255.0
        return np.concatenate([a[..., :3] * a[..., 3:], a[..., 3:]], axis=2)


def quality(pred: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """``(iou, psnr)`` of a premultiplied RGBA image against the truth (module docstring).

    Parameters
    ----------
    pred : numpy.ndarray
        ``(H, W, 4)`` float32 premultiplied RGBA in [0, 1].
    truth : numpy.ndarray
        ``(H, W, 4)`` float32 premultiplied RGBA in [0, 1], the reference.

    Returns
    -------
    iou : float
        Silhouette IoU (alpha > 0.5).
    psnr : float
        PSNR of the premultiplied RGB, data range 1, dB, capped at ``PSNR_CAP``.
    """
    iou = shadow_iou(pred[..., 3] > 0.5, truth[..., 3] > 0.5)
    p = psnr(pred[..., :3], truth[..., :3], data_range=1.0)
    return iou, min(p, PSNR_CAP)


def _metrics(vals: list[tuple[float, float]]) -> dict[str, float]:
    v = np.asarray(vals, dtype=np.float64)
    return {"iou": float(v[:, 0].mean()), "err_iou": float(1.0 - v[:, 0].mean()),
            "psnr": float(v[:, 1].mean()), "iou_min": float(v[:, 0].min()), "psnr_min": float(v[:, 1].min())}


def _evaluate(methods: dict[str, Callable[[float], np.ndarray]], truths: dict[float, np.ndarray],
              section: str, params: dict[str, Any], notes: dict[str, str] | None = None
              ) -> list[dict[str, Any]]:
    """One row per method: metrics over the azimuths of ``truths``, the per-call times."""
    rows = []
    for method, fn in methods.items():
        vals, secs = [], []
        for az, gt in truths.items():
            t0 = time.perf_counter()
            img = fn(az)
            secs.append(time.perf_counter() - t0)
            vals.append(quality(img, gt))
        rows.append(make_row(SUITE, method, dict(section=section, **params), Timing.from_seconds(secs),
                             metrics=_metrics(vals), note=(notes or {}).get(method, "")))
    return rows


def _ring_methods(asset: BillboardAsset) -> dict[str, Callable[[float], np.ndarray]]:
    def via_pair(fn: Callable[[int, int, float], np.ndarray]) -> Callable[[float], np.ndarray]:
        def call(az: float) -> np.ndarray:
            i, j, s, _ = asset.ring.pair(az)
            return fn(i, j, s)
        return call

    def paper(i: int, j: int, s: float) -> np.ndarray:
        return asset.morph(i, j, s, coverage=False)

    return {"morph": via_pair(asset.morph), "morph-paper": via_pair(paper),
            "classic": lambda az: asset.classic(), "nearest": via_pair(asset.nearest),
            "crossfade": via_pair(asset.crossfade)}


def _meshes(quick: bool) -> tuple[str, ...]:
    return ("chair", "tree") if quick else BILLBOARD_MESHES


def _size(quick: bool) -> int:
    return 128 if quick else 256


def _means(rows: list[dict[str, Any]], section: str, params: dict[str, Any]) -> list[dict[str, Any]]:
    """Rows ``mesh = "all"``: each method's metrics and times averaged over the meshes."""
    out = []
    for method in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == method]
        metrics = {k: float(np.mean([r["metrics"][k] for r in sel])) for k in sel[0]["metrics"]}
        t = Timing(float(np.mean([r["ms_median"] for r in sel])), min(r["ms_min"] for r in sel),
                   max(r["ms_max"] for r in sel), sum(r["repeats"] for r in sel))
        out.append(make_row(SUITE, method, dict(section=section, mesh="all", **params), t, metrics=metrics,
                            note=f"mean over {len(sel)} meshes"))
    return out


# --------------------------------------------------------------------------- sections


def pair_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """``K = 2`` inside the arc and beyond it (module docstring)."""
    size = _size(quick)
    rows: dict[str, list[dict[str, Any]]] = {"pair-inside": [], "pair-outside": []}
    for name in _meshes(quick):
        asset = cache.asset(name, 2, size)
        vm = asset.morpher(0)
        note = f"{vm.mode}, {vm.report['layers']} layers, {vm.report['n_used']} mesh pairs"
        inside = {az: cache.truth(name, asset.camera(az)) for az in PAIR_INSIDE}
        outside = {az: cache.truth(name, asset.cameras.camera(az)) for az in PAIR_OUTSIDE}
        params = {"mesh": name, "views": 2, "size": size}
        rows["pair-inside"] += _evaluate(_ring_methods(asset), inside, "pair-inside", params, {"morph": note})
        rows["pair-outside"] += _evaluate(_ring_methods(asset), outside, "pair-outside", params,
                                          {"morph": "clamped to the nearer reference (= nearest)"})
    out: list[dict[str, Any]] = []
    for section, rs in rows.items():
        out += rs + _means(rs, section, {"views": 2, "size": size})
    return out


def ring_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """Rings of K views over 360 degrees (module docstring)."""
    size = _size(quick)
    azimuths = np.arange(12 if quick else 24) * (30.0 if quick else 15.0) + 7.5
    out: list[dict[str, Any]] = []
    for k in ((8,) if quick else RINGS):
        rs: list[dict[str, Any]] = []
        for name in _meshes(quick):
            asset = cache.asset(name, k, size)
            truths = {float(az): cache.truth(name, asset.camera(float(az))) for az in azimuths}
            layers = sorted({asset.morpher(p).report["layers"] for p in range(k)})
            rs += _evaluate(_ring_methods(asset), truths, "ring", {"mesh": name, "views": k, "size": size},
                            {"morph": f"layers {layers}"})
        out += rs + _means(rs, "ring", {"views": k, "size": size})
    return out


def _golden_azimuths(n: int) -> np.ndarray:
    """``n`` azimuths ``5 + 137.5078 m`` (mod 360, the golden angle): spread evenly over the
    circle and incommensurate with every ring's spacing, so no ring's references are favoured
    (``7.5 + 15 m`` would fall exactly on a 48-view ring's references)."""
    return np.mod(5.0 + (180.0 * (3.0 - np.sqrt(5.0))) * np.arange(n), 360.0)


def _dense_views(cache: AssetCache, name: str, quad: QuadCameras, n: int) -> tuple[ViewRing, np.ndarray]:
    """``n`` views on a full ring rendered by the camera rule of ``quad`` (premultiplied float32)."""
    ring = ViewRing(n)
    return ring, np.stack([cache.truth(name, quad.camera(a)) for a in ring.azimuths_deg()])


def equal_memory_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """K-view morph rings (K = 8, and 12 unless quick) against denser rings of half-resolution
    views of the same bytes."""
    size = _size(quick)
    out: list[dict[str, Any]] = []
    for k in ((8,) if quick else (8, 12)):
        rs: list[dict[str, Any]] = []
        for name in _meshes(quick):
            rs += _equal_memory_case(cache, name, k, size, quick)
        out += rs + _means(rs, "equal-memory", {"views": k, "size": size})
    return out


def _equal_memory_case(cache: AssetCache, name: str, k: int, size: int, quick: bool) -> list[dict[str, Any]]:
    small = size // 2
    azimuths = _golden_azimuths(12 if quick else 24)
    asset = cache.asset(name, k, size)
    truths = {float(az): cache.truth(name, asset.camera(float(az))) for az in azimuths}
    params = {"mesh": name, "views": k, "size": size}
    rs = _evaluate({"morph": _ring_methods(asset)["morph"]}, truths, "equal-memory", params,
                   {"morph": f"{asset.memory_bytes} bytes ({asset.image_bytes} colour)"})
    per_view = 4 * small * small
    counts = {"dense-images": asset.image_bytes // per_view, "dense-total": asset.memory_bytes // per_view}
    q = asset.cameras
    dense_quad = QuadCameras(q.pivot, q.distance, q.elevation_deg, q.half_extent, (small, small))
    big_quad = QuadCameras(q.pivot, q.distance, q.elevation_deg, q.half_extent, (size, size))
    for label, n in counts.items():
        ring, views = _dense_views(cache, name, dense_quad, int(n))
        az_ref = ring.azimuths_deg()
        dense_truth = {}
        for az in azimuths:
            i, j, s, _ = ring.pair(float(az))
            dense_truth[float(az)] = cache.truth(name, big_quad.chord_camera(az_ref[i], az_ref[j], s))

        def up(img: np.ndarray) -> np.ndarray:
            return cv2.resize(img, (size, size), interpolation=cv2.INTER_LINEAR)

        def nearest(az: float, ring: ViewRing = ring, views: np.ndarray = views) -> np.ndarray:
            i, j, s, _ = ring.pair(az)
            return up(views[i if s <= 0.5 else j])

        def crossfade(az: float, ring: ViewRing = ring, views: np.ndarray = views) -> np.ndarray:
            i, j, s, _ = ring.pair(az)
            return up(cv2.addWeighted(views[i], 1.0 - s, views[j], s, 0.0))

        note = f"{n} views of {small}^2: {int(n) * per_view} bytes"
        rs += _evaluate({f"{label}-nearest": nearest, f"{label}-crossfade": crossfade}, dense_truth,
                        "equal-memory", params, {f"{label}-nearest": note, f"{label}-crossfade": note})
    return rs


def bake_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """Bake time of a K = 8, 256^2, 3-level asset, and one call of each method on it."""
    rows: list[dict[str, Any]] = []
    renderer = cache.renderer
    bake_asset(cache.mesh("teapot"), renderer, views=2, size=64, levels=1)  # warm-up (compiled kernels)
    for name in (("cow",) if quick else BILLBOARD_MESHES):
        mesh = cache.mesh(name)
        holder: list[BillboardAsset] = []
        cpu: list[float] = []

        def bake(mesh: trimesh.Trimesh = mesh, name: str = name, holder: list[BillboardAsset] = holder,
                 cpu: list[float] = cpu) -> None:
            c0 = time.process_time()
            holder[:] = [bake_asset(mesh, renderer, name=name, views=8, size=256, levels=3)]
            cpu.append(time.process_time() - c0)

        t = time_call(bake, repeats=1 if quick else 2, warmup=0)
        asset = holder[0]
        params = {"section": "bake", "mesh": name, "views": 8, "size": 256}
        metrics = {"faces": float(len(mesh.faces)), "memory_bytes": float(asset.memory_bytes),
                   "cpu_ms": 1e3 * float(np.median(cpu))}
        rows.append(make_row(SUITE, "bake", params, t, metrics=metrics,
                             note="8 renders + the level-0 morphers of 8 pairs (target < 2 s)"))
        rows += _call_rows(asset, name, 5 if quick else 11)
    return rows


def _call_rows(asset: BillboardAsset, name: str, repeats: int) -> list[dict[str, Any]]:
    """One call of ``morph``, ``morph-paper``, ``crossfade`` and ``nearest`` at azimuth 100, level 0."""
    i, j, s, _ = asset.ring.pair(100.0)
    calls = time_calls({"morph": lambda: asset.morph(i, j, s),
                        "morph-paper": lambda: asset.morph(i, j, s, coverage=False),
                        "crossfade": lambda: asset.crossfade(i, j, s),
                        "nearest": lambda: asset.nearest(i, j, s)}, repeats=repeats)
    params = {"section": "call", "mesh": name, "views": asset.ring.views, "size": asset.size[0]}
    return [make_row(SUITE, method, params, tm, note=f"azimuth 100 (pair {(i, j)}, s = {s:.3f}), level 0")
            for method, tm in calls.items()]


# --------------------------------------------------------------------------- scenes


#: Camera elevation of the scene accuracy and stability orbits (the assets' default ring elevation).
ELEVATION_DEG = 10.0


def _modes(cache_capacity: int = 4096) -> dict[str, BillboardMode]:
    return {"morph": MorphMode(MorphCache(cache_capacity)),
            "morph-paper": MorphMode(MorphCache(cache_capacity), coverage=False), "classic": ClassicMode(),
            "nearest": NearestMode(), "crossfade": CrossfadeMode(MorphCache(cache_capacity))}


class TrueViewMode(BillboardMode):
    """The best image a billboard of an asset's camera rule can show: the mesh rendered by the
    asset's camera at the placement's viewing azimuth and level (no morph, no clamping), put on
    the same quad. What a billboard still misses then is the quad's own error (a flat image for
    a solid object, the bake's perspective for the scene's).

    Parameters
    ----------
    renderer : SceneRenderer
        Renders the views.
    items : mapping of str to sequence of Item
        Each asset's bake items (object frame).
    """

    name = "true-view"

    def __init__(self, renderer: SceneRenderer, items: Mapping[str, Sequence[Item]]) -> None:
        self.renderer = renderer
        self.items = dict(items)

    def image(self, asset: BillboardSource, placement: Placement) -> tuple[np.ndarray, float]:
        """The rendered view, premultiplied, and ``outside_deg`` 0.

        Parameters
        ----------
        asset : BillboardSource
            A :class:`BillboardAsset` (its ``cameras``).
        placement : Placement
            Where and how it is drawn.

        Returns
        -------
        image : (h, w, 4) float32
            Premultiplied RGBA.
        outside_deg : float
            ``0``.
        """
        if not isinstance(asset, BillboardAsset):
            raise ValidationError(expected_got("asset", "a BillboardAsset (true-view renders its cameras)",
                                               type(asset).__name__))
        cam = asset.cameras.camera(placement.azimuth_deg, placement.level)
        img = self.renderer.source_view(cam, self.items[asset.name], bake_lights(), ambient=BAKE_AMBIENT)
        return to_premultiplied(img.astype(np.float32) / np.float32(255.0), 4), 0.0


def _accuracy_scene(asset: BillboardSource, rng: np.random.Generator) -> BillboardScene:
    # 9 instances on a 3 x 3 grid 2.5 units apart, random yaws: the orbit sees each from every side
    g = np.linspace(-2.5, 2.5, 3)
    xy = np.array([(x, y) for x in g for y in g])
    inst = Instances((asset.name,), np.zeros(9, np.int64), xy, rng.uniform(0, 360, 9), np.ones(9))
    return BillboardScene({asset.name: asset}, inst, backdrop=Backdrop())


def scene_accuracy_rows(assets: Sequence[BillboardSource], meshes: Mapping[str, Sequence[Item]],
                        renderer: SceneRenderer, lights: Sequence[Light], ambient: float, *,
                        frames: int = 24, shape: tuple[int, int] = (480, 640),
                        seed: int = 0) -> list[dict[str, Any]]:
    """Per-billboard accuracy of each mode against the real meshes along an orbit (see the module notes).

    Parameters
    ----------
    assets : sequence of BillboardSource
        One row group per asset (its ring: ``K = 2`` split inside/outside the arc).
    meshes : mapping of str to sequence of Item
        The items each asset was baked from (object frame).
    renderer : SceneRenderer
        Renders the real meshes (the reference).
    lights, ambient
        The bake's lights and ambient level.
    frames : int
        Orbit frames (a full circle).
    shape : (H, W)
        Frame size in pixels.
    seed : int
        Seeds the instances' yaws.

    Returns
    -------
    list of dict
        Rows (``make_row``) with mean ``iou``/``psnr`` and the number of billboard samples ``n``.
    """
    rows: list[dict[str, Any]] = []
    for asset in assets:
        scene = _accuracy_scene(asset, np.random.default_rng(seed))
        radius = 8.0
        height = float(asset.pivot[2]) + radius * np.tan(np.radians(ELEVATION_DEG))
        path = OrbitPath(centre=(0.0, 0.0, float(asset.pivot[2])), radius=radius, height=height,
                         start_deg=0.0, end_deg=360.0 * (frames - 1) / frames)
        truth_mode = MeshMode(renderer, {asset.name: meshes[asset.name]}, lights, ambient, supersample=3)
        modes: dict[str, BillboardMode] = _modes()
        if isinstance(asset, BillboardAsset):
            modes["true-view"] = TrueViewMode(renderer, {asset.name: meshes[asset.name]})
        samples: dict[str, list[dict[str, Any]]] = {m: [] for m in modes}
        ms: dict[str, list[float]] = {m: [] for m in modes}
        for cam in path.cameras(frames, shape):
            truth = scene.render(cam, truth_mode)
            for name, mode in modes.items():
                f = scene.render(cam, mode)
                samples[name] += box_errors(f, truth)
                ms[name].append(f.stats.ms / 1e3)
        k = asset.ring.views
        groups: dict[str, Any] = {"all": lambda o: True}
        if k == 2:
            groups = {"inside": lambda o: o == 0.0, "outside<=30": lambda o: 0.0 < o <= 30.0}
        for gname, keep in groups.items():
            for name, errs in samples.items():
                sel = [e for e in errs if keep(asset.ring.pair(e["azimuth_deg"])[3])]
                if not sel:
                    continue
                params = {"section": "scene-accuracy", "mesh": asset.name, "views": k, "azimuths": gname,
                          "size": asset.size[0]}
                rows.append(make_row(SUITE, name, params,
                                     Timing.from_seconds(ms[name]),
                                     metrics={"iou": float(np.mean([e["iou"] for e in sel])),
                                              "psnr": float(np.mean([e["psnr"] for e in sel])),
                                              "n": float(len(sel))},
                                     note=f"{len(sel)} billboard views, {frames} orbit frames (frame times: "
                                     "9 billboards, cache warm from frame to frame)"))
    return rows


def step_changes(layers: Sequence[np.ndarray]) -> np.ndarray:
    """Mean absolute change of consecutive premultiplied layers ``(H, W, 4)`` over the pixels
    either covers (alpha > 0), ``(len - 1,)``.

    Parameters
    ----------
    layers : sequence of numpy.ndarray
        ``(H, W, 4)`` float premultiplied RGBA layers, consecutive frames.

    Returns
    -------
    numpy.ndarray
        ``(len(layers) - 1,)`` float64 mean absolute change per step (0 where neither covers a pixel).
    """
    out = []
    for a, b in zip(layers[:-1], layers[1:], strict=True):
        m = (a[..., 3] > 0) | (b[..., 3] > 0)
        out.append(float(np.abs(a[m] - b[m]).mean()) if m.any() else 0.0)
    return np.array(out)


def temporal_rows(asset: BillboardSource, meshes: Mapping[str, Sequence[Item]] | None = None,
                  renderer: SceneRenderer | None = None, lights: Sequence[Light] = (),
                  ambient: float = 0.35, *, start_deg: float = -30.0, end_deg: float = 30.0,
                  step_deg: float = 0.5, shape: tuple[int, int] = (480, 640)) -> list[dict[str, Any]]:
    """Image change per ``step_deg`` orbit step about one instance, per mode (see the module notes).

    With ``meshes`` and ``renderer``, the real meshes' row is added as the reference.

    Parameters
    ----------
    asset : BillboardSource
        The billboard asset, one instance at the origin.
    meshes : mapping of str to sequence of Item, optional
        The items the asset was baked from (object frame), by asset name.
    renderer : SceneRenderer, optional
        Renders the real meshes.
    lights : sequence of Light
        The bake's lights (for the real meshes).
    ambient : float
        The bake's ambient level.
    start_deg : float
        Orbit azimuth of the first frame, degrees.
    end_deg : float
        Orbit azimuth of the last frame, degrees.
    step_deg : float
        Orbit step between frames, degrees.
    shape : (int, int)
        Frame ``(H, W)`` in pixels.

    Returns
    -------
    list of dict
        Rows with ``step_max``, ``step_median``, ``max_over_median``.
    """
    inst = Instances((asset.name,), np.zeros(1, np.int64), np.zeros((1, 2)), np.zeros(1), np.ones(1))
    scene = BillboardScene({asset.name: asset}, inst, backdrop=Backdrop())
    radius = 4.0 * max(asset.half_extent)
    height = float(asset.pivot[2]) + radius * np.tan(np.radians(ELEVATION_DEG))
    path = OrbitPath(centre=tuple(float(v) for v in asset.pivot), radius=radius, height=height)
    n = int(round((end_deg - start_deg) / step_deg)) + 1
    cams = [path.camera_at_deg(start_deg + k * step_deg, shape) for k in range(n)]
    modes: dict[str, Any] = dict(_modes())
    if meshes is not None and renderer is not None:
        modes["mesh"] = MeshMode(renderer, {asset.name: meshes[asset.name]}, lights, ambient, supersample=3)
    rows = []
    for name, mode in modes.items():
        frames = [scene.render(c, mode) for c in cams]
        d = step_changes([f.layer for f in frames])
        med, mx = float(np.median(d)), float(d.max())
        params = {"section": "scene-temporal", "mesh": asset.name, "views": asset.ring.views,
                  "from_deg": start_deg, "to_deg": end_deg, "step_deg": step_deg}
        rows.append(make_row(SUITE, name, params,
                             Timing.from_seconds([f.stats.ms / 1e3 for f in frames]),
                             metrics={"step_max": mx, "step_median": med,
                                      "max_over_median": mx / med if med > 0 else 1e9},
                             note=f"{len(d)} steps"))
    return rows


def _field(asset: BillboardSource, n: int, seed: int) -> tuple[BillboardScene, float]:
    inst = place_random([asset.name], n, np.random.default_rng(seed))
    half = max(1.0, 1.5 * np.sqrt(n) / 2)
    return BillboardScene({asset.name: asset}, inst, backdrop=Backdrop()), half


def speed_rows(asset: BillboardSource, items: Sequence[Item], renderer: SceneRenderer,
               lights: Sequence[Light], ambient: float, *, counts: Sequence[int] = (10, 100, 1000),
               shape: tuple[int, int] = (480, 640), faces: int = 0, repeats: int = 5,
               mesh_repeats: int = 3, seed: int = 0) -> list[dict[str, Any]]:
    """Frame times per billboard count and mode, cold and warm cache (see the module notes).

    Parameters
    ----------
    asset : BillboardSource
        The billboard asset, instanced at random over a field.
    items : sequence of Item
        The items the asset was baked from (object frame), for the mesh rows.
    renderer : SceneRenderer
        Renders the mesh rows.
    lights : sequence of Light
        The bake's lights.
    ambient : float
        The bake's ambient level.
    counts : sequence of int
        Billboard counts, one case each.
    shape : (int, int)
        Frame ``(H, W)`` in pixels.
    faces : int
        The mesh's face count, recorded in the rows' params.
    repeats : int
        Timed frames of the billboard modes.
    mesh_repeats : int
        Timed frames of the mesh modes.
    seed : int
        Seeds the instances' placement.

    Returns
    -------
    list of dict
        Rows with ``n_drawn``, ``hit_rate`` (warm rows) in the metrics.
    """
    rows: list[dict[str, Any]] = []
    for n in counts:
        rows += _speed_case(asset, items, renderer, lights, ambient, n, shape, faces, repeats, mesh_repeats,
                            seed)
    return rows


def _speed_case(asset: BillboardSource, items: Sequence[Item], renderer: SceneRenderer,
                lights: Sequence[Light], ambient: float, n: int, shape: tuple[int, int], faces: int,
                repeats: int, mesh_repeats: int, seed: int) -> list[dict[str, Any]]:
    scene, half = _field(asset, n, seed)
    cam = PanPath.over(half).camera_at(0.5, shape)
    params = {"section": "scene-speed", "mesh": asset.name, "faces": faces, "views": asset.ring.views,
              "billboards": n, "size": asset.size[0]}
    drawn = float(len(scene.plan(cam).placements))
    rows = []

    def row(method: str, t: Timing, note: str = "", **metrics: float) -> None:
        rows.append(make_row(SUITE, method, params, t, metrics={"n_drawn": drawn, **metrics}, note=note))

    for name, cls in (("morph", MorphMode), ("crossfade", CrossfadeMode)):
        row(f"{name}-cold", time_call(lambda cls=cls: scene.render(cam, cls(MorphCache())),
                                      repeats=max(2, repeats // 2), warmup=1), "a new cache every frame")
    # the warm modes and the classic billboards interleaved (time_calls): their ratio holds on a busy machine
    warm = {"morph-warm": MorphMode(MorphCache()), "crossfade-warm": CrossfadeMode(MorphCache()),
            "classic": ClassicMode()}
    times = time_calls({k: (lambda m=m: scene.render(cam, m)) for k, m in warm.items()}, repeats=repeats,
                       warmup=1)
    for k, m in warm.items():
        if k == "classic":
            row(k, times[k])
        else:
            row(k, times[k], "the same frame again", hit_rate=scene.render(cam, m).stats.hit_rate)
    mesh = MeshMode(renderer, {asset.name: items}, lights, ambient)
    row("mesh", time_call(lambda: scene.render(cam, mesh), repeats=mesh_repeats, warmup=1),
        "every instance in the frustum rendered")
    quads = MeshMode(renderer, {asset.name: [Item(_quad_mesh(asset))]}, lights, ambient)
    row("gl-quads", time_call(lambda: scene.render(cam, quads), repeats=mesh_repeats, warmup=1),
        "one untextured quad per instance in pyrender: a lower bound of a GL textured-quad compositor")
    classic_ms = next(r["ms_median"] for r in rows if r["method"] == "classic")
    for r in rows:
        r["metrics"]["x_classic"] = r["ms_median"] / classic_ms
    return rows


def _quad_mesh(asset: BillboardSource) -> trimesh.Trimesh:
    """The asset's billboard quad (facing +x) as a two-triangle mesh."""
    hw, hh = asset.half_extent
    px, py, pz = (float(v) for v in asset.pivot)
    v = [[px, py - hw, pz - hh], [px, py + hw, pz - hh], [px, py + hw, pz + hh], [px, py - hw, pz + hh]]
    return trimesh.Trimesh(v, [[0, 1, 2], [0, 2, 3]], process=False)


def hit_rate_rows(asset: BillboardSource, *, n: int = 1000, frames: int = 60, step_deg: float = 0.5,
                  shape: tuple[int, int] = (480, 640), quantum_deg: float = 1.0, capacity: int = 4096,
                  seed: int = 0) -> list[dict[str, Any]]:
    """The morph cache along an orbit of an ``n``-billboard field, ``step_deg`` per frame
    (see the module notes); the timing is the frame time along the path (warm from frame to frame).

    Parameters
    ----------
    asset : BillboardSource
        The billboard asset, instanced at random over a field.
    n : int
        Billboards in the field.
    frames : int
        Frames along the orbit.
    step_deg : float
        Orbit step between frames, degrees.
    shape : (int, int)
        Frame ``(H, W)`` in pixels.
    quantum_deg : float
        Azimuth quantum of the morph cache's keys, degrees.
    capacity : int
        Morph cache capacity (entries).
    seed : int
        Seeds the instances' placement.

    Returns
    -------
    list of dict
        One row: ``hit_rate`` after the first frame, ``cache_entries``, ``cache_mb``, ``n_drawn``.
    """
    scene, half = _field(asset, n, seed)
    base = OrbitPath.around(half)
    path = replace(base, end_deg=base.start_deg + step_deg * (frames - 1))
    mode = MorphMode(MorphCache(capacity), quantum_deg=quantum_deg)
    hits = misses = drawn = 0
    ms = []
    for k, cam in enumerate(path.cameras(frames, shape)):
        f = scene.render(cam, mode)
        if k > 0:  # the first frame fills the cache
            hits += f.stats.hits
            misses += f.stats.misses
            drawn += f.stats.n_drawn
            ms.append(f.stats.ms)
    rate = hits / max(hits + misses, 1)
    params = {"section": "scene-hit-rate", "mesh": asset.name, "views": asset.ring.views, "billboards": n,
              "frames": frames, "step_deg": step_deg, "quantum_deg": quantum_deg}
    return [make_row(SUITE, "morph-path", params,
                     Timing.from_seconds([m / 1e3 for m in ms]),
                     metrics={"hit_rate": rate, "cache_entries": float(len(mode.cache)),
                              "cache_mb": mode.cache.nbytes / 2**20, "n_drawn": drawn / max(len(ms), 1)},
                     note="orbit about the field; counts after the first frame")]


def scene_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """The scene section: accuracy, temporal stability, speed and cache rows (module docstring).

    Parameters
    ----------
    cache : AssetCache
        Meshes and baked assets shared by the sections.
    quick : bool
        Smaller assets and frames, fewer cases (a smoke run).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    size = 128 if quick else 256
    shape = (240, 320) if quick else (480, 640)
    lights, ambient = bake_lights(), BAKE_AMBIENT
    r = cache.renderer
    cow = cache.mesh("cow")
    items = {"cow": bake_items(cow)}
    assets = [cache.asset("cow", k, size, 3) for k in (2, 8)]
    rows = scene_accuracy_rows(assets, items, r, lights, ambient, frames=8 if quick else 24, shape=shape)
    for row in rows:
        row["params"]["distance_factor"] = DISTANCE_FACTOR
    for factor in () if quick else (4.0, 8.0):
        # the same K = 2 scene with the bake cameras nearer (the default's evidence)
        near = cache.asset("cow", 2, size, 3, distance_factor=factor)
        other = scene_accuracy_rows([near], items, r, lights, ambient, frames=24, shape=shape)
        for row in other:
            row["params"].update(section="scene-distance", distance_factor=factor)
        rows += other
    for a in assets:
        span = (-30.0, 0.0 if quick else 30.0) if a.ring.views == 2 else (0.0, 45.0 if quick else 90.0)
        rows += temporal_rows(a, items, r, lights, ambient, start_deg=span[0], end_deg=span[1], shape=shape)
    meshes = {len(cow.faces): (assets[1], items["cow"])}
    if not quick:
        big = normalize(sample_mesh("cow", faces=60000))
        big_asset = bake_asset(big, r, name="cow", views=8, size=size, levels=3)
        meshes[len(big.faces)] = (big_asset, bake_items(big))
    counts = (10, 100) if quick else (10, 100, 1000)
    for faces, (a8, its) in meshes.items():
        rows += speed_rows(a8, its, r, lights, ambient, counts=counts, shape=shape, faces=faces,
                           repeats=3 if quick else 5, mesh_repeats=2 if quick else 3)
    for step in (0.5, 3.0):
        rows += hit_rate_rows(assets[1], n=100 if quick else 1000, frames=10 if quick else 60,
                              step_deg=step, shape=shape)
    return rows


#: The suite's sections, in order; each ``(cache, quick) -> rows``.
SECTIONS: list[Callable[[AssetCache, bool], list[dict[str, Any]]]] = [
    pair_rows, ring_rows, equal_memory_rows, bake_rows, scene_rows]


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """Run every section of :data:`SECTIONS`; see the module docstring.

    Parameters
    ----------
    quick : bool
        Smaller assets and fewer cases in every section (a smoke run).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    rows: list[dict[str, Any]] = []
    with Renderer() as r:
        cache = AssetCache(r)
        for section in SECTIONS:
            rows += section(cache, quick)
    return rows
