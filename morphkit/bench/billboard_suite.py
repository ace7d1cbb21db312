"""Suite ``billboards``: view-morphed billboard assets against the classic billboard and impostors.

Assets. Each mesh of :data:`morphkit.meshes.BILLBOARD_MESHES` (teapot, chair, cow,
tree, person; normalised, coloured by the 3-D checker, ``appearance="checker"`` of
:func:`morphkit.billboard.bake_items`: they have no look of their own, lit by
:func:`morphkit.billboard.bake_lights`) is baked with :func:`morphkit.billboard.bake_asset`
(elevation 10 degrees). The ``textured-*`` sections bake textured meshes in their own look.

Ground truth. For a viewing azimuth the asset shows the view of a virtual camera
(:meth:`BillboardAsset.camera`: the in-between camera of the morph, on the chord
between the two references); pyrender renders the mesh with that camera, the
bake's items and lights, and every method's image is compared with it in the
image frame of the billboard quad (the whole image is the billboard's box).
Beyond the arc of a ``K = 2`` asset the truth is the view from the ring camera
at the true azimuth (``asset.cameras.camera``), while the asset shows the
clamped reference.

Metrics (per azimuth, then averaged): ``iou`` -- silhouette IoU (alpha > 0.5,
:func:`morphkit.imaging.metrics.shadow_iou`), ``err_iou = 1 - iou``; ``psnr`` -- on the
premultiplied RGB (the billboard over black) over the whole box, data range 1
(:func:`morphkit.imaging.metrics.psnr`; identical images are capped at 99 dB); ``*_min``
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

* ``textured-ring`` (``K = 8``, azimuths ``7.5 + 15 n``) and ``textured-pair`` (``K = 2``,
  inside the arc) -- textured meshes baked in their own look (``appearance="own"``):
  the packaged photo crate (:func:`morphkit.programs.fixtures.textured_demo_asset`) and the
  alpha-masked leaf plant (:func:`morphkit.programs.fixtures.write_leaf_plant`), loaded ``+z`` up
  by :func:`morphkit.meshes.load_mesh`, against their real meshes drawn in the same look
  (:meth:`BillboardAsset.items`), same cameras: ``morph``, ``classic``, ``nearest``,
  ``crossfade``; besides IoU and PSNR, the detail each keeps: ``psnr_hp`` (PSNR of the
  high-pass band, the colour minus its Gaussian blur of ``HIGH_PASS_SIGMA`` px) and
  ``sharpness`` (mean Sobel gradient magnitude over the truth's; 1 is as sharp, below 1
  blurred); ``textured-bake`` -- the photo crate's bake (``K = 8``, 3 levels) in its own
  look against the checker, interleaved; ``one-colour`` -- a box of one vertex colour
  (``ONE_COLOUR``) baked at elevation 0 (only its vertical faces, at right angles to
  the bake light): the largest channel error (``err_255``, 0..255) of the mean covered colour
  of the morph at ``s = 1/2`` (``err_255_ref``: of a reference) against the analytic
  :func:`morphkit.billboard.baking.bakelook.sideways_colour` (target within 2);
* ``scene-*`` -- scenes of many billboards against the real meshes, run by
  :func:`scene_rows`: accuracy, temporal stability, frame time and the morph cache's
  hit rate (:mod:`morphkit.bench.billboard_scenes`, where each kind of row is described).

Rows with ``mesh = "all"`` average the per-mesh rows.
``--quick``: chair and tree, 128^2 (``equal-memory``: 128^2 vs 64^2), ``K = 8``
rings only, 12 ring azimuths, one bake; textured assets at 96^2 (else 192^2), 8 ring
azimuths, one bake of each look; scenes at 320 x 240, 10 and 100
billboards, the ~6k-face cow only.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import cv2
import numpy as np
import trimesh

from .. import tol
from ..billboard import (
    BAKE_AMBIENT,
    BillboardAsset,
    QuadCameras,
    ViewRing,
    bake_asset,
    bake_items,
    bake_lights,
)
from ..billboard.baking.bakelook import sideways_colour
from ..billboard.cameras import DISTANCE_FACTOR
from ..camera import CameraModel
from ..imaging.metrics import psnr, shadow_iou
from ..memo import Memo
from ..meshes import BILLBOARD_MESHES, load_mesh, normalize, sample_mesh
from ..programs.fixtures import textured_demo_asset, write_leaf_plant
from ..protocols import SceneRenderer
from ..scene import Item
from ..validate import as_int
from . import dome_suite
from .billboard_scenes import SUITE, hit_rate_rows, scene_accuracy_rows, speed_rows, temporal_rows
from .harness import Timing, make_row, pick_sections, section_name, time_call, time_calls

__all__ = ["run", "AssetCache", "SECTIONS", "section_name", "selected_sections", "SUITE",
           "FLOOR_METHOD", "PLOT_OPTIONS", "quality", "scene_rows"]

#: The method the table's ratio column divides by.
FLOOR_METHOD = "crossfade"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite.
PLOT_OPTIONS: dict[str, Any] = {
    "error_key": "err_iou", "panel_keys": ("section",), "scene_keys": ("section", "mesh"),
    "defaults": ({"method": "morph", "views": 2},),
    "default_label": "default: morph, K = 2 (bake_asset)"}

PAIR_INSIDE = (-25.0, -15.0, -5.0, 5.0, 15.0, 25.0)
PAIR_OUTSIDE = (-60.0, -45.0, -35.0, 35.0, 45.0, 60.0)
RINGS = (6, 8, 12)
PSNR_CAP = 99.0
#: Gaussian sigma (px) of the blur the ``textured`` section's high-pass band subtracts.
HIGH_PASS_SIGMA = 2.0


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
        self.max_assets = as_int(max_assets, "max_assets", lo=1)
        self._meshes: Memo[str, trimesh.Trimesh] = Memo()
        self._items: Memo[str, list[Item]] = Memo()
        # (name, views, size, levels, distance factor) -> (asset, bake seconds)
        self._assets: Memo[tuple[Any, ...], tuple[BillboardAsset, float]] = Memo(self.max_assets)

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
        return self._meshes.get(name, lambda: normalize(sample_mesh(name)))

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
        return self._baked(name, views, size, levels, distance_factor)[0]

    def _baked(self, name: str, views: int, size: int, levels: int,
               distance_factor: float) -> tuple[BillboardAsset, float]:
        """``(asset, bake seconds)``, baked on the first call (see :meth:`asset`)."""

        def bake() -> tuple[BillboardAsset, float]:
            t0 = time.perf_counter()
            a = bake_asset(self.mesh(name), self.renderer, name=name, views=views, size=size, levels=levels,
                           distance_factor=distance_factor, appearance="checker")
            return a, time.perf_counter() - t0

        return self._assets.get((name, views, size, levels, float(distance_factor)), bake)

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
        return self._baked(name, views, size, levels, DISTANCE_FACTOR)[1]

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
        items = self._items.get(name, lambda: bake_items(self.mesh(name), "checker"))
        img = self.renderer.source_view(camera, items, bake_lights(), ambient=BAKE_AMBIENT)
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
        note = f"{vm.mode}, {vm.report.layers} layers, {vm.report.n_used} mesh pairs"
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
            layers = sorted({asset.morpher(p).report.layers for p in range(k)})
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
    # warm-up (compiled kernels)
    bake_asset(cache.mesh("teapot"), renderer, views=2, size=64, levels=1, appearance="checker")
    for name in (("cow",) if quick else BILLBOARD_MESHES):
        mesh = cache.mesh(name)
        holder: list[BillboardAsset] = []
        cpu: list[float] = []

        def bake(mesh: trimesh.Trimesh = mesh, name: str = name, holder: list[BillboardAsset] = holder,
                 cpu: list[float] = cpu) -> None:
            c0 = time.process_time()
            holder[:] = [bake_asset(mesh, renderer, name=name, views=8, size=256, levels=3,
                                    appearance="checker")]
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
    assets = [cache.asset("cow", k, size, 3) for k in (2, 8)]
    items = {"cow": assets[0].items(cow)}  # the assets' look (the checker)
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
        big_asset = bake_asset(big, r, name="cow", views=8, size=size, levels=3, appearance="checker")
        meshes[len(big.faces)] = (big_asset, big_asset.items(big))
    counts = (10, 100) if quick else (10, 100, 1000)
    for faces, (a8, its) in meshes.items():
        rows += speed_rows(a8, its, r, lights, ambient, counts=counts, shape=shape, faces=faces,
                           repeats=3 if quick else 5, mesh_repeats=2 if quick else 3)
    for step in (0.5, 3.0):
        rows += hit_rate_rows(assets[1], n=100 if quick else 1000, frames=10 if quick else 60,
                              step_deg=step, shape=shape)
    return rows


# --------------------------------------------------------------------------- textured


def _premultiplied(img: np.ndarray) -> np.ndarray:
    a = img.astype(np.float32) / 255.0
    return np.concatenate([a[..., :3] * a[..., 3:], a[..., 3:]], axis=2)


def _high_pass(img: np.ndarray) -> np.ndarray:
    """The detail band of a premultiplied image's colour: itself minus a Gaussian blur (sigma 2 px)."""
    rgb = np.ascontiguousarray(img[..., :3])
    return rgb - cv2.GaussianBlur(rgb, (0, 0), HIGH_PASS_SIGMA)


def _sharpness(img: np.ndarray) -> float:
    """Mean gradient magnitude (Sobel) of the premultiplied colour's luminance-like mean."""
    g = np.ascontiguousarray(img[..., :3].mean(axis=2))
    gx, gy = cv2.Sobel(g, cv2.CV_32F, 1, 0), cv2.Sobel(g, cv2.CV_32F, 0, 1)
    return float(np.hypot(gx, gy).mean())


def _textured_meshes(folder: str) -> dict[str, trimesh.Trimesh]:
    """The textured assets of the section: the packaged photo crate and the alpha-masked leaf plant."""
    return {"photo-crate": load_mesh(textured_demo_asset()),
            "leaf-plant": load_mesh(write_leaf_plant(folder))}


def _textured_case(renderer: SceneRenderer, name: str, mesh: trimesh.Trimesh, views: int, size: int,
                   azimuths: np.ndarray) -> list[dict[str, Any]]:
    asset = bake_asset(mesh, renderer, name=name, views=views, size=size, levels=1)
    items, lights = asset.items(mesh), bake_lights()
    truths = {float(az): _premultiplied(renderer.source_view(asset.camera(float(az)), items, lights,
                                                               ambient=BAKE_AMBIENT)) for az in azimuths}
    methods = {k: v for k, v in _ring_methods(asset).items() if k != "morph-paper"}
    section = "textured-ring" if views > 2 else "textured-pair"
    rows = _evaluate(methods, truths, section, {"mesh": name, "views": views, "size": size})
    for row in rows:  # the detail the method keeps: its high-pass band and its sharpness against the truth
        fn = methods[row["method"]]
        hp, sharp = [], []
        for az, gt in truths.items():
            img = fn(az)
            hp.append(min(psnr(_high_pass(img), _high_pass(gt), data_range=1.0), PSNR_CAP))
            sharp.append(_sharpness(img) / max(_sharpness(gt), tol.ZERO))
        row["metrics"].update(psnr_hp=float(np.mean(hp)), sharpness=float(np.mean(sharp)))
    return rows


#: The stored (sRGB) vertex colour of the ``one-colour`` row's box.
ONE_COLOUR = (220, 60, 40)


def one_colour_box() -> trimesh.Trimesh:
    """A 0.6 x 0.4 x 1 box standing on ``z = 0``, every vertex :data:`ONE_COLOUR`.

    Returns
    -------
    trimesh.Trimesh
        With ``ColorVisuals`` vertex colours.
    """
    box = trimesh.creation.box(extents=(0.6, 0.4, 1.0))
    box.apply_translation([0.0, 0.0, 0.5])
    box.visual.vertex_colors = np.tile([*ONE_COLOUR, 255], (len(box.vertices), 1)).astype(np.uint8)
    return box


def _one_colour_rows(renderer: SceneRenderer, size: int) -> list[dict[str, Any]]:
    """A box of one vertex colour seen at elevation 0 (only its vertical faces, at right angles to
    the light): the mean of the covered pixels against the analytic shading (:func:`sideways_colour`)."""
    asset = bake_asset(one_colour_box(), renderer, name="red-box", views=2, size=size, levels=1,
                       elevation_deg=0.0)
    want = sideways_colour(ONE_COLOUR)
    t0 = time.perf_counter()
    img = asset.morph(0, 1, 0.5)
    secs = time.perf_counter() - t0
    errs = []
    for im in (asset.reference(0), img):
        cov = im[..., 3] > 0.99
        mean = 255.0 * (im[..., :3][cov] / im[..., 3:][cov]).mean(axis=0)
        errs.append(float(np.abs(mean - want).max()))
    return [make_row(SUITE, "morph", {"section": "one-colour", "mesh": "red-box", "views": 2, "size": size},
                     Timing.from_seconds([secs]), metrics={"err_255": errs[1], "err_255_ref": errs[0]},
                     note=f"expected {np.round(want, 1).tolist()} (target: within 2/255)")]


def textured_rows(cache: AssetCache, quick: bool) -> list[dict[str, Any]]:
    """Textured assets in their own look against their real meshes (module docstring).

    Parameters
    ----------
    cache : AssetCache
        Its renderer bakes and renders (the textured assets are not cached).
    quick : bool
        96^2 and 8 ring azimuths, one bake per look (else 192^2, 24 azimuths, two).

    Returns
    -------
    list of dict
        The ``textured-ring``, ``textured-pair``, ``textured-bake`` and ``one-colour`` rows.
    """
    import tempfile

    r = cache.renderer
    size = 96 if quick else 192
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as folder:
        meshes = _textured_meshes(folder)
        for views in (8, 2):
            rs: list[dict[str, Any]] = []
            azimuths = (np.asarray(PAIR_INSIDE) if views == 2
                        else np.arange(8 if quick else 24) * (45.0 if quick else 15.0) + 7.5)
            for name, mesh in meshes.items():
                rs += _textured_case(r, name, mesh, views, size, azimuths)
            rows += rs + _means(rs, rs[0]["params"]["section"], {"views": views, "size": size})
        mesh = meshes["photo-crate"]
        secs: dict[str, list[float]] = {"checker": [], "own": []}
        cpu: dict[str, list[float]] = {"checker": [], "own": []}
        for appearance in ("checker", "own") * (1 if quick else 2):  # interleaved: the machine's drift
            t0, c0 = time.perf_counter(), time.process_time()
            bake_asset(mesh, r, name="photo-crate", views=8, size=size, levels=3, appearance=appearance)
            secs[appearance].append(time.perf_counter() - t0)
            cpu[appearance].append(time.process_time() - c0)
        for appearance, ss in secs.items():
            params = {"section": "textured-bake", "mesh": "photo-crate", "views": 8, "size": size}
            rows.append(make_row(SUITE, f"bake-{appearance}", params, Timing.from_seconds(ss),
                                 metrics={"cpu_ms": 1e3 * float(np.median(cpu[appearance]))},
                                 note="bake_asset K = 8, 3 levels, in that appearance (interleaved)"))
    rows += _one_colour_rows(r, size)
    return rows


#: The suite's sections, in order; each ``(cache, quick) -> rows``.
SECTIONS: list[Callable[[AssetCache, bool], list[dict[str, Any]]]] = [
    pair_rows, ring_rows, equal_memory_rows, bake_rows, textured_rows, scene_rows]
SECTIONS += dome_suite.SECTIONS

def selected_sections(names: str | None = None) -> list[Callable[[AssetCache, bool], list[dict[str, Any]]]]:
    """The sections named in ``names`` (comma-separated, ``morphkit bench billboards --sections``),
    in :data:`SECTIONS` order; all of them when ``names`` is None or empty.

    Parameters
    ----------
    names : str, optional
        E.g. ``"dome-bands,dome-relit"``.

    Returns
    -------
    list of callable
        The sections to run.

    Raises
    ------
    ValidationError
        A name that is not a section's.
    """
    return pick_sections(names, SECTIONS)


def run(*, quick: bool = False, sections: str | None = None) -> list[dict[str, Any]]:
    """Run every section of :data:`SECTIONS`, or those named in ``sections``; see the module docstring.

    Parameters
    ----------
    quick : bool
        Smaller assets and fewer cases in every section (a smoke run).
    sections : str, optional
        Comma-separated section names (:func:`section_name`, e.g. ``"dome-bands,dome-speed"``);
        None or empty: every section.

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    chosen = selected_sections(sections)  # before the renderer starts: a bad name fails at once
    rows: list[dict[str, Any]] = []
    with Renderer() as r:
        cache = AssetCache(r)
        for section in chosen:
            rows += section(cache, quick)
    return rows
