"""The relightable (dome) billboard asset file: one versioned ``.npz``.

Format ``"morphkit-billboard"`` (:data:`~.assetfile.FORMAT`), version
:data:`DOME_VERSION` (3): version 2 and older are one-elevation ring assets
(:mod:`.assetfile`), refused here with "re-bake". Written atomically
(:func:`morphkit.files.fileio.write_bytes`), read with ``allow_pickle=False``:

==============  =======================  ==================================================
array           dtype, shape             content
==============  =======================  ==================================================
``meta``        uint8 ``(n,)``           UTF-8 JSON, below
``rgba``        uint8 ``(V, n, n, 4)``   straight sRGB albedo and coverage of each view
``normal``      int8 ``(V, n, n, 3)``    ``round(127 n)``, object frame
``depth``       float16 ``(V, n, n)``    linear depth minus the camera distance ``D``
                                         (``+inf`` where nothing is drawn)
==============  =======================  ==================================================

``meta``: ``format``, ``version``, ``kind`` (``"dome"``), ``name``, ``mesh_hash``,
``appearance``, ``source_up``, ``rings`` (list of ``[elevation_deg, views]``),
``top``, ``pivot``, ``distance``, ``radius``, ``size``, ``levels`` and ``sha256``
(per array). :func:`read_dome` raises :class:`~morphkit.errors.FileFormatError` for a
missing, truncated or corrupt file, another format, kind or version, missing keys or
arrays, wrong dtypes or shapes, NaN or ``-inf`` depths, drawn depths outside the views' near and
far planes (:meth:`~morphkit.views.domecameras.DomeCameras.depth_range`: a negative depth draws nothing), or a
checksum that does not match.
"""

from __future__ import annotations

import io
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ... import tol
from ...errors import FileFormatError, ValidationError, expected_got
from ...files.fileio import ARCHIVE_ERRORS, array_digest, write_bytes
from ...views.domecameras import DomeCameras
from .assetfile import FORMAT, peek_meta

__all__ = ["DOME_VERSION", "DomeRecord", "write_dome", "read_dome", "dome_record", "is_dome_file"]

#: Version of the dome asset file (3: views over the hemisphere with albedo, normals and
#: depth; 2 and older: a ring at one elevation, lit by the bake light).
DOME_VERSION = 3

_ARRAYS = ("rgba", "normal", "depth")


@dataclass(frozen=True)
class DomeRecord:
    """What a dome asset file holds (plain data; field meanings: the module docstring).

    Parameters
    ----------
    name : str
        Asset name.
    mesh_hash : str
        Hash of the mesh's shape and look.
    appearance : str
        ``"own"`` or ``"checker"``.
    source_up : str or None
        Up axis the mesh file was loaded with.
    rings : list of [float, int]
        The view dome's rings.
    top : bool
        A top view.
    pivot : list of 3 float
        Quad centre.
    distance, radius : float
        Camera distance and bounding radius.
    size : int
        Level-0 image side.
    levels : int
        Pyramid levels.
    rgba, normal, depth : numpy.ndarray
        The views' stored surfaces (depth relative to ``distance``).
    """

    name: str
    mesh_hash: str
    appearance: str
    source_up: str | None
    rings: list[list[float]]
    top: bool
    pivot: list[float]
    distance: float
    radius: float
    size: int
    levels: int
    rgba: np.ndarray
    normal: np.ndarray
    depth: np.ndarray


def write_dome(path: str | os.PathLike[str], rec: DomeRecord) -> Path:
    """Write ``rec`` to ``path`` atomically (the folder must exist).

    Parameters
    ----------
    path : str or os.PathLike
        Output ``.npz`` file.
    rec : DomeRecord
        What to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    arrays = {k: np.ascontiguousarray(getattr(rec, k)) for k in _ARRAYS}
    meta = {"format": FORMAT, "version": DOME_VERSION, "kind": "dome", "name": rec.name,
            "mesh_hash": rec.mesh_hash, "appearance": rec.appearance, "source_up": rec.source_up,
            "rings": [[float(e), int(k)] for e, k in rec.rings], "top": bool(rec.top),
            "pivot": [float(x) for x in rec.pivot], "distance": float(rec.distance),
            "radius": float(rec.radius), "size": int(rec.size), "levels": int(rec.levels),
            "sha256": {k: array_digest(a) for k, a in arrays.items()}}
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta, allow_nan=False).encode(), np.uint8), **arrays)
    return write_bytes(path, buf.getvalue())


def _bad(what: str, expected: Any, got: Any) -> FileFormatError:
    return FileFormatError(expected_got(f"dome billboard asset file: {what}", expected, got))


def _get(meta: dict[str, Any], key: str, kind: type | tuple[type, ...]) -> Any:
    if key not in meta:
        raise _bad("meta", f"a {key!r} entry", "none")
    v = meta[key]
    if isinstance(v, bool) and kind is not bool:
        raise _bad(key, str(kind), repr(v))
    if not isinstance(v, kind):
        raise _bad(key, str(kind), repr(v))
    return v


def read_dome(path: str | os.PathLike[str]) -> DomeRecord:
    """Read and check a dome asset file written by :func:`write_dome`.

    Parameters
    ----------
    path : str or os.PathLike
        An asset file.

    Returns
    -------
    DomeRecord
        Its checked contents.

    Raises
    ------
    FileFormatError
        See the module docstring; a version-2 (ring) asset says to re-bake it.
    """
    p = Path(path)
    if not p.is_file():
        raise _bad("path", "an existing file", str(p))
    try:
        z = np.load(p, allow_pickle=False)
        if not isinstance(z, np.lib.npyio.NpzFile):
            raise _bad(p.name, f"a {FORMAT} .npz archive", f"a single {type(z).__name__}")
        with z:
            names = set(z.files)
            if "meta" not in names:
                raise _bad("arrays", "a 'meta' array", sorted(names))
            meta = json.loads(bytes(z["meta"]).decode("utf-8"))
            if not isinstance(meta, dict):
                raise _bad("meta", "a JSON object", type(meta).__name__)
            if meta.get("format") != FORMAT:
                raise _bad("format", FORMAT, repr(meta.get("format")))
            version = meta.get("version")
            if version != DOME_VERSION or meta.get("kind") != "dome":
                older = isinstance(version, int) and not isinstance(version, bool) and version < DOME_VERSION
                raise _bad("version", f"{DOME_VERSION} (views over the hemisphere, relightable)",
                           repr(version) + (" (a one-elevation ring asset lit by its bake light: re-bake it "
                                            "as a dome asset, bake_dome or morphkit bake --dome)"
                                            if older else ""))
            missing = [k for k in _ARRAYS if k not in names]
            if missing:
                raise _bad("arrays", f"all of {list(_ARRAYS)}", f"{missing} missing")
            arrays = {k: z[k] for k in _ARRAYS}
    except FileFormatError:
        raise
    except ARCHIVE_ERRORS as exc:
        raise _bad(p.name, f"a complete {FORMAT} .npz file",
                   f"an unreadable file ({type(exc).__name__}: {str(exc)[:120]})") from exc
    sums = _get(meta, "sha256", dict)
    for k, a in arrays.items():
        if sums.get(k) != array_digest(a):
            raise _bad(f"array {k!r}", "the checksum recorded in meta", "different bytes (corrupt file)")
    return dome_record(meta, arrays)


def dome_record(meta: dict[str, Any], arrays: dict[str, np.ndarray]) -> DomeRecord:
    """A :class:`DomeRecord` from a dome asset's metadata and arrays, checked as :func:`read_dome`
    checks a file's (a dome carried in another container, e.g. a glTF export, is read through it).

    Parameters
    ----------
    meta : dict
        The metadata (the module notes: ``name``, ``mesh_hash``, ``rings``, ``pivot``, ...).
    arrays : dict of str to numpy.ndarray
        ``rgba``, ``normal`` and ``depth``.

    Returns
    -------
    DomeRecord

    Raises
    ------
    FileFormatError
        Arrays or metadata of the wrong kind, or depths outside the views' near and far planes.
    """
    missing = [k for k in _ARRAYS if k not in arrays]
    if missing:
        raise _bad("arrays", f"all of {list(_ARRAYS)}", f"{missing} missing")
    rgba, normal, depth = arrays["rgba"], arrays["normal"], arrays["depth"]
    if rgba.dtype != np.uint8 or rgba.ndim != 4 or rgba.shape[3] != 4:
        raise _bad("rgba", "uint8 (V, n, n, 4)", f"{rgba.dtype} {rgba.shape}")
    v, n = rgba.shape[0], rgba.shape[1]
    if normal.dtype != np.int8 or normal.shape != (v, n, n, 3):
        raise _bad("normal", f"int8 {(v, n, n, 3)}", f"{normal.dtype} {normal.shape}")
    if depth.dtype != np.float16 or depth.shape != (v, n, n):
        raise _bad("depth", f"float16 {(v, n, n)}", f"{depth.dtype} {depth.shape}")
    if np.isnan(depth).any() or np.isneginf(depth).any():
        raise _bad("depth", "finite values or +inf (nothing drawn)", "NaN or -inf values")
    rings = _get(meta, "rings", list)
    for r in rings:
        finite = isinstance(r, list) and all(
            isinstance(x, int | float) and not isinstance(x, bool) and np.isfinite(x) for x in r)
        if not (finite and len(r) == 2):
            raise _bad("rings", "a list of [elevation_deg, views] (finite numbers)", repr(rings)[:200])
    pivot = _get(meta, "pivot", list)
    if len(pivot) != 3 or not all(isinstance(x, int | float) and np.isfinite(x) for x in pivot):
        raise _bad("pivot", "3 finite numbers", repr(pivot))
    src = meta.get("source_up")
    if src is not None and not isinstance(src, str):
        raise _bad("source_up", "a string or null", repr(src))
    distance, radius = float(_get(meta, "distance", (int, float))), float(_get(meta, "radius", (int, float)))
    size = _get(meta, "size", int)
    try:
        near, far = DomeCameras(np.asarray(pivot, np.float64), distance, radius, size).depth_range()
    except ValidationError as exc:
        raise _bad("meta", "a camera distance, radius and size that make the views' cameras",
                   str(exc)) from exc
    drawn = depth[np.isfinite(depth)].astype(np.float64) + distance  # linear depths of the drawn texels
    slack = tol.DOME_DEPTH_SLACK_REL * far
    if drawn.size and (drawn.min() < near - slack or drawn.max() > far + slack):
        raise _bad("depth", f"drawn depths (depth + distance {distance:g}) within the views' near and far "
                   f"planes [{near:g}, {far:g}], or +inf (nothing drawn)",
                   f"{drawn.min():g} to {drawn.max():g}"
                   + (" (behind the camera)" if drawn.min() <= 0 else ""))
    return DomeRecord(
        name=_get(meta, "name", str), mesh_hash=_get(meta, "mesh_hash", str),
        appearance=_get(meta, "appearance", str), source_up=src, rings=rings, top=_get(meta, "top", bool),
        pivot=[float(x) for x in pivot], distance=distance, radius=radius, size=size,
        levels=_get(meta, "levels", int), rgba=rgba, normal=normal, depth=depth)


def is_dome_file(path: str | Path) -> bool:
    """Whether ``path`` is a regular file whose metadata says it is a dome asset
    (``format`` :data:`~.assetfile.FORMAT`, ``kind`` ``"dome"``), whatever its version: which
    reader to hand it to. Anything unreadable answers False (its reader then says why).

    Parameters
    ----------
    path : str or pathlib.Path
        An ``.npz`` asset file.

    Returns
    -------
    bool
    """
    meta = peek_meta(path)
    return meta is not None and meta.get("format") == FORMAT and meta.get("kind") == "dome"

