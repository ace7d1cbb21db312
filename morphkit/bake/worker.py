"""The worker side of a bake: one task bakes one asset, in whatever process runs it.

A task (:class:`BakeTask`, plain picklable data) names the mesh file, the hash
the driver read, the output folder, the kinds to bake and the file's up axis
(resolved by the driver, :func:`morphkit.meshes.resolve_up`). :func:`bake_task`
re-hashes the file (a file changed since the driver read it is refused, so
the manifest's hash is the one baked), loads it once with
:func:`morphkit.meshes.load_mesh` turned ``+z`` up from that axis, bakes each
kind from it (passing the axis as ``source_up``) and saves each output
atomically (the kinds' ``save`` writes through :mod:`morphkit.files.fileio`), then
hashes what it wrote. A mesh that cannot be baked (a
:class:`~morphkit.errors.MorphkitError`: unreadable, empty, degenerate) gives a
result carrying the error message, which the driver records; so does an output
that cannot be written (an ``OSError``, with its ``errno``: the driver stops the
run when the output's file system is full or read-only); any other exception is
a bug and propagates through Dask (the driver records it too).

One GL context per worker thread: :func:`worker_renderer` creates a
:class:`~morphkit.render.Renderer` the first time a thread asks and reuses it
for every later task of that thread (a Dask worker started by ``morphkit
bake`` has one thread); they are closed when the process exits.
"""

from __future__ import annotations

import atexit
import dataclasses
import os
import socket
import threading
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from ..errors import AssetWarning, MeshError, MorphkitError, expected_got
from ..meshes import load_mesh
from ..protocols import SceneRenderer
from .kinds import AssetKind, output_name
from .manifest import OutputRecord, file_digest

__all__ = ["BakeTask", "TaskResult", "bake_task", "worker_renderer"]

_local = threading.local()
_opened: list[SceneRenderer] = []
_lock = threading.Lock()


def worker_renderer() -> SceneRenderer:
    """This thread's renderer, created on first use and kept until the process exits.

    Returns
    -------
    SceneRenderer
        A :class:`~morphkit.render.Renderer` owned by this thread (closed at process exit).
    """
    r = getattr(_local, "renderer", None)
    if r is None:
        from ..render import Renderer  # GL only where a task runs

        r = _local.renderer = Renderer()
        with _lock:
            if not _opened:
                atexit.register(_close_all)
            _opened.append(r)
    return r


def _close_all() -> None:
    with _lock:
        for r in _opened:
            r.close()  # type: ignore[attr-defined]
        _opened.clear()


@dataclass(frozen=True)
class BakeTask:
    """One asset to bake: ``<out_dir>/<name><kind.suffix>`` for each of ``kinds``.

    Parameters
    ----------
    name : str
        Asset name (POSIX relative path without the mesh suffix).
    input_path : str
        The mesh file, absolute path.
    input_sha256 : str
        Hex digest of the mesh file as the driver read it.
    input_bytes : int
        The mesh file's size as the driver read it.
    out_dir : str
        The output folder.
    kinds : tuple of AssetKind
        The kinds to bake.
    up_axis : {"z", "y"}
        The mesh file's up axis, resolved (:func:`morphkit.meshes.resolve_up`): the mesh is
        loaded turned ``+z`` up from it.
    """

    name: str
    input_path: str
    input_sha256: str
    input_bytes: int
    out_dir: str
    kinds: tuple[AssetKind, ...]
    up_axis: str


@dataclass(frozen=True)
class TaskResult:
    """What :func:`bake_task` made: one output record per kind, timings (s: ``load``, one per
    kind, ``total``, and ``cpu``, the worker process's CPU time during the task), who ran it;
    or, when the mesh could not be baked, ``error`` (and no outputs).

    Parameters
    ----------
    name : str
        Asset name.
    outputs : dict of str to OutputRecord
        One record per kind name (empty on error).
    timings_s : dict of str to float
        Seconds: ``load``, one per kind, ``total``, ``cpu``.
    worker : str
        ``host:pid`` of the process that ran the task.
    error : str, optional
        ``"<ErrorType>: <message>"`` when the mesh could not be baked, or an output not written.
    errno : int, optional
        The OS error number when an output could not be written (``errno.ENOSPC``: the disk is
        full, ``errno.EROFS``, ...); ``error`` names the file.
    warnings : tuple of str
        The messages of the :class:`~morphkit.errors.AssetWarning` s the task gave (a look's
        fallback: a texture that could not be drawn), in order, each once: the driver says
        them (a worker's own stderr would print them in Python's two-line form, far from the
        run's lines).
    """

    name: str
    outputs: dict[str, OutputRecord]
    timings_s: dict[str, float]
    worker: str
    error: str | None = None
    errno: int | None = None
    warnings: tuple[str, ...] = ()


def bake_task(task: BakeTask) -> TaskResult:
    """Bake one asset (see the module docstring).

    Parameters
    ----------
    task : BakeTask
        The asset, its input hash, the output folder and the kinds.

    Returns
    -------
    TaskResult
        The outputs and the look's warnings (:attr:`TaskResult.warnings`), or ``error``:
        ``"<ErrorType>: <message>"`` when the file is
        unreadable, empty or degenerate, changed since it was hashed, or a kind
        refused the mesh (any :class:`~morphkit.errors.MorphkitError`), or it needs more
        memory than the worker has (a ``MemoryError``); or when an
        output could not be written (an ``OSError``: a full disk, a read-only folder),
        with its ``errno``.
    """
    worker = f"{socket.gethostname()}:{os.getpid()}"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AssetWarning)
        try:
            result = _bake(task, worker)
        except MorphkitError as exc:
            result = TaskResult(task.name, {}, {}, worker, f"{type(exc).__name__}: {exc}")
        except MemoryError as exc:  # sizes past the worker's memory: this asset fails, not the run
            result = TaskResult(task.name, {}, {}, worker, f"MemoryError: {exc or 'an allocation failed'}")
    for w in caught:  # others as they would have been shown
        if not issubclass(w.category, AssetWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    said = tuple(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, AssetWarning)))
    return dataclasses.replace(result, warnings=said) if said else result


def _bake(task: BakeTask, worker: str) -> TaskResult:
    t0 = time.perf_counter()
    c0 = time.process_time()
    digest, _ = file_digest(task.input_path)
    if digest != task.input_sha256:
        raise MeshError(expected_got(f"mesh file {task.input_path!r}",
                                     f"the content hashed before the bake (sha256 {task.input_sha256[:12]})",
                                     f"sha256 {digest[:12]} (changed while baking)"))
    mesh = load_mesh(task.input_path, up=task.up_axis)
    timings = {"load": time.perf_counter() - t0}
    renderer = worker_renderer()
    outputs = {}
    for kind in task.kinds:
        t = time.perf_counter()
        rel = output_name(task.name, kind)
        target = Path(task.out_dir) / rel
        baked = kind.bake(mesh, renderer, task.up_axis)
        try:  # the saves write atomically: a failed one leaves no file
            target.parent.mkdir(parents=True, exist_ok=True)
            baked.save(target)
            sha, nbytes = file_digest(target)
        except OSError as exc:  # the output folder's file system: the driver decides (it may stop)
            return TaskResult(task.name, {}, {}, worker, f"{type(exc).__name__}: cannot write {rel}: "
                              f"{exc.strerror or exc}", errno=exc.errno)
        dt = time.perf_counter() - t
        outputs[kind.name] = OutputRecord(rel, sha, nbytes, kind.version, kind.options(), dt)
        timings[kind.name] = dt
    timings["total"] = time.perf_counter() - t0
    timings["cpu"] = time.process_time() - c0  # this worker process's CPU meanwhile, all threads
    return TaskResult(task.name, outputs, timings, worker)
