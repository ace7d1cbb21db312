"""Output folders: one rule for every command that writes into a folder.

A command (``demo``, ``shadows``, ``billboards``, ``bake``, ``viewmorph --frames``)
writes into a folder that is

* new (created, with its missing parents, only when the work starts), or empty, or
* a previous run of the same command: it holds that command's marker
  (:data:`MARKER_NAME`, written when a run starts, or an older run's own index:
  ``index.json`` of a demo, ``manifest.json`` of a bake, told by its content from another
  program's file of that name, :attr:`OutputRule.recognise`). Such a folder is
  replaced only when asked (``--overwrite``): the files the new run writes
  replace the old ones, and the files the previous run *recorded* that the new run
  did not write again (old frames beyond the new count) are removed at the end, so
  old and new output never mix. Every other file stays: a user's own file beside a
  run, in a subfolder, or named like the command's (``compare_0000 - edited.png``).
  A bake *resumes* its previous run instead (:attr:`OutputRule.resume`; its
  manifest says what is done).

The record: a run lists the files it wrote (created or replaced during the run, of
the command's names, :attr:`OutputRule.owns`) in its marker's ``files``, when it ends
(cleanly or by an exception). A previous run without that list (an older morphkit's
run, whose index lists its files under ``files``, or a killed run) is replaced by the
index's list where there is one, else by the command's exact names alone
(:func:`owned`: ``frames/frame_0003.png``, never ``frames/frame_0003 (copy).png``).

Frames: every command that writes a sequence names its frames alike, ``frames/frame_0000.png``
(:func:`frame_name`); a finished folder holds one file of morphkit's own, its marker.

Anything else (a folder holding other files, or another command's output, a
file, another program's file under an index's name: a web app's ``manifest.json``, never
read as a bake's nor replaced) is refused with a one-line :class:`~morphkit.errors.OutputExistsError`
(or :class:`~morphkit.errors.ValidationError` for a path that cannot be a
folder) before any work and before anything is created: a refusal leaves no
folder behind. :func:`claim_output` makes the check (no side effect);
:meth:`OutputClaim.writing` creates the folder, takes its lock (``fcntl.flock`` on the
folder itself, so that a finished folder holds one file of morphkit's own, the marker: a
second run into the same folder at the same time is refused,
:class:`~morphkit.errors.OutputBusyError`), removes the temporary files of a killed
run (``TEMPORARY``; a run that is killed cannot remove its own) and writes the marker. On exit,
clean or not, it removes the temporary files again (a process of the run killed mid-write, e.g. a
bake's worker process, while the run went on). A run that fails or is interrupted before writing
anything (a bad input found once the folder was claimed) leaves the folder as it was: it removes
what it created (its marker, the folder and its parents, a subfolder such as ``frames/``) and puts
back the marker it found. A subfolder morphkit writes into (:func:`subfolders`) that holds nothing
(an older version left one when it stopped before its first frame) counts as nothing: it never
makes a folder "hold other files".
"""

from __future__ import annotations

import fcntl
import json
import os
import re
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

from ..errors import FileFormatError, OutputBusyError, OutputExistsError, ValidationError, expected_got
from .fileio import open_regular, write_bytes, write_json

__all__ = ["MARKER_NAME", "LOCK_NAME", "FRAMES_FOLDER", "frame_name", "OutputRule", "OutputClaim",
           "claim_output", "previous_run", "owned", "subfolders", "DEMO_OUTPUT", "SHADOWS_OUTPUT",
           "BILLBOARDS_OUTPUT", "RENDER_OUTPUT", "PLAN_OUTPUT", "BAKE_OUTPUT", "VIEWMORPH_OUTPUT",
           "BAKE_MANIFEST_FORMAT",
           "is_bake_manifest", "check_output_file"]

#: The marker of a command's output folder: ``{"morphkit_output": 1, "command": ..., "status":
#: "running" | "complete", "started": ...}``.
MARKER_NAME = ".morphkit-output.json"

#: The lock file older versions kept in an output folder (the lock is now taken on the folder
#: itself); a run removes one it finds.
LOCK_NAME = ".morphkit-output.lock"

#: Names of files morphkit itself leaves in a folder: its marker and an older version's lock file
#: (and the temporary files a killed process could not remove, :data:`TEMPORARY`).
HOUSEKEEPING = (MARKER_NAME, LOCK_NAME)

#: A temporary file morphkit names: :func:`morphkit.files.fileio.atomic_output`'s and
#: :class:`morphkit.programs.video.VideoFile`'s (``.<stem>.<8 random>.part<suffix>``), a probe of
#: :func:`morphkit.files.fileio.check_writable` or of the video writer (``.morphkit-probe-<8 random>``,
#: with the video's suffix), and an older version's video (``.billboards.<8 random>.webm``, also
#: ``shadows`` and ``.mp4``): left only by a process that was killed, removed by the next run into
#: the folder. Nothing else is taken for one (``.notes.webm``, ``.billboards.webm`` stay).
TEMPORARY = re.compile(r"^(\..+\.[a-z0-9_]{8}\.part(\.[^.]+)*|\.morphkit-probe-[a-z0-9_]{8}(\.[a-z0-9]+)?"
                       r"|\.(billboards|shadows)\.[a-z0-9_]{8}\.(webm|mp4))$")


def _housekeeping(name: str) -> bool:
    """``name`` is a file morphkit itself leaves in a folder (:data:`HOUSEKEEPING`, :data:`TEMPORARY`)."""
    return name in HOUSEKEEPING or TEMPORARY.match(name) is not None


@dataclass(frozen=True)
class OutputRule:
    """What one command writes into its output folder.

    Parameters
    ----------
    command : str
        The command's name (in messages and in the marker).
    owns : tuple of str
        Patterns of the paths (relative, POSIX) of the files a run writes (:func:`owned`:
        ``*`` is any characters but ``/``, ``#`` one or more digits); a run records the
        files it wrote of these names, and with ``--overwrite`` the recorded files the
        new run did not write again are removed.
    markers : tuple of str
        Files that also mark a previous run (an older run's index).
    resume : bool
        A previous run is continued, not replaced (no ``--overwrite`` needed).
    recognise : callable, optional
        Whether a file named as one of :attr:`markers` is the command's (its content), not
        another program's file of that name; None takes any.
    """

    command: str
    owns: tuple[str, ...]
    markers: tuple[str, ...] = ()
    resume: bool = False
    recognise: Callable[[Path], bool] | None = None


def _json_holding(key: str) -> Callable[[Path], bool]:
    """A :attr:`OutputRule.recognise` test: the file is a JSON object holding ``key``."""

    def test(path: Path) -> bool:
        try:
            with open_regular(path, path.name) as f:  # a FIFO is never waited on: not ours
                data = json.loads(f.read().decode("utf-8"))
        except (OSError, ValueError, FileFormatError):
            return False
        return isinstance(data, dict) and key in data

    return test


#: The ``format`` a morphkit bake manifest names (:mod:`morphkit.bake.manifest`): how the folder rule
#: tells a bake's ``manifest.json`` from another program's.
BAKE_MANIFEST_FORMAT = "morphkit-bake-manifest"


def _no_json_constant(name: str) -> float:
    raise ValueError(f"{name} is not a JSON number")


def is_bake_manifest(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is a morphkit bake manifest (of any version, or damaged), not another
    program's file of the same name (a web app's ``manifest.json``).

    Parameters
    ----------
    path : path-like
        A file named :data:`morphkit.bake.manifest.MANIFEST_NAME`.

    Returns
    -------
    bool
        True for a regular file whose JSON object names :data:`BAKE_MANIFEST_FORMAT` as its
        ``format``, or that is not JSON (or no object) but holds that name (a manifest cut
        short: :meth:`morphkit.bake.manifest.Manifest.open` reports it); False for anything else
        (absent, not a regular file, unreadable, JSON of another format).
    """
    p = Path(path)
    if not p.is_file():
        return False
    try:
        with open_regular(p, p.name) as f:  # never waits on a FIFO
            text = f.read().decode("utf-8", errors="replace")
    except (OSError, FileFormatError):
        return False
    try:
        d = json.loads(text, parse_constant=_no_json_constant)
    except (ValueError, TypeError):
        return BAKE_MANIFEST_FORMAT in text
    return d.get("format") == BAKE_MANIFEST_FORMAT if isinstance(d, dict) else BAKE_MANIFEST_FORMAT in text




def _bake_manifest(path: Path) -> bool:
    """A :attr:`OutputRule.recognise` test: a morphkit bake manifest (damaged ones too)."""
    return is_bake_manifest(path)


#: The folder of a command's frame sequence (``billboards``, ``shadows``, ``viewmorph --frames``): every
#: command names its frames alike, :func:`frame_name`.
FRAMES_FOLDER = "frames"


def frame_name(index: int) -> str:
    """The path, relative to the output folder, of frame ``index`` of any command's sequence.

    Parameters
    ----------
    index : int
        The frame's number, from 0.

    Returns
    -------
    str
        ``frames/frame_0000.png`` (four digits, more past 9999).

    Examples
    --------
    >>> frame_name(3)
    'frames/frame_0003.png'
    """
    return f"{FRAMES_FOLDER}/frame_{int(index):04d}.png"


#: ``morphkit demo``: PNGs and the preview page in the folder itself and ``index.json``
#: (:mod:`morphkit.programs.demo`).
DEMO_OUTPUT = OutputRule("demo", ("*.png", "*.html", "index.json"), markers=("index.json",),
                         recognise=_json_holding("morphkit_demo"))
#: ``morphkit shadows``: ``frames/frame_NNNN.png`` and ``shadows.webm`` (:mod:`morphkit.programs.playback`;
#: ``frame_NNNN.png`` in the folder itself and ``shadows.mp4`` are what older versions wrote).
SHADOWS_OUTPUT = OutputRule("shadows", ("frames/frame_#.png", "shadows.webm", "frame_#.png", "shadows.mp4"))
#: ``morphkit billboards``: ``frames/frame_NNNN.png``, ``billboards.webm``, ``compare_NNNN.png``,
#: ``billboards.json`` (:mod:`morphkit.programs.sequence`; ``billboards.mp4``: older versions').
BILLBOARDS_OUTPUT = OutputRule("billboards", ("frames/frame_#.png", "billboards.webm", "billboards.mp4",
                                              "compare_#.png", "billboards.json"),
                               markers=("billboards.json",), recognise=_json_holding("morphkit_billboards"))
#: ``morphkit render SCENE``: ``frames/frame_NNNN.png``, ``render.webm``, ``compare_NNNN.png``,
#: ``render.json`` (:mod:`morphkit.programs.scenerender`).
RENDER_OUTPUT = OutputRule("render", ("frames/frame_#.png", "render.webm", "compare_#.png", "render.json"),
                           markers=("render.json",), recognise=_json_holding("morphkit_render"))
#: ``morphkit plan SCENE``: ``plan.json``, ``plan.png`` and the error tables it measured,
#: ``tables/ASSET.REPRESENTATION.npz`` (:mod:`morphkit.programs.planning.planrun`).
PLAN_OUTPUT = OutputRule("plan", ("plan.json", "plan.png", "tables/*.npz"), markers=("plan.json",),
                         recognise=_json_holding("morphkit_plan"))
#: ``morphkit bake``: resumed; ``manifest.json`` marks a bake (:mod:`morphkit.bake.manifest`).
BAKE_OUTPUT = OutputRule("bake", ("manifest.json", "manifest.journal", "*.npz"),
                         markers=("manifest.json",), resume=True, recognise=_bake_manifest)
#: ``morphkit viewmorph --frames N``: ``frames/frame_NNNN.png`` (older versions: ``frame_NNN.png`` in the
#: folder itself).
VIEWMORPH_OUTPUT = OutputRule("viewmorph", ("frames/frame_#.png", "frame_#.png"))


def subfolders() -> frozenset[str]:
    """The subfolders morphkit's commands write into (the first part of an :attr:`OutputRule.owns`
    pattern holding a ``/``: ``frames``).

    Returns
    -------
    frozenset of str
        Folder names.
    """
    rules = (DEMO_OUTPUT, SHADOWS_OUTPUT, BILLBOARDS_OUTPUT, RENDER_OUTPUT, PLAN_OUTPUT, BAKE_OUTPUT,
             VIEWMORPH_OUTPUT)
    return frozenset(pat.split("/", 1)[0] for rule in rules for pat in rule.owns if "/" in pat)


def _pattern(pattern: str) -> re.Pattern[str]:
    """The regular expression of an :attr:`OutputRule.owns` pattern."""
    parts = {"*": "[^/]*", "#": "[0-9]+"}
    return re.compile("".join(parts.get(c, re.escape(c)) for c in pattern))


def owned(rel: str, rule: OutputRule) -> bool:
    """Whether the relative POSIX path ``rel`` is one of the names ``rule``'s command writes.

    A pattern of :attr:`OutputRule.owns` matches the whole path: ``*`` is any characters
    but ``/`` (``*.png`` is a PNG in the folder itself, not in a subfolder), ``#`` one or
    more digits (``frame_#.png`` is ``frame_0003.png``, not ``frame_0003 (copy).png``).

    Parameters
    ----------
    rel : str
        A path relative to the output folder, ``/``-separated.
    rule : OutputRule
        The command.

    Returns
    -------
    bool
        True when a pattern matches.
    """
    return any(_pattern(pat).fullmatch(rel) for pat in rule.owns)


def _ours(path: Path, rule: OutputRule) -> bool:
    """Whether ``path``, named as one of ``rule``'s markers, is a file of the command's."""
    return path.is_file() and (rule.recognise is None or rule.recognise(path))


def _foreign(folder: Path, rule: OutputRule) -> str | None:
    """The name of a file (or folder) in ``folder`` named as one of ``rule``'s markers that is not
    the command's (another program's ``manifest.json``), or None."""
    return next((n for n in rule.markers if (folder / n).exists() and not _ours(folder / n, rule)), None)


def _recorded(folder: Path, rule: OutputRule) -> set[str] | None:
    """The files the previous run in ``folder`` recorded (its marker's ``files``, else its index's
    ``files``: names, or objects with a ``path``), or None when it recorded none."""
    for name in (MARKER_NAME, *rule.markers):
        if name != MARKER_NAME and not _ours(folder / name, rule):
            continue  # another program's file of an index's name: its "files" are not ours
        try:
            with open_regular(folder / name, name) as f:  # a FIFO or a folder is no record
                data = json.loads(f.read().decode("utf-8"))
        except (OSError, ValueError, FileFormatError):
            continue
        files = data.get("files") if isinstance(data, dict) else None
        if isinstance(files, list):
            rels = [f.get("path") if isinstance(f, dict) else f for f in files]
            return {r for r in rels if isinstance(r, str)}
    return None


def _marker_command(folder: Path) -> str | None:
    """The command named by ``folder``'s marker, ``"?"`` for an unreadable one, None without."""
    marker = folder / MARKER_NAME
    if not marker.is_file():
        return None
    try:
        with open_regular(marker, MARKER_NAME) as f:
            data = json.loads(f.read().decode("utf-8"))
        return str(data["command"]) if isinstance(data, dict) and "command" in data else "?"
    except (OSError, ValueError, FileFormatError):
        return "?"


def _marker_pid(folder: Path) -> str:
    """The pid a folder's marker names (the run holding its lock), or ``"?"``."""
    try:
        with open_regular(folder / MARKER_NAME, MARKER_NAME) as f:
            pid = json.loads(f.read().decode("utf-8")).get("pid")
    except (OSError, ValueError, AttributeError, FileFormatError):
        return "?"
    return str(pid) if type(pid) is int else "?"


def previous_run(folder: str | os.PathLike[str], rule: OutputRule) -> Path | None:
    """The file that marks a previous run of ``rule``'s command in ``folder``, or None.

    Parameters
    ----------
    folder : str or os.PathLike
        An output folder (need not exist).
    rule : OutputRule
        The command.

    Returns
    -------
    pathlib.Path or None
        The command's own index (:attr:`OutputRule.markers`, recognised by
        :attr:`OutputRule.recognise`) when there is one, else the marker (:data:`MARKER_NAME`)
        when it names this command, else None.
    """
    p = Path(folder)
    for name in rule.markers:
        if _ours(p / name, rule):
            return p / name
    return p / MARKER_NAME if _marker_command(p) == rule.command else None


def _files(folder: Path) -> dict[str, tuple[int, int]]:
    """Every file under ``folder``: relative POSIX path -> (inode, mtime in ns)."""
    out = {}
    for root, _dirs, names in os.walk(folder):
        for name in names:
            full = Path(root) / name
            with suppress(OSError):
                st = full.lstat()
                out[full.relative_to(folder).as_posix()] = (st.st_ino, st.st_mtime_ns)
    return out


def _dirs(folder: Path) -> set[str]:
    """Every folder under ``folder`` (relative POSIX paths)."""
    out = set()
    for root, dirs, _names in os.walk(folder):
        out.update((Path(root) / d).relative_to(folder).as_posix() for d in dirs)
    return out


def _empty_leftover(path: Path) -> bool:
    """``path`` is one of the subfolders morphkit writes into (:func:`subfolders`) holding nothing but
    what morphkit leaves (:data:`TEMPORARY`): a run that stopped before its first frame made it."""
    if path.name not in subfolders() or path.is_symlink() or not path.is_dir():
        return False
    try:
        return all(not e.is_dir(follow_symlinks=False) and TEMPORARY.match(e.name) for e in os.scandir(path))
    except OSError:
        return False


@dataclass(frozen=True)
class OutputClaim:
    """An output folder checked for a command (:func:`claim_output`); write with :meth:`writing`.

    Parameters
    ----------
    path : pathlib.Path
        The folder, absolute.
    rule : OutputRule
        The command.
    previous : bool
        The folder holds a previous run of the command.
    """

    path: Path
    rule: OutputRule
    previous: bool

    @contextmanager
    def writing(self) -> Iterator[Path]:
        """Create the folder, lock it and mark it; finish (or undo) on exit.

        On a clean exit a replaced previous run's files that were not written again are
        removed and the marker says ``complete``. On an exception (an interrupt too)
        before anything but the marker was written, the folder is left as it was: what this
        call created is removed (the marker, subfolders, the folder and its parents) and the
        marker it found is put back. Either
        way no temporary file (``TEMPORARY``) is left: the block's writers are done, and one
        killed mid-write cannot remove its own.

        Yields
        ------
        pathlib.Path
            The folder.

        Raises
        ------
        ValidationError
            The folder cannot be created or written.
        OutputBusyError
            Another run holds the folder's lock.
        """
        p = self.path
        created = []
        for d in (p, *p.parents):
            if d.exists():
                break
            created.append(d)
        try:
            p.mkdir(parents=True, exist_ok=True)
            # the folder's own descriptor, read-only: no lock file to leave behind, and no file
            # held open for writing (the file system can be remounted read-only under a run)
            lock = os.open(p, os.O_RDONLY | os.O_DIRECTORY)
        except OSError as exc:
            _remove_dirs(created)
            raise ValidationError(expected_got(f"{self.rule.command} output folder", "a folder morphkit can "
                                               "create and write", f"{str(p)!r} ({type(exc).__name__}: "
                                               f"{exc.strerror or exc})")) from exc
        try:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _marker_pid(p)
                raise OutputBusyError(expected_got(
                    f"{self.rule.command} output folder {str(p)!r}", "one no other run is writing to (wait "
                    "for it to finish, or choose another folder)", f"one locked by process {holder}")
                ) from None
            _remove_temporaries(p)  # locked: a temporary file here is a killed run's, half written
            before, dirs_before = _files(p), _dirs(p)
            try:
                with open_regular(p / MARKER_NAME, MARKER_NAME) as f:
                    old_marker: bytes | None = f.read()
            except (OSError, FileFormatError):
                old_marker = None
            previous = _recorded(p, self.rule) if self.previous else set()
            if previous is None:  # no record: the command's exact names
                previous = {rel for rel in before if owned(rel, self.rule)}
            marker = {"morphkit_output": 1, "command": self.rule.command, "status": "running",
                      "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "pid": os.getpid()}
            try:
                with suppress(FileNotFoundError):
                    (p / LOCK_NAME).unlink()  # an older version's lock file
                write_json(p / MARKER_NAME, marker)  # with the pid: a second run names the holder
            except OSError as exc:
                raise ValidationError(expected_got(f"{self.rule.command} output folder", "a folder morphkit "
                                                   "can write", f"{str(p)!r} ({type(exc).__name__}: "
                                                   f"{exc.strerror or exc})")) from exc

            def record(after: dict[str, tuple[int, int]], keep: set[str]) -> list[str]:
                """The files of this run: those it wrote, and ``keep`` (the previous run's, where kept)."""
                wrote = {rel for rel, st in after.items() if before.get(rel) != st and owned(rel, self.rule)}
                return sorted(wrote | (keep & set(after)))

            try:
                yield p
            except BaseException:
                _remove_temporaries(p)  # a process of this run killed mid-write (a bake's worker)
                after = _files(p)
                if {rel for rel, st in after.items() if before.get(rel) != st} <= {MARKER_NAME}:
                    # refused (or stopped) before writing anything: the folder is left as it was
                    with suppress(OSError):
                        if old_marker is None:
                            (p / MARKER_NAME).unlink()
                        else:
                            write_bytes(p / MARKER_NAME, old_marker)
                    # the subfolders this run made (innermost first), then the folder and its parents
                    _remove_dirs([p / d for d in sorted(_dirs(p) - dirs_before, reverse=True)] + created)
                else:  # the next --overwrite replaces what this run and the one before it wrote
                    with suppress(OSError):
                        write_json(p / MARKER_NAME, {**marker, "files": record(after, previous)})
                raise
            _remove_temporaries(p)
            after = _files(p)
            if not self.rule.resume:
                for rel in sorted(previous):  # the previous run's files not written again
                    if rel in before and after.get(rel) == before[rel]:
                        with suppress(OSError):
                            (p / rel).unlink()
                        after.pop(rel, None)
            keep = previous if self.rule.resume else set()
            write_json(p / MARKER_NAME, {**marker, "status": "complete", "files": record(after, keep)})
        finally:
            os.close(lock)  # releases the lock


def _remove_temporaries(folder: Path) -> None:
    """Remove the temporary files (``TEMPORARY``) under ``folder``: a writer killed mid-write
    (a killed run, or a bake's worker process killed while the run went on) leaves them."""
    for rel in _files(folder):
        if TEMPORARY.match(rel.rsplit("/", 1)[-1]):
            with suppress(OSError):
                (folder / rel).unlink()


def _remove_dirs(dirs: list[Path]) -> None:
    """Remove the folders (innermost first) that are empty."""
    for d in dirs:
        with suppress(OSError):
            d.rmdir()


def claim_output(path: str | os.PathLike[str], rule: OutputRule, *, overwrite: bool = False) -> OutputClaim:
    """Check that ``path`` may take ``rule``'s command's output (module docstring); nothing is created.

    Parameters
    ----------
    path : str or os.PathLike
        The output folder.
    rule : OutputRule
        The command.
    overwrite : bool
        Replace a previous run of the command (``--overwrite``).

    Returns
    -------
    OutputClaim
        The folder, to write with :meth:`OutputClaim.writing`.

    Raises
    ------
    ValidationError
        ``path`` is a file, lies under a file, or cannot be listed.
    OutputExistsError
        The folder holds files that are not a previous run of the command (another
        program's file named as the command's index among them), or a previous run and
        ``overwrite`` is False (and the command does not resume).
    """
    p = Path(os.path.abspath(os.fspath(path)))
    what = f"{rule.command} output"
    in_the_way = next((a for a in (p, *p.parents) if a.exists() and not a.is_dir()), None)
    if in_the_way == p:
        raise ValidationError(expected_got(f"{what} folder", "a folder", f"the file {p}"))
    if in_the_way is not None:
        raise ValidationError(expected_got(f"{what} folder", "a folder morphkit can create and write",
                                           f"{str(p)!r} (NotADirectoryError: {in_the_way} is a file)"))
    if not p.exists():
        return OutputClaim(p, rule, False)
    try:
        entries = sorted(e.name for e in os.scandir(p))
    except OSError as exc:
        raise ValidationError(expected_got(what, "a folder morphkit can list",
                                           f"{p} ({type(exc).__name__}: {exc.strerror or exc})")) from exc
    # what morphkit itself leaves: its marker, a killed run's temporary files, and a subfolder it made
    # that holds nothing of them (a run stopped before its first frame, by an older version)
    housekeeping = all(_housekeeping(e) or _empty_leftover(p / e) for e in entries)
    if not entries or (housekeeping and _marker_command(p) is None):
        return OutputClaim(p, rule, False)
    foreign = _foreign(p, rule)
    if foreign is not None:  # never read as the command's index, nor replaced by it
        raise OutputExistsError(expected_got(
            f"{what} folder", f"a new or empty folder, or a previous {rule.command} run",
            f"{p} holding {foreign!r} of another program (not morphkit {rule.command}'s; it is never "
            "replaced: choose another folder)"))
    mark = previous_run(p, rule)
    if mark is None:
        other = _marker_command(p)
        got = (f"{p} holding the output of morphkit {other}" if other not in (None, "?") else
               f"{p} holding {len(entries)} entries that are not one, e.g. {entries[0]!r}")
        raise OutputExistsError(expected_got(f"{what} folder", f"a new or empty folder, or a previous "
                                             f"{rule.command} run", got))
    if not rule.resume and not overwrite:
        raise OutputExistsError(expected_got(
            f"{what} folder", f"one without a previous {rule.command} (--overwrite / overwrite=True "
            "replaces it)", f"{p} holding {mark.name}"))
    return OutputClaim(p, rule, True)


def check_output_file(path: str | os.PathLike[str], kind: str, suffixes: tuple[str, ...], *,
                      overwrite: bool = False) -> Path:
    """``path`` if one output file of ``kind`` may be written there (checked before any work): the
    usual rule of a command writing one file (``-o OUT``), as :func:`claim_output` is of a folder.

    Parameters
    ----------
    path : path-like
        The output file.
    kind : str
        What it is, for the message, e.g. ``"a .glb"`` (the message says ``a .glb file path``).
    suffixes : tuple of str
        Its allowed extensions, lower case, with the dot.
    overwrite : bool, optional
        An existing file may be replaced.

    Returns
    -------
    Path

    Raises
    ------
    ValidationError
        Another extension, a folder, or a path under a file.
    OutputExistsError
        ``path`` exists and ``overwrite`` is not given.
    """
    p = Path(path)
    if p.suffix.lower() not in suffixes:
        raise ValidationError(expected_got("-o", f"{kind} file path", repr(str(p))))
    in_the_way = next((a for a in p.parents if a.exists() and not a.is_dir()), None)
    if in_the_way is not None:
        raise ValidationError(expected_got("-o", "a path whose parents are folders",
                                           f"{str(p)!r}, where {str(in_the_way)!r} is a file"))
    if p.is_dir():
        raise ValidationError(expected_got("-o", f"{kind} file path", f"the folder {str(p)!r}"))
    if p.exists() and not overwrite:
        raise OutputExistsError(expected_got("output", "a new file, or --overwrite to replace it",
                                             f"the existing file {str(p)!r}"))
    return p
