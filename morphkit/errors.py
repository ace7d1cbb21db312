"""The morphkit exception hierarchy: every error morphkit raises on purpose.

Each message says what was expected and what was got; build messages with
:func:`expected_got` so they read the same everywhere.

Hierarchy::

    MorphkitError
    ├── ValidationError (also ValueError)    bad argument: shape, dtype, value, NaN
    │   ├── MeshError                         unreadable, unknown or empty mesh
    │   ├── OutOfRangeError                   a position outside a baked range
    │   ├── OutputExistsError                 an output folder holds what a run would replace
    │   └── UsageError                        a command-line option's value refused (the CLI exits 2)
    ├── GeometryError                         degenerate geometry (refused, not repaired)
    │   ├── FoldOverError                     a warp triangle flips or collapses
    │   └── DegenerateViewError               camera inside object, epipole in image, ...
    ├── RenderError                           the GL boundary failed
    ├── FileFormatError                       a saved file is corrupt, truncated or foreign
    ├── BudgetError                           no representation is predicted to meet an error budget
    ├── ClusterError                          the Dask scheduler is unreachable or has no workers
    ├── OutputBusyError                       another run is writing into the same output folder
    └── OutputWriteError                      the output's file system stopped taking writes mid-run
                                              (disk full, read-only): the run stopped, finished work kept

    AssetWarning (a UserWarning)              a mesh's look could not be loaded or drawn as given:
    │                                         a documented fallback was used (e.g. a missing texture)
    └── MeshLookWarning                       ... found when the look is drawn (morphkit.meshes.look: e.g.
                                              a texture without UVs drawn in its mean colour)

    Terminated (a KeyboardInterrupt)          SIGTERM arrived (the command line's handler raises it):
                                              unwound like Ctrl-C, temporary files removed

Warnings: filter on :class:`AssetWarning`, the one name for every look
fallback, whether the loader (:func:`morphkit.meshes.load_mesh`) or the
renderer (:mod:`morphkit.meshes.look`) found it, e.g.
``warnings.simplefilter("error", AssetWarning)`` to refuse every fallback.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "MorphkitError",
    "ValidationError",
    "MeshError",
    "OutOfRangeError",
    "GeometryError",
    "FoldOverError",
    "DegenerateViewError",
    "RenderError",
    "FileFormatError",
    "BudgetError",
    "ClusterError",
    "OutputExistsError",
    "UsageError",
    "OutputBusyError",
    "OutputWriteError",
    "Terminated",
    "AssetWarning",
    "MeshLookWarning",
    "expected_got",
]


class MorphkitError(Exception):
    """Base class of every error morphkit raises on purpose."""


class ValidationError(MorphkitError, ValueError):
    """An argument has the wrong type, shape, dtype or value."""


class MeshError(ValidationError):
    """A mesh could not be found, read, or is empty/degenerate."""


class OutOfRangeError(ValidationError):
    """A position lies outside the range a precomputation covers."""


class GeometryError(MorphkitError):
    """The geometry is degenerate for the requested operation."""


class FoldOverError(GeometryError):
    """A destination triangle of a mesh warp flips orientation or has ~zero area."""


class DegenerateViewError(GeometryError):
    """A camera/light configuration cannot produce a meaningful image."""


class RenderError(MorphkitError):
    """The rendering boundary (pyrender/OpenGL) failed."""


class FileFormatError(MorphkitError):
    """A morphkit file is truncated, corrupt, of another version or for another setup."""


class BudgetError(MorphkitError):
    """No choice of representations is predicted to meet an error budget (the message names the best
    reachable figure and what bounds it)."""


class ClusterError(MorphkitError):
    """The distributed engine (a Dask scheduler and its workers) cannot be reached or used."""


class OutputExistsError(ValidationError):
    """An output folder holds files a run would replace or mix with its own (refused before any work)."""


class UsageError(ValidationError):
    """A command-line option's value, or a combination of options, is refused: the command line was
    used wrongly (``morphkit`` exits with 2, as for argparse's own usage errors; see
    :mod:`morphkit.cli`)."""


class OutputBusyError(MorphkitError):
    """Another run is writing into the same output folder (it holds the folder's lock)."""


class OutputWriteError(MorphkitError):
    """The output folder's file system refused a write mid-run (full, over quota, read-only, no
    permission): the run stopped; what it finished is kept, a rerun goes on from there.

    Parameters
    ----------
    message : str
        The one-line message (:func:`expected_got`).
    errno : int
        The OS error number of the refused write (``errno.ENOSPC``, ``errno.EROFS``, ...).
    """

    def __init__(self, message: str, errno: int) -> None:
        super().__init__(message)
        self.errno = errno

    def __reduce__(self) -> tuple:
        """Pickled with its errno (the default would call the class with the message alone).

        Returns
        -------
        tuple
            The class and its arguments ``(message, errno)``.
        """
        return type(self), (str(self), self.errno)


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: raised by the command line's handler (:func:`morphkit.cli.main`) so that the
    run unwinds as after Ctrl-C (every ``except KeyboardInterrupt`` and ``finally`` runs: atomic
    writes remove their temporary files, an output folder its unfinished claim)."""


class AssetWarning(UserWarning):
    """A mesh's look could not be loaded or drawn as given; a documented fallback was used.

    The one warning class to filter on for every look fallback (see the module notes).
    """


class MeshLookWarning(AssetWarning):
    """An :class:`AssetWarning` found when a mesh's look is drawn (:mod:`morphkit.meshes.look`)."""


def expected_got(what: str, expected: Any, got: Any) -> str:
    """Format the standard message: ``"<what>: expected <expected>, got <got>"``.

    Parameters
    ----------
    what : str
        What was checked (an argument or file name).
    expected : Any
        What was expected; formatted with ``str``.
    got : Any
        What was given instead; formatted with ``str``.

    Returns
    -------
    str
        The message.

    Examples
    --------
    >>> from morphkit.errors import ValidationError, expected_got
    >>> expected_got("grid", "k >= 2 samples per axis", 1)
    'grid: expected k >= 2 samples per axis, got 1'
    >>> issubclass(ValidationError, ValueError)
    True
    """
    return f"{what}: expected {expected}, got {got}"
