"""The bake manifest: what was baked from what, with which options, and how it went.

One JSON file, ``<out>/manifest.json`` (:data:`MANIFEST_NAME`)::

    {"format": "morphkit-bake-manifest", "version": 1, "morphkit_version": "...",
     "options": {kind: {...}},               # the last run's options, per kind
     "run": {"started", "wall_s", "workers", "scheduler", "baked", "skipped", "failed"},
     "assets": {name: {"input": abs path, "input_sha256", "input_bytes",
                       "up_axis": "z" | "y",
                       "status": "baked" | "skipped" | "failed", "error": str | null,
                       "outputs": {kind: {"file" (relative to <out>), "sha256", "bytes",
                                          "version", "options", "seconds"}},
                       "timings_s": {"load", kind..., "total", "cpu"}, "worker", "updated"}}}

``status`` is what the last run did with the asset; ``outputs`` always lists the
files that are current for the recorded input. ``up_axis`` is the up axis the
input was loaded with for those outputs (the run's ``--up-axis`` resolved for
the file by :func:`morphkit.meshes.resolve_up`); ``run`` records the requested
``up`` (``"auto"``, ``"z"`` or ``"y"``).

Nothing lost. The manifest file is only ever replaced atomically
(:func:`morphkit.files.fileio.write_json`), and every finished asset's record is first
appended to a journal, ``<out>/manifest.journal`` (:data:`JOURNAL_NAME`, one
JSON record per line, ``fsync``-ed: :func:`morphkit.files.fileio.append_lines`), the
moment its result arrives (results that arrive together share one disk sync).
:meth:`Manifest.commit` folds the journal into the manifest and removes it;
:meth:`Manifest.open` replays a journal a crash left behind (a truncated last
line is skipped). So a run killed at any point keeps every asset that finished,
at the cost of one appended line per asset instead of rewriting the whole
manifest per asset.

Incremental: :meth:`Manifest.up_to_date` says whether an asset's output for a
kind can be kept: same input hash, same up axis, same options and format
version, and the file still there with the recorded hash. A record without
``up_axis`` (a manifest written before the bake had an up axis, when every file
was loaded as it is stored) counts as ``"z"`` (:data:`LEGACY_UP_AXIS`): an OBJ
or glTF library baked then, now ``"y"`` by default, is re-baked turned upright;
a PLY or STL one is kept.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from .. import __version__
from ..errors import FileFormatError, expected_got
from ..files.fileio import append_lines, open_regular, write_json
from ..files.outfolder import BAKE_MANIFEST_FORMAT, is_bake_manifest
from .kinds import AssetKind, output_name

__all__ = ["MANIFEST_NAME", "JOURNAL_NAME", "MANIFEST_FORMAT", "MANIFEST_VERSION", "LEGACY_UP_AXIS",
           "OutputRecord", "AssetRecord", "Manifest", "BakedFrom", "baked_from", "baked_beside",
           "ManifestRecords", "file_digest", "utc_now", "is_bake_manifest"]

#: File name of the manifest in the output folder.
MANIFEST_NAME = "manifest.json"
#: File name of the append-only journal of finished assets (replayed by the next run).
JOURNAL_NAME = "manifest.journal"
#: The format name stored in the manifest (the output folders' rule recognises a bake by it:
#: :data:`morphkit.files.outfolder.BAKE_MANIFEST_FORMAT`).
MANIFEST_FORMAT = BAKE_MANIFEST_FORMAT
#: The manifest format version this code reads and writes (``up_axis`` is optional in it).
MANIFEST_VERSION = 1
#: The up axis of a record without one: before the bake had an up axis every file was loaded
#: as stored, i.e. taken as ``+z`` up.
LEGACY_UP_AXIS = "z"


def file_digest(path: str | os.PathLike[str]) -> tuple[str, int]:
    """``(sha256 hex digest, size in bytes)`` of a file's content.

    Parameters
    ----------
    path : path-like
        The file, read in 1 MiB chunks.

    Returns
    -------
    digest : str
        The sha256 hex digest of the content.
    size : int
        The content's size in bytes.
    """
    h = hashlib.sha256()
    n = 0
    with open(path, "rb") as f:
        while chunk := f.read(1 << 20):
            h.update(chunk)
            n += len(chunk)
    return h.hexdigest(), n


def utc_now() -> str:
    """The current time, ISO 8601 UTC, to the second.

    Returns
    -------
    str
        E.g. ``"2026-01-31T12:00:00+00:00"``.
    """
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def _canonical(obj: Any) -> Any:
    """``obj`` as it reads back from JSON (tuples become lists), for comparisons."""
    return json.loads(json.dumps(obj))


@dataclass
class OutputRecord:
    """One output file of one asset for one kind.

    Parameters
    ----------
    file : str
        The file, a POSIX path relative to the output folder.
    sha256 : str
        Hex digest of the file's content.
    bytes : int
        The file's size.
    version : int
        The kind's file format version it was written with.
    options : dict
        The kind's options it was baked with (JSON values).
    seconds : float
        Wall time of baking and saving it.
    """

    file: str  # POSIX path relative to the output folder
    sha256: str
    bytes: int
    version: int
    options: dict[str, Any]
    seconds: float


@dataclass
class AssetRecord:
    """What the manifest knows of one asset (see the module docstring).

    Parameters
    ----------
    name : str
        Asset name (POSIX relative path without the mesh suffix).
    input : str
        The mesh file, absolute path.
    input_sha256 : str
        Hex digest of the mesh file's content.
    input_bytes : int
        The mesh file's size.
    status : str
        What the last run did: ``"baked"``, ``"skipped"`` or ``"failed"``.
    error : str, optional
        ``"<ErrorType>: <message>"`` when it failed.
    outputs : dict of str to OutputRecord
        The current output per kind name.
    timings_s : dict of str to float
        Seconds: ``load``, one per kind, ``total``, ``cpu``.
    worker : str, optional
        ``host:pid`` of the process that baked it.
    updated : str
        When the record was made (:func:`utc_now`); set by :meth:`Manifest.record` when empty.
    up_axis : {"z", "y"}, optional
        The up axis the input was loaded with for ``outputs`` (:func:`morphkit.meshes.resolve_up`);
        ``None`` in records written before the bake had one (read as :data:`LEGACY_UP_AXIS`).
    """

    name: str
    input: str
    input_sha256: str
    input_bytes: int
    status: str  # "baked" | "skipped" | "failed"
    error: str | None = None
    outputs: dict[str, OutputRecord] = field(default_factory=dict)
    timings_s: dict[str, float] = field(default_factory=dict)
    worker: str | None = None
    updated: str = ""
    up_axis: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON types (the manifest's ``assets`` entry).

        Returns
        -------
        dict
            The fields by name, ``outputs`` as dicts too.
        """
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> AssetRecord:
        """The record from its :meth:`to_dict` form.

        Parameters
        ----------
        d : dict
            A record as :meth:`to_dict` gives it (e.g. read back from JSON).

        Returns
        -------
        AssetRecord
            The record, ``outputs`` as :class:`OutputRecord`.
        """
        d = dict(_checked_record(d))
        d["outputs"] = {k: OutputRecord(**v) for k, v in d.get("outputs", {}).items()}
        return cls(**d)


def _no_constant(name: str) -> Any:
    """``json.loads``' hook for ``NaN``/``Infinity``: the manifest is strict JSON (written with
    ``allow_nan=False``), so a file holding them is refused (a ValueError), never carried on
    to fail at the next commit."""
    raise ValueError(f"{name} is not a JSON number")


_STATUSES = ("baked", "skipped", "failed")
_RECORD_TYPES: dict[str, Any] = {"name": str, "input": str, "input_sha256": str, "input_bytes": int,
                                 "status": str, "error": (str, type(None)), "outputs": dict,
                                 "timings_s": dict, "worker": (str, type(None)), "updated": str}
_OUTPUT_TYPES: dict[str, Any] = {"file": str, "sha256": str, "bytes": int, "version": int,
                                 "options": dict, "seconds": (int, float)}


def _fields_ok(d: Any, types: dict[str, Any], required: tuple[str, ...]) -> bool:
    """``d`` is a dict with ``required`` keys, each known key of its type (finite numbers)."""
    if not isinstance(d, dict) or not set(required) <= set(d):
        return False
    for k, v in d.items():
        if k in types and (isinstance(v, bool) or not isinstance(v, types[k])):
            return False
        if isinstance(v, float) and not math.isfinite(v):
            return False
    return True


def _checked_record(d: Any) -> dict[str, Any]:
    """``d`` if it is a record's :meth:`AssetRecord.to_dict` form (JSON types checked), else a
    FileFormatError: a hand-edited or damaged manifest never reaches the bake as wrong types."""
    ok = (_fields_ok(d, _RECORD_TYPES, ("name", "input", "input_sha256", "input_bytes", "status"))
          and d["status"] in _STATUSES
          and all(isinstance(k, str) and _fields_ok(v, _OUTPUT_TYPES, tuple(_OUTPUT_TYPES))
                  for k, v in d.get("outputs", {}).items())
          and all(type(v) in (int, float) and math.isfinite(v) for v in d.get("timings_s", {}).values()))
    if not ok:
        raise FileFormatError(expected_got("manifest asset record", "the fields of a bake record, "
                                           "each of its JSON type", repr(d)[:200]))
    return d


class Manifest:
    """The manifest of one output folder (open with :meth:`open`).

    Parameters
    ----------
    folder : pathlib.Path
        The output folder.
    assets : dict of str to AssetRecord, optional
        Every asset ever baked into the folder, by name (default none).
    options : dict, optional
        The last run's options per kind (default none).
    run : dict, optional
        The last run: started, wall_s, workers, scheduler, baked, skipped, failed (default none).
    """

    def __init__(self, folder: Path, assets: dict[str, AssetRecord] | None = None,
                 options: dict[str, Any] | None = None, run: dict[str, Any] | None = None) -> None:
        self.folder = Path(folder)
        self.assets: dict[str, AssetRecord] = dict(assets or {})
        self.options: dict[str, Any] = dict(options or {})
        self.run: dict[str, Any] = dict(run or {})

    @property
    def path(self) -> Path:
        """The manifest file (``<folder>/manifest.json``)."""
        return self.folder / MANIFEST_NAME

    @property
    def journal(self) -> Path:
        """The journal file (``<folder>/manifest.journal``)."""
        return self.folder / JOURNAL_NAME

    @classmethod
    def open(cls, folder: str | os.PathLike[str]) -> Manifest:
        """Read ``<folder>/manifest.json`` (empty if absent) and replay a journal left by a crash.

        Parameters
        ----------
        folder : path-like
            The output folder.

        Returns
        -------
        Manifest
            The manifest of ``folder``, with the journal's records applied (the journal is kept
            until :meth:`commit`).

        Raises
        ------
        FileFormatError
            The manifest is unreadable or of another format or version.
        """
        folder = Path(folder)
        m = cls(folder)
        if m.path.exists():
            try:
                with open_regular(m.path, "manifest") as f:  # a FIFO or a folder: refused, not waited on
                    text = f.read().decode("utf-8")
                d = json.loads(text, parse_constant=_no_constant)
                if d.get("format") != MANIFEST_FORMAT:
                    raise FileFormatError(expected_got(f"manifest {m.path}", MANIFEST_FORMAT,
                                                       d.get("format")))
                if d.get("version") != MANIFEST_VERSION:
                    raise FileFormatError(expected_got(f"manifest {m.path} version", MANIFEST_VERSION,
                                                       d.get("version")))
                m.assets = {k: AssetRecord.from_dict(v) for k, v in d["assets"].items()}
                m.options, m.run = d.get("options", {}), d.get("run", {})
                if not (isinstance(m.options, dict) and isinstance(m.run, dict)
                        and all(type(m.run.get(k, 0)) in (int, float) and math.isfinite(m.run.get(k, 0))
                                for k in ("baked", "skipped", "failed", "wall_s"))):
                    raise FileFormatError(expected_got(f"manifest {m.path} options and run", "objects",
                                                       f"{d.get('options')!r}, {d.get('run')!r}"[:200]))
            except (ValueError, KeyError, TypeError, AttributeError, UnicodeDecodeError) as exc:
                raise FileFormatError(expected_got(f"manifest {m.path}", f"a {MANIFEST_FORMAT} JSON file",
                                                   f"{type(exc).__name__}: {exc}")) from exc
        if m.journal.exists():
            with open_regular(m.journal, "manifest journal") as f:
                journal = f.read().decode("utf-8", errors="replace")
            for line in journal.splitlines():
                try:
                    rec = AssetRecord.from_dict(json.loads(line, parse_constant=_no_constant))
                except (ValueError, KeyError, TypeError, FileFormatError):
                    continue  # the line a crash cut short (or damaged: the asset is baked again)
                m.assets[rec.name] = rec
        return m

    # ----------------------------------------------------------- incremental
    def up_to_date(self, name: str, input_sha256: str, kind: AssetKind, *, up_axis: str) -> bool:
        """True when ``name``'s output for ``kind`` was baked from this input, turned from this up
        axis, with these options and format version, and the file is still there with the recorded
        hash.

        Parameters
        ----------
        name : str
            Asset name.
        input_sha256 : str
            Hex digest of the mesh file as it is now.
        kind : AssetKind
            The kind, with the options of this run.
        up_axis : {"z", "y"}
            The up axis this run loads the file with (resolved: :func:`morphkit.meshes.resolve_up`);
            a record without one counts as :data:`LEGACY_UP_AXIS`.

        Returns
        -------
        bool
            Whether the recorded output can be kept (the file is re-hashed to check).
        """
        rec = self.assets.get(name)
        out = None if rec is None else rec.outputs.get(kind.name)
        if rec is None or out is None or rec.input_sha256 != input_sha256:
            return False
        if (rec.up_axis or LEGACY_UP_AXIS) != up_axis:
            return False
        if out.version != kind.version or _canonical(out.options) != _canonical(kind.options()):
            return False
        if out.file != output_name(name, kind):
            return False
        path = self.folder / out.file
        return path.is_file() and path.stat().st_size == out.bytes and file_digest(path)[0] == out.sha256

    # --------------------------------------------------------------- updates
    def record(self, *recs: AssetRecord) -> None:
        """Set each record and append them to the journal (durable at once, one disk sync).

        Parameters
        ----------
        *recs : AssetRecord
            The records; an empty ``updated`` is set to now.
        """
        for rec in recs:
            rec.updated = rec.updated or utc_now()
            self.assets[rec.name] = rec
        append_lines(self.journal, [json.dumps(r.to_dict(), allow_nan=False) for r in recs])

    def mark_skipped(self, name: str, input_path: str, *, up_axis: str) -> None:
        """This run kept ``name``'s outputs, baked from ``input_path`` (in memory; written by
        :meth:`commit`).

        Parameters
        ----------
        name : str
            Asset name, already in the manifest.
        input_path : str
            The mesh file this run found for it, absolute path.
        up_axis : {"z", "y"}
            The up axis its outputs were baked with (:meth:`up_to_date` checked it), recorded where
            an older record had none.
        """
        self.assets[name].input = input_path
        self.assets[name].status = "skipped"
        self.assets[name].error = None
        self.assets[name].up_axis = up_axis

    def commit(self) -> Path:
        """Write the manifest atomically, then drop the journal it now contains.

        Returns
        -------
        pathlib.Path
            The manifest file.
        """
        write_json(self.path, self.to_dict())
        try:
            self.journal.unlink()
        except FileNotFoundError:
            pass
        return self.path

    # ----------------------------------------------------------------- views
    def to_dict(self) -> dict[str, Any]:
        """The whole manifest as JSON types (what ``manifest.json`` holds).

        Returns
        -------
        dict
            ``format``, ``version``, ``morphkit_version``, ``options``, ``run`` and ``assets``
            (sorted by name).
        """
        return {"format": MANIFEST_FORMAT, "version": MANIFEST_VERSION, "morphkit_version": __version__,
                "options": self.options, "run": self.run,
                "assets": {k: self.assets[k].to_dict() for k in sorted(self.assets)}}

    def counts(self, names: list[str] | None = None) -> dict[str, int]:
        """How many of ``names`` (default: all assets) are baked, skipped and failed.

        Parameters
        ----------
        names : list of str, optional
            Asset names, each in the manifest (default: all assets).

        Returns
        -------
        dict of str to int
            ``{"baked": n, "skipped": n, "failed": n}``.
        """
        keys = self.assets if names is None else names
        out = {"baked": 0, "skipped": 0, "failed": 0}
        for k in keys:
            out[self.assets[k].status] += 1
        return out

    def failed(self) -> dict[str, str]:
        """``{name: error}`` of the assets that failed.

        Returns
        -------
        dict of str to str
            Error message by asset name (empty when none was recorded).
        """
        return {k: r.error or "" for k, r in self.assets.items() if r.status == "failed"}

    def summary(self) -> str:
        """One line on the last run: baked, skipped, failed, wall time.

        Returns
        -------
        str
            E.g. ``"<n> baked, <n> skipped, <n> failed in <wall> s"``.
        """
        r = self.run
        return (f"{r.get('baked', 0)} baked, {r.get('skipped', 0)} skipped, {r.get('failed', 0)} failed "
                f"in {r.get('wall_s', 0.0):.1f} s")


@dataclass(frozen=True)
class BakedFrom:
    """What a bake manifest records of the input an output file was baked from.

    Parameters
    ----------
    manifest : pathlib.Path
        The ``manifest.json`` that lists the output.
    input : pathlib.Path
        The input mesh file, as the bake recorded it.
    input_sha256 : str
        The input file's sha256 when it was baked.
    up_axis : {"z", "y"}
        The up axis it was loaded with (:data:`LEGACY_UP_AXIS` for records without one).
    """

    manifest: Path
    input: Path
    input_sha256: str
    up_axis: str


def baked_from(output: str | os.PathLike[str]) -> BakedFrom | None:
    """The record of the bake that wrote ``output``: the ``manifest.json`` of its folder or the
    nearest parent folder that lists it, or None.

    A ``manifest.json`` that is not a morphkit bake manifest (a web app's:
    :func:`is_bake_manifest`) is passed over, as is one that does not list the file: the search
    goes on upwards.

    Parameters
    ----------
    output : path-like
        A baked file (an atlas, a billboard or dome asset).

    Returns
    -------
    BakedFrom or None
        The recorded input, or None when no manifest lists the file.

    Raises
    ------
    FileFormatError
        A morphkit manifest on the way up is damaged or of another version (:meth:`Manifest.open`).
    """
    found = _listing(output)
    if found is None:
        return None
    folder, rec = found
    return BakedFrom(folder / MANIFEST_NAME, Path(rec.input), rec.input_sha256, rec.up_axis or LEGACY_UP_AXIS)


def _listing(output: str | os.PathLike[str]) -> tuple[Path, AssetRecord] | None:
    """The folder of the nearest bake manifest that lists ``output``, and its asset's record."""
    target = Path(output).resolve()
    for folder in [target.parent, *target.parent.parents]:
        if not is_bake_manifest(folder / MANIFEST_NAME):
            continue
        for rec in Manifest.open(folder).assets.values():
            if any((folder / o.file).resolve() == target for o in rec.outputs.values()):
                return folder, rec
    return None


def baked_beside(output: str | os.PathLike[str], kind: str) -> Path | None:
    """The file the bake that wrote ``output`` made of the same asset for another ``kind``
    (a dome asset's sun atlas), when its manifest lists one that exists; else None.

    Parameters
    ----------
    output : path-like
        A baked file.
    kind : str
        The other kind's name (``AssetKind.name``, e.g. ``"sun_atlas"``).

    Returns
    -------
    pathlib.Path or None
        The other output file.

    Raises
    ------
    FileFormatError
        A morphkit manifest on the way up is damaged or of another version.
    """
    found = _listing(output)
    other = None if found is None else found[1].outputs.get(kind)
    if found is None or other is None:
        return None
    path = found[0] / other.file
    return path if path.is_file() else None


class ManifestRecords:
    """The bake manifests as :class:`morphkit.protocols.InputRecords`: :func:`baked_from`, the
    input checked against its recorded sha256."""

    def find(self, output: Path) -> tuple[Path, str] | str | None:
        """See :meth:`morphkit.protocols.InputRecords.find`.

        Parameters
        ----------
        output : pathlib.Path
            A baked file.

        Returns
        -------
        (pathlib.Path, str) or str or None
            The input and its up axis, why not, or None.
        """
        rec = baked_from(output)
        if rec is None:
            return None
        if rec.input.is_file() and file_digest(rec.input)[0] == rec.input_sha256:
            return rec.input, rec.up_axis
        return (f"{rec.input} (the input {rec.manifest} records for {Path(output).name}) is missing or "
                "changed since the bake")

