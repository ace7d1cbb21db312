"""The mesh files a bake covers and the asset name each one gets.

An input is a mesh file or a folder. A file's asset name is its stem
(``props/barrel.obj`` -> ``barrel``); a folder is searched recursively for
files with a mesh suffix (:data:`MESH_SUFFIXES`; hidden files and folders are
skipped) and each one is named by its path relative to the folder, suffix
removed (``trees/oak.ply`` under ``lib/`` -> ``trees/oak``), so the output
folder mirrors the input folder. Two inputs with the same name are refused
before any work (their outputs would overwrite each other). Entries with a mesh
suffix that are not regular files (a broken link, a link loop, a FIFO) are assets
too: the bake records each as failed, unopened, and goes on with the others.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import trimesh

from ..errors import MeshError, ValidationError, expected_got

__all__ = ["AssetInput", "MESH_SUFFIXES", "find_inputs"]

#: Suffixes taken from a folder: every format trimesh loads, less archives and point clouds
#: (a file named on the command line is tried whatever its suffix).
MESH_SUFFIXES: frozenset[str] = frozenset(
    f".{s}" for s in trimesh.available_formats()
    if s not in {"zip", "bz2", "tar.gz", "tar.bz2", "xyz"} and "." not in s)


@dataclass(frozen=True)
class AssetInput:
    """One mesh file to bake.

    Parameters
    ----------
    name : str
        Asset name: a POSIX relative path without the mesh suffix; outputs are
        ``<out>/<name><kind suffix>``.
    path : pathlib.Path
        The mesh file, absolute.
    """

    name: str
    path: Path


def find_inputs(inputs: Sequence[str | os.PathLike[str]]) -> list[AssetInput]:
    """The mesh files named by ``inputs`` (files or folders), sorted by asset name.

    Parameters
    ----------
    inputs : sequence of path-like
        Mesh files and folders (searched recursively).

    Returns
    -------
    list of AssetInput
        One per distinct file (a file named twice is baked once).

    Raises
    ------
    MeshError
        An input does not exist, or no mesh file was found at all.
    ValidationError
        Two different files get the same asset name.
    """
    if isinstance(inputs, str | os.PathLike):
        inputs = [inputs]
    found: dict[str, AssetInput] = {}

    def add(name: str, path: Path) -> None:
        try:
            path = path.resolve()
        except (OSError, RuntimeError):  # a link loop (RuntimeError before Python 3.13): fails when baked
            path = Path(os.path.abspath(path))
        old = found.get(name)
        if old is not None and old.path != path:
            raise ValidationError(expected_got(
                f"asset name {name!r}", "one mesh file per name (outputs are named after it)",
                f"two: {old.path} and {path}"))
        found[name] = AssetInput(name, path)

    for raw in inputs:
        p = Path(raw)
        if p.is_file() or (p.exists() and not p.is_dir()):  # a FIFO: an asset that fails
            add(p.stem, p)
        elif p.is_dir():
            n = 0
            for f in sorted(p.rglob("*")):
                rel = f.relative_to(p)
                # not f.is_file(): a broken link or a FIFO with a mesh suffix is an asset that fails
                if (not f.is_dir() and f.suffix.lower() in MESH_SUFFIXES
                        and not any(part.startswith(".") for part in rel.parts)):
                    add(rel.with_suffix("").as_posix(), f)
                    n += 1
            if n == 0:
                raise MeshError(expected_got(f"input folder {str(p)!r}", "mesh files ("
                                             + ", ".join(sorted(MESH_SUFFIXES)) + ")", "none"))
        else:
            raise MeshError(expected_got("input", "an existing mesh file or folder",
                                         f"{str(p)!r} (not found)"))
    if not found:
        raise MeshError(expected_got("inputs", "at least one mesh file or folder", "none"))
    return [found[k] for k in sorted(found)]
