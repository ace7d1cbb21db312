"""``morphkit bench bake``: throughput of the bake pipeline (Dask) against a plain serial loop.

Library (generated, stated once): 16 meshes of mixed size written to a temporary
folder -- the cow-like mesh at 4k..100k faces (``.ply``), the teapot at
resolutions 4..24 (1k..37k faces, ``.obj``), the chair with 2..5 slats
(``.ply``); each baked into one 512 x 512, 3 x 3 shadow atlas (the
:class:`~morphkit.bake.ShadowAtlasKind` defaults). ``--quick``: 8 of them at 256 x 256.

Rows (``what``):

* ``library``: the whole library, in three phases, each with one local
  cluster alive (its scheduler and nannies run in this process and cost CPU
  even when idle) and timed interleaved with ``serial`` -- a plain loop in this
  process (``load_mesh``, ``bake_atlas``, ``save``; one renderer created
  beforehand), the loop a user writes by hand. ``dask_1`` / ``dask_2``:
  :func:`~morphkit.bake.bake_library` on a local cluster of 1 / 2 worker
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
  a measurement). CPU figures are medians over the repeats.
* ``startup``: starting a local cluster of 1 / 2 workers (until all are connected).
* ``rerun``: ``bake_library`` again on a complete output folder, nothing changed
  (every input and output hashed, no cluster started); ``fraction_of_first``:
  its time over the best ``dask_2`` run's (start-up excluded), and
  ``fraction_of_first_with_startup``.
* ``overhead``: ``noop_task`` -- the scheduler's cost per task, measured with
  trivial tasks through the 2-worker client (``client.map`` of 400 no-ops, wall
  time / 400: submission, scheduling, transfer and result of each task);
  ``idle_cluster`` -- this process's CPU while that cluster idles (``cpu_per_s``);
  ``journal_append`` -- the driver's fsync-ed manifest journal line for one
  result (results that arrive together share one).

The projection for a larger cluster from these figures is in ``docs/RESULTS.md``.
"""

from __future__ import annotations

import logging
import shutil
import statistics
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..bake import BakeOptions, ShadowAtlasKind, bake_library, find_inputs, open_client, worker_renderer
from ..fileio import append_lines
from ..meshes import chair, cow, load_mesh, teapot
from .harness import Timing, make_row

#: The suite's name in bench rows.
SUITE = "bake"
#: The method the table's ratio column divides by: the hand-written serial loop.
FLOOR_METHOD = "serial"
#: Keyword arguments of :func:`morphkit.bench.harness.write_plots` for this suite.
PLOT_OPTIONS = {"size_key": "assets", "panel_keys": ("what",)}

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


def write_library(folder: Path, quick: bool) -> list[Path]:
    """Write the benchmark's meshes into ``folder``; return their paths.

    Parameters
    ----------
    folder : pathlib.Path
        Output folder (created).
    quick : bool
        Every other mesh of the library only.

    Returns
    -------
    list of pathlib.Path
        The mesh files written.
    """
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, arg, suffix in LIBRARY[::2] if quick else LIBRARY:
        p = folder / f"{name}_{arg}{suffix}"
        _BUILD[name](arg).export(p)
        paths.append(p)
    return paths


def warm_worker() -> int:
    """Run on every worker before timing: imports, the GL context, one tiny bake (numba caches).

    Returns
    -------
    int
        The worker's process id.
    """
    import os

    import numpy as np

    from ..scene import PointLight
    from ..shadow import MotionRange, bake_atlas

    bake_atlas(teapot(4), np.eye(4), MotionRange([-0.5, -0.5], [0.5, 0.5]), PointLight([0, 0, 2.0]),
               (32, 32), renderer=worker_renderer(), progress=False)
    return os.getpid()


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


def _serial(paths: list[Path], kind: ShadowAtlasKind, out: Path) -> None:
    out.mkdir(parents=True)
    renderer = worker_renderer()
    for p in paths:
        kind.bake(load_mesh(p), renderer).save(out / f"{p.stem}{kind.suffix}")


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


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    """The suite's rows (``morphkit bench bake``); ``quick``: fewer and smaller meshes.

    Parameters
    ----------
    quick : bool
        Fewer and smaller meshes, smaller atlases, one repeat.

    Returns
    -------
    list of dict
        The rows (:func:`morphkit.bench.harness.make_row`).
    """
    kind = ShadowAtlasKind(atlas_size=256 if quick else 512)
    options = BakeOptions((kind,))
    repeats = 1 if quick else 3
    rows: list[dict[str, Any]] = []
    tmp = Path(tempfile.mkdtemp(prefix="morphkit-bench-bake-"))
    try:
        paths = write_library(tmp / "lib", quick)
        n = len(find_inputs([tmp / "lib"]))
        warm_worker()  # this process too: the serial loop's renderer and caches
        # one cluster at a time (a cluster's scheduler and nannies run in this process and cost
        # CPU even when idle), each phase interleaved with the serial loop
        for method, workers, defaults in (("dask_1", 1, False), ("dask_2", 2, False),
                                          ("dask_1_dask_defaults", 1, True)):
            case = {"what": "library", "assets": n, "atlas": kind.atlas_size, "phase": method}
            t0 = time.perf_counter()
            with _cluster(workers, defaults) as client:
                client.wait_for_workers(workers)
                startup = time.perf_counter() - t0
                client.run(warm_worker)
                address = client.scheduler.address
                wall: dict[str, list[float]] = {"serial": [], method: []}
                cpu: dict[str, list[float]] = {"serial": [], method: []}
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
                serial_best, serial_cpu = min(wall["serial"]), statistics.median(cpu["serial"])
                best = min(wall[method])
                rows.append(make_row(SUITE, "serial", case, Timing.from_seconds(wall["serial"]), metrics={
                    "assets_per_min": 60.0 * n / serial_best, "driver_cpu_s": serial_cpu}))
                rows.append(make_row(SUITE, method, case, Timing.from_seconds(wall[method]), metrics={
                    "assets_per_min": 60.0 * n / best, "speedup": serial_best / best,
                    "driver_cpu_s": statistics.median(cpu[method]),
                    "worker_cpu_s": statistics.median(sum(c) for c in tasks_cpu),
                    "idle_speedup_est": statistics.median(serial_cpu / idle_makespan(c, d, workers)
                                                          for c, d in zip(tasks_cpu, cpu[method],
                                                                          strict=True))},
                    note="speedup: best of repeats" if repeats > 1 else ""))
                name = f"start_{workers}_workers" + ("_dask_defaults" if defaults else "")
                rows.append(make_row(SUITE, name, {"what": "startup", "assets": n},
                                     Timing.from_seconds([startup])))
                if method != "dask_2":
                    continue
                done = tmp / f"out_{method}_{repeats - 1}"
                # rerun with nothing changed, on the last complete output
                rerun = []
                for _ in range(repeats):
                    t0 = time.perf_counter()
                    m = bake_library([tmp / "lib"], done, options=options, progress=False)
                    rerun.append(time.perf_counter() - t0)
                    if m.run["skipped"] != n:
                        raise RuntimeError(f"bench bake: rerun baked again: {m.run}")
                rows.append(make_row(SUITE, "rerun", {"what": "rerun", "assets": n},
                                     Timing.from_seconds(rerun), metrics={
                                         "fraction_of_first": min(rerun) / best,
                                         "fraction_of_first_with_startup": min(rerun) / (best + startup)}))
                # the scheduler's overhead per task (same client), the driver's journal line per result
                k = 400
                client.gather(client.map(noop, range(50), pure=False))  # warm
                per = []
                for _ in range(3):
                    t0 = time.perf_counter()
                    client.gather(client.map(noop, range(k), pure=False))
                    per.append((time.perf_counter() - t0) / k)
                rows.append(make_row(SUITE, "noop_task", {"what": "overhead", "assets": k},
                                     Timing.from_seconds(per), note="per task, 2 workers"))
                c0, t0 = time.process_time(), time.perf_counter()
                time.sleep(2.0)
                rows.append(make_row(SUITE, "idle_cluster", {"what": "overhead", "assets": 0},
                                     Timing.from_seconds([time.process_time() - c0]),
                                     metrics={"cpu_per_s": (time.process_time() - c0)
                                              / (time.perf_counter() - t0)},
                                     note="driver CPU of an idle 2-worker cluster over 2 s"))
        log = tmp / "journal"
        per = []
        for i in range(200):
            t0 = time.perf_counter()
            append_lines(log, [f'{{"name": "x{i}", "status": "baked", "outputs": {{}}}}'])
            per.append(time.perf_counter() - t0)
        rows.append(make_row(SUITE, "journal_append", {"what": "overhead", "assets": 200},
                             Timing.from_seconds(per), note="per result (fsync)"))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return rows
