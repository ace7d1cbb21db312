"""The shadow atlas file: one versioned ``.npz`` (maps, anchors, control points, light, rig).

Written atomically through :mod:`morphkit.fileio`; read with ``allow_pickle=False``
and checked: a missing, truncated, corrupt, other-format or other-version file,
or one baked for another light, is a :class:`~morphkit.errors.FileFormatError`.
"""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FileFormatError, expected_got
from ..fileio import write_bytes
from ..scene import DirectionalLight, PointLight
from .atlas import ShadowAtlas
from .rig import LightRig

__all__ = ["ATLAS_FORMAT", "ATLAS_VERSION", "save_atlas", "load_atlas", "light_to_dict", "light_from_dict"]

#: The format name stored in every atlas file.
ATLAS_FORMAT = "morphkit-shadow-atlas"
#: The atlas file format version this code reads and writes (another is a FileFormatError).
ATLAS_VERSION = 1


def save_atlas(atlas: ShadowAtlas, path: str | Path) -> Path:
    """Write ``atlas`` to one ``.npz`` file (maps, anchors, grid, light, range, rig, version), atomically
    (:mod:`morphkit.fileio`: an interrupted save leaves the file that was there)."""
    path = Path(path)
    meta = {
        "format": ATLAS_FORMAT, "version": ATLAS_VERSION,
        "light": light_to_dict(atlas.rig.light),
        "rig": atlas.rig.params(),
        "control_grid": list(atlas.control_grid),
        "anchor_kind": atlas.anchor_kind,
    }
    buf = io.BytesIO()
    np.savez_compressed(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8),
                        xs=atlas.xs, ys=atlas.ys, maps=atlas.maps, anchors=atlas.anchors,
                        plane_anchors=atlas.plane_anchors, control=atlas.control,
                        triangles=atlas.triangles)
    write_bytes(path, buf.getvalue())
    return path


def load_atlas(path: str | Path, *, light: DirectionalLight | PointLight | None = None
               ) -> ShadowAtlas:
    """Read an atlas written by :func:`save_atlas` (or :meth:`ShadowAtlas.save`).

    Raises
    ------
    FileFormatError
        Missing, truncated or corrupt file; another format or version; or,
        when ``light`` is given, an atlas baked for another light.
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in ("meta", "xs", "ys", "maps", "anchors", "plane_anchors",
                                      "control", "triangles")}
        meta = json.loads(bytes(data["meta"]).decode())
    except FileNotFoundError as exc:
        raise FileFormatError(expected_got("atlas file", "an existing file", str(path))) from exc
    except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError, json.JSONDecodeError,
            UnicodeDecodeError) as exc:
        raise FileFormatError(expected_got(
            "atlas file", f"a complete {ATLAS_FORMAT} .npz file",
            f"an unreadable file {path.name} ({type(exc).__name__}: {exc})")) from exc
    if meta.get("format") != ATLAS_FORMAT:
        raise FileFormatError(expected_got("atlas format", ATLAS_FORMAT, meta.get("format")))
    if meta.get("version") != ATLAS_VERSION:
        raise FileFormatError(expected_got("atlas version", ATLAS_VERSION, meta.get("version")))
    stored = light_from_dict(meta["light"])
    if light is not None and light_to_dict(light) != meta["light"]:
        raise FileFormatError(expected_got("atlas light", f"the light it is used with "
                                           f"{light_to_dict(light)}", f"baked for {meta['light']}"))
    rig = LightRig.from_params(stored, meta["rig"])
    atlas = ShadowAtlas(rig, data["xs"], data["ys"], data["maps"], data["anchors"], data["plane_anchors"],
                tuple(meta["control_grid"]), meta["anchor_kind"])
    if atlas.maps.shape[2:] != rig.shape or atlas.maps.shape[:2] != (len(atlas.ys), len(atlas.xs)):
        raise FileFormatError(expected_got("atlas maps", f"shape ({len(atlas.ys)}, {len(atlas.xs)}, "
                                           f"{rig.shape[0]}, {rig.shape[1]})", atlas.maps.shape))
    # control points and triangles are stored for other readers; they must
    # agree with what the anchors and the light rig give
    if (data["control"].shape != atlas.control.shape
            or not np.allclose(data["control"], atlas.control, rtol=0, atol=1e-6)
            or not np.array_equal(data["triangles"], atlas.triangles)):
        raise FileFormatError(expected_got("atlas control points", "consistent with its anchors "
                                           "and light rig", "different values (corrupt file?)"))
    return atlas


def light_to_dict(light: DirectionalLight | PointLight) -> dict[str, Any]:
    """The JSON form of a light, as stored in an atlas file.

    Parameters
    ----------
    light : DirectionalLight or PointLight
        The light (world frame).

    Returns
    -------
    dict
        ``{"type": "directional", "direction": [x, y, z]}`` or
        ``{"type": "point", "position": [x, y, z]}`` (floats rounded to 12 digits).
    """
    if isinstance(light, DirectionalLight):
        return {"type": "directional", "direction": [round(float(v), 12) for v in light.direction]}
    return {"type": "point", "position": [round(float(v), 12) for v in light.position]}


def light_from_dict(d: dict[str, Any]) -> DirectionalLight | PointLight:
    """The light stored by :func:`light_to_dict`.

    Parameters
    ----------
    d : dict
        A dict as :func:`light_to_dict` writes it.

    Returns
    -------
    DirectionalLight or PointLight
        The light (world frame).

    Raises
    ------
    FileFormatError
        When ``d["type"]`` is neither ``"directional"`` nor ``"point"``.
    """
    if d.get("type") == "directional":
        return DirectionalLight(np.array(d["direction"]))
    if d.get("type") == "point":
        return PointLight(np.array(d["position"]))
    raise FileFormatError(expected_got("atlas light type", "'directional' or 'point'", d.get("type")))
