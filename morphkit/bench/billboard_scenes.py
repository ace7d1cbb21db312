"""The ``scene-*`` sections of ``morphkit bench billboards``: scenes of many billboards
against the real meshes (:func:`morphkit.bench.billboard_suite.scene_rows` runs them;
each kind of row is its own function):

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
  asset rows (:mod:`morphkit.bench.billboard_suite`), the scene camera is not the bake's camera (its distance,
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
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

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
    bake_lights,
    place_random,
)
from ..billboard.compare import box_errors
from ..billboard.protocols import BillboardSource
from ..errors import ValidationError, expected_got
from ..imaging.composite import to_premultiplied
from ..protocols import SceneRenderer
from ..scene import Item, Light
from .harness import Timing, make_row, time_call, time_calls

__all__ = ["SUITE", "TrueViewMode", "scene_accuracy_rows", "temporal_rows", "speed_rows", "hit_rate_rows",
           "step_changes"]

#: The suite's name in bench rows (these rows belong to ``morphkit bench billboards``).
SUITE = "billboards"

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
