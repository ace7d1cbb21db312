"""The ``dome-*`` sections of ``morphkit bench billboards``: billboards seen from any
height and relit by the scene's lights, against octahedral impostors at equal bytes.

Assets. The sample meshes ``cow`` and ``tree`` (``--quick``: the tree only;
:func:`morphkit.meshes.sample_mesh`, normalised, ``appearance="checker"`` as the other
billboard rows) baked by :func:`~morphkit.billboard.domeasset.bake_dome` with the default
:class:`~morphkit.views.dome.ViewDome` at ``S^2`` per view (``S = 128``, quick 64), 3
levels; the octahedral impostor (:func:`~morphkit.billboard.impostor.bake_impostor`) of the
same mesh at **equal bytes**: 12 x 12 frames, 3 mip levels, the largest frame side whose
bytes fit the dome asset's :attr:`~morphkit.billboard.domeasset.DomeAsset.memory_bytes`
(:func:`~morphkit.billboard.impostor.impostor_frame_size`), output ``S^2`` (the same image
size, so the same truth); ``bytes`` in every row is the method's asset's. Both assets fit the
same :class:`~morphkit.views.domecameras.DomeCameras` to the same normalised mesh (their
pivots and half extents are checked equal), so every method's surface is in the frame of the
dome asset's :meth:`~morphkit.billboard.domeasset.DomeAsset.camera` for a direction.

Methods: ``morph`` (``DomeAsset.surface``: per-pixel depth morph of the 3 views around the
direction), ``impostor`` (``OctahedralImpostor.surface``: 3-frame blend with one parallax
step), ``nearest``, ``crossfade``, ``classic`` (the dome's baselines: the nearest view on
its card, the 3 views blended on their cards, the front view for every direction).

Sections (each ``(cache, quick) -> rows``, appended to ``billboard_suite.SECTIONS``):

* ``dome-bands`` -- directions per elevation band 0-20, 20-40, 40-60, 60-80, 80-90 degrees
  (:data:`BANDS`; 12 per band, quick 4; azimuths by the golden angle, elevations stratified
  in the band with a seeded jitter, none within :data:`MIN_VIEW_SEP_DEG` of a dome view or
  an impostor frame: :func:`band_directions`). Ground truth: the mesh's passes
  (``Renderer.source_passes``, supersampled as the bake) by the dome asset's camera of the
  direction, shaded by :func:`~morphkit.imaging.shading.shade_passes` under the bake lighting
  (:func:`~morphkit.billboard.baking.bakelook.bake_lights`, ``BAKE_AMBIENT``); each method's surface
  shaded by :func:`~morphkit.imaging.shading.shade` under the same lighting (object frame = world
  frame). Metrics per direction, then the mean per band (``band = "all"``: over every
  direction): ``iou`` (alpha > 0.5) and ``psnr`` (premultiplied shaded RGB, whole image,
  data range 1, capped at 99 dB), ``*_min`` the worst direction; time: one ``surface()``
  call (median over the directions).
* ``dome-relit`` -- 3 directions per band (quick 1) under each of the 8 suns of
  :func:`~morphkit.sunpath.sun_directions_8` relative to the viewing azimuth, one at a
  time (``Lighting(BAKE_AMBIENT, (sun,))``), truth and methods shaded as above; ``psnr_<sun>``
  per sun, ``psnr_relit`` their mean, ``psnr_bake`` the same directions under the bake
  lighting and ``relit_delta = psnr_bake - psnr_relit`` (target <= 2 dB); ``iou`` the mean
  silhouette IoU. Methods: morph, impostor, nearest, crossfade.
* ``dome-temporal`` -- a field of 100 trees (quick 20; random positions and yaws,
  seeded, scale 1, :func:`~morphkit.billboard.frames.instances.place_random`) with
  :class:`~morphkit.billboard.frames.facing.ViewpointFacing`, along
  :meth:`FlyoverPath.around <morphkit.billboard.frames.paths.FlyoverPath.around>` (5 to 85 degrees
  elevation, a quarter circle) in 60 frames (quick 24) at 640 x 480 (quick 320 x 240):
  :class:`~morphkit.sunlit.litmodes.LitMode` with ``MorphSurface`` (dome scene),
  ``MorphSurface(name="impostor")`` (the same instances of the impostor), ``NearestSurface``,
  ``CrossfadeSurface``, under the bake lighting; ground truth
  :class:`~morphkit.sunlit.litmesh.LitMeshMode` (the meshes' passes at every instance's
  pose, supersampled 2x, same lighting), whose own row ``mesh`` is the scene's reference step
  change (the camera moves, so every layer changes). ``step_max``, ``step_median``,
  ``max_over_median`` of :func:`~morphkit.bench.billboard_scenes.step_changes` over the
  frames' layers (target max/median <= 2). Accuracy rows ``dome-scene`` per band of each
  drawn billboard's viewing elevation (and ``all``): ``iou``, ``psnr`` of
  :func:`~morphkit.billboard.compare.box_errors` (per billboard screen box, final RGB, data
  range 255) against the truth frame, ``n`` the billboards. ``ring-morph``: the ring asset the
  ring baseline is measured with (``bake_asset`` K = 8 at 10 degrees elevation, ``S^2``, 3
  levels, ``AxialFacing``, ``MorphMode``) against ``MeshMode`` (bake lights and ambient,
  supersampled 2x) on the same flyover and instances; its ``n`` counts only the billboards
  it draws (edge-on quads from above are not drawn). ``dome-temporal-one``: the same modes
  on one instance at the origin, the fly-over about its pivot at 4 half extents (the quad
  stays centred, only its image changes; 161 frames, quick 41): a view or frame switch
  shows as a spike (``argmax_elevation``: the eye's elevation at the largest step).
* ``dome-speed`` -- 1000 trees (quick 200) over a field, 640 x 480 (quick 320 x 240), one
  camera 30 degrees up at the flyover's distance: the warm frame time (one frame fills
  the cache, then the median of repeats, interleaved by
  :func:`~morphkit.bench.harness.time_calls`) of ``LitMode`` morph (dome assets),
  impostor, ``classic-lit`` (``ClassicSurface``, relit) and ``classic`` (the ring asset's
  ``ClassicMode``: one image per asset, no shading, ``AxialFacing``); ``x_classic`` and
  ``x_impostor`` are each row's median over classic's and the impostor's (targets: morph
  <= 2 x classic, <= impostor).
* ``dome-bake`` -- ``bake_dome`` of the tree at 256^2 per view (quick 128), wall time
  (median of 3, quick 1) and ``cpu_ms`` (the process's CPU time, all threads), ``views``
  and ``bytes``; ``bake_impostor`` at equal bytes (frame side from
  :func:`~morphkit.billboard.impostor.impostor_frame_size`), timed the same way.
"""

from __future__ import annotations

import math
import time
import weakref
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np
import trimesh

from ..billboard import (
    BAKE_AMBIENT,
    Backdrop,
    BillboardScene,
    ClassicMode,
    Instances,
    MeshMode,
    MorphCache,
    MorphMode,
    bake_asset,
    bake_lights,
    place_random,
)
from ..billboard.compare import box_errors
from ..billboard.domeasset import DOME_SUPERSAMPLE, DomeAsset, bake_dome
from ..billboard.frames.facing import AxialFacing, ViewpointFacing
from ..billboard.frames.paths import FlyoverPath
from ..billboard.impostor import OctahedralImpostor, bake_impostor, impostor_frame_size
from ..errors import ValidationError, expected_got
from ..imaging.metrics import psnr, shadow_iou
from ..imaging.shading import Lighting, shade, shade_passes
from ..memo import Memo
from ..protocols import SceneRenderer
from ..sunlit.litmesh import LitMeshMode
from ..sunlit.litmodes import ClassicSurface, CrossfadeSurface, LitMode, MorphSurface, NearestSurface
from ..sunpath import sun_directions_8
from ..views.domecameras import direction
from .billboard_scenes import SUITE, step_changes
from .harness import Timing, make_row, time_calls

__all__ = ["MeshSource", "BANDS", "MIN_VIEW_SEP_DEG", "band_directions", "band_label", "SECTIONS",
           "dome_bands_rows", "dome_relit_rows", "dome_temporal_rows", "dome_speed_rows", "dome_bake_rows"]

#: Elevation bands (degrees, ``[lo, hi)``; the last includes 90) of the per-band rows.
BANDS: tuple[tuple[float, float], ...] = ((0.0, 20.0), (20.0, 40.0), (40.0, 60.0), (60.0, 80.0), (80.0, 90.0))
#: A bench direction keeps at least this angle (degrees) from every stored view or frame.
MIN_VIEW_SEP_DEG = 1.0
#: PSNR of identical images (dB), as the other billboard rows cap it.
PSNR_CAP = 99.0
#: Golden angle, degrees.
GOLDEN_DEG = 180.0 * (3.0 - math.sqrt(5.0))
#: Seed of the bench directions and instance fields.
SEED = 25
#: Frames a side of the impostor (the engines' default).
IMPOSTOR_FRAMES = 12
#: Pyramid levels of the dome assets and mip levels of the impostors.
LEVELS = 3


class MeshSource(Protocol):
    """What the dome sections use of ``billboard_suite.AssetCache`` (declared here: importing it
    would make a cycle).

    Parameters
    ----------
    *args, **kwargs
        Not used: a protocol is not instantiated, classes implement its members.
    """

    renderer: SceneRenderer

    def mesh(self, name: str) -> trimesh.Trimesh:
        """The sample mesh ``name``, normalised.

        Parameters
        ----------
        name : str
            A sample mesh name.

        Returns
        -------
        trimesh.Trimesh
            The mesh.
        """
        ...


def band_label(band: tuple[float, float]) -> str:
    """``"lo-hi"`` of a band, e.g. ``"0-20"``.

    Parameters
    ----------
    band : (float, float)
        Degrees.

    Returns
    -------
    str
        The label.
    """
    return f"{band[0]:g}-{band[1]:g}"


def _band_of(elevation_deg: float) -> str:
    for lo, hi in BANDS:
        if lo <= elevation_deg < hi or (hi == BANDS[-1][1] and elevation_deg >= lo):
            return band_label((lo, hi))
    return "below"


def band_directions(band: tuple[float, float], n: int, rng: np.random.Generator,
                    avoid: np.ndarray | None = None, *, start: int = 0) -> list[tuple[float, float]]:
    """``n`` viewing directions ``(azimuth, elevation)`` in an elevation band.

    Azimuths ``5 + 137.5 (start + k)`` degrees (the golden angle, wrapped to ``[-180, 180)``);
    elevations stratified, ``lo + (hi - lo) (k + u_k) / n`` with ``u_k`` uniform in
    ``[0.1, 0.9]``; a direction within :data:`MIN_VIEW_SEP_DEG` of a row of ``avoid``
    (unit vectors: stored views) is turned by ``2 MIN_VIEW_SEP_DEG`` of azimuth until it is not.

    Parameters
    ----------
    band : (float, float)
        ``(lo, hi)``, degrees, ``0 <= lo < hi <= 90``.
    n : int
        Directions, ``>= 1``.
    rng : numpy.random.Generator
        The elevation jitter.
    avoid : (K, 3) float, optional
        Unit directions to keep away from.
    start : int, optional
        Index of the first golden-angle azimuth (bands continue each other's sequence).

    Returns
    -------
    list of (float, float)
        Degrees.

    Raises
    ------
    ValidationError
        A band outside ``[0, 90]`` or ``n < 1``.
    """
    lo, hi = float(band[0]), float(band[1])
    if not 0.0 <= lo < hi <= 90.0 or n < 1:
        raise ValidationError(expected_got("band, n", "0 <= lo < hi <= 90 and n >= 1", f"{band}, {n}"))
    u = rng.uniform(0.1, 0.9, n)
    out = []
    cos_min = math.cos(math.radians(MIN_VIEW_SEP_DEG))
    for k in range(n):
        a = (5.0 + GOLDEN_DEG * (start + k) + 180.0) % 360.0 - 180.0
        e = lo + (hi - lo) * (k + u[k]) / n
        for _ in range(360):
            if avoid is None or float(np.max(avoid @ direction(a, e))) < cos_min:
                break
            a = (a + 2.0 * MIN_VIEW_SEP_DEG + 180.0) % 360.0 - 180.0
        out.append((float(a), float(e)))
    return out


def _quality(pred: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """``(iou, psnr)``: silhouette IoU (alpha > 0.5) and PSNR of the premultiplied RGB, data range 1."""
    iou = shadow_iou(pred[..., 3] > 0.5, truth[..., 3] > 0.5)
    return iou, min(psnr(pred[..., :3], truth[..., :3], data_range=1.0), PSNR_CAP)


# --------------------------------------------------------------------------- assets

_ASSETS: weakref.WeakKeyDictionary[Any, Memo[tuple[str, int], tuple[DomeAsset, OctahedralImpostor]]] = (
    weakref.WeakKeyDictionary())


def _meshes(quick: bool) -> tuple[str, ...]:
    return ("tree",) if quick else ("cow", "tree")


def _size(quick: bool) -> int:
    return 64 if quick else 128


def _impostor(mesh: trimesh.Trimesh, renderer: SceneRenderer, name: str, budget: int,
              out_size: int) -> OctahedralImpostor:
    m = impostor_frame_size(budget, IMPOSTOR_FRAMES, LEVELS)
    return bake_impostor(mesh, renderer, name=name, frames=IMPOSTOR_FRAMES, frame_size=m, levels=LEVELS,
                         out_size=out_size, appearance="checker")


def _assets(cache: MeshSource, name: str, size: int) -> tuple[DomeAsset, OctahedralImpostor]:
    """The dome asset of mesh ``name`` at ``size`` and its impostor at equal bytes (baked once per cache)."""
    memo = _ASSETS.setdefault(cache, Memo(4))

    def bake() -> tuple[DomeAsset, OctahedralImpostor]:
        mesh = cache.mesh(name)
        dome = bake_dome(mesh, cache.renderer, name=name, size=size, levels=LEVELS, appearance="checker")
        imp = _impostor(mesh, cache.renderer, name, dome.memory_bytes, size)
        same = (np.allclose(dome.pivot, imp.pivot) and np.allclose(dome.half_extent, imp.half_extent)
                and math.isclose(dome.cameras.distance, imp.cameras.distance))
        if not same or imp.memory_bytes > dome.memory_bytes:
            raise ValidationError(expected_got(f"impostor of {name!r}", "the dome's pivot, half extent and "
                                               "distance, at most its bytes", f"pivot {imp.pivot}, half "
                                               f"{imp.half_extent}, {imp.memory_bytes} B"))
        return dome, imp

    return memo.get((name, size), bake)


def _methods(dome: DomeAsset, imp: OctahedralImpostor) -> dict[str, Callable[[float, float], Any]]:
    return {"morph": dome.surface, "impostor": imp.surface, "nearest": dome.nearest_surface,
            "crossfade": dome.crossfade_surface, "classic": lambda a, e: dome.classic_surface()}


def _bake_lighting() -> Lighting:
    return Lighting(BAKE_AMBIENT, tuple(bake_lights()))


def _directions(dome: DomeAsset, imp: OctahedralImpostor,
                per_band: int) -> dict[str, list[tuple[float, float]]]:
    avoid = np.vstack([direction(dome.dome.azimuths_deg(), dome.dome.elevations_deg()), imp.frame_dirs])
    rng = np.random.default_rng(SEED)
    return {band_label(b): band_directions(b, per_band, rng, avoid, start=i * per_band)
            for i, b in enumerate(BANDS)}


def _truth_passes(cache: MeshSource, dome: DomeAsset, a: float, e: float) -> tuple[Any, Any]:
    cam = dome.camera(a, e)
    items = dome.items(cache.mesh(dome.name))
    return cache.renderer.source_passes(cam, items, bake_lights(), ambient=BAKE_AMBIENT,
                                        supersample=DOME_SUPERSAMPLE), cam


def _mean_rows(rows: list[dict[str, Any]], key: str, value: str, note: str) -> list[dict[str, Any]]:
    """Per method, rows with ``params[key] = value``: metrics and times averaged over ``rows``."""
    out = []
    for method in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == method]
        metrics = {k: float(np.mean([r["metrics"][k] for r in sel])) for k in sel[0]["metrics"]}
        t = Timing(float(np.mean([r["ms_median"] for r in sel])), min(r["ms_min"] for r in sel),
                   max(r["ms_max"] for r in sel), sum(r["repeats"] for r in sel))
        params = dict(sel[0]["params"], **{key: value})
        out.append(make_row(SUITE, method, params, t, metrics=metrics, note=f"{note} ({len(sel)} rows)"))
    return out


# --------------------------------------------------------------------------- dome-bands


def dome_bands_rows(cache: MeshSource, quick: bool) -> list[dict[str, Any]]:
    """Per elevation band: every method against the mesh under the bake lighting (module docstring).

    Parameters
    ----------
    cache : AssetCache
        Meshes and the renderer (``billboard_suite.AssetCache``).
    quick : bool
        The tree only, ``S = 64``, 4 directions per band.

    Returns
    -------
    list of dict
        Rows (:func:`~morphkit.bench.harness.make_row`).
    """
    size, lighting = _size(quick), _bake_lighting()
    rows: list[dict[str, Any]] = []
    for name in _meshes(quick):
        dome, imp = _assets(cache, name, size)
        methods = _methods(dome, imp)
        per_mesh: list[dict[str, Any]] = []
        vals: dict[str, list[tuple[float, float]]] = {m: [] for m in methods}
        secs: dict[str, list[float]] = {m: [] for m in methods}
        for band, dirs in _directions(dome, imp, 4 if quick else 12).items():
            bv: dict[str, list[tuple[float, float]]] = {m: [] for m in methods}
            bs: dict[str, list[float]] = {m: [] for m in methods}
            for a, e in dirs:
                passes, cam = _truth_passes(cache, dome, a, e)
                truth = shade_passes(passes, lighting, cam)
                for m, fn in methods.items():
                    t0 = time.perf_counter()
                    surf = fn(a, e)
                    bs[m].append(time.perf_counter() - t0)
                    bv[m].append(_quality(shade(surf, lighting), truth))
            for m in methods:
                vals[m] += bv[m]
                secs[m] += bs[m]
                per_mesh.append(_band_row(m, name, band, size, bv[m], bs[m], dome, imp))
        per_mesh += [_band_row(m, name, "all", size, vals[m], secs[m], dome, imp) for m in methods]
        rows += per_mesh
    if len(_meshes(quick)) > 1:
        for band in [band_label(b) for b in BANDS] + ["all"]:
            sel = [r for r in rows if r["params"]["band"] == band]
            rows += _mean_rows(sel, "mesh", "all", "mean over the meshes")
    return rows


def _band_row(method: str, mesh: str, band: str, size: int, vals: list[tuple[float, float]],
              secs: list[float], dome: DomeAsset, imp: OctahedralImpostor) -> dict[str, Any]:
    v = np.asarray(vals, np.float64)
    nbytes = imp.memory_bytes if method == "impostor" else dome.memory_bytes
    metrics = {"iou": float(v[:, 0].mean()), "psnr": float(v[:, 1].mean()), "iou_min": float(v[:, 0].min()),
               "psnr_min": float(v[:, 1].min()), "n": float(len(v)), "bytes": float(nbytes)}
    note = (f"{IMPOSTOR_FRAMES}x{IMPOSTOR_FRAMES} frames of {imp.frame_side}^2" if method == "impostor"
            else f"{dome.dome.views} views of {size}^2")
    return make_row(SUITE, method, {"section": "dome-bands", "mesh": mesh, "band": band, "size": size},
                    Timing.from_seconds(secs), metrics=metrics, note=note)


# --------------------------------------------------------------------------- dome-relit


def dome_relit_rows(cache: MeshSource, quick: bool) -> list[dict[str, Any]]:
    """Under 8 suns against under the bake light, per method (module docstring).

    Parameters
    ----------
    cache : AssetCache
        Meshes and the renderer.
    quick : bool
        The tree only, ``S = 64``, one direction per band.

    Returns
    -------
    list of dict
        Rows (:func:`~morphkit.bench.harness.make_row`).
    """
    size, bake_l = _size(quick), _bake_lighting()
    rows: list[dict[str, Any]] = []
    for name in _meshes(quick):
        dome, imp = _assets(cache, name, size)
        methods = {k: v for k, v in _methods(dome, imp).items() if k != "classic"}
        dirs = [d for ds in _directions(dome, imp, 1 if quick else 3).values() for d in ds]
        bake_p: dict[str, list[float]] = {m: [] for m in methods}
        ious: dict[str, list[float]] = {m: [] for m in methods}
        sun_p: dict[str, dict[str, list[float]]] = {m: {} for m in methods}
        secs: dict[str, list[float]] = {m: [] for m in methods}
        for a, e in dirs:
            passes, cam = _truth_passes(cache, dome, a, e)
            surfs = {}
            for m, fn in methods.items():
                t0 = time.perf_counter()
                surfs[m] = fn(a, e)
                secs[m].append(time.perf_counter() - t0)
            truth = shade_passes(passes, bake_l, cam)
            for m, s in surfs.items():
                iou, p = _quality(shade(s, bake_l), truth)
                bake_p[m].append(p)
                ious[m].append(iou)
            for sname, lt in sun_directions_8(a).items():
                lighting = Lighting(BAKE_AMBIENT, (lt,))
                truth = shade_passes(passes, lighting, cam)
                for m, s in surfs.items():
                    sun_p[m].setdefault(sname, []).append(_quality(shade(s, lighting), truth)[1])
        for m in methods:
            per_sun = {f"psnr_{k}": float(np.mean(v)) for k, v in sun_p[m].items()}
            relit = float(np.mean(list(per_sun.values())))
            pb = float(np.mean(bake_p[m]))
            metrics = {"iou": float(np.mean(ious[m])), "psnr_bake": pb, "psnr_relit": relit,
                       "relit_delta": pb - relit, **per_sun}
            rows.append(make_row(SUITE, m, {"section": "dome-relit", "mesh": name, "size": size},
                                 Timing.from_seconds(secs[m]), metrics=metrics,
                                 note=f"{len(dirs)} directions x 8 suns (target relit_delta <= 2 dB)"))
    if len(_meshes(quick)) > 1:
        rows += _mean_rows(rows, "mesh", "all", "mean over the meshes")
    return rows


# --------------------------------------------------------------------------- dome-temporal


def _field(names: str, n: int, seed: int) -> tuple[Any, float]:
    inst = place_random([names], n, np.random.default_rng(seed), scale=(1.0, 1.0))
    return inst, max(1.0, 1.5 * math.sqrt(n) / 2)


def dome_temporal_rows(cache: MeshSource, quick: bool) -> list[dict[str, Any]]:
    """Step changes and per-billboard accuracy along the fly-over (module docstring).

    Parameters
    ----------
    cache : AssetCache
        Meshes and the renderer.
    quick : bool
        20 trees, 24 frames at 320 x 240, ``S = 64``.

    Returns
    -------
    list of dict
        ``dome-temporal`` and ``dome-scene`` rows.
    """
    size, name = _size(quick), "tree"
    n, frames = (20, 24) if quick else (100, 60)
    shape = (240, 320) if quick else (480, 640)
    r = cache.renderer
    dome, imp = _assets(cache, name, size)
    ring = bake_asset(cache.mesh(name), r, name=name, views=8, size=size, levels=LEVELS, elevation_deg=10.0,
                      appearance="checker")
    inst, half = _field(name, n, SEED)
    items = {name: dome.items(cache.mesh(name))}
    lighting = _bake_lighting()
    lit = {"dome": BillboardScene({name: dome}, inst, backdrop=Backdrop(), facing=ViewpointFacing()),
           "impostor": BillboardScene({name: imp}, inst, backdrop=Backdrop(), facing=ViewpointFacing())}
    ring_scene = BillboardScene({name: ring}, inst, backdrop=Backdrop(), facing=AxialFacing())
    big = MorphCache(8192, 1024 * 2**20)
    modes: dict[str, tuple[Any, Any]] = {
        "morph": (lit["dome"], LitMode(MorphSurface(), lighting, cache=big)),
        "impostor": (lit["impostor"], LitMode(MorphSurface(name="impostor"), lighting, cache=big)),
        "nearest": (lit["dome"], LitMode(NearestSurface(), lighting, cache=big)),
        "crossfade": (lit["dome"], LitMode(CrossfadeSurface(), lighting, cache=big)),
        "ring-morph": (ring_scene, MorphMode(MorphCache(8192, 1024 * 2**20))),
    }
    truth_lit = LitMeshMode(r, items, lighting, supersample=DOME_SUPERSAMPLE, name="mesh")
    truth_ring = MeshMode(r, {name: ring.items(cache.mesh(name))}, bake_lights(), BAKE_AMBIENT,
                          supersample=DOME_SUPERSAMPLE)
    path = FlyoverPath.around(half)
    layers: dict[str, list[np.ndarray]] = {m: [] for m in [*modes, "mesh"]}
    ms: dict[str, list[float]] = {m: [] for m in layers}
    errs: dict[str, list[tuple[float, dict[str, Any]]]] = {m: [] for m in modes}
    for cam in path.cameras(frames, shape):
        truth = lit["dome"].render(cam, truth_lit)
        layers["mesh"].append(truth.layer)
        ms["mesh"].append(truth.stats.ms / 1e3)
        ring_truth = ring_scene.render(cam, truth_ring)
        for m, (scene, mode) in modes.items():
            f = scene.render(cam, mode)
            layers[m].append(f.layer)
            ms[m].append(f.stats.ms / 1e3)
            ref = ring_truth if m == "ring-morph" else truth
            errs[m] += [(pl.elevation_deg, er)
                        for pl, er in zip(f.placements, box_errors(f, ref), strict=True)]
    rows = []
    base = {"mesh": name, "billboards": n, "frames": frames, "size": size, "shape": f"{shape[1]}x{shape[0]}"}
    for m, ls in layers.items():
        d = step_changes(ls)
        med, mx = float(np.median(d)), float(d.max())
        rows.append(make_row(SUITE, m, {"section": "dome-temporal", **base}, Timing.from_seconds(ms[m]),
                             metrics={"step_max": mx, "step_median": med,
                                      "max_over_median": mx / med if med > 0 else 1e9},
                             note=f"{len(d)} steps, flyover 5-85 deg (target max/median <= 2)"))
    for m, es in errs.items():
        for band in [band_label(b) for b in BANDS] + ["all"]:
            sel = [er for el, er in es if band == "all" or _band_of(el) == band]
            if not sel:
                continue
            metrics = {"iou": float(np.mean([er["iou"] for er in sel])),
                       "psnr": float(np.mean([er["psnr"] for er in sel])), "n": float(len(sel))}
            rows.append(make_row(SUITE, m, {"section": "dome-scene", "band": band, **base},
                                 Timing.from_seconds(ms[m]), metrics=metrics,
                                 note="per billboard box vs "
                                 + ("MeshMode" if m == "ring-morph" else "LitMeshMode")))
    one = {m: mode for m, (_, mode) in modes.items()} | {"mesh": truth_lit}
    return rows + _one_instance_rows(dome, imp, ring, one, 41 if quick else 161, shape)


def _one_instance_rows(dome: DomeAsset, imp: OctahedralImpostor, ring: Any, modes: dict[str, Any],
                       frames: int, shape: tuple[int, int]) -> list[dict[str, Any]]:
    """Step changes of one instance at the origin seen along a fly-over about its pivot (the quad
    stays centred, so only its image changes: a frame switch shows as a spike)."""
    name = dome.name
    inst = Instances((name,), np.zeros(1, np.int64), np.zeros((1, 2)), np.zeros(1), np.ones(1))
    scenes = {"dome": BillboardScene({name: dome}, inst, backdrop=Backdrop(), facing=ViewpointFacing()),
              "impostor": BillboardScene({name: imp}, inst, backdrop=Backdrop(), facing=ViewpointFacing()),
              "ring": BillboardScene({name: ring}, inst, backdrop=Backdrop(), facing=AxialFacing())}
    path = FlyoverPath(centre=tuple(float(v) for v in dome.pivot), distance=4.0 * max(dome.half_extent))
    cams = path.cameras(frames, shape)
    rows = []
    for m, mode in modes.items():
        scene = scenes["impostor" if m == "impostor" else "ring" if m == "ring-morph" else "dome"]
        fs = [scene.render(c, mode) for c in cams]
        d = step_changes([f.layer for f in fs])
        med, mx = float(np.median(d)), float(d.max())
        rows.append(make_row(SUITE, m, {"section": "dome-temporal-one", "mesh": name, "frames": frames,
                                        "size": dome.size[0], "shape": f"{shape[1]}x{shape[0]}"},
                             Timing.from_seconds([f.stats.ms / 1e3 for f in fs]),
                             metrics={"step_max": mx, "step_median": med,
                                      "max_over_median": mx / med if med > 0 else 1e9,
                                      "argmax_elevation": path.elevation_at(float(np.argmax(d) + 0.5)
                                                                            / (frames - 1))},
                             note=f"{len(d)} steps of {80 / (frames - 1):.2f} deg elevation, one instance"))
    return rows


# --------------------------------------------------------------------------- dome-speed


def dome_speed_rows(cache: MeshSource, quick: bool) -> list[dict[str, Any]]:
    """Warm frame time of 1000 relit billboards against the classic billboard and the impostor.

    Parameters
    ----------
    cache : AssetCache
        Meshes and the renderer.
    quick : bool
        200 trees at 320 x 240, ``S = 64``.

    Returns
    -------
    list of dict
        Rows with ``x_classic``, ``x_impostor``, ``n_drawn``.
    """
    size, name = _size(quick), "tree"
    n = 200 if quick else 1000
    shape = (240, 320) if quick else (480, 640)
    r = cache.renderer
    dome, imp = _assets(cache, name, size)
    ring = bake_asset(cache.mesh(name), r, name=name, views=8, size=size, levels=LEVELS, elevation_deg=10.0,
                      appearance="checker")
    inst, half = _field(name, n, SEED + 1)
    base = FlyoverPath.around(half)
    cam = FlyoverPath(centre=base.centre, distance=base.distance, start_elevation_deg=30.0,
                      end_elevation_deg=30.0, start_deg=-45.0, end_deg=-45.0).camera_at(0.0, shape)
    lighting = _bake_lighting()
    dome_scene = BillboardScene({name: dome}, inst, backdrop=Backdrop(), facing=ViewpointFacing())
    imp_scene = BillboardScene({name: imp}, inst, backdrop=Backdrop(), facing=ViewpointFacing())
    ring_scene = BillboardScene({name: ring}, inst, backdrop=Backdrop(), facing=AxialFacing())

    def big() -> MorphCache:
        return MorphCache(8192, 1024 * 2**20)

    cases = {"morph": (dome_scene, LitMode(MorphSurface(), lighting, cache=big())),
             "impostor": (imp_scene, LitMode(MorphSurface(name="impostor"), lighting, cache=big())),
             "classic-lit": (dome_scene, LitMode(ClassicSurface(), lighting, cache=big())),
             "classic": (ring_scene, ClassicMode())}
    drawn = {k: float(len(s.plan(cam).placements)) for k, (s, _) in cases.items()}
    times = time_calls({k: (lambda s=s, m=m: s.render(cam, m)) for k, (s, m) in cases.items()},
                       repeats=3 if quick else 5, warmup=1)
    rows = []
    for k in cases:
        metrics = {"n_drawn": drawn[k], "x_classic": times[k].ms_median / times["classic"].ms_median,
                   "x_impostor": times[k].ms_median / times["impostor"].ms_median}
        rows.append(make_row(SUITE, k, {"section": "dome-speed", "mesh": name, "billboards": n, "size": size,
                                        "shape": f"{shape[1]}x{shape[0]}"}, times[k], metrics=metrics,
                             note="warm cache, the same frame again "
                             "(target morph <= 2x classic, <= impostor)"))
    return rows


# --------------------------------------------------------------------------- dome-bake


def dome_bake_rows(cache: MeshSource, quick: bool) -> list[dict[str, Any]]:
    """Bake time and bytes of one dome asset and of its impostor at equal bytes.

    Parameters
    ----------
    cache : AssetCache
        Meshes and the renderer.
    quick : bool
        128^2 and one bake each (else 256^2, median of 3).

    Returns
    -------
    list of dict
        Rows with ``cpu_ms``, ``views``, ``bytes``.
    """
    size, name, repeats = (128, "tree", 1) if quick else (256, "tree", 3)
    mesh, r = cache.mesh(name), cache.renderer
    bake_dome(mesh, r, name="warm-up", size=32, levels=1, appearance="checker")
    rows = []
    holder: dict[str, Any] = {}
    wall: dict[str, list[float]] = {"bake-dome": [], "bake-impostor": []}
    cpu: dict[str, list[float]] = {"bake-dome": [], "bake-impostor": []}
    for _ in range(repeats):  # interleaved: the machine's drift falls on both
        for k in wall:
            t0, c0 = time.perf_counter(), time.process_time()
            if k == "bake-dome":
                holder[k] = bake_dome(mesh, r, name=name, size=size, levels=LEVELS, appearance="checker")
            else:
                holder[k] = _impostor(mesh, r, name, holder["bake-dome"].memory_bytes, size)
            wall[k].append(time.perf_counter() - t0)
            cpu[k].append(time.process_time() - c0)
    dome, imp = holder["bake-dome"], holder["bake-impostor"]
    for k in wall:
        views = dome.dome.views if k == "bake-dome" else IMPOSTOR_FRAMES ** 2
        side = size if k == "bake-dome" else imp.frame_side
        nbytes = dome.memory_bytes if k == "bake-dome" else imp.memory_bytes
        rows.append(make_row(SUITE, k, {"section": "dome-bake", "mesh": name, "size": size},
                             Timing.from_seconds(wall[k]),
                             metrics={"cpu_ms": 1e3 * float(np.median(cpu[k])), "views": float(views),
                                      "bytes": float(nbytes), "side": float(side)},
                             note=f"{views} views of {side}^2, {LEVELS} levels (target < 5 s at 256^2)"))
    return rows


#: The dome sections, in order (appended to ``billboard_suite.SECTIONS``).
SECTIONS: list[Callable[[Any, bool], list[dict[str, Any]]]] = [
    dome_bands_rows, dome_relit_rows, dome_temporal_rows, dome_speed_rows, dome_bake_rows]
