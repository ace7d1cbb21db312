"""How a command-line run stops on a signal: Ctrl-C (SIGINT) and SIGTERM unwind it alike.

:func:`stop_signals` raises ``KeyboardInterrupt`` for SIGINT and
:class:`~morphkit.errors.Terminated` (a ``KeyboardInterrupt``) for SIGTERM while a command runs, so
every cleanup path of the run (atomic writes, an output folder's claim, a bake's cluster) is taken
for both; :func:`report_stop` prints the run's one line and gives its exit code (128 + the signal's
number). :func:`morphkit.cli.main` uses both.
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from ..errors import Terminated

__all__ = ["STOP_LINES", "Stop", "report_stop", "stop_signals"]

#: The line and exit code of a run a signal stopped (:func:`report_stop`): 128 + the signal's number.
STOP_LINES = {signal.SIGINT: ("morphkit: interrupted", 130), signal.SIGTERM: ("morphkit: terminated", 143)}


def report_stop(signum: int) -> int:
    """Print the one line of a run that signal ``signum`` stopped (:data:`STOP_LINES`) on stderr.

    Parameters
    ----------
    signum : int
        ``signal.SIGINT`` or ``signal.SIGTERM``.

    Returns
    -------
    int
        The run's exit code: 130 or 143.
    """
    line, code = STOP_LINES[signal.Signals(signum)]
    print(line, file=sys.stderr)
    return code


class Stop:
    """The signal that stopped the run (``SIGINT``, ``SIGTERM``), or None while none came."""

    signum: int | None = None


@contextmanager
def stop_signals() -> Iterator[Stop]:
    """While the block runs, Ctrl-C (SIGINT) raises ``KeyboardInterrupt`` and SIGTERM
    :class:`~morphkit.errors.Terminated` (a ``KeyboardInterrupt``: the run unwinds the same way,
    removing its temporary files), and the signal is recorded, so that an interrupt a library
    swallowed is still told as one; a ``KeyboardInterrupt`` raised in a C callback (where Python can
    only report it as "Exception ignored", with a traceback) records it silently. A signal's own
    handler is replaced only where Python's default is installed (not where it is ignored, or
    another handler was set) and only in the main thread; both are restored on leaving.

    Yields
    ------
    Stop
        Its ``signum`` is the signal that came (None while none did).
    """
    stop = Stop()
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return
    defaults = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}
    previous = {signum: signal.getsignal(signum) for signum in defaults}

    def on_signal(signum: int, frame: Any) -> None:
        stop.signum = signum
        raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt

    hook = sys.unraisablehook

    def on_unraisable(info: Any) -> None:
        if isinstance(info.exc_value, KeyboardInterrupt):
            if stop.signum is None:
                stop.signum = signal.SIGTERM if isinstance(info.exc_value, Terminated) else signal.SIGINT
            return
        hook(info)

    mine = [signum for signum, default in defaults.items() if previous[signum] is default]
    for signum in mine:
        signal.signal(signum, on_signal)
    sys.unraisablehook = on_unraisable
    try:
        yield stop
    finally:
        for signum in mine:
            signal.signal(signum, previous[signum])
        sys.unraisablehook = hook
