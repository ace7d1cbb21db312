"""Baking a library of meshes: ``morphkit bake`` and its Python API, on Dask.

* :mod:`.inputs` -- which mesh files, and the asset name of each;
* :mod:`.kinds` -- what is baked of a mesh: the :class:`AssetKind` protocol and
  :class:`ShadowAtlasKind` (one versioned file per asset and kind);
* :mod:`.manifest` -- the manifest (hashes, options, outputs, timings, status)
  and its crash-safe journal;
* :mod:`.worker` -- one task = one asset, in a worker process with its own GL context;
* :mod:`.cluster` -- a local cluster of worker processes, or an existing scheduler;
* :mod:`.pipeline` -- :func:`bake_library`, the driver.

::

    from morphkit.bake import BakeOptions, ShadowAtlasKind, bake_library

    manifest = bake_library(["props/"], "baked/",
                            options=BakeOptions((ShadowAtlasKind(atlas_size=256),)), workers=4)
    print(manifest.summary(), manifest.failed())
"""

from __future__ import annotations

from ..files.fileio import check_writable
from .cluster import CONNECT_TIMEOUT_S, default_workers, open_client
from .inputs import MESH_SUFFIXES, AssetInput, find_inputs
from .kinds import (
    AssetKind,
    BillboardKind,
    DomeKind,
    SavableAsset,
    ShadowAtlasKind,
    SunAtlasKind,
    output_name,
)
from .manifest import MANIFEST_NAME, AssetRecord, Manifest, OutputRecord, file_digest
from .pipeline import BakeOptions, bake_library
from .worker import BakeTask, TaskResult, bake_task, worker_renderer

__all__ = [
    "bake_library",
    "BakeOptions",
    "check_writable",
    "AssetKind",
    "SunAtlasKind",
    "SavableAsset",
    "ShadowAtlasKind",
    "BillboardKind",
    "DomeKind",
    "output_name",
    "AssetInput",
    "MESH_SUFFIXES",
    "find_inputs",
    "Manifest",
    "AssetRecord",
    "OutputRecord",
    "MANIFEST_NAME",
    "file_digest",
    "BakeTask",
    "TaskResult",
    "bake_task",
    "worker_renderer",
    "CONNECT_TIMEOUT_S",
    "default_workers",
    "open_client",
]
