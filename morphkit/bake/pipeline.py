"""``bake_library``: bake every mesh of a library into an output folder, on Dask.

The driver (this module) finds the mesh files (:mod:`.inputs`), checks the
output folder is writable before any work, reads the manifest (:mod:`.manifest`),
hashes every input and keeps each asset whose outputs are up to date. The rest
become one task per asset (:func:`.worker.bake_task`), submitted largest input
first (so the run does not end on one long task) to a Dask client
(:mod:`.cluster`: local worker processes, or an existing scheduler). As
results arrive (``as_completed``, in the batches that arrive together) each is
journaled at once, so a crash loses no finished asset; the manifest is rewritten
atomically every :data:`COMMIT_INTERVAL_S` (longer for a huge manifest) and at
the end. A task that raises (an unreadable,
empty or degenerate mesh) or whose worker died more often than Dask allows
(``distributed.scheduler.allowed-failures``, counted against every task the
worker held, running or queued; a worker killed once is replaced and its tasks
re-run) is recorded as failed with its error; the others go on. A write the output
folder's file system refuses (full, read-only: :data:`STOP_ERRNOS`), by a worker
or by the driver's journal, stops the run at once with one
:class:`~morphkit.errors.OutputWriteError` naming the file system: every later
write would fail too. What was journaled is kept; a rerun bakes the rest.
"""

from __future__ import annotations

import errno
import os
import shutil
import stat
import time
import uuid
import warnings
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import AssetWarning, OutputWriteError, ValidationError, expected_got
from ..files.outfolder import BAKE_OUTPUT, claim_output
from ..meshes import UP_AXES, resolve_up
from ..validate import as_int
from .cluster import check_scheduler, open_client
from .inputs import AssetInput, find_inputs
from .kinds import AssetKind, ShadowAtlasKind
from .manifest import LEGACY_UP_AXIS, AssetRecord, Manifest, file_digest, utc_now
from .worker import BakeTask, bake_task

__all__ = ["BakeOptions", "bake_library", "COMMIT_INTERVAL_S", "HASH_THREADS", "STOP_ERRNOS", "STOP_WAIT_S"]

#: Seconds between atomic rewrites of the manifest during a run (the journal holds the rest);
#: longer for a manifest so large that rewriting it would take over 5% of the time.
COMMIT_INTERVAL_S = 2.0

#: Threads hashing inputs and existing outputs before a run.
HASH_THREADS = 8

#: OS errors of a write into the output folder that stop the run (``errno`` numbers): its file
#: system is full (or over quota), read-only, refuses permission or fails, so every later
#: write would be refused too. The run raises :class:`~morphkit.errors.OutputWriteError`;
#: another OS error fails its asset only (e.g. a name too long for the file system).
STOP_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM, errno.EIO})

#: Seconds a stopped run waits for the tasks its workers are still executing: Dask cancels the
#: tasks not started, but one running cannot be interrupted, and it would finish its save (or
#: remove its temporary file) after the run had reported; past this the run reports anyway.
STOP_WAIT_S = 60.0


@dataclass(frozen=True)
class BakeOptions:
    """What to bake of every asset: one or more kinds (:class:`~morphkit.bake.kinds.AssetKind`).

    Parameters
    ----------
    kinds : tuple of AssetKind
        Distinct names and suffixes; default: one :class:`~morphkit.bake.kinds.ShadowAtlasKind`.
    up : {"auto", "z", "y"}
        The mesh files' up axis (``morphkit bake --up-axis``): ``"auto"`` is each format's default
        (:func:`morphkit.meshes.resolve_up`: glTF/GLB and OBJ ``+y``, every other format ``+z``).
        Every kind bakes the mesh turned ``+z`` up from it; the axis used is recorded per asset
        in the manifest and is part of what decides whether an asset is up to date.
    """

    kinds: tuple[AssetKind, ...] = field(default_factory=lambda: (ShadowAtlasKind(),))
    up: str = "auto"

    def __post_init__(self) -> None:
        kinds = tuple(self.kinds)
        if not kinds:
            raise ValidationError(expected_got("bake kinds", "at least one", "none"))
        for k in kinds:
            if not isinstance(k, AssetKind):
                raise ValidationError(expected_got("bake kind", "an AssetKind (name, suffix, version, "
                                                   "options(), bake())", type(k).__name__))
        for attr in ("name", "suffix"):
            values = [getattr(k, attr) for k in kinds]
            if len(set(values)) != len(values):
                raise ValidationError(expected_got(f"bake kind {attr}s", "distinct", values))
        object.__setattr__(self, "kinds", kinds)
        if not isinstance(self.up, str) or self.up.lower() not in ("auto", *UP_AXES):
            raise ValidationError(expected_got("bake up axis", "'auto', " + " or ".join(map(repr, UP_AXES))
                                               + " (morphkit's world is +z up)", repr(self.up)))
        object.__setattr__(self, "up", self.up.lower())

    def as_dict(self) -> dict[str, dict]:
        """``{kind name: options}``.

        Returns
        -------
        dict of str to dict
            Each kind's ``options()`` by its ``name``.
        """
        return {k.name: k.options() for k in self.kinds}


def bake_library(inputs: Sequence[str | os.PathLike[str]] | str | os.PathLike[str],
                 out: str | os.PathLike[str], *, options: BakeOptions | None = None,
                 workers: int | None = None, scheduler: str | None = None,
                 progress: bool = True) -> Manifest:
    """Bake every mesh of ``inputs`` into ``out``, skipping what is up to date.

    Parameters
    ----------
    inputs : path-like or sequence of path-like
        Mesh files (any format trimesh loads) and folders (searched recursively;
        :func:`~morphkit.bake.inputs.find_inputs` names the assets).
    out : path-like
        Output folder (created): ``<name><suffix>`` per asset and kind, and
        ``manifest.json``.
    options : BakeOptions, optional
        The kinds to bake (default: the shadow atlas with its defaults).
    workers : int, optional
        Local worker processes (default: the CPU count). Not with ``scheduler``.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:port``).
    progress : bool
        A progress bar over the assets on a terminal (tqdm, on stderr).

    Returns
    -------
    Manifest
        Also written to ``out/manifest.json``; ``manifest.run`` has the counts
        of this run and ``manifest.failed()`` the errors.

    Raises
    ------
    MeshError
        An input is missing, or no mesh file was found.
    ValidationError
        The output folder is not writable, two inputs share an asset name,
        both ``workers`` and ``scheduler`` are given, or ``scheduler`` is malformed (all
        before any work).
    OutputExistsError
        ``out`` holds files and is not a bake's output folder (:mod:`morphkit.files.outfolder`).
    OutputBusyError
        Another bake is writing into ``out`` (it holds the folder's lock).
    ClusterError
        ``scheduler`` does not answer as a Dask scheduler within
        :data:`~morphkit.bake.cluster.CONNECT_TIMEOUT_S`, or has no worker.
    FileFormatError
        ``out`` holds a manifest that is not one.
    OutputWriteError
        ``out``'s file system refused a write mid-run (:data:`STOP_ERRNOS`: full, read-only, ...):
        the run stopped; what it baked is kept (journaled), a rerun bakes the rest.
    """
    options = BakeOptions() if options is None else options
    if not isinstance(options, BakeOptions):
        raise ValidationError(expected_got("options", "a BakeOptions", type(options).__name__))
    if workers is not None and scheduler is not None:
        raise ValidationError(expected_got("workers and scheduler", "one of them", "both"))
    if workers is not None:
        workers = as_int(workers, "workers", lo=1)
    t_start = time.perf_counter()
    started = utc_now()
    assets = find_inputs(inputs)
    claim = claim_output(out, BAKE_OUTPUT)  # new, empty or a bake (resumed); foreign files refused
    if scheduler is not None:  # a malformed address or no scheduler there: refused before any work
        scheduler = check_scheduler(scheduler)
    with claim.writing() as folder:  # locked: a second bake into the same folder is refused
        return _bake_into(folder, assets, options, workers, scheduler, progress, t_start, started)


def _bake_into(folder: Path, assets: list[AssetInput], options: BakeOptions, workers: int | None,
               scheduler: str | None, progress: bool, t_start: float, started: str) -> Manifest:
    """The body of :func:`bake_library` once its output folder is claimed and locked."""
    from distributed import as_completed
    from tqdm import tqdm

    manifest = Manifest.open(folder)
    manifest.options = options.as_dict()

    def plan(a: AssetInput) -> tuple[AssetInput, str, int, str, tuple[AssetKind, ...] | OSError]:
        try:
            sha, size = _regular_file_digest(a.path)
        except OSError as exc:  # a broken link, a FIFO, an unreadable file: this asset fails, not the run
            return a, "", 0, "", exc
        up = resolve_up(a.path, options.up)
        return a, sha, size, up, tuple(k for k in options.kinds
                                       if not manifest.up_to_date(a.name, sha, k, up_axis=up))

    tasks: list[BakeTask] = []
    # hashing reads every input and every existing output: threads (hashlib releases the GIL)
    with ThreadPoolExecutor(max_workers=HASH_THREADS) as pool:
        for a, sha, size, up, stale in pool.map(plan, assets):
            if isinstance(stale, OSError):
                manifest.record(_unreadable_record(manifest, a, stale))
            elif stale:
                tasks.append(BakeTask(a.name, str(a.path), sha, size, str(folder), stale, up))
            else:
                manifest.mark_skipped(a.name, str(a.path), up_axis=up)
    # largest inputs first: a long task started last would leave the other workers idle at the end
    tasks.sort(key=lambda t: -t.input_bytes)
    names = [a.name for a in assets]
    n_skipped = len(assets) - len(tasks)
    bar = tqdm(total=len(assets), initial=n_skipped, unit="asset", desc="morphkit bake",
               disable=None if progress else True, dynamic_ncols=True)
    n_workers = 0
    stop: tuple[int, str] | None = None  # a write the output's file system refused: (errno, what)
    n_kept = 0  # assets baked and journaled by this run
    said: list[str] = []  # the tasks' AssetWarnings (TaskResult.warnings), said when the bar is done
    try:
        if tasks:
            with open_client(workers=workers, scheduler=scheduler) as client:
                n_workers = len(client.scheduler_info(n_workers=-1)["workers"])
                token = uuid.uuid4().hex[:8]
                # keys travel as UTF-8 (msgpack): a file name that is not UTF-8 (surrogate escapes)
                # would cancel the whole run; the name in the key is only for Dask's dashboard
                futures = {client.submit(bake_task, t, key=f"morphkit-bake-{token}-{i}-{_key_safe(t.name)}",
                                         pure=False): t for i, t in enumerate(tasks)}
                last_commit, commit_s = time.perf_counter(), 0.0
                n_failed = 0
                try:
                    for batch in as_completed(list(futures), loop=client.loop).batches():
                        done = [(futures.pop(fut), fut) for fut in batch]
                        recs = [_record(manifest, task, fut) for task, fut in done]
                        said += [w for _t, fut in done if fut.status == "finished"
                                 for w in fut.result().warnings]
                        stop = next(filter(None, (_refused_write(task, fut) for task, fut in done)), None)
                        for fut in batch:
                            fut.release()
                        try:
                            manifest.record(*recs)  # the results that arrived together: one disk sync
                            n_kept += sum(r.status == "baked" for r in recs)
                            # rewrite the manifest every COMMIT_INTERVAL_S, and no more than 5% of the time
                            due = time.perf_counter() - last_commit > max(COMMIT_INTERVAL_S, 20 * commit_s)
                            if due and not stop:
                                t0 = time.perf_counter()
                                manifest.commit()
                                last_commit = time.perf_counter()
                                commit_s = last_commit - t0
                        except OSError as exc:  # the journal or the manifest (atomic: the old one stays)
                            stop = stop or (exc.errno or errno.EIO, "the manifest")
                        n_failed += sum(r.status == "failed" for r in recs)
                        bar.update(len(recs))
                        if n_failed:
                            bar.set_postfix(failed=n_failed, refresh=False)
                        if stop:  # every later write would be refused too: stop here, keep what is done
                            client.cancel(list(futures))
                            _wait_executing(client, f"morphkit-bake-{token}-", STOP_WAIT_S)
                            break
                except KeyboardInterrupt:  # Ctrl-C: no task starts after it (the cluster closes next)
                    client.cancel(list(futures))
                    raise
    finally:
        bar.close()
        for message in dict.fromkeys(said):  # the workers' look fallbacks, after the bar, each once
            warnings.warn(message, AssetWarning, stacklevel=2)
    if stop:
        with suppress(OSError):  # what did not reach the journal, if there is room now
            manifest.commit()
        raise _stopped(folder, *stop, n_kept, len(tasks) - n_kept)
    counts = manifest.counts(names)
    manifest.run = {"started": started, "wall_s": round(time.perf_counter() - t_start, 3),
                    "workers": n_workers if tasks else 0,
                    "scheduler": scheduler or ("local" if tasks else None), "up": options.up,
                    "assets": len(assets), **counts}
    try:
        manifest.commit()
    except OSError as exc:  # atomic: the old manifest and the journal stay
        raise _stopped(folder, exc.errno or errno.EIO, "the manifest", n_kept, len(tasks) - n_kept) from exc
    return manifest


def _executing(prefix: str, dask_worker: Any = None) -> list[str]:
    """The keys starting with ``prefix`` that a worker is still executing, cancelled ones included
    (run on each worker by ``Client.run``, which passes ``dask_worker``)."""
    ws = dask_worker.state
    return [str(ts.key) for ts in ws.executing | ws.long_running if str(ts.key).startswith(prefix)]


def _wait_executing(client: Any, prefix: str, timeout: float) -> None:
    """Return once no worker executes a task whose key starts with ``prefix`` (:data:`STOP_WAIT_S`),
    or after ``timeout`` seconds, or when the workers cannot be asked."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            left = client.run(_executing, prefix)
        except Exception:  # noqa: BLE001 - a worker gone: nothing of it left to wait for
            return
        if not any(left.values()):
            return
        time.sleep(0.05)


def _refused_write(task: BakeTask, fut: object) -> tuple[int, str] | None:
    """``(errno, what)`` when ``fut``'s task could not write its output because the output's file
    system refuses writes (:data:`STOP_ERRNOS`), else None."""
    if fut.cancelled() or fut.exception() is not None:  # type: ignore[attr-defined]
        return None
    err = fut.result().errno  # type: ignore[attr-defined]
    return (err, f"the output of {task.name!r}") if err in STOP_ERRNOS else None


def _mount_point(path: Path) -> Path:
    """The mount point of the file system holding ``path`` (the topmost parent on its device)."""
    try:
        dev = path.stat().st_dev
        while path.parent != path and path.parent.stat().st_dev == dev:
            path = path.parent
    except OSError:
        pass
    return path


def _stopped(folder: Path, err: int, what: str, n_kept: int, n_left: int) -> OutputWriteError:
    """The one-line error of a run stopped by a write its output's file system refused.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder.
    err : int
        The refused write's errno.
    what : str
        What was being written.
    n_kept : int
        Assets this run baked and journaled (kept).
    n_left : int
        Assets this run was to bake and did not.

    Returns
    -------
    OutputWriteError
        Naming the error, the file system (its mount point and free bytes) and what to do.
    """
    try:
        free = f"{shutil.disk_usage(folder).free} bytes free"
    except OSError:
        free = "free space unknown"
    code = errno.errorcode.get(err, f"errno {err}")
    return OutputWriteError(expected_got(
        f"bake output folder {str(folder)!r}", "a file system that takes every output",
        f"{code} ({os.strerror(err)}) writing {what}, on the file system mounted at {_mount_point(folder)} "
        f"({free}); the bake stopped: {n_kept} asset{'s' if n_kept != 1 else ''} baked and kept, {n_left} "
        "not baked (free space or make the folder writable, then run the bake again)"), err)


def _key_safe(name: str) -> str:
    """``name`` with each byte that is not UTF-8 (a surrogate escape) as U+FFFD."""
    return name.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def _regular_file_digest(path: Path) -> tuple[str, int]:
    """:func:`~.manifest.file_digest` of a regular file; anything else is refused unopened.

    Parameters
    ----------
    path : pathlib.Path
        An input mesh file.

    Returns
    -------
    tuple of (str, int)
        The sha256 hex digest and the size in bytes.

    Raises
    ------
    OSError
        ``path`` is a broken link, a link loop, a FIFO (opening it would wait for a writer
        forever), a device or socket, or cannot be read.
    """
    st = os.stat(path)  # follows links: a broken one or a loop raises here
    if not stat.S_ISREG(st.st_mode):
        raise OSError(errno.EINVAL, "not a regular file (a FIFO, device or socket)", str(path))
    return file_digest(path)


def _unreadable_record(manifest: Manifest, a: AssetInput, exc: OSError) -> AssetRecord:
    """The failed record of an asset whose input cannot be read (its old outputs are kept).

    Parameters
    ----------
    manifest : Manifest
        The output folder's manifest.
    a : AssetInput
        The asset.
    exc : OSError
        Why its input cannot be read.

    Returns
    -------
    AssetRecord
        Status ``failed``, the reason in ``error`` (one line).
    """
    old = manifest.assets.get(a.name)
    why = exc.strerror or str(exc)
    return AssetRecord(name=a.name, input=str(a.path), input_sha256="", input_bytes=0, status="failed",
                       error=f"{type(exc).__name__}: cannot read the input: {why}",
                       outputs={} if old is None else dict(old.outputs))


def _record(manifest: Manifest, task: BakeTask, fut: object) -> AssetRecord:
    """The manifest record of a finished future: its outputs, or its error."""
    old = manifest.assets.get(task.name)
    # outputs of other kinds are kept only when baked from the same file turned the same way
    same = (old is not None and old.input_sha256 == task.input_sha256
            and (old.up_axis or LEGACY_UP_AXIS) == task.up_axis)
    keep = dict(old.outputs) if same else {}
    base = {"name": task.name, "input": task.input_path, "input_sha256": task.input_sha256,
            "input_bytes": task.input_bytes, "up_axis": task.up_axis}
    res = None
    if fut.cancelled():  # type: ignore[attr-defined]
        error = "the task was cancelled (the scheduler or its workers went away); a rerun bakes it"
    elif (exc := fut.exception()) is not None:  # type: ignore[attr-defined]
        error = _describe(exc)
    else:
        res = fut.result()  # type: ignore[attr-defined]
        error = res.error
    if error is not None:
        for k in task.kinds:
            keep.pop(k.name, None)
        return AssetRecord(**base, status="failed", error=error, outputs=keep,
                           worker=None if res is None else res.worker)
    keep.update(res.outputs)
    return AssetRecord(**base, status="baked", outputs=keep,
                       timings_s={k: round(v, 4) for k, v in res.timings_s.items()}, worker=res.worker)


def _describe(exc: BaseException) -> str:
    from distributed import KilledWorker

    if isinstance(exc, KilledWorker):
        # Dask counts a death against every task the worker held: the one it ran and those queued
        # on it; its own message (a long paragraph) says "died while running it" of both
        n = exc.allowed_failures + 1
        last = getattr(exc.last_worker, "address", exc.last_worker)
        text = (f"KilledWorker: the worker process holding this task (baking it, or with it queued) died "
                f"{n} time{'s' if n > 1 else ''}, more than Dask allows "
                f"(distributed.scheduler.allowed-failures = {n - 1}; last worker {last}); a rerun bakes it")
    else:
        text = f"{type(exc).__name__}: {exc}"
    return " ".join(text.split())  # one line (Dask's messages span several)


