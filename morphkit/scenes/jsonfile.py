"""JSON scene files: a :class:`~morphkit.scenes.description.SceneDescription` on disk.

A scene file is one JSON object, ``{"morphkit_scene": 1, ...}``, checked on reading against the
JSON Schema shipped with morphkit (:data:`SCHEMA_PATH`, ``morphkit/data/scene.schema.json``; the
fields are documented there and in ``docs/scenes.md``). A file of another version, or one that
fails the schema, is refused naming the failing path (``$.instances.scatter.count``).

An asset's ``source`` is a sample mesh's name, or a file: a relative path is taken relative to
the scene file's folder (and a file inside that folder is written so, the folder moving as a
whole; others as absolute paths); the name of a file morphkit ships
(:data:`morphkit.meshes.SAMPLE_FILES`, e.g. ``photo_crate.glb``) that is not in that folder is
the shipped file.

Example
-------
::

    {"morphkit_scene": 1,
     "assets": [{"name": "tree", "source": "tree"}, {"name": "crate", "source": "crate.glb", "scale": 0.6}],
     "instances": {"scatter": {"count": 100, "seed": 3}},
     "camera": {"path": "flyover"},
     "sun": {"day": {}},
     "shadows": {"soft": "pcss"},
     "image": {"width": 640, "height": 480}, "frames": 24}
"""

from __future__ import annotations

import json
import os
from functools import cache
from pathlib import Path
from typing import Any

from ..billboard.frames.backdrop import Ground
from ..errors import FileFormatError, ValidationError, expected_got
from ..files.fileio import read_json, write_json
from ..meshes import BILLBOARD_MESHES, SAMPLE_FILES, sample_file
from .camerapaths import camera_from_json
from .description import SceneAsset, SceneDescription, SceneShadows
from .placing import placement_from_json
from .suns import sun_from_json

__all__ = [
    "SCENE_FORMAT",
    "SCHEMA_PATH",
    "scene_schema",
    "scene_from_json",
    "scene_to_json",
    "read_scene_file",
    "write_scene_file",
    "is_scene_file",
]

#: The version of the scene files this morphkit reads and writes (``"morphkit_scene"``).
SCENE_FORMAT = 1
#: The JSON Schema of scene files of version :data:`SCENE_FORMAT`.
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "data" / "scene.schema.json"


@cache
def scene_schema() -> dict[str, Any]:
    """The scene files' JSON Schema (draft 2020-12), read once.

    Returns
    -------
    dict
    """
    return json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))


def _check_schema(obj: Any, where: str) -> None:
    """``obj`` against the schema; the first failure named by its path in the file."""
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import best_match

    err = best_match(Draft202012Validator(scene_schema()).iter_errors(obj))
    if err is not None:
        raise FileFormatError(
            expected_got(
                f"scene file {where}",
                "a scene following morphkit's scene schema",
                f"at {err.json_path}: {err.message}",
            )
        )


def _source(src: str, folder: Path | None) -> str:
    """An asset's source as the scene uses it: a sample mesh's name as is; a path relative to the
    file's folder; a file morphkit ships (:data:`morphkit.meshes.SAMPLE_FILES`) named alone and not
    in that folder: the shipped one."""
    if src in BILLBOARD_MESHES or folder is None or Path(src).is_absolute():
        return src
    here = folder / src
    if not here.exists() and src in SAMPLE_FILES:
        return str(sample_file(src))
    return str(here)


def scene_from_json(
    obj: Any, *, folder: str | os.PathLike[str] | None = None, where: str = "(in memory)"
) -> SceneDescription:
    """The scene a parsed scene file describes.

    Parameters
    ----------
    obj : object
        The file's parsed JSON.
    folder : path-like, optional
        The folder relative asset paths are taken from (the file's).
    where : str, optional
        The file's name, for messages.

    Returns
    -------
    SceneDescription

    Raises
    ------
    FileFormatError
        Another version, or a document failing the schema (the failing path named).
    ValidationError
        Values the schema admits but the scene cannot be (e.g. two assets of one name,
        an instance of an asset not in the scene).
    """
    if not isinstance(obj, dict) or "morphkit_scene" not in obj:
        raise FileFormatError(
            expected_got(
                f"scene file {where}",
                'a JSON object with "morphkit_scene"',
                type(obj).__name__ if not isinstance(obj, dict) else sorted(obj)[:6],
            )
        )
    if obj["morphkit_scene"] != SCENE_FORMAT:
        raise FileFormatError(
            expected_got(
                f"scene file {where}", f"version {SCENE_FORMAT}", f"version {obj['morphkit_scene']!r}"
            )
        )
    _check_schema(obj, where)
    base = None if folder is None else Path(folder)
    try:
        assets = tuple(
            SceneAsset(a["name"], _source(a["source"], base), a.get("scale", 1.0), a.get("up", "auto"))
            for a in obj["assets"]
        )
        sh = obj.get("shadows")
        image = obj.get("image", {"width": 640, "height": 480})
        desc = SceneDescription(
            assets,
            placement_from_json(obj["instances"]),
            camera=camera_from_json(obj.get("camera", {"path": "pan"})),
            sun=sun_from_json(obj.get("sun")),
            shape=(image["height"], image["width"]),
            frames=obj.get("frames", 48),
            views=obj.get("views"),
            asset_size=obj.get("asset_size", 128),
            shadows=None if sh is None else SceneShadows(**sh),
            fog=obj.get("fog", True),
            ground=Ground(**obj.get("ground", {})),
        )
        desc.instances.first(desc.names)  # every instance's asset is the scene's
    except ValidationError as exc:
        raise ValidationError(f"scene file {where}: {exc}") from exc
    return desc


def scene_to_json(scene: SceneDescription, *, folder: str | os.PathLike[str] | None = None) -> dict[str, Any]:
    """The scene file of ``scene`` (what :func:`scene_from_json` reads back).

    Parameters
    ----------
    scene : SceneDescription
        Assets read from files (a glTF scene's meshes cannot be written into a scene file).
    folder : path-like, optional
        The folder the file is written to: asset paths inside it are written relative to it.

    Returns
    -------
    dict
        JSON-ready, valid against the schema.

    Raises
    ------
    ValidationError
        An asset held only in memory (a glTF scene's mesh).
    """
    base = None if folder is None else Path(folder).resolve()
    assets = []
    for a in scene.assets:
        if a.mesh is not None:
            raise ValidationError(
                expected_got(
                    f"asset {a.name!r}",
                    "an asset read from a file or a sample name",
                    f"a mesh of a glTF scene ({a.source}): render the glTF itself",
                )
            )
        src = a.source
        shipped = {sample_file(nm).resolve(): nm for nm in SAMPLE_FILES}
        if base is not None and src not in BILLBOARD_MESHES:
            p = Path(src).resolve()
            src = os.path.relpath(p, base) if p.is_relative_to(base) else shipped.get(p, str(p))
        assets.append({"name": a.name, "source": src, "scale": a.scale, "up": a.up})
    g = scene.ground
    out: dict[str, Any] = {
        "morphkit_scene": SCENE_FORMAT,
        "assets": assets,
        "instances": scene.instances.to_json(),
        "camera": scene.camera.to_json(),
        "sun": scene.sun.to_json(),
        "shadows": None
        if scene.shadows is None
        else {
            "soft": scene.shadows.soft,
            "sun_atlas_size": scene.shadows.sun_atlas_size,
            "sun_radius_deg": scene.shadows.sun_radius_deg,
        },
        "image": {"width": scene.shape[1], "height": scene.shape[0]},
        "frames": scene.frames,
        "views": scene.views,
        "asset_size": scene.asset_size,
        "fog": scene.fog,
        "ground": {"color_a": list(g.color_a), "color_b": list(g.color_b), "cell": g.cell},
    }
    _check_schema(out, "(written)")
    return out


def is_scene_file(path: str | os.PathLike[str]) -> bool:
    """``path`` names a JSON scene file (by its suffix, ``.json``).

    Parameters
    ----------
    path : path-like

    Returns
    -------
    bool
    """
    return Path(path).suffix.lower() == ".json"


def read_scene_file(path: str | os.PathLike[str]) -> SceneDescription:
    """Read a JSON scene file (the module notes).

    Parameters
    ----------
    path : path-like
        The file.

    Returns
    -------
    SceneDescription

    Raises
    ------
    FileFormatError
        No regular file there, not JSON, another version, or failing the schema.
    ValidationError
        Values the scene cannot be.
    """
    p = Path(path)
    obj = read_json(p, "scene file")
    return scene_from_json(obj, folder=p.resolve().parent, where=str(p))


def write_scene_file(
    scene: SceneDescription, path: str | os.PathLike[str], *, overwrite: bool = False
) -> Path:
    """Write ``scene`` as a JSON scene file (atomically).

    Parameters
    ----------
    scene : SceneDescription
    path : path-like
        The file; a file already there is replaced only with ``overwrite``.
    overwrite : bool, optional

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    OutputExistsError
        A file is there and ``overwrite`` is false.
    ValidationError
        A scene that cannot be written (:func:`scene_to_json`).
    """
    from ..errors import OutputExistsError

    p = Path(path)
    if p.exists() and not overwrite:
        raise OutputExistsError(
            expected_got(
                f"scene file {p}", "a path that holds nothing (or --overwrite)", "a file already there"
            )
        )
    return write_json(p, scene_to_json(scene, folder=p.resolve().parent))
