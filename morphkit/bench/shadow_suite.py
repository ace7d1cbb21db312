"""``morphkit bench shadows``: warped shadow maps vs re-rendering vs image-based maps.

Scene (stated once; every figure names it): a sample mesh (normalised: largest
extent 1, resting on the ground) moving over the range ``[-0.6, 0.6]^2`` of
the ground plane, lit by a **point light** at ``(0.25, -0.2, 2.4)`` (a spot
light ~2 object sizes above the range: the shadow changes shape with
position), and in a second scene by a **directional light** travelling
``(-0.5, 0.35, -1)``. Light frusta follow the object (:mod:`morphkit.shadow.rig`).

Ground truth: the ray-cast shadow (:mod:`morphkit.imaging.groundtruth`) at the centres of
a ``256 x 256`` grid over the ground square ``[-1.7, 1.7]^2``. Metrics, averaged
over seeded random positions in the range: ``iou`` (shadow-mask IoU, shadow =
visibility < 0.5) and ``mae`` (mean absolute visibility error over the grid).

Methods (one row each, timed in the same run, interleaved): ``warp`` (3 x 3
atlas, composed warps, projected control points, 17 x 17 control grid unless the
row says otherwise), ``warp_nearest`` (the same atlas, only the nearest sample's
map warped: ``blend="nearest"``), ``reproject`` (the same atlas, every pixel of
the cell's largest-weight map and of its neighbours' hidden layers moved in 3-D
into one z-buffer: ``warps="reproject"``; ``prep_ms`` is the one-off time to
build the layers, ``layer_mb`` their run-time memory), ``reproject_full`` (the
neighbours' whole maps instead: ``layers=False``),
``warp_three`` (the paper's three warps with interpolated
control points, shared anchors, 5 x 15 grid), ``direct`` (re-render per frame), ``ibr_nearest`` /
``ibr_blend`` with ``k`` maps per axis (the number in the method name) (32 by default, 3 for equal memory
with the atlas). ``ms_median`` is the time to produce one shadow map; rows with
``what=frame`` time a whole frame (camera drawn once, lit and unlit, at 512^2, shadow
map, lookup, composite). Memory (``mem_mb``) is the precomputed data.

One-pass frames (rows with ``what=frame_once``): the cow at ~6k and ~1M faces
(:func:`frame_once_rows`), camera 512^2, 512^2 maps, the point light: ``two_warp`` (the frame
as before: the camera drawn lit, then unlit; the warped map), ``once_warp`` and
``once_reproject`` (the camera drawn once, :meth:`Renderer.frame_pass
<morphkit.render.Renderer.frame_pass>`), ``once_direct`` (the direct frame: one pass and the
light's map re-rendered every frame), ``camera_once`` / ``camera_two`` (the camera draws
alone). ``vs_direct`` is a row's median over ``once_direct``'s; ``mean_levels`` the mean
absolute shaded difference of the one-pass frame against the two-render frame (levels of 255).

Cut-outs (rows with ``what=cutout``): the leaf plant of
:func:`morphkit.programs.fixtures.write_leaf_plant` (a stem and three alpha-masked leaf
cards, loaded by :func:`morphkit.meshes.load_mesh`) under the point light at
``256^2``: ``warp``, ``reproject`` and ``direct`` against the cut-out-aware ray
cast (the maps have holes where the leaves' texels are masked); ``iou_solid`` is the
same map against a ray cast of the bare card squares, the shadow a cut-out-blind
truth would give.
"""

from __future__ import annotations

import gc
import tempfile
import time
from typing import Any

import numpy as np
import trimesh

from ..imaging.groundtruth import hard_visibility, receiver_grid
from ..imaging.metrics import shadow_iou
from ..memo import Memo
from ..meshes import load_mesh, sample_mesh
from ..programs.fixtures import write_leaf_plant
from ..protocols import FrameRenderer, SceneRenderer
from ..scene import DirectionalLight, PointLight, SceneObject
from ..shadow import DirectShadow, ImageBasedShadow, MotionRange, bake_atlas, shadow_visibility
from .harness import Timing, make_row, pick_sections, section_name, time_cycling

__all__ = ["run", "frame_once_rows", "FLOOR_METHOD", "PLOT_OPTIONS"]

SUITE = "shadows"
#: The method the table's ratio column divides by (see :mod:`morphkit.bench`).
FLOOR_METHOD = "direct"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite's plots.
PLOT_OPTIONS: dict[str, Any] = {
    "size_key": "size", "error_key": "iou_err", "panel_keys": ("mesh", "what", "light"),
    "scene_keys": ("what", "light", "mesh"), "family": r"_\d+(?:x\d+)?",
    "defaults": ({"method": "warp", "size": 512}, {"method": "warp_17x17"}),
    "default_label": "default: warp (3x3 atlas, 17x17 grid, 512²)"}

MOTION = MotionRange([-0.6, -0.6], [0.6, 0.6])
POINT = PointLight([0.25, -0.2, 2.4])
SUN = DirectionalLight([-0.5, 0.35, -1.0])
GROUND_HALF, GROUND_N = 1.7, 256


def _positions(n: int, seed: int = 2026) -> np.ndarray:
    return np.random.default_rng(seed).uniform(MOTION.lo, MOTION.hi, (n, 2))


class _Truth:
    """Ray-cast ground truth per (mesh, light, position), computed once."""

    def __init__(self) -> None:
        self.grid = receiver_grid(GROUND_HALF, (GROUND_N, GROUND_N)).reshape(-1, 3)
        self._cache: Memo[tuple[int, int, bytes], np.ndarray] = Memo()

    def __call__(self, mesh: Any, light: Any, xy: np.ndarray) -> np.ndarray:
        def cast() -> np.ndarray:
            pose = np.eye(4)
            pose[:2, 3] = xy
            return hard_visibility(self.grid, light, SceneObject(mesh, pose))

        return self._cache.get((id(mesh), id(light), xy.tobytes()), cast)


def _errors(method: Any, mesh: Any, light: Any, xys: np.ndarray, truth: _Truth) -> dict[str, float]:
    ious, maes = [], []
    for xy in xys:
        gt = truth(mesh, light, xy)
        d, cam = method.shadow_map(xy)
        est = shadow_visibility(truth.grid, d, cam)
        ious.append(shadow_iou(est < 0.5, gt < 0.5))
        maes.append(float(np.mean(np.abs(est - gt))))
    return {"iou": float(np.mean(ious)), "iou_min": float(np.min(ious)),
            "iou_err": 1.0 - float(np.mean(ious)), "mae": float(np.mean(maes))}


def _time_maps(methods: dict[str, Any], xys: np.ndarray, repeats: int) -> dict[str, Timing]:
    """Time one shadow map per call, cycling through positions (cells differ)."""
    return time_cycling({name: m.shadow_map for name, m in methods.items()}, xys,
                        repeats=repeats, warmup=2)


def _prepare(atlas: Any) -> dict[str, float]:
    """Build the atlas's hidden layers ahead (timed once) and report their memory."""
    seconds = atlas.prepare()
    return {"prep_ms": 1e3 * seconds, "layer_mb": atlas.layer_bytes / 2**20}


def _accuracy_rows(renderer: SceneRenderer, quick: bool, truth: _Truth) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    meshes = ["cow"] if quick else ["teapot", "chair", "cow"]
    sizes = [128, 256] if quick else [64, 128, 256, 512, 1024]
    n_pos = 8 if quick else 50
    ibr_k = 8 if quick else 32
    xys = _positions(n_pos)
    lights = [("point", POINT)] if quick else [("point", POINT), ("directional", SUN)]
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        for light_name, light in lights:
            for size in sizes:
                if size > 512 and light_name != "point":
                    continue
                shape = (size, size)
                atlas = bake_atlas(mesh, np.eye(4), MOTION, light, shape, renderer=renderer,
                                   progress=False)
                methods: dict[str, Any] = {
                    "warp": atlas.method(),
                    "warp_nearest": atlas.method(blend="nearest"),
                    "reproject": atlas.method(warps="reproject"),
                    "reproject_full": atlas.method(warps="reproject", layers=False),
                    "direct": DirectShadow(atlas.rig, mesh, renderer),
                }
                prep = _prepare(atlas)
                if light_name == "point":
                    shared = bake_atlas(mesh, np.eye(4), MOTION, light, shape, renderer=renderer,
                                        anchors="shared", control_grid=(5, 15), progress=False)
                    methods["warp_three"] = shared.method(warps="three", dst="interpolate")
                ibr3 = ImageBasedShadow.bake(mesh, np.eye(4), MOTION, light, shape, renderer=renderer,
                                             grid=3, mode="blend", progress=False)
                methods["ibr_blend_3"] = ibr3
                k = ibr_k if size <= 512 else 16
                ibr = ImageBasedShadow.bake(mesh, np.eye(4), MOTION, light, shape, renderer=renderer,
                                            grid=k, mode="nearest", progress=False)
                methods[f"ibr_nearest_{k}"] = ibr
                methods[f"ibr_blend_{k}"] = ImageBasedShadow(ibr.atlas, "blend")
                timings = _time_maps(methods, xys, repeats=5 if quick else 15)
                for name, m in methods.items():
                    err = _errors(m, mesh, light, xys, truth)
                    err["mem_mb"] = m.memory_bytes / 2**20
                    if name == "reproject":
                        err.update(prep)
                    note = "" if size <= 512 or not name.startswith("ibr_") else "ibr grid 16 at 1024"
                    rows.append(make_row(SUITE, name, {"what": "map", "mesh": mesh_name,
                                                       "light": light_name, "size": size,
                                                       "faces": len(mesh.faces)},
                                         timings[name], metrics=err, note=note))
                del ibr, ibr3, methods
                gc.collect()
    return rows


def _cutout_rows(renderer: SceneRenderer, quick: bool, truth: _Truth) -> list[dict[str, Any]]:
    """The leaf plant (alpha-masked cards) against the cut-out-aware ray cast (module notes)."""
    with tempfile.TemporaryDirectory() as folder:
        plant = load_mesh(write_leaf_plant(folder))
    solid = trimesh.Trimesh(plant.vertices, plant.faces, process=False)  # the cards without their masks
    xys = _positions(8 if quick else 20, seed=13)
    size = 256
    atlas = bake_atlas(plant, np.eye(4), MOTION, POINT, (size, size), renderer=renderer, progress=False)
    methods = {"warp": atlas.method(), "reproject": atlas.method(warps="reproject"),
               "direct": DirectShadow(atlas.rig, plant, renderer)}
    _prepare(atlas)
    timings = _time_maps(methods, xys, repeats=3 if quick else 7)
    rows = []
    for name, m in methods.items():
        err = _errors(m, plant, POINT, xys, truth)
        err["iou_solid"] = _errors(m, solid, POINT, xys, truth)["iou"]
        rows.append(make_row(SUITE, name, {"what": "cutout", "mesh": "leaf_plant", "light": "point",
                                           "size": size, "faces": len(plant.faces)},
                             timings[name], metrics=err))
    return rows


def _control_grid_rows(renderer: SceneRenderer, quick: bool, truth: _Truth) -> list[dict[str, Any]]:
    rows = []
    meshes = ["cow"] if quick else ["teapot", "chair", "cow"]
    grids = [(5, 15), (17, 17)] if quick else [(5, 15), (7, 15), (9, 9), (12, 12), (17, 17), (33, 33)]
    xys = _positions(8 if quick else 20, seed=7)
    size = 256 if quick else 512
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        methods = {}
        for g in grids:
            atlas = bake_atlas(mesh, np.eye(4), MOTION, POINT, (size, size), renderer=renderer,
                               control_grid=g, progress=False)
            methods[f"warp_{g[0]}x{g[1]}"] = atlas.method()
        timings = _time_maps(methods, xys, repeats=5 if quick else 10)
        for name, m in methods.items():
            rows.append(make_row(SUITE, name, {"what": "control_grid", "mesh": mesh_name,
                                               "light": "point", "size": size},
                                 timings[name], metrics=_errors(m, mesh, POINT, xys, truth)))
    return rows


def _complexity_rows(renderer: SceneRenderer, quick: bool) -> list[dict[str, Any]]:
    """Cow from ~6k to ~1M faces at 512^2: warp vs direct time per shadow map."""
    rows = []
    faces = [6000, 50000] if quick else [6000, 50000, 300000, 1000000]
    size = 256 if quick else 512
    xys = _positions(10, seed=11)
    for f in faces:
        mesh = sample_mesh("cow", faces=f)
        atlas = bake_atlas(mesh, np.eye(4), MOTION, POINT, (size, size), renderer=renderer,
                           progress=False)
        methods = {"warp": atlas.method(), "warp_nearest": atlas.method(blend="nearest"),
                   "reproject": atlas.method(warps="reproject"),
                   "reproject_full": atlas.method(warps="reproject", layers=False),
                   "direct": DirectShadow(atlas.rig, mesh, renderer)}
        prep = _prepare(atlas)
        timings = _time_maps(methods, xys, repeats=5 if quick else 15)
        for name in methods:
            rows.append(make_row(SUITE, name, {"what": "complexity", "mesh": "cow", "light": "point",
                                               "size": size, "faces": len(mesh.faces)},
                                 timings[name], metrics=prep if name == "reproject" else None))
    return rows


def _frame_rows(renderer: SceneRenderer, quick: bool) -> list[dict[str, Any]]:
    """Whole frame: camera pass (lit and unlit in one draw, 512^2) + shadow map + lookup + composite."""
    from ..camera import look_at, perspective
    from ..scene import Receiver, Scene
    from ..shadow.frame import render_frame

    rows = []
    meshes = ["cow"] if quick else ["teapot", "chair", "cow"]
    sizes = [128, 256] if quick else [64, 128, 256, 512]
    cam = perspective(np.deg2rad(45), (512, 512), look_at([2.4, -2.2, 1.8], [0.0, 0.0, 0.2]),
                      znear=0.1, zfar=20)
    xys = _positions(6, seed=5)
    for mesh_name in meshes:
        mesh = sample_mesh(mesh_name)
        for size in sizes:
            atlas = bake_atlas(mesh, np.eye(4), MOTION, POINT, (size, size), renderer=renderer,
                               progress=False)
            methods = {"warp": atlas.method(), "reproject": atlas.method(warps="reproject"),
                       "direct": DirectShadow(atlas.rig, mesh, renderer)}
            atlas.prepare()
            fns = {}
            for name, m in methods.items():

                def frame(xy: np.ndarray, m: Any = m, mesh: Any = mesh) -> None:
                    pose = np.eye(4)
                    pose[:2, 3] = xy
                    scene = Scene(SceneObject(mesh, pose), POINT, cam, Receiver(2.0))
                    d, lcam = m.shadow_map(xy)
                    render_frame(renderer, scene,
                                 lambda p, n, d=d, lcam=lcam: shadow_visibility(p, d, lcam, normals=n))

                fns[name] = frame
            timings = time_cycling(fns, xys, repeats=3 if quick else 7, warmup=1)
            for name in methods:
                rows.append(make_row(SUITE, name, {"what": "frame", "mesh": mesh_name, "light": "point",
                                                   "size": size, "faces": len(mesh.faces)},
                                     timings[name]))
    return rows


def frame_once_rows(renderer: FrameRenderer, faces: tuple[int, ...] = (6000, 1000000), size: int = 512,
                    repeats: int = 7, *, receiver_only: bool = False) -> list[dict[str, Any]]:
    """Whole frames drawing the camera once vs twice vs the direct frame (module notes).

    Parameters
    ----------
    renderer : FrameRenderer
        Draws the frames (one-pass and two-render).
    faces : tuple of int
        Face counts of the subdivided cow (:func:`~morphkit.meshes.sample_mesh`).
    size : int
        Camera and shadow-map side, pixels.
    repeats : int
        Interleaved timed rounds per case (medians).
    receiver_only : bool
        Frames in the receiver-only mode (the two-render frame then draws the object alone too).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..camera import look_at, perspective

    cam = perspective(np.deg2rad(45), (size, size), look_at([2.4, -2.2, 1.8], [0.0, 0.0, 0.2]),
                      znear=0.1, zfar=20)
    rows = []
    for f in faces:
        rows += _frame_once_case(renderer, cam, sample_mesh("cow", faces=f), repeats, receiver_only)
        gc.collect()
    return rows


def _frame_once_case(renderer: FrameRenderer, cam: Any, mesh: trimesh.Trimesh, repeats: int,
                     receiver_only: bool) -> list[dict[str, Any]]:
    """:func:`frame_once_rows` for one mesh."""
    from ..scene import Receiver, Scene
    from ..shadow.frame import frame_items, render_frame

    xys = _positions(6, seed=5)
    atlas = bake_atlas(mesh, np.eye(4), MOTION, POINT, cam.shape, renderer=renderer, progress=False)
    atlas.prepare()
    maps = {"warp": atlas.method(), "reproject": atlas.method(warps="reproject"),
            "direct": DirectShadow(atlas.rig, mesh, renderer)}

    def scene_at(xy: np.ndarray) -> Scene:
        pose = np.eye(4)
        pose[:2, 3] = xy
        return Scene(SceneObject(mesh, pose), POINT, cam, Receiver(2.0))

    def frame(xy: np.ndarray, m: Any, one_pass: bool) -> dict[str, np.ndarray]:
        d, lcam = m.shadow_map(xy)
        return render_frame(renderer, scene_at(xy), lambda p, n: shadow_visibility(p, d, lcam, normals=n),
                            one_pass=one_pass, receiver_only=receiver_only)

    def camera(xy: np.ndarray, once: bool) -> None:
        sc = scene_at(xy)
        if once:
            renderer.frame_pass(cam, frame_items(sc), [POINT], ambient=sc.ambient)
        else:
            for lights in ([POINT], []):
                renderer.color_depth(cam, frame_items(sc), lights, ambient=sc.ambient)

    fns = {"two_warp": lambda xy: frame(xy, maps["warp"], False),
           "once_warp": lambda xy: frame(xy, maps["warp"], True),
           "once_reproject": lambda xy: frame(xy, maps["reproject"], True),
           "once_direct": lambda xy: frame(xy, maps["direct"], True),
           "camera_once": lambda xy: camera(xy, True), "camera_two": lambda xy: camera(xy, False)}
    timings = time_cycling(fns, xys, repeats=repeats, warmup=len(xys))  # warm: every position once

    def levels(m: Any) -> float:  # mean |one pass - two renders| of shaded, levels of 255
        return float(np.mean([np.abs(frame(xy, m, True)["shaded"].astype(np.int16)
                                     - frame(xy, m, False)["shaded"]).mean() for xy in xys]))

    mean_levels = {f"once_{k}": levels(m) for k, m in maps.items()}
    floor = timings["once_direct"].ms_median
    rows = []
    for name, t in timings.items():
        metrics = {"vs_direct": t.ms_median / floor}
        if name in mean_levels:
            metrics["mean_levels"] = mean_levels[name]
        params = {"what": "frame_once", "mesh": "cow", "light": "point", "size": cam.shape[0],
                  "faces": len(mesh.faces), "receiver_only": receiver_only}
        rows.append(make_row(SUITE, name, params, t, metrics=metrics))
    return rows


#: The suite's sections in their order (``--sections``: their names less ``_rows``, dashes for
#: underscores: accuracy, cutout, control-grid, complexity, frame, frame-once).
SECTIONS = (_accuracy_rows, _cutout_rows, _control_grid_rows, _complexity_rows, _frame_rows, frame_once_rows)


def run(*, quick: bool = False, sections: str | None = None) -> list[dict[str, Any]]:
    """All shadow rows: accuracy + map time, cut-outs, control-grid sweep, complexity sweep, frames.

    Parameters
    ----------
    quick : bool
        Fewer and smaller cases (a smoke run).
    sections : str, optional
        Comma-separated names of the sections to run (``SECTIONS``); all when None.

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    from ..render import Renderer

    picked = {section_name(s) for s in pick_sections(sections, SECTIONS)}
    t0 = time.perf_counter()
    truth = _Truth()
    rows: list[dict[str, Any]] = []
    with Renderer() as renderer:
        for section in (_accuracy_rows, _cutout_rows, _control_grid_rows):
            if section_name(section) in picked:
                rows += section(renderer, quick, truth)
        for section in (_complexity_rows, _frame_rows):
            if section_name(section) in picked:
                rows += section(renderer, quick)
        if section_name(frame_once_rows) in picked:
            rows += frame_once_rows(renderer, (6000, 50000) if quick else (6000, 1000000),
                                    256 if quick else 512, 3 if quick else 9)
    print(f"shadows suite: {len(rows)} rows in {time.perf_counter() - t0:.0f} s", flush=True)
    return rows
