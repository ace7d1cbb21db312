"""``morphkit bench bake``: throughput of the bake pipeline (Dask) against a plain serial loop.

Library (generated, stated once): 16 meshes of mixed size written to a temporary
folder -- the cow-like mesh at 4k..100k faces (``.ply``), the teapot at
resolutions 4..24 (1k..37k faces, ``.obj``, written ``+y`` up as exporters write
OBJ, so that :func:`~morphkit.meshes.load_mesh` turns them back upright), the chair
with 2..5 slats (``.ply``); each baked into one 512 x 512, 3 x 3 shadow atlas (the
:class:`~morphkit.bake.ShadowAtlasKind` defaults). ``--quick``: 8 of them at 256 x 256.

Rows (``what``):

* ``library``: the whole library, in one phase per worker count (``--workers``,
  default 1 2) and one with Dask's default worker settings, each with one local
  cluster alive (its scheduler and nannies run in this process and cost CPU
  even when idle) and timed interleaved with ``serial`` -- a plain loop in this
  process (``load_mesh``, ``bake_atlas``, ``save``; one renderer created
  beforehand), the loop a user writes by hand. ``dask_N``:
  :func:`~morphkit.bake.bake_library` on a local cluster of N worker
  processes as ``morphkit bake`` starts it (:func:`~morphkit.bake.open_client`;
  start-up timed apart, workers warmed: imports and GL context), into a fresh
  output folder each time (everything baked: input hashing, manifest journal and
  commits included); ``dask_1_dask_defaults``: ``dask_1`` on a cluster with
  Dask's default worker settings (``MALLOC_TRIM_THRESHOLD_=65536``, the thread
  profiler on), which ``morphkit bake`` changes
  (:data:`morphkit.bake.cluster.LOCAL_WORKER_CONFIG`). Metrics:
  ``assets_per_min``; ``speedup`` over the phase's ``serial`` (best of the
  repeats of each: the machine is shared); ``driver_cpu_s``: CPU time of this
  process during the run (the serial loop itself; for Dask the driver and the
  local cluster's scheduler and nannies); ``worker_cpu_s``: the tasks' CPU time
  (each worker process's during its tasks, from the manifest);
  ``idle_speedup_est``: the serial loop's CPU time over :func:`idle_makespan`,
  what the speedup would be on this machine with nothing else running (CPU
  times are far less disturbed by other load than wall times; an estimate, not
  a measurement). CPU figures are medians over the repeats. ``speedup_vs_1``:
  ``dask_1``'s best wall time over ``dask_N``'s (the speed-up curve).
* ``startup``: starting a local cluster of N workers (``start_N_workers``: wall
  time until all are connected), then warming them; metrics ``warm_s`` (wall of
  warming every worker: its GL context and one tiny bake), per worker (means):
  ``worker_import_cpu_s`` (the worker process's CPU until it runs its first
  task: interpreter, Dask, morphkit's imports), ``worker_warm_cpu_s`` (GL
  context and first bake) and ``worker_start_cpu_s`` (their sum: what each
  worker pays once).
* ``compile``: numba's compilation per process, from its compile events
  (:func:`kernel_workload`, run in a fresh process): ``cold`` with an empty
  ``NUMBA_CACHE_DIR`` (a fresh machine), ``cached`` in a second process with the
  cache the first wrote. Metrics ``compile_s`` (all kernels), ``bake_compile_s``
  (during a default atlas bake alone), ``kernels``.
* ``projection``: the wall time and speed-up of a library of
  :data:`PROJECTED_ASSETS` assets on 1 / 4 / 16 workers of a machine with a
  core per worker, computed by :func:`project_bake` from the figures measured
  here (assumptions in its docstring and in each row's note). A projection,
  not a measurement.
* ``rerun``: ``bake_library`` again on a complete output folder, nothing changed
  (every input and output hashed, no cluster started); ``fraction_of_first``:
  its time over the best run's of the most workers (start-up excluded), and
  ``fraction_of_first_with_startup``.
* ``overhead``: ``noop_task`` -- the scheduler's cost per task, measured with
  trivial tasks through the client of the most workers (``client.map`` of 400 no-ops, wall
  time / 400: submission, scheduling, transfer and result of each task);
  ``idle_cluster`` -- this process's CPU while that cluster idles (``cpu_per_s``);
  ``journal_append`` -- the driver's fsync-ed manifest journal line for one
  result (results that arrive together share one).

The projection for a larger cluster from these figures is in ``docs/results/bake.md``.
"""

from __future__ import annotations

import json
import logging
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import morphkit

from .. import tol
from ..bake import BakeOptions, ShadowAtlasKind, bake_library, find_inputs, open_client, worker_renderer
from ..errors import ValidationError, expected_got
from ..files.fileio import append_lines
from ..meshes import Y_UP_TO_Z_UP, chair, cow, load_mesh, resolve_up, teapot
from ..settings import child_environment, numba
from ..validate import as_int
from .harness import Timing, make_row

#: The suite's name in bench rows.
SUITE = "bake"
#: The method the table's ratio column divides by: the hand-written serial loop.
FLOOR_METHOD = "serial"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite.
PLOT_OPTIONS = {"size_key": "assets", "panel_keys": ("what",)}
#: Worker counts of the ``library`` phases by default (``morphkit bench bake --workers``).
DEFAULT_WORKERS: tuple[int, ...] = (1, 2)
#: The library size of the ``projection`` rows (the target: 256 assets).
PROJECTED_ASSETS = 256
#: Worker counts of the ``projection`` rows.
PROJECTED_WORKERS: tuple[int, ...] = (1, 4, 16)

#: (builder, argument, suffix) of the library's meshes; quick takes every other one.
LIBRARY: tuple[tuple[str, int, str], ...] = (
    ("cow", 4000, ".ply"), ("cow", 8000, ".ply"), ("cow", 16000, ".ply"), ("cow", 30000, ".ply"),
    ("cow", 50000, ".ply"), ("cow", 100000, ".ply"),
    ("teapot", 4, ".obj"), ("teapot", 6, ".obj"), ("teapot", 8, ".obj"), ("teapot", 12, ".obj"),
    ("teapot", 16, ".obj"), ("teapot", 24, ".obj"),
    ("chair", 2, ".ply"), ("chair", 3, ".ply"), ("chair", 4, ".ply"), ("chair", 5, ".ply"),
)
_BUILD = {"cow": lambda n: cow(faces=n), "teapot": lambda n: teapot(resolution=n),
          "chair": lambda n: chair(slats=n)}


def write_library(folder: Path, quick: bool, assets: int | None = None) -> list[Path]:
    """Write the benchmark's meshes into ``folder``; return their paths.

    Parameters
    ----------
    folder : pathlib.Path
        Output folder (created).
    quick : bool
        Every other mesh of the library only.
    assets : int, optional
        The library's size: its meshes repeated in order until there are ``assets`` files,
        copy ``k`` of a mesh turned by ``k`` degrees about the up axis (so that every input,
        and its hash, differs; the bake's work per copy is the same). None: each mesh once.

    Returns
    -------
    list of pathlib.Path
        The mesh files written; each loads (:func:`~morphkit.meshes.load_mesh`, ``up="auto"``)
        upright: a format read ``+y`` up (OBJ) is written ``+y`` up.
    """
    import numpy as np
    import trimesh

    entries = LIBRARY[::2] if quick else LIBRARY
    total = len(entries) if assets is None else as_int(assets, "library assets", lo=1,
                                                       hi=tol.MAX_BENCH_ASSETS)
    folder.mkdir(parents=True, exist_ok=True)
    built: dict[int, Any] = {}
    paths = []
    for i in range(total):
        name, arg, suffix = entries[i % len(entries)]
        copy = i // len(entries)
        p = folder / (f"{name}_{arg}{suffix}" if assets is None else f"{name}_{arg}_{copy:03d}{suffix}")
        if i % len(entries) not in built:
            built[i % len(entries)] = _BUILD[name](arg)
        mesh = built[i % len(entries)].copy()
        if copy:
            mesh.apply_transform(trimesh.transformations.rotation_matrix(np.deg2rad(copy), [0.0, 0.0, 1.0]))
        if resolve_up(p) == "y":
            mesh.apply_transform(Y_UP_TO_Z_UP.T)  # the inverse rotation: +z up -> +y up
        mesh.export(p)
        paths.append(p)
    return paths


def warm_worker() -> dict[str, float]:
    """Run on every worker before timing: the GL context, one tiny bake; report the start-up CPU.

    Returns
    -------
    dict of str to float
        ``import_cpu_s``: this process's CPU time when called (interpreter, Dask and
        morphkit imports: everything before the first task); ``warm_cpu_s``: the CPU of
        the GL context and the tiny bake; ``warm_s``: their wall time.
    """
    import numpy as np

    from ..scene import PointLight
    from ..shadow import MotionRange, bake_atlas

    c0, t0 = time.process_time(), time.perf_counter()
    bake_atlas(teapot(4), np.eye(4), MotionRange([-0.5, -0.5], [0.5, 0.5]), PointLight([0, 0, 2.0]),
               (32, 32), renderer=worker_renderer(), progress=False)
    return {"import_cpu_s": c0, "warm_cpu_s": time.process_time() - c0, "warm_s": time.perf_counter() - t0}


def kernel_workload() -> dict[str, float]:
    """numba's compile time in this process: a default-kind atlas bake, then playback through
    every compiled path (composed warps and reprojection at 512^2, in bands of rows where this
    machine has the threads, the shadow lookup, a frame's drawn pixels and shade, the default
    soft shadow's filtered lookup, a field's splatted sun view), from numba's ``numba:compile``
    events (run it in a fresh process: :func:`measure_compile`). ``scripts/setup.sh`` runs it
    once, so that the demo, the tests and a bake compile nothing after setup.

    Returns
    -------
    dict of str to float
        ``compile_s`` (seconds inside top-level compilations, all kernels), ``bake_compile_s``
        (of them, during the atlas bake), ``kernels`` (compilations), ``wall_s`` (the workload).
    """
    import numpy as np

    from ..billboard.frames.instances import Instances
    from ..imaging.composite import shade
    from ..imaging.groundtruth import receiver_grid
    from ..scene import AreaLight, PointLight
    from ..shadow import (
        MotionRange,
        bake_atlas,
        bake_soft_atlas,
        default_soft_shadow,
        shadow_visibility,
    )
    from ..shadow.pixels import drawn_pixels
    from ..sunlit import FieldShadow, bake_sun_atlas
    from ..warp import warp_mesh

    if numba is None:  # pragma: no cover - numba is a dependency
        return {"compile_s": 0.0, "bake_compile_s": 0.0, "kernels": 0.0, "wall_s": 0.0}
    from numba.core import event

    t0 = time.perf_counter()
    with event.install_recorder("numba:compile") as rec:
        light, motion, mesh = PointLight([0.25, -0.2, 2.4]), MotionRange([-0.6, -0.6], [0.6, 0.6]), teapot(6)
        renderer = worker_renderer()
        atlas = bake_atlas(mesh, np.eye(4), motion, light, (128, 128), renderer=renderer, progress=False)
        n_bake = len(rec.buffer)
        ground = receiver_grid(1.5, (64, 64)).reshape(-1, 3)
        for warps in ("composed", "reproject"):
            depth, cam = atlas.shadow_map([0.2, -0.3], warps=warps)
            shadow_visibility(ground, depth, cam)
        drawn_pixels(cam, depth, light)  # a frame's per-pixel kernels (render_frame)
        shade(np.zeros((*cam.shape, 3), np.uint8), np.zeros((*cam.shape, 3), np.uint8),
              np.ones(cam.shape, np.float32))
        # the demo's sizes: maps of 512^2 warp and reproject in bands of rows
        big = bake_atlas(mesh, np.eye(4), motion, light, (512, 512), renderer=renderer, progress=False)
        for warps in ("composed", "reproject"):
            big.shadow_map([0.2, -0.3], warps=warps)
        # the default soft shadow (its filtered lookup over the reprojected maps)
        area = AreaLight([0.25, -0.2, 2.4], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0])
        soft = bake_soft_atlas(mesh, np.eye(4), motion, area, (128, 128), renderer=renderer, progress=False)
        default_soft_shadow(soft, area).visibility(np.array([0.1, 0.1]), ground)
        # a field's sun view, splatted (a map large enough for bands of rows), of one asset and of two
        sun_atlas = bake_sun_atlas(mesh, renderer, size=32)
        for names in (("a",), ("a", "b")):
            field = Instances(names, np.arange(2) % len(names), np.array([[0.0, 0.0], [1.5, 0.5]]),
                              np.array([0.0, 40.0]), np.ones(2))
            FieldShadow(dict.fromkeys(names, sun_atlas)).build(field, np.array([0.3, -0.2, 0.9]), 400.0)
        # an image's piecewise-affine warp (view morphing, billboards)
        pts = np.stack(np.meshgrid(np.linspace(0, 63, 5), np.linspace(0, 63, 5)), -1).reshape(-1, 2)
        warp_mesh(np.zeros((64, 64, 3), np.uint8), pts, pts * 0.9 + 3.0, (64, 64))

    def top_level(buffer: list[Any]) -> tuple[float, int]:
        total, depth, start, n = 0.0, 0, 0.0, 0
        for ts, ev in buffer:
            if ev.is_start:
                start = ts if depth == 0 else start
                depth += 1
            else:
                depth -= 1
                n += 1
                total += ts - start if depth == 0 else 0.0
        return total, n

    compile_s, kernels = top_level(rec.buffer)
    return {"compile_s": compile_s, "bake_compile_s": top_level(rec.buffer[:n_bake])[0],
            "kernels": float(kernels), "wall_s": time.perf_counter() - t0}


def measure_compile(cache_dir: Path) -> dict[str, float]:
    """:func:`kernel_workload` in a fresh Python process whose numba cache is ``cache_dir``.

    Parameters
    ----------
    cache_dir : pathlib.Path
        ``NUMBA_CACHE_DIR`` of the child (empty: a fresh machine; reused: cached kernels).

    Returns
    -------
    dict of str to float
        :func:`kernel_workload`'s figures, and ``process_s``: the child's whole wall time.
    """
    code = ("import json\nfrom morphkit.bench.bake_suite import kernel_workload\n"
            "print(json.dumps(kernel_workload()))")
    root = str(Path(morphkit.__file__).resolve().parent.parent)
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=root,
                         env=child_environment(NUMBA_CACHE_DIR=str(cache_dir)), check=False)
    if res.returncode != 0:
        raise RuntimeError(f"bench bake: the compile probe failed:\n{res.stderr[-2000:]}")
    return {**json.loads(res.stdout.strip().splitlines()[-1]), "process_s": time.perf_counter() - t0}


def noop(i: int) -> int:
    """A trivial task: the scheduler's overhead alone.

    Parameters
    ----------
    i : int
        Any value.

    Returns
    -------
    int
        ``i``.
    """
    return i


def idle_makespan(task_cpu: list[float], driver_cpu: float, workers: int) -> float:
    """Seconds a run would take on an otherwise idle machine with one core per worker: the tasks'
    CPU times (in submission order) list-scheduled on ``workers`` (each to the first free worker,
    as Dask does with one thread per worker), but no less than all the CPU, driver's included,
    spread over the cores.

    Parameters
    ----------
    task_cpu : list of float
        CPU seconds of each task, in submission order.
    driver_cpu : float
        CPU seconds of the driver process.
    workers : int
        Worker processes, one core each.

    Returns
    -------
    float
        The idle-machine makespan, seconds.
    """
    free = [0.0] * workers
    for c in task_cpu:
        free[free.index(min(free))] += c
    return max(max(free), (sum(task_cpu) + driver_cpu) / workers)


def project_bake(task_s: Sequence[float], *, assets: int, workers: int, fixed_s: float,
                 worker_start_s: float, per_task_s: float, growth_per_worker: float = 0.0) -> float:
    """Projected wall time of a bake of ``assets`` tasks on ``workers`` workers, cluster start included.

    Model (each term measured by :func:`run`): ``fixed_s`` (the cluster's scheduler and
    nannies, paid once) + ``worker_start_s`` (each worker's imports, GL context and first
    bake: paid by every worker, in parallel, each on its own core) + the tasks list-scheduled
    in submission order on ``workers`` (each to the first free one, as Dask does with one
    thread per worker; :func:`idle_makespan`), the task times being ``task_s`` repeated to
    ``assets`` tasks (the same mix of meshes) and each grown by ``growth_per_worker`` per
    worker beyond the first (contention for memory bandwidth; 0: none) + ``per_task_s`` per
    task of work done serially by the driver and scheduler (hashing, the journal, the
    scheduler's per-task cost), overlapped with the tasks where they are longer.

    Assumptions: one core per worker as fast as the one the task times were measured on; no
    other load; inputs and outputs on a disk that keeps up.

    Parameters
    ----------
    task_s : sequence of float
        Seconds of each task of the measured library, in submission order.
    assets : int
        Tasks in the projected library.
    workers : int
        Worker processes, one core each.
    fixed_s : float
        Seconds paid once per run (the cluster without its workers).
    worker_start_s : float
        Seconds each worker pays before its first task.
    per_task_s : float
        Serial driver and scheduler seconds per task.
    growth_per_worker : float, optional
        Relative growth of every task's time per worker beyond the first.

    Returns
    -------
    float
        Projected seconds.
    """
    if not task_s or assets < 1 or workers < 1:
        raise ValidationError(expected_got("project_bake inputs", "task times, assets >= 1, workers >= 1",
                                           f"{len(task_s)} task times, {assets} assets, {workers} workers"))
    grow = 1.0 + growth_per_worker * (workers - 1)
    tasks = [task_s[i % len(task_s)] * grow for i in range(assets)]
    compute = idle_makespan(tasks, 0.0, workers)
    return fixed_s + worker_start_s + max(compute, assets * per_task_s)


def _serial(paths: list[Path], kind: ShadowAtlasKind, out: Path) -> None:
    out.mkdir(parents=True)
    renderer = worker_renderer()
    for p in paths:
        up = resolve_up(p)  # as bake_library resolves it (BakeOptions' default "auto")
        kind.bake(load_mesh(p, up=up), renderer, up).save(out / f"{p.stem}{kind.suffix}")


@contextmanager
def _cluster(workers: int, dask_defaults: bool) -> Iterator[Any]:
    """A local cluster as ``morphkit bake`` starts it (:func:`~morphkit.bake.open_client`), or
    the same with Dask's default worker settings."""
    if not dask_defaults:
        with open_client(workers=workers) as client:
            yield client
        return
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as cluster, \
            Client(cluster, set_as_default=False) as client:
        yield client


def run(*, quick: bool = False, workers: Sequence[int] = DEFAULT_WORKERS, assets: int | None = None,
        repeats: int | None = None, serial_once: bool = False,
        dask_defaults: bool | None = None) -> list[dict[str, Any]]:
    """The suite's rows (``morphkit bench bake``); ``quick``: fewer and smaller meshes.

    Parameters
    ----------
    quick : bool
        Fewer and smaller meshes, smaller atlases, one repeat; no phase with Dask's defaults
        and no ``compile`` rows (the cold compilation alone takes a minute here).
    workers : sequence of int, optional
        The worker counts of the ``library`` phases (distinct, >= 1; 1 is added when missing:
        the speed-up curve divides by it).
    assets : int, optional
        The library's size (:func:`write_library`; ``morphkit bench bake --assets``): e.g. 256,
        the measured target on a machine with the cores for it. None: the 16 meshes.
    repeats : int, optional
        Timed repeats of each phase (default 3, ``quick`` 1).
    serial_once : bool
        Time the serial loop in the first phase only (an idle machine with a core per worker,
        where interleaving guards against nothing and a large library's serial loop costs
        minutes per phase); later phases' ``speedup`` divides the first phase's serial time.
    dask_defaults : bool, optional
        Add the ``dask_1_dask_defaults`` phase (default: unless ``quick``).

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    counts = sorted({1, *(as_int(w, "workers", lo=1, hi=tol.MAX_LOCAL_WORKERS) for w in workers)})
    if assets is not None:  # refused before any work (write_library checks it again)
        as_int(assets, "library assets", lo=1, hi=tol.MAX_BENCH_ASSETS)
    kind = ShadowAtlasKind(atlas_size=256 if quick else 512)
    options = BakeOptions((kind,))
    repeats = (1 if quick else 3) if repeats is None else int(repeats)
    if repeats < 1:
        raise ValidationError(expected_got("repeats", ">= 1", repeats))
    rows: list[dict[str, Any]] = []
    tmp = Path(tempfile.mkdtemp(prefix="morphkit-bench-bake-"))
    try:
        warm_worker()  # this process too: the serial loop's renderer and caches (and every row's ``gl``)
        # fresh cache (a fresh machine), then a second process with the kernels on disk
        probes = () if quick else ("cold", "cached")
        for name in probes:
            c = measure_compile(tmp / "numba-cache")
            rows.append(make_row(SUITE, name, {"what": "compile", "assets": 1},
                                 Timing.from_seconds([c["compile_s"]]),
                                 metrics={k: c[k] for k in ("compile_s", "bake_compile_s", "kernels",
                                                            "wall_s", "process_s")},
                                 note="numba compile time per process (fresh process; "
                                      + ("empty NUMBA_CACHE_DIR)" if name == "cold" else "cache on disk)")))
        paths = write_library(tmp / "lib", quick, assets)
        n = len(find_inputs([tmp / "lib"]))
        phases = [(f"dask_{w}", w, False) for w in counts]
        if (not quick) if dask_defaults is None else dask_defaults:
            phases.append(("dask_1_dask_defaults", 1, True))
        best_of: dict[str, float] = {}
        task_cpu_of: dict[str, list[float]] = {}
        start_of: dict[int, dict[str, float]] = {}
        serial_of: dict[str, float] = {}
        # one cluster at a time (a cluster's scheduler and nannies run in this process and cost
        # CPU even when idle), each phase interleaved with the serial loop
        for method, w, defaults in phases:
            case = {"what": "library", "assets": n, "atlas": kind.atlas_size, "phase": method}
            t0 = time.perf_counter()
            with _cluster(w, defaults) as client:
                client.wait_for_workers(w)
                startup = time.perf_counter() - t0
                t0 = time.perf_counter()
                # on each worker's task thread (its renderer is per thread), not client.run's
                warm = client.gather([client.submit(warm_worker, workers=[a], allow_other_workers=False,
                                                    pure=False) for a in client.scheduler_info()["workers"]])
                warm_s = time.perf_counter() - t0
                address = client.scheduler.address
                timed = [method] if serial_once and serial_of else ["serial", method]
                wall: dict[str, list[float]] = {m_name: [] for m_name in timed}
                cpu: dict[str, list[float]] = {m_name: [] for m_name in timed}
                tasks_cpu: list[list[float]] = []
                for r in range(repeats):
                    for m_name in wall:
                        out = tmp / f"out_{m_name}_{r}"
                        c0, t0 = time.process_time(), time.perf_counter()
                        if m_name == "serial":
                            _serial(paths, kind, out)
                        else:
                            m = bake_library([tmp / "lib"], out, options=options, scheduler=address,
                                             progress=False)
                            if m.run["failed"]:
                                raise RuntimeError(f"bench bake failed: {m.failed()}")
                            order = sorted(m.assets.values(), key=lambda a: -a.input_bytes)  # submitted
                            tasks_cpu.append([a.timings_s["cpu"] for a in order])
                        wall[m_name].append(time.perf_counter() - t0)
                        cpu[m_name].append(time.process_time() - c0)
                        if r < repeats - 1 or m_name != method:
                            shutil.rmtree(out)
                if "serial" in wall:
                    serial_of = {"best": min(wall["serial"]), "cpu": statistics.median(cpu["serial"])}
                serial_best, serial_cpu = serial_of["best"], serial_of["cpu"]
                best = best_of[method] = min(wall[method])
                task_cpu_of[method] = [statistics.median(c) for c in zip(*tasks_cpu, strict=True)]
                metrics = {"assets_per_min": 60.0 * n / best, "speedup": serial_best / best,
                           "driver_cpu_s": statistics.median(cpu[method]),
                           "worker_cpu_s": statistics.median(sum(c) for c in tasks_cpu),
                           "idle_speedup_est": statistics.median(serial_cpu / idle_makespan(c, d, w)
                                                                 for c, d in zip(tasks_cpu, cpu[method],
                                                                                 strict=True))}
                if not defaults:
                    metrics["speedup_vs_1"] = best_of["dask_1"] / best
                if "serial" in wall:
                    rows.append(make_row(SUITE, "serial", case, Timing.from_seconds(wall["serial"]), metrics={
                        "assets_per_min": 60.0 * n / serial_best, "driver_cpu_s": serial_cpu}))
                note = "speedup: best of repeats" if repeats > 1 else ""
                if "serial" not in wall:
                    note = (note + "; " if note else "") + "speedup over the first phase's serial loop"
                rows.append(make_row(SUITE, method, case, Timing.from_seconds(wall[method]), metrics=metrics,
                                     note=note))
                costs = {"warm_s": warm_s,
                         "worker_import_cpu_s": statistics.fmean(x["import_cpu_s"] for x in warm),
                         "worker_warm_cpu_s": statistics.fmean(x["warm_cpu_s"] for x in warm)}
                costs["worker_start_cpu_s"] = costs["worker_import_cpu_s"] + costs["worker_warm_cpu_s"]
                if not defaults:
                    start_of[w] = {"startup_s": startup, **costs}
                name = f"start_{w}_workers" + ("_dask_defaults" if defaults else "")
                rows.append(make_row(SUITE, name, {"what": "startup", "assets": n, "workers": w},
                                     Timing.from_seconds([startup]), metrics=costs))
                if method != f"dask_{counts[-1]}":
                    continue
                rows += _rerun_and_overhead_rows(client, tmp / f"out_{method}_{repeats - 1}", options, n,
                                                 best, startup, repeats, w)
        rows.append(_journal_row(tmp / "journal"))
        rows += _projection_rows(rows, task_cpu_of["dask_1"], start_of, counts, n)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return rows


def _rerun_and_overhead_rows(client: Any, done: Path, options: BakeOptions, n: int, best: float,
                             startup: float, repeats: int, workers: int) -> list[dict[str, Any]]:
    """Rerun with nothing changed (on the last complete output); the scheduler's cost per task
    and an idle cluster's CPU, through ``client``."""
    rows = []
    rerun = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        m = bake_library([done.parent / "lib"], done, options=options, progress=False)
        rerun.append(time.perf_counter() - t0)
        if m.run["skipped"] != n:
            raise RuntimeError(f"bench bake: rerun baked again: {m.run}")
    rows.append(make_row(SUITE, "rerun", {"what": "rerun", "assets": n}, Timing.from_seconds(rerun), metrics={
        "fraction_of_first": min(rerun) / best,
        "fraction_of_first_with_startup": min(rerun) / (best + startup), "per_asset_s": min(rerun) / n}))
    k = 400
    client.gather(client.map(noop, range(50), pure=False))  # warm
    per = []
    for _ in range(3):
        t0 = time.perf_counter()
        client.gather(client.map(noop, range(k), pure=False))
        per.append((time.perf_counter() - t0) / k)
    rows.append(make_row(SUITE, "noop_task", {"what": "overhead", "assets": k}, Timing.from_seconds(per),
                         note=f"per task, {workers} workers"))
    c0, t0 = time.process_time(), time.perf_counter()
    time.sleep(2.0)
    rows.append(make_row(SUITE, "idle_cluster", {"what": "overhead", "assets": 0},
                         Timing.from_seconds([time.process_time() - c0]),
                         metrics={"cpu_per_s": (time.process_time() - c0) / (time.perf_counter() - t0)},
                         note=f"driver CPU of an idle {workers}-worker cluster over 2 s"))
    return rows


def _journal_row(log: Path) -> dict[str, Any]:
    per = []
    for i in range(200):
        t0 = time.perf_counter()
        append_lines(log, [f'{{"name": "x{i}", "status": "baked", "outputs": {{}}}}'])
        per.append(time.perf_counter() - t0)
    return make_row(SUITE, "journal_append", {"what": "overhead", "assets": 200}, Timing.from_seconds(per),
                    note="per result (fsync)")


def _projection_rows(rows: list[dict[str, Any]], task_s: list[float], start_of: dict[int, dict[str, float]],
                     counts: list[int], n: int) -> list[dict[str, Any]]:
    """The ``projection`` rows (:func:`project_bake`) from the measured rows of this run."""
    by = {r["method"]: r for r in rows}
    s1 = start_of[1]
    worker_start = statistics.fmean(v["worker_start_cpu_s"] for v in start_of.values())
    # the 1-worker cluster's start beyond its worker's own start-up CPU: scheduler, nanny, spawn
    fixed = max(0.0, s1["startup_s"] - s1["worker_import_cpu_s"])
    per_task = by["noop_task"]["ms_median"] / 1e3 + by["journal_append"]["ms_median"] / 1e3 \
        + by["rerun"]["metrics"]["per_asset_s"]
    # contention measured here: growth of the summed task CPU per added worker (2 busy cores
    # shared with other jobs: an upper bound more than an estimate)
    wmax = counts[-1]
    growth = 0.0
    if wmax > 1:
        ratio = by[f"dask_{wmax}"]["metrics"]["worker_cpu_s"] / by["dask_1"]["metrics"]["worker_cpu_s"]
        growth = max(0.0, (ratio - 1.0) / (wmax - 1))
    out = []
    one = project_bake(task_s, assets=PROJECTED_ASSETS, workers=1, fixed_s=fixed, worker_start_s=worker_start,
                       per_task_s=per_task)  # growth applies beyond the first worker only
    for w in PROJECTED_WORKERS:
        metrics = {"fixed_s": fixed, "worker_start_s": worker_start, "per_task_s": per_task,
                   "task_s_mean": statistics.fmean(task_s), "growth_per_worker": growth}
        for label, g in (("", 0.0), ("_contended", growth)):
            t = project_bake(task_s, assets=PROJECTED_ASSETS, workers=w, fixed_s=fixed,
                             worker_start_s=worker_start, per_task_s=per_task, growth_per_worker=g)
            metrics[f"wall_s{label}"] = t
            metrics[f"speedup{label}"] = one / t
        out.append(make_row(SUITE, f"projected_{w}", {"what": "projection", "assets": PROJECTED_ASSETS,
                                                     "workers": w},
                            Timing.from_seconds([metrics["wall_s"]]), metrics=metrics,
                            note=f"PROJECTED from {n} measured tasks (1 core per worker, idle machine; "
                                 "_contended: task time grown by the measured growth per worker)"))
    return out
