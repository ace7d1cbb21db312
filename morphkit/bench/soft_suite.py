"""``morphkit bench soft``: soft shadows of an area light, warped vs re-rendered, averaged vs filtered.

Scene (stated once; every figure names it): a sample mesh (normalised: largest
extent 1, resting on the ground) moving over ``[-0.6, 0.6]^2`` of the ground
plane, lit by a square **area light** ``0.6 x 0.6`` parallel to the ground,
centred at ``(0.25, -0.2, 2.4)`` (the shadow suite's point light, grown). The
atlas is baked for a point light at the centre over the range grown by the
light's extent, ``[-0.9, 0.9]^2`` (:func:`morphkit.shadow.soft.bake_soft_atlas`;
3 x 3 maps, 17 x 17 control grid).

Methods (timed in the same run, interleaved), each with ``N`` light samples
(the number in the name: 4 = 2 x 2, 5 = the paper's centre + corners, 9 = 3 x 3,
16 = 4 x 4, 64 = 8 x 8 cell centres). Averaging ``N`` hard shadows
(:class:`~morphkit.shadow.soft.SoftShadow`): ``warp_N`` (one mesh warp of the
atlas per sample), ``reproject_N`` (one reprojection of the atlas per sample),
``direct_N`` (one depth render per sample: Heckbert & Herf). Filtering each
sample's lookup over its cell of the light (:mod:`morphkit.shadow.filtering.penumbra`):
``pcf_N`` and ``pcss_N`` on the mesh warps, ``pcss-reproject_N`` (the default,
:func:`~morphkit.shadow.filtering.penumbra.default_soft_shadow`) on the reprojections;
at 256^2 also ``pcss-direct_9`` and ``pcf-reproject_9`` (like with like) and
``direct_64`` (the banding reference). ``hard``: one warped map for the light's
centre. ``ms_median`` is the time to produce the soft visibility of the
``256 x 256`` ground grid (all maps and lookups).

Ground truth: the ray-cast fraction of the light seen by each ground point, over
the ground square ``[-1.7, 1.7]^2`` sampled at ``256 x 256`` pixel centres, with
``16 x 16`` light samples (in ``--quick`` too). Metrics, averaged over seeded
random positions: ``mae`` (mean abs visibility error over the grid),
``mae_shadow`` (the same over the points that truth or estimate do not see
fully lit: the shadow and penumbra, where the error lives), ``mae_same`` (for
the averaging methods: against the ray cast with the method's *own* ``N``
samples, the method's error without the sampling error), ``banding``
(:func:`banding`) and ``mae_contact`` (the error within 2 map texels of the
lines where the object touches the ground: :func:`contact_region`).

Light-size sweep (wide penumbrae are where banding shows most): the
same scene and metrics with the square light's side set to each of
``LIGHT_SIZES`` (:func:`light_of_size`; the suite's own light is 0.6), its own
atlas (baked over the range grown by that light) and its own 256-sample ray cast;
rows ``what="light-size"`` with the side in ``light``.
"""

from __future__ import annotations

import gc
import time
from typing import Any

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from .. import tol
from ..imaging.groundtruth import area_visibility, receiver_grid, sampled_visibility
from ..memo import Memo
from ..meshes import sample_mesh
from ..protocols import SceneRenderer
from ..scene import AreaLight, SceneObject
from ..shadow import DirectShadow, MotionRange, SoftShadow, bake_soft_atlas
from ..shadow.filtering.penumbra import PcfSoftShadow, PcssSoftShadow, PenumbraSoftShadow
from ..shadow.soft import FIVE_SAMPLES
from .harness import Timing, make_row, time_cycling

__all__ = ["run", "run_subset", "accuracy_rows", "light_size_rows", "light_of_size", "banding",
           "contact_region", "SoftTruth", "FLOOR_METHOD", "PLOT_OPTIONS", "LIGHT_SIZES"]

SUITE = "soft"
#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "warp_9"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS: dict[str, Any] = {
    "size_key": "size", "error_key": "mae_shadow", "panel_keys": ("mesh", "what"),
    "scene_keys": ("what", "mesh"), "family": r"_\d+", "defaults": ({"method": "pcss-reproject_9"},),
    "default_label": "default: pcss-reproject_9"}

MOTION = MotionRange([-0.6, -0.6], [0.6, 0.6])
AREA = AreaLight([0.25, -0.2, 2.4], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])
GROUND_HALF, GROUND_N = 1.7, 256
TRUTH_SAMPLES = 16  # per axis: the 256-sample ray cast
SAMPLES: dict[int, Any] = {4: (2, 2), 5: FIVE_SAMPLES, 9: (3, 3), 16: (4, 4), 64: (8, 8)}
FILTERED: dict[str, type[PenumbraSoftShadow]] = {"pcf": PcfSoftShadow, "pcss": PcssSoftShadow}
#: Height (world units; meshes have largest extent 1) below which the object touches the ground.
CONTACT_HEIGHT = 0.005
#: Half-width of the contact region, in light-map texels at the ground.
CONTACT_TEXELS = 2.0
#: Sides (world units) of the square light in the light-size sweep (:func:`light_size_rows`).
LIGHT_SIZES = (0.2, 0.5, 1.0)


def light_of_size(size: float) -> AreaLight:
    """The suite's area light (same centre and orientation) with side ``size``.

    Parameters
    ----------
    size : float
        Side of the square light, world units (the suite's own light: 0.6).

    Returns
    -------
    morphkit.scene.AreaLight
        The light.
    """
    half = 0.5 * float(size)
    return AreaLight(AREA.center, [half, 0.0, 0.0], [0.0, half, 0.0])


def _positions(n: int, seed: int = 2026) -> np.ndarray:
    return np.random.default_rng(seed).uniform(MOTION.lo, MOTION.hi, (n, 2))


def banding(est: np.ndarray, truth: np.ndarray) -> float:
    """Mean ``|gradient error|`` of a visibility image over the penumbra: the banding measure.

    Over every pair of neighbouring grid points (along rows and along columns)
    of which one, in the estimate or in the truth, is in the penumbra (between
    :data:`morphkit.tol.PENUMBRA_EPS` and ``1 -`` it: round-off of a sum of lit and shadowed
    terms is not penumbra): the mean of ``|(e1 - e0) - (t1 - t0)|``, in visibility per
    grid step. A banded penumbra is flat between jumps of ``1/N`` where the truth
    ramps, so every step adds about its height; a smooth penumbra of the right
    width scores near zero (``docs/results/soft_shadows.md`` gives the reason in full).

    Parameters
    ----------
    est, truth : (H, W) float
        Estimated and true visibility on the same grid.

    Returns
    -------
    float
        The measure (0 without any penumbra).
    """
    e, t = np.asarray(est, np.float64), np.asarray(truth, np.float64)
    lo, hi = tol.PENUMBRA_EPS, 1.0 - tol.PENUMBRA_EPS
    pen = ((e > lo) & (e < hi)) | ((t > lo) & (t < hi))
    total, count = 0.0, 0
    for ax in (0, 1):
        d = np.abs(np.diff(e, axis=ax) - np.diff(t, axis=ax))
        region = np.take(pen, range(1, pen.shape[ax]), ax) | np.take(pen, range(pen.shape[ax] - 1), ax)
        total += float(d[region].sum())
        count += int(region.sum())
    return total / count if count else 0.0


def contact_region(mesh: trimesh.Trimesh, xy: np.ndarray, grid: np.ndarray, radius: float
                   ) -> np.ndarray:
    """Grid points within ``radius`` of where the object touches the ground.

    The contact lines are the object's surface below ``CONTACT_HEIGHT``
    (surface samples, seeded), moved to ``xy``.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The object, resting on the ground at translation ``0``.
    xy : (2,) float
        Its translation.
    grid : (P, 3) float
        Ground points.
    radius : float
        World units (2 map texels at the ground).

    Returns
    -------
    (P,) bool
        The contact region.
    """
    pts, _faces = trimesh.sample.sample_surface(mesh, 200_000, seed=7)
    low = pts[pts[:, 2] < float(mesh.bounds[0, 2]) + CONTACT_HEIGHT][:, :2] + xy
    if len(low) == 0:
        return np.zeros(len(grid), bool)
    dist, _idx = cKDTree(low).query(grid[:, :2], distance_upper_bound=radius)
    return np.isfinite(dist)


class SoftTruth:
    """Ray-cast area-light visibility per (mesh, position, samples), computed once.

    Parameters
    ----------
    dense : int
        Light samples per axis of the reference ray cast.
    light : morphkit.scene.AreaLight, optional
        The area light (default: the suite's ``AREA``).
    """

    def __init__(self, dense: int, light: AreaLight | None = None) -> None:
        self.grid = receiver_grid(GROUND_HALF, (GROUND_N, GROUND_N)).reshape(-1, 3)
        self.dense = dense
        self.light = AREA if light is None else light
        self._cache: Memo[tuple[Any, ...], np.ndarray] = Memo()

    def __call__(self, mesh_name: str, mesh: Any, xy: np.ndarray,
                 same_as: SoftShadow | None = None, dense: int | None = None) -> np.ndarray:
        """Dense truth, or with ``same_as`` the truth with that method's own samples."""
        dense = self.dense if dense is None else dense
        key = (mesh_name, xy.tobytes(), dense,
               None if same_as is None else same_as.offsets.tobytes())
        def cast() -> np.ndarray:
            pose = np.eye(4)
            pose[:2, 3] = xy
            obj = SceneObject(mesh, pose)
            return (area_visibility(self.grid, self.light, obj, dense) if same_as is None
                    else sampled_visibility(self.grid, same_as.point_lights(), obj))

        return self._cache.get(key, cast)

    def contact(self, mesh_name: str, mesh: Any, xy: np.ndarray, radius: float) -> np.ndarray:
        """:func:`contact_region` of the grid, computed once per case.

        Parameters
        ----------
        mesh_name : str
            The sample mesh's name (the cache key).
        mesh : trimesh.Trimesh
            The mesh, object frame.
        xy : (2,) float
            The object's translation on the ground.
        radius : float
            Distance from the contact lines, world units.

        Returns
        -------
        (P,) bool
            Grid points within ``radius`` of where the object touches the ground.
        """
        key = ("contact", mesh_name, xy.tobytes(), radius)
        return self._cache.get(key, lambda: contact_region(mesh, xy, self.grid, radius))


def _errors(soft: SoftShadow, mesh_name: str, mesh: Any, xys: np.ndarray, truth: SoftTruth,
            contact_radius: float) -> dict[str, float]:
    out: dict[str, list[float]] = {"mae": [], "mae_shadow": [], "banding": [], "mae_contact": []}
    averaged = not isinstance(soft, PenumbraSoftShadow)
    if averaged:
        out["mae_same"] = []
    for xy in xys:
        est = soft.visibility(xy, truth.grid)
        gt = truth(mesh_name, mesh, xy)
        err = np.abs(est - gt)
        out["mae"].append(float(err.mean()))
        region = (gt < 1) | (est < 1)
        out["mae_shadow"].append(float(err[region].mean()) if region.any() else 0.0)
        out["banding"].append(banding(est.reshape(GROUND_N, GROUND_N),
                                      gt.reshape(GROUND_N, GROUND_N)))
        contact = truth.contact(mesh_name, mesh, xy, contact_radius)
        out["mae_contact"].append(float(err[contact].mean()) if contact.any() else 0.0)
        if averaged:
            out["mae_same"].append(float(np.abs(est - truth(mesh_name, mesh, xy, soft)).mean()))
    return {k: float(np.mean(v)) for k, v in out.items()}


def _time(methods: dict[str, SoftShadow], xys: np.ndarray, grid: np.ndarray, repeats: int
          ) -> dict[str, Any]:
    """Time one soft visibility of ``grid`` per call, cycling through positions."""
    fns = {name: (lambda xy, m=m: m.visibility(xy, grid)) for name, m in methods.items()}
    return time_cycling(fns, xys, repeats=repeats, warmup=1)


def _methods(atlas: Any, direct: DirectShadow, ns: list[int], *, extras: bool
             ) -> dict[str, SoftShadow]:
    reproject = atlas.method(warps="reproject")
    methods = {"hard": SoftShadow(atlas, AREA, np.zeros((1, 2)))}
    for n in ns:
        methods[f"warp_{n}"] = SoftShadow(atlas, AREA, SAMPLES[n])
        methods[f"reproject_{n}"] = SoftShadow(reproject, AREA, SAMPLES[n])
        methods[f"direct_{n}"] = SoftShadow(direct, AREA, SAMPLES[n])
        for label, cls in FILTERED.items():
            methods[f"{label}_{n}"] = cls(atlas, AREA, SAMPLES[n])
        methods[f"pcss-reproject_{n}"] = PcssSoftShadow(reproject, AREA, SAMPLES[n])
    if extras:  # the banding reference, and the filters on the other map sources
        methods["direct_64"] = SoftShadow(direct, AREA, SAMPLES[64])
        methods["pcss-direct_9"] = PcssSoftShadow(direct, AREA, SAMPLES[9])
        methods["pcf-reproject_9"] = PcfSoftShadow(reproject, AREA, SAMPLES[9])
    return methods


def accuracy_rows(renderer: SceneRenderer, truth: SoftTruth, meshes: list[str], sizes: list[int],
                  ns: list[int], n_positions: int, repeats: int) -> list[dict[str, Any]]:
    """Error and time rows per mesh and map size (the extras at 256^2 only).

    Parameters
    ----------
    renderer : morphkit.render.Renderer
        Bakes and re-renders.
    truth : SoftTruth
        The ray-cast reference (cached).
    meshes : list of str
        Sample mesh names.
    sizes : list of int
        Map sizes.
    ns : list of int
        Sample counts (keys of ``SAMPLES``).
    n_positions : int
        Seeded random positions per case.
    repeats : int
        Timing repeats.

    Returns
    -------
    list of dict
        The rows.
    """
    rows = []
    xys = _positions(n_positions)
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        for size in sizes:
            atlas = bake_soft_atlas(mesh, np.eye(4), MOTION, AREA, (size, size), renderer=renderer,
                                    progress=False)
            methods = _methods(atlas, DirectShadow(atlas.rig, mesh, renderer), ns,
                               extras=size == 256)
            timings = _time(methods, xys, truth.grid, repeats=repeats)
            # 2 map texels at the ground (depth ~ the light's height) in world units
            radius = CONTACT_TEXELS * float(AREA.center[2]) / float(atlas.rig.fx)
            for name, m in methods.items():
                err = _errors(m, mesh_name, mesh, xys, truth, radius)
                err["mem_mb"] = (atlas.memory_bytes if "direct" not in name else 0) / 2**20
                rows.append(make_row(SUITE, name, {"what": "soft", "mesh": mesh_name, "size": size,
                                                   "samples": m.n_samples,
                                                   "faces": len(mesh.faces)},
                                     timings[name], metrics=err))
            del atlas, methods
            gc.collect()
    return rows


def light_size_rows(renderer: SceneRenderer, meshes: list[str], light_sizes: list[float],
                    n_positions: int, repeats: int) -> list[dict[str, Any]]:
    """The light-size sweep (module docstring): 256^2 maps, ``N = 9`` for the warp and
    the default (``pcss-reproject_9``) and PCSS on the mesh warps (``pcss_9``), against
    ``direct_16`` and the banding reference ``direct_64``, per mesh and light side.

    Parameters
    ----------
    renderer : morphkit.render.Renderer
        Bakes and re-renders.
    meshes : list of str
        Sample mesh names.
    light_sizes : list of float
        Sides of the square light, world units.
    n_positions : int
        Seeded random positions per case.
    repeats : int
        Timing repeats.

    Returns
    -------
    list of dict
        The rows, ``what="light-size"``, the side in ``light``.
    """
    rows = []
    xys = _positions(n_positions)
    size = 256
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        for side in light_sizes:
            light = light_of_size(side)
            truth = SoftTruth(TRUTH_SAMPLES, light)
            atlas = bake_soft_atlas(mesh, np.eye(4), MOTION, light, (size, size), renderer=renderer,
                                    progress=False)
            direct = DirectShadow(atlas.rig, mesh, renderer)
            methods: dict[str, SoftShadow] = {
                "warp_9": SoftShadow(atlas, light, SAMPLES[9]),
                "pcss_9": PcssSoftShadow(atlas, light, SAMPLES[9]),
                "pcss-reproject_9": PcssSoftShadow(atlas.method(warps="reproject"), light, SAMPLES[9]),
                "direct_16": SoftShadow(direct, light, SAMPLES[16]),
                "direct_64": SoftShadow(direct, light, SAMPLES[64])}
            timings = _time(methods, xys, truth.grid, repeats=repeats)
            radius = CONTACT_TEXELS * float(light.center[2]) / float(atlas.rig.fx)
            for name, m in methods.items():
                err = _errors(m, mesh_name, mesh, xys, truth, radius)
                rows.append(make_row(SUITE, name, {"what": "light-size", "mesh": mesh_name, "size": size,
                                                   "samples": m.n_samples, "faces": len(mesh.faces),
                                                   "light": float(side)},
                                     timings[name], metrics=err))
            del atlas, methods
            gc.collect()
    return rows


def _reference_rows(truth: SoftTruth) -> list[dict[str, Any]]:
    """The 256-sample ray cast against a 1024-sample one (cow, one position): converged?"""
    mesh = sample_mesh("cow")
    xy = _positions(1)[0]
    t0 = time.perf_counter()
    fine = truth("cow", mesh, xy, dense=32)
    ms = 1e3 * (time.perf_counter() - t0)
    ref = truth("cow", mesh, xy)
    err = np.abs(ref - fine)
    region = (ref < 1) | (fine < 1)
    n = GROUND_N
    metrics = {"mae": float(err.mean()), "mae_shadow": float(err[region].mean()),
               "banding": banding(ref.reshape(n, n), fine.reshape(n, n))}
    row = make_row(SUITE, "raycast_256", {"what": "reference", "mesh": "cow", "size": 0,
                                          "samples": 256, "faces": len(mesh.faces)},
                   Timing(ms, ms, ms, 1), metrics=metrics,
                   note="against a 1024-sample ray cast; the time is the 1024-sample cast's")
    return [row]


def _complexity_rows(renderer: SceneRenderer, quick: bool) -> list[dict[str, Any]]:
    """Cow from ~6k to ~1M faces, 256^2 maps, 9 samples: time of one soft shadow."""
    rows = []
    faces = [6000, 50000] if quick else [6000, 50000, 300000, 1000000]
    size = 256
    xys = _positions(6, seed=11)
    grid = receiver_grid(GROUND_HALF, (GROUND_N, GROUND_N)).reshape(-1, 3)
    for f in faces:
        mesh = sample_mesh("cow", faces=f)
        atlas = bake_soft_atlas(mesh, np.eye(4), MOTION, AREA, (size, size), renderer=renderer,
                                progress=False)
        direct = DirectShadow(atlas.rig, mesh, renderer)
        methods = {"warp_9": SoftShadow(atlas, AREA, (3, 3)),
                   "pcss_9": PcssSoftShadow(atlas, AREA, (3, 3)),
                   "pcss-reproject_9": PcssSoftShadow(atlas.method(warps="reproject"), AREA, (3, 3)),
                   "direct_9": SoftShadow(direct, AREA, (3, 3)),
                   "direct_16": SoftShadow(direct, AREA, (4, 4))}
        timings = _time(methods, xys, grid, repeats=3 if quick else 5)
        for name, m in methods.items():
            rows.append(make_row(SUITE, name, {"what": "complexity", "mesh": "cow", "size": size,
                                               "samples": m.n_samples, "faces": len(mesh.faces)},
                                 timings[name]))
    return rows


def run_subset(meshes: list[str], sizes: list[int], ns: list[int], n_positions: int, repeats: int,
               *, complexity: bool = True, reference: bool = True,
               light_sizes: list[float] | None = None, light_meshes: list[str] | None = None,
               json_path: str | None = None) -> list[dict[str, Any]]:
    """A chosen part of the full run (the full run is long on a shared machine): accuracy rows
    for ``meshes`` x ``sizes`` x ``ns``, then the complexity sweep and the reference check.

    Parameters
    ----------
    meshes : list of str
        Sample mesh names.
    sizes : list of int
        Map sizes.
    ns : list of int
        Sample counts (4, 5, 9, 16).
    n_positions : int
        Seeded random positions per case.
    repeats : int
        Timing repeats.
    complexity : bool
        Add the full complexity sweep (6k to 1M faces).
    reference : bool
        Add the 256- against 1024-sample ray-cast row.
    light_sizes : list of float, optional
        Add the light-size sweep (:func:`light_size_rows`) with these sides.
    light_meshes : list of str, optional
        The sweep's meshes (default: ``meshes``).
    json_path : str, optional
        Write the rows there as JSON.

    Returns
    -------
    list of dict
        The rows.
    """
    from ..render import Renderer
    from .harness import format_table, write_json

    truth = SoftTruth(dense=TRUTH_SAMPLES)
    with Renderer() as renderer:
        rows = accuracy_rows(renderer, truth, meshes, sizes, ns, n_positions, repeats)
        if light_sizes:
            rows += light_size_rows(renderer, meshes if light_meshes is None else light_meshes,
                                    list(light_sizes), n_positions, repeats)
        if complexity:
            rows += _complexity_rows(renderer, False)
    if reference:
        rows += _reference_rows(truth)
    print(format_table(rows, floor_method=FLOOR_METHOD), flush=True)
    if json_path is not None:
        write_json(rows, json_path)
    return rows


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """All soft-shadow rows: accuracy + time per mesh and map size, the light-size sweep
    (teapot), complexity sweep.

    Parameters
    ----------
    quick : bool
        Fewer and smaller cases (a smoke run).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    t0 = time.perf_counter()
    truth = SoftTruth(dense=TRUTH_SAMPLES)
    with Renderer() as renderer:
        if quick:
            rows = accuracy_rows(renderer, truth, ["cow"], [256], [4, 9], 2, 3)
        else:
            rows = accuracy_rows(renderer, truth, ["teapot", "chair", "cow"], [128, 256, 512],
                                 [4, 5, 9, 16], 10, 7)
            rows += light_size_rows(renderer, ["teapot"], list(LIGHT_SIZES), 10, 7)
            rows += _reference_rows(truth)
        rows += _complexity_rows(renderer, quick)
    print(f"soft suite: {len(rows)} rows in {time.perf_counter() - t0:.0f} s", flush=True)
    return rows
