"""The shadow atlas file: one versioned ``.npz`` (maps, anchors, control points, light, rig).

Written atomically through :mod:`morphkit.files.fileio`; read with ``allow_pickle=False``
and checked before anything is built from it:

* every array's dtype, shape and SHA-256 checksum are stored in the metadata
  and verified (a damaged file, two map rows swapped, surface and plane anchors
  swapped: the checksum differs);
* values: depths finite or ``+inf`` (no NaN, no ``-inf``), anchors, control points
  and sample positions finite, sample positions increasing from the range's
  ``lo`` to its ``hi``; shapes consistent with each other and with the rig;
* every metadata key is present and of its type (a missing key or a wrongly
  typed field names the field; never a raw ``KeyError``/``TypeError``/``ValueError``);
* the stored control points agree with those the anchors and the rig give.

Any failure is a :class:`~morphkit.errors.FileFormatError`. Files of another
version are refused (re-bake to get a current one); version 1 had no checksums, version 2
no record of its mesh (``mesh_sha256``: the occluder's :func:`morphkit.meshes.shape_hash`,
which :func:`morphkit.programs.playback.baked_mesh` checks the mesh it loads against).
"""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from ... import tol
from ...errors import FileFormatError, MorphkitError, ValidationError, expected_got
from ...files.fileio import ARCHIVE_ERRORS, array_digest, open_regular, write_bytes
from ...scene import DirectionalLight, PointLight
from ...validate import as_pose
from ..baked import BakedAtlas
from ..rig import LightRig, MotionRange

__all__ = ["ATLAS_FORMAT", "ATLAS_VERSION", "ARRAYS", "save_atlas", "load_atlas",
           "light_to_dict", "light_from_dict"]

#: The format name stored in every atlas file.
ATLAS_FORMAT = "morphkit-shadow-atlas"
#: Version 3: the occluder's :func:`morphkit.meshes.shape_hash` (``"mesh_sha256"``), after
#: version 2's per-array dtype, shape and SHA-256 in the metadata (``"arrays"``).
ATLAS_VERSION = 3

#: The arrays of an atlas file besides ``meta`` (the UTF-8 JSON metadata as uint8).
ARRAYS = ("xs", "ys", "maps", "anchors", "plane_anchors", "control", "triangles")

_ANCHOR_KINDS = ("sample", "shared", "plane")


def save_atlas(atlas: BakedAtlas, path: str | Path) -> Path:
    """Write ``atlas`` to one ``.npz`` file (maps, anchors, grid, light, range, rig, version,
    and each array's dtype, shape and SHA-256), atomically (:mod:`morphkit.files.fileio`: an
    interrupted save leaves the file that was there).

    Parameters
    ----------
    atlas : morphkit.shadow.baked.BakedAtlas
        The baked atlas (a :class:`~morphkit.shadow.atlas.ShadowAtlas` saves its
        ``baked`` data: :meth:`ShadowAtlas.save <morphkit.shadow.atlas.ShadowAtlas.save>`).
    path : str or pathlib.Path
        The ``.npz`` file to write; its folder must exist.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    arrays = {"xs": atlas.xs, "ys": atlas.ys, "maps": atlas.maps, "anchors": atlas.anchors,
              "plane_anchors": atlas.plane_anchors, "control": atlas.control,
              "triangles": atlas.triangles}
    arrays = {k: np.ascontiguousarray(v) for k, v in arrays.items()}
    meta = {
        "format": ATLAS_FORMAT, "version": ATLAS_VERSION,
        "light": light_to_dict(atlas.rig.light),
        "rig": atlas.rig.params(),
        "control_grid": list(atlas.control_grid),
        "anchor_kind": atlas.anchor_kind,
        "mesh_sha256": atlas.mesh_sha256,
        "arrays": {k: {"dtype": str(v.dtype), "shape": list(v.shape), "sha256": array_digest(v)}
                   for k, v in arrays.items()},
    }
    buf = io.BytesIO()
    np.savez_compressed(buf, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8), **arrays)
    write_bytes(path, buf.getvalue())
    return path


def load_atlas(path: str | Path, *, light: DirectionalLight | PointLight | None = None
               ) -> BakedAtlas:
    """Read an atlas written by :func:`save_atlas` (or :meth:`ShadowAtlas.save`), checked
    (module docstring).

    Parameters
    ----------
    path : path-like
        The ``.npz`` file.
    light : DirectionalLight or PointLight, optional
        The light the atlas will be used with; it must be the one it was baked for.

    Returns
    -------
    morphkit.shadow.baked.BakedAtlas
        The baked data (:meth:`ShadowAtlas.load <morphkit.shadow.atlas.ShadowAtlas.load>`
        makes a ready-to-use atlas of it).

    Raises
    ------
    FileFormatError
        Missing, truncated or corrupt file (a checksum differs); another format
        or version; missing or wrongly typed metadata; NaN or ``-inf`` depths,
        non-finite anchors or positions, inconsistent shapes; pickled object
        arrays; or, when ``light`` is given, an atlas baked for another light.
    ValidationError
        ``light`` is neither a DirectionalLight nor a PointLight.
    """
    path = Path(path)
    if light is not None and not isinstance(light, DirectionalLight | PointLight):
        raise ValidationError(expected_got("light", "a DirectionalLight or PointLight",
                                           type(light).__name__))
    data = _read_arrays(path)
    meta = _read_meta(data["meta"])
    if meta.get("format") != ATLAS_FORMAT:
        raise FileFormatError(expected_got("atlas format", ATLAS_FORMAT, repr(meta.get("format"))[:80]))
    version = meta.get("version")
    if type(version) is not int or version != ATLAS_VERSION:
        raise FileFormatError(expected_got(
            "atlas version", f"{ATLAS_VERSION} (files of other versions are not read: re-bake the atlas "
            "with morphkit.shadow.bake_atlas and save it again to get one)", repr(version)[:80]))
    stored = light_from_dict(_key(meta, "light", "atlas metadata"))
    if light is not None and light_to_dict(light) != light_to_dict(stored):
        raise FileFormatError(expected_got("atlas light", f"the light it is used with "
                                           f"{light_to_dict(light)}", f"baked for {light_to_dict(stored)}"))
    rig = _rig_from_meta(stored, _key(meta, "rig", "atlas metadata"))
    grid = _key(meta, "control_grid", "atlas metadata")
    if not (isinstance(grid, list) and len(grid) == 2 and all(_is_int(v) and v >= 2 for v in grid)):
        raise FileFormatError(expected_got("atlas control_grid", "[rows, cols], integers >= 2",
                                           repr(grid)[:80]))
    kind = _key(meta, "anchor_kind", "atlas metadata")
    if kind not in _ANCHOR_KINDS:
        raise FileFormatError(expected_got("atlas anchor_kind", "'sample', 'shared' or 'plane'",
                                           repr(kind)[:80]))
    mesh_sha256 = _key(meta, "mesh_sha256", "atlas metadata")
    if mesh_sha256 is not None and not (isinstance(mesh_sha256, str)
                                        and re.fullmatch(r"[0-9a-f]{64}", mesh_sha256)):
        raise FileFormatError(expected_got("atlas mesh_sha256", "64 hex digits or null",
                                           repr(mesh_sha256)[:80]))
    _check_checksums(data, _key(meta, "arrays", "atlas metadata"))
    _check_values(data, rig, (grid[0], grid[1]))
    try:
        atlas = BakedAtlas(rig, data["xs"], data["ys"], data["maps"], data["anchors"],
                           data["plane_anchors"], (grid[0], grid[1]), kind, mesh_sha256)
    except (MorphkitError, ArithmeticError, IndexError, TypeError, ValueError) as exc:
        raise FileFormatError(expected_got("atlas", "data that builds an atlas",
                                           f"{type(exc).__name__}: {exc}"[:200])) from exc
    # control points and triangles are stored for other readers; they must
    # agree with what the anchors and the light rig give
    if (data["control"].shape != atlas.control.shape
            or not np.allclose(data["control"], atlas.control, rtol=0, atol=tol.PX_EQUAL)
            or not np.array_equal(data["triangles"], atlas.triangles)):
        raise FileFormatError(expected_got("atlas control points", "consistent with its anchors "
                                           "and light rig", "different values (corrupt file?)"))
    return atlas


def light_to_dict(light: DirectionalLight | PointLight) -> dict[str, Any]:
    """The light as the atlas file stores it (JSON types; rounded to 12 digits).

    Parameters
    ----------
    light : DirectionalLight or PointLight
        The light (direction or position in world frame).

    Returns
    -------
    dict
        ``{"type": "directional", "direction": [x, y, z]}`` or
        ``{"type": "point", "position": [x, y, z]}``.
    """
    if isinstance(light, DirectionalLight):
        return {"type": "directional", "direction": [round(float(v), 12) for v in light.direction]}
    return {"type": "point", "position": [round(float(v), 12) for v in light.position]}


def light_from_dict(d: Any) -> DirectionalLight | PointLight:
    """The light of :func:`light_to_dict`'s dict, checked (:class:`FileFormatError` if not one).

    Parameters
    ----------
    d : Any
        The value read from the file.

    Returns
    -------
    DirectionalLight or PointLight
        The light.
    """
    if not isinstance(d, dict):
        raise FileFormatError(expected_got("atlas light", "an object", repr(d)[:80]))
    kind = d.get("type")
    if kind not in ("directional", "point"):
        raise FileFormatError(expected_got("atlas light type", "'directional' or 'point'", repr(kind)[:80]))
    key = "direction" if kind == "directional" else "position"
    v = _vector(_key(d, key, "atlas light"), f"atlas light {key}", (3,))
    try:
        return DirectionalLight(v) if kind == "directional" else PointLight(v)
    except MorphkitError as exc:
        raise FileFormatError(expected_got("atlas light", "a valid light", str(exc))) from exc


# ------------------------------------------------------------------ reading
def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    names = ("meta",) + ARRAYS
    want = f"a complete {ATLAS_FORMAT} .npz file with the arrays {', '.join(names)}"
    try:
        # opened by open_regular: a FIFO or a folder is refused, never waited on
        with open_regular(path, "atlas file") as f, np.load(f, allow_pickle=False) as z:
            if not hasattr(z, "files"):  # a bare .npy
                raise FileFormatError(expected_got("atlas file", want, f"one array in {path.name}"))
            for k in names:
                if k not in z.files:
                    raise FileFormatError(expected_got("atlas file", want, f"no {k!r} in {path.name}"))
            return {k: _read_one(z, k) for k in names}
    except FileNotFoundError as exc:
        raise FileFormatError(expected_got("atlas file", "an existing file", str(path))) from exc
    except ARCHIVE_ERRORS as exc:
        raise FileFormatError(expected_got(
            "atlas file", f"a complete {ATLAS_FORMAT} .npz file",
            f"an unreadable file {path.name} ({type(exc).__name__}: {exc})"[:300])) from exc


def _read_one(z: Any, k: str) -> np.ndarray:
    try:
        return z[k]
    except ValueError as exc:
        if "allow_pickle" in str(exc):
            raise FileFormatError(expected_got(f"atlas array {k!r}", "a numeric array (pickled objects "
                                               "are never loaded)", "an object array")) from exc
        raise


def _read_meta(raw: np.ndarray) -> dict[str, Any]:
    if raw.dtype != np.uint8 or raw.ndim != 1:
        raise FileFormatError(expected_got("atlas metadata", "UTF-8 JSON bytes (uint8)",
                                           f"{raw.dtype} of shape {raw.shape}"))
    try:
        meta = json.loads(bytes(raw).decode())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise FileFormatError(expected_got("atlas metadata", "UTF-8 JSON", f"{type(exc).__name__}: {exc}")
                              ) from exc
    if not isinstance(meta, dict):
        raise FileFormatError(expected_got("atlas metadata", "a JSON object", type(meta).__name__))
    return meta


def _key(d: dict[str, Any], k: str, where: str) -> Any:
    if k not in d:
        raise FileFormatError(expected_got(where, f"a key {k!r}", f"keys {sorted(d)}"[:200]))
    return d[k]


def _is_int(v: Any) -> bool:
    return type(v) is int


def _is_number(v: Any) -> bool:
    return type(v) in (int, float) and math.isfinite(v)


def _vector(v: Any, where: str, shape: tuple[int, ...]) -> np.ndarray:
    """Nested JSON lists of finite numbers of ``shape``, as float64."""
    want = " x ".join(map(str, shape)) + " finite numbers"

    def ok(x: Any, dims: tuple[int, ...]) -> bool:
        if not dims:
            return _is_number(x)
        return isinstance(x, list) and len(x) == dims[0] and all(ok(y, dims[1:]) for y in x)

    if not ok(v, shape):
        raise FileFormatError(expected_got(where, want, repr(v)[:120]))
    return np.array(v, dtype=np.float64)


def _rig_from_meta(light: DirectionalLight | PointLight, p: Any) -> LightRig:
    if not isinstance(p, dict):
        raise FileFormatError(expected_got("atlas rig", "an object", repr(p)[:80]))
    shape = _key(p, "shape", "atlas rig")
    if not (isinstance(shape, list) and len(shape) == 2 and all(_is_int(v) and v >= 1 for v in shape)):
        raise FileFormatError(expected_got("atlas rig shape", "[H, W], integers >= 1", repr(shape)[:80]))
    lo = _vector(_key(p, "lo", "atlas rig"), "atlas rig lo", (2,))
    hi = _vector(_key(p, "hi", "atlas rig"), "atlas rig hi", (2,))
    try:
        MotionRange(lo, hi)
    except MorphkitError as exc:
        raise FileFormatError(expected_got("atlas rig range", "a valid motion range (lo < hi)", str(exc))
                              ) from exc
    R = _vector(_key(p, "R", "atlas rig"), "atlas rig R", (3, 3))
    for k in ("fx", "fy"):
        v = _key(p, k, "atlas rig")
        if not (_is_number(v) and v > 0):
            raise FileFormatError(expected_got(f"atlas rig {k}", "a finite number > 0", repr(v)[:80]))
    for k in ("znear", "zfar"):
        v = _key(p, k, "atlas rig")
        if not _is_number(v):
            raise FileFormatError(expected_got(f"atlas rig {k}", "a finite number", repr(v)[:80]))
    if not p["zfar"] > p["znear"]:
        raise FileFormatError(expected_got("atlas rig zfar", f"> znear {p['znear']}", p["zfar"]))
    _vector(_key(p, "anchor0", "atlas rig"), "atlas rig anchor0", (3,))
    pose = _vector(_key(p, "base_pose", "atlas rig"), "atlas rig base_pose", (4, 4))
    T = np.eye(4)
    T[:3, :3] = R
    for name, m in (("R", T), ("base_pose", pose)):
        try:
            as_pose(m, name)
        except ValidationError as exc:
            raise FileFormatError(expected_got(f"atlas rig {name}", "a rotation", str(exc))) from exc
    back = _key(p, "back", "atlas rig")
    if isinstance(light, DirectionalLight) and not _is_number(back):
        raise FileFormatError(expected_got("atlas rig back", "a number for a directional light",
                                           repr(back)[:80]))
    if isinstance(light, PointLight) and back is not None:
        raise FileFormatError(expected_got("atlas rig back", "null for a point light", repr(back)[:80]))
    try:
        return LightRig.from_params(light, p)
    except (MorphkitError, KeyError, TypeError, ValueError) as exc:
        raise FileFormatError(expected_got("atlas rig", "parameters that build a light rig",
                                           f"{type(exc).__name__}: {exc}"[:200])) from exc


_SHA256 = re.compile(r"[0-9a-f]{64}")


def _check_checksums(data: dict[str, np.ndarray], decl: Any) -> None:
    if not isinstance(decl, dict):
        raise FileFormatError(expected_got("atlas arrays", "an object", repr(decl)[:80]))
    for k in ARRAYS:
        d = _key(decl, k, "atlas arrays")
        ok = (isinstance(d, dict) and isinstance(d.get("dtype"), str) and isinstance(d.get("shape"), list)
              and all(_is_int(n) and n >= 0 for n in d["shape"])
              and isinstance(d.get("sha256"), str) and _SHA256.fullmatch(d["sha256"]) is not None)
        if not ok:
            raise FileFormatError(expected_got(f"atlas arrays {k}", "an object with dtype, shape, sha256",
                                               repr(d)[:120]))
        a = data[k]
        if str(a.dtype) != d["dtype"] or list(a.shape) != d["shape"]:
            raise FileFormatError(expected_got(f"atlas array {k!r}", f"{d['dtype']} of shape {d['shape']}",
                                               f"{a.dtype} of shape {list(a.shape)} (corrupt file)"))
        got = array_digest(a)
        if got != d["sha256"]:
            raise FileFormatError(expected_got(f"atlas array {k!r}", f"sha256 {d['sha256'][:16]}...",
                                               f"{got[:16]}... (corrupt file)"))


def _finite(a: np.ndarray, name: str) -> None:
    if a.dtype.kind != "f":
        raise FileFormatError(expected_got(f"atlas {name}", "floating-point values", str(a.dtype)))
    if not np.all(np.isfinite(a)):
        bad = int(np.count_nonzero(~np.isfinite(a)))
        raise FileFormatError(expected_got(f"atlas {name}", "finite values", f"{bad} NaN/inf values"))


def _check_values(data: dict[str, np.ndarray], rig: LightRig, control_grid: tuple[int, int]) -> None:
    maps = data["maps"]
    if maps.dtype != np.float32 or maps.ndim != 4:
        raise FileFormatError(expected_got("atlas maps", "float32 of shape (ky, kx, H, W)",
                                           f"{maps.dtype} of shape {maps.shape}"))
    bad = int(np.count_nonzero(np.isnan(maps) | (maps == -np.inf)))
    if bad:
        raise FileFormatError(expected_got("atlas maps", "finite or +inf depths", f"{bad} NaN/-inf values"))
    for k in ("xs", "ys", "anchors", "plane_anchors", "control"):
        _finite(data[k], k)
    xs, ys = data["xs"], data["ys"]
    for k, s in (("xs", xs), ("ys", ys)):
        if s.ndim != 1 or len(s) < 2 or np.any(np.diff(s) <= 0):
            raise FileFormatError(expected_got(f"atlas {k}", "increasing sample positions (at least 2)",
                                               np.round(s, 6).tolist() if s.ndim == 1 else s.shape))
    ky, kx = len(ys), len(xs)
    n = control_grid[0] * control_grid[1]
    want = {"maps": (ky, kx, *rig.shape), "anchors": (ky, kx, n, 3), "plane_anchors": (ky, kx, n, 3),
            "control": (ky, kx, n, 2)}
    for k, shape in want.items():
        if data[k].shape != shape:
            raise FileFormatError(expected_got(f"atlas {k}", f"shape {shape} (from xs, ys, control_grid "
                                               "and the rig's map shape)", data[k].shape))
    tri = data["triangles"]
    if tri.dtype.kind not in "iu" or tri.ndim != 2 or tri.shape[1] != 3:
        raise FileFormatError(expected_got("atlas triangles", "integers of shape (T, 3)",
                                           f"{tri.dtype} of shape {tri.shape}"))
    span = rig.motion.hi - rig.motion.lo
    for k, s, axis in (("xs", xs, 0), ("ys", ys, 1)):
        lo, hi = rig.motion.lo[axis], rig.motion.hi[axis]
        if abs(s[0] - lo) > tol.REL_EQUAL * span[axis] or abs(s[-1] - hi) > tol.REL_EQUAL * span[axis]:
            raise FileFormatError(expected_got(f"atlas {k}", f"samples from {lo:g} to {hi:g} (the rig's "
                                               "range)", f"{s[0]:g} to {s[-1]:g}"))
