"""``morphkit bench bake``: throughput of the bake pipeline (Dask) against a plain serial loop.

Library (generated, stated once): 16 meshes of mixed size written to a temporary
folder -- the cow-like mesh at 4k..100k faces (``.ply``), the teapot at
resolutions 4..24 (1k..37k faces, ``.obj``), the chair with 2..5 slats
(``.ply``); each baked into one 512 x 512, 3 x 3 shadow atlas (the
:class:`~morphkit.bake.ShadowAtlasKind` defaults). ``--quick``: 8 of them at 256 x 256.

Rows (``what``):

* ``library``: the whole library, timed in the same run and interleaved:
  ``serial`` -- a plain loop in this process (``load_mesh``, ``bake_atlas``,
  ``save``; one renderer created beforehand), the loop a user writes by hand;
  ``dask_1`` / ``dask_2`` -- :func:`~morphkit.bake.bake_library` on a local
  cluster of 1 / 2 worker processes (:func:`~morphkit.bake.open_client`, as
  ``morphkit bake`` starts it) started beforehand (start-up timed apart,
  workers warmed: imports and GL context), into a fresh output folder each time
  (everything baked: input hashing, manifest journal and commits included);
  ``dask_1_malloc_trim`` -- ``dask_1`` on a cluster with Dask's default worker
  setting ``MALLOC_TRIM_THRESHOLD_=65536``, which ``morphkit bake`` drops
  (:data:`morphkit.bake.cluster.LOCAL_WORKER_CONFIG`).
  Metrics: ``assets_per_min`` and ``speedup`` over ``serial`` (best of the
  repeats: the machine is shared), ``driver_cpu_s``: CPU time of this process
  during the run (the serial loop itself; for Dask the driver and the local
  cluster's scheduler, which share the machine with the workers).
* ``startup``: starting (and closing) a local cluster of 1 / 2 workers, once each.
* ``rerun``: ``bake_library`` again on a complete output folder, nothing changed
  (every input and output hashed, no cluster started); metric
  ``fraction_of_first`` = its time over the ``dask_2`` run's (start-up excluded)
  and ``fraction_of_first_with_startup``.
* ``overhead``: ``noop_task`` -- the scheduler's cost per task, measured with
  trivial tasks through the same 2-worker client (``client.map`` of 400 no-ops,
  wall time / 400: submission, scheduling, transfer and result of each task);
  ``journal_append`` -- the driver's fsync-ed manifest journal line per result.

The projection for a larger cluster from these figures is in ``docs/RESULTS.md``.
"""

from __future__ import annotations

import logging
import shutil
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from ..bake import BakeOptions, ShadowAtlasKind, bake_library, find_inputs, open_client, worker_renderer
from ..fileio import append_line
from ..meshes import chair, cow, load_mesh, teapot
from .harness import Timing, make_row

SUITE = "bake"
FLOOR_METHOD = "serial"
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
    """Write the benchmark's meshes into ``folder``; return their paths."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, arg, suffix in LIBRARY[::2] if quick else LIBRARY:
        p = folder / f"{name}_{arg}{suffix}"
        _BUILD[name](arg).export(p)
        paths.append(p)
    return paths


def warm_worker() -> int:
    """Run on every worker before timing: imports, the GL context, one tiny bake (numba caches)."""
    import os

    import numpy as np

    from ..scene import PointLight
    from ..shadow import MotionRange, bake_atlas

    bake_atlas(teapot(4), np.eye(4), MotionRange([-0.5, -0.5], [0.5, 0.5]), PointLight([0, 0, 2.0]),
               (32, 32), renderer=worker_renderer(), progress=False)
    return os.getpid()


def noop(i: int) -> int:
    """A trivial task: the scheduler's overhead alone."""
    return i


def _serial(paths: list[Path], kind: ShadowAtlasKind, out: Path) -> None:
    out.mkdir(parents=True)
    renderer = worker_renderer()
    for p in paths:
        kind.bake(load_mesh(p), renderer).save(out / f"{p.stem}{kind.suffix}")


def run(*, quick: bool = False) -> list[dict[str, Any]]:
    from distributed import Client, LocalCluster

    kind = ShadowAtlasKind(atlas_size=256 if quick else 512)
    options = BakeOptions((kind,))
    repeats = 1 if quick else 3
    rows: list[dict[str, Any]] = []
    tmp = Path(tempfile.mkdtemp(prefix="morphkit-bench-bake-"))
    try:
        paths = write_library(tmp / "lib", quick)
        n = len(find_inputs([tmp / "lib"]))
        case = {"what": "library", "assets": n, "atlas": kind.atlas_size}
        warm_worker()  # this process too: the serial loop's renderer and caches
        stack = ExitStack()
        clients: dict[int, Any] = {}
        startup: dict[int, float] = {}
        try:
            for w in (1, 2):
                t0 = time.perf_counter()
                clients[w] = stack.enter_context(open_client(workers=w))
                clients[w].wait_for_workers(w)
                startup[w] = time.perf_counter() - t0
                clients[w].run(warm_worker)
            address = {w: c.scheduler.address for w, c in clients.items()}
            # the same 1-worker cluster with Dask's default worker memory settings
            dask_default = stack.enter_context(LocalCluster(
                n_workers=1, threads_per_worker=1, processes=True, dashboard_address="127.0.0.1:0",
                silence_logs=logging.ERROR))
            with Client(dask_default, set_as_default=False) as c:
                c.run(warm_worker)
            address[0] = dask_default.scheduler_address
            samples: dict[str, list[float]] = {"serial": [], "dask_1": [], "dask_2": [],
                                               "dask_1_malloc_trim": []}
            cpu: dict[str, list[float]] = {k: [] for k in samples}
            first_out = None
            for r in range(repeats):
                for method in samples:
                    out = tmp / f"out_{method}_{r}"
                    c0 = time.process_time()
                    t0 = time.perf_counter()
                    if method == "serial":
                        _serial(paths, kind, out)
                    else:
                        w = 0 if method.endswith("trim") else int(method[-1])
                        m = bake_library([tmp / "lib"], out, options=options,
                                         scheduler=address[w], progress=False)
                        if m.run["failed"]:
                            raise RuntimeError(f"bench bake failed: {m.failed()}")
                        if w == 2:
                            first_out = out
                    samples[method].append(time.perf_counter() - t0)
                    cpu[method].append(time.process_time() - c0)
                    if out != first_out:
                        shutil.rmtree(out)
            serial_s = min(samples["serial"])
            for method, s in samples.items():
                t = Timing.from_seconds(s)
                best = min(s)
                rows.append(make_row(SUITE, method, case, t, metrics={
                    "assets_per_min": 60.0 * n / best, "speedup": serial_s / best,
                    "driver_cpu_s": min(cpu[method])},
                    note="best of repeats for the metrics" if len(s) > 1 else ""))
            for w, s in startup.items():
                rows.append(make_row(SUITE, f"start_{w}_workers", {"what": "startup", "assets": n},
                                     Timing.from_seconds([s])))

            # rerun with nothing changed, on the last dask_2 output
            rerun = []
            for _ in range(repeats):
                t0 = time.perf_counter()
                m = bake_library([tmp / "lib"], first_out, options=options, progress=False)
                rerun.append(time.perf_counter() - t0)
                if m.run["skipped"] != n:
                    raise RuntimeError(f"bench bake: rerun baked again: {m.run}")
            first = min(samples["dask_2"])
            rows.append(make_row(SUITE, "rerun", {"what": "rerun", "assets": n}, Timing.from_seconds(rerun),
                                 metrics={"fraction_of_first": min(rerun) / first,
                                          "fraction_of_first_with_startup":
                                              min(rerun) / (first + startup[2])}))

            # the scheduler's overhead per task, and the driver's journal line per result
            k = 400
            c = clients[2]
            c.gather(c.map(noop, range(50), pure=False))  # warm
            per = []
            for _ in range(3):
                t0 = time.perf_counter()
                c.gather(c.map(noop, range(k), pure=False))
                per.append((time.perf_counter() - t0) / k)
            rows.append(make_row(SUITE, "noop_task", {"what": "overhead", "assets": k},
                                 Timing.from_seconds(per), note="per task, 2 workers"))
            log = tmp / "journal"
            per = []
            for i in range(200):
                t0 = time.perf_counter()
                append_line(log, f'{{"name": "x{i}", "status": "baked", "outputs": {{}}}}')
                per.append(time.perf_counter() - t0)
            rows.append(make_row(SUITE, "journal_append", {"what": "overhead", "assets": 200},
                                 Timing.from_seconds(per), note="per result (fsync)"))
        finally:
            stack.close()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return rows
