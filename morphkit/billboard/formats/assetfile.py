"""The billboard asset file: one versioned ``.npz`` (images + a JSON metadata blob).

Layout (format :data:`FORMAT`, version :data:`VERSION`), written atomically
through :func:`morphkit.files.fileio.atomic_write` and read with
``np.load(..., allow_pickle=False)``:

==============  =======================  ==================================================
array           dtype, shape             content
==============  =======================  ==================================================
``meta``        uint8 ``(n,)``           UTF-8 JSON, below
``images``      uint8 ``(K, H, W, 4)``   the reference views, straight RGBA (the renders)
``depth``       float16 ``(K, H, W)``    their linear depth (``+inf`` background); only the
                                         per-pixel layer keys of the morphs are made from it
``points3d``    float32 ``(N, 3)``       every pair's correspondences as object-frame points
                                         (pair ``p`` holds rows ``offsets[p]:offsets[p+1]``);
                                         their pixels are their projections in the two views
``offsets``     int64 ``(P + 1,)``       see ``points3d``
``front``       uint8 ``(H, W, 4)``      the front view (azimuth 0) for the classic billboard;
                                         ``(0, 0, 4)`` when a reference is at azimuth 0
==============  =======================  ==================================================

``meta``: ``format``, ``version``, ``name``, ``mesh_hash`` (sha256 hex of
the shape and the look, :func:`morphkit.billboard.mesh_hash`), ``appearance``
(``"own"`` or ``"checker"``), ``source_up`` (``"z"``, ``"y"`` or null: the up
axis the mesh file was loaded with),
``ring`` (``views``, ``arc_deg``, ``elevation_deg``), ``quad`` (``pivot``,
``distance``, ``elevation_deg``, ``half_extent``, ``shape``), ``levels``,
``layers`` (the morphs' ``ViewMorpher(layers=...)``), ``pairs``,
``front_view`` (index of the reference at azimuth 0, or -1), ``cameras``
(per view: ``azimuth_deg``, ``K`` 3x3, ``cam2world`` 4x4 -- for readers; the
loader checks them against the camera rule) and ``sha256`` (per array, the
hash of its bytes, checked on load). Everything a morpher needs is in the
file: no rendering on load.

:func:`read_record` raises :class:`~morphkit.errors.FileFormatError` -- never a
``KeyError``/``ValueError``/``TypeError`` -- for a missing, truncated or
corrupt file, another format or version, a missing key or array, a wrong dtype
or shape, or an array whose checksum does not match.
"""

from __future__ import annotations

import io
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import FileFormatError, expected_got
from ...files.fileio import ARCHIVE_ERRORS, array_digest, write_bytes

__all__ = ["FORMAT", "VERSION", "APPEARANCES", "AssetRecord", "write_record", "read_record", "peek_meta"]

#: The format name stored in every billboard asset file.
FORMAT = "morphkit-billboard"
#: The asset file format version this code reads and writes (another is a FileFormatError).
#: 2: ``appearance`` and ``source_up`` recorded, ``mesh_hash`` covers the look (version 1
#: files were baked in the 3-D checker whatever the mesh's look: re-bake them).
VERSION = 2

#: The looks an asset can be baked in (``meta['appearance']``): the mesh's own, or the 3-D checker.
APPEARANCES = ("own", "checker")

_ARRAYS = ("images", "depth", "points3d", "offsets", "front")


@dataclass(frozen=True)
class AssetRecord:
    """What an asset file holds (plain data; :class:`morphkit.billboard.BillboardAsset`
    is built from it). Field meanings: the module docstring.

    Parameters
    ----------
    name : str
        Asset name.
    mesh_hash : str
        sha256 hex of the source mesh.
    ring : dict
        ``views``, ``arc_deg``, ``elevation_deg``.
    quad : dict
        ``pivot``, ``distance``, ``elevation_deg``, ``half_extent``, ``shape``.
    levels : int
        Pyramid levels.
    layers : int or "auto"
        The morphs' ``ViewMorpher(layers=...)``.
    pairs : list of (int, int)
        Reference index pairs that are morphed.
    front_view : int
        Index of the reference at azimuth 0, or ``-1``.
    cameras : list of dict
        Per view: ``azimuth_deg``, ``K`` (3x3), ``cam2world`` (4x4, object frame).
    images : (K, H, W, 4) uint8
        Reference views, straight RGBA.
    depth : (K, H, W) float16
        Their linear depth, ``+inf`` background.
    points3d : (N, 3) float32
        All pairs' correspondences, object frame.
    offsets : (P + 1,) int64
        Pair ``p`` holds ``points3d[offsets[p]:offsets[p + 1]]``.
    front : (H, W, 4) uint8
        Front view (straight RGBA), or ``(0, 0, 4)`` when a reference is at azimuth 0.
    appearance : str
        The look the references were rendered in: ``"own"`` or ``"checker"``.
    source_up : str or None
        The up axis the mesh file was loaded with (``"z"``, ``"y"``), None when not known.
    """

    name: str
    mesh_hash: str
    ring: dict[str, Any]
    quad: dict[str, Any]
    levels: int
    layers: int | str
    pairs: list[tuple[int, int]]
    front_view: int
    cameras: list[dict[str, Any]]
    images: np.ndarray
    depth: np.ndarray
    points3d: np.ndarray
    offsets: np.ndarray
    front: np.ndarray
    appearance: str = "own"
    source_up: str | None = None


def write_record(path: str | os.PathLike[str], rec: AssetRecord) -> Path:
    """Write ``rec`` to ``path`` (atomically; the folder must exist). Returns ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        Output ``.npz`` file.
    rec : AssetRecord
        What to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    arrays = {k: np.ascontiguousarray(getattr(rec, k)) for k in _ARRAYS}
    meta = {"format": FORMAT, "version": VERSION, "name": rec.name, "mesh_hash": rec.mesh_hash,
            "ring": rec.ring, "quad": rec.quad, "levels": rec.levels, "layers": rec.layers,
            "pairs": [list(p) for p in rec.pairs], "front_view": rec.front_view, "cameras": rec.cameras,
            "appearance": rec.appearance, "source_up": rec.source_up,
            "sha256": {k: array_digest(a) for k, a in arrays.items()}}
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta, allow_nan=False).encode(), np.uint8), **arrays)
    return write_bytes(path, buf.getvalue())


def _bad(what: str, expected: Any, got: Any) -> FileFormatError:
    return FileFormatError(expected_got(f"billboard asset file: {what}", expected, got))


def read_record(path: str | os.PathLike[str]) -> AssetRecord:
    """Read and check an asset file written by :func:`write_record`.

    Parameters
    ----------
    path : str or os.PathLike
        An asset file.

    Returns
    -------
    AssetRecord
        Its checked contents.

    Raises
    ------
    FileFormatError
        See the module docstring.
    """
    p = Path(path)
    if not p.is_file():
        raise _bad("path", "an existing file", str(p))
    try:
        z = np.load(p, allow_pickle=False)
        if not isinstance(z, np.lib.npyio.NpzFile):  # a bare .npy array
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
            if version != VERSION:
                older = isinstance(version, int) and not isinstance(version, bool) and version < VERSION
                raise _bad("version", VERSION, repr(version) + (
                    " (an older asset file: re-bake it with this morphkit, e.g. bake_asset or "
                    "morphkit bake --billboard)" if older else ""))
            missing = [k for k in _ARRAYS if k not in names]
            if missing:
                raise _bad("arrays", f"all of {list(_ARRAYS)}", f"{missing} missing")
            arrays = {k: z[k] for k in _ARRAYS}
    except FileFormatError:
        raise
    except ARCHIVE_ERRORS as exc:  # json.JSONDecodeError is a ValueError
        raise _bad(p.name, f"a complete {FORMAT} .npz file", f"an unreadable file "
                   f"({type(exc).__name__}: {str(exc)[:120]})") from exc
    return _record(meta, arrays)


def peek_meta(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The JSON metadata of an ``.npz`` asset file (ring or dome, any version), read without its
    arrays; None when ``path`` is not a regular file or its metadata cannot be read (its reader
    then says why). For telling files apart before reading one, never for trusting it.

    Parameters
    ----------
    path : str or os.PathLike
        An ``.npz`` asset file.

    Returns
    -------
    dict or None
    """
    p = Path(path)
    try:
        if not p.is_file():  # a FIFO or a folder is no asset file: never opened here
            return None
        with np.load(p, allow_pickle=False) as z:
            meta = json.loads(bytes(z["meta"]).decode("utf-8"))
    except Exception:  # noqa: BLE001 -- any failure: not recognised (the reader reports it)
        return None
    return meta if isinstance(meta, dict) else None


def _get(meta: dict[str, Any], key: str, kind: type | tuple[type, ...], where: str = "meta") -> Any:
    if key not in meta:
        raise _bad(where, f"a key {key!r}", f"keys {sorted(meta)}")
    v = meta[key]
    if isinstance(v, bool) and bool not in (kind if isinstance(kind, tuple) else (kind,)):
        raise _bad(f"{where}[{key!r}]", _kind_name(kind), repr(v))
    if not isinstance(v, kind):
        raise _bad(f"{where}[{key!r}]", _kind_name(kind), f"{type(v).__name__} {v!r}"[:100])
    return v


def _kind_name(kind: type | tuple[type, ...]) -> str:
    ks = kind if isinstance(kind, tuple) else (kind,)
    return " or ".join(k.__name__ for k in ks)


def _numbers(v: Any, n: int, what: str) -> list[float]:
    if not isinstance(v, list) or len(v) != n or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
        raise _bad(what, f"a list of {n} numbers", repr(v)[:100])
    return [float(x) for x in v]


def _record(meta: dict[str, Any], arrays: dict[str, np.ndarray]) -> AssetRecord:
    sums = _get(meta, "sha256", dict)
    for k, a in arrays.items():
        if sums.get(k) != array_digest(a):
            raise _bad(f"array {k!r}", "the checksum stored in its metadata", "different bytes (corrupt)")
    ring = _get(meta, "ring", dict)
    views = _get(ring, "views", int, "ring")
    _get(ring, "arc_deg", (int, float), "ring")
    _get(ring, "elevation_deg", (int, float), "ring")
    quad = _get(meta, "quad", dict)
    _numbers(_get(quad, "pivot", list, "quad"), 3, "quad['pivot']")
    _get(quad, "distance", (int, float), "quad")
    _get(quad, "elevation_deg", (int, float), "quad")
    _numbers(_get(quad, "half_extent", list, "quad"), 2, "quad['half_extent']")
    shape = _get(quad, "shape", list, "quad")
    if len(shape) != 2 or not all(isinstance(x, int) and not isinstance(x, bool) and x > 0 for x in shape):
        raise _bad("quad['shape']", "two positive ints (H, W)", repr(shape))
    h, w = shape
    layers = _get(meta, "layers", (int, str))
    pairs_raw = _get(meta, "pairs", list)
    pairs = []
    for pr in pairs_raw:
        if not (isinstance(pr, list) and len(pr) == 2 and all(isinstance(x, int) and not isinstance(x, bool)
                                                              and 0 <= x < views for x in pr)):
            raise _bad("meta['pairs']", f"pairs of view indices in [0, {views})", repr(pr))
        pairs.append((pr[0], pr[1]))
    front_view = _get(meta, "front_view", int)
    cameras = _get(meta, "cameras", list)
    if len(cameras) != views or not all(isinstance(c, dict) for c in cameras):
        raise _bad("meta['cameras']", f"{views} camera objects", f"{len(cameras)} entries")
    images, depth, pts, offsets, front = (arrays[k] for k in _ARRAYS)
    for name, a, dtype, shp in (("images", images, np.uint8, (views, h, w, 4)),
                                ("depth", depth, np.float16, (views, h, w)),
                                ("offsets", offsets, np.int64, (len(pairs) + 1,))):
        if a.dtype != dtype or a.shape != shp:
            raise _bad(f"array {name!r}", f"{np.dtype(dtype)} of shape {shp}",
                       f"{a.dtype} of shape {a.shape}")
    if pts.dtype != np.float32 or pts.ndim != 2 or pts.shape[1] != 3 or not np.all(np.isfinite(pts)):
        raise _bad("array 'points3d'", "finite float32 of shape (N, 3)", f"{pts.dtype} of shape {pts.shape}")
    if offsets[0] != 0 or offsets[-1] != len(pts) or np.any(np.diff(offsets) < 0):
        raise _bad("array 'offsets'", f"non-decreasing from 0 to {len(pts)}", offsets.tolist()[:12])
    want_front = (0, 0, 4) if 0 <= front_view < views else (h, w, 4)
    if front_view >= views or front_view < -1:
        raise _bad("meta['front_view']", f"-1 or a view index in [0, {views})", front_view)
    if front.dtype != np.uint8 or front.shape != want_front:
        raise _bad("array 'front'", f"uint8 of shape {want_front}", f"{front.dtype} of shape {front.shape}")
    bad = int(np.count_nonzero(np.isnan(depth) | (depth == -np.inf)))
    if bad:  # as the shadow atlas loader: finite or +inf depths
        raise _bad("array 'depth'", "finite or +inf depths (+inf for background)", f"{bad} NaN/-inf values")
    appearance = _get(meta, "appearance", str)
    if appearance not in APPEARANCES:
        raise _bad("meta['appearance']", f"one of {list(APPEARANCES)}", repr(appearance))
    source_up = _get(meta, "source_up", (str, type(None)))
    if source_up not in (None, "z", "y"):
        raise _bad("meta['source_up']", "'z', 'y' or null", repr(source_up))
    return AssetRecord(_get(meta, "name", str), _get(meta, "mesh_hash", str), ring, quad,
                       _get(meta, "levels", int), layers, pairs, front_view, cameras,
                       images, depth, pts, offsets, front, appearance, source_up)
