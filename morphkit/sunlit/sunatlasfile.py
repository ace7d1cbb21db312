"""The sun atlas file: one versioned ``.npz`` holding a :class:`~.sunatlas.SunAtlas`.

Format ``"morphkit-sun-atlas"``, version :data:`SUN_ATLAS_VERSION`. Written atomically
(:func:`morphkit.files.fileio.write_bytes`), read with ``allow_pickle=False``:

============  =====================  =====================================================
array         dtype, shape           content
============  =====================  =====================================================
``meta``      uint8 ``(n,)``         UTF-8 JSON, below
``depth``     float16 ``(V, n, n)``  each light view's depth minus the camera distance
                                     (``+inf`` where nothing is drawn)
``coverage``  uint8 ``(V, n, n)``    255 where the mesh is drawn
============  =====================  =====================================================

``meta``: ``format``, ``version``, ``mesh_hash`` (64 hex digits), ``rings`` (list of
``[elevation_deg, views]``), ``top``, ``pivot``, ``distance``, ``radius``, ``size`` and ``sha256``
(per array). :func:`read_sun_atlas` raises :class:`~morphkit.errors.FileFormatError`, naming the
file, for a missing, truncated or corrupt file, another format or version, missing keys or
arrays, a key of another JSON type than written (``"top": "false"``, ``"size": 16.5``: never
read as something else), arrays that do not fit the dome and the cameras, drawn depths outside
the light views' near and far planes (``distance -+ 1.5 radius``, with
:data:`~morphkit.tol.DOME_DEPTH_SLACK_REL` for the float16 rounding: a depth behind the camera
is a damaged file, not a shadow), or a checksum that does not match.
"""

from __future__ import annotations

import io
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import tol
from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import ARCHIVE_ERRORS, array_digest, open_regular, write_bytes
from ..views.dome import MAX_RINGS, ViewDome
from ..views.domecameras import DomeCameras
from .sunatlas import SunAtlas

__all__ = ["SUN_ATLAS_FORMAT", "SUN_ATLAS_VERSION", "write_sun_atlas", "read_sun_atlas", "SavableSunAtlas"]

#: The ``format`` entry of a sun atlas file's metadata.
SUN_ATLAS_FORMAT = "morphkit-sun-atlas"
#: Version of the sun atlas file.
SUN_ATLAS_VERSION = 1

_ARRAYS = ("depth", "coverage")
_HEX64 = re.compile(r"[0-9a-f]{64}")


def write_sun_atlas(path: str | os.PathLike[str], atlas: SunAtlas) -> Path:
    """Write ``atlas`` to ``path`` atomically (the folder must exist).

    Parameters
    ----------
    path : str or os.PathLike
        Output ``.npz`` file.
    atlas : SunAtlas
        What to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    arrays = {k: np.ascontiguousarray(getattr(atlas, k)) for k in _ARRAYS}
    cams = atlas.cameras
    meta = {"format": SUN_ATLAS_FORMAT, "version": SUN_ATLAS_VERSION, "mesh_hash": atlas.mesh_hash,
            "rings": [[float(e), int(k)] for e, k in atlas.dome.rings], "top": bool(atlas.dome.top),
            "pivot": [float(x) for x in cams.pivot], "distance": float(cams.distance),
            "radius": float(cams.radius), "size": int(cams.shape[0]),
            "sha256": {k: array_digest(a) for k, a in arrays.items()}}
    buf = io.BytesIO()
    np.savez(buf, meta=np.frombuffer(json.dumps(meta, allow_nan=False).encode(), np.uint8), **arrays)
    return write_bytes(path, buf.getvalue())


def _bad(path: Path, what: str, expected: Any, got: Any) -> FileFormatError:
    return FileFormatError(expected_got(f"sun atlas file {str(path)!r}: {what}", expected, got))


def _number(v: Any) -> bool:
    return type(v) in (int, float) and math.isfinite(v)


def _ring(v: Any) -> bool:
    return isinstance(v, list) and len(v) == 2 and _number(v[0]) and type(v[1]) is int


#: The metadata entries besides format, version and sha256: what each must be, and its test.
_META: dict[str, tuple[str, Any]] = {
    "mesh_hash": ("64 hex digits", lambda v: isinstance(v, str) and _HEX64.fullmatch(v) is not None),
    "rings": (f"1 to {MAX_RINGS} [elevation_deg, views] (a number and an integer)",
              lambda v: isinstance(v, list) and 1 <= len(v) <= MAX_RINGS and all(map(_ring, v))),
    "top": ("true or false", lambda v: isinstance(v, bool)),
    "pivot": ("3 finite numbers", lambda v: isinstance(v, list) and len(v) == 3 and all(map(_number, v))),
    "distance": ("a finite number", _number),
    "radius": ("a finite number", _number),
    "size": ("an integer", lambda v: type(v) is int),
}


def read_sun_atlas(path: str | os.PathLike[str]) -> SunAtlas:
    """Read and check a sun atlas file written by :func:`write_sun_atlas`.

    Parameters
    ----------
    path : str or os.PathLike
        A sun atlas file.

    Returns
    -------
    SunAtlas
        The atlas, as it was written.

    Raises
    ------
    FileFormatError
        See the module docstring.
    """
    p = Path(path)
    try:
        with open_regular(p, f"sun atlas file {str(p)!r}") as f:
            data = f.read()
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            names = set(z.files)
            if "meta" not in names:
                raise _bad(p, "arrays", "a 'meta' array", sorted(names))
            meta = json.loads(bytes(z["meta"]).decode("utf-8"))
            if not isinstance(meta, dict) or meta.get("format") != SUN_ATLAS_FORMAT:
                got = meta.get("format") if isinstance(meta, dict) else type(meta).__name__
                raise _bad(p, "format", SUN_ATLAS_FORMAT, repr(got))
            version = meta.get("version")
            if type(version) is not int or version != SUN_ATLAS_VERSION:
                raise _bad(p, "version", SUN_ATLAS_VERSION, repr(version) + " (re-bake it)")
            missing = [k for k in _ARRAYS if k not in names]
            if missing:
                raise _bad(p, "arrays", f"all of {list(_ARRAYS)}", f"{missing} missing")
            arrays = {k: z[k] for k in _ARRAYS}
    except FileFormatError:
        raise
    except (*ARCHIVE_ERRORS, AttributeError) as exc:
        raise _bad(p, "content", f"a complete {SUN_ATLAS_FORMAT} .npz file",
                   f"an unreadable file ({type(exc).__name__}: {str(exc)[:120]})") from exc
    sums = meta.get("sha256")
    for k, a in arrays.items():
        if not isinstance(sums, dict) or sums.get(k) != array_digest(a):
            raise _bad(p, f"array {k!r}", "the checksum recorded in meta", "different bytes (corrupt file)")
    for key, (want, ok) in _META.items():
        if key not in meta:
            raise _bad(p, "meta", f"a {key!r} entry", f"keys {sorted(meta)}"[:200])
        if not ok(meta[key]):
            raise _bad(p, key, want, repr(meta[key])[:120])
    try:
        dome = ViewDome(tuple((float(e), k) for e, k in meta["rings"]), meta["top"])
        cams = DomeCameras(np.asarray(meta["pivot"], np.float64), float(meta["distance"]),
                           float(meta["radius"]), meta["size"])
        atlas = SunAtlas(dome, cams, arrays["depth"], arrays["coverage"], meta["mesh_hash"])
    except ValidationError as exc:
        raise _bad(p, "meta", "a dome, cameras and arrays that fit them", f"{type(exc).__name__}: {exc}"
                   ) from exc
    drawn = atlas.depth[np.isfinite(atlas.depth)].astype(np.float64)  # offsets from the distance
    reach = 1.5 * cams.radius + tol.DOME_DEPTH_SLACK_REL * (cams.distance + 1.5 * cams.radius)
    if drawn.size and np.abs(drawn).max() > reach:
        raise _bad(p, "depth", f"drawn depths within the light views' near and far planes (offsets "
                   f"within +-{1.5 * cams.radius:g} of the distance {cams.distance:g}), or +inf",
                   f"offsets {drawn.min():g} to {drawn.max():g}")
    return atlas


@dataclass(frozen=True, eq=False)
class SavableSunAtlas:
    """A sun atlas that writes itself to its file (what a bake kind returns:
    :class:`morphkit.bake.kinds.SavableAsset`).

    Parameters
    ----------
    atlas : SunAtlas
        The atlas.
    """

    atlas: SunAtlas

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the atlas to ``path`` atomically (:func:`write_sun_atlas`).

        Parameters
        ----------
        path : str or os.PathLike
            Output ``.npz`` file; its folder exists.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        return write_sun_atlas(path, self.atlas)
