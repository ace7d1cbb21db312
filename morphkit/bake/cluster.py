"""Where bake tasks run: a Dask client on a local cluster of worker processes, or on a scheduler.

* Default: :class:`distributed.LocalCluster` with ``workers`` worker
  *processes* (one thread each, so one GL context each: OSMesa and numpy's
  GIL-bound work scale with processes, not threads); ``workers`` defaults to
  the CPUs this process may use.
* ``scheduler="tcp://host:port"``: a :class:`distributed.Client` on an
  existing Dask scheduler; the same tasks are submitted. Start one with
  ``dask scheduler`` and, on each machine, ``dask worker tcp://host:8786
  --nthreads 1 --nworkers N`` (the same morphkit installed on the scheduler and
  the workers: the scheduler unpickles the tasks; input and output paths must be
  the same on every machine, e.g. a shared file system). A malformed address is
  a :class:`~morphkit.errors.ValidationError` (:func:`scheduler_address`); an
  address that does not answer within :data:`CONNECT_TIMEOUT_S`, or a
  scheduler without any worker after that long, is a
  :class:`~morphkit.errors.ClusterError` (no hang).

Local workers are configured for bakes (:data:`LOCAL_WORKER_CONFIG`):

* they keep glibc's own memory management: Dask starts worker processes with
  ``MALLOC_TRIM_THRESHOLD_=65536`` (to hand freed memory back to the system
  early), which also switches off glibc's dynamic mmap threshold, so every large
  temporary numpy array of a bake costs fresh page faults; a worker then bakes
  markedly slower than the same loop in the parent process, and as fast without
  it (figures: ``docs/results/bake.md``);
* Dask's statistical profiler of the worker threads (for its dashboard, which a
  bake does not show) is off: it samples the task's thread every 10 ms, which
  costs the task CPU;
* they never take SIGINT (it stays blocked in them, ``_sigint_held``): a Ctrl-C at the terminal
  stops the run, which cancels the tasks and closes the cluster, instead of each worker printing
  its ``KeyboardInterrupt`` traceback;
* Dask's own log lines, the workers' too, print only when critical: a bake reports a failed asset
  itself (the manifest, one line on stderr), and what Dask logs as an error while a stopped run
  closes the cluster (a worker's heartbeat to the scheduler that is going away) is no failure.

For your own cluster, start workers with
``DASK_DISTRIBUTED__NANNY__PRE_SPAWN_ENVIRON='{"MALLOC_TRIM_THRESHOLD_": None}'``
and ``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False`` (or the same keys in
a Dask config file).
"""

from __future__ import annotations

import logging
import os
import signal
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from ..errors import ClusterError, ValidationError, expected_got
from ..files.fileio import quiet_stderr

__all__ = ["CONNECT_TIMEOUT_S", "LOCAL_WORKER_CONFIG", "default_workers", "open_client", "check_scheduler",
           "scheduler_address"]

#: Seconds to wait for a scheduler to answer, and then for its first worker.
CONNECT_TIMEOUT_S = 5.0


#: Dask configuration of the local cluster's worker processes (see the module docstring).
LOCAL_WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                       "distributed.worker.profile.enabled": False}


def default_workers() -> int:
    """The CPUs this process may use (the default number of local worker processes).

    Returns
    -------
    int
        The CPUs in this process's affinity mask where the platform has one, else
        ``os.cpu_count()`` (at least 1).
    """
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


@contextmanager
def open_client(*, workers: int | None = None, scheduler: str | None = None,
                timeout: float | None = None) -> Iterator[object]:
    """A :class:`distributed.Client`, closed (with its local cluster) on exit.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (default :func:`default_workers`); not with ``scheduler``.
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float, optional
        Seconds to wait for the scheduler, then for at least one worker
        (default :data:`CONNECT_TIMEOUT_S`, read at call time).

    Raises
    ------
    ValidationError
        Both ``workers`` and ``scheduler``, or ``workers < 1``.
    ClusterError
        The scheduler does not answer, or has no worker, within ``timeout``.
    """
    from distributed import Client, LocalCluster

    if workers is not None and scheduler is not None:
        raise ValidationError(expected_got("workers and scheduler", "one of them", "both"))
    timeout = CONNECT_TIMEOUT_S if timeout is None else float(timeout)
    if scheduler is not None:
        scheduler = check_scheduler(scheduler, timeout)
        try:
            client = Client(scheduler, timeout=timeout, set_as_default=False)
        except (OSError, ValueError, TypeError) as exc:  # TimeoutError is an OSError
            raise ClusterError(expected_got("Dask scheduler", f"one answering at {scheduler!r} within "
                                            f"{timeout:g} s", f"{type(exc).__name__}: {exc}")) from exc
        try:
            try:
                client.wait_for_workers(1, timeout=timeout)
            except (TimeoutError, OSError) as exc:
                raise ClusterError(expected_got(f"Dask scheduler {scheduler!r}", "at least one worker "
                                                f"within {timeout:g} s", "none")) from exc
            yield client
        finally:
            client.close()
        return
    n = default_workers() if workers is None else workers
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValidationError(expected_got("workers", "an integer >= 1", repr(workers)))
    import dask

    with _quiet_logs(), dask.config.set(LOCAL_WORKER_CONFIG), _sigint_held() as release:
        # the cluster's threads, and the workers they start, never take Ctrl-C (_sigint_held); the
        # scheduler's HTTP server always starts: a free port on localhost (8787 may be taken)
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address="127.0.0.1:0", silence_logs=logging.CRITICAL)
        try:
            release()  # a Ctrl-C that came meanwhile is raised here: the cluster is closed below
            client = Client(cluster, set_as_default=False)
            try:
                yield client
            finally:
                client.close()
        finally:
            cluster.close()


def scheduler_address(address: str) -> str:
    """``address`` as a Dask scheduler's address, checked for its form only (nothing is asked).

    Only ``tcp://host:port`` or ``host:port`` (port 1..65535), and ``inproc://`` of a
    scheduler in this process, are taken.

    Parameters
    ----------
    address : str
        The scheduler's address.

    Returns
    -------
    str
        The address as given (stripped).

    Raises
    ------
    ValidationError
        A malformed or unsupported address (a bad value: the command line's usage error).
    """
    from distributed.comm import parse_address, parse_host_port

    text = str(address).strip()
    expected = "tcp://HOST:PORT (PORT 1..65535) of a running Dask scheduler"
    try:
        scheme, loc = parse_address(text)
        if scheme == "inproc":  # a scheduler in this process (tests, notebooks): nothing to ask
            return text
        host, port = parse_host_port(loc)
        ok = scheme == "tcp" and host != "" and 1 <= int(port) <= 65535
    except (ValueError, TypeError):
        ok = False
    if not ok:
        raise ValidationError(expected_got("Dask scheduler address", expected, repr(address)))
    return text


def check_scheduler(address: str, timeout: float | None = None) -> str:
    """Refuse, within ``timeout`` seconds, an address that is not a Dask scheduler's.

    A malformed or unsupported address (:func:`scheduler_address`) is refused at once;
    otherwise the address is asked who it is (Dask's ``identity`` message) and must answer
    as a scheduler within ``timeout`` (``inproc://`` addresses are taken as they are): a port
    that never answers, nothing listening, or another server (HTTP, ...) is refused, not waited
    on (Dask's own client may wait for such a server far longer than its timeout).

    Parameters
    ----------
    address : str
        The scheduler's address.
    timeout : float, optional
        Seconds to wait for the answer, in all (default :data:`CONNECT_TIMEOUT_S`, read at
        call time).

    Returns
    -------
    str
        The address as given (stripped).

    Raises
    ------
    ValidationError
        A malformed or unsupported address.
    ClusterError
        No scheduler answered there in time.
    """
    import asyncio

    from distributed.comm import connect, parse_address

    timeout = CONNECT_TIMEOUT_S if timeout is None else float(timeout)
    text = scheduler_address(address)
    if parse_address(text)[0] == "inproc":  # a scheduler in this process: nothing to ask
        return text

    async def identity() -> object:
        comm = await connect(text, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    try:
        reply = asyncio.run(asyncio.wait_for(identity(), timeout))
    except (OSError, ValueError, TypeError, asyncio.TimeoutError) as exc:  # a comm error is an OSError
        got = "no answer" if isinstance(exc, asyncio.TimeoutError) or not str(exc) else " ".join(
            f"{type(exc).__name__}: {exc}".split())
        raise ClusterError(expected_got("Dask scheduler", f"one answering at {text!r} within {timeout:g} s",
                                        got)) from exc
    except Exception as exc:  # a server that speaks something else: Dask fails to decode it
        raise ClusterError(expected_got("Dask scheduler", f"one answering at {text!r} within {timeout:g} s",
                                        f"{type(exc).__name__} (not a Dask scheduler)")) from exc
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else type(reply).__name__
        raise ClusterError(expected_got("Dask scheduler", f"one answering at {text!r} within {timeout:g} s",
                                        f"an answer from a {kind}, not a Dask scheduler"))
    return text


@contextmanager
def _sigint_held() -> Iterator[Callable[[], None]]:
    """SIGINT blocked in the calling thread until the block calls the function it is given, or ends
    (a Ctrl-C that came meanwhile is delivered then: ``KeyboardInterrupt`` there).

    A thread inherits the signal mask of the thread that starts it, and a process that of the thread
    that forks it, across ``exec`` too: the local cluster's event-loop thread, started while SIGINT is
    held, keeps it blocked, and so do the worker processes it spawns (restarted ones too). A Ctrl-C
    at the terminal, which signals the whole process group, reaches only this process then: the
    run stops and closes the cluster, and its workers print no ``KeyboardInterrupt`` traceback.
    """
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        yield lambda: None
        return
    from multiprocessing import resource_tracker

    # started first: starting it unblocks SIGINT in the thread that starts it; its stderr held back
    # (its only lines are a warning at exit about semaphores a closing cluster had not freed yet)
    with quiet_stderr():
        resource_tracker.ensure_running()
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})

    def release() -> None:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)

    try:
        yield release
    finally:
        release()


@contextmanager
def _quiet_logs() -> Iterator[None]:
    """Dask's INFO lines (workers starting and closing) off in this process (the local cluster shows
    only critical lines while it runs, module notes)."""
    logger = logging.getLogger("distributed")
    old = logger.level
    logger.setLevel(logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(old)
